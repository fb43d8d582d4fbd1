!> The contact active-set update (interface_contact_t%update_states, begin_step) on a
!> box with two faults, the tractions and jumps set by hand (no solve):
!>  - every transition at a margin of twice the tolerance beyond its limit
!>    (stick -> slip, stick -> open even above the friction limit, slip ->
!>    open, slip -> stick, open -> stick), and no change at half the
!>    tolerance short of it or inside (stick just below tau or above it
!>    within the tolerance, stick with t_N > 0 within the tolerance, slip
!>    with |t_T + (A/s) dg| within the tolerance below tau, where dg is
!>    measured from jump_step, open with g_N > 0 or within the tolerance
!>    below 0); the return value is the global number of changes;
!>  - fresh is true exactly for the elements that went stick -> slip in the
!>    last update for the first time in the step, and false again after an
!>    update without changes;
!>  - an element cycling stick <-> slip beyond the 1e-3 bound is held on its
!>    fifth change if within its own stabilization allowance, not without one,
!>    nor when that allowance exceeds its friction limit and the violation
!>    does too (the allowance counts at most tau); the largest held
!>    violation is reported with its kind and allowance;
!>  - the cap of 4 changes per element and step: an element driven stick ->
!>    slip -> stick -> slip -> stick is held in stick on the fifth change and
!>    counted in held of its fault; one driven open -> stick -> open -> stick
!>    -> open is held in open and counted in held_open, not held; after
!>    begin_step both change again and nothing is held;
!>  - after every update the statuses of the ghost elements are their
!>    owners' (each element's expected status follows from its original id,
!>    so it is the same on every rank that has it), the counts are global;
!>  - early closing (close_ratio 0.5): an open element beside a closed one
!>    closes when its gap fell below half its gap at the previous update,
!>    not one without a closed neighbour or above the ratio; with 0, none.
!> Run on 1 and 2 ranks.
program test_contact_states
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use fault_config, only: fault_config_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use simulation, only: simulation_t
  use simulation_factory, only: make_simulation
  use coupled_simulation, only: coupled_simulation_t
  use interface_contact, only: interface_contact_t, state_stick, state_slip, state_open, state_names, max_flips, &
                               violation_names, viol_beyond
  use strings, only: itoa
  use assertions, only: test_suite_t
  use deck_files, only: write_lines
  implicit none

  ! how an element's traction and jump are set (set_element), the status it
  ! starts from and the status update_states must give it
  integer, parameter :: to_slip = 1, below_tau = 2, above_tau_within = 3, stick_to_open = 4, &
                        tension_within = 5, slip_to_open = 6, slip_to_stick = 7, slip_within = 8, &
                        open_to_stick = 9, open_wide = 10, closing_within = 11, slip_reversed = 12, n_kinds = 12
  integer, parameter :: from(n_kinds) = [state_stick, state_stick, state_stick, state_stick, state_stick, &
                                         state_slip, state_slip, state_slip, state_open, state_open, state_open, &
                                         state_slip]
  integer, parameter :: to(n_kinds) = [state_slip, state_stick, state_stick, state_open, state_stick, &
                                       state_open, state_stick, state_slip, state_stick, state_open, state_open, &
                                       state_stick]
  !> each kind's margin from its limit, in tolerances (tol t_ref in traction, tol g_ref in normal jump): 2
  !> beyond it for a change, 1/2 short of it for none (open_wide: g_N = g_ref instead)
  real(rp), parameter :: margin(n_kinds) = [2.0_rp, -0.5_rp, 0.5_rp, 2.0_rp, 0.5_rp, 2.0_rp, -2.0_rp, -0.5_rp, &
                                            -2.0_rp, 0.0_rp, -0.5_rp, 2.0_rp]
  character(len=40), parameter :: kind_names(n_kinds) = [character(len=40) :: &
    '|t_T| = tau + 2 tol t_ref', '|t_T| = tau - tol t_ref / 2', '|t_T| = tau + tol t_ref / 2', &
    't_N = 2 tol t_ref, |t_T| > tau', 't_N = tol t_ref / 2', 't_N = 2 tol t_ref', &
    '|t_T + (A/s) dg| = tau - 2 tol t_ref', '|t_T + (A/s) dg| = tau - tol t_ref / 2', &
    'g_N = -2 tol g_ref', 'g_N = g_ref > 0', 'g_N = -tol g_ref / 2', &
    '|z| = tau + 2 tol t_ref, c dg vs t_T < 0']
  real(rp), parameter :: tol = 1.0e-6_rp            !< the status tolerance (the deck's default)
  real(rp), parameter :: t0 = 1.0e7_rp              !< compression [Pa]: the largest |traction|, so t_ref
  real(rp), parameter :: g0 = 1.0e-3_rp             !< opening of open_wide [m]: the largest |jump|, so g_ref
  real(rp), parameter :: dir(2) = [0.6_rp, 0.8_rp]  !< direction of the tangential tractions and slips
  real(rp), parameter :: pi = acos(-1.0_rp)
  !> the cap's roles (by original id): 0 stays open and wide (g_ref), 1 cycles stick <-> slip, 2 open <-> stick
  integer, parameter :: role_start(0:2) = [state_open, state_stick, state_open]

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(logger_t) :: log
  type(error_status_t) :: st
  type(dist_mesh_t) :: dm
  type(fault_config_t), allocatable :: faults(:)
  class(simulation_t), allocatable, target :: sim
  type(coupled_simulation_t), pointer :: cs => null()
  type(interface_contact_t), pointer :: ct => null()
  character(len=64) :: tmp_deck
  integer, allocatable :: how(:), want(:), role(:)
  logical, allocatable :: want_fresh(:)
  integer(gp), allocatable :: want_held(:), want_held_open(:)
  integer(gp) :: changed
  integer(ip) :: e, nown
  integer :: k, f
  character(len=32) :: label
  real(rp), allocatable :: fric_keep(:), coh_keep(:)

  call comm%init_world()
  call suite%init('contact_states', comm)
  call log%init(comm, 0)
  write(tmp_deck, '(a,i0,a)') '/tmp/test_contact_states_', comm%size, '.nml'

  ! two faults across the unit box, 4 x 4 elements of 0.25 x 0.25 each, with
  ! other friction and cohesion
  call write_lines(comm, tmp_deck, [character(len=100) :: "&mesh source = 'box', nx = 4, ny = 4, nz = 4 /", &
    "&fault name = 'low', normal_axis = 'z', position = 0.25, friction_angle = 20.0 /", &
    "&fault name = 'high', normal_axis = 'z', position = 0.75, friction_angle = 30.0, cohesion = 1.0e6 /", &
    "&material region = 'domain', young = 1.0e10, poisson = 0.25 /", &
    "&boundary set = 'zmin', type = 'displacement', ux = 0.0, uy = 0.0, uz = 0.0 /"])
  call setup(st)
  call suite%assert_true(st%ok(), 'mesh and the contact composition set up: '//trim(st%msg))
  if (.not. st%ok()) call suite%finish()
  nown = dm%iface_map%n_owned
  call suite%assert_equal_int(int(dm%iface_map%n_global), 32, '32 interface elements on two faults')
  if (comm%size > 1) call suite%assert_true(comm%sum(dm%n_ifaces - nown) > 0, &
                                            'ghost interface elements exist (the ghost checks are not empty)')
  allocate(how(dm%n_ifaces), want(dm%n_ifaces), role(dm%n_ifaces), want_fresh(dm%n_ifaces))
  allocate(want_held(size(faults)), want_held_open(size(faults)))
  want_held = 0
  want_held_open = 0

  ! ---- every transition and its tolerance, the kinds spread over both faults by original id ----------
  do e = 1, dm%n_ifaces
    how(e) = int(mod(dm%iface_orig(e) - 1, int(n_kinds, gp))) + 1
    ct%state(e) = from(how(e))
    ! a jump at the step's start, so that dg /= jump
    ct%jump_step(:, e) = [0.0_rp, 1.0e-4_rp, -2.0e-4_rp]
    call set_element(e, how(e))
  end do
  want = to(how)
  want_fresh = from(how) == state_stick .and. to(how) == state_slip
  changed = ct%update_states(dm, tol)
  ! 32 elements: kinds 1 to 8 on 3 each, 9 to 12 on 2; kinds 1, 4, 6, 7, 9 and 12 change
  call check('kinds', changed, 16)
  do k = 1, n_kinds
    call suite%assert_true(.not. comm%any_true(any(pack(ct%state(1:nown), how(1:nown) == k) /= to(k))), &
      'kind '//itoa(k)//': '//trim(state_names(from(k)))//' with '//trim(kind_names(k))//' -> '// &
      trim(state_names(to(k))))
  end do

  ! the same tractions and jumps again: nothing changes, fresh is cleared
  want_fresh = .false.
  changed = ct%update_states(dm, tol)
  call check('again', changed, 0)

  ! ---- held between stick and slip within the element's stabilization allowance ------------------
  ! each element cycles stick <-> slip 5 times, 5e-3 t_ref beyond its limit
  ! (5x the 1e-3 bound: stuck with |t_T| = tau + 5e-3 t_ref, slipping with
  ! c dg = -5e-3 t_ref along t_T = tau); role 1 (even original ids) with an
  ! allowance c |dg| = 1e-2 t_ref at its stuck iterates, role 0 with none
  ! (dg = 0): the fifth change holds role 1 only
  do e = 1, dm%n_ifaces
    role(e) = int(mod(dm%iface_orig(e) - 1, 2_gp))
  end do
  call ct%begin_step(cs%ctx)
  ct%state = state_stick
  ct%slipped = .false.
  do k = 1, max_flips + 1
    do e = 1, dm%n_ifaces
      call set_cycle(e, tau_of(e))
    end do
    want = merge(state_slip, state_stick, ct%state == state_stick)
    want_held = 0
    if (k == max_flips + 1) then
      where (role == 1) want = ct%state
      do e = 1, nown
        if (role(e) == 1) want_held(ct%fault(e)) = want_held(ct%fault(e)) + 1
      end do
      want_held = [(comm%sum(want_held(f)), f = 1, size(faults))]
    end if
    want_fresh = want == state_slip .and. ct%state == state_stick .and. k == 1
    write(label, '(a,i0)') 'allow ', k
    changed = ct%update_states(dm, tol)
    call check(trim(label), changed, int(merge(comm%sum(int(count(role(1:nown) == 0), gp)), &
                                               int(dm%iface_map%n_global, gp), k == max_flips + 1)))
  end do
  ! the log's account of the largest held violation: stuck 5e-3 t_ref beyond
  ! the limit, held within an allowance of 1e-2 t_ref (not within the bound)
  call suite%assert_true(ct%held_kind == viol_beyond, 'allow: the held violation is named '// &
                         trim(violation_names(viol_beyond))//' (got kind '//itoa(ct%held_kind)//')')
  call suite%assert_close(ct%held_excess, 5.0e-3_rp, 1.0e-9_rp, 'allow: largest held violation')
  call suite%assert_close(ct%held_allow, 1.0e-2_rp, 1.0e-9_rp, 'allow: its allowance')

  ! ---- the allowance is at most the element's friction limit ---------------------------------------
  ! the same cycle with tau = 2e-3 t_ref (no friction angle, cohesion only):
  ! role 1's c |dg| = 1e-2 t_ref counts as 2e-3, below the 5e-3 violation,
  ! so no element is held and all change the fifth time too
  fric_keep = ct%fric
  coh_keep = ct%coh
  ct%fric = 0.0_rp
  ct%coh = 2.0e-3_rp * t0
  call ct%begin_step(cs%ctx)
  ct%state = state_stick
  ct%slipped = .false.
  want_held = 0
  do k = 1, max_flips + 1
    do e = 1, dm%n_ifaces
      call set_cycle(e, ct%coh(e))
    end do
    want = merge(state_slip, state_stick, ct%state == state_stick)
    want_fresh = want == state_slip .and. ct%state == state_stick .and. k == 1
    write(label, '(a,i0)') 'allow at most tau ', k
    changed = ct%update_states(dm, tol)
    call check(trim(label), changed, int(dm%iface_map%n_global))
  end do
  ct%fric = fric_keep
  ct%coh = coh_keep

  ! ---- the cap: original ids 2, 5, 8, ... cycle stick <-> slip, 3, 6, 9, ... open <-> stick, 1, 4,
  ! ---- 7, ... stay open and wide (g_ref); the fifth update is held, begin_step frees the sixth
  call ct%begin_step(cs%ctx)
  do e = 1, dm%n_ifaces
    role(e) = int(mod(dm%iface_orig(e) - 1, 3_gp))
    ct%state(e) = role_start(role(e))
  end do
  ct%slipped = .false.
  want = ct%state
  do k = 1, max_flips + 2
    if (k == max_flips + 2) call ct%begin_step(cs%ctx)
    ! drive every cycling element to its other status
    do e = 1, dm%n_ifaces
      select case (role(e))
      case (0)
        how(e) = open_wide
      case (1)
        how(e) = merge(to_slip, slip_to_stick, want(e) == state_stick)
      case default
        how(e) = merge(open_to_stick, stick_to_open, want(e) == state_open)
      end select
      call set_element(e, how(e))
    end do
    ! fresh (the direction held) on an element's first slip of the step only
    want_fresh = how == to_slip .and. (k == 1 .or. k == max_flips + 2)
    if (k == max_flips + 1) then
      ! held: the status stays; counted per fault (global)
      want_fresh = .false.
      do e = 1, nown
        if (role(e) == 1) want_held(ct%fault(e)) = want_held(ct%fault(e)) + 1
        if (role(e) == 2) want_held_open(ct%fault(e)) = want_held_open(ct%fault(e)) + 1
      end do
      want_held = [(comm%sum(want_held(f)), f = 1, size(faults))]
      want_held_open = [(comm%sum(want_held_open(f)), f = 1, size(faults))]
      call suite%assert_true(all(want_held > 0) .and. all(want_held_open > 0), &
                             'cap: both faults hold elements of both sorts (the per-fault counts are tested)')
    else
      want = to(how)
      want_held = 0
      want_held_open = 0
    end if
    write(label, '(a,i0)') 'cap ', k
    changed = ct%update_states(dm, tol)
    ! 21 cycling elements (original ids 2, 5, ..., 32 and 3, 6, ..., 30)
    call check(trim(label), changed, merge(0, 21, k == max_flips + 1))
  end do

  ! ---- the friction limit is never negative -------------------------------------------------------
  ! friction 60 degrees, no cohesion, every element stick in slight tension
  ! within the tolerance (t_N = 0.9 tol t_ref, t_ref from one element at
  ! -t0) and no shear: tau = -tan(phi) t_N would be -1.56 tol t_ref, below
  ! |t_T| = 0 by more than the tolerance, and the elements went to slip
  call ct%begin_step(cs%ctx)
  ct%fric = tan(60.0_rp * pi / 180.0_rp)
  ct%coh = 0.0_rp
  ct%state = state_stick
  ct%trac = 0.0_rp
  ct%trac(1, :) = 0.9_rp * tol * t0
  ct%jump = 0.0_rp
  ct%jump_step = 0.0_rp
  do e = 1, dm%n_ifaces
    if (dm%iface_orig(e) == 1) ct%trac(1, e) = -t0
  end do
  changed = ct%update_states(dm, tol)
  call suite%assert_true(changed == 0 .and. all(ct%state == state_stick), &
    'no shear, t_N > 0 within the tolerance, friction 60 degrees, no cohesion: stays stick (tau >= 0)')

  ! ---- early closing (&contact close_ratio): on each fault the column x < 0.25
  ! is closed, the others open at g0; at the next update the second column's
  ! half y < 0.5 has 0.4 g0 (closes with 0.5, not with 0), its half y > 0.5
  ! 0.6 g0 (stays), the columns beyond 0.4 g0 (stay: no closed neighbour)
  do k = 1, 2
    call ct%begin_step(cs%ctx)
    ct%ccfg%close_ratio = merge(0.5_rp, 0.0_rp, k == 1)
    label = merge('close_ratio 0.5', 'close_ratio 0  ', k == 1)
    ct%fric = tan(30.0_rp * pi / 180.0_rp)
    ct%coh = 0.0_rp
    ct%trac = 0.0_rp
    ct%jump = 0.0_rp
    ct%jump_step = 0.0_rp
    do e = 1, dm%n_ifaces
      if (centre(e, 1) < 0.25_rp) then
        ct%state(e) = state_stick
        ct%trac(1, e) = -t0
      else
        ct%state(e) = state_open
        ct%jump(1, e) = g0
      end if
    end do
    want = ct%state
    changed = ct%update_states(dm, tol)
    call suite%assert_true(changed == 0 .and. all(ct%state == want), &
      'early closing, '//trim(label)//': no change at the first update of the step')
    do e = 1, dm%n_ifaces
      if (ct%state(e) /= state_open) cycle
      ct%jump(1, e) = 0.4_rp * g0
      if (centre(e, 1) < 0.5_rp .and. centre(e, 2) > 0.5_rp) ct%jump(1, e) = 0.6_rp * g0
      if (k == 1 .and. centre(e, 1) < 0.5_rp .and. centre(e, 2) < 0.5_rp) want(e) = state_stick
    end do
    changed = ct%update_states(dm, tol)
    call suite%assert_equal_int(int(changed), merge(4, 0, k == 1), &
      'early closing, '//trim(label)//': status changes of the second update')
    call suite%assert_true(.not. comm%any_true(any(ct%state /= want)), 'early closing, '//trim(label)// &
      ': only the elements beside a closed one whose gap fell below the ratio close (owned and ghost)')
  end do

  call sim%free()
  call dm%free()
  call suite%finish()

contains

  !> Coordinate i of local interface element e's centre (its minus side).
  real(rp) function centre(e, i)
    integer(ip), intent(in) :: e
    integer, intent(in) :: i
    centre = sum(dm%coords(i, dm%iface_nodes(:, 1, e))) / 4.0_rp
  end function centre

  !> Mesh, faults, materials and boundaries from the deck; the composition
  !> 'contact' (mechanics and interface contact) set up and its first step
  !> begun (K and the row scales s); ct its contact component.
  subroutine setup(st)
    type(error_status_t), intent(out) :: st
    type(deck_t) :: d
    type(mesh_config_t) :: cfg
    integer :: k
    call make_simulation('contact', sim, st)
    sim%comm = comm
    if (st%ok()) call d%load(comm, tmp_deck, st)
    if (st%ok()) call cfg%read(d, log, st)
    if (st%ok()) call sim%read_deck(d, cfg, log, st)
    if (st%ok()) call build_mesh(comm, cfg, log, dm, st, sim%faults)
    if (st%ok()) call sim%setup(dm, log, st)
    if (st%ok()) call sim%begin_step(1.0_rp, 1.0_rp, st)
    if (.not. st%ok()) return
    faults = sim%faults
    select type (sim)
    type is (coupled_simulation_t)
      cs => sim
      do k = 1, size(sim%slots)
        select type (c => sim%slots(k)%c)
        type is (interface_contact_t)
          ct => c
        end select
      end do
    end select
  end subroutine setup

  !> One step of the stick <-> slip cycle of local element e under friction
  !> limit tau: stuck 5e-3 t0 beyond it (role 1 with an allowance c |dg| of
  !> 1e-2 t0, role 0 with none), slipping back by c dg = -5e-3 t0.
  subroutine set_cycle(e, tau)
    integer(ip), intent(in) :: e
    real(rp), intent(in) :: tau
    if (ct%state(e) == state_stick) then
      ct%trac(:, e) = [-t0, (tau + 5.0e-3_rp * t0) * dir]
      ct%jump(:, e) = [0.0_rp, ct%jump_step(2:3, e) + merge(1.0e-2_rp, 0.0_rp, role(e) == 1) * t0 / c_of(e) * dir]
    else
      ct%trac(:, e) = [-t0, tau * dir]
      ct%jump(:, e) = [0.0_rp, ct%jump_step(2:3, e) - 5.0e-3_rp * t0 / c_of(e) * dir]
    end if
  end subroutine set_cycle

  !> The friction limit of local element e under t0, and its c = A / s.
  real(rp) function tau_of(e)
    integer(ip), intent(in) :: e
    tau_of = faults(ct%fault(e))%cohesion + tan(faults(ct%fault(e))%friction_angle * pi / 180.0_rp) * t0
  end function tau_of
  real(rp) function c_of(e)
    integer(ip), intent(in) :: e
    c_of = ct%area(e) / ct%s(e)
  end function c_of

  !> Traction and jump of local element e for kind k (see the header), from
  !> the deck's friction and cohesion and the element's c = A / s; closed
  !> under t0, on the step's tangential jump.
  subroutine set_element(e, k)
    integer(ip), intent(in) :: e
    integer, intent(in) :: k
    real(rp) :: tau, c, dt
    tau = faults(ct%fault(e))%cohesion + tan(faults(ct%fault(e))%friction_angle * pi / 180.0_rp) * t0
    c = ct%area(e) / ct%s(e)
    dt = margin(k) * tol * t0
    ct%trac(:, e) = [-t0, 0.0_rp, 0.0_rp]
    ct%jump(:, e) = [0.0_rp, ct%jump_step(2:3, e)]
    select case (k)
    case (to_slip, below_tau, above_tau_within)
      ct%trac(2:3, e) = (tau + dt) * dir
    case (stick_to_open)
      ct%trac(:, e) = [dt, 0.5_rp * t0 * dir]              ! open before slip
    case (tension_within, slip_to_open)
      ct%trac(1, e) = dt
    case (slip_to_stick, slip_within)
      ! on the limit, with a slip increment against it: |t_T + c dg| = tau + dt
      ct%trac(2:3, e) = tau * dir
      ct%jump(2:3, e) = ct%jump(2:3, e) + dt / c * dir
    case (slip_reversed)
      ! on the limit, the slip increment reversed: c dg = -(2 tau + dt) along
      ! t_T, so z = t_T + c dg = -(tau + dt) d lies beyond the limit (|z| >
      ! tau: slip by the |z| test alone, the direction swapped), but the slip
      ! turned back against the traction: stick
      ct%trac(2:3, e) = tau * dir
      ct%jump(2:3, e) = ct%jump(2:3, e) - (2.0_rp * tau + dt) / c * dir
    case (open_to_stick, open_wide, closing_within)        ! open: no traction
      ct%trac(:, e) = 0.0_rp
      ct%jump(1, e) = merge(g0, margin(k) * tol * g0, k == open_wide)
    end select
  end subroutine set_element

  !> After an update: its return value (n_changes expected), the statuses
  !> of all local elements (want), fresh of the owned ones (want_fresh),
  !> held and held_open (want_held, want_held_open).
  subroutine check(what, changed, n_changes)
    character(len=*), intent(in) :: what
    integer(gp), intent(in) :: changed
    integer, intent(in) :: n_changes
    call suite%assert_equal_int(int(changed), n_changes, what//': global number of status changes returned')
    call suite%assert_true(.not. comm%any_true(any(ct%state(1:nown) /= want(1:nown))), &
                           what//': statuses of the owned elements')
    call suite%assert_true(.not. comm%any_true(any(ct%state(nown+1:) /= want(nown+1:))), &
                           what//': statuses of the ghost elements = their owners''')
    call suite%assert_true(.not. comm%any_true(any(ct%fresh(1:nown) .neqv. want_fresh(1:nown))), &
                           what//': fresh exactly on the elements that went stick -> slip')
    call suite%assert_true(all(ct%held == want_held) .and. all(ct%held_open == want_held_open), &
                           what//': held and held_open per fault (global)')
  end subroutine check

end program test_contact_states
