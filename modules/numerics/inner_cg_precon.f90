!> z = A^-1 r by an inner CG (with a preconditioner of A) to a tight relative
!> tolerance: a stand-in for an exact block solve inside a block
!> preconditioner. It is a diagnostic: comparing it with one cycle of the
!> inner preconditioner separates the error of a Schur-complement
!> approximation from that of its multigrid. The result is a nonlinear
!> function of r, so the outer method must be flexible (FGMRES).
module inner_cg_precon
  use kinds, only: rp, name_len
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  implicit none
  private

  public :: inner_cg_precon_t

  type, extends(precon_t) :: inner_cg_precon_t
    type(csr_matrix_t), pointer :: a => null()    !< the block (must outlive this)
    class(precon_t), allocatable :: inner         !< preconditioner of the inner CG
    type(cg_t) :: solver
    integer :: iterations = 0                     !< inner CG iterations, summed over applications
    integer :: applications = 0
  contains
    procedure :: init => inner_cg_init
    procedure :: apply => inner_cg_apply
    procedure :: name => inner_cg_name
    procedure :: free => inner_cg_free
  end type inner_cg_precon_t

contains

  !> Solve with a (pointed to) and inner (moved in, set up on a) to rtol
  !> within max_iter iterations.
  subroutine inner_cg_init(self, a, inner, rtol, max_iter, status)
    class(inner_cg_precon_t), intent(inout) :: self
    type(csr_matrix_t), target, intent(in) :: a
    class(precon_t), allocatable, intent(inout) :: inner
    real(rp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    type(error_status_t), intent(inout) :: status
    call self%free()
    self%a => a
    call move_alloc(inner, self%inner)
    self%setup_time = self%inner%setup_time
    call self%solver%init(a%row_map%comm, rtol, 0.0_rp, max_iter, status)
  end subroutine inner_cg_init

  subroutine inner_cg_apply(self, r, z)
    class(inner_cg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    type(solve_info_t) :: info
    z = 0.0_rp
    call self%solver%solve(self%a, self%inner, r, z, info)
    self%iterations = self%iterations + info%iterations
    self%applications = self%applications + 1
  end subroutine inner_cg_apply

  function inner_cg_name(self) result(s)
    class(inner_cg_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'inner CG + '//trim(self%inner%name())
  end function inner_cg_name

  subroutine inner_cg_free(self)
    class(inner_cg_precon_t), intent(inout) :: self
    if (allocated(self%inner)) then
      call self%inner%free()
      deallocate(self%inner)
    end if
    self%a => null()
    self%iterations = 0
    self%applications = 0
    self%setup_time = 0.0_rp
  end subroutine inner_cg_free
end module inner_cg_precon
