!> A preconditioner M with a subspace correction applied before it: a space
!> of n_s vectors (Z, each with a few entries in the block vector), a left
!> space Y of the same shape, the operator L = Y^T A Z (a sparse matrix of
!> its own, given by the caller) and an approximate inverse P of L:
!>
!>   c = P (Y^T r),  w = Z c,  z = w + M^-1 (r - A w)
!>
!> (one product with A per application). Made for the fractures' pressure
!> with the normal traction following it (contact_precon.f90): a mode per
!> element that the Jacobian nearly annihilates, where L is a Laplacian on
!> the fracture surface that BoomerAMG solves and that M, with diagonals for
!> the traction and pressure blocks, does not.
module subspace_precon
  use kinds, only: rp, ip, name_len
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  implicit none
  private

  public :: subspace_precon_t

  type, extends(precon_t) :: subspace_precon_t
    class(precon_t), pointer :: m => null()        !< the preconditioner of A
    class(linear_operator_t), pointer :: a => null()
    class(precon_t), pointer :: pl => null()       !< approximate inverse of L
    !> subspace vector k (owned row k of L): entries ptr(k)..ptr(k+1)-1 at
    !> block-vector positions idx, values zval (in Z) and yval (in Y)
    integer(ip), allocatable :: ptr(:), idx(:)
    real(rp), allocatable :: zval(:), yval(:)
    real(rp), allocatable :: s(:), c(:), w(:), y(:)
  contains
    procedure :: setup
    procedure :: apply => sp_apply
    procedure :: name => sp_name
    procedure :: free => sp_free
  end type subspace_precon_t

contains

  !> Keep m, a and pl (set up already) and the vectors (moved in); n_block:
  !> owned length of the block vector. Not collective.
  subroutine setup(self, m, a, pl, ptr, idx, zval, yval, n_block)
    class(subspace_precon_t), intent(inout) :: self
    class(precon_t), intent(in), target :: m, pl
    class(linear_operator_t), intent(in), target :: a
    integer(ip), allocatable, intent(inout) :: ptr(:), idx(:)
    real(rp), allocatable, intent(inout) :: zval(:), yval(:)
    integer(ip), intent(in) :: n_block
    call self%free()
    self%m => m
    self%a => a
    self%pl => pl
    call move_alloc(ptr, self%ptr)
    call move_alloc(idx, self%idx)
    call move_alloc(zval, self%zval)
    call move_alloc(yval, self%yval)
    allocate(self%s(size(self%ptr) - 1), self%c(size(self%ptr) - 1), self%w(n_block), self%y(n_block))
  end subroutine setup

  subroutine sp_apply(self, r, z)
    class(subspace_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer(ip) :: k, j
    do k = 1, size(self%s)
      self%s(k) = 0.0_rp
      do j = self%ptr(k), self%ptr(k + 1) - 1
        self%s(k) = self%s(k) + self%yval(j) * r(self%idx(j))
      end do
    end do
    call self%pl%apply(self%s, self%c)
    self%w = 0.0_rp
    do k = 1, size(self%c)
      do j = self%ptr(k), self%ptr(k + 1) - 1
        self%w(self%idx(j)) = self%w(self%idx(j)) + self%zval(j) * self%c(k)
      end do
    end do
    call self%a%apply(self%w, self%y)
    self%y = r - self%y
    call self%m%apply(self%y, z)
    z = z + self%w
  end subroutine sp_apply

  function sp_name(self) result(s)
    class(subspace_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'subspace+'//trim(self%m%name())
  end function sp_name

  subroutine sp_free(self)
    class(subspace_precon_t), intent(inout) :: self
    nullify(self%m, self%a, self%pl)
    if (allocated(self%ptr)) deallocate(self%ptr, self%idx, self%zval, self%yval)
    if (allocated(self%s)) deallocate(self%s, self%c, self%w, self%y)
    self%setup_time = 0.0_rp
  end subroutine sp_free
end module subspace_precon
