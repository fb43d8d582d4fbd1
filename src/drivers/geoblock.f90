!> geoblock: coupled poromechanics and fault mechanics on distributed meshes.
!>
!> Usage: mpirun -np N geoblock DECK.nml
!> The deck is a file of namelist groups (see README.md and input/). The
!> physics named in &run is made by simulation_factory and run by the one
!> time loop (time_loop.f90).
program geoblock
  use kinds, only: path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use status_sync, only: agree
  use os_services, only: make_directory
  use strings, only: itoa
  use deck, only: deck_t
  use run_config, only: run_config_t
  use simulation, only: simulation_t
  use simulation_factory, only: make_simulation, physics_names
  use time_loop, only: run_simulation
  implicit none

  type(parallel_comm_t) :: comm
  type(logger_t) :: log
  type(deck_t) :: d
  type(run_config_t) :: run
  type(error_status_t) :: status
  class(simulation_t), allocatable :: sim
  character(len=path_len) :: path
  integer :: ios

  call comm%init_world()
  call log%init(comm)
  path = ''
  if (command_argument_count() >= 1) call get_command_argument(1, path)
  if (len_trim(path) == 0) call log%fatal(comm, 'usage: geoblock DECK.nml   (see README.md for the deck groups)')

  call d%load(comm, trim(path), status)
  if (status%ok()) call d%check_groups( &
    [character(len=16) :: 'run', 'mesh', 'material', 'boundary', 'time', 'solver', 'amg', 'output', 'biot', 'source', &
     'afsai', 'block_fsai', 'fault', 'contact'], &
    [character(len=16) :: 'material', 'boundary', 'source', 'fault'], status)
  if (status%ok()) call run%read(d, log, status)
  if (status%ok()) then
    call make_simulation(run%physics, sim, status)
    if (.not. status%ok()) then
      call status%clear()
      call d%fail(status, 'run', 1, 'physics', 'must be one of '//physics_names//" (got '"//trim(run%physics)//"')")
    end if
  end if
  if (.not. status%ok()) call log%fatal(comm, status%msg)
  log%verbosity = run%verbosity

  ! output directory and log file (made by rank 0)
  if (comm%is_root()) then
    call make_directory(trim(run%out_dir), status)
    if (status%ok()) then
      call log%open_file(trim(run%out_dir)//'/'//trim(run%prefix)//'.log', ios)
      if (ios /= 0) call status%set("cannot write the log file '"//trim(run%out_dir)//'/'//trim(run%prefix)// &
                                    ".log'")
    end if
  end if
  call agree(comm, status)
  if (.not. status%ok()) call log%fatal(comm, 'output directory (&output dir): '//trim(status%msg))

  call log%info('geoblock: '//trim(run%title))
  call log%info('deck: '//trim(path)//', ranks: '//itoa(comm%size))
  call run_simulation(comm, log, d, run, sim)
  call log%close()
  call comm%finalize()
end program geoblock
