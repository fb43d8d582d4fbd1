!> Symmetric diagonal scaling of a linear system, A x = b  ->  (D A D) y = D b,
!> x = D y, with D = diag(d) > 0.
!>
!> Block systems mix units (forces, pressures, volumes): their residual norm
!> is dominated by one block and says nothing about the others. Scaling every
!> row and column by 1/sqrt(|a_ii|) (or an approximation of the Schur
!> complement's diagonal where a_ii vanishes) makes the blocks comparable, so
!> that a relative residual of the scaled system is a meaningful stopping
!> test. A preconditioner M ~ A^-1 becomes D^-1 M D^-1 ~ (D A D)^-1.
module scaled_system
  use kinds, only: rp, ip, name_len
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  implicit none
  private

  public :: scaled_operator_t, scaled_precon_t

  type, extends(linear_operator_t) :: scaled_operator_t
    class(linear_operator_t), pointer :: a => null()
    real(rp), allocatable :: d(:)
    real(rp), allocatable :: w(:)
  contains
    procedure :: init => sop_init
    procedure :: apply => sop_apply
    procedure :: n_owned => sop_n_owned
  end type scaled_operator_t

  type, extends(precon_t) :: scaled_precon_t
    class(precon_t), pointer :: m => null()
    real(rp), allocatable :: d(:)
    real(rp), allocatable :: w(:)
  contains
    procedure :: init => spc_init
    procedure :: apply => spc_apply
    procedure :: name => spc_name
  end type scaled_precon_t

contains

  !> Wrap operator a (kept by pointer) with scaling d (owned entries, > 0).
  subroutine sop_init(self, a, d)
    class(scaled_operator_t), intent(inout) :: self
    class(linear_operator_t), intent(in), target :: a
    real(rp), intent(in) :: d(:)
    self%a => a
    self%d = d
    if (allocated(self%w)) deallocate(self%w)
    allocate(self%w(size(d)))
  end subroutine sop_init

  !> y = D A D x.
  subroutine sop_apply(self, x, y)
    class(scaled_operator_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    self%w = self%d * x
    call self%a%apply(self%w, y)
    y = self%d * y
  end subroutine sop_apply

  integer(ip) function sop_n_owned(self)
    class(scaled_operator_t), intent(in) :: self
    sop_n_owned = size(self%d, kind=ip)
  end function sop_n_owned

  !> Wrap preconditioner m (kept by pointer) with scaling d.
  subroutine spc_init(self, m, d)
    class(scaled_precon_t), intent(inout) :: self
    class(precon_t), intent(in), target :: m
    real(rp), intent(in) :: d(:)
    self%m => m
    self%d = d
    if (allocated(self%w)) deallocate(self%w)
    allocate(self%w(size(d)))
  end subroutine spc_init

  !> z = D^-1 M D^-1 r.
  subroutine spc_apply(self, r, z)
    class(scaled_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    self%w = r / self%d
    call self%m%apply(self%w, z)
    z = z / self%d
  end subroutine spc_apply

  function spc_name(self) result(s)
    class(scaled_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'scaled '//trim(self%m%name())
  end function spc_name
end module scaled_system
