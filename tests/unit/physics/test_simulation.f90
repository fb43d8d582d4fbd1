!> The simulation contract, exercised on each physics through the factory
!> and the drivers' Newton loop, with decks of tests/decks:
!>  - a step changes the state, and save_state / load_state give it back
!>    exactly (what a step cut does);
!>  - a step solved again from a restored state gives bit for bit the same
!>    state as the first time (nothing outside the state record survives a
!>    cut);
!>  - the factory refuses an unknown physics and names the valid ones.
!> Usage: test_simulation [DECK ...] (default: an elasticity, a Biot and a
!> contact deck of tests/decks).
program test_simulation
  use kinds, only: rp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use timer_set, only: timer_set_t
  use state_record, only: state_record_t
  use deck, only: deck_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use simulation, only: simulation_t, step_stats_t
  use simulation_factory, only: make_simulation
  use step_schedule, only: step_schedule_t
  use newton_loop, only: newton_loop_t
  use assertions, only: test_suite_t
  implicit none

  type(parallel_comm_t) :: comm
  type(logger_t) :: log
  type(test_suite_t) :: suite
  character(len=256) :: arg
  integer :: k

  call comm%init_world()
  call log%init(comm, 0)
  call suite%init('simulation', comm)
  if (command_argument_count() == 0) then
    call check_physics('tests/decks/invariance.nml', 'elasticity')
    call check_physics('tests/decks/terzaghi_test.nml', 'biot')
    call check_physics('tests/decks/contact_block.nml', 'contact')
  else
    do k = 1, command_argument_count()
      call get_command_argument(k, arg)
      call check_physics(trim(arg), '')
    end do
  end if
  call check_factory()
  call suite%finish()
  call comm%finalize()

contains

  !> Two steps of the deck at path (physics expected), with the state
  !> checks of the header.
  subroutine check_physics(path, expected)
    character(len=*), intent(in) :: path, expected
    class(simulation_t), allocatable, target :: sim
    type(dist_mesh_t), target :: mesh
    type(newton_loop_t) :: newton
    type(step_schedule_t) :: schedule
    type(state_record_t) :: s0, s1, s1b, sa, sb
    real(rp) :: t0, t1, t2, dt1, dt2
    integer :: first
    logical :: ok
    call prepare(path, sim, mesh, newton, schedule, ok)
    call suite%assert_true(ok, trim(path)//': set up')
    if (.not. ok) return
    if (len(expected) > 0) &
      call suite%assert_true(sim%name() == expected, trim(path)//": the factory made '"//trim(sim%name())//"'")
    first = schedule%first_step()
    t0 = 0.0_rp
    ok = schedule%next(first, t0, t1, dt1)
    if (ok) ok = schedule%next(first + 1, t1, t2, dt2)
    call suite%assert_true(ok, trim(sim%name())//': the schedule has two steps')
    call sim%save_state(s0)
    call step(sim, newton, first, t1, dt1, .true.)
    call sim%save_state(s1)
    call suite%assert_true(.not. same(s0, s1), trim(sim%name())//': the first step changes the state')
    ! a step that is not accepted, then a cut back to the accepted state
    call step(sim, newton, first + 1, t2, dt2, .false.)
    call restore(sim, s1)
    call sim%save_state(s1b)
    call suite%assert_true(same(s1, s1b), trim(sim%name())//': load_state gives back the saved state exactly')
    ! the same step twice from the restored state
    call step(sim, newton, first + 1, t2, dt2, .true.)
    call sim%save_state(sa)
    call restore(sim, s1)
    call step(sim, newton, first + 1, t2, dt2, .true.)
    call sim%save_state(sb)
    call suite%assert_true(.not. same(s1, sa), trim(sim%name())//': the second step changes the state')
    call suite%assert_true(same(sa, sb), trim(sim%name())//': a step solved again after a restore is bit-identical')
    call newton%free()
    call sim%free()
    call mesh%free()
  end subroutine check_physics

  !> Deck, mesh, set-up and Newton loop of the deck at path, as the time
  !> loop makes them (no output). ok on every rank alike.
  subroutine prepare(path, sim, mesh, newton, schedule, ok)
    character(len=*), intent(in) :: path
    class(simulation_t), allocatable, intent(inout), target :: sim
    type(dist_mesh_t), intent(inout), target :: mesh
    type(newton_loop_t), intent(inout) :: newton
    type(step_schedule_t), intent(inout) :: schedule
    logical, intent(out) :: ok
    type(deck_t) :: d
    type(run_config_t) :: run
    type(mesh_config_t) :: mcfg
    type(error_status_t) :: status
    call d%load(comm, path, status)
    if (status%ok()) call run%read(d, log, status)
    if (status%ok()) call make_simulation(run%physics, sim, status)
    if (status%ok()) call mcfg%read(d, log, status)
    if (status%ok()) then
      sim%comm = comm
      call sim%read_deck(d, mcfg, log, status)
    end if
    if (status%ok()) call build_mesh(comm, mcfg, log, mesh, status, sim%faults)
    if (status%ok()) call sim%setup(mesh, log, status)
    call agree(comm, status)
    if (status%ok()) call newton%init(comm, sim, 'build/test-out/simulation_residuals.csv', &
                                          'build/test-out/simulation', .false., status)
    if (status%ok()) call schedule%init(run, sim%transient, sim%initial_step)
    ok = status%ok()
    if (.not. ok .and. comm%is_root()) print '(a)', '  '//trim(status%msg)
  end subroutine prepare

  !> One step to t (size dt) from the accepted state; accepted if accept.
  subroutine step(sim, newton, k, t, dt, accept)
    class(simulation_t), intent(inout), target :: sim
    type(newton_loop_t), intent(inout) :: newton
    integer, intent(in) :: k
    real(rp), intent(in) :: t, dt
    logical, intent(in) :: accept
    type(error_status_t) :: status
    type(timer_set_t) :: timers
    type(step_stats_t) :: stats
    logical :: converged, cut_helps
    character(len=msg_len) :: why
    call sim%begin_step(t, dt, status)
    if (status%ok()) call newton%solve_step(sim, log, timers, k, t, dt, stats, converged, cut_helps, why, status)
    call suite%assert_true(status%ok() .and. converged, trim(sim%name())//': step '//trim(itoa(k))// &
                           ' converges '//trim(why)//trim(status%msg))
    if (accept) call sim%accept_step()
  end subroutine step

  subroutine restore(sim, st)
    class(simulation_t), intent(inout) :: sim
    type(state_record_t), intent(in) :: st
    type(error_status_t) :: status
    call sim%load_state(st, status)
    call suite%assert_true(status%ok(), trim(sim%name())//': load_state '//trim(status%msg))
  end subroutine restore

  !> The two records hold the same names with bit-identical arrays, on
  !> every rank.
  logical function same(a, b)
    type(state_record_t), intent(in) :: a, b
    integer :: k, j
    same = a%n == b%n
    do k = 1, a%n
      if (.not. same) exit
      j = b%find(a%e(k)%name)
      same = j > 0
      if (.not. same) exit
      if (allocated(a%e(k)%r)) then
        same = allocated(b%e(j)%r)
        if (same) same = size(a%e(k)%r) == size(b%e(j)%r)
        if (same) same = all(a%e(k)%r == b%e(j)%r)
      else
        same = allocated(b%e(j)%i)
        if (same) same = size(a%e(k)%i) == size(b%e(j)%i)
        if (same) same = all(a%e(k)%i == b%e(j)%i)
      end if
    end do
    same = .not. comm%any_true(.not. same)
  end function same

  !> An unknown physics name is refused with the valid names in the message.
  subroutine check_factory()
    class(simulation_t), allocatable :: sim
    type(error_status_t) :: status
    call make_simulation('poroelasticity', sim, status)
    call suite%assert_true(.not. status%ok() .and. .not. allocated(sim) .and. &
      index(status%msg, "'elasticity', 'biot', 'contact'") > 0, 'factory: unknown physics refused: '//trim(status%msg))
  end subroutine check_factory

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=12) :: s
    write(s, '(i0)') i
  end function itoa
end program test_simulation
