!> MUMPS 5.5 as a distributed sparse direct solver and exact preconditioner.
!>
!> MUMPS has a native Fortran interface (a SEQUENCE derived type and one
!> driver routine), so there is no bind(C) layer: the include below compiles
!> as it is under -std=f2008 and lives only in this module.
!>
!> Data layout:
!> - matrix: distributed assembled input (ICNTL(18)=3), each rank passes its
!>   owned rows as coordinate triplets with 1-based global ids;
!> - right-hand side: distributed (ICNTL(20)=10), each rank passes its owned
!>   entries, so no rank ever holds a vector of the global size;
!> - solution: distributed (ICNTL(21)=1). MUMPS returns on each rank the
!>   entries of the pivots it eliminated (ISOL_loc), which are not the owned
!>   rows; one alltoallv sends them to their owners. The send/receive plan
!>   depends only on the factorization, so it is built at the first solve
!>   after a set-up and reused by the following ones.
!> This keeps memory per rank proportional to the owned part and avoids
!> funnelling every application of the preconditioner through rank 0, which a
!> centralized right-hand side and solution (ICNTL(20)=ICNTL(21)=0) would do.
!>
!> That distributed layout is not repeatable bit for bit: MUMPS assembles
!> the contribution blocks that reach a front from other ranks in the order
!> the messages arrive, which varies from run to run (measured: the
!> determinant of the Sneddon contact matrix on 2 ranks changes in its
!> 15th digit between identical runs; on one process it never does). So the
!> default layout is the host layout (on_host): every rank sends its rows
!> to rank 0, one MUMPS process on rank 0 (MPI_COMM_SELF) factorizes the
!> centralized matrix (ICNTL(18)=0), and each solve gathers the right-hand
!> side on rank 0 and scatters the solution back (ICNTL(20)=ICNTL(21)=0).
!> Repeats are then bit-identical on any fixed number of ranks, at the price
!> of rank 0 holding the factors; on_host = .false. gives the distributed
!> layout above for systems whose factors do not fit one process.
!>
!> A mumps_solver_t owns a MUMPS instance: do not copy it (the copy would
!> share MUMPS' internal pointers); call free() when done.
module mumps_solver
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use kinds, only: rp, ip, gp, mumps_int, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time, self_f_handle
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use index_map, only: rank_of
  use precon, only: precon_t
  implicit none
  private

  include 'dmumps_struc.h'

  public :: mumps_solver_t

  interface
    !> The MUMPS driver (double precision); id%JOB selects the phase.
    subroutine dmumps(id)
      import :: dmumps_struc
      type(dmumps_struc), intent(inout) :: id
    end subroutine dmumps
  end interface

  ! MUMPS JOB values
  integer, parameter :: job_init = -1, job_end = -2, job_analyse = 1, job_factorize = 2, &
                        job_solve = 3
  !> ICNTL(14) for the single retry after a workspace error: one generous
  !> step, since there is no second attempt.
  integer, parameter :: retry_mem_relax = 200

  !> Direct solver: setup() analyses and factorizes A, solve()/apply() give
  !> x = A^-1 b on the owned entries of each rank.
  type, extends(precon_t) :: mumps_solver_t
    ! ---- settings, read by setup() ----
    integer :: verbosity = 0          !< 0: MUMPS silent; 1..4: MUMPS printing level ICNTL(4)
    integer :: mem_relax = -1         !< ICNTL(14), percent of workspace above the estimate; < 0: MUMPS default
    logical :: on_host = .true.       !< factorize on rank 0 alone (bit-identical repeats); else distributed
    ! ---- statistics of the last successful setup() ----
    integer(gp) :: n_global = 0       !< order of the matrix
    integer(gp) :: nnz_input = 0      !< entries passed to MUMPS (one triangle when symmetric)
    real(rp) :: analysis_time = 0.0_rp  !< seconds (max over ranks); setup_time = analysis + factorization
    real(rp) :: factor_time = 0.0_rp    !< seconds (max over ranks)
    integer :: peak_mem_max_mb = 0    !< INFOG(21): peak memory of the factorization, MB, max over ranks
    integer :: peak_mem_total_mb = 0  !< INFOG(22): the same, summed over ranks
    integer(gp) :: factor_entries = 0 !< INFOG(29): entries in the factors, all ranks
    real(rp) :: factor_flops = 0.0_rp !< RINFOG(3): flops of the elimination, all ranks
    logical :: retried = .false.      !< the factorization needed the workspace retry
    ! ---- state ----
    type(parallel_comm_t), private :: comm
    type(dmumps_struc), private :: id
    logical, private :: active = .false.    !< a MUMPS instance exists (JOB=-1 done)
    logical, private :: factored = .false.  !< factors are ready for solve()
    logical, private :: host = .false.      !< this factorization uses the host layout (on_host, several ranks)
    integer(ip), private :: n_owned = 0
    integer(gp), private :: first = 1
    integer(gp), allocatable, private :: offsets(:)  !< (0:size) first global row of each rank
    integer(ip), private :: n_sol = 0                !< solution entries MUMPS returns here (INFO(23))
    ! redistribution plan of the solution: entry k of SOL_loc goes to
    ! position send_pos(k) of the send buffer; received value m is owned entry recv_local(m)
    logical, private :: plan_ready = .false.
    integer(ip), allocatable, private :: send_count(:), recv_count(:)
    integer(ip), allocatable, private :: send_pos(:), recv_local(:)
  contains
    procedure :: setup
    procedure :: solve
    procedure :: apply => mumps_apply
    procedure :: name => mumps_name
    procedure :: free => mumps_free
    procedure :: summary
  end type mumps_solver_t

contains

  !> One line on the last factorization for the log: entries in the factors,
  !> peak memory, analysis + factorization time.
  function summary(self) result(line)
    class(mumps_solver_t), intent(in) :: self
    character(len=msg_len) :: line
    write(line, '(a,i0,a,i0,a,i0,a,f8.3,a)') '  MUMPS: ', self%factor_entries, ' entries in the factors, peak memory ', &
      self%peak_mem_max_mb, ' MB (max over ranks), ', self%peak_mem_total_mb, ' MB (total), analysis + factorization ', &
      self%setup_time, ' s'
  end function summary

  !> Analyse and factorize A (collective over A's communicator).
  !>   A         : square distributed matrix, owned rows on each rank
  !>   status    : on a MUMPS error, code = INFOG(1) (< 0) and a message with
  !>               INFOG(1), INFOG(2) and their meaning; unchanged on success
  !>   symmetric : .true.: A is symmetric; only its lower triangle (global
  !>               column <= global row) is passed and MUMPS computes an LDL^T
  !>               factorization with pivoting (SYM=2, also fine for SPD
  !>               matrices). Default .false.: LU (SYM=0).
  !> A previous factorization held by self is released first.
  subroutine setup(self, A, status, symmetric)
    class(mumps_solver_t), intent(inout) :: self
    type(csr_matrix_t), intent(in) :: A
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: symmetric
    logical :: sym
    real(rp) :: t0
    integer(ip) :: i

    sym = .false.
    if (present(symmetric)) sym = symmetric
    call self%free()
    if (.not. (associated(A%row_map) .and. associated(A%col_map))) &
      error stop 'mumps_solver%setup: the matrix has no index maps (not initialized)'
    if (A%row_map%n_global /= A%col_map%n_global) then
      call status%set('mumps_solver%setup: the matrix is not square')
      return
    end if
    if (A%row_map%n_global < 1 .or. A%row_map%n_global > int(huge(1_mumps_int), gp)) then
      call status%set('mumps_solver%setup: matrix order out of the range of MUMPS 32-bit indices')
      return
    end if
    self%comm = A%row_map%comm
    self%n_global = A%row_map%n_global
    self%n_owned = A%n_rows
    self%first = A%row_map%first
    self%offsets = A%row_map%offsets

    ! a new instance (in the host layout, on rank 0 alone)
    self%host = self%on_host .and. self%comm%size > 1
    self%id%COMM = merge(self_f_handle(), self%comm%f_handle(), self%host)
    self%id%SYM = merge(2, 0, sym)
    self%id%PAR = 1                      ! the host works too
    call run_job(self, job_init)
    if (failed(self, 'initialization', status)) return
    self%active = .true.
    ! user arrays: MUMPS never allocates them, so we own them from here on
    nullify(self%id%IRN_loc, self%id%JCN_loc, self%id%A_loc, self%id%RHS_loc, &
            self%id%IRHS_loc, self%id%SOL_loc, self%id%ISOL_loc, self%id%IRN, self%id%JCN, self%id%A, &
            self%id%RHS)
    call set_controls(self)

    ! analysis and factorization
    call fill_triplets(self, A, sym)
    if (self%host) call gather_triplets(self)
    self%id%N = int(self%n_global, mumps_int)
    t0 = wall_time()
    call run_job(self, job_analyse)
    self%analysis_time = self%comm%max(wall_time() - t0)
    if (failed(self, 'analysis', status)) then
      call free_triplets(self)
      return
    end if
    t0 = wall_time()
    call run_job(self, job_factorize)
    if (is_workspace_error(self%id%INFOG(1))) then
      self%retried = .true.
      self%id%ICNTL(14) = max(retry_mem_relax, 2 * self%id%ICNTL(14))
      call run_job(self, job_factorize)
    end if
    self%factor_time = self%comm%max(wall_time() - t0)
    call free_triplets(self)
    if (failed(self, 'factorization', status)) return
    self%setup_time = self%analysis_time + self%factor_time

    self%peak_mem_max_mb = self%id%INFOG(21)
    self%peak_mem_total_mb = self%id%INFOG(22)
    self%factor_entries = int(self%id%INFOG(29), gp)
    if (self%factor_entries < 0) self%factor_entries = -self%factor_entries * 1000000_gp
    self%factor_flops = self%id%RINFOG(3)

    self%factored = .true.
    self%plan_ready = .false.
    if (self%host) then
      ! centralized right-hand side and solution, on rank 0
      allocate(self%id%RHS(merge(int(self%n_global, ip), 1_ip, self%comm%is_root())))
      self%id%NRHS = 1
      self%id%LRHS = int(self%n_global, mumps_int)
      return
    end if
    ! distributed right-hand side (owned rows) and distributed solution
    self%n_sol = self%id%INFO(23)
    allocate(self%id%IRHS_loc(max(1, self%n_owned)), self%id%RHS_loc(max(1, self%n_owned)))
    do i = 1, self%n_owned
      self%id%IRHS_loc(i) = int(self%first + i - 1, mumps_int)
    end do
    self%id%RHS_loc = 0.0_rp
    self%id%NRHS = 1
    self%id%Nloc_RHS = self%n_owned
    self%id%LRHS_loc = max(1, self%n_owned)
    allocate(self%id%SOL_loc(max(1, self%n_sol)), self%id%ISOL_loc(max(1, self%n_sol)))
    self%id%LSOL_loc = self%n_sol
  end subroutine setup

  !> Run MUMPS phase job: on every rank, or in the host layout on rank 0
  !> alone, whose INFOG and RINFOG then reach every rank, so that all ranks
  !> take the same branch after the call.
  subroutine run_job(self, job)
    type(mumps_solver_t), intent(inout) :: self
    integer, intent(in) :: job
    integer(ip) :: info(size(self%id%INFOG))
    real(rp) :: rinfo(size(self%id%RINFOG))
    self%id%JOB = job
    if (.not. self%host) then
      call dmumps(self%id)
      return
    end if
    if (self%comm%is_root()) call dmumps(self%id)
    if (job == job_end) return
    info = int(self%id%INFOG, ip)
    rinfo = self%id%RINFOG
    call self%comm%bcast(info)
    call self%comm%bcast(rinfo)
    self%id%INFOG = int(info, mumps_int)
    self%id%RINFOG = rinfo
  end subroutine run_job

  !> Host layout: the owned triplets of every rank become the centralized
  !> matrix (IRN, JCN, A) on rank 0, in rank order. Collective.
  subroutine gather_triplets(self)
    type(mumps_solver_t), intent(inout) :: self
    integer(ip) :: scount(0:self%comm%size-1), rcount(0:self%comm%size-1)
    integer(ip) :: n, m
    integer(ip), allocatable :: ibuf(:)
    n = int(self%id%NNZ_loc, ip)
    scount = 0
    scount(0) = n
    call self%comm%alltoall_i(scount, rcount)
    m = sum(rcount)
    allocate(self%id%IRN(max(1, m)), self%id%JCN(max(1, m)), self%id%A(max(1, m)), ibuf(max(1, m)))
    call self%comm%alltoallv(int(self%id%IRN_loc(1:n), ip), scount, ibuf, rcount)
    self%id%IRN(1:m) = int(ibuf(1:m), mumps_int)
    call self%comm%alltoallv(int(self%id%JCN_loc(1:n), ip), scount, ibuf, rcount)
    self%id%JCN(1:m) = int(ibuf(1:m), mumps_int)
    call self%comm%alltoallv(self%id%A_loc(1:n), scount, self%id%A, rcount)
    self%id%NNZ = int(m, kind(self%id%NNZ))
    self%id%NZ = m
    deallocate(self%id%IRN_loc, self%id%JCN_loc, self%id%A_loc)
  end subroutine gather_triplets

  !> Controls set once per instance (after JOB=-1, which resets them).
  subroutine set_controls(self)
    type(mumps_solver_t), intent(inout) :: self
    if (self%verbosity > 0) then
      self%id%ICNTL(1) = output_unit     ! error messages
      self%id%ICNTL(2) = merge(output_unit, -1, self%verbosity >= 3)   ! per-rank diagnostics
      self%id%ICNTL(3) = output_unit     ! global information (host)
      self%id%ICNTL(4) = min(self%verbosity, 4)
    else
      ! errors still reach the caller through INFOG and the status
      self%id%ICNTL(1:3) = -1
      self%id%ICNTL(4) = 0
    end if
    self%id%ICNTL(5) = 0                 ! assembled matrix
    if (self%host) then
      self%id%ICNTL(18) = 0              ! centralized matrix on the host
      self%id%ICNTL(20) = 0              ! centralized dense right-hand side
      self%id%ICNTL(21) = 0              ! centralized solution (overwrites RHS)
      self%id%ICNTL(10) = 4              ! up to 4 steps of iterative refinement (centralized rhs only)
    else
      self%id%ICNTL(18) = 3              ! distributed: pattern at analysis, values at factorization
      self%id%ICNTL(20) = 10             ! distributed dense right-hand side
      self%id%ICNTL(21) = 1              ! distributed solution
    end if
    if (self%mem_relax >= 0) self%id%ICNTL(14) = self%mem_relax
  end subroutine set_controls

  !> Owned rows as 1-based global triplets (lower triangle only if sym).
  subroutine fill_triplets(self, A, sym)
    type(mumps_solver_t), intent(inout) :: self
    type(csr_matrix_t), intent(in) :: A
    logical, intent(in) :: sym
    integer(ip) :: i, k, n
    integer(gp) :: grow, gcol

    n = 0
    do i = 1, A%n_rows
      grow = A%row_map%first + i - 1
      do k = A%row_ptr(i), A%row_ptr(i+1) - 1
        if (sym) then
          if (A%col_map%global_id(A%col(k)) > grow) cycle
        end if
        n = n + 1
      end do
    end do
    allocate(self%id%IRN_loc(max(1, n)), self%id%JCN_loc(max(1, n)), self%id%A_loc(max(1, n)))
    n = 0
    do i = 1, A%n_rows
      grow = A%row_map%first + i - 1
      do k = A%row_ptr(i), A%row_ptr(i+1) - 1
        gcol = A%col_map%global_id(A%col(k))
        if (sym .and. gcol > grow) cycle
        n = n + 1
        self%id%IRN_loc(n) = int(grow, mumps_int)
        self%id%JCN_loc(n) = int(gcol, mumps_int)
        self%id%A_loc(n) = A%val(k)
      end do
    end do
    self%id%NNZ_loc = int(n, kind(self%id%NNZ_loc))
    self%id%NZ_loc = n
    self%nnz_input = self%comm%sum(int(n, gp))
  end subroutine fill_triplets

  !> The triplets are not needed after the factorization.
  subroutine free_triplets(self)
    type(mumps_solver_t), intent(inout) :: self
    if (associated(self%id%IRN_loc)) deallocate(self%id%IRN_loc)
    if (associated(self%id%JCN_loc)) deallocate(self%id%JCN_loc)
    if (associated(self%id%A_loc)) deallocate(self%id%A_loc)
    if (associated(self%id%IRN)) deallocate(self%id%IRN)
    if (associated(self%id%JCN)) deallocate(self%id%JCN)
    if (associated(self%id%A)) deallocate(self%id%A)
  end subroutine free_triplets

  !> Workspace errors of the factorization that a larger ICNTL(14) cures.
  logical function is_workspace_error(code)
    integer, intent(in) :: code
    select case (code)
    case (-8, -9, -17, -20)
      is_workspace_error = .true.
    case default
      is_workspace_error = .false.
    end select
  end function is_workspace_error

  !> True (and status set) when the last MUMPS call failed. INFOG is the
  !> same on every rank, so every rank takes the same branch.
  logical function failed(self, phase, status)
    type(mumps_solver_t), intent(in) :: self
    character(len=*), intent(in) :: phase
    type(error_status_t), intent(inout) :: status
    character(len=msg_len) :: msg
    failed = self%id%INFOG(1) < 0
    if (.not. failed) return
    write(msg, '(a,i0,a,i0,a)') 'mumps_solver: MUMPS '//phase//' failed: INFOG(1) = ', &
      self%id%INFOG(1), ', INFOG(2) = ', self%id%INFOG(2), ': '//infog_meaning(self%id%INFOG(1))
    call status%set(msg, self%id%INFOG(1))
  end function failed

  !> A short meaning of the common MUMPS error codes (users' guide 5.5, section
  !> "Error diagnostics").
  function infog_meaning(code) result(s)
    integer, intent(in) :: code
    character(len=:), allocatable :: s
    select case (code)
    case (-1)
      s = 'an error occurred on the rank given by INFOG(2)'
    case (-2)
      s = 'number of entries out of range'
    case (-3)
      s = 'phase called out of order (JOB)'
    case (-5, -7)
      s = 'out of memory during the analysis (INFOG(2): size requested)'
    case (-6)
      s = 'structurally singular matrix (INFOG(2): structural rank)'
    case (-8)
      s = 'integer workspace too small (raise mem_relax, ICNTL(14))'
    case (-9)
      s = 'real workspace too small (raise mem_relax, ICNTL(14))'
    case (-10)
      s = 'numerically singular matrix (INFOG(2): pivots eliminated)'
    case (-11, -14)
      s = 'workspace too small for the solve'
    case (-13)
      s = 'memory allocation failed (INFOG(2): size requested, if < 0 in millions)'
    case (-16)
      s = 'matrix order N out of range'
    case (-17, -20)
      s = 'internal MPI buffer too small (raise mem_relax, ICNTL(14))'
    case (-19)
      s = 'maximum working memory ICNTL(23) too small'
    case (-22)
      s = 'a user array is not associated or too small (INFOG(2) says which)'
    case (-40)
      s = 'matrix declared positive definite is not'
    case (-50, -51, -52)
      s = 'the fill-reducing ordering failed'
    case (-53)
      s = 'input changed between the phases'
    case default
      s = 'see "Error diagnostics" in the MUMPS 5.5 users guide'
    end select
  end function infog_meaning

  !> x = A^-1 b on the owned entries (collective).
  !>   b, x   : owned entries (size >= owned rows of the matrix of setup)
  !>   status : optional; on failure code = INFOG(1) of the MUMPS error (or 1
  !>            for a misuse). Without status, a failure stops the program.
  subroutine solve(self, b, x, status)
    class(mumps_solver_t), intent(inout) :: self
    real(rp), intent(in) :: b(:)
    real(rp), intent(out) :: x(:)
    type(error_status_t), intent(inout), optional :: status
    type(error_status_t) :: st
    real(rp), allocatable :: sbuf(:), rbuf(:)
    integer(ip) :: n

    n = self%n_owned
    if (.not. self%factored) then
      call st%set('mumps_solver%solve: no factorization (setup not called or failed)')
    else if (self%comm%any_true(size(b) < n .or. size(x) < n)) then
      call st%set('mumps_solver%solve: b or x is shorter than the owned rows on some rank')
    else if (self%host) then
      call solve_on_host(self, b, x, st)
      if (st%ok()) return
    else
      self%id%RHS_loc(1:n) = b(1:n)
      call run_job(self, job_solve)
      if (.not. failed(self, 'solve', st)) then
        if (.not. self%plan_ready) call build_plan(self, st)
      end if
    end if
    if (.not. st%ok()) then
      if (present(status)) then
        call status%set(st%msg, st%code)
        return
      end if
      write(error_unit, '(a)') trim(st%msg)
      error stop 'mumps_solver%solve failed'
    end if

    allocate(sbuf(self%n_sol), rbuf(n))
    sbuf(self%send_pos) = self%id%SOL_loc(1:self%n_sol)
    call self%comm%alltoallv(sbuf, self%send_count, rbuf, self%recv_count)
    x(self%recv_local) = rbuf
  end subroutine solve

  !> Host layout: gather b on rank 0 (rows in rank order are the global
  !> order), solve there, send each rank its owned part of x. Collective.
  subroutine solve_on_host(self, b, x, status)
    type(mumps_solver_t), intent(inout) :: self
    real(rp), intent(in) :: b(:)
    real(rp), intent(out) :: x(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: to_root(0:self%comm%size-1), per_rank(0:self%comm%size-1), none(0:self%comm%size-1)
    integer(ip) :: n
    n = self%n_owned
    to_root = 0
    to_root(0) = n
    none = 0
    per_rank = 0
    if (self%comm%is_root()) per_rank = int(self%offsets(1:) - self%offsets(:self%comm%size-1), ip)
    call self%comm%alltoallv(b(1:n), to_root, self%id%RHS, per_rank)
    call run_job(self, job_solve)
    if (failed(self, 'solve', status)) return
    if (self%comm%is_root()) then
      call self%comm%alltoallv(self%id%RHS, per_rank, x(1:n), to_root)
    else
      call self%comm%alltoallv(self%id%RHS(1:0), none, x(1:n), to_root)
    end if
  end subroutine solve_on_host

  !> Plan sending each solution entry MUMPS returned here (ISOL_loc) to the
  !> rank that owns its row. Collective; valid until the next setup.
  subroutine build_plan(self, status)
    type(mumps_solver_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: dest(:), start(:), sgid(:), rgid(:)
    integer(ip) :: np, k, p, m
    logical :: bad

    np = self%comm%size
    if (allocated(self%send_count)) deallocate(self%send_count, self%recv_count, self%send_pos, &
                                               self%recv_local)
    allocate(self%send_count(0:np-1), self%recv_count(0:np-1), start(0:np-1))
    allocate(dest(self%n_sol), self%send_pos(self%n_sol), sgid(self%n_sol))
    self%send_count = 0
    do k = 1, self%n_sol
      dest(k) = rank_of(self%offsets, int(self%id%ISOL_loc(k), gp))
      self%send_count(dest(k)) = self%send_count(dest(k)) + 1
    end do
    start(0) = 0
    do p = 1, np - 1
      start(p) = start(p-1) + self%send_count(p-1)
    end do
    do k = 1, self%n_sol
      start(dest(k)) = start(dest(k)) + 1
      self%send_pos(k) = start(dest(k))
      sgid(self%send_pos(k)) = int(self%id%ISOL_loc(k), ip)
    end do
    call self%comm%alltoall_i(self%send_count, self%recv_count)
    m = sum(self%recv_count)
    allocate(rgid(m), self%recv_local(m))
    call self%comm%alltoallv(sgid, self%send_count, rgid, self%recv_count)
    do k = 1, m
      self%recv_local(k) = int(int(rgid(k), gp) - self%first, ip) + 1
    end do
    ! each owned entry must arrive exactly once
    bad = m /= self%n_owned
    if (.not. bad .and. m > 0) bad = minval(self%recv_local) < 1 .or. maxval(self%recv_local) > self%n_owned
    if (self%comm%any_true(bad)) then
      call status%set('mumps_solver: the distributed solution of MUMPS does not cover the owned rows')
      return
    end if
    self%plan_ready = .true.
  end subroutine build_plan

  !> z = A^-1 r (the exact preconditioner). precon_t%apply has no status,
  !> so a MUMPS failure here stops the program (on every rank: INFOG is global).
  subroutine mumps_apply(self, r, z)
    class(mumps_solver_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    call self%solve(r, z)
  end subroutine mumps_apply

  !> 'mumps', as in the deck.
  function mumps_name(self) result(s)
    class(mumps_solver_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'mumps'
  end function mumps_name

  !> Release the factors, the MUMPS instance and the work arrays
  !> (collective when a factorization exists). Settings are kept.
  subroutine mumps_free(self)
    class(mumps_solver_t), intent(inout) :: self
    if (self%active) then
      call free_triplets(self)
      if (associated(self%id%RHS_loc)) deallocate(self%id%RHS_loc)
      if (associated(self%id%IRHS_loc)) deallocate(self%id%IRHS_loc)
      if (associated(self%id%SOL_loc)) deallocate(self%id%SOL_loc)
      if (associated(self%id%ISOL_loc)) deallocate(self%id%ISOL_loc)
      if (associated(self%id%RHS)) deallocate(self%id%RHS)
      call run_job(self, job_end)
    end if
    self%active = .false.
    self%factored = .false.
    self%plan_ready = .false.
    if (allocated(self%offsets)) deallocate(self%offsets)
    if (allocated(self%send_count)) deallocate(self%send_count, self%recv_count, self%send_pos, &
                                               self%recv_local)
    self%n_owned = 0
    self%n_sol = 0
    self%n_global = 0
    self%nnz_input = 0
    self%analysis_time = 0.0_rp
    self%factor_time = 0.0_rp
    self%peak_mem_max_mb = 0
    self%peak_mem_total_mb = 0
    self%factor_entries = 0
    self%factor_flops = 0.0_rp
    self%retried = .false.
    ! what precon_t%free does (a binding of an abstract parent cannot be called)
    self%setup_time = 0.0_rp
  end subroutine mumps_free

end module mumps_solver
