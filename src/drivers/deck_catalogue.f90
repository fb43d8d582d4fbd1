!> The example decks behind the deck reference (geoblock --reference,
!> --help GROUP) and their readings.
!>
!> For every physics of simulation_factory: a base deck with the few
!> variables it cannot do without, and examples of the other groups. Each
!> deck is read by the path of a run (deck_t%load, run_config, the factory,
!> time_loop's read_physics_groups) and resolved by run_parameters'
!> resolved_groups, the registry that writes <prefix>_parameters.nml. An
!> example the physics refuses shows a group (or a kind of it) the physics
!> does not take; the base deck with every example it takes, then the
!> variants of &mesh (a core, a Gmsh file) and &time (a list of times)
!> give the variables, and the reader's defaults (deck_reference). So the
!> reference states what the readers do, not what was written about them.
!>
!> The decks are written to a temporary file (rank 0) and removed.
module deck_catalogue
  use kinds, only: name_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use os_services, only: process_id
  use strings, only: itoa
  use deck, only: deck_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use probe_config, only: probe_config_t
  use param_group, only: param_group_t, base_name, push_line, param_line_len
  use simulation, only: simulation_t
  use simulation_factory, only: make_simulation, physics_names
  use time_loop, only: read_physics_groups
  use run_parameters, only: resolved_groups
  use deck_reference, only: reading_t, reference_t
  implicit none
  private

  public :: build_reference


  !> One example group: its deck line, and what it adds to the &material
  !> line (a variable it needs there).
  type :: example_t
    character(len=240) :: text = ''
    character(len=40) :: material = ''
  end type example_t

  !> Defaults that depend on the deck rather than on the reader.
  character(len=160), parameter :: fixed_defaults(8) = [character(len=160) :: &
    'run%physics=''elasticity''', &
    'output%prefix=(the deck''s file name without its extension)', &
    'probe%name=(''probe<k>'', k the number of the &probe group)', &
    'fault%dip_axis=(the first axis other than normal_axis)', &
    'source%name=(''source<k>'', k the number of the &source group)', &
    'source%rate=(required unless pressure is given)', &
    'source%pressure=(required unless rate is given)', &
    'source%index=(required with pressure)']

  !> The examples of the groups a base deck leaves out, in deck order.
  type(example_t), parameter :: examples(19) = [ &
      example_t("&region name = 'lower_part', upper(3) = 0.5 /", ''), &
      example_t("&region name = 'upper_part', lower(3) = 0.5 /", ''), &
      example_t("&boundary set = 'zmin', type = 'displacement', ux = 0.0 /", ''), &
      example_t("&boundary set = 'zmin', type = 'displacement', uy = 0.0, uz = 0.0 /", ''), &
      example_t("&boundary set = 'zmax', type = 'traction', traction = 0.0, 0.0, -1.0e6 /", ''), &
      example_t("&boundary set = 'xmax', type = 'normal_traction', normal_traction = -1.0e6 /", ''), &
      example_t("&boundary set = 'zmax', type = 'pressure', pressure = 0.0 /", ''), &
      example_t("&boundary set = 'xmin', type = 'flux', flux = 0.0 /", ''), &
      example_t('&geostatic /', 'density = 2000.0'), &
      example_t("&pressure_change region = 'lower_part', value = -1.0e6 /", ''), &
      example_t("&pressure_change region = 'upper_part', value = -1.0e6, point = 0.5, 0.5, 0.75 /", ''), &
      example_t("&source region = 'domain', rate = 1.0e-6 /", ''), &
      example_t("&source region = 'upper_part', name = 'producer', pressure = 1.0e6, index = 1.0e-10 /", ''), &
      example_t("&fault name = 'disc', position = 0.25, radius = 0.2, centre = 0.5, 0.25, 0.5 /", ''), &
      example_t("&well name = 'w1', point = 0.5, 0.5, 0.5, rate = 1.0e-6 /", ''), &
      example_t("&well name = 'w2', segment = 0.5, 0.0, 0.5, 0.5, 1.0, 0.5, rate = 1.0e-6 /", ''), &
      example_t("&fracture_pressure fault = 'f', value = 1.0e6 /", ''), &
      example_t("&probe name = 'centre', x = 0.5, y = 0.5, z = 0.5, fields = 'ux' /", ''), &
      example_t("&probe set = 'zmax', fields = 'uz' /", '')]

contains

  !> The reference of every physics, from its example decks; groups and
  !> repeatable are the deck groups the program knows and those that may
  !> repeat (deck_t%check_groups). Collective; status names the deck and
  !> the reader's message when a base deck is refused (an example that has
  !> gone stale).
  subroutine build_reference(comm, groups, repeatable, ref, status)
    type(parallel_comm_t), intent(inout) :: comm
    character(len=*), intent(in) :: groups(:), repeatable(:)
    type(reference_t), intent(out) :: ref
    type(error_status_t), intent(inout) :: status
    character(len=name_len), allocatable :: names(:)
    logical, allocatable :: transient(:)
    character(len=path_len) :: path
    character(len=:), allocatable :: incomplete
    integer :: p
    call physics_list(names)
    allocate(transient(size(names)))
    transient = .false.
    call ref%init(names, transient, repeatable, fixed_defaults)
    path = temporary_path()
    do p = 1, size(names)
      call read_physics(comm, path, groups, repeatable, names(p), p, ref, status)
      if (.not. status%ok()) exit
    end do
    call remove_file(comm, path)
    if (.not. status%ok()) return
    call ref%finish(incomplete)
    if (len(incomplete) > 0) call status%set('deck reference:'//incomplete)
  end subroutine build_reference

  !> The names of simulation_factory's physics_names ("'a', 'b'").
  subroutine physics_list(names)
    character(len=name_len), allocatable, intent(out) :: names(:)
    integer :: i, j
    character(len=name_len), allocatable :: tmp(:)
    allocate(names(0))
    i = index(physics_names, "'")
    do while (i > 0)
      j = i + index(physics_names(i + 1:), "'")
      ! (no array constructor: gfortran 12's checked build mistakes the lengths)
      allocate(tmp(size(names) + 1))
      tmp(1:size(names)) = names
      tmp(size(tmp)) = physics_names(i + 1:j - 1)
      call move_alloc(tmp, names)
      i = index(physics_names(j + 1:), "'")
      if (i > 0) i = i + j
    end do
  end subroutine physics_list

  !> The readings of physics `name` (number p) into ref: each example alone
  !> on the base deck (to see whether the physics takes it), then the base
  !> deck with the examples it took, then the variants of &mesh and &time.
  subroutine read_physics(comm, path, groups, repeatable, name, p, ref, status)
    type(parallel_comm_t), intent(inout) :: comm
    character(len=*), intent(in) :: path, name
    character(len=*), intent(in) :: groups(:), repeatable(:)
    integer, intent(in) :: p
    type(reference_t), intent(inout) :: ref
    type(error_status_t), intent(inout) :: status
    logical :: transient, taken(size(examples))
    type(error_status_t) :: probe
    integer :: k
    transient = .false.
    do k = 1, size(examples)
      call probe%clear()
      call take(deck_lines(name, 'box', examples(k:k)), .false., probe)
      taken(k) = probe%ok()
    end do
    call take(deck_lines(name, 'box', pack(examples, taken)), .true., status)
    if (status%ok()) call take(deck_lines(name, 'core', examples(1:0)), .true., status)
    if (status%ok()) call take(deck_lines(name, 'gmsh', examples(1:0)), .true., status)
    if (status%ok() .and. transient) call take(deck_lines(name, 'times', examples(1:0)), .true., status)
    ref%transient(p) = transient
    if (.not. status%ok()) call status%set("deck reference: the example deck of physics '"//trim(name)// &
                                           "' was refused: "//trim(status%msg))
  contains
    !> Read the deck lines; keep: add the reading to ref.
    subroutine take(lines, keep, st)
      character(len=*), intent(in) :: lines(:)
      logical, intent(in) :: keep
      type(error_status_t), intent(inout) :: st
      type(reading_t) :: r
      call read_deck_text(comm, path, groups, repeatable, lines, p, r, transient, st)
      if (keep .and. st%ok()) call ref%add(r)
    end subroutine take
  end subroutine read_physics

  !> The deck of physics `name`: its base groups with &mesh of the variant
  !> ('box', 'core', 'gmsh') or &time of the variant 'times', then ex.
  function deck_lines(name, variant, ex) result(lines)
    character(len=*), intent(in) :: name, variant
    type(example_t), intent(in) :: ex(:)
    character(len=param_line_len), allocatable :: lines(:)
    character(len=:), allocatable :: material
    logical :: flow, faults, transient
    integer :: k
    flow = name == 'fracture_flow' .or. name == 'poromechanics_faults'
    faults = name == 'contact' .or. flow
    transient = name == 'biot' .or. flow
    allocate(lines(0))
    call push_line(lines, '! an example deck of the deck reference (deck_catalogue.f90)')
    ! elasticity leaves &run physics out: its default
    if (name /= 'elasticity') call push_line(lines, "&run physics = '"//name//"' /")
    select case (variant)
    case ('core')
      call push_line(lines, '&mesh nx = 4, ny = 4, nz = 4, core_n = 2, 0, 0, '// &
               'core_lower = 0.25, 0.0, 0.0, core_upper = 0.75, 0.0, 0.0 /')
    case ('gmsh')
      call push_line(lines, "&mesh source = 'gmsh', file = 'example.msh' /")
    case default
      call push_line(lines, '&mesh nx = 4, ny = 4, nz = 4 /')
    end select
    material = "&material region = 'domain', young = 1.0e9, poisson = 0.25"
    if (name == 'biot' .or. name == 'poromechanics_faults') material = material//', permeability = 1.0e-12'
    do k = 1, size(ex)
      if (len_trim(ex(k)%material) > 0) material = material//', '//trim(ex(k)%material)
    end do
    call push_line(lines, material//' /')
    if (variant == 'times') then
      call push_line(lines, '&time times = 1.0, 2.0 /')
    else if (transient) then
      call push_line(lines, '&time dt = 1.0, t_end = 1.0 /')
    end if
    if (faults .and. variant == 'gmsh') then
      call push_line(lines, "&fault name = 'f' /")
    else if (faults) then
      call push_line(lines, "&fault name = 'f', normal_axis = 'z', position = 0.5 /")
    end if
    do k = 1, size(ex)
      call push_line(lines, ex(k)%text)
    end do
  end function deck_lines

  !> Read the deck text as a run would and resolve its groups into r
  !> (physics number p); transient: the physics steps in time. Collective.
  subroutine read_deck_text(comm, path, groups, repeatable, lines, p, r, transient, status)
    type(parallel_comm_t), intent(inout) :: comm
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: groups(:), repeatable(:), lines(:)
    integer, intent(in) :: p
    type(reading_t), intent(out) :: r
    logical, intent(inout) :: transient
    type(error_status_t), intent(inout) :: status
    type(deck_t) :: d
    type(logger_t) :: log
    type(run_config_t) :: run
    type(mesh_config_t) :: mcfg
    type(probe_config_t), allocatable :: probes(:)
    class(simulation_t), allocatable :: sim
    type(param_group_t), allocatable :: resolved(:)
    call log%init(comm, verbosity=0)
    call write_lines(comm, path, lines, status)
    if (status%ok()) call d%load(comm, path, status)
    if (status%ok()) call d%check_groups(groups, repeatable, status)
    if (status%ok()) call run%read(d, log, status)
    if (status%ok()) call make_simulation(run%physics, sim, status)
    if (status%ok()) call read_physics_groups(comm, log, d, run, sim, mcfg, status, probes)
    if (status%ok()) then
      transient = sim%transient
      r%physics = p
      ! into a local array first: gfortran 12 copies the groups shallowly
      ! into a component (the groups then share their variables)
      call resolved_groups(run, mcfg, sim, probes, resolved)
      call move_alloc(resolved, r%groups)
      call given_flags(d, r)
    end if
    if (allocated(sim)) call sim%free()
  end subroutine read_deck_text

  !> Whether the deck wrote each variable of each resolved group (the k-th
  !> group of a name is the deck's k-th group of that name).
  subroutine given_flags(d, r)
    type(deck_t), intent(in) :: d
    type(reading_t), intent(inout) :: r
    integer :: g, j, k
    allocate(r%given(size(r%groups)))
    do g = 1, size(r%groups)
      k = 0
      do j = 1, g
        if (r%groups(j)%name == r%groups(g)%name) k = k + 1
      end do
      call group_flags(d, r%groups(g), k, r%given(g)%flag)
    end do
  end subroutine given_flags

  !> Whether the deck's k-th group of g's name wrote each variable of g.
  subroutine group_flags(d, g, k, flag)
    type(deck_t), intent(in) :: d
    type(param_group_t), intent(in) :: g
    integer, intent(in) :: k
    logical, allocatable, intent(out) :: flag(:)
    integer :: i
    allocate(flag(g%n))
    do i = 1, g%n
      flag(i) = d%assigned(trim(g%name), k, base_name(g%p(i)%name))
    end do
  end subroutine group_flags

  !> $TMPDIR (or /tmp)/geoblock_reference_<pid>.nml
  function temporary_path() result(path)
    character(len=path_len) :: path
    character(len=path_len) :: dir
    integer :: n, st
    call get_environment_variable('TMPDIR', dir, n, st)
    if (st /= 0 .or. n == 0) dir = '/tmp'
    path = trim(dir)//'/geoblock_reference_'//itoa(process_id())//'.nml'
  end function temporary_path

  !> Write lines to path on rank 0; status (the same on every rank) names
  !> the file when it cannot be written.
  subroutine write_lines(comm, path, lines, status)
    type(parallel_comm_t), intent(inout) :: comm
    character(len=*), intent(in) :: path, lines(:)
    type(error_status_t), intent(inout) :: status
    integer :: u, ios, k
    character(len=256) :: msg
    ios = 0
    if (comm%is_root()) then
      open(newunit=u, file=trim(path), status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios == 0) then
        do k = 1, size(lines)
          write(u, '(a)') trim(lines(k))
        end do
        close(u)
      end if
    end if
    call comm%bcast(ios)
    if (ios /= 0) call status%set("deck reference: cannot write the example deck '"//trim(path)//"'")
  end subroutine write_lines

  subroutine remove_file(comm, path)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    integer :: u, ios
    if (.not. comm%is_root()) return
    open(newunit=u, file=trim(path), status='old', iostat=ios)
    if (ios == 0) close(u, status='delete')
  end subroutine remove_file
end module deck_catalogue
