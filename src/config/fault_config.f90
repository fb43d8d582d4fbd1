!> Deck group &fault (any number, one per fault or fracture): where a fault
!> lies and its contact properties.
!>
!>   name              name of the fault; with source = 'gmsh' the physical
!>                     surface of the mesh that is the fault            [required]
!> Geometry, for source = 'box' only (refused with 'gmsh', where the mesh file
!> holds it): the fault lies on the node layer of the box nearest to position
!> along normal_axis, made planar with the inclination dip (see box_mesh).
!>   normal_axis       'x', 'y' or 'z': axis the (undipped) fault is normal to  ['y']
!>   position          coordinate of the fault along normal_axis [m], at the
!>                     middle of the box along dip_axis                  [required]
!>   dip               inclination [degrees], |dip| < 80: the fault rises
!>                     by tan(dip) along normal_axis per unit of dip_axis   [0]
!>   dip_axis          'x', 'y' or 'z', not normal_axis     [first axis /= normal_axis]
!>   lower(3), upper(3) in-plane extent [m]: the fault's quads are those whose
!>                     centres (before the dip) lie within [lower, upper] in the
!>                     two in-plane coordinates; the component along normal_axis
!>                     is ignored. An extent strictly inside the box makes a
!>                     fracture with tips                          [the whole box]
!>   radius            [m], > 0: a circular fault (a disc): of the quads within
!>                     lower..upper, only those whose centres lie within radius
!>                     of centre in the fault plane; dip = 0 only  [none: the rectangle]
!>   centre(3)         the disc's centre [m]; its two in-plane components are
!>                     used (the one along normal_axis is ignored)   [required with radius]
!> Contact properties (used by the contact physics):
!>   friction_angle    Coulomb friction angle [degrees], 0 <= . < 90        [30]
!>   cohesion          [Pa], >= 0                                            [0]
!>   pressure          fluid pressure acting on both faces [Pa]              [0]
!>   pressure_history  optional file of "time factor" rows (# comments) that
!>                     multiplies pressure, as history in &boundary         ['']
!>   initial_state     'stick' or 'open'                                ['stick']
!> Exchange with the matrix's fluid (physics = 'poromechanics_faults' only;
!> matrix_flow_component.f90):
!>   exchange          'open': the matrix's pressure on the fault's faces is
!>                     the fracture's; 'sealing': no flux through the faces;
!>                     'barrier': a flux lambda |f| (p - p_f) through a face
!>                     of area |f|                                    ['open']
!>   exchange_transmissibility  lambda [m/(Pa s)], > 0 (= k_b / (mu w) of a
!>                     barrier of permeability k_b and thickness w); with
!>                     exchange = 'barrier' only, and required there
module fault_config
  use kinds, only: rp, name_len, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use strings, only: rtoa
  use history_file, only: read_history, history_factor
  use os_services, only: absolute_path
  use param_group, only: param_group_t
  implicit none
  private

  public :: fault_config_t, read_faults, load_fault_histories

  !> One &fault group, validated. lower/upper default to -huge/+huge (the
  !> whole box); hist_t/hist_f hold the pressure history once loaded.
  type :: fault_config_t
    character(len=name_len) :: name = ''
    ! geometry for source = 'box'
    character(len=1) :: normal_axis = 'y'
    real(rp) :: position = unset_real                !< [m]
    real(rp) :: dip = 0.0_rp                         !< [degrees]
    character(len=1) :: dip_axis = ''
    real(rp) :: lower(3) = -huge(1.0_rp), upper(3) = huge(1.0_rp)   !< [m]
    real(rp) :: radius = 0.0_rp                      !< [m] of a circular fault; 0: none (the rectangle)
    real(rp) :: centre(3) = 0.0_rp                   !< [m] centre of the disc (in-plane components used)
    ! contact properties
    real(rp) :: friction_angle = 30.0_rp             !< [degrees]
    real(rp) :: cohesion = 0.0_rp                    !< [Pa]
    real(rp) :: pressure = 0.0_rp                    !< [Pa]
    character(len=path_len) :: pressure_history = ''
    character(len=8) :: initial_state = 'stick'
    ! exchange with the matrix's fluid
    character(len=8) :: exchange = 'open'
    real(rp) :: exchange_transmissibility = 0.0_rp   !< [m/(Pa s)], 'barrier' only
    real(rp), allocatable :: hist_t(:), hist_f(:)
    logical :: box_geometry = .true.                 !< the geometry variables apply (box mesh)
  contains
    procedure :: factor
    procedure :: describe => describe_fault
    procedure :: normal_index
    procedure :: dip_index
  end type fault_config_t

  character(len=*), parameter :: axes = 'xyz'

contains

  !> Read every &fault group for a mesh from source ('box' or 'gmsh').
  subroutine read_faults(d, log, faults, status, source)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(fault_config_t), allocatable, intent(out) :: faults(:)
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in) :: source
    character(len=name_len) :: name
    character(len=1) :: normal_axis, dip_axis
    real(rp) :: position, dip, lower(3), upper(3), radius, centre(3), friction_angle, cohesion, pressure
    character(len=path_len) :: pressure_history
    character(len=8) :: initial_state, exchange
    real(rp) :: exchange_transmissibility
    integer :: k, j, i, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=8) :: ic
    namelist /fault/ name, normal_axis, position, dip, dip_axis, lower, upper, radius, centre, friction_angle, &
                     cohesion, pressure, pressure_history, initial_state, exchange, exchange_transmissibility

    allocate(faults(d%count('fault')))
    do k = 1, size(faults)
      name = ''; normal_axis = ' '; position = unset_real; dip = unset_real; dip_axis = ' '
      lower = unset_real; upper = unset_real; radius = unset_real; centre = unset_real
      friction_angle = 30.0_rp; cohesion = 0.0_rp; pressure = 0.0_rp; pressure_history = ''
      initial_state = 'stick'; exchange = 'open'; exchange_transmissibility = unset_real
      call d%block('fault', k, b)
      read(b, nml=fault, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('fault', k, ios, msg, status)
        return
      end if
      if (len_trim(name) == 0) call d%fail(status, 'fault', k, 'name', 'required')
      do j = 1, k - 1
        if (faults(j)%name == name) then
          write(ic, '(i0)') j
          call d%fail(status, 'fault', k, 'name', "'"//trim(name)//"' is already the name of &fault number "// &
                      trim(ic)//' (fault names must be distinct)')
        end if
      end do
      select case (source)
      case ('box')
        if (normal_axis == ' ') normal_axis = 'y'
        if (index(axes, normal_axis) == 0) &
          call d%fail(status, 'fault', k, 'normal_axis', "must be 'x', 'y' or 'z' (got '"//normal_axis//"')")
        if (position == unset_real) call d%fail(status, 'fault', k, 'position', "required when the mesh is a box")
        if (dip == unset_real) dip = 0.0_rp
        if (.not. (abs(dip) < 80.0_rp)) &
          call d%fail(status, 'fault', k, 'dip', 'must lie in (-80, 80) degrees (got '//rtoa(dip)//')')
        if (dip_axis == ' ') then
          dip_axis = 'x'
          if (normal_axis == 'x') dip_axis = 'y'
        end if
        if (index(axes, dip_axis) == 0) then
          call d%fail(status, 'fault', k, 'dip_axis', "must be 'x', 'y' or 'z' (got '"//dip_axis//"')")
        else if (dip_axis == normal_axis) then
          call d%fail(status, 'fault', k, 'dip_axis', "must differ from normal_axis ('"//normal_axis//"')")
        end if
        do i = 1, 3
          if (axes(i:i) == normal_axis) cycle
          if (lower(i) /= unset_real .and. upper(i) /= unset_real) then
            if (upper(i) <= lower(i)) then
              write(ic, '(i0)') i
              call d%fail(status, 'fault', k, 'upper('//trim(ic)//')', 'must be greater than lower('//trim(ic)//')')
            end if
          end if
        end do
        where (lower == unset_real) lower = -huge(1.0_rp)
        where (upper == unset_real) upper = huge(1.0_rp)
        call check_disc()
      case ('gmsh')
        if (normal_axis /= ' ') call gmsh_refuses('normal_axis')
        if (position /= unset_real) call gmsh_refuses('position')
        if (dip /= unset_real) call gmsh_refuses('dip')
        if (dip_axis /= ' ') call gmsh_refuses('dip_axis')
        if (any(lower /= unset_real)) call gmsh_refuses('lower')
        if (any(upper /= unset_real)) call gmsh_refuses('upper')
        if (radius /= unset_real) call gmsh_refuses('radius')
        if (any(centre /= unset_real)) call gmsh_refuses('centre')
        normal_axis = 'y'; dip = 0.0_rp; dip_axis = 'x'
        lower = -huge(1.0_rp); upper = huge(1.0_rp)
        radius = 0.0_rp; centre = 0.0_rp
      case default
        call status%set("read_faults: unknown mesh source '"//trim(source)//"'")
      end select
      if (.not. (friction_angle >= 0.0_rp .and. friction_angle < 90.0_rp)) &
        call d%fail(status, 'fault', k, 'friction_angle', 'must lie in [0, 90) degrees (got '//rtoa(friction_angle)//')')
      if (.not. (cohesion >= 0.0_rp)) &
        call d%fail(status, 'fault', k, 'cohesion', 'must not be negative (got '//rtoa(cohesion)//')')
      if (initial_state /= 'stick' .and. initial_state /= 'open') &
        call d%fail(status, 'fault', k, 'initial_state', "must be 'stick' or 'open' (got '"//trim(initial_state)//"')")
      call check_exchange(d, k, exchange, exchange_transmissibility, status)
      if (.not. status%ok()) return
      faults(k)%name = name
      faults(k)%normal_axis = normal_axis
      faults(k)%position = position
      faults(k)%dip = dip
      faults(k)%dip_axis = dip_axis
      faults(k)%lower = lower
      faults(k)%upper = upper
      faults(k)%radius = radius
      faults(k)%centre = centre
      faults(k)%friction_angle = friction_angle
      faults(k)%cohesion = cohesion
      faults(k)%pressure = pressure
      call d%input_path('fault', k, 'pressure_history', pressure_history, faults(k)%pressure_history, status)
      faults(k)%initial_state = initial_state
      faults(k)%box_geometry = source == 'box'
      faults(k)%exchange = exchange
      faults(k)%exchange_transmissibility = exchange_transmissibility
    end do
  contains

    !> radius and centre of a circular fault (box): radius > 0, dip = 0, the
    !> in-plane components of centre given; without radius, no centre.
    !> Leaves radius = 0 (no disc) or the disc with centre's normal
    !> component on the plane (position) when the deck left it out.
    subroutine check_disc()
      integer :: a, c
      a = index(axes, normal_axis)
      if (radius == unset_real) then
        if (any(centre /= unset_real)) &
          call d%fail(status, 'fault', k, 'centre', 'is the centre of a circular fault and needs radius')
        radius = 0.0_rp; centre = 0.0_rp
        return
      end if
      if (.not. (radius > 0.0_rp)) &
        call d%fail(status, 'fault', k, 'radius', 'must be positive (got '//rtoa(radius)//')')
      if (dip /= 0.0_rp) &
        call d%fail(status, 'fault', k, 'radius', 'a circular fault must have dip = 0 (got dip = '//rtoa(dip)// &
                    '): the disc of a dipping fault is not supported')
      do c = 1, 3
        if (c == a .or. centre(c) /= unset_real) cycle
        write(ic, '(i0)') c
        call d%fail(status, 'fault', k, 'centre('//trim(ic)//')', 'required with radius (the in-plane '// &
                    'components of the centre of the disc)')
      end do
      if (a > 0) then
        if (centre(a) == unset_real) centre(a) = position
      end if
    end subroutine check_disc

    subroutine gmsh_refuses(var)
      character(len=*), intent(in) :: var
      call d%fail(status, 'fault', k, var, "only for a box mesh: with source = 'gmsh' the mesh file holds the "// &
                  "fault's geometry")
    end subroutine gmsh_refuses
  end subroutine read_faults

  !> exchange is 'open', 'sealing' or 'barrier'; a barrier needs its
  !> transmissibility (> 0), which the others refuse (&fault number k; an
  !> unset transmissibility becomes 0).
  subroutine check_exchange(d, k, exchange, exchange_transmissibility, status)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: k
    character(len=*), intent(in) :: exchange
    real(rp), intent(inout) :: exchange_transmissibility
    type(error_status_t), intent(inout) :: status
    if (exchange /= 'open' .and. exchange /= 'sealing' .and. exchange /= 'barrier') then
      call d%fail(status, 'fault', k, 'exchange', "must be 'open', 'sealing' or 'barrier' (got '"// &
                  trim(exchange)//"')")
    else if (exchange == 'barrier') then
      if (exchange_transmissibility == unset_real) then
        call d%fail(status, 'fault', k, 'exchange_transmissibility', "required with exchange = 'barrier' "// &
                    '(the flux per area and pressure difference through the barrier, m/(Pa s))')
      else if (.not. (exchange_transmissibility > 0.0_rp .and. exchange_transmissibility < huge(1.0_rp))) then
        call d%fail(status, 'fault', k, 'exchange_transmissibility', 'must be positive and finite (got '// &
                    rtoa(exchange_transmissibility)//')')
      end if
    else if (exchange_transmissibility /= unset_real) then
      call d%fail(status, 'fault', k, 'exchange_transmissibility', "is for exchange = 'barrier' only (got "// &
                  "exchange = '"//trim(exchange)//"')")
    end if
    if (exchange_transmissibility == unset_real) exchange_transmissibility = 0.0_rp
  end subroutine check_exchange

  !> The resolved &fault group: the geometry only for a box mesh, a
  !> circular fault's radius and centre only when it has them.
  subroutine describe_fault(self, g)
    class(fault_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    character(len=10) :: v
    integer :: i
    call g%init('fault', 'a fault or fracture: where it lies (box meshes) and its friction (one group per fault)')
    call g%add('name', self%name, '-', 'name of the fault; with a Gmsh mesh the internal physical surface that '// &
               'is the fault', 'unique')
    if (self%box_geometry) then
      call g%add('normal_axis', self%normal_axis, '-', 'box: axis the undipped fault is normal to', &
                 "'x', 'y' or 'z'")
      call g%add('position', self%position, 'm', 'box: the fault is the node layer nearest to this coordinate '// &
                 'along normal_axis (at mid-box along dip_axis)')
      call g%add('dip', self%dip, 'degrees', 'box: inclination along dip_axis (the layer is sheared into the '// &
                 'plane; cells crossing a fracture with tips are squared up)', '(-80, 80)')
      call g%add('dip_axis', self%dip_axis, '-', 'box: axis along which the fault rises', &
                 "'x', 'y' or 'z', not normal_axis")
      call g%add_bounds('lower', self%lower, '(none: the box edge)', 'm', 'box: lower in-plane bound of the '// &
                        'quads (the component along normal_axis is ignored); inside the box: a fracture with tips')
      call g%add_bounds('upper', self%upper, '(none: the box edge)', 'm', 'box: upper in-plane bound of the '// &
                        'quads', '> lower')
      if (self%radius > 0.0_rp) then
        call g%add('radius', self%radius, 'm', 'box, dip = 0: a circular fault, the quads whose centres lie '// &
                   'within radius of centre in its plane', '> 0')
        do i = 1, 3
          write(v, '(a,i0,a)') 'centre(', i, ')'
          call g%add(trim(v), self%centre(i), 'm', 'centre of the circular fault (its in-plane components are '// &
                     'required with radius)')
        end do
      else
        call g%add_unset('radius', '(none: the rectangle lower..upper)', 'm', 'box, dip = 0: a circular fault, '// &
                         'the quads whose centres lie within radius of centre in its plane', 'real', '> 0')
      end if
    end if
    call g%add('friction_angle', self%friction_angle, 'degrees', 'Coulomb friction angle phi: tau_max = c - '// &
               'tan(phi) t_N', '[0, 90)')
    call g%add('cohesion', self%cohesion, 'Pa', 'cohesion c', '>= 0')
    call g%add('pressure', self%pressure, 'Pa', 'fluid pressure on both faces, grown with the load like the '// &
               "other loads (not with 'fracture_flow', where it is an unknown)")
    call g%add('pressure_history', absolute_path(self%pressure_history), '-', "file of 'time factor' rows "// &
               "scaling pressure ('': none)")
    call g%add('initial_state', self%initial_state, '-', 'status of every element at the start', &
               "'stick' or 'open'")
    call g%add('exchange', self%exchange, '-', "exchange with the matrix's fluid ('poromechanics_faults'): "// &
               "'open' (the faces' matrix pressure is the fracture's), 'sealing' (no flux through the faces) or "// &
               "'barrier' (flux lambda |f| (p - p_f) through a face)", "'open', 'sealing' or 'barrier'")
    if (self%exchange == 'barrier') then
      call g%add('exchange_transmissibility', self%exchange_transmissibility, 'm/(Pa s)', 'lambda of the '// &
                 'barrier: flux per face area and pressure difference (k_b / (mu w))', "> 0; exchange = 'barrier' only")
    else
      call g%add_unset('exchange_transmissibility', "(none: exchange is not 'barrier')", 'm/(Pa s)', 'lambda of '// &
                       'the barrier: flux per face area and pressure difference (k_b / (mu w))', 'real', &
                       "> 0; exchange = 'barrier' only")
    end if
  end subroutine describe_fault

  !> Axis index 1..3 of normal_axis.
  integer function normal_index(self)
    class(fault_config_t), intent(in) :: self
    normal_index = index(axes, self%normal_axis)
  end function normal_index

  !> Axis index 1..3 of dip_axis (its default when left empty).
  integer function dip_index(self)
    class(fault_config_t), intent(in) :: self
    dip_index = index(axes, self%dip_axis)
    if (self%dip_axis == ' ') dip_index = merge(2, 1, self%normal_axis == 'x')
  end function dip_index

  !> Multiplier of the fault's pressure at time t [s] (elasticity: the load
  !> factor): 1 without a history, else the history linearly interpolated.
  real(rp) function factor(self, t)
    class(fault_config_t), intent(in) :: self
    real(rp), intent(in) :: t
    factor = 1.0_rp
    if (allocated(self%hist_t)) factor = history_factor(self%hist_t, self%hist_f, t)
  end function factor

  !> Read the pressure_history files of the faults (rank 0) and broadcast
  !> them (format of module history_file). Errors name the fault, the file
  !> and the line. Collective.
  subroutine load_fault_histories(comm, faults, status)
    type(parallel_comm_t), intent(in) :: comm
    type(fault_config_t), intent(inout) :: faults(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    character(len=msg_len) :: msg
    do k = 1, size(faults)
      if (len_trim(faults(k)%pressure_history) == 0) cycle
      call read_history(comm, faults(k)%pressure_history, faults(k)%hist_t, faults(k)%hist_f, msg)
      if (len_trim(msg) > 0) then
        call status%set("&fault '"//trim(faults(k)%name)//"': pressure_history file '"// &
                        trim(faults(k)%pressure_history)//"': "//trim(msg), 1)
        return
      end if
    end do
  end subroutine load_fault_histories
end module fault_config
