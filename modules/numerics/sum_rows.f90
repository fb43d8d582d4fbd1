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
    if (associated(self%g)) call merge_row(self%g, i, self%alpha_g, gcol, val, n)
    if (associated(self%h)) call merge_row(self%h, i, self%alpha_h, gcol, val, n)
  end subroutine row

  !> Add alpha times row i of a into gcol/val(1:n): found ids add in place,
  !> the others are appended in a's order. A short row of a is looked up
  !> linearly; a longer one (the rows of nodes at faults: tens of entries
  !> against the ~81 of K's row) by one walk along the row's ids sorted
  !> (a's rows are ascending): looking up every entry linearly was 3 % of
  !> the nine-fracture case's run (34 x 34 x 69 cells, 2 ranks). Both add
  !> the same terms in the same order.
  subroutine merge_row(a, i, alpha, gcol, val, n)
    type(global_csr_t), intent(in) :: a
    integer(ip), intent(in) :: i
    real(rp), intent(in) :: alpha
    integer(gp), intent(inout) :: gcol(:)
    real(rp), intent(inout) :: val(:)
    integer(ip), intent(inout) :: n
    integer(ip), parameter :: short_row = 8
    integer(ip) :: j, j0, j1, n0
    j0 = a%row_ptr(i)
    j1 = a%row_ptr(i + 1) - 1
    if (j1 < j0) return
    n0 = n
    if (j1 - j0 < short_row) then
      do j = j0, j1
        call add(j, position(a%gcol(j), gcol, n0))
      end do
    else
      call walk(n0)
    end if
  contains
    !> The walk: ids(1:n0) the row's ids ascending, at(k) the place of ids(k).
    subroutine walk(n0)
      integer(ip), intent(in) :: n0
      integer(gp) :: ids(n0)
      integer(ip) :: at(n0), j, p
      ids = gcol(1:n0)
      call sort_ids(ids, at)
      p = 1
      do j = j0, j1
        if (j > j0) then
          if (a%gcol(j) < a%gcol(j - 1)) p = 1     ! not ascending: from the start
        end if
        do while (p <= n0)
          if (ids(p) >= a%gcol(j)) exit
          p = p + 1
        end do
        if (p <= n0) then
          if (ids(p) == a%gcol(j)) then
            call add(j, at(p))
            cycle
          end if
        end if
        call add(j, 0_ip)
      end do
    end subroutine walk

    !> Entry j of a into place q of the row (0: appended).
    subroutine add(j, q)
      integer(ip), intent(in) :: j, q
      if (q == 0) then
        n = n + 1
        gcol(n) = a%gcol(j)
        val(n) = alpha * a%val(j)
      else
        val(q) = val(q) + alpha * a%val(j)
      end if
    end subroutine add
  end subroutine merge_row

  !> Sort ids ascending by insertion (a row of K is nearly in order: owned
  !> columns ascending, then the ghosts); at returns the original places.
  pure subroutine sort_ids(ids, at)
    integer(gp), intent(inout) :: ids(:)
    integer(ip), intent(out) :: at(:)
    integer(ip) :: k, m, tp
    integer(gp) :: t
    do k = 1, size(ids, kind=ip)
      at(k) = k
    end do
    do k = 2, size(ids, kind=ip)
      t = ids(k)
      tp = at(k)
      m = k - 1
      do while (m >= 1)
        if (ids(m) <= t) exit
        ids(m + 1) = ids(m)
        at(m + 1) = at(m)
        m = m - 1
      end do
      ids(m + 1) = t
      at(m + 1) = tp
    end do
  end subroutine sort_ids

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
