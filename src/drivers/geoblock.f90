!> geoblock: coupled poromechanics and fault mechanics on distributed meshes.
!>
!> Usage: mpirun -np N geoblock DECK.nml
!>        geoblock --check DECK.nml     read and check the deck, print it resolved, no run
!>        geoblock --help [GROUP]       usage, or every variable of one deck group
!>        geoblock --reference          every group and variable as Markdown (doc/reference/decks.md)
!>        geoblock --version
!> The deck is a file of namelist groups (doc/decks.md, doc/reference/decks.md
!> and input/). The physics named in &run is made by simulation_factory and
!> run by the one time loop (time_loop.f90).
program geoblock
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds, only: path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use status_sync, only: agree
  use os_services, only: make_directory, end_process
  use strings, only: itoa
  use deck, only: deck_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use simulation, only: simulation_t
  use simulation_factory, only: make_simulation, physics_names
  use time_loop, only: run_simulation, read_physics_groups
  use probe_config, only: probe_config_t
  use run_parameters, only: show_parameters
  use deck_reference, only: reference_t
  use deck_catalogue, only: build_reference
  use build_info, only: geoblock_version, git_commit, built_against
  use machine_memory, only: return_freed_memory
  implicit none

  !> the deck groups (the repeatable ones may appear more than once)
  character(len=17), parameter :: groups(21) = [character(len=17) :: 'run', 'mesh', 'region', 'material', 'boundary', &
    'time', 'solver', 'amg', 'output', 'biot', 'source', 'afsai', 'block_fsai', 'fault', 'contact', 'probe', &
    'fracture_flow', 'well', 'fracture_pressure', 'geostatic', 'pressure_change']
  character(len=17), parameter :: repeatable(9) = [character(len=17) :: 'region', 'material', 'boundary', 'source', &
    'fault', 'probe', 'well', 'fracture_pressure', 'pressure_change']

  type(parallel_comm_t) :: comm
  type(logger_t) :: log
  type(deck_t) :: d
  type(run_config_t) :: run
  type(error_status_t) :: status
  class(simulation_t), allocatable :: sim
  character(len=path_len) :: path
  character(len=16) :: mode

  call return_freed_memory()
  call comm%init_world()
  call log%init(comm)
  call command_line(comm, log, mode, path)
  if (mode == 'help' .and. len_trim(path) == 0) call say_and_end(usage_text())
  if (mode == 'help' .or. mode == 'reference') call reference_mode()
  if (mode == 'version') call say_and_end(version_text())

  call d%load(comm, trim(path), status)
  if (status%ok()) call d%check_groups(groups, repeatable, status)
  if (status%ok()) call run%read(d, log, status)
  if (status%ok()) then
    call make_simulation(run%physics, sim, status)
    if (.not. status%ok()) then
      call status%clear()
      call d%fail(status, 'run', 1, 'physics', 'must be one of '//physics_names//" (got '"//trim(run%physics)//"')")
    end if
  end if
  if (.not. status%ok()) call log%fatal(comm, status%msg)
  if (mode == 'check') call check_deck()
  log%verbosity = run%verbosity
  call open_log()
  call log%info('geoblock '//geoblock_version//' ('//git_commit//'): '//trim(run%title))
  call log%info('deck: '//trim(path)//', ranks: '//itoa(comm%size))
  call run_simulation(comm, log, d, run, sim)
  call log%close()
  call comm%finalize()

contains

  !> The mode ('run', 'check', 'help', 'reference', 'version') and the deck
  !> path (for 'help': the group asked about, or '') from the command line;
  !> a wrong command line stops with the usage.
  subroutine command_line(comm, log, mode, path)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    character(len=*), intent(out) :: mode, path
    integer :: k, n, length
    character(len=path_len) :: arg
    character(len=:), allocatable :: problem
    mode = 'run'
    path = ''
    problem = ''
    n = command_argument_count()
    do k = 1, n
      call get_command_argument(k, arg, length)
      if (length > len(arg)) then
        problem = 'argument '//itoa(k)//' is longer than '//itoa(len(arg))//' characters'
      else if (arg == '--help' .or. arg == '-h') then
        mode = 'help'
      else if (arg == '--version') then
        mode = 'version'
      else if (arg == '--check') then
        mode = 'check'
      else if (arg == '--reference') then
        mode = 'reference'
      else if (arg(1:1) == '-') then
        problem = "unknown option '"//trim(arg)//"'"
      else if (len_trim(path) > 0) then
        problem = "more than one deck given ('"//trim(path)//"' and '"//trim(arg)//"')"
      else
        path = arg
      end if
      if (len(problem) > 0) exit
    end do
    if (mode == 'help' .and. len(problem) == 0) return
    if (mode == 'version') return
    if (mode == 'reference' .and. len(problem) == 0 .and. len_trim(path) > 0) &
      problem = "--reference takes no deck (got '"//trim(path)//"')"
    if (mode == 'reference' .and. len(problem) == 0) return
    if (len(problem) == 0 .and. len_trim(path) == 0) problem = 'no deck given'
    if (len(problem) > 0) call log%fatal(comm, problem//'; usage: geoblock [--check] DECK.nml | --help [GROUP] '// &
                                         '| --reference | --version')
  end subroutine command_line

  !> Print text on rank 0 and end the run with status 0.
  subroutine say_and_end(text)
    character(len=*), intent(in) :: text
    if (comm%is_root()) write(*, '(a)') text
    call comm%finalize()
    call end_process(0)
  end subroutine say_and_end

  function usage_text() result(s)
    character(len=:), allocatable :: s
    character(len=*), parameter :: nl = new_line('a')
    integer :: k
    s = 'usage: mpirun -np N geoblock DECK.nml     run the deck'//nl// &
        '       geoblock --check DECK.nml          read and check the deck, print it resolved, run nothing'//nl// &
        '       geoblock --help [GROUP]            this text, or every variable of one deck group'//nl// &
        '       geoblock --reference               every group and variable, as Markdown'//nl// &
        '       geoblock --version'//nl//nl// &
        'A deck is a file of Fortran namelist groups (&name ... /). Groups:'//nl
    do k = 1, size(groups)
      s = s//'  &'//trim(groups(k))
      if (any(repeatable == groups(k))) s = s//' (may repeat)'
      s = s//nl
    end do
    s = s//'physics (&run physics): '//physics_names//nl// &
        'Every variable with its type, unit, default and allowed values: geoblock --help GROUP, or'//nl// &
        'doc/reference/decks.md; how decks work: doc/decks.md; the manual: doc/README.md; examples in input/.'// &
        nl//'Exit status: 0 done, 2 bad input or a run that cannot go on (one "geoblock: error:" line).'
  end function usage_text

  function version_text() result(s)
    character(len=:), allocatable :: s
    s = 'geoblock '//geoblock_version//' (commit '//git_commit//')'//new_line('a')// &
        'built against: '//built_against
  end function version_text

  !> --reference: the deck reference as Markdown; --help GROUP: one group
  !> of it as text. Both read example decks of every physics (deck_catalogue).
  subroutine reference_mode()
    type(reference_t) :: ref
    character(len=:), allocatable :: topic
    call build_reference(comm, groups, repeatable, ref, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    if (mode == 'reference') then
      if (comm%is_root()) call ref%markdown(output_unit, 'geoblock '//geoblock_version)
    else
      topic = trim(path)
      if (topic(1:1) == '&') topic = topic(2:)
      if (.not. ref%has_group(topic)) call log%fatal(comm, "--help: no deck group '"//trim(path)//"'; the "// &
                                                     'groups: '//ref%group_names())
      if (comm%is_root()) call ref%group_text(output_unit, topic)
    end if
    flush(output_unit)
    call comm%finalize()
    call end_process(0)
  end subroutine reference_mode

  !> --check: read every group the physics uses, print the resolved deck
  !> (what <prefix>_parameters.nml of a run would hold; the output is a
  !> deck) and stop.
  subroutine check_deck()
    type(mesh_config_t) :: mcfg
    type(probe_config_t), allocatable :: probes(:)
    call read_physics_groups(comm, log, d, run, sim, mcfg, status, probes)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call show_parameters(comm, d%path, run, mcfg, sim, probes)
    ! a comment line, so that the output is itself a deck
    call say_and_end("! deck '"//trim(path)//"' is valid (physics "//trim(run%physics)//'); nothing was run')
  end subroutine check_deck

  !> The output directory and the log file (made by rank 0). Collective.
  subroutine open_log()
    integer :: ios
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
  end subroutine open_log
end program geoblock
