!> Abstract Krylov solver and the report of one solve.
module krylov
  use kinds, only: rp, ip, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  implicit none
  private

  public :: krylov_t, solve_info_t

  !> What one linear solve did.
  type :: solve_info_t
    integer :: iterations = 0
    real(rp) :: res0 = 0.0_rp              !< initial residual norm
    real(rp) :: rel_res = 0.0_rp           !< final residual / ||b||
    real(rp) :: backward = -1.0_rp         !< a direct solve's componentwise backward error (< 0: not computed)
    real(rp) :: backward0 = -1.0_rp        !< the same before our iterative refinement
    logical :: converged = .false.
    real(rp) :: solve_time = 0.0_rp
    real(rp), allocatable :: history(:)    !< relative residual per iteration (0..iterations)
    character(len=msg_len) :: msg = ''     !< why it stopped when it did not converge
  contains
    procedure :: finish
  end type solve_info_t

  type, abstract :: krylov_t
    type(parallel_comm_t) :: comm
    real(rp) :: rtol = 1.0e-8_rp           !< relative to ||b||
    real(rp) :: atol = 0.0_rp
    integer :: max_iter = 1000
    integer :: restart = 100
  contains
    procedure(solve_iface), deferred :: solve
    procedure(name_iface), deferred :: name
    procedure :: configure
  end type krylov_t

  abstract interface
    !> Solve A x = b with preconditioner m; x holds the initial guess on entry.
    subroutine solve_iface(self, a, m, b, x, info)
      import :: krylov_t, linear_operator_t, precon_t, rp, solve_info_t
      class(krylov_t), intent(inout) :: self
      class(linear_operator_t), intent(inout) :: a
      class(precon_t), intent(inout) :: m
      real(rp), intent(in) :: b(:)
      real(rp), intent(inout) :: x(:)
      type(solve_info_t), intent(out) :: info
    end subroutine solve_iface
    function name_iface(self) result(s)
      import :: krylov_t, name_len
      class(krylov_t), intent(in) :: self
      character(len=name_len) :: s
    end function name_iface
  end interface
contains

  !> Record the iteration count and the time since t0, and trim the history
  !> to 0:its (common end of every Krylov solve).
  subroutine finish(info, its, t0)
    class(solve_info_t), intent(inout) :: info
    integer, intent(in) :: its
    real(rp), intent(in) :: t0
    real(rp), allocatable :: hist(:)
    info%iterations = its
    allocate(hist(0:its))
    hist = info%history(0:its)
    call move_alloc(hist, info%history)
    info%solve_time = wall_time() - t0
  end subroutine finish

  !> Set the communicator and the parameters common to every Krylov method.
  !> rtol, atol: tolerances of the residual norm (relative to ||b||,
  !> absolute); max_iter: total iterations. Omitted values keep the defaults.
  !> Bad values (rtol or atol < 0, max_iter < 0) set status, or stop when
  !> status is absent (the deck readers range-check first, so then it is a
  !> programming error). Returns .false. on a bad value.
  logical function configure(self, comm, rtol, atol, max_iter, status)
    class(krylov_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in), optional :: rtol, atol
    integer, intent(in), optional :: max_iter
    type(error_status_t), intent(inout), optional :: status
    character(len=msg_len) :: m
    self%comm = comm
    if (present(rtol)) self%rtol = rtol
    if (present(atol)) self%atol = atol
    if (present(max_iter)) self%max_iter = max_iter
    m = ''
    if (.not. (self%rtol >= 0.0_rp .and. self%atol >= 0.0_rp)) then
      write(m, '(a,es10.3,a,es10.3,a)') trim(self%name())//'%init: rtol = ', self%rtol, ' and atol = ', &
        self%atol, ' must be >= 0'
    else if (self%max_iter < 0) then
      write(m, '(a,i0,a)') trim(self%name())//'%init: max_iter = ', self%max_iter, ' must be >= 0'
    end if
    configure = len_trim(m) == 0
    if (configure) return
    if (.not. present(status)) error stop 'krylov%init: bad parameters'
    call status%set(trim(m))
  end function configure
end module krylov
