!> Deck groups &run, &time and &output: run control.
!>
!> &run      title        free text shown in the log                         ['']
!>           physics      'elasticity', 'biot' (three-field poromechanics),
!>                        'contact' (elasticity with frictional faults, &fault
!>                        and &contact groups) or 'fracture_flow' (contact
!>                        with fluid in the fractures); the driver checks the
!>                        name against simulation_factory                   ['elasticity']
!>           verbosity    screen: 0 quiet, 1 progress lines, 2 also the
!>                        parameters; the log file always gets all of them [1]
!>           restart      checkpoint file to resume from (written by a run of
!>                        the same deck and physics on the same number of
!>                        ranks); the run goes on at the step after the
!>                        checkpoint's and continues its outputs            [none]
!> &time     n_steps      elasticity, contact: load steps; loads grow linearly and reach
!>                        their full value at the last step (>= 1)           [1]
!>           dt           biot, fracture_flow: first time step [s] (> 0)     [required]
!>           t_end        biot, fracture_flow: end time [s] (> 0)            [required]
!>                        (check_transient: required for every physics that
!>                        steps in time)
!>           dt_growth    biot, fracture_flow: ratio of successive steps (>= 1) [1]
!>           dt_max       biot, fracture_flow: largest step [s]              [no limit]
!>           undrained    biot, fracture_flow: a step 0 at t = 0 (biot: the
!>                        undrained response; fracture_flow: the mechanical
!>                        equilibrium at the initial pressure)           [.true.]
!>           times        biot, fracture_flow: explicit list of step end
!>                        times [s], increasing;
!>                        replaces dt, dt_growth, dt_max and t_end          [none]
!>           max_steps    the most steps a run may take (>= 1): n_steps, the
!>                        number of times, or the steps dt, dt_growth and
!>                        dt_max take to reach t_end (counted at read time)
!>                        above it are refused, and the schedule stops with
!>                        an error if it ever goes beyond it              [100000]
!> &output   dir          output directory (created if missing)             ['out']
!>           prefix       file name prefix                        [deck file name without .nml]
!>           fields       write HDF5 fields + XDMF                             [.true.]
!>           every        write every n-th step (the first and the last always) [1]
!>           export_matrix  write the assembled matrix and right-hand side of
!>                        the first step in MatrixMarket format                [.false.]
!>           checkpoint_every  write a checkpoint every n-th step (>= 0; 0 never;
!>                        SIGTERM / SIGUSR1 write one anyway)                  [0]
!>           checkpoint_file  the checkpoint's path, overwritten at each
!>                        checkpoint; a plain name goes into dir  [<dir>/<prefix>_checkpoint.h5]
module run_config
  use, intrinsic :: iso_fortran_env, only: int64
  use kinds, only: rp, ip, path_len, msg_len, name_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use strings, only: itoa, rtoa
  use os_services, only: absolute_path
  use param_group, only: param_group_t
  implicit none
  private

  public :: run_config_t

  integer, parameter :: max_times = 4096
  integer, parameter :: default_max_steps = 100000

  type :: run_config_t
    character(len=128) :: title = ''
    character(len=name_len) :: physics = 'elasticity'
    integer :: verbosity = 1
    integer :: n_steps = 1
    integer :: max_steps = default_max_steps      !< the most steps of a run
    real(rp) :: dt = -1.0_rp, t_end = -1.0_rp, dt_growth = 1.0_rp, dt_max = huge(1.0_rp)
    logical :: undrained = .true.
    real(rp), allocatable :: times(:)            !< explicit step end times (biot), if given
    character(len=path_len) :: out_dir = 'out'
    character(len=name_len) :: prefix = ''
    logical :: fields = .true.
    integer :: every = 1
    logical :: export_matrix = .false.
    integer :: checkpoint_every = 0
    character(len=path_len) :: checkpoint_file = ''   !< path of the checkpoint (resolved: never blank)
    character(len=path_len) :: restart = ''           !< checkpoint to resume from ('' none)
    character(len=path_len) :: checkpoint_given = ''  !< checkpoint_file as the deck gave it
  contains
    procedure :: read => read_run_config
    procedure :: describe => describe_run_config
    procedure :: check_transient
  end type run_config_t

contains

  !> Read &run, &time and &output (all optional). The time-step variables
  !> are checked for a transient physics by check_transient.
  subroutine read_run_config(self, d, log, status)
    class(run_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call read_run_group(self, d, log, status)
    if (status%ok()) call read_time_group(self, d, log, status)
    if (status%ok()) call read_output_group(self, d, log, status)
  end subroutine read_run_config

  subroutine read_run_group(self, d, log, status)
    type(run_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=128) :: title
    character(len=name_len) :: physics
    character(len=path_len) :: restart
    integer :: verbosity, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /run/ title, physics, verbosity, restart
    title = ''; physics = 'elasticity'; verbosity = 1; restart = ''
    if (d%count('run') > 0) then
      call d%block('run', 1, b)
      read(b, nml=run, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('run', 1, ios, msg, status)
        return
      end if
      if (verbosity < 0 .or. verbosity > 2) &
        call d%fail(status, 'run', 1, 'verbosity', 'must be 0, 1 or 2 (got '//itoa(verbosity)//')')
    end if
    if (.not. status%ok()) return
    self%title = title
    self%physics = physics
    self%verbosity = verbosity
    self%restart = restart
  end subroutine read_run_group

  subroutine read_time_group(self, d, log, status)
    type(run_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: n_steps, ios, nt, max_steps
    real(rp) :: dt, t_end, dt_growth, dt_max, times(max_times)
    logical :: undrained
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /time/ n_steps, dt, t_end, dt_growth, dt_max, undrained, times, max_steps
    max_steps = default_max_steps
    n_steps = 1; dt = unset_real; t_end = unset_real; dt_growth = 1.0_rp; dt_max = huge(1.0_rp); undrained = .true.
    times = unset_real
    if (d%count('time') > 0) then
      call d%block('time', 1, b)
      read(b, nml=time, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('time', 1, ios, msg, status)
        return
      end if
      if (n_steps < 1) call d%fail(status, 'time', 1, 'n_steps', 'must be at least 1 (got '//itoa(n_steps)//')')
      if (max_steps < 1) call d%fail(status, 'time', 1, 'max_steps', 'must be at least 1 (got '//itoa(max_steps)//')')
      if (status%ok() .and. n_steps > max_steps) call d%fail(status, 'time', 1, 'n_steps', &
        'n_steps = '//itoa(n_steps)//' is more than max_steps = '//itoa(max_steps)//' (raise max_steps)')
    end if
    nt = count(times /= unset_real)
    if (status%ok() .and. nt > max_steps) call d%fail(status, 'time', 1, 'times', &
      'the '//itoa(nt)//' times are more steps than max_steps = '//itoa(max_steps)//' (raise max_steps)')
    if (nt > 0) then
      if (any(times(nt+1:) /= unset_real)) call d%fail(status, 'time', 1, 'times', 'give the times without gaps')
      if (.not. times(1) > 0.0_rp) call d%fail(status, 'time', 1, 'times', 'the first time must be positive')
      if (nt > 1) then
        if (any(times(2:nt) <= times(1:nt-1))) call d%fail(status, 'time', 1, 'times', 'times must increase')
      end if
      if (dt /= unset_real .or. t_end /= unset_real) &
        call d%fail(status, 'time', 1, 'times', 'give either times or dt and t_end, not both')
      if (status%ok()) then
        dt = times(1)
        t_end = times(nt)
      end if
    end if
    if (.not. status%ok()) return
    self%n_steps = n_steps
    self%max_steps = max_steps
    self%dt = dt
    self%t_end = t_end
    self%dt_growth = dt_growth
    self%dt_max = dt_max
    self%undrained = undrained
    if (allocated(self%times)) deallocate(self%times)
    if (nt > 0) self%times = times(1:nt)
  end subroutine read_time_group

  subroutine read_output_group(self, d, log, status)
    type(run_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: ios, p, every, checkpoint_every
    character(len=path_len) :: dir, checkpoint_file
    character(len=name_len) :: prefix
    logical :: fields, export_matrix
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /output/ dir, prefix, fields, export_matrix, every, checkpoint_every, checkpoint_file
    dir = 'out'; fields = .true.; export_matrix = .false.; every = 1; checkpoint_every = 0; checkpoint_file = ''
    ! default prefix: the deck's file name without directory and extension
    prefix = d%path(index(d%path, '/', back=.true.) + 1:)
    p = index(prefix, '.', back=.true.)
    if (p > 1) prefix = prefix(1:p-1)
    if (d%count('output') > 0) then
      call d%block('output', 1, b)
      read(b, nml=output, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('output', 1, ios, msg, status)
        return
      end if
      if (len_trim(dir) == 0) call d%fail(status, 'output', 1, 'dir', 'must not be empty')
      if (every < 1) call d%fail(status, 'output', 1, 'every', 'must be at least 1 (got '//itoa(every)//')')
      if (checkpoint_every < 0) call d%fail(status, 'output', 1, 'checkpoint_every', &
        'must be 0 (never) or a positive number of steps (got '//itoa(checkpoint_every)//')')
      if (len_trim(prefix) == 0 .or. index(trim(prefix), '/') > 0 .or. index(trim(prefix), ' ') > 0) &
        call d%fail(status, 'output', 1, 'prefix', 'must be a plain file name (no blanks or /)')
    end if
    if (.not. status%ok()) return
    self%out_dir = dir
    self%prefix = prefix
    self%fields = fields
    self%every = every
    self%export_matrix = export_matrix
    self%checkpoint_every = checkpoint_every
    self%checkpoint_given = checkpoint_file
    ! a plain name lives in the output directory, a path is taken as it is
    if (len_trim(checkpoint_file) == 0) then
      self%checkpoint_file = trim(dir)//'/'//trim(prefix)//'_checkpoint.h5'
    else if (index(checkpoint_file, '/') == 0) then
      self%checkpoint_file = trim(dir)//'/'//trim(checkpoint_file)
    else
      self%checkpoint_file = checkpoint_file
    end if
  end subroutine read_output_group

  !> A physics that steps in time needs dt and t_end (or times) in &time,
  !> with dt_growth >= 1 and dt_max > 0; physics names it in the messages.
  subroutine check_transient(self, d, physics, status)
    class(run_config_t), intent(in) :: self
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: physics
    type(error_status_t), intent(inout) :: status
    if (self%dt == unset_real) then
      call d%fail(status, 'time', 1, 'dt', "required for physics = '"//trim(physics)//"'")
    else if (.not. self%dt > 0.0_rp) then
      call d%fail(status, 'time', 1, 'dt', 'must be positive (got '//rtoa(self%dt)//')')
    end if
    if (self%t_end == unset_real) then
      call d%fail(status, 'time', 1, 't_end', "required for physics = '"//trim(physics)//"'")
    else if (.not. self%t_end > 0.0_rp) then
      call d%fail(status, 'time', 1, 't_end', 'must be positive (got '//rtoa(self%t_end)//')')
    end if
    if (.not. self%dt_growth >= 1.0_rp) &
      call d%fail(status, 'time', 1, 'dt_growth', 'must be >= 1 (got '//rtoa(self%dt_growth)//')')
    if (.not. self%dt_max > 0.0_rp) &
      call d%fail(status, 'time', 1, 'dt_max', 'must be positive (got '//rtoa(self%dt_max)//')')
    if (status%ok() .and. .not. allocated(self%times)) call check_step_count(self, d, status)
  end subroutine check_transient

  !> The resolved &run, &time and &output groups (groups(1:3)), both kinds
  !> of stepping in &time (the physics drops the kind it does not use).
  subroutine describe_run_config(self, groups)
    class(run_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: groups(3)
    associate (g => groups(1))
      call g%init('run', 'what to run: the physics, the screen output, a restart')
      call g%add('title', self%title, '-', 'free text shown in the log', 'up to 128 characters')
      call g%add('physics', self%physics, '-', 'what to solve (see the physics table)', &
                 "'elasticity', 'biot', 'contact' or 'fracture_flow'")
      call g%add('verbosity', self%verbosity, '-', 'screen: 0 quiet, 1 progress, 2 also the parameters (the log '// &
                 'file always gets everything)', '0, 1 or 2')
      if (len_trim(self%restart) > 0) then
        call g%add('restart', absolute_path(self%restart), '-', 'checkpoint file the run resumed from')
      else
        call g%add_unset('restart', '(none)', '-', 'checkpoint file to resume from (written by the same deck on '// &
                         'the same number of ranks; relative to the working directory)', 'string', &
                         'a geoblock checkpoint')
      end if
    end associate
    associate (g => groups(2))
      call g%init('time', 'the steps: load steps, or time steps with their sizes')
      call g%add('n_steps', self%n_steps, '-', 'load steps; loads reach their full value at the last', &
                 '>= 1, <= max_steps')
      if (allocated(self%times)) then
        call g%add('times', self%times, 's', 'step end times (replace dt, t_end, dt_growth, dt_max)', &
                   '> 0, increasing, at most 4096', 'real list')
      else
        if (self%dt /= unset_real) then
          call g%add('dt', self%dt, 's', 'first time step', '> 0')
        else
          call g%add_unset('dt', '(not set)', 's', 'first time step', 'real', '> 0')
        end if
        if (self%t_end /= unset_real) then
          call g%add('t_end', self%t_end, 's', 'end time', '> 0')
        else
          call g%add_unset('t_end', '(not set)', 's', 'end time', 'real', '> 0')
        end if
        call g%add_unset('times', '(none: dt and t_end)', 's', 'step end times (replace dt, t_end, dt_growth, '// &
                         'dt_max)', 'real list', '> 0, increasing, at most 4096')
      end if
      call g%add('dt_growth', self%dt_growth, '-', 'ratio of successive steps', '>= 1')
      if (self%dt_max < huge(1.0_rp)) then
        call g%add('dt_max', self%dt_max, 's', 'largest step', '> 0')
      else
        call g%add_unset('dt_max', '(none)', 's', 'largest step (none: no limit)', 'real', '> 0')
      end if
      call g%add('undrained', self%undrained, '-', 'start with the undrained (instantaneous) response at t = 0: '// &
                 'step 0')
      call g%add('max_steps', self%max_steps, '-', 'the most steps a run may take (the steps dt, dt_growth and '// &
                 'dt_max need to reach t_end are counted when the deck is read)', '>= 1')
    end associate
    associate (g => groups(3))
      call g%init('output', 'what the run writes, where, and how often')
      call g%add('dir', self%out_dir, '-', 'output directory, created if missing (relative to the working '// &
                 'directory)', 'not empty')
      call g%add('prefix', self%prefix, '-', 'file name prefix of every output file', 'a file name: no blanks or /')
      call g%add('fields', self%fields, '-', 'write HDF5 fields + XDMF')
      call g%add('every', self%every, '-', 'write every n-th step (the first and last always)', '>= 1')
      call g%add('export_matrix', self%export_matrix, '-', 'write the first linear system as assembled '// &
                 '(MatrixMarket <prefix>_K.mtx, <prefix>_rhs.mtx)')
      call g%add('checkpoint_every', self%checkpoint_every, '-', 'checkpoint every n-th step (0 never; SIGTERM '// &
                 'and SIGUSR1 write one anyway)', '>= 0')
      call g%add('checkpoint_file', self%checkpoint_given, '-', "checkpoint path, overwritten at each checkpoint; "// &
                 "a plain name goes into dir ('': <dir>/<prefix>_checkpoint.h5)")
    end associate
  end subroutine describe_run_config

  !> The steps from dt (growing by dt_growth, at most dt_max) to t_end must
  !> be at most max_steps: counted step by step as the schedule takes them,
  !> without arithmetic that could overflow, up to max_steps + 1.
  subroutine check_step_count(self, d, status)
    type(run_config_t), intent(in) :: self
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
    real(rp) :: t, h, step_dt, t_stop
    integer :: k
    character(len=:), allocatable :: about, cap
    t = 0.0_rp
    h = self%dt
    t_stop = self%t_end * (1.0_rp - 1.0e-12_rp)   ! the schedule's end tolerance
    k = 0
    do while (t < t_stop)
      if (k >= self%max_steps) exit
      k = k + 1
      step_dt = min(h, self%dt_max, self%t_end - t)
      t = t + step_dt
      if (h >= self%t_end / self%dt_growth) then
        h = self%t_end                              ! growing further changes nothing
      else
        h = h * self%dt_growth
      end if
    end do
    if (t >= t_stop) return
    ! with constant steps, the count is t_end / dt (written from its logarithm: it may exceed the doubles)
    about = ''
    if (self%dt_growth == 1.0_rp .or. self%dt_max <= self%dt) &
      about = ', about '//steps_text(log10(self%t_end) - log10(min(self%dt, self%dt_max)))
    cap = ''
    if (self%dt_max < huge(1.0_rp)) cap = ', dt_max = '//rtoa(self%dt_max)
    call d%fail(status, 'time', 1, 'max_steps', 't_end = '//rtoa(self%t_end)//' with dt = '//rtoa(self%dt)// &
      ', dt_growth = '//rtoa(self%dt_growth)//cap//' takes more than max_steps = '//itoa(self%max_steps)// &
      ' steps'//about//' (raise max_steps, or use a larger dt, dt_growth or dt_max)')
  end subroutine check_step_count

  !> A step count 10**e as text: "2.5e+07" style, or "1e320" beyond the doubles.
  function steps_text(e) result(s)
    real(rp), intent(in) :: e
    character(len=:), allocatable :: s
    character(len=32) :: t
    if (e < 15.0_rp) then
      write(t, '(i0)') nint(10.0_rp**e, kind=int64)
    else if (e < 300.0_rp) then
      write(t, '(es10.3)') 10.0_rp**e
    else
      write(t, '(a,i0)') '1e', nint(e)
    end if
    s = trim(adjustl(t))
  end function steps_text
end module run_config
