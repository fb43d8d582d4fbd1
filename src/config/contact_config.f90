!> Deck group &contact: the discretization of the contact conditions on the
!> faults (&fault groups) and the active-set / Newton driver (physics =
!> 'contact' and 'fracture_flow').
!>
!>   space          the discretization: 'stabilized' (Q1 displacements, P0
!>                  tractions, not inf-sup stable: needs the stabilization)
!>                  or 'bubble' (Q1 enriched with a face bubble per interface
!>                  face and side, P0 tractions: stable, a pure saddle point;
!>                  physics 'contact' only)                          ['stabilized']
!>   stabilization  'algebraic' (the jump stabilization H_t of Franceschini et
!>                  al., CMAME 368 (2020) 113161, needed by the Q1-P0 pair) or
!>                  'none' (the bare saddle point; use block = 'augmented');
!>                  space 'bubble' has none, and refuses 'algebraic'
!>                                          ['algebraic'; 'none' for 'bubble']
!>   block          preconditioner of the (u, t) system with method = 'fgmres':
!>                  'reordered' (t first; S* = K + C1 H~^-1 C2 with a regular
!>                  diagonal H~, BoomerAMG), 'classical' (u first; explicit
!>                  S = -H_t - C2 diag(K)^-1 C1, preconditioned by schur_precon)
!>                  or 'augmented' (reordered with H~ = D, the augmentation
!>                  diagonal, whatever H_t is)
!>                  (fracture_flow: 'reordered' only)
!>                                      ['reordered'; 'augmented' for 'bubble']
!>   schur_precon   classical: 'boomeramg' or 'jacobi' for -S        ['boomeramg']
!>   aug_scale      scale of the regular diagonal H~ (and D), > 0          [1]
!>   schur_solve    reordered, augmented: how S* is applied: 'vcycle' (one
!>                  BoomerAMG cycle), 'pcg' (schur_its steps of CG with
!>                  BoomerAMG from zero: a stronger, flexible preconditioner
!>                  whose counts grow less with the mesh) or 'inner_cg' (CG +
!>                  BoomerAMG to 1e-10, a near-exact solve: a diagnostic that
!>                  separates the Schur approximation from the AMG; slow)
!>                  ['pcg' for the reordered preconditioner of contact alone:
!>                  flat counts (with the inexact Newton loop the V-cycle
!>                  is ~10 % faster up to n = 40: contact.md);
!>                  'vcycle' with a fluid, where the saved iterations do not
!>                  pay for the second cycle, and for the other blocks; the
!>                  composition resolves it: resolve_schur_solve]
!>   schur_its      schur_solve = 'pcg': CG steps per application, 1..50  [2]
!>   max_newton     Newton / active-set iterations per step, >= 1          [30]
!>   newton_tol     the Newton loop's tolerance, per field, on the residual of
!>                  the iterate in physical units: force [N] against the
!>                  largest of the loads, K u and the faces' forces;
!>                  traction [Pa] (each contact row over its element's
!>                  scale s) against the tractions and fluid pressures; with
!>                  the fluid, volume of the step [m^3] against the sum of
!>                  the mass rows' terms. A step has converged when every
!>                  field is within newton_tol (or at round-off: 16 eps
!>                  times its terms' operands) and the last update changed
!>                  no status. In (0, 1)                              [1e-8]
!>   status_tol     relative tolerance of the status checks (tractions against
!>                  the largest traction, gaps against the largest jump),
!>                  in (0, 1)                                             [1e-6]
!>   open_fraction  damped opening: an update opens a closed element in tension
!>                  only if its tension is at least open_fraction times the
!>                  largest tension of the closed elements that may change
!>                  (so the worst one always opens); 0 opens all, in [0, 1)
!>                                                                        [0]
!>   close_ratio    early closing: an open element beside a closed one closes,
!>                  once a step, when its gap fell below close_ratio times
!>                  its gap at the previous update (0.5: the line through its
!>                  last two gaps reaches zero by the next update); 0: only
!>                  an overlap closes it, in [0, 1). Seed's nine fractures,
!>                  opening step: 9 Newton iterations against 12
!>                  (doc/benchmarks.md#active-set)                     [0.5]
!>   moving_rtol    FGMRES: relative tolerance of the linear solve of a Newton
!>                  iteration that may still move the active set (each after
!>                  an update that changed a status, the first of a step
!>                  after a step that did): its statuses are a guess, and
!>                  digits beyond moving_rtol decide nothing; after the
!>                  statuses settled (with the matrix's fluid, physics
!>                  'poromechanics_faults', they solve to rtol), Eisenstat and
!>                  Walker's forcing term
!>                  between &solver rtol and moving_rtol (newton_loop's
!>                  solve_rtol). The step's convergence is judged on the
!>                  residual as always. 0: rtol throughout (the exact Newton
!>                  loop), in [0, 1)                                  [1e-3]
!>   max_cuts       depth of the halvings of a step that fails (its Newton
!>                  loop or a linear solve does not converge): its sub-steps
!>                  may be down to dt / 2^max_cuts, growing back after two
!>                  easy ones (time_loop advance); a step whose first linear
!>                  solve failed and would be repeated by a cut (a load
!>                  step, the step at t = 0) stops at once, >= 0        [8]
!>   reuse          FGMRES: keep the preconditioner's Schur part (S* and its
!>                  BoomerAMG, S_p) while every element sticks, as when it was
!>                  built (with the fluid: at the same step size): the
!>                  Jacobian is then the same, so the iterations are too and
!>                  the set-up is saved; rebuilt at every Newton iteration
!>                  otherwise                                         [.true.]
!>   amg_lag        FGMRES with 'reordered': the BoomerAMG hierarchy of S*
!>                  (S**) is built anew every amg_lag Newton iterations and
!>                  at every step's first one; in between it is refreshed
!>                  for the new S* (amg_refresh; geoblock's cycle
!>                  only), 1..100                                       [1]
!>   amg_refresh    with amg_lag > 1, what a refresh between two builds
!>                  renews: 'fine' (the finest level only) or 'galerkin'
!>                  (every level: the coarse ones as P^T A P with the
!>                  interpolation of the last build; its strength graphs,
!>                  coarsening and interpolation are what is saved)  ['fine']
module contact_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use strings, only: itoa, rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: contact_config_t

  type :: contact_config_t
    character(len=name_len) :: space = 'stabilized'
    character(len=name_len) :: stabilization = 'algebraic'
    character(len=name_len) :: block = 'reordered'
    character(len=name_len) :: schur_precon = 'boomeramg'
    real(rp) :: aug_scale = 1.0_rp
    !> '' until the deck sets it or the composition resolves it
    !> (resolve_schur_solve)
    character(len=name_len) :: schur_solve = ''
    logical :: schur_given = .false.              !< the deck set schur_solve
    integer :: schur_its = 2
    integer :: max_newton = 30
    real(rp) :: newton_tol = 1.0e-8_rp
    real(rp) :: status_tol = 1.0e-6_rp
    real(rp) :: open_fraction = 0.0_rp
    real(rp) :: close_ratio = 0.5_rp
    real(rp) :: moving_rtol = 1.0e-3_rp
    integer :: max_cuts = 8
    logical :: reuse = .true.
    integer :: amg_lag = 1
    character(len=name_len) :: amg_refresh = 'fine'
  contains
    procedure :: read => read_contact_config
    procedure :: resolve_schur_solve
    procedure :: describe => describe_contact_config
  end type contact_config_t

contains

  !> Read and check &contact (optional group).
  subroutine read_contact_config(self, d, log, status)
    class(contact_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: space, stabilization, block, schur_precon, schur_solve, amg_refresh
    real(rp) :: aug_scale, newton_tol, status_tol, open_fraction, moving_rtol, close_ratio
    integer :: max_newton, max_cuts, schur_its, amg_lag, ios
    logical :: reuse
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /contact/ space, stabilization, block, schur_precon, aug_scale, schur_solve, schur_its, max_newton, &
                       newton_tol, status_tol, open_fraction, moving_rtol, max_cuts, reuse, close_ratio, amg_lag, &
                       amg_refresh

    ! stabilization and block: '' until the deck sets them (their defaults
    ! follow the space)
    space = self%space; stabilization = ''; block = ''; schur_precon = self%schur_precon
    aug_scale = self%aug_scale; schur_solve = self%schur_solve; max_newton = self%max_newton; newton_tol = self%newton_tol
    status_tol = self%status_tol; max_cuts = self%max_cuts; reuse = self%reuse; schur_its = self%schur_its
    open_fraction = self%open_fraction; moving_rtol = self%moving_rtol; close_ratio = self%close_ratio
    amg_lag = self%amg_lag; amg_refresh = self%amg_refresh
    if (d%count('contact') > 0) then
      call d%block('contact', 1, b)
      read(b, nml=contact, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('contact', 1, ios, msg, status)
        return
      end if
    end if
    if (space /= 'stabilized' .and. space /= 'bubble') call d%fail(status, 'contact', 1, 'space', &
      "must be 'stabilized' or 'bubble' (got '"//trim(space)//"')")
    if (space == 'bubble' .and. stabilization == 'algebraic') call d%fail(status, 'contact', 1, 'stabilization', &
      "'algebraic' with space = 'bubble': the face bubbles make the tractions stable, the system is a pure "// &
      "saddle point with no H_t (leave stabilization out, or set 'none')")
    if (len_trim(stabilization) == 0) stabilization = merge('none     ', 'algebraic', space == 'bubble')
    if (len_trim(block) == 0) block = merge('augmented', 'reordered', space == 'bubble')
    if (stabilization /= 'algebraic' .and. stabilization /= 'none') call d%fail(status, 'contact', 1, &
      'stabilization', "must be 'algebraic' or 'none' (got '"//trim(stabilization)//"')")
    if (block /= 'reordered' .and. block /= 'classical' .and. block /= 'augmented') call d%fail(status, &
      'contact', 1, 'block', "must be 'reordered', 'classical' or 'augmented' (got '"//trim(block)//"')")
    if (schur_precon /= 'boomeramg' .and. schur_precon /= 'jacobi') call d%fail(status, 'contact', 1, &
      'schur_precon', "must be 'boomeramg' or 'jacobi' (got '"//trim(schur_precon)//"')")
    if (len_trim(schur_solve) > 0 .and. schur_solve /= 'vcycle' .and. schur_solve /= 'pcg' .and. &
        schur_solve /= 'inner_cg') call d%fail(status, &
      'contact', 1, 'schur_solve', "must be 'vcycle', 'pcg' or 'inner_cg' (got '"//trim(schur_solve)//"')")
    if (len_trim(schur_solve) > 0 .and. schur_solve /= 'vcycle' .and. block == 'classical') &
      call d%fail(status, 'contact', 1, 'schur_solve', &
      "'"//trim(schur_solve)//"' applies to S* of block = 'reordered' or 'augmented', not to 'classical'")
    if (schur_its < 1 .or. schur_its > 50) call d%fail(status, 'contact', 1, 'schur_its', &
      'must lie in 1..50 (got '//itoa(schur_its)//')')
    if (.not. (aug_scale > 0.0_rp)) call d%fail(status, 'contact', 1, 'aug_scale', &
      'must be > 0 (got '//rtoa(aug_scale)//')')
    if (max_newton < 1) call d%fail(status, 'contact', 1, 'max_newton', 'must be >= 1 (got '//itoa(max_newton)//')')
    if (.not. (newton_tol > 0.0_rp .and. newton_tol < 1.0_rp)) call d%fail(status, 'contact', 1, 'newton_tol', &
      'must lie in (0, 1) (got '//rtoa(newton_tol)//')')
    if (.not. (status_tol > 0.0_rp .and. status_tol < 1.0_rp)) call d%fail(status, 'contact', 1, 'status_tol', &
      'must lie in (0, 1) (got '//rtoa(status_tol)//')')
    if (.not. (open_fraction >= 0.0_rp .and. open_fraction < 1.0_rp)) call d%fail(status, 'contact', 1, &
      'open_fraction', 'must lie in [0, 1) (got '//rtoa(open_fraction)//')')
    if (.not. (moving_rtol >= 0.0_rp .and. moving_rtol < 1.0_rp)) call d%fail(status, 'contact', 1, &
      'moving_rtol', 'must lie in [0, 1) (got '//rtoa(moving_rtol)//')')
    if (.not. (close_ratio >= 0.0_rp .and. close_ratio < 1.0_rp)) call d%fail(status, 'contact', 1, &
      'close_ratio', 'must lie in [0, 1) (got '//rtoa(close_ratio)//')')
    if (max_cuts < 0) call d%fail(status, 'contact', 1, 'max_cuts', 'must be >= 0 (got '//itoa(max_cuts)//')')
    if (amg_lag < 1 .or. amg_lag > 100) call d%fail(status, 'contact', 1, 'amg_lag', &
      'must lie in 1..100 (got '//itoa(amg_lag)//')')
    if (amg_refresh /= 'fine' .and. amg_refresh /= 'galerkin') call d%fail(status, 'contact', 1, 'amg_refresh', &
      "must be 'fine' or 'galerkin' (got '"//trim(amg_refresh)//"')")
    if (.not. status%ok()) return
    self%amg_lag = amg_lag; self%amg_refresh = amg_refresh
    self%open_fraction = open_fraction; self%moving_rtol = moving_rtol; self%close_ratio = close_ratio
    self%space = space; self%stabilization = stabilization; self%block = block; self%schur_precon = schur_precon
    self%aug_scale = aug_scale; self%schur_solve = schur_solve; self%max_newton = max_newton; self%newton_tol = newton_tol
    self%status_tol = status_tol; self%max_cuts = max_cuts; self%reuse = reuse; self%schur_its = schur_its
    self%schur_given = len_trim(schur_solve) > 0
  end subroutine read_contact_config

  !> The default of schur_solve, when the deck left it out: 'pcg' for the
  !> reordered preconditioner of the contact system alone, 'vcycle' with a
  !> fluid (fluid: the composition has the fractures' or the matrix's flow)
  !> and for the other blocks. Measured on 2 ranks, 2026-12-02, lexicographic
  !> Gauss-Seidel: the contact block's five levels (n = 8..40) 18 -> 20
  !> FGMRES iterations a Newton iteration (1.11x) against 24 -> 38 for the
  !> V-cycle, at n = 40 set-up + solve 4.5 / 12.0 / 14.4 s (stick / slip /
  !> open) against the V-cycle's 4.0 / 11.3 / 13.8 s and 5.6 / 14.1 / 17.8 s
  !> with hypre's C/F order; HI24L medium 273 s wall against 284 s (V-cycle)
  !> and 302 s (V-cycle, C/F order), 823 FGMRES iterations against 1,494.
  !> The nine fractures' step 5 (S**, the fluid in the fractures): 89
  !> iterations but 56.5 s of solve against 143 and 45.5 s: 'vcycle'. (On a
  !> slab with flat cells the composition sets 'vcycle' in its place:
  !> coupled_simulation's solver_setup.)
  subroutine resolve_schur_solve(self, fluid)
    class(contact_config_t), intent(inout) :: self
    logical, intent(in) :: fluid
    if (len_trim(self%schur_solve) > 0) return
    self%schur_solve = merge('pcg   ', 'vcycle', self%block == 'reordered' .and. .not. fluid)
  end subroutine resolve_schur_solve

  subroutine describe_contact_config(self, g)
    class(contact_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('contact', 'the discretization of the contact conditions, their block preconditioner and the '// &
                'Newton / active-set loop')
    call g%add('space', self%space, '-', "'stabilized': Q1 displacements, P0 tractions with the stabilization "// &
               "H_t; 'bubble': Q1 enriched with face bubbles, inf-sup stable (contact only)", &
               "'stabilized' or 'bubble'")
    call g%add('stabilization', self%stabilization, '-', "the traction jump stabilization H_t ('none' with "// &
               "space = 'bubble', where 'algebraic' is refused; 'none' with 'stabilized' is not inf-sup stable: "// &
               "the run warns)", "'algebraic' or 'none'")
    call g%add('block', self%block, '-', "FGMRES preconditioner of the (t, u) system ('augmented' with space "// &
               "= 'bubble'; fracture_flow: 'reordered')", "'reordered', 'classical' or 'augmented'")
    call g%add('schur_precon', self%schur_precon, '-', "block = 'classical': preconditioner of -S", &
               "'boomeramg' or 'jacobi'")
    call g%add('aug_scale', self%aug_scale, '-', 'scale of the regular diagonal H~ of the reordered '// &
               'preconditioner and of D of the augmented one', '> 0')
    call g%add('schur_solve', self%schur_solve, '-', "how S* (S** with the fluid) is applied: one BoomerAMG "// &
               "cycle, schur_its CG steps with BoomerAMG, or CG to 1e-10 (a slow diagnostic)", &
               "'vcycle', 'pcg' or 'inner_cg' (not with block = 'classical')")
    call g%add('schur_its', self%schur_its, '-', "schur_solve = 'pcg': CG steps per application of S*^-1", '1..50')
    call g%add('max_newton', self%max_newton, '-', 'Newton / active-set iterations per step before it is cut', &
               '>= 1')
    call g%add('newton_tol', self%newton_tol, '-', 'relative residual per field of the Newton loop (force, '// &
               'traction, fluid volume of the step, each against the magnitude it balances)', '(0, 1)')
    call g%add('status_tol', self%status_tol, '-', 'relative tolerance of the stick / slip / open checks', '(0, 1)')
    call g%add('open_fraction', self%open_fraction, '-', 'damped opening: an update opens a closed element '// &
               'only if its tension is at least open_fraction times the largest tension of the closed elements '// &
               '(0: every element in tension opens)', '[0, 1)')
    call g%add('close_ratio', self%close_ratio, '-', 'early closing: an open element beside a closed one '// &
               'closes (once a step) when its gap fell below close_ratio times its gap at the previous update '// &
               '(0: only an overlap closes it)', '[0, 1)')
    call g%add('moving_rtol', self%moving_rtol, '-', 'FGMRES: relative tolerance of the solve of a Newton '// &
               'iteration that may still move the active set (each after an update that changed a status, the '// &
               'first of a step after one that did); once statuses settle, Eisenstat-Walker forcing down to '// &
               '&solver rtol, but rtol with a fluid in the matrix (0: rtol throughout, the exact loop)', '[0, 1)')
    call g%add('max_cuts', self%max_cuts, '-', 'halvings of a step whose Newton loop does not converge: its '// &
               'sub-steps may be down to dt / 2^max_cuts (they grow back after two easy ones) before the run stops', &
               '>= 0')
    call g%add('reuse', self%reuse, '-', "FGMRES: keep the preconditioner's Schur part (S* and its AMG, S_p) "// &
               'while every element sticks, as when it was built')
    call g%add('amg_lag', self%amg_lag, '-', "FGMRES with 'reordered': the BoomerAMG hierarchy of S* (S**) is "// &
               'built anew every amg_lag Newton iterations and at every step''s first; in between it is refreshed '// &
               "for the new S* (amg_refresh; geoblock's cycle only)", '1..100')
    call g%add('amg_refresh', self%amg_refresh, '-', 'between two builds of amg_lag: only the finest level '// &
               "takes the new S* ('fine'; the coarse levels are the build's), or every level does, the coarse "// &
               "ones as P^T A P with the build's interpolation ('galerkin': the Galerkin products of a build "// &
               'without its coarsening and interpolation)', "'fine' or 'galerkin'")
  end subroutine describe_contact_config
end module contact_config
