!> hypre's MGR (multigrid reduction) on a whole block system, one cycle per
!> application: the peer of our block preconditioners (&solver precon =
!> 'mgr'), on the very distributed matrices they see.
!>
!> MGR reduces the system level by level: at each level the F-points (the
!> labels not kept) are relaxed, interpolated and restricted, and the kept
!> labels (C-points) form the next level's system; the last is solved by
!> BoomerAMG. Every row carries a label (the point marker array), here one
!> per block and displacement or traction component. The strategies follow
!> GEOS's (src/coreComponents/linearAlgebra/interfaces/hypre/mgrStrategies,
!> GEOS-DEV/GEOS: SinglePhasePoromechanics, HybridSinglePhasePoromechanics,
!> LagrangianContactMechanics), adapted to our blocks:
!>   biot (u, q, p): level 0 keeps q and p: F = u relaxed by one BoomerAMG
!>     V-cycle (our &amg settings, three functions), Jacobi interpolation,
!>     injection, non-Galerkin coarse grid (A_FF^-1 by its diagonal); level
!>     1 keeps p: F = q by Jacobi, Jacobi interpolation, injection, Galerkin;
!>     p by BoomerAMG.
!>   contact (u, t): level 0 keeps u: F = t by one l1-Jacobi sweep,
!>     block-Jacobi interpolation (3 x 3 blocks of an element's tractions),
!>     injection, Galerkin; u by BoomerAMG (no separate components, as GEOS).
!>   fracture flow (u, t, p): the contact level first (keeps u and p), then
!>     p as F by Jacobi, Jacobi interpolation, injection, Galerkin; u by
!>     BoomerAMG.
!>   poromechanics with faults (u, q, pm, t, p): level 0 keeps q, pm, t,
!>     p: F = u by one BoomerAMG V-cycle (ours, three functions), Jacobi
!>     interpolation, injection, non-Galerkin (Biot's first level); level 1
!>     keeps q, pm, p: F = t by l1-Jacobi, block-Jacobi interpolation,
!>     injection, Galerkin (the contact's level, on the tractions' Schur
!>     complement after u); level 2 keeps pm, p: F = q by Jacobi, Jacobi
!>     interpolation, injection, Galerkin; the two pressures together by
!>     BoomerAMG, as our block preconditioner's group. The contact's order
!>     (t first, then u) leaves u to an F-relaxation at a later level, which
!>     hypre 2.26 does by its own one-function BoomerAMG (a user's F-solver
!>     only at the first level): 47 and 85 FGMRES iterations at 8^3 and 16^3
!>     cells (tests/decks/poro_faults_states.nml, step 3, Newton 2) against
!>     36 and 39 in this order.
!> Level settings are hypre 2.26's codes (HYPRE_parcsr_ls.h): F-relaxation
!> 0 Jacobi, 2 AMG, 18 l1-Jacobi; interpolation 2 Jacobi, 12 block Jacobi;
!> restriction 0 injection; coarse grid 0 Galerkin, 1 non-Galerkin.
module mgr_precon
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_loc, c_funloc
  use kinds, only: rp, ip, hypre_int, name_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use index_map, only: index_map_t
  use block_matrix, only: block_matrix_t
  use precon, only: precon_t
  use amg_params, only: amg_params_t
  use hypre_ij, only: hypre_ij_t, hypre_check
  use boomeramg_precon, only: amg_configure
  use hypre_c, only: HYPRE_ClearAllErrors, HYPRE_GetError, HYPRE_BoomerAMGCreate, HYPRE_BoomerAMGDestroy, &
    HYPRE_BoomerAMGSetup, HYPRE_BoomerAMGSolve, HYPRE_BoomerAMGSetNumFunctions, &
    HYPRE_MGRCreate, HYPRE_MGRDestroy, HYPRE_MGRSetup, HYPRE_MGRSolve, &
    HYPRE_MGRSetCpointsByPointMarkerArray, HYPRE_MGRSetNonCpointsToFpoints, HYPRE_MGRSetMaxCoarseLevels, &
    HYPRE_MGRSetLevelFRelaxType, HYPRE_MGRSetCoarseGridMethod, HYPRE_MGRSetLevelInterpType, &
    HYPRE_MGRSetLevelRestrictType, HYPRE_MGRSetLevelNumRelaxSweeps, HYPRE_MGRSetFSolver, &
    HYPRE_MGRSetCoarseSolver, HYPRE_MGRSetMaxIter, HYPRE_MGRSetTol, HYPRE_MGRSetPrintLevel, &
    HYPRE_MGRSetPMaxElmts, HYPRE_MGRSetMaxGlobalSmoothIters
  implicit none
  private

  public :: mgr_precon_t, mgr_strategy_t, mgr_biot, mgr_contact, mgr_flow, mgr_poro_faults

  integer, parameter :: max_levels = 3, max_labels = 9

  !> The reduction: labels kept at each level and the level settings.
  type :: mgr_strategy_t
    character(len=name_len) :: name = ''
    integer :: n_labels = 0, n_levels = 0
    integer :: n_kept(max_levels) = 0
    integer(hypre_int) :: kept(max_labels, max_levels) = 0
    integer(hypre_int) :: frelax(max_levels) = 0, interp(max_levels) = 2, restrict(max_levels) = 0
    integer(hypre_int) :: cg_method(max_levels) = 0, sweeps(max_levels) = 1
    integer :: coarse_functions = 1                !< functions of the last level's BoomerAMG
  end type mgr_strategy_t

  !> One MGR cycle as M^-1. Holds C handles: do not copy by assignment.
  type, extends(precon_t) :: mgr_precon_t
    type(parallel_comm_t) :: comm
    type(hypre_ij_t) :: ij
    type(c_ptr) :: solver = c_null_ptr, coarse = c_null_ptr, fsolver = c_null_ptr
    integer(hypre_int), allocatable :: marker(:)   !< label of every owned row (hypre keeps a pointer)
    type(mgr_strategy_t) :: strategy
    integer :: apply_errors = 0
  contains
    procedure :: setup
    procedure :: setup_blocks
    procedure :: apply => mgr_apply
    procedure :: name => mgr_name
    procedure :: free => mgr_free
  end type mgr_precon_t

contains

  !> Biot, labels u x, y, z = 0, 1, 2, q = 3, p = 4.
  function mgr_biot() result(s)
    type(mgr_strategy_t) :: s
    s%name = 'biot'
    s%n_labels = 5
    s%n_levels = 2
    s%n_kept(1:2) = [2, 1]
    s%kept(1:2, 1) = [3, 4]
    s%kept(1, 2) = 4
    s%frelax(1:2) = [2, 0]
    s%interp(1:2) = [2, 2]
    s%restrict(1:2) = [0, 0]
    s%cg_method(1:2) = [1, 0]
  end function mgr_biot

  !> Contact, labels u x, y, z = 0, 1, 2, t normal, tangential = 3, 4, 5.
  function mgr_contact() result(s)
    type(mgr_strategy_t) :: s
    s%name = 'contact'
    s%n_labels = 6
    s%n_levels = 1
    s%n_kept(1) = 3
    s%kept(1:3, 1) = [0, 1, 2]
    s%frelax(1) = 18
    s%interp(1) = 12
    s%restrict(1) = 0
    s%cg_method(1) = 0
  end function mgr_contact

  !> Fracture flow, labels u = 0, 1, 2, t = 3, 4, 5, p = 6.
  function mgr_flow() result(s)
    type(mgr_strategy_t) :: s
    s = mgr_contact()
    s%name = 'fracture flow'
    s%n_labels = 7
    s%n_levels = 2
    s%n_kept(1:2) = [4, 3]
    s%kept(1:4, 1) = [0, 1, 2, 6]
    s%kept(1:3, 2) = [0, 1, 2]
    s%frelax(2) = 0
    s%interp(2) = 2
    s%restrict(2) = 0
    s%cg_method(2) = 0
  end function mgr_flow

  !> Poromechanics with faults, labels u = 0, 1, 2, q = 3, pm = 4, t = 5,
  !> 6, 7, p = 8 (the components' order: mechanics, matrix flow, contact,
  !> fracture flow): u, then t, then q; (pm, p) on the last level.
  function mgr_poro_faults() result(s)
    type(mgr_strategy_t) :: s
    s%name = 'poromechanics with faults'
    s%n_labels = 9
    s%n_levels = 3
    s%n_kept(1:3) = [6, 3, 2]
    s%kept(1:6, 1) = [3, 4, 5, 6, 7, 8]
    s%kept(1:3, 2) = [3, 4, 8]
    s%kept(1:2, 3) = [4, 8]
    s%frelax(1:3) = [2, 18, 0]
    s%interp(1:3) = [2, 12, 2]
    s%restrict(1:3) = [0, 0, 0]
    s%cg_method(1:3) = [1, 0, 0]
  end function mgr_poro_faults

  !> Build MGR for the square monolithic matrix a, label(i) the strategy's
  !> label of owned row i, amg the settings of its BoomerAMGs. Collective;
  !> setup_time is its seconds. status reports a hypre failure on every
  !> rank alike.
  subroutine setup(self, a, label, strategy, amg, status)
    class(mgr_precon_t), intent(inout), target :: self
    type(csr_matrix_t), intent(in) :: a
    integer, intent(in) :: label(:)
    type(mgr_strategy_t), intent(in) :: strategy
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    integer(hypre_int), allocatable, target :: levels(:,:)
    type(c_ptr) :: ptrs(max_levels)
    integer(hypre_int) :: ierr
    integer :: l
    real(rp) :: t0
    t0 = wall_time()
    call self%free()
    self%comm = a%row_map%comm
    self%strategy = strategy
    call self%ij%init(a, status)
    if (.not. status%ok()) return
    ! at least one entry, so that a rank without rows passes no NULL
    allocate(self%marker(max(size(label), 1)))
    self%marker = 0
    self%marker(1:size(label)) = int(label, hypre_int)
    allocate(levels(max_labels, max_levels))
    levels = strategy%kept
    do l = 1, max_levels
      ptrs(l) = c_loc(levels(1, l))
    end do
    ierr = HYPRE_ClearAllErrors()
    ierr = HYPRE_MGRCreate(self%solver)
    ierr = HYPRE_MGRSetCpointsByPointMarkerArray(self%solver, int(strategy%n_labels, hypre_int), &
      int(strategy%n_levels, hypre_int), int(strategy%n_kept, hypre_int), ptrs, c_loc(self%marker))
    ierr = HYPRE_MGRSetNonCpointsToFpoints(self%solver, 1_hypre_int)
    ierr = HYPRE_MGRSetMaxCoarseLevels(self%solver, int(strategy%n_levels, hypre_int))
    ierr = HYPRE_MGRSetLevelFRelaxType(self%solver, strategy%frelax)
    ierr = HYPRE_MGRSetLevelNumRelaxSweeps(self%solver, strategy%sweeps)
    ierr = HYPRE_MGRSetLevelInterpType(self%solver, strategy%interp)
    ierr = HYPRE_MGRSetLevelRestrictType(self%solver, strategy%restrict)
    ierr = HYPRE_MGRSetCoarseGridMethod(self%solver, strategy%cg_method)
    ierr = HYPRE_MGRSetMaxGlobalSmoothIters(self%solver, 0_hypre_int)
    ierr = HYPRE_MGRSetPMaxElmts(self%solver, 0_hypre_int)
    ierr = HYPRE_MGRSetPrintLevel(self%solver, 0_hypre_int)
    ierr = HYPRE_MGRSetMaxIter(self%solver, 1_hypre_int)
    ierr = HYPRE_MGRSetTol(self%solver, 0.0_rp)
    if (strategy%frelax(1) == 2) then
      ! the first level's F-points (the displacement) by our BoomerAMG
      ierr = HYPRE_BoomerAMGCreate(self%fsolver)
      call amg_configure(self%fsolver, amg)
      ierr = HYPRE_BoomerAMGSetNumFunctions(self%fsolver, 3_hypre_int)
      ierr = HYPRE_MGRSetFSolver(self%solver, c_funloc(HYPRE_BoomerAMGSolve), c_funloc(HYPRE_BoomerAMGSetup), &
                                 self%fsolver)
    end if
    ierr = HYPRE_BoomerAMGCreate(self%coarse)
    call amg_configure(self%coarse, amg)
    ierr = HYPRE_BoomerAMGSetNumFunctions(self%coarse, int(strategy%coarse_functions, hypre_int))
    ierr = HYPRE_MGRSetCoarseSolver(self%solver, c_funloc(HYPRE_BoomerAMGSolve), c_funloc(HYPRE_BoomerAMGSetup), &
                                    self%coarse)
    ierr = HYPRE_MGRSetup(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x)
    call hypre_check(self%comm, HYPRE_GetError(), 'mgr_precon: MGR set-up ('//trim(strategy%name)//')', status)
    self%setup_time = wall_time() - t0
  end subroutine setup

  !> Build MGR for the block matrix bm (its monolithic copy): the rows of
  !> block i get the labels first_label(i) + (0 .. ncomp(i) - 1), cycling
  !> over the block's interleaved components. Collective.
  subroutine setup_blocks(self, bm, ncomp, first_label, strategy, amg, status)
    class(mgr_precon_t), intent(inout), target :: self
    type(block_matrix_t), intent(in) :: bm
    integer, intent(in) :: ncomp(:), first_label(:)
    type(mgr_strategy_t), intent(in) :: strategy
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    type(index_map_t), target :: cmap
    type(csr_matrix_t) :: mono
    integer, allocatable :: label(:)
    integer(ip) :: i, r
    real(rp) :: t0
    t0 = wall_time()
    call bm%monolithic(cmap, mono)
    allocate(label(bm%offset(bm%nb + 1)))
    do i = 1, bm%nb
      do r = bm%offset(i) + 1, bm%offset(i + 1)
        label(r) = first_label(i) + int(mod(r - bm%offset(i) - 1, int(ncomp(i), ip)))
      end do
    end do
    call self%setup(mono, label, strategy, amg, status)
    call mono%free()
    call cmap%free()
    self%setup_time = wall_time() - t0
  end subroutine setup_blocks

  !> z = M^-1 r: one MGR cycle from z = 0. Collective. A hypre error is
  !> counted in apply_errors (the Krylov solver sees the bad z).
  subroutine mgr_apply(self, r, z)
    class(mgr_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer(hypre_int) :: ierr
    if (.not. c_associated(self%solver)) error stop 'mgr_precon%apply: setup() was not called'
    ierr = HYPRE_ClearAllErrors()
    call self%ij%set_rhs(r)
    call self%ij%zero_x()
    ierr = HYPRE_MGRSolve(self%solver, self%ij%par_a, self%ij%par_b, self%ij%par_x)
    call self%ij%get_x(z, ierr)
    if (ierr /= 0) self%apply_errors = self%apply_errors + 1
  end subroutine mgr_apply

  function mgr_name(self) result(s)
    class(mgr_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'mgr'
  end function mgr_name

  subroutine mgr_free(self)
    class(mgr_precon_t), intent(inout) :: self
    integer(hypre_int) :: ierr
    if (c_associated(self%solver)) ierr = HYPRE_MGRDestroy(self%solver)
    if (c_associated(self%coarse)) ierr = HYPRE_BoomerAMGDestroy(self%coarse)
    if (c_associated(self%fsolver)) ierr = HYPRE_BoomerAMGDestroy(self%fsolver)
    self%solver = c_null_ptr
    self%coarse = c_null_ptr
    self%fsolver = c_null_ptr
    call self%ij%free()
    if (allocated(self%marker)) deallocate(self%marker)
    self%apply_errors = 0
    self%setup_time = 0.0_rp
  end subroutine mgr_free
end module mgr_precon
