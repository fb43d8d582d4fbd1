!> Preconditioners of one sparse matrix, built by the name a deck gives:
!> 'boomeramg', 'jacobi', 'afsai' (ours), 'hypre_fsai', 'mumps' (exact) or
!> 'none'. Every place that needs a preconditioner of a matrix (the
!> elasticity solve, the diagonal and Schur blocks of the block
!> preconditioners) makes it here, so a new kind is added in one place.
module precon_factory
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa
  use csr_matrix, only: csr_matrix_t
  use machine_memory, only: peak_resident_bytes
  use precon, only: precon_t, identity_precon_t
  use jacobi_precon, only: jacobi_precon_t
  use boomeramg_precon, only: boomeramg_precon_t
  use afsai_precon, only: afsai_precon_t
  use hypre_fsai_precon, only: hypre_fsai_precon_t
  use mumps_solver, only: mumps_solver_t
  use amg_params, only: amg_params_t
  use fsai_params, only: fsai_params_t
  implicit none
  private

  public :: precon_params_t, precon_names, make_precon, setup_precon, make_and_setup, report_precon, stored_nnz

  !> The names make_precon knows, for error messages.
  character(len=*), parameter :: precon_names = "'boomeramg', 'jacobi', 'afsai', 'hypre_fsai', 'mumps', 'none'"

  !> Settings of the preconditioners that have some.
  type :: precon_params_t
    type(amg_params_t) :: amg                !< BoomerAMG
    type(fsai_params_t) :: fsai              !< aFSAI and hypre's FSAI (steps, step size, tolerance)
    !> BoomerAMG with amg%interp_vec_variant > 0: the near-null space of
    !> the matrix, (owned rows, k) (the rigid-body modes of elasticity)
    real(rp), allocatable :: modes(:,:)
  end type precon_params_t

contains

  !> Allocate p as the preconditioner called name (nothing is set up).
  !> status names the valid choices when name is unknown.
  subroutine make_precon(name, p, status)
    character(len=*), intent(in) :: name
    class(precon_t), allocatable, intent(inout) :: p
    type(error_status_t), intent(inout) :: status
    if (allocated(p)) then
      call p%free()
      deallocate(p)
    end if
    select case (name)
    case ('boomeramg')
      allocate(boomeramg_precon_t :: p)
    case ('jacobi')
      allocate(jacobi_precon_t :: p)
    case ('afsai')
      allocate(afsai_precon_t :: p)
    case ('hypre_fsai')
      allocate(hypre_fsai_precon_t :: p)
    case ('mumps')
      allocate(mumps_solver_t :: p)
    case ('none')
      allocate(identity_precon_t :: p)
    case default
      call status%set("unknown preconditioner '"//trim(name)//"' (valid: "//precon_names//")")
    end select
  end subroutine make_precon

  !> Set p up for matrix a (kept by pointer where the type needs it later).
  !> symmetric: a is symmetric (MUMPS factorizes LDL^T); keys: partition-
  !> independent ordering keys of the owned rows (aFSAI). Collective; records
  !> the set-up seconds in p%setup_time and the rise of the peak resident
!> memory in p%setup_rise.
  subroutine setup_precon(p, a, params, status, symmetric, keys)
    class(precon_t), intent(inout) :: p
    type(csr_matrix_t), intent(in), target :: a
    type(precon_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: symmetric
    integer(gp), intent(in), optional :: keys(:)
    real(rp) :: t0
    integer(gp) :: m0
    t0 = wall_time()
    m0 = peak_resident_bytes()
    select type (p)
    type is (boomeramg_precon_t)
      if (allocated(params%modes)) then
        call p%setup(a, params%amg, status, modes=params%modes)
      else
        call p%setup(a, params%amg, status)
      end if
    type is (jacobi_precon_t)
      call p%setup(a, status)
    type is (afsai_precon_t)
      call p%setup(a, params%fsai, status, keys)
    type is (hypre_fsai_precon_t)
      call p%setup(a, params%fsai%max_steps, params%fsai%step_size, params%fsai%tol, status)
    type is (mumps_solver_t)
      call p%setup(a, status, symmetric)
    class default
    end select
    p%setup_time = wall_time() - t0
    p%setup_rise = max(peak_resident_bytes() - m0, 0_gp)
  end subroutine setup_precon

  !> make_precon and setup_precon in one call.
  subroutine make_and_setup(name, p, a, params, status, symmetric, keys)
    character(len=*), intent(in) :: name
    class(precon_t), allocatable, intent(inout) :: p
    type(csr_matrix_t), intent(in), target :: a
    type(precon_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: symmetric
    integer(gp), intent(in), optional :: keys(:)
    call make_precon(name, p, status)
    if (status%ok()) call setup_precon(p, a, params, status, symmetric, keys)
  end subroutine make_and_setup

  !> Non-zeros a preconditioner stores beyond the matrix (aFSAI: its factor;
  !> Jacobi, BoomerAMG and the others: not counted). Collective.
  integer(gp) function stored_nnz(p)
    class(precon_t), intent(in) :: p
    stored_nnz = 0
    select type (p)
    type is (afsai_precon_t)
      stored_nnz = p%nnz_factor()
    end select
  end function stored_nnz

  !> Log what the last set-up of p (for matrix a) built: the AMG hierarchy,
  !> the aFSAI factor, hypre FSAI's size, or the MUMPS factors and their
  !> memory. Collective.
  subroutine report_precon(p, a, log, status)
    class(precon_t), intent(inout) :: p
    type(csr_matrix_t), intent(in) :: a
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=msg_len) :: line
    type(parallel_comm_t) :: comm
    integer :: i
    comm = a%row_map%comm
    select type (p)
    type is (boomeramg_precon_t)
      call p%measure_hierarchy(status)
      if (.not. status%ok()) return
      write(line, '(a,i0,a,f6.3,a)') '  BoomerAMG: ', p%num_levels, ' levels, grid complexity ', &
        p%grid_complexity, ', rows per level:'
      do i = 1, size(p%level_rows)
        line = trim(line)//' '//itoa(int(p%level_rows(i)))
      end do
      call log%info(line)
    type is (mumps_solver_t)
      call log%info(p%summary())
    type is (afsai_precon_t)
      write(line, '(a,i0,a,f7.2,a,es10.3,a)') '  aFSAI: ', p%nnz_factor(), ' non-zeros in G (', &
        real(p%nnz_factor(), rp) / real(a%row_map%n_global, rp), ' per row), one application ', &
        apply_time(p, comm, a%n_rows) * 1.0e3_rp, ' ms'
      call log%info(line)
    type is (hypre_fsai_precon_t)
      write(line, '(a,i0,a,es10.3,a)') '  hypre FSAI: at most ', p%nnz_g_max, &
        ' non-zeros in G (hypre does not report the count), one application ', &
        apply_time(p, comm, a%n_rows) * 1.0e3_rp, ' ms'
      call log%info(line)
    class default
    end select
  end subroutine report_precon

  !> Mean wall time of one application of p (20 applications to a vector of
  !> ones with n_own owned entries; the slowest rank). Collective.
  real(rp) function apply_time(p, comm, n_own)
    class(precon_t), intent(inout) :: p
    type(parallel_comm_t), intent(inout) :: comm
    integer(ip), intent(in) :: n_own
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
end module precon_factory
