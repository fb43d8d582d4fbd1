!> Named wall-clock accumulators for the timing summary, each with the rise
!> of the process's peak resident memory (VmHWM) while it ran: the sum of
!> a rank's rises over its top-level timers is its peak, and each rise says
!> which phase first needed the memory (a later phase that reuses freed
!> memory shows none).
module timer_set
  use kinds, only: rp, gp, name_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use logger, only: logger_t
  use machine_memory, only: peak_resident_bytes
  implicit none
  private

  public :: timer_set_t

  integer, parameter :: max_timers = 64

  type :: timer_set_t
    integer :: n = 0
    character(len=name_len) :: names(max_timers) = ''
    real(rp) :: total(max_timers) = 0.0_rp
    real(rp) :: started(max_timers) = -1.0_rp
    integer :: calls(max_timers) = 0
    integer(gp) :: hwm0(max_timers) = 0        !< peak resident bytes at the start
    integer(gp) :: rise(max_timers) = 0        !< summed rises of the peak [bytes]
  contains
    procedure :: start
    procedure :: stop => stop_timer
    procedure :: add
    procedure :: elapsed
    procedure :: report
  end type timer_set_t

contains

  integer function find(self, name)
    class(timer_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer :: i
    do i = 1, self%n
      if (self%names(i) == name) then
        find = i
        return
      end if
    end do
    if (self%n == max_timers) error stop 'timer_set: too many timers'
    self%n = self%n + 1
    self%names(self%n) = name
    find = self%n
  end function find

  subroutine start(self, name)
    class(timer_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer :: i
    i = find(self, name)
    self%started(i) = wall_time()
    self%hwm0(i) = peak_resident_bytes()
  end subroutine start

  !> Stop a timer; returns the seconds of this interval if asked.
  subroutine stop_timer(self, name, seconds)
    class(timer_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(out), optional :: seconds
    integer :: i
    real(rp) :: dt
    i = find(self, name)
    dt = 0.0_rp
    if (self%started(i) >= 0.0_rp) dt = wall_time() - self%started(i)
    self%total(i) = self%total(i) + dt
    self%calls(i) = self%calls(i) + 1
    if (self%started(i) >= 0.0_rp .and. self%hwm0(i) >= 0) &
      self%rise(i) = self%rise(i) + max(peak_resident_bytes() - self%hwm0(i), 0_gp)
    self%started(i) = -1.0_rp
    if (present(seconds)) seconds = dt
  end subroutine stop_timer

  !> Add an interval measured elsewhere (seconds, and the rise of the peak
  !> resident memory in it [bytes]) to a timer, as one call.
  subroutine add(self, name, seconds, rise)
    class(timer_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in) :: seconds
    integer(gp), intent(in), optional :: rise
    integer :: i
    i = find(self, name)
    self%total(i) = self%total(i) + seconds
    self%calls(i) = self%calls(i) + 1
    if (present(rise)) self%rise(i) = self%rise(i) + max(rise, 0_gp)
  end subroutine add

  real(rp) function elapsed(self, name)
    class(timer_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    elapsed = self%total(find(self, name))
  end function elapsed

  !> Timing summary: the maximum over ranks of each accumulator.
  subroutine report(self, comm, log)
    class(timer_set_t), intent(in) :: self
    type(parallel_comm_t), intent(in) :: comm
    type(logger_t), intent(inout) :: log
    integer :: i
    integer(gp) :: peak
    character(len=160) :: line
    call log%info('timing summary (seconds, maximum over ranks)')
    do i = 1, self%n
      write(line, '(2x,a32,f12.3,i8,a)') self%names(i), comm%max(self%total(i)), self%calls(i), ' calls'
      call log%info(line)
    end do
    ! the peak resident memory: of the largest rank and over all ranks
    peak = peak_resident_bytes()
    if (comm%any_true(peak < 0)) return
    write(line, '(a,i0,a,i0,a)') 'peak resident memory: ', comm%max(peak) / 2_gp**20, ' MB on the largest rank, ', &
      comm%sum(peak) / 2_gp**20, ' MB over all ranks'
    call log%info(line)
    ! where the peak was reached: the timers whose phase raised it
    call log%info('peak memory rise by phase (MB, largest over ranks; indented: parts of the line above)')
    do i = 1, self%n
      if (comm%max(self%rise(i)) < 2_gp**20) cycle
      write(line, '(2x,a32,i12)') self%names(i), comm%max(self%rise(i)) / 2_gp**20
      call log%info(line)
    end do
  end subroutine report
end module timer_set
