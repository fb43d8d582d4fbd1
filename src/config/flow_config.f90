!> Deck groups of the fluid in the fractures (physics = 'fracture_flow').
!>
!> &fracture_flow (optional group):
!>   viscosity          fluid viscosity mu [Pa s], > 0                    [1e-3]
!>   residual_aperture  hydraulic aperture a0 of a closed fracture [m], in
!>                      (0, 1):
!>                      the aperture is a = max(g_N, 0) + a0, so that closed
!>                      fractures still conduct                          [1e-5]
!>   initial_pressure   fluid pressure in every fracture at the start [Pa]   [0]
!>   compressibility    fluid compressibility c_f [1/Pa], in [0, 1e-3): the storage
!>                      A a c_f dp of an element; it fixes the pressure of a
!>                      closed fracture, which the rock does not (water at
!>                      20 C: 4.5e-10)                                 [4.5e-10]
!>   pressure_block     method = 'fgmres': how the block preconditioner treats
!>                      the pressure: 'schur' (the seed's second level: the
!>                      pressure last, its Schur complement S_p from the
!>                      diagonal of the first level's S*) or 'eliminated'
!>                      (eliminated with the tractions before the
!>                      displacement, by the row sums of its block: the
!>                      fluid's constraint on the opening joins S* as
!>                      S** = S* - Q1 D_p^-1 Q2, one AMG per iteration;
!>                      on the reduced nine-fracture case 2.3x faster
!>                      over the run than 'schur', measured before the
!>                      subspace correction)                  ['eliminated']
!>   pressure_precon    pressure_block = 'schur': preconditioner of S_p,
!>                      'boomeramg' or 'jacobi'                  ['boomeramg']
!>   subspace_correction  method = 'fgmres': before the block preconditioner,
!>                      a correction in the fractures' subspace: per
!>                      element its pressure with its normal traction (which
!>                      the Jacobian nearly annihilates on closed elements
!>                      when the fluid is stiff and the residual aperture
!>                      small), its operator a Laplacian on the fracture
!>                      surfaces solved by BoomerAMG; on the nine-fracture
!>                      case it keeps the counts near the contact-only ones
!>                      under refinement                             [.true.]
!>
!> &well (any number; at least one or a fracture gets no fluid): a source of
!> fluid, either at a point (into the fracture element whose centre is
!> nearest to it) or along a segment that crosses one or more fractures, its
!> rate split among them by their pressures (fracture_wells):
!>   name               name of the well (CSV column)                  [required]
!>   point(3)           where the well meets the fracture [m]
!>   segment(6)         start and end [m] of a straight well: it feeds the
!>                      element of every fault it crosses (one per fault),
!>                      all at one bottom-hole pressure p_w, the connection
!>                      rates J_i (p_w - p_i) summing to the well's rate
!>                                       [one of point and segment is required]
!>   radius             segment wells: well radius r_w [m], > 0, below
!>                      Peaceman's equivalent radius of the elements    [0.1]
!>   index              segment wells: connection index J [m^3/(Pa s)], > 0,
!>                      the same for every connection
!>                                  [Peaceman's, from the aperture: fracture_wells]
!>   rate               injection rate [m^3/s] (negative: production); with
!>                      history, the rate is rate times the history's factor
!>                      at the time                                    [required]
!>   history            optional file of "time factor" rows (# comments),
!>                      linear between rows, as in &boundary             ['']
!>
!> &fracture_pressure (any number): a prescribed fluid pressure on the
!> elements of a fault whose centres lie within [lower, upper].
!>   fault              name of the fault                              [required]
!>   lower(3), upper(3) the box of the element centres [m]         [the whole space]
!>   value              pressure [Pa]; with history, times the history's factor
!>                      at the time                                    [required]
!>   history            optional file of "time factor" rows               ['']
module flow_config
  use kinds, only: rp, name_len, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use strings, only: rtoa, itoa
  use history_file, only: read_history, history_factor
  use param_group, only: param_group_t
  implicit none
  private

  public :: flow_config_t, well_config_t, read_wells, load_well_histories
  public :: pressure_bc_t, read_pressure_bcs

  type :: flow_config_t
    real(rp) :: viscosity = 1.0e-3_rp              !< [Pa s]
    real(rp) :: residual_aperture = 1.0e-5_rp      !< [m]
    real(rp) :: initial_pressure = 0.0_rp          !< [Pa]
    real(rp) :: compressibility = 4.5e-10_rp       !< [1/Pa]
    character(len=name_len) :: pressure_precon = 'boomeramg'
    character(len=name_len) :: pressure_block = 'eliminated'
    logical :: subspace_correction = .true.
    !> pressure_block or pressure_precon given in the deck (physics
    !> 'poromechanics_faults' has its own pressure group and refuses them)
    logical :: block_choice_given = .false.
  contains
    procedure :: read => read_flow_config
    procedure :: describe => describe_flow_config
  end type flow_config_t

  type :: well_config_t
    character(len=name_len) :: name = ''
    real(rp) :: point(3) = 0.0_rp                  !< [m]
    logical :: along = .false.                     !< a segment well (segment set, point not)
    real(rp) :: segment(6) = 0.0_rp                !< start, end [m]
    real(rp) :: radius = 0.1_rp                    !< [m]
    real(rp) :: index = 0.0_rp                     !< [m^3/(Pa s)]; 0: Peaceman's
    real(rp) :: rate = 0.0_rp                      !< [m^3/s]
    character(len=path_len) :: history = ''
    real(rp), allocatable :: hist_t(:), hist_f(:)
  contains
    procedure :: rate_at
    procedure :: describe => describe_well
  end type well_config_t

  type :: pressure_bc_t
    character(len=name_len) :: fault = ''
    real(rp) :: lower(3) = -huge(1.0_rp), upper(3) = huge(1.0_rp)   !< [m]
    real(rp) :: value = 0.0_rp                     !< [Pa]
    type(well_config_t) :: shape                   !< the history (its rate is 1)
  contains
    procedure :: value_at => pbc_value_at
    procedure :: describe => describe_pressure_bc
  end type pressure_bc_t

contains

  !> Read and check every &fracture_pressure group and load its history
  !> (rank 0 reads, every rank gets it). Collective.
  subroutine read_pressure_bcs(comm, d, log, faults, bcs, status)
    type(parallel_comm_t), intent(in) :: comm
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    character(len=*), intent(in) :: faults(:)
    type(pressure_bc_t), allocatable, intent(out) :: bcs(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: fault
    real(rp) :: lower(3), upper(3), value
    character(len=path_len) :: history
    integer :: k, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /fracture_pressure/ fault, lower, upper, value, history
    allocate(bcs(d%count('fracture_pressure')))
    do k = 1, size(bcs)
      fault = ''; lower = -huge(1.0_rp); upper = huge(1.0_rp); value = unset_real; history = ''
      call d%block('fracture_pressure', k, b)
      read(b, nml=fracture_pressure, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('fracture_pressure', k, ios, msg, status)
        return
      end if
      if (.not. any(faults == fault)) call d%fail(status, 'fracture_pressure', k, 'fault', "'"//trim(fault)// &
        "' is not the name of a &fault")
      if (value == unset_real) call d%fail(status, 'fracture_pressure', k, 'value', 'required [Pa]')
      if (any(upper < lower)) call d%fail(status, 'fracture_pressure', k, 'upper', 'must not be below lower')
      if (.not. status%ok()) return
      bcs(k)%fault = fault
      bcs(k)%lower = lower
      bcs(k)%upper = upper
      bcs(k)%value = value
      bcs(k)%shape%name = 'fracture_pressure'
      bcs(k)%shape%rate = 1.0_rp
      call d%input_path('fracture_pressure', k, 'history', history, bcs(k)%shape%history, status)
      if (.not. status%ok()) return
      if (len_trim(bcs(k)%shape%history) > 0) then
        call read_history(comm, bcs(k)%shape%history, bcs(k)%shape%hist_t, bcs(k)%shape%hist_f, msg)
        if (len_trim(msg) > 0) then
          call status%set("&fracture_pressure number "//itoa(k)//": history file '"// &
                          trim(bcs(k)%shape%history)//"': "//trim(msg), 1)
          return
        end if
      end if
    end do
  end subroutine read_pressure_bcs

  !> The prescribed pressure at time t [Pa].
  real(rp) function pbc_value_at(self, t)
    class(pressure_bc_t), intent(in) :: self
    real(rp), intent(in) :: t
    pbc_value_at = self%value * self%shape%rate_at(t)
  end function pbc_value_at

  subroutine describe_pressure_bc(self, g)
    class(pressure_bc_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('fracture_pressure', 'a prescribed fluid pressure on the elements of a fault whose centres lie '// &
                'in a box')
    call g%add('fault', self%fault, '-', 'the fault whose elements get the pressure', 'a &fault name')
    call g%add_bounds('lower', self%lower, '(none)', 'm', 'lower corner of the box of element centres')
    call g%add_bounds('upper', self%upper, '(none)', 'm', 'upper corner of the box of element centres', '>= lower')
    call g%add('value', self%value, 'Pa', 'the prescribed fluid pressure (times the history factor)')
    call g%add('history', self%shape%history, '-', "file of 'time factor' rows scaling the value ('': none)")
  end subroutine describe_pressure_bc

  !> Read and check &fracture_flow.
  subroutine read_flow_config(self, d, log, status)
    class(flow_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    real(rp) :: viscosity, residual_aperture, initial_pressure, compressibility
    character(len=name_len) :: pressure_precon, pressure_block
    logical :: subspace_correction
    integer :: ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /fracture_flow/ viscosity, residual_aperture, initial_pressure, compressibility, pressure_precon, &
                             pressure_block, subspace_correction
    viscosity = self%viscosity; residual_aperture = self%residual_aperture; initial_pressure = self%initial_pressure
    compressibility = self%compressibility; pressure_precon = self%pressure_precon
    pressure_block = self%pressure_block
    subspace_correction = self%subspace_correction
    if (d%count('fracture_flow') == 1) then
      call d%block('fracture_flow', 1, b)
      ! sentinels: was either solver choice given?
      pressure_precon = char(0)
      pressure_block = char(0)
      read(b, nml=fracture_flow, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('fracture_flow', 1, ios, msg, status)
        return
      end if
      self%block_choice_given = pressure_precon /= char(0) .or. pressure_block /= char(0)
      if (pressure_precon == char(0)) pressure_precon = self%pressure_precon
      if (pressure_block == char(0)) pressure_block = self%pressure_block
    end if
    if (.not. (viscosity > 0.0_rp)) call d%fail(status, 'fracture_flow', 1, 'viscosity', &
      'must be > 0 (got '//rtoa(viscosity)//')')
    if (.not. (residual_aperture > 0.0_rp .and. residual_aperture < 1.0_rp)) call d%fail(status, 'fracture_flow', &
      1, 'residual_aperture', 'must lie in (0, 1) m (got '//rtoa(residual_aperture)//')')
    if (.not. (compressibility >= 0.0_rp .and. compressibility < 1.0e-3_rp)) call d%fail(status, 'fracture_flow', &
      1, 'compressibility', 'must lie in [0, 1e-3) 1/Pa (got '//rtoa(compressibility)//')')
    if (pressure_precon /= 'boomeramg' .and. pressure_precon /= 'jacobi') call d%fail(status, 'fracture_flow', 1, &
      'pressure_precon', "must be 'boomeramg' or 'jacobi' (got '"//trim(pressure_precon)//"')")
    if (pressure_block /= 'schur' .and. pressure_block /= 'eliminated') call d%fail(status, 'fracture_flow', 1, &
      'pressure_block', "must be 'schur' or 'eliminated' (got '"//trim(pressure_block)//"')")
    if (.not. status%ok()) return
    self%subspace_correction = subspace_correction
    self%compressibility = compressibility
    self%pressure_precon = pressure_precon
    self%pressure_block = pressure_block
    self%viscosity = viscosity
    self%residual_aperture = residual_aperture
    self%initial_pressure = initial_pressure
  end subroutine read_flow_config

  subroutine describe_flow_config(self, g)
    class(flow_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('fracture_flow', 'the fluid in the fractures (cubic law) and the u-t-p block preconditioner')
    call g%add('viscosity', self%viscosity, 'Pa s', 'fluid viscosity mu', '> 0')
    call g%add('residual_aperture', self%residual_aperture, 'm', 'hydraulic aperture a0 of a closed fracture: '// &
               'a = max(g_N, 0) + a0', '(0, 1)')
    call g%add('initial_pressure', self%initial_pressure, 'Pa', 'fluid pressure in the fractures at the start')
    call g%add('compressibility', self%compressibility, '1/Pa', 'fluid compressibility c_f (fixes the pressure '// &
               'of a closed fracture: 0 is refused while a fault starts closed with no &fracture_pressure)', &
               '[0, 1e-3)')
    call g%add('pressure_block', self%pressure_block, '-', "FGMRES: the pressure eliminated with the tractions "// &
               "before the displacement (one AMG per iteration), or its Schur complement last (the seed's); "// &
               "refused with physics = 'poromechanics_faults'", &
               "'eliminated' or 'schur'")
    call g%add('pressure_precon', self%pressure_precon, '-', "pressure_block = 'schur': preconditioner of S_p "// &
               "(refused with physics = 'poromechanics_faults')", &
               "'boomeramg' or 'jacobi'")
    call g%add('subspace_correction', self%subspace_correction, '-', "FGMRES: the fractures' subspace "// &
               'correction before the block preconditioner (per element its pressure with its normal traction, AMG)')
  end subroutine describe_flow_config

  !> Read and check every &well group (rank 0 reads the histories later,
  !> load_well_histories).
  subroutine read_wells(d, log, wells, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(well_config_t), allocatable, intent(out) :: wells(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: name
    real(rp) :: point(3), segment(6), radius, index, rate
    character(len=path_len) :: history
    integer :: k, j, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /well/ name, point, segment, radius, index, rate, history
    allocate(wells(d%count('well')))
    do k = 1, size(wells)
      name = ''; point = unset_real; segment = unset_real; radius = unset_real; index = unset_real
      rate = unset_real; history = ''
      call d%block('well', k, b)
      read(b, nml=well, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('well', k, ios, msg, status)
        return
      end if
      if (len_trim(name) == 0) call d%fail(status, 'well', k, 'name', 'required')
      do j = 1, k - 1
        if (wells(j)%name == name) call d%fail(status, 'well', k, 'name', "'"//trim(name)// &
          "' is already the name of another &well (well names must be distinct)")
      end do
      if (all(point == unset_real) .and. all(segment == unset_real)) then
        call d%fail(status, 'well', k, 'point', 'required (three coordinates [m]), or segment (start and end)')
      else if (any(point /= unset_real) .and. any(segment /= unset_real)) then
        call d%fail(status, 'well', k, 'segment', 'a well is at a point or along a segment, not both')
      else if (any(point /= unset_real) .and. any(point == unset_real)) then
        call d%fail(status, 'well', k, 'point', 'needs three coordinates [m]')
      else if (any(segment /= unset_real) .and. any(segment == unset_real)) then
        call d%fail(status, 'well', k, 'segment', 'needs six coordinates [m]: start x, y, z, end x, y, z')
      else if (any(segment /= unset_real)) then
        if (all(segment(1:3) == segment(4:6))) call d%fail(status, 'well', k, 'segment', &
          'its start and end are the same point')
      end if
      if (all(segment == unset_real)) then
        if (radius /= unset_real) call d%fail(status, 'well', k, 'radius', 'only for a well along a segment')
        if (index /= unset_real) call d%fail(status, 'well', k, 'index', 'only for a well along a segment')
      end if
      if (radius /= unset_real .and. .not. radius > 0.0_rp) call d%fail(status, 'well', k, 'radius', &
        'must be > 0 [m], got '//rtoa(radius))
      if (index /= unset_real .and. .not. index > 0.0_rp) call d%fail(status, 'well', k, 'index', &
        'must be > 0 [m^3/(Pa s)], got '//rtoa(index))
      if (rate == unset_real) call d%fail(status, 'well', k, 'rate', 'required [m^3/s]')
      if (.not. status%ok()) return
      wells(k)%name = name
      wells(k)%along = any(segment /= unset_real)
      if (wells(k)%along) then
        wells(k)%segment = segment
        wells(k)%point = segment(1:3)
        if (radius /= unset_real) wells(k)%radius = radius
        if (index /= unset_real) wells(k)%index = index
      else
        wells(k)%point = point
      end if
      wells(k)%rate = rate
      call d%input_path('well', k, 'history', history, wells(k)%history, status)
    end do
  end subroutine read_wells

  !> Rank 0 reads the wells' history files, every rank gets them. Collective.
  subroutine load_well_histories(comm, wells, status)
    type(parallel_comm_t), intent(in) :: comm
    type(well_config_t), intent(inout) :: wells(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    character(len=msg_len) :: msg
    do k = 1, size(wells)
      if (len_trim(wells(k)%history) == 0) cycle
      call read_history(comm, wells(k)%history, wells(k)%hist_t, wells(k)%hist_f, msg)
      if (len_trim(msg) > 0) then
        call status%set("&well '"//trim(wells(k)%name)//"': history file '"//trim(wells(k)%history)//"': "// &
                        trim(msg), 1)
        return
      end if
    end do
  end subroutine load_well_histories

  !> The rate at time t [m^3/s].
  real(rp) function rate_at(self, t)
    class(well_config_t), intent(in) :: self
    real(rp), intent(in) :: t
    rate_at = self%rate
    if (allocated(self%hist_t)) rate_at = self%rate * history_factor(self%hist_t, self%hist_f, t)
  end function rate_at

  subroutine describe_well(self, g)
    class(well_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('well', 'a source of fluid into the fractures, at a point or along a segment that crosses them')
    call g%add('name', self%name, '-', 'name of the well (columns of <prefix>_probes.csv)', 'unique')
    if (self%along) then
      call g%add_unset('point', '(none: along segment)', 'm', 'a well at a point: the fracture element whose '// &
                       'centre is nearest gets its fluid (give point or segment)', 'real(3)')
      call g%add('segment', self%segment, 'm', 'a well along a segment, start x, y, z and end x, y, z: it feeds '// &
                 "the element of every fault it crosses, the rate split by the connections' pressures", &
                 'start /= end')
      call g%add('radius', self%radius, 'm', "segment well: well radius r_w, below Peaceman's equivalent "// &
                 'radius of every element it feeds', '> 0')
      if (self%index > 0.0_rp) then
        call g%add('index', self%index, 'm3/(Pa s)', 'segment well: connection index J of every fracture it '// &
                   'crosses', '> 0')
      else
        call g%add_unset('index', "(Peaceman's, from the aperture)", 'm3/(Pa s)', 'segment well: connection '// &
                         'index J of every fracture it crosses', 'real', '> 0')
      end if
    else
      call g%add('point(1)', self%point(1), 'm', 'a well at a point: the fracture element whose centre is '// &
                 'nearest gets its fluid (give point or segment)')
      call g%add('point(2)', self%point(2), 'm', 'a well at a point, y')
      call g%add('point(3)', self%point(3), 'm', 'a well at a point, z')
      call g%add_unset('segment', '(none: at point)', 'm', 'a well along a segment, start x, y, z and end x, y, z: '// &
                       "it feeds the element of every fault it crosses, the rate split by the connections' "// &
                       'pressures', 'real(6)', 'start /= end')
    end if
    call g%add('rate', self%rate, 'm3/s', 'injection rate, times the history factor (negative: production)')
    call g%add('history', self%history, '-', "file of 'time factor' rows scaling the rate ('': none)")
  end subroutine describe_well
end module flow_config
