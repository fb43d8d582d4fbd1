!> The run's side of checkpoints (the file format is checkpoint_file's):
!> what the time loop saves after a step (the physics' state record, the
!> step, its time, the schedule's next step size, the output's index) and
!> how a run resumes from it (&run restart): the state loaded into the
!> physics, the output series continued, the step after the checkpoint's
!> as the next one. A restart checks that the deck's schedule goes on as the
!> checkpoint's run would have, so that the resumed run is the continuous
!> one bit for bit (same number of ranks).
module run_checkpoint
  use kinds, only: rp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use field_output, only: field_output_t
  use checkpoint_file, only: checkpoint_info_t, write_checkpoint, read_checkpoint
  use simulation, only: simulation_t
  use step_schedule, only: step_schedule_t
  implicit none
  private

  public :: save_run, resume_run

contains

  !> Write the checkpoint at path after step `step`, accepted at time t
  !> with a last (sub-)step of size last_dt; with_output: out is open and its
  !> index goes along. Collective; status agrees.
  subroutine save_run(comm, sim, schedule, out, with_output, path, step, t, last_dt, status)
    type(parallel_comm_t), intent(in) :: comm
    class(simulation_t), intent(inout) :: sim
    type(step_schedule_t), intent(in) :: schedule
    type(field_output_t), intent(in) :: out
    logical, intent(in) :: with_output
    character(len=*), intent(in) :: path
    integer, intent(in) :: step
    real(rp), intent(in) :: t, last_dt
    type(error_status_t), intent(inout) :: status
    type(checkpoint_info_t) :: info
    type(state_record_t) :: st, out_index
    real(rp) :: t_next, dt
    info%physics = sim%name()
    info%n_ranks = comm%size
    info%step = step
    info%time = t
    info%known_steps = schedule%known_steps()
    if (schedule%next(step + 1, t, t_next, dt)) info%next_dt = dt
    info%last_dt = last_dt
    if (with_output) then
      info%n_outputs = out%writer%n_outputs()
      call out%writer%save_index(out_index)
    end if
    call sim%save_state(st)
    st%time = t
    st%step = step
    call write_checkpoint(comm, path, info, st, with_output, out_index, status)
  end subroutine save_run

  !> Resume from the checkpoint at path: the physics' state, the output
  !> series (with_output), and the step to go on with (step: the step after
  !> the checkpoint's, t: its start). Collective; status agrees and names
  !> the file.
  subroutine resume_run(comm, log, sim, schedule, out, with_output, path, step, t, status)
    type(parallel_comm_t), intent(in) :: comm
    type(logger_t), intent(inout) :: log
    class(simulation_t), intent(inout) :: sim
    type(step_schedule_t), intent(in) :: schedule
    type(field_output_t), intent(inout) :: out
    logical, intent(in) :: with_output
    character(len=*), intent(in) :: path
    integer, intent(out) :: step
    real(rp), intent(out) :: t
    type(error_status_t), intent(inout) :: status
    type(checkpoint_info_t) :: info
    type(state_record_t) :: st, out_index
    logical :: has_index
    integer :: missing
    call read_checkpoint(comm, path, sim%name(), info, st, has_index, out_index, status)
    if (status%ok()) call check_schedule(schedule, info, status)
    if (status%ok()) then
      call sim%load_state(st, status)
      call agree(comm, status)
    end if
    if (status%ok() .and. with_output .and. has_index) then
      call out%writer%resume(out_index, missing, status)
      if (status%ok() .and. missing > 0) call log%warn(itoa(missing)//' output step files of the run before '// &
        'the restart are not in the output directory; the XDMF index lists them all')
    end if
    if (.not. status%ok()) then
      if (index(status%msg, trim(path)) == 0) status%msg = "restart file '"//trim(path)//"': "//trim(status%msg)
      return
    end if
    step = info%step + 1
    t = info%time
    call log%info("restart from '"//trim(path)//"': step "//itoa(info%step)//' at t = '//trim(rtoa(t))// &
                  ' was the last one done; the run goes on with step '//itoa(step))
  end subroutine resume_run

  !> The deck's schedule continues as the checkpoint's run would have (or,
  !> after a checkpoint at its run's end, goes on past it).
  subroutine check_schedule(schedule, info, status)
    type(step_schedule_t), intent(in) :: schedule
    type(checkpoint_info_t), intent(in) :: info
    type(error_status_t), intent(inout) :: status
    real(rp) :: t_next, dt
    if (schedule%known_steps() /= info%known_steps) then
      call status%set('written by a run of '//itoa(info%known_steps)//' load steps, this deck has '// &
                      itoa(schedule%known_steps())//' (&time n_steps must not change)')
      return
    end if
    dt = 0.0_rp
    if (.not. schedule%next(info%step + 1, info%time, t_next, dt)) dt = 0.0_rp
    ! a checkpoint written at the end of its run (no next step) may be
    ! continued by a deck whose t_end lies further
    if (info%next_dt == 0.0_rp .and. dt > 0.0_rp) return
    if (dt /= info%next_dt) call status%set('the deck''s &time gives step '//itoa(info%step + 1)// &
      ' the size '//trim(rtoa(dt))//', the checkpoint''s run '//trim(rtoa(info%next_dt))// &
      ' (&time must not change)')
  end subroutine check_schedule
end module run_checkpoint
