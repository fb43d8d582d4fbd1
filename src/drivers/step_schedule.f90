!> The nominal steps of a run, from &time:
!>
!>  load steps (a quasi-static physics): steps 1 .. n_steps to the load
!>    factors step / n_steps (the "time" t runs from 0 to 1), after a step
!>    0 of size 0 at load 0 when the physics asks for one (&geostatic: the
!>    equilibrium of the in-situ state);
!>  time steps (a transient physics): an optional initial step 0 of size 0
!>    at t = 0 (&time undrained), then steps to the times of &time times, or
!>    of sizes dt * dt_growth**(step-1), at most dt_max, the last one ending
!>    at t_end.
!>
!> The driver may cut a nominal step into smaller sub-steps; the schedule
!> only says where each nominal step must end. The run is bounded by &time
!> max_steps (checked at read time where the count is known; beyond_limit
!> tells the driver when a run goes past it anyway).
module step_schedule
  use kinds, only: rp
  use run_config, only: run_config_t
  implicit none
  private

  public :: step_schedule_t

  !> Relative tolerance of "t has reached t_end".
  real(rp), parameter :: end_tol = 1.0e-12_rp

  type :: step_schedule_t
    logical :: transient = .false.
    integer :: n_steps = 1                    !< load steps
    integer :: max_steps = huge(1)            !< the most steps of the run
    logical :: initial_step = .false.         !< transient: a step of size 0 at t = 0 first
    real(rp) :: dt = 0.0_rp, t_end = 0.0_rp, dt_growth = 1.0_rp, dt_max = huge(1.0_rp)
    real(rp), allocatable :: times(:)
  contains
    procedure :: init
    procedure :: first_step
    procedure :: next
    procedure :: is_last
    procedure :: known_steps
    procedure :: beyond_limit
  end type step_schedule_t

contains

  !> The schedule of run for a transient or a quasi-static physics.
  subroutine init(self, run, transient, in_situ)
    class(step_schedule_t), intent(inout) :: self
    type(run_config_t), intent(in) :: run
    logical, intent(in) :: transient
    logical, intent(in) :: in_situ      !< a step 0 for the in-situ equilibrium (&geostatic)
    self%transient = transient
    self%n_steps = run%n_steps
    self%max_steps = run%max_steps
    self%initial_step = (transient .and. run%undrained) .or. in_situ
    self%dt = run%dt
    self%t_end = run%t_end
    self%dt_growth = run%dt_growth
    self%dt_max = run%dt_max
    if (allocated(run%times)) self%times = run%times
  end subroutine init

  !> Number of the first step: 0 for an initial step, else 1.
  integer function first_step(self)
    class(step_schedule_t), intent(in) :: self
    first_step = merge(0, 1, self%initial_step)
  end function first_step

  !> Step number `step` starts at time t: where it ends (t_target) and its
  !> size dt. False when the run is over.
  logical function next(self, step, t, t_target, dt)
    class(step_schedule_t), intent(in) :: self
    integer, intent(in) :: step
    real(rp), intent(in) :: t
    real(rp), intent(out) :: t_target, dt
    next = .true.
    if (.not. self%transient) then
      next = step <= self%n_steps
      t_target = real(step, rp) / real(self%n_steps, rp)
      dt = t_target - t
    else if (step == 0) then
      t_target = 0.0_rp
      dt = 0.0_rp
    else
      next = t < self%t_end * (1.0_rp - end_tol)
      if (allocated(self%times)) then
        dt = self%times(min(step, size(self%times))) - t
      else
        ! the growing size only where it can be the smallest: far beyond the
        ! others its power could overflow (the minimum is the same either way)
        dt = min(self%dt_max, self%t_end - t)
        if (dt > 0.0_rp) then
          if (log(self%dt) + real(step - 1, rp) * log(self%dt_growth) < log(dt) + 1.0_rp) &
            dt = min(self%dt * self%dt_growth**(step - 1), self%dt_max, self%t_end - t)
        end if
      end if
      t_target = t + dt
    end if
  end function next

  !> Step `step`, ending at t, is the last one of the run.
  logical function is_last(self, step, t)
    class(step_schedule_t), intent(in) :: self
    integer, intent(in) :: step
    real(rp), intent(in) :: t
    if (self%transient) then
      is_last = t >= self%t_end * (1.0_rp - end_tol)
    else
      is_last = step == self%n_steps
    end if
  end function is_last

  !> Step `step` would go beyond &time max_steps (the first step is 1; an
  !> initial step 0 does not count).
  logical function beyond_limit(self, step)
    class(step_schedule_t), intent(in) :: self
    integer, intent(in) :: step
    beyond_limit = step > self%max_steps
  end function beyond_limit

  !> The number of steps when known in advance (load steps), else 0.
  integer function known_steps(self)
    class(step_schedule_t), intent(in) :: self
    known_steps = merge(0, self%n_steps, self%transient)
  end function known_steps
end module step_schedule
