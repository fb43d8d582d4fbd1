!> The benchmarks' reference cost: one CG solve of K u = f (a mechanics block
!> and its right-hand side) with BoomerAMG, to the tolerance of the run.
!> Its iterations and times are logged, its solution is thrown away; the
!> benchmark scripts divide the coupled solve by it.
module elastic_reference
  use kinds, only: rp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use csr_matrix, only: csr_matrix_t
  use amg_params, only: amg_params_t
  use precon, only: precon_t
  use boomeramg_precon, only: boomeramg_precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  use dist_vector, only: pnorm2
  implicit none
  private

  public :: solve_elastic_reference

contains

  !> Solve k u = b once with CG. When p is a BoomerAMG preconditioner of k it
  !> is used as it is; otherwise one is set up with amg (and freed).
  !> A zero b is replaced by ones so that the solve is not empty.
  !> rtol, max_iter: the CG tolerance (relative) and iteration cap.
  subroutine solve_elastic_reference(comm, log, k, b, rtol, max_iter, amg, p)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(csr_matrix_t), intent(inout) :: k
    real(rp), intent(in) :: b(:)
    real(rp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    type(amg_params_t), intent(in) :: amg
    class(precon_t), intent(inout), optional :: p
    type(cg_t) :: solver
    type(solve_info_t) :: info
    type(boomeramg_precon_t) :: own
    type(error_status_t) :: status
    real(rp), allocatable :: x(:), rhs(:)
    real(rp) :: t_setup
    logical :: given
    character(len=msg_len) :: line
    allocate(rhs(size(b)), x(size(b)))
    rhs = b
    if (pnorm2(comm, rhs) == 0.0_rp) rhs = 1.0_rp
    x = 0.0_rp
    call solver%init(comm, rtol, 0.0_rp, max_iter)
    given = .false.
    if (present(p)) then
      select type (p)
      type is (boomeramg_precon_t)
        given = .true.
        call solver%solve(k, p, rhs, x, info)
        t_setup = p%setup_time
      end select
    end if
    if (.not. given) then
      call own%setup(k, amg, status)
      if (.not. status%ok()) call log%fatal(comm, 'elastic reference: '//trim(status%msg))
      call solver%solve(k, own, rhs, x, info)
      t_setup = own%setup_time
      call own%free()
    end if
    write(line, '(a,i0,a,es9.2,a,f8.3,a,f8.3,a)') 'elastic reference (CG + BoomerAMG on K): iterations ', &
      info%iterations, ', rel. residual ', info%rel_res, ', AMG setup ', t_setup, ' s, solve ', &
      info%solve_time, ' s'
    call log%info(line)
  end subroutine solve_elastic_reference
end module elastic_reference
