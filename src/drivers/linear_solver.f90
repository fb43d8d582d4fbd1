!> The linear solver of a run, built by name from &solver and &amg: a Krylov
!> method (fgmres, cg) with a preconditioner (boomeramg, jacobi, none), or the
!> direct solver MUMPS (method = 'mumps').
module linear_solver
  use kinds, only: rp, ip, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use dist_vector, only: pnorm2
  use krylov, only: krylov_t, solve_info_t
  use precon, only: precon_t, identity_precon_t
  use fgmres, only: fgmres_t
  use cg, only: cg_t
  use jacobi_precon, only: jacobi_precon_t
  use boomeramg_precon, only: boomeramg_precon_t
  use amg_params, only: amg_params_t
  use logger, only: logger_t
  use strings, only: itoa
  use mumps_solver, only: mumps_solver_t
  use afsai_precon, only: afsai_precon_t
  use hypre_fsai_precon, only: hypre_fsai_precon_t
  use fsai_params, only: fsai_params_t
  use kinds, only: gp
  use solver_config, only: solver_config_t
  implicit none
  private

  public :: linear_solver_t

  type :: linear_solver_t
    type(solver_config_t) :: cfg
    type(amg_params_t) :: amg
    type(fsai_params_t) :: fsai
    class(krylov_t), allocatable :: krylov
    class(precon_t), allocatable :: precon
    logical :: direct = .false.
  contains
    procedure :: init
    procedure :: setup
    procedure :: solve
    procedure :: describe
    procedure :: setup_report
    procedure :: free
  end type linear_solver_t

contains

  !> Choose the methods; nothing is built yet.
  subroutine init(self, comm, cfg, amg, status, fsai)
    class(linear_solver_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    type(solver_config_t), intent(in) :: cfg
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    type(fsai_params_t), intent(in), optional :: fsai   !< settings of precon = 'afsai' or 'hypre_fsai'
    call self%free()
    self%cfg = cfg
    self%amg = amg
    if (present(fsai)) self%fsai = fsai
    self%direct = cfg%method == 'mumps'
    select case (cfg%method)
    case ('fgmres')
      allocate(fgmres_t :: self%krylov)
      select type (k => self%krylov)
      type is (fgmres_t)
        call k%init(comm, cfg%rtol, cfg%atol, cfg%max_iter, cfg%restart, status)
      end select
    case ('cg')
      allocate(cg_t :: self%krylov)
      select type (k => self%krylov)
      type is (cg_t)
        call k%init(comm, cfg%rtol, cfg%atol, cfg%max_iter, status)
      end select
    case ('mumps')
      allocate(mumps_solver_t :: self%precon)
      return
    case default
      call status%set("linear solver: unknown method '"//trim(cfg%method)//"' (valid: fgmres, cg, mumps)")
      return
    end select
    select case (cfg%precon)
    case ('boomeramg')
      allocate(boomeramg_precon_t :: self%precon)
    case ('jacobi')
      allocate(jacobi_precon_t :: self%precon)
    case ('afsai')
      allocate(afsai_precon_t :: self%precon)
    case ('hypre_fsai')
      allocate(hypre_fsai_precon_t :: self%precon)
    case ('none')
      allocate(identity_precon_t :: self%precon)
    case default
      call status%set("linear solver: unknown preconditioner '"//trim(cfg%precon)// &
                      "' (valid: boomeramg, jacobi, afsai, hypre_fsai, none)")
    end select
  end subroutine init

  !> Build the preconditioner (or factorize) for matrix a. Collective.
  subroutine setup(self, a, status, symmetric, keys)
    class(linear_solver_t), intent(inout) :: self
    type(csr_matrix_t), intent(inout), target :: a
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: symmetric
    integer(gp), intent(in), optional :: keys(:)   !< ordering keys of the owned rows (aFSAI)
    real(rp) :: t0
    t0 = wall_time()
    select type (m => self%precon)
    type is (boomeramg_precon_t)
      call m%setup(a, self%amg, status)
    type is (afsai_precon_t)
      call m%setup(a, self%fsai, status, keys)
    type is (hypre_fsai_precon_t)
      call m%setup(a, self%fsai%max_steps, self%fsai%step_size, self%fsai%tol, status)
    type is (jacobi_precon_t)
      call m%setup(a, status)
    type is (mumps_solver_t)
      call m%setup(a, status, symmetric)
    class default
    end select
    self%precon%setup_time = wall_time() - t0
  end subroutine setup

  !> Solve a x = b; x holds the initial guess. info reports the true residual.
  subroutine solve(self, a, b, x, info)
    class(linear_solver_t), intent(inout) :: self
    type(csr_matrix_t), intent(inout) :: a
    real(rp), intent(in) :: b(:)
    real(rp), intent(inout) :: x(:)
    type(solve_info_t), intent(out) :: info
    real(rp), allocatable :: r(:)
    real(rp) :: t0, bnorm
    type(parallel_comm_t) :: comm
    if (self%direct) then
      comm = a%row_map%comm
      t0 = wall_time()
      call self%precon%apply(b, x)
      allocate(r(size(b)))
      call a%apply(x, r)
      r = b - r
      bnorm = pnorm2(comm, b)
      info%iterations = 0
      info%res0 = bnorm
      info%rel_res = pnorm2(comm, r) / max(bnorm, tiny(1.0_rp))
      info%converged = info%rel_res <= max(self%cfg%rtol, 1.0e-10_rp) .or. bnorm == 0.0_rp
      if (.not. info%converged) write(info%msg, '(a,es10.3)') &
        'the direct solve left a relative residual of ', info%rel_res
      info%solve_time = wall_time() - t0
    else
      call self%krylov%solve(a, self%precon, b, x, info)
    end if
  end subroutine solve

  !> One line naming the solver, for the log.
  function describe(self) result(s)
    class(linear_solver_t), intent(in) :: self
    character(len=:), allocatable :: s
    if (self%direct) then
      s = 'MUMPS direct solver'
    else
      s = trim(self%krylov%name())//' + '//trim(self%precon%name())
    end if
  end function describe

  !> Log what the last set-up built: the AMG hierarchy, or the MUMPS factors
  !> and their peak memory. Collective.
  subroutine setup_report(self, a, log, status)
    class(linear_solver_t), intent(inout) :: self
    type(csr_matrix_t), intent(in) :: a
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=msg_len) :: line
    type(parallel_comm_t) :: comm
    integer :: i
    integer(gp) :: n
    integer(ip) :: n_own
    comm = a%row_map%comm
    n = a%row_map%n_global
    n_own = a%n_rows
    select type (m => self%precon)
    type is (boomeramg_precon_t)
      call m%measure_hierarchy(status)
      if (.not. status%ok()) return
      write(line, '(a,i0,a,f6.3,a)') '  BoomerAMG: ', m%num_levels, ' levels, grid complexity ', &
        m%grid_complexity, ', rows per level:'
      do i = 1, size(m%level_rows)
        line = trim(line)//' '//itoa(int(m%level_rows(i)))
      end do
      call log%info(line)
    type is (mumps_solver_t)
      write(line, '(a,i0,a,i0,a,i0,a,f8.3,a)') '  MUMPS: ', m%factor_entries, ' entries in the factors, peak memory ', &
        m%peak_mem_max_mb, ' MB (max over ranks), ', m%peak_mem_total_mb, ' MB (total), analysis + factorization ', &
        m%setup_time, ' s'
      call log%info(line)
    type is (afsai_precon_t)
      write(line, '(a,i0,a,f7.2,a,es10.3,a)') '  aFSAI: ', m%nnz_factor(), ' non-zeros in G (', &
        real(m%nnz_factor(), rp) / real(n, rp), ' per row), one application ', apply_time(m) * 1.0e3_rp, ' ms'
      call log%info(line)
    type is (hypre_fsai_precon_t)
      write(line, '(a,i0,a,es10.3,a)') '  hypre FSAI: at most ', m%nnz_g_max, &
        ' non-zeros in G (hypre does not report the count), one application ', apply_time(m) * 1.0e3_rp, ' ms'
      call log%info(line)
    class default
    end select
  contains
    !> Mean wall time of one application (20 applications to a fixed vector).
    real(rp) function apply_time(p)
      class(precon_t), intent(inout) :: p
      real(rp), allocatable :: r(:), z(:)
      real(rp) :: t0
      integer :: k
      allocate(r(n_own), z(n_own))
      r = 1.0_rp
      call comm%barrier()
      t0 = wall_time()
      do k = 1, 20
        call p%apply(r, z)
      end do
      apply_time = comm%max(wall_time() - t0) / 20.0_rp
    end function apply_time
  end subroutine setup_report

  subroutine free(self)
    class(linear_solver_t), intent(inout) :: self
    if (allocated(self%precon)) then
      call self%precon%free()
      deallocate(self%precon)
    end if
    if (allocated(self%krylov)) deallocate(self%krylov)
  end subroutine free
end module linear_solver
