!> BoomerAMG (hypre) as a preconditioner: one V-cycle from a zero initial
!> guess per application.
!>
!> setup() copies the matrix into hypre (hypre_ij_t) and builds the AMG
!> hierarchy with the settings of an amg_params_t; update() takes new values
!> in the same pattern and rebuilds the hierarchy; setup_rows() and
!> update_rows() take a matrix given row by row (hypre_ij's ij_rows_t), never
!> stored whole on our side. For systems
!> (num_functions > 1) every owned row gets a function id: by default
!> mod(global row - 1, num_functions), i.e. interleaved unknowns (our
!> displacement dofs 3*(node-1)+c), or the ids given by the caller. hypre
!> gets them explicitly (HYPRE_BoomerAMGSetDofFunc) so that the mapping does
!> not depend on how rows are split among ranks.
module boomeramg_precon
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int, c_null_ptr, c_associated, c_f_pointer, &
    c_size_t, c_sizeof, c_loc
  use kinds, only: rp, ip, gp, hypre_int, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  use amg_params, only: amg_params_t, amg_line_len
  use hypre_ij, only: hypre_ij_t, ij_rows_t, hypre_check
  use amg_cycle_c, only: gb_amg_cycle_fits, gb_amg_cycle, gb_amg_refresh_fine, gb_amg_regalerkin, &
                         gb_amg_compact_create, gb_amg_compact_free, gb_amg_fine_narrowed, &
                         gb_amg_fine_product
  use index_map, only: index_map_t
  use strings, only: lower
  use hypre_c, only: HYPRE_MEMORY_HOST, HYPRE_BoomerAMGSetRelaxOrder, HYPRE_ClearAllErrors, HYPRE_GetError, hypre_CAlloc, &
    HYPRE_BoomerAMGCreate, HYPRE_BoomerAMGDestroy, HYPRE_BoomerAMGSetup, HYPRE_BoomerAMGSolve, &
    HYPRE_BoomerAMGGetGridHierarchy, HYPRE_BoomerAMGSetTol, HYPRE_BoomerAMGSetMaxIter, &
    HYPRE_BoomerAMGSetPrintLevel, HYPRE_BoomerAMGSetNumFunctions, HYPRE_BoomerAMGSetDofFunc, &
    HYPRE_BoomerAMGSetNodal, HYPRE_BoomerAMGSetCoarsenType, HYPRE_BoomerAMGSetInterpType, &
    HYPRE_BoomerAMGSetAggNumLevels, HYPRE_BoomerAMGSetAggInterpType, &
    HYPRE_BoomerAMGSetAggPMaxElmts, HYPRE_BoomerAMGSetNumPaths, &
    HYPRE_BoomerAMGSetStrongThreshold, HYPRE_BoomerAMGSetMaxRowSum, &
    HYPRE_BoomerAMGSetMaxLevels, HYPRE_BoomerAMGSetMaxCoarseSize, &
    HYPRE_BoomerAMGSetRelaxType, HYPRE_BoomerAMGSetCycleRelaxType, &
    HYPRE_BoomerAMGSetNumSweeps, HYPRE_BoomerAMGSetRelaxWt, HYPRE_BoomerAMGSetCycleType, &
    HYPRE_BoomerAMGSetTruncFactor, HYPRE_BoomerAMGSetPMaxElmts, HYPRE_BoomerAMGSetInterpVectors, &
    HYPRE_BoomerAMGSetInterpVecVariant, HYPRE_BoomerAMGSetInterpVecQMax, HYPRE_IJVectorDestroy
  implicit none
  private

  public :: boomeramg_precon_t, amg_configure

  !> One BoomerAMG V-cycle as M^-1. Holds C handles: do not copy by
  !> assignment; call free() when done.
  type, extends(precon_t) :: boomeramg_precon_t
    type(parallel_comm_t) :: comm
    type(amg_params_t) :: params
    type(hypre_ij_t) :: ij                         !< hypre copy of A, vectors b and x
    type(c_ptr) :: solver = c_null_ptr             !< HYPRE_Solver (owned here)
    integer(hypre_int), allocatable :: dof_func(:) !< 0-based function id per owned row (systems)
    real(rp), allocatable :: modes(:,:)            !< (owned rows, k) near-null space for the interpolation
    type(c_ptr), allocatable :: mode_ij(:)         !< their IJ vectors (owned here)
    type(c_ptr), allocatable :: mode_par(:)        !< their ParVectors (hypre keeps this array)
    integer :: apply_errors = 0                    !< applications in which hypre reported an error
    ! hierarchy sizes, known after measure_hierarchy() (same on every rank)
    integer :: num_levels = 0
    integer(gp), allocatable :: level_rows(:)      !< (num_levels) global rows per level, finest first
    real(rp) :: grid_complexity = 0.0_rp           !< sum of level rows / fine rows
    logical :: own_cycle = .false.                 !< apply runs amg_cycle.c's V-cycle (set per set-up)
    !> its level values in single precision, in place (&amg precision),
    !> the finest level's in ij's matrix (ij%narrowed); its halo buffers
    !> outlive a set-up (the next one takes them over)
    type(c_ptr) :: compact = c_null_ptr
  contains
    procedure :: setup
    procedure :: setup_rows
    procedure :: update
    procedure :: update_rows
    procedure :: refresh_rows
    procedure :: matrix_product
    procedure :: apply => amg_apply
    procedure :: name => amg_name
    procedure :: measure_hierarchy
    procedure :: hierarchy_lines
    procedure :: free => amg_free
  end type boomeramg_precon_t

contains

  !> Build the preconditioner for the square matrix a with the settings
  !> params. dof_func (optional, num_functions > 1): the 0-based function id
  !> of each owned row; without it unknowns are taken as interleaved
  !> (id = mod(global row - 1, num_functions)). Nodal coarsening (nodal > 0)
  !> needs whole nodes on every rank, interleaved. Collective; times itself
  !> into setup_time (seconds). status reports, on every rank alike, bad
  !> settings, a bad dof_func, or a failure of hypre.
  subroutine setup(self, a, params, status, dof_func, modes)
    class(boomeramg_precon_t), intent(inout), target :: self
    type(csr_matrix_t), intent(in) :: a
    type(amg_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: dof_func(:)
    real(rp), intent(in), optional :: modes(:,:)   !< (owned rows, k): used with params%interp_vec_variant > 0
    real(rp) :: t0
    t0 = wall_time()
    call copy_in(self, a, params, status, dof_func, modes)
    if (.not. status%ok()) return
    call build_hierarchy(self, status)
    self%setup_time = wall_time() - t0
  end subroutine setup

  !> setup's first part: the settings, the function ids and hypre's copy
  !> of a. Collective.
  subroutine copy_in(self, a, params, status, dof_func, modes)
    class(boomeramg_precon_t), intent(inout), target :: self
    type(csr_matrix_t), intent(in) :: a
    type(amg_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: dof_func(:)
    real(rp), intent(in), optional :: modes(:,:)
    if (.not. associated(a%row_map)) then
      call self%free()
      call status%set('boomeramg_precon%setup: the matrix has no pattern')
      return
    end if
    call prepare(self, a%row_map, params, status, dof_func, modes)
    if (status%ok()) call self%ij%init(a, status)
  end subroutine copy_in

  !> The settings and the function ids over the owned rows of row_map.
  subroutine prepare(self, row_map, params, status, dof_func, modes)
    class(boomeramg_precon_t), intent(inout), target :: self
    type(index_map_t), intent(in) :: row_map
    type(amg_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: dof_func(:)
    real(rp), intent(in), optional :: modes(:,:)
    call self%free()
    call params%validate(status)
    if (.not. status%ok()) return
    self%comm = row_map%comm
    self%params = params
    call make_dof_func(self, row_map, status, dof_func)
    if (.not. status%ok()) return
    if (present(modes) .and. params%interp_vec_variant > 0) self%modes = modes
  end subroutine prepare

  !> As setup, for a matrix given row by row (hypre_ij's ij_rows_t: e.g. a
  !> sum of matrices never stored whole here). Collective.
  subroutine setup_rows(self, src, params, status, modes)
    class(boomeramg_precon_t), intent(inout), target :: self
    class(ij_rows_t), intent(in) :: src
    type(amg_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    real(rp), intent(in), optional :: modes(:,:)   !< as for setup
    real(rp) :: t0
    t0 = wall_time()
    if (.not. associated(src%row_map)) then
      call self%free()
      call status%set('boomeramg_precon%setup_rows: the matrix has no row map')
      return
    end if
    call prepare(self, src%row_map, params, status, modes=modes)
    if (status%ok()) call self%ij%init_rows(src, status)
    if (.not. status%ok()) return
    call build_hierarchy(self, status)
    self%setup_time = wall_time() - t0
  end subroutine setup_rows

  !> As update, for a matrix given row by row over the same owned rows (its
  !> pattern may differ). Collective.
  subroutine update_rows(self, src, status)
    class(boomeramg_precon_t), intent(inout), target :: self
    class(ij_rows_t), intent(in) :: src
    type(error_status_t), intent(inout) :: status
    call renew(self, 'update_rows', status, src=src)
  end subroutine update_rows

  !> A lagged update (geoblock's cycle only; otherwise update_rows): hypre's
  !> copy of the matrix anew from src (the same rows), and the hierarchy's
  !> finest level on it, with its l1 norms. The coarse levels stay those of
  !> the last set-up, or with galerkin = .true. are made anew from the new
  !> matrix with the last set-up's interpolation (P^T A P level by level:
  !> hypre's strength, coarsening and interpolation are saved, not its
  !> Galerkin products). Collective; setup_time is the time of this refresh.
  subroutine refresh_rows(self, src, status, galerkin)
    class(boomeramg_precon_t), intent(inout), target :: self
    class(ij_rows_t), intent(in) :: src
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: galerkin
    real(rp) :: t0
    logical :: coarse
    if (.not. self%own_cycle) then
      call self%update_rows(src, status)
      return
    end if
    coarse = .false.
    if (present(galerkin)) coarse = galerkin
    t0 = wall_time()
    call self%ij%rebuild_rows(src, status)
    if (.not. status%ok()) return
    if (coarse) then
      call hypre_check(self%comm, int(gb_amg_regalerkin(self%solver, self%ij%par_a), hypre_int), &
                       'boomeramg_precon: the coarse levels of a hierarchy by its interpolation', status)
      if (c_associated(self%compact)) self%compact = gb_amg_compact_create(self%solver, self%compact)
    else
      call hypre_check(self%comm, int(gb_amg_refresh_fine(self%solver, self%compact, self%ij%par_a), hypre_int), &
                       'boomeramg_precon: the finest level of a lagged hierarchy', status)
    end if
    self%ij%narrowed = gb_amg_fine_narrowed(self%compact) == 1_c_int
    self%setup_time = wall_time() - t0
  end subroutine refresh_rows

  !> New values of the matrix given to setup() (same pattern): copy them and
  !> rebuild the hierarchy with the same settings. Collective; setup_time is
  !> the time of this update.
  subroutine update(self, a, status)
    class(boomeramg_precon_t), intent(inout), target :: self
    type(csr_matrix_t), intent(in) :: a
    type(error_status_t), intent(inout) :: status
    call renew(self, 'update', status, a=a)
  end subroutine update

  !> update (a) or update_rows (src): the old hierarchy goes first (its
  !> finest level is the IJ matrix that is replaced), then hypre's copy
  !> anew and the hierarchy on it. what: the caller's name, for messages.
  subroutine renew(self, what, status, a, src)
    class(boomeramg_precon_t), intent(inout), target :: self
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    type(csr_matrix_t), intent(in), optional :: a
    class(ij_rows_t), intent(in), optional :: src
    integer(hypre_int) :: ierr
    real(rp) :: t0
    t0 = wall_time()
    if (.not. self%ij%is_ready()) then
      call status%set('boomeramg_precon%'//what//': setup() was not called')
      return
    end if
    if (c_associated(self%solver)) ierr = HYPRE_BoomerAMGDestroy(self%solver)
    self%solver = c_null_ptr
    if (present(a)) call self%ij%update_values(a, status)
    if (present(src)) call self%ij%rebuild_rows(src, status)
    if (.not. status%ok()) return
    call build_hierarchy(self, status)
    self%setup_time = wall_time() - t0
  end subroutine renew

  !> y = A x with hypre's copy of A (owned entries), rounded to single
  !> precision as the cycle holds it (&amg precision = 'single'). Collective.
  subroutine matrix_product(self, x, y)
    class(boomeramg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer(hypre_int) :: ierr
    if (.not. self%ij%is_ready()) error stop 'boomeramg_precon%matrix_product: setup() was not called'
    if (.not. c_associated(self%compact)) then
      call self%ij%matvec(x, y)
      return
    end if
    ! the values the cycle holds, alike on every rank (a rank may have
    ! kept its doubles)
    call self%ij%set_rhs(x)
    ierr = int(gb_amg_fine_product(self%compact, self%ij%par_a, self%ij%par_b, self%ij%par_x), hypre_int)
    call self%ij%get_x(y)
  end subroutine matrix_product

  !> Function id of every owned row (num_functions > 1), checked.
  subroutine make_dof_func(self, row_map, status, dof_func)
    type(boomeramg_precon_t), intent(inout) :: self
    type(index_map_t), intent(in) :: row_map
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: dof_func(:)
    integer :: nf, i
    integer(gp) :: first
    character(len=msg_len) :: msg
    logical :: bad

    nf = self%params%num_functions
    if (nf == 1) return
    first = row_map%first
    allocate(self%dof_func(row_map%n_owned))
    bad = .false.
    msg = ''
    if (present(dof_func)) then
      if (size(dof_func) /= row_map%n_owned) then
        bad = .true.
        write(msg, '(a,i0,a,i0,a)') 'boomeramg_precon%setup: dof_func has ', size(dof_func), &
          ' entries for ', row_map%n_owned, ' owned rows'
      else if (any(dof_func < 0 .or. dof_func >= nf)) then
        bad = .true.
        write(msg, '(a,i0)') 'boomeramg_precon%setup: dof_func entries must lie in 0..', nf - 1
      else
        self%dof_func = int(dof_func, hypre_int)
      end if
    else
      do i = 1, row_map%n_owned
        self%dof_func(i) = int(mod(first + i - 2, int(nf, gp)), hypre_int)
      end do
    end if
    if (.not. bad .and. self%params%nodal > 0) then
      ! hypre's nodal coarsening takes blocks of nf consecutive rows as nodes
      bad = mod(first - 1, int(nf, gp)) /= 0 .or. mod(row_map%n_owned, nf) /= 0
      if (.not. bad) then
        do i = 1, row_map%n_owned
          if (self%dof_func(i) /= mod(i - 1, nf)) bad = .true.
        end do
      end if
      if (bad) write(msg, '(a,i0,a,i0,a)') 'boomeramg_precon%setup: nodal = ', self%params%nodal, &
        ' needs whole nodes of ', nf, ' interleaved unknowns on every rank'
    end if
    if (self%comm%any_true(bad)) then
      if (.not. bad) msg = 'boomeramg_precon%setup: bad dof_func or node layout on another rank'
      call status%set(msg)
    end if
  end subroutine make_dof_func

  !> (Re)create the hypre solver with self%params and build the hierarchy of
  !> the matrix in self%ij.
  subroutine build_hierarchy(self, status)
    type(boomeramg_precon_t), intent(inout), target :: self
    type(error_status_t), intent(inout) :: status
    type(amg_params_t) :: p
    integer(hypre_int) :: ierr
    integer(hypre_int), pointer :: f(:)
    type(c_ptr) :: fp
    integer :: n, i
    logical :: no_memory

    p = self%params
    no_memory = .false.
    if (c_associated(self%solver)) ierr = HYPRE_BoomerAMGDestroy(self%solver)
    self%solver = c_null_ptr
    call free_modes(self)
    ierr = HYPRE_ClearAllErrors()
    ierr = HYPRE_BoomerAMGCreate(self%solver)
    call amg_configure(self%solver, p)
    if (allocated(self%modes)) then
      ! the near-null space (rigid-body modes) in the interpolation (GM)
      n = size(self%modes, 2)
      allocate(self%mode_ij(n), self%mode_par(n))
      do i = 1, n
        call self%ij%new_vector(self%modes(:, i), self%mode_ij(i), self%mode_par(i))
      end do
      ierr = HYPRE_BoomerAMGSetInterpVectors(self%solver, int(n, hypre_int), c_loc(self%mode_par))
      ierr = HYPRE_BoomerAMGSetInterpVecVariant(self%solver, int(p%interp_vec_variant, hypre_int))
      ierr = HYPRE_BoomerAMGSetInterpVecQMax(self%solver, int(p%interp_vec_qmax, hypre_int))
    end if
    if (p%num_functions > 1) then
      ierr = HYPRE_BoomerAMGSetNumFunctions(self%solver, int(p%num_functions, hypre_int))
      ierr = HYPRE_BoomerAMGSetNodal(self%solver, int(p%nodal, hypre_int))
      ! hypre keeps and later frees dof_func: give it memory from its own
      ! allocator (at least one entry, so that an empty rank passes no NULL)
      n = size(self%dof_func)
      fp = hypre_CAlloc(int(max(n, 1), c_size_t), c_sizeof(0_hypre_int), HYPRE_MEMORY_HOST)
      if (c_associated(fp)) then
        call c_f_pointer(fp, f, [max(n, 1)])
        f = 0
        f(1:n) = self%dof_func
        ierr = HYPRE_BoomerAMGSetDofFunc(self%solver, fp)
      else
        no_memory = .true.
      end if
    end if
    if (self%comm%any_true(no_memory)) then
      call status%set('boomeramg_precon: no memory for the dof_func array of hypre')
      return
    end if
    if (self%ij%narrowed) error stop 'boomeramg_precon: a set-up on values held as floats'
    ierr = HYPRE_BoomerAMGSetup(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x)
    call hypre_check(self%comm, HYPRE_GetError(), 'boomeramg_precon: BoomerAMG set-up', status)
    ! geoblock's cycle where it reproduces hypre's (amg_cycle.c), decided
    ! alike on every rank
    self%own_cycle = .false.
    if (status%ok() .and. lower(p%cycle_code) == 'geoblock') &
      self%own_cycle = .not. self%comm%any_true(gb_amg_cycle_fits(self%solver) /= 1_c_int)
    ! its level values in single precision where asked, in place
    ! (amg_cycle.c; the last set-up's halo buffers are taken over)
    if (self%own_cycle .and. lower(p%precision) == 'single') then
      self%compact = gb_amg_compact_create(self%solver, self%compact)
    else
      call free_compact(self)
    end if
    self%ij%narrowed = gb_amg_fine_narrowed(self%compact) == 1_c_int
    ! the sizes of the previous hierarchy no longer hold
    self%num_levels = 0
    if (allocated(self%level_rows)) deallocate(self%level_rows)
    self%grid_complexity = 0.0_rp
  end subroutine build_hierarchy

  !> Settings p on the BoomerAMG solver handle `solver` as a preconditioner
  !> (one cycle from a zero guess, no convergence test), all but the
  !> function map of systems (the caller's). Also for a BoomerAMG that
  !> another hypre solver runs (the F-relaxation or coarse grid of MGR).
  subroutine amg_configure(solver, p)
    type(c_ptr), intent(in) :: solver
    type(amg_params_t), intent(in) :: p
    integer(hypre_int) :: ierr
    integer :: down, up
    ierr = HYPRE_BoomerAMGSetTol(solver, 0.0_rp)
    ierr = HYPRE_BoomerAMGSetMaxIter(solver, 1_hypre_int)
    ierr = HYPRE_BoomerAMGSetPrintLevel(solver, int(p%print_level, hypre_int))
    ierr = HYPRE_BoomerAMGSetCoarsenType(solver, int(p%coarsen_id(), hypre_int))
    ierr = HYPRE_BoomerAMGSetInterpType(solver, int(p%interp_id(), hypre_int))
    ierr = HYPRE_BoomerAMGSetPMaxElmts(solver, int(p%p_max_elmts, hypre_int))
    ierr = HYPRE_BoomerAMGSetTruncFactor(solver, p%trunc_factor)
    ierr = HYPRE_BoomerAMGSetAggNumLevels(solver, int(p%agg_num_levels, hypre_int))
    ierr = HYPRE_BoomerAMGSetAggInterpType(solver, int(p%agg_interp_id(), hypre_int))
    ierr = HYPRE_BoomerAMGSetAggPMaxElmts(solver, int(p%agg_p_max_elmts, hypre_int))
    ierr = HYPRE_BoomerAMGSetNumPaths(solver, int(p%num_paths, hypre_int))
    ierr = HYPRE_BoomerAMGSetStrongThreshold(solver, p%strong_threshold)
    ierr = HYPRE_BoomerAMGSetMaxRowSum(solver, p%max_row_sum)
    ierr = HYPRE_BoomerAMGSetMaxLevels(solver, int(p%max_levels, hypre_int))
    ierr = HYPRE_BoomerAMGSetMaxCoarseSize(solver, int(p%max_coarse_size, hypre_int))
    call p%relax_ids(down, up)
    ierr = HYPRE_BoomerAMGSetRelaxType(solver, int(down, hypre_int))
    ierr = HYPRE_BoomerAMGSetCycleRelaxType(solver, int(down, hypre_int), 1_hypre_int)
    ierr = HYPRE_BoomerAMGSetCycleRelaxType(solver, int(up, hypre_int), 2_hypre_int)
    ierr = HYPRE_BoomerAMGSetCycleRelaxType(solver, 9_hypre_int, 3_hypre_int)
    ierr = HYPRE_BoomerAMGSetRelaxOrder(solver, int(p%relax_order_id(), hypre_int))
    ierr = HYPRE_BoomerAMGSetNumSweeps(solver, int(p%num_sweeps, hypre_int))
    ierr = HYPRE_BoomerAMGSetRelaxWt(solver, p%relax_wt)
    ierr = HYPRE_BoomerAMGSetCycleType(solver, int(p%cycle_id(), hypre_int))
  end subroutine amg_configure

  !> Destroy the IJ vectors of the near-null space (after the solver).
  subroutine free_modes(self)
    type(boomeramg_precon_t), intent(inout) :: self
    integer(hypre_int) :: ierr
    integer :: i
    if (.not. allocated(self%mode_ij)) return
    do i = 1, size(self%mode_ij)
      if (c_associated(self%mode_ij(i))) ierr = HYPRE_IJVectorDestroy(self%mode_ij(i))
    end do
    deallocate(self%mode_ij, self%mode_par)
  end subroutine free_modes

  !> Measure the hierarchy of the last set-up: num_levels, level_rows and
  !> grid_complexity, from the last level that holds each fine row. hypre
  !> does not expose the coarse operators, so the operator complexity is not
  !> available. Collective. On demand, not in every set-up, because hypre
  !> 2.26's HYPRE_BoomerAMGGetGridHierarchy leaks its work buffer (8 bytes per
  !> owned row per call): call it once for the log, not in a Newton loop.
  subroutine measure_hierarchy(self, status)
    class(boomeramg_precon_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer(hypre_int), allocatable :: cgrid(:)
    integer(hypre_int) :: ierr
    integer(gp), allocatable :: counts(:)
    integer :: l, top

    if (.not. c_associated(self%solver)) then
      call status%set('boomeramg_precon%measure_hierarchy: setup() was not called')
      return
    end if
    allocate(cgrid(max(self%ij%n_rows, 1)))
    cgrid = 0
    ierr = HYPRE_BoomerAMGGetGridHierarchy(self%solver, cgrid)
    call hypre_check(self%comm, HYPRE_GetError(), 'boomeramg_precon: reading the grid hierarchy', &
                     status)
    if (.not. status%ok()) return
    top = 0
    if (self%ij%n_rows > 0) top = maxval(cgrid(1:self%ij%n_rows))
    self%num_levels = self%comm%max(int(top, ip)) + 1
    allocate(counts(self%num_levels))
    do l = 1, self%num_levels
      counts(l) = count(cgrid(1:self%ij%n_rows) >= l - 1)
    end do
    call self%comm%sum_all(counts)
    if (allocated(self%level_rows)) deallocate(self%level_rows)
    self%level_rows = counts
    self%grid_complexity = 0.0_rp
    if (counts(1) > 0) self%grid_complexity = real(sum(counts), rp) / real(counts(1), rp)
  end subroutine measure_hierarchy

  !> z = M^-1 r: one V-cycle on A z = r from z = 0. Collective. A hypre error
  !> does not stop the run: it is counted in apply_errors (the Krylov solver
  !> will see the bad z).
  subroutine amg_apply(self, r, z)
    class(boomeramg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer(hypre_int) :: ierr
    if (.not. c_associated(self%solver)) error stop 'boomeramg_precon%apply: setup() was not called'
    ierr = HYPRE_ClearAllErrors()
    call self%ij%set_rhs(r)
    if (self%own_cycle) then
      ierr = int(gb_amg_cycle(self%solver, self%compact, self%ij%par_b, self%ij%par_x), hypre_int)
    else
      call self%ij%zero_x()
      ierr = HYPRE_BoomerAMGSolve(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x)
    end if
    call self%ij%get_x(z, ierr)
    if (ierr /= 0) self%apply_errors = self%apply_errors + 1
  end subroutine amg_apply

  function amg_name(self) result(s)
    class(boomeramg_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'boomeramg'
  end function amg_name

  !> Lines describing the hierarchy found by measure_hierarchy(), for the
  !> log: number of levels, grid complexity, rows per level.
  subroutine hierarchy_lines(self, lines)
    class(boomeramg_precon_t), intent(in) :: self
    character(len=amg_line_len), allocatable, intent(out) :: lines(:)
    integer :: l
    allocate(lines(2 + self%num_levels))
    write(lines(1), '(a,i0)') 'levels = ', self%num_levels
    write(lines(2), '(a,f0.3)') 'grid complexity = ', self%grid_complexity
    do l = 1, self%num_levels
      write(lines(2 + l), '(a,i0,a,i0)') 'level ', l - 1, ': rows = ', self%level_rows(l)
    end do
  end subroutine hierarchy_lines

  !> Frees the single-precision level values (none: nothing).
  subroutine free_compact(self)
    type(boomeramg_precon_t), intent(inout) :: self
    call gb_amg_compact_free(self%compact)
    self%compact = c_null_ptr
  end subroutine free_compact

  !> Destroy the hypre solver and matrix copy.
  subroutine amg_free(self)
    class(boomeramg_precon_t), intent(inout) :: self
    integer(hypre_int) :: ierr
    call free_compact(self)
    if (c_associated(self%solver)) ierr = HYPRE_BoomerAMGDestroy(self%solver)
    self%solver = c_null_ptr
    call free_modes(self)
    if (allocated(self%modes)) deallocate(self%modes)
    call self%ij%free()
    if (allocated(self%dof_func)) deallocate(self%dof_func)
    if (allocated(self%level_rows)) deallocate(self%level_rows)
    self%num_levels = 0
    self%grid_complexity = 0.0_rp
    self%apply_errors = 0
    ! what precon_t%free does (a binding of an abstract parent cannot be called)
    self%setup_time = 0.0_rp
  end subroutine amg_free
end module boomeramg_precon
