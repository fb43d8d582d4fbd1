!> A sum of distributed matrices given to hypre row by row (hypre_ij's
!> ij_rows_t): m + alpha_g g (+ alpha_h h), with m a csr_matrix_t (its own
!> column map) and g, h global_csr_t's over the same owned rows. Each row is
!> merged when hypre asks for it, so the sum is never stored here: the
!> reordered contact preconditioner's S* = K + C1 H~^-1 C2 (and S**) exists
!> only in its BoomerAMG's copy (0.4 GB a rank less at HI24L's size than
!> keeping S*'s pattern for the next refresh).
module sum_rows
  use kinds, only: rp, ip, gp
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t
  use hypre_ij, only: csr_rows_t
  implicit none
  private

  public :: sum_rows_t

  !> a (csr_rows_t's matrix) + alpha_g g (+ alpha_h h)
  type, extends(csr_rows_t) :: sum_rows_t
    type(global_csr_t), pointer :: g => null()    !< null: no such term
    type(global_csr_t), pointer :: h => null()    !< null: no such term
    real(rp) :: alpha_g = 1.0_rp, alpha_h = 1.0_rp
  contains
    procedure :: init
    procedure :: max_row
    procedure :: row
    procedure :: diagonal
  end type sum_rows_t

contains

  !> m + alpha_g g (+ alpha_h h), all pointed to (they must outlive self);
  !> the rows are m's owned rows.
  subroutine init(self, m, g, alpha_g, h, alpha_h)
    class(sum_rows_t), intent(inout) :: self
    type(csr_matrix_t), intent(in), target :: m
    type(global_csr_t), intent(in), target, optional :: g, h
    real(rp), intent(in), optional :: alpha_g, alpha_h
    self%row_map => m%row_map
    self%a => m
    self%g => null()
    self%h => null()
    if (present(g)) then
      if (g%n_rows /= m%n_rows) error stop 'sum_rows%init: g has other rows than m'
      self%g => g
    end if
    if (present(h)) then
      if (h%n_rows /= m%n_rows) error stop 'sum_rows%init: h has other rows than m'
      self%h => h
    end if
    if (present(alpha_g)) self%alpha_g = alpha_g
    if (present(alpha_h)) self%alpha_h = alpha_h
  end subroutine init

  !> m's longest row plus g's and h's (a bound of the sum's).
  integer(ip) function max_row(self)
    class(sum_rows_t), intent(in) :: self
    max_row = self%csr_rows_t%max_row()
    if (associated(self%g)) max_row = max_row + longest(self%g)
    if (associated(self%h)) max_row = max_row + longest(self%h)
  end function max_row

  integer(ip) function longest(a)
    type(global_csr_t), intent(in) :: a
    longest = 0
    if (a%n_rows > 0) longest = maxval(a%row_ptr(2:a%n_rows + 1) - a%row_ptr(1:a%n_rows))
  end function longest

  !> Owned row i of the sum: m's entries in m's order, then those of g and h
  !> that m's row lacks, in their order (ascending ids).
  subroutine row(self, i, gcol, val, n)
    class(sum_rows_t), intent(in) :: self
    integer(ip), intent(in) :: i
    integer(gp), intent(inout) :: gcol(:)
    real(rp), intent(inout) :: val(:)
    integer(ip), intent(out) :: n
    call self%csr_rows_t%row(i, gcol, val, n)
    if (associated(self%g)) call merge(self%g, self%alpha_g)
    if (associated(self%h)) call merge(self%h, self%alpha_h)
  contains
    !> Add alpha times row i of a into gcol/val(1:n): found ids add in
    !> place (a linear search: only the rows of elements at faults have such
    !> terms), the others are appended.
    subroutine merge(a, alpha)
      type(global_csr_t), intent(in) :: a
      real(rp), intent(in) :: alpha
      integer(ip) :: j, q, n0
      n0 = n
      do j = a%row_ptr(i), a%row_ptr(i + 1) - 1
        q = position(a%gcol(j), gcol, n0)
        if (q == 0) then
          n = n + 1
          gcol(n) = a%gcol(j)
          val(n) = alpha * a%val(j)
        else
          val(q) = val(q) + alpha * a%val(j)
        end if
      end do
    end subroutine merge
  end subroutine row

  !> Position of id in ids(1:n), 0 when absent.
  pure integer(ip) function position(id, ids, n)
    integer(gp), intent(in) :: id, ids(:)
    integer(ip), intent(in) :: n
    integer(ip) :: k
    position = 0
    do k = 1, n
      if (ids(k) == id) then
        position = k
        return
      end if
    end do
  end function position

  !> The sum's diagonal over the owned rows.
  subroutine diagonal(self, d)
    class(sum_rows_t), intent(in) :: self
    real(rp), intent(out) :: d(:)
    integer(gp), allocatable :: gcol(:)
    real(rp), allocatable :: val(:)
    integer(ip) :: i, n, q
    allocate(gcol(self%max_row()), val(self%max_row()))
    do i = 1, self%a%n_rows
      call self%row(i, gcol, val, n)
      q = position(self%row_map%first + i - 1, gcol, n)
      d(i) = 0.0_rp
      if (q > 0) d(i) = val(q)
    end do
  end subroutine diagonal
end module sum_rows
