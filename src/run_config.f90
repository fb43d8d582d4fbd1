!> Deck groups &run, &time and &output: run control.
!>
!> &run      title        free text shown in the log                         ['']
!>           physics      'elasticity' (the physics this build solves)        ['elasticity']
!>           verbosity    0 quiet, 1 progress lines, 2 also the deck echo     [1]
!> &time     n_steps      load steps; loads grow linearly and reach their
!>                        full value at the last step (>= 1)                 [1]
!> &output   dir          output directory (created if missing)             ['out']
!>           prefix       file name prefix                        [deck file name without .nml]
!>           fields       write HDF5 fields + XDMF each step                  [.true.]
!>           export_matrix  write the assembled matrix and right-hand side of
!>                        the first step in MatrixMarket format                [.false.]
module run_config
  use kinds, only: ip, path_len, msg_len, name_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, echo_len
  use strings, only: itoa
  implicit none
  private

  public :: run_config_t

  type :: run_config_t
    character(len=128) :: title = ''
    character(len=name_len) :: physics = 'elasticity'
    integer :: verbosity = 1
    integer :: n_steps = 1
    character(len=path_len) :: out_dir = 'out'
    character(len=name_len) :: prefix = ''
    logical :: fields = .true.
    logical :: export_matrix = .false.
  contains
    procedure :: read => read_run_config
  end type run_config_t

contains

  !> Read &run, &time and &output (all optional).
  subroutine read_run_config(self, d, log, status)
    class(run_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=128) :: title
    character(len=name_len) :: physics
    integer :: verbosity, n_steps, ios, p
    character(len=path_len) :: dir
    character(len=name_len) :: prefix
    logical :: fields, export_matrix
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=echo_len) :: echo(16)
    namelist /run/ title, physics, verbosity
    namelist /time/ n_steps
    namelist /output/ dir, prefix, fields, export_matrix

    title = ''; physics = 'elasticity'; verbosity = 1
    if (d%count('run') > 0) then
      call d%block('run', 1, b)
      read(b, nml=run, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('run', 1, ios, msg, status)
        return
      end if
      if (physics /= 'elasticity') &
        call d%fail(status, 'run', 1, 'physics', "must be 'elasticity' (got '"//trim(physics)//"')")
      if (verbosity < 0 .or. verbosity > 2) &
        call d%fail(status, 'run', 1, 'verbosity', 'must be 0, 1 or 2 (got '//itoa(verbosity)//')')
    end if
    n_steps = 1
    if (d%count('time') > 0) then
      call d%block('time', 1, b)
      read(b, nml=time, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('time', 1, ios, msg, status)
        return
      end if
      if (n_steps < 1) call d%fail(status, 'time', 1, 'n_steps', 'must be at least 1 (got '//itoa(n_steps)//')')
    end if
    dir = 'out'; fields = .true.; export_matrix = .false.
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
      if (len_trim(prefix) == 0 .or. index(trim(prefix), '/') > 0 .or. index(trim(prefix), ' ') > 0) &
        call d%fail(status, 'output', 1, 'prefix', 'must be a plain file name (no blanks or /)')
    end if
    if (.not. status%ok()) return
    self%title = title
    self%physics = physics
    self%verbosity = verbosity
    self%n_steps = n_steps
    self%out_dir = dir
    self%prefix = prefix
    self%fields = fields
    self%export_matrix = export_matrix
    echo = ''
    write(echo, nml=run, iostat=ios)
    call d%echo(log, echo)
    echo = ''
    write(echo, nml=time, iostat=ios)
    call d%echo(log, echo)
    echo = ''
    write(echo, nml=output, iostat=ios)
    call d%echo(log, echo)
  end subroutine read_run_config
end module run_config
