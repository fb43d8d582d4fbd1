!> The one time loop of every physics: the run's preamble (&mesh, the
!> physics' deck groups, the distributed mesh, the physics' set-up, the
!> output), then the steps of the schedule, each solved by the Newton loop
!> and, when it fails, cut in half (down to sim%max_cuts halvings, growing
!> back after easy sub-steps: advance); a progress
!> line per step, the fields every &output every steps, a timing summary.
!> Every error stops all ranks with one message (logger%fatal).
!>
!> Checkpoints (run_checkpoint.f90): after every &output checkpoint_every-th
!> step, and after the step during which any rank got SIGTERM or SIGUSR1; a
!> signal then ends the run cleanly (outputs closed, exit status 0) with a
!> line that says how to resume. &run restart starts the loop at the step
!> after a checkpoint's, from its state.
module time_loop
  use kinds, only: rp, gp, msg_len, path_len
  use machine_memory, only: total_memory_bytes
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use timer_set, only: timer_set_t
  use strings, only: itoa, rtoa
  use os_services, only: catch_stop_signals, stop_requested, signal_name
  use state_record, only: state_record_t
  use deck, only: deck_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use field_output, only: field_output_t
  use probe_config, only: probe_config_t, read_probes
  use probe_fields, only: probe_fields_t
  use probe_output, only: probe_output_t
  use simulation, only: simulation_t, step_stats_t
  use step_schedule, only: step_schedule_t
  use newton_loop, only: newton_loop_t
  use run_checkpoint, only: save_run, resume_run
  use run_parameters, only: record_parameters
  implicit none
  private

  public :: run_simulation, read_physics_groups

  !> What the loop carries from step to step.
  type :: run_state_t
    type(step_schedule_t) :: schedule
    type(newton_loop_t) :: newton
    type(field_output_t) :: out
    type(probe_output_t) :: probes       !< <prefix>_probes.csv
    type(timer_set_t) :: timers
    type(state_record_t) :: saved        !< the last accepted state (restored by a cut)
    real(rp) :: t = 0.0_rp               !< time (load factor) of the last accepted state
    integer :: first = 0                 !< the first step this run solves
  end type run_state_t

contains

  !> Run the simulation sim (made by simulation_factory from &run physics)
  !> of deck d. Stops collectively on any error.
  subroutine run_simulation(comm, log, d, run, sim)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    class(simulation_t), intent(inout), target :: sim
    type(dist_mesh_t), target :: mesh
    type(run_state_t) :: rs
    type(step_stats_t) :: stats
    integer :: step, sig, k
    character(len=msg_len) :: line
    character(len=msg_len), allocatable :: notes(:)

    call catch_stop_signals()
    call rs%timers%start('total')
    call prepare(comm, log, d, run, sim, mesh, rs)
    step = rs%first
    do
      stats = step_stats_t(step=step, n_steps=rs%schedule%known_steps())
      if (.not. rs%schedule%next(step, rs%t, stats%t, stats%dt)) exit
      if (rs%schedule%beyond_limit(step)) call log%fatal(comm, 'step '//itoa(step)//' (t = '//trim(rtoa(rs%t))// &
        '): the run would take more than &time max_steps = '//itoa(run%max_steps)//' steps (raise max_steps)')
      call advance(comm, log, sim, rs, stats)
      call sim%report_step(stats, line)
      if (stats%near_rtol > 0) line = trim(line)//'  near-rtol solves '//itoa(stats%near_rtol)
      call log%info(line)
      call sim%step_notes(notes)
      do k = 1, size(notes)
        call log%info(trim(notes(k)))
      end do
      call record_probes(comm, log, sim, rs, step)
      if (run%fields .and. (mod(step, run%every) == 0 .or. step <= 1 .or. rs%schedule%is_last(step, rs%t))) &
        call write_step(comm, log, sim, rs)
      ! a stop signal on any rank ends the run here, unless it is over anyway
      sig = comm%max(stop_requested())
      if (rs%schedule%is_last(step, rs%t)) sig = 0
      if (sig /= 0 .or. (run%checkpoint_every > 0 .and. step > 0 .and. mod(step, max(run%checkpoint_every, 1)) == 0)) &
        call checkpoint(comm, log, run, sim, rs, step, stats%dt)
      if (sig /= 0) then
        call log%info('stopped by signal '//signal_name(sig)//' after step '//itoa(step)//' (t = '//trim(rtoa(rs%t))// &
                      '): checkpoint '//trim(run%checkpoint_file)//"; resume with &run restart = '"// &
                      trim(run%checkpoint_file)//"'")
        exit
      end if
      step = step + 1
    end do
    call sim%finish(log)
    if (run%fields) call log%info('output: '//trim(rs%out%path())//' (open it in ParaView)')
    call log%info('residual histories: '//rs%newton%history%path)
    call rs%newton%check_export(sim, log)
    call rs%timers%stop('total')
    call rs%timers%report(comm, log)
    call rs%newton%free()
    call rs%probes%free()
    call rs%out%free()
    call sim%free()
    call mesh%free()
  end subroutine run_simulation

  !> The preamble: deck groups, mesh, set-up, output, solver. Collective.
  subroutine prepare(comm, log, d, run, sim, mesh, rs)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    class(simulation_t), intent(inout), target :: sim
    type(dist_mesh_t), intent(inout), target :: mesh
    type(run_state_t), intent(inout) :: rs
    type(mesh_config_t) :: mcfg
    type(probe_config_t), allocatable :: pcfg(:)
    character(len=8), allocatable :: avail(:)
    type(error_status_t) :: status
    character(len=path_len) :: base
    call read_physics_groups(comm, log, d, run, sim, mcfg, status, pcfg)
    ! the resolved deck, before anything can fail (a failed run leaves it too)
    if (status%ok()) call record_parameters(comm, log, d%path, run, mcfg, sim, pcfg, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call rs%schedule%init(run, sim%transient, sim%initial_step)

    call rs%timers%start('mesh')
    call build_mesh(comm, mcfg, log, mesh, status, sim%faults)
    call rs%timers%stop('mesh')
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call sim%setup(mesh, log, status)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)

    if (run%fields) then
      call rs%out%init(mesh, run%out_dir, run%prefix, status)
      if (status%ok()) call sim%open_output(rs%out, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if
    rs%first = rs%schedule%first_step()
    if (len_trim(run%restart) > 0) then
      call resume_run(comm, log, sim, rs%schedule, rs%out, run%fields, run%restart, rs%first, rs%t, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if
    base = trim(run%out_dir)//'/'//trim(run%prefix)
    call sim%probe_names(avail)
    if (len_trim(run%restart) > 0) then
      ! the matrix export belongs to the first step of the whole run
      call rs%newton%init(comm, sim, trim(base)//'_residuals.csv', trim(base), .false., status, &
                          keep_through=rs%first - 1)
      if (status%ok()) call rs%probes%init(d, pcfg, mesh, avail, sim%name(), trim(base)//'_probes.csv', &
                                           sim%transient, status, keep_through=rs%first - 1)
    else
      call rs%probes%init(d, pcfg, mesh, avail, sim%name(), trim(base)//'_probes.csv', sim%transient, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
      call rs%newton%init(comm, sim, trim(base)//'_residuals.csv', trim(base), run%export_matrix, status)
    end if
    if (.not. status%ok()) call log%fatal(comm, status%msg)
  end subroutine prepare

  !> The deck groups of the mesh and of the physics (and, for a physics that
  !> steps in time, the time-step variables), read and checked; the values
  !> are echoed to the log by record_parameters. Collective.
  subroutine read_physics_groups(comm, log, d, run, sim, mcfg, status, probes)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    class(simulation_t), intent(inout) :: sim
    type(mesh_config_t), intent(inout) :: mcfg
    type(error_status_t), intent(inout) :: status
    type(probe_config_t), allocatable, intent(out), optional :: probes(:)   !< &probe groups
    type(probe_config_t), allocatable :: pcfg(:)
    integer(gp) :: mem_total
    call mcfg%read(d, log, status)
    ! the machine's memory as rank 0 sees it, so that every rank decides alike
    mem_total = -1
    if (comm%is_root()) mem_total = total_memory_bytes()
    call comm%bcast(mem_total)
    call mcfg%check_size(d, run%physics, mem_total, status)
    sim%comm = comm
    if (status%ok()) call sim%read_deck(d, mcfg, log, status)
    if (status%ok()) call sim%check_foreign(d, status)
    if (status%ok() .and. sim%transient) call run%check_transient(d, sim%name(), status)
    if (status%ok()) call read_probes(d, log, pcfg, status)
    if (status%ok() .and. present(probes)) call move_alloc(pcfg, probes)
  end subroutine read_physics_groups

  !> Write the checkpoint of the accepted step `step` (last sub-step dt).
  !> Collective; stops the run when it cannot be written.
  subroutine checkpoint(comm, log, run, sim, rs, step, dt)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(run_config_t), intent(in) :: run
    class(simulation_t), intent(inout) :: sim
    type(run_state_t), intent(inout) :: rs
    integer, intent(in) :: step
    real(rp), intent(in) :: dt
    type(error_status_t) :: status
    call rs%timers%start('checkpoint')
    call save_run(comm, sim, rs%schedule, rs%out, run%fields, run%checkpoint_file, step, rs%t, dt, status)
    call rs%timers%stop('checkpoint')
    if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(step)//': '//trim(status%msg))
    call log%detail('checkpoint after step '//itoa(step)//': '//trim(run%checkpoint_file))
  end subroutine checkpoint

  !> Solve one nominal step (stats%t: its end, stats%dt: its size) from the
  !> accepted state rs%t: sub-steps of the current size until stats%t is
  !> reached. A sub-step that fails is halved; the sub-steps may be at most
  !> sim%max_cuts halvings below the nominal size. After two sub-steps in a
  !> row that converged easily (in at most easy_newton Newton iterations)
  !> the size doubles again, up to the nominal one, so that a hard start (a
  !> fracture opening from its residual aperture) does not sentence the
  !> rest of the step to the smallest size. (The open fracture of a0 1e-5 m
  !> in 1 m elements, dt 1000 s, needed its sub-steps of 15.6 s only for
  !> the first seconds; at that size throughout, 64 sub-steps.) Every
  !> sub-step advances the time by at least the nominal size over
  !> 2^max_cuts, so the loop ends. Collective; stops the run when a step
  !> cannot be solved.
  subroutine advance(comm, log, sim, rs, stats)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    class(simulation_t), intent(inout), target :: sim
    type(run_state_t), intent(inout) :: rs
    type(step_stats_t), intent(inout) :: stats
    type(error_status_t) :: status
    real(rp) :: t_target, dl, t_new, dt
    logical :: converged, cut_helps
    character(len=msg_len) :: why
    integer :: depth, easy, newton_before, easy_newton
    t_target = stats%t
    dl = stats%dt
    depth = 0
    easy = 0
    easy_newton = max(3, sim%max_newton / 4)
    do
      ! a sub-step of size dl; the one that reaches the target ends on it
      dt = dl
      t_new = rs%t + dl
      if (t_new >= t_target - 1.0e-9_rp * dl) then
        t_new = t_target
        if (stats%cuts > 0) dt = t_target - rs%t
      end if
      newton_before = stats%newton
      call sim%save_state(rs%saved)
      call sim%begin_step(t_new, dt, status)
      if (status%ok()) call rs%newton%solve_step(sim, log, rs%timers, stats%step, t_new, dt, stats, converged, &
                                                 cut_helps, why, status)
      call agree(comm, status)
      if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(stats%step)//': '//trim(status%msg))
      if (converged) then
        call sim%accept_step()
        rs%t = t_new
        stats%dt = dt
        if (rs%t >= t_target * (1.0_rp - 1.0e-12_rp)) exit
        easy = merge(easy + 1, 0, stats%newton - newton_before <= easy_newton)
        if (depth > 0 .and. easy >= 2) then
          dl = 2.0_rp * dl
          depth = depth - 1
          easy = 0
        end if
        cycle
      end if
      easy = 0
      call sim%load_state(rs%saved, status)
      if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(stats%step)//': '//trim(status%msg))
      if (.not. cut_helps .and. sim%max_cuts > 0) then
        if (dt == 0.0_rp) then
          why = trim(why)//'; not cut: the step at t = 0 has no size to halve'
        else
          why = trim(why)//'; not cut: its first linear system does not depend on the step size, so a smaller '// &
                'step would solve the same one'
        end if
        call log%fatal(comm, 'step '//itoa(stats%step)//' (t = '//trim(rtoa(t_new))//'): '//trim(why))
      end if
      if (depth >= sim%max_cuts) call fail_step(comm, log, sim, stats, t_new, why)
      stats%cuts = stats%cuts + 1
      depth = depth + 1
      call log%warn('step '//itoa(stats%step)//': no convergence at t = '//trim(rtoa(t_new))//' ('//trim(why)// &
                    '); the step is cut in half')
      dl = 0.5_rp * dl
    end do
  end subroutine advance

  !> Stop the run: step stats%step could not be solved at time t (why).
  subroutine fail_step(comm, log, sim, stats, t, why)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    class(simulation_t), intent(in) :: sim
    type(step_stats_t), intent(in) :: stats
    real(rp), intent(in) :: t
    character(len=*), intent(in) :: why
    if (sim%max_cuts == 0) call log%fatal(comm, 'step '//itoa(stats%step)//': '//trim(why))
    call log%fatal(comm, 'step '//itoa(stats%step)//' (t = '//trim(rtoa(t))//'): no convergence at '// &
      itoa(sim%max_cuts)//' halvings of the step ('//itoa(stats%cuts)//' cuts in all): '//trim(why)// &
      ' (raise max_newton or max_cuts in &'//trim(sim%controls_group())// &
      ', or use more steps in &time)')
  end subroutine fail_step

  !> The probe row of the accepted step `step` (every step). Collective.
  subroutine record_probes(comm, log, sim, rs, step)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    class(simulation_t), intent(inout) :: sim
    type(run_state_t), intent(inout) :: rs
    integer, intent(in) :: step
    type(probe_fields_t) :: pf
    type(error_status_t) :: status
    call sim%sample(pf, status)
    if (status%ok()) call rs%probes%record(sim%mesh, step, rs%t, pf, status)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(step)//': '//trim(status%msg))
  end subroutine record_probes

  !> The fields of the accepted step at time rs%t. Collective.
  subroutine write_step(comm, log, sim, rs)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    class(simulation_t), intent(inout) :: sim
    type(run_state_t), intent(inout) :: rs
    type(error_status_t) :: status
    call rs%timers%start('output')
    call rs%out%begin_step(rs%t, status)
    if (status%ok()) call sim%write_output(rs%out, status)
    if (status%ok()) call rs%out%end_step(status)
    call rs%timers%stop('output')
    if (.not. status%ok()) call log%fatal(comm, status%msg)
  end subroutine write_step
end module time_loop
