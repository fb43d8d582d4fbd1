!> hypre's adaptive FSAI (HYPRE_FSAI*, hypre 2.26) as a preconditioner:
!> M^-1 = G^T G with G a sparse lower triangular approximation of the
!> inverse Cholesky factor of an SPD matrix A. It is here as the reference
!> that benchmarks compare geoblock's own adaptive FSAI against.
!>
!> setup() copies the matrix into hypre (hypre_ij_t) and lets hypre build G
!> with the adaptive pattern search of Janna and Ferronato (SIAM J. Sci.
!> Comput. 33(6), 2011, 3357-3380; also FSAIPACK, ACM TOMS 41(2), 2015): a
!> row's pattern grows in up to max_steps steps of at most step_size entries
!> each, the entries of largest Kaporin-number gradient first, and stops
!> early once a step lowers that row's Kaporin number by less than the
!> fraction kap_tol (hypre's par_fsai_setup.c). apply() is one step of hypre's
!> FSAI Richardson iteration from a zero guess with omega = 1, i.e.
!> z = G^T G r.
!>
!> Facts of hypre 2.26 that a comparison must know (hypre's sources,
!> src/parcsr_ls/par_fsai_setup.c and par_fsai_solve.c):
!> - G is built from the rank-local block of A only (the ParCSR "diag"
!>   part): on p ranks G is block diagonal with one block per rank, so the
!>   preconditioner, and the iteration counts, depend on the rank count.
!> - a row of G holds at most max_steps*step_size + 1 entries.
!> - hypre keeps G in its private solver data and has no public accessor
!>   for G or its number of non-zeros (the density is only printed, by
!>   print level 1). nnz_g therefore stays -1 (unknown); nnz_g_max is the
!>   bound above, summed over the rows.
module hypre_fsai_precon
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, hypre_int, hypre_real, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  use hypre_ij, only: hypre_ij_t, hypre_check
  use hypre_c, only: HYPRE_ClearAllErrors, HYPRE_FSAICreate, HYPRE_FSAIDestroy, HYPRE_FSAISetup, &
    HYPRE_FSAISolve, HYPRE_FSAISetAlgoType, HYPRE_FSAISetMaxSteps, HYPRE_FSAISetMaxStepSize, &
    HYPRE_FSAISetKapTolerance, HYPRE_FSAISetOmega, HYPRE_FSAISetMaxIterations, &
    HYPRE_FSAISetEigMaxIters, HYPRE_FSAISetTolerance, HYPRE_FSAISetPrintLevel, &
    HYPRE_FSAISetZeroGuess
  implicit none
  private

  public :: hypre_fsai_precon_t

  !> The hypre calls of a set-up, in order; their position is the id that
  !> the ranks agree on when one fails.
  integer, parameter :: n_calls = 12
  character(len=*), parameter :: call_names(n_calls) = [character(len=26) :: &
    'HYPRE_FSAICreate', 'HYPRE_FSAISetAlgoType', 'HYPRE_FSAISetMaxSteps', &
    'HYPRE_FSAISetMaxStepSize', 'HYPRE_FSAISetKapTolerance', 'HYPRE_FSAISetOmega', &
    'HYPRE_FSAISetMaxIterations', 'HYPRE_FSAISetEigMaxIters', 'HYPRE_FSAISetTolerance', &
    'HYPRE_FSAISetPrintLevel', 'HYPRE_FSAISetZeroGuess', 'HYPRE_FSAISetup']

  !> hypre's FSAI as M^-1 = G^T G. Holds C handles: do not copy by
  !> assignment; call free() when done.
  type, extends(precon_t) :: hypre_fsai_precon_t
    type(parallel_comm_t) :: comm
    type(hypre_ij_t) :: ij                   !< hypre copy of A, vectors b and x
    type(c_ptr) :: solver = c_null_ptr       !< HYPRE_Solver (owned here)
    logical :: ready = .false.               !< set-up succeeded
    integer :: max_steps = 0                 !< settings of the last set-up
    integer :: step_size = 0
    real(rp) :: kap_tol = 0.0_rp
    integer(gp) :: n_global = 0              !< global rows of A
    integer(gp) :: nnz_g = -1_gp             !< global non-zeros of G: unknown (no hypre accessor)
    integer(gp) :: nnz_g_max = -1_gp         !< bound: n_global * (max_steps*step_size + 1)
    real(rp) :: factor_time = 0.0_rp         !< seconds in HYPRE_FSAISetup (part of setup_time)
    integer :: apply_errors = 0              !< applications in which hypre reported an error
  contains
    procedure :: setup
    procedure :: apply => fsai_apply
    procedure :: name => fsai_name
    procedure :: free => fsai_free
  end type hypre_fsai_precon_t

contains

  !> Build G for the SPD matrix a (square, rows and columns owned alike):
  !> max_steps (>= 0) pattern steps of at most step_size (>= 0) entries per
  !> row, a row's search stopping once a step lowers its Kaporin number by
  !> less than the fraction kap_tol (>= 0; 0 never stops early). hypre's
  !> defaults are 3, 5, 1e-3. Collective; times itself into setup_time
  !> (seconds, the copy into hypre included; factor_time is hypre's part).
  !> status reports, on every rank alike, a bad argument by name, a matrix
  !> that hypre_ij refuses, or the first hypre call that failed.
  subroutine setup(self, a, max_steps, step_size, kap_tol, status)
    class(hypre_fsai_precon_t), intent(inout) :: self
    type(csr_matrix_t), intent(in) :: a
    integer, intent(in) :: max_steps, step_size
    real(rp), intent(in) :: kap_tol
    type(error_status_t), intent(inout) :: status
    character(len=msg_len) :: msg
    real(rp) :: t0, t1
    integer :: first_bad
    integer(hypre_int) :: ierr, first_ierr

    t0 = wall_time()
    call self%free()
    ! the arguments are the same on every rank: no agreement needed
    msg = ''
    if (max_steps < 0) then
      write(msg, '(a,i0,a)') 'hypre_fsai_precon%setup: max_steps = ', max_steps, ' must be >= 0'
    else if (step_size < 0) then
      write(msg, '(a,i0,a)') 'hypre_fsai_precon%setup: step_size = ', step_size, ' must be >= 0'
    else if (.not. (ieee_is_finite(kap_tol) .and. kap_tol >= 0.0_rp)) then
      write(msg, '(a,es10.3,a)') 'hypre_fsai_precon%setup: kap_tol = ', kap_tol, &
        ' must be finite and >= 0'
    else if (.not. associated(a%row_map)) then
      msg = 'hypre_fsai_precon%setup: the matrix has no pattern'
    end if
    if (len_trim(msg) > 0) then
      call status%set(trim(msg))
      return
    end if
    self%comm = a%row_map%comm
    self%max_steps = max_steps
    self%step_size = step_size
    self%kap_tol = kap_tol
    self%n_global = a%row_map%n_global
    self%nnz_g = -1_gp
    self%nnz_g_max = self%n_global * (int(max_steps, gp) * int(step_size, gp) + 1_gp)

    call self%ij%init(a, status)
    if (.not. status%ok()) then
      call self%free()
      return
    end if

    ! hypre's error flag is global and sticky, and every call returns it:
    ! the first call that returns nonzero is the one that failed
    first_bad = 0
    first_ierr = 0
    ierr = HYPRE_ClearAllErrors()
    call track(HYPRE_FSAICreate(self%solver), 1, first_bad, first_ierr)
    ! the native algorithm (2 is its OpenMP variant; Debian's hypre has no OpenMP)
    call track(HYPRE_FSAISetAlgoType(self%solver, 1_hypre_int), 2, first_bad, first_ierr)
    call track(HYPRE_FSAISetMaxSteps(self%solver, int(max_steps, hypre_int)), 3, first_bad, first_ierr)
    call track(HYPRE_FSAISetMaxStepSize(self%solver, int(step_size, hypre_int)), 4, first_bad, &
               first_ierr)
    call track(HYPRE_FSAISetKapTolerance(self%solver, real(kap_tol, hypre_real)), 5, first_bad, &
               first_ierr)
    ! a preconditioner: one Richardson step x = omega G^T G b from x = 0,
    ! with omega = 1 kept (no eigenvalue estimate replaces it) and no
    ! convergence test
    call track(HYPRE_FSAISetOmega(self%solver, 1.0_hypre_real), 6, first_bad, first_ierr)
    call track(HYPRE_FSAISetMaxIterations(self%solver, 1_hypre_int), 7, first_bad, first_ierr)
    call track(HYPRE_FSAISetEigMaxIters(self%solver, 0_hypre_int), 8, first_bad, first_ierr)
    call track(HYPRE_FSAISetTolerance(self%solver, 0.0_hypre_real), 9, first_bad, first_ierr)
    call track(HYPRE_FSAISetPrintLevel(self%solver, 0_hypre_int), 10, first_bad, first_ierr)
    call track(HYPRE_FSAISetZeroGuess(self%solver, 1_hypre_int), 11, first_bad, first_ierr)
    call agree(self, first_bad, first_ierr, status)
    if (.not. status%ok()) return

    t1 = wall_time()
    call track(HYPRE_FSAISetup(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x), 12, &
               first_bad, first_ierr)
    call agree(self, first_bad, first_ierr, status)
    if (.not. status%ok()) return
    self%factor_time = wall_time() - t1
    self%ready = .true.
    self%setup_time = wall_time() - t0
  end subroutine setup

  !> Remember the id of the first call of a sequence whose flag ierr is nonzero.
  subroutine track(ierr, id, first_bad, first_ierr)
    integer(hypre_int), intent(in) :: ierr
    integer, intent(in) :: id
    integer, intent(inout) :: first_bad
    integer(hypre_int), intent(inout) :: first_ierr
    if (ierr /= 0 .and. first_bad == 0) then
      first_bad = id
      first_ierr = ierr
    end if
  end subroutine track

  !> Collective: when a hypre call failed on some rank, status names the
  !> earliest failed call over the ranks (the same message everywhere) and
  !> the hypre objects are released.
  subroutine agree(self, first_bad, first_ierr, status)
    type(hypre_fsai_precon_t), intent(inout) :: self
    integer, intent(in) :: first_bad
    integer(hypre_int), intent(in) :: first_ierr
    type(error_status_t), intent(inout) :: status
    integer(ip) :: id
    id = n_calls + 1
    if (first_bad > 0) id = int(first_bad, ip)
    id = self%comm%min(id)
    if (id > n_calls) return
    call hypre_check(self%comm, first_ierr, 'hypre_fsai_precon%setup: '//trim(call_names(id)), status)
    call self%free()
  end subroutine agree

  !> z = G^T G r: one FSAI step from a zero guess. Collective. A hypre error
  !> does not stop the run: it is counted in apply_errors (the Krylov solver
  !> will see the bad z).
  subroutine fsai_apply(self, r, z)
    class(hypre_fsai_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer(hypre_int) :: ierr
    if (.not. self%ready) error stop 'hypre_fsai_precon%apply: setup() was not called or failed'
    ierr = HYPRE_ClearAllErrors()
    call self%ij%set_rhs(r)
    ! hypre ignores x with the zero guess on; zeroing it anyway keeps the
    ! result independent of the previous application should it not
    call self%ij%zero_x()
    ierr = HYPRE_FSAISolve(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x)
    call self%ij%get_x(z, ierr)
    if (ierr /= 0) self%apply_errors = self%apply_errors + 1
  end subroutine fsai_apply

  function fsai_name(self) result(s)
    class(hypre_fsai_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'hypre_fsai'
  end function fsai_name

  !> Destroy the hypre solver and matrix copy; forget the settings.
  subroutine fsai_free(self)
    class(hypre_fsai_precon_t), intent(inout) :: self
    integer(hypre_int) :: ierr
    if (c_associated(self%solver)) ierr = HYPRE_FSAIDestroy(self%solver)
    self%solver = c_null_ptr
    call self%ij%free()
    self%ready = .false.
    self%max_steps = 0
    self%step_size = 0
    self%kap_tol = 0.0_rp
    self%n_global = 0
    self%nnz_g = -1_gp
    self%nnz_g_max = -1_gp
    self%factor_time = 0.0_rp
    self%apply_errors = 0
    ! what precon_t%free does (a binding of an abstract parent cannot be called)
    self%setup_time = 0.0_rp
  end subroutine fsai_free
end module hypre_fsai_precon
