!> Deck group &boundary (any number): a condition on a tagged surface set.
!>
!>   set          name of the surface set ('xmin' ... 'zmax' for a box)     [required]
!>   type         'displacement', 'traction', 'normal_traction', 'pressure'
!>                or 'flux'                                                [required]
!>   ux, uy, uz   prescribed displacement components [m]; a component left
!>                out is free                                              [free]
!>   traction(3)  prescribed traction vector [Pa], for type = 'traction'   [required]
!>   normal_traction  for type = 'normal_traction': a traction along the
!>                face's outward unit normal n, t = normal_traction n [Pa],
!>                negative = compression (pushing into the body), the sign
!>                of a total stress sigma_nn; for curved surfaces (a sphere
!>                under a uniform radial load), where n changes from face to
!>                face and within a face (it is taken at each quadrature
!>                point of the face)                                       [required]
!>   type = 'pressure' (biot): pressure  prescribed fluid pressure [Pa]     [required]
!>   type = 'flux' (biot):     flux      prescribed outward normal Darcy
!>                             flux [m/s]                                  [required]
!>   lower(3), upper(3)  the condition acts only on the faces of the set
!>                whose centres lie in [lower, upper] [m] (to 1e-9 of the
!>                mesh's extent; a component left out is open on that side;
!>                lower < upper); every type. A displacement condition fixes
!>                the nodes of those faces. A box that selects no face of the
!>                set is refused (by the physics, which sees the mesh)    [the whole set]
!>   history      optional file of "time factor" rows (# comments): the
!>                condition's value is multiplied by the factor, linearly
!>                interpolated in time (constant before the first and after
!>                the last row); elasticity and contact use the load
!>                factor as time                                        ['']
!> Boundary faces with neither a pressure nor a flux condition are
!> impermeable (no flow). Elasticity and contact scale the loads by the load
!> factor of the step (see &time); biot and fracture_flow apply them in full
!> from t = 0+.
module boundary_config
  use kinds, only: rp, name_len, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use history_file, only: read_history, history_factor
  use os_services, only: absolute_path
  use param_group, only: param_group_t
  use strings, only: rtoa
  implicit none
  private

  public :: boundary_config_t, read_boundaries, load_histories

  !> The condition types, for messages and the parameter echo.
  character(len=*), parameter :: type_names = &
    "'displacement', 'traction', 'normal_traction', 'pressure' or 'flux'"

  type :: boundary_config_t
    character(len=name_len) :: set = ''
    character(len=16) :: type = ''
    logical :: fixed(3) = .false.          !< displacement: which components are prescribed
    real(rp) :: value(3) = 0.0_rp          !< displacement [m] or traction [Pa]
    character(len=path_len) :: history = ''
    real(rp), allocatable :: hist_t(:), hist_f(:)
    real(rp) :: lower(3) = -huge(1.0_rp), upper(3) = huge(1.0_rp)   !< [m], +-huge: open
  contains
    procedure :: factor
    procedure :: has_box
    procedure :: describe => describe_boundary
  end type boundary_config_t

contains

  !> Read every &boundary group.
  subroutine read_boundaries(d, log, bcs, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(boundary_config_t), allocatable, intent(out) :: bcs(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: set
    character(len=16) :: type
    real(rp) :: ux, uy, uz, traction(3), normal_traction, pressure, flux, lower(3), upper(3)
    character(len=path_len) :: history
    integer :: k, ios, i
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=1) :: ax
    namelist /boundary/ set, type, ux, uy, uz, traction, normal_traction, pressure, flux, history, lower, upper

    allocate(bcs(d%count('boundary')))
    do k = 1, size(bcs)
      set = ''; type = ''; ux = unset_real; uy = unset_real; uz = unset_real; traction = unset_real
      normal_traction = unset_real; pressure = unset_real; flux = unset_real; history = ''
      lower = -huge(1.0_rp); upper = huge(1.0_rp)
      call d%block('boundary', k, b)
      read(b, nml=boundary, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('boundary', k, ios, msg, status)
        return
      end if
      if (len_trim(set) == 0) call d%fail(status, 'boundary', k, 'set', 'required')
      bcs(k)%set = set
      bcs(k)%type = type
      do i = 1, 3
        write(ax, '(i1)') i
        if (.not. lower(i) < upper(i)) call d%fail(status, 'boundary', k, 'upper('//ax//')', &
          'must be greater than lower('//ax//') (got lower '//rtoa(lower(i))//', upper '//rtoa(upper(i))//')')
      end do
      bcs(k)%lower = lower
      bcs(k)%upper = upper
      call d%input_path('boundary', k, 'history', history, bcs(k)%history, status)
      select case (type)
      case ('displacement')
        bcs(k)%fixed = [ux, uy, uz] /= unset_real
        if (.not. any(bcs(k)%fixed)) &
          call d%fail(status, 'boundary', k, 'ux', 'a displacement condition needs at least one of ux, uy, uz')
        if (any(traction /= unset_real)) &
          call d%fail(status, 'boundary', k, 'traction', "not used with type = 'displacement'")
        bcs(k)%value = merge([ux, uy, uz], 0.0_rp, bcs(k)%fixed)
      case ('traction')
        if (any(traction == unset_real)) &
          call d%fail(status, 'boundary', k, 'traction', "required (3 components) with type = 'traction'")
        if (any([ux, uy, uz] /= unset_real)) &
          call d%fail(status, 'boundary', k, 'ux', "ux, uy, uz are not used with type = 'traction'")
        bcs(k)%value = traction
      case ('normal_traction')
        if (normal_traction == unset_real) &
          call d%fail(status, 'boundary', k, 'normal_traction', "required with type = 'normal_traction' "// &
                      "(the traction along the outward normal [Pa], negative in compression)")
        if (any(traction /= unset_real)) &
          call d%fail(status, 'boundary', k, 'traction', "not used with type = 'normal_traction' (its value is "// &
                      "the scalar normal_traction)")
        if (any([ux, uy, uz] /= unset_real)) &
          call d%fail(status, 'boundary', k, 'ux', "ux, uy, uz are not used with type = 'normal_traction'")
        bcs(k)%value = [normal_traction, 0.0_rp, 0.0_rp]
      case ('pressure')
        if (pressure == unset_real) call d%fail(status, 'boundary', k, 'pressure', "required with type = 'pressure'")
        bcs(k)%value = [pressure, 0.0_rp, 0.0_rp]
      case ('flux')
        if (flux == unset_real) call d%fail(status, 'boundary', k, 'flux', "required with type = 'flux'")
        bcs(k)%value = [flux, 0.0_rp, 0.0_rp]
      case ('')
        call d%fail(status, 'boundary', k, 'type', "required: "//type_names)
      case default
        call d%fail(status, 'boundary', k, 'type', "must be "//type_names//" (got '"//trim(type)//"')")
      end select
      if (type /= 'normal_traction' .and. normal_traction /= unset_real) &
        call d%fail(status, 'boundary', k, 'normal_traction', "only used with type = 'normal_traction'")
      if (type /= 'pressure' .and. pressure /= unset_real) &
        call d%fail(status, 'boundary', k, 'pressure', "only used with type = 'pressure'")
      if (type /= 'flux' .and. flux /= unset_real) &
        call d%fail(status, 'boundary', k, 'flux', "only used with type = 'flux'")
      if (.not. status%ok()) return
    end do
  end subroutine read_boundaries

  !> The resolved &boundary group: the variables of its type.
  subroutine describe_boundary(self, g)
    class(boundary_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    character(len=2), parameter :: comp(3) = ['ux', 'uy', 'uz']
    integer :: i
    call g%init('boundary', 'a condition on a surface set or a part of it (faces with no flow condition are '// &
                'impermeable)')
    call g%add('set', self%set, '-', "surface set: 'xmin' ... 'zmax' of a box, a Gmsh physical surface")
    call g%add('type', self%type, '-', "the condition ('pressure', 'flux': biot only)", type_names)
    select case (self%type)
    case ('displacement')
      do i = 1, 3
        if (self%fixed(i)) then
          call g%add(comp(i), self%value(i), 'm', "type = 'displacement': a prescribed component (at least one)")
        else
          call g%add_unset(comp(i), '(free)', 'm', "type = 'displacement': a prescribed component (at least one)", &
                           'real')
        end if
      end do
    case ('traction')
      call g%add('traction', self%value, 'Pa', "type = 'traction': the traction vector (biot: a total traction)")
    case ('normal_traction')
      call g%add('normal_traction', self%value(1), 'Pa', "type = 'normal_traction': traction along the "// &
                 'outward normal, taken at each quadrature point (follows a curved surface); negative: compression')
    case ('pressure')
      call g%add('pressure', self%value(1), 'Pa', "type = 'pressure': the fluid pressure of a drained face")
    case ('flux')
      call g%add('flux', self%value(1), 'm/s', "type = 'flux': the outward normal Darcy flux")
    end select
    call g%add_bounds('lower', self%lower, '(open)', 'm', 'acts only on the faces of the set whose centres lie '// &
                      'in [lower, upper] (a component left out is open)')
    call g%add_bounds('upper', self%upper, '(open)', 'm', 'upper corner of that box', '> lower; the box must '// &
                      'select a face of the set')
    call g%add('history', absolute_path(self%history), '-', "file of 'time factor' rows scaling the value "// &
               "(relative to the deck's directory; elasticity and contact: time is the load factor; '': none)")
  end subroutine describe_boundary

  !> Whether the condition acts on part of its set only (lower or upper given).
  logical function has_box(self)
    class(boundary_config_t), intent(in) :: self
    has_box = any(self%lower > -huge(1.0_rp)) .or. any(self%upper < huge(1.0_rp))
  end function has_box

  !> Multiplier of the condition's value at time t (1 without a history).
  real(rp) function factor(self, t)
    class(boundary_config_t), intent(in) :: self
    real(rp), intent(in) :: t
    factor = 1.0_rp
    if (allocated(self%hist_t)) factor = history_factor(self%hist_t, self%hist_f, t)
  end function factor

  !> Read the history files of the conditions (rank 0) and broadcast them.
  !> Errors name the condition, the file and the line. Collective.
  subroutine load_histories(comm, bcs, status)
    type(parallel_comm_t), intent(in) :: comm
    type(boundary_config_t), intent(inout) :: bcs(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    character(len=msg_len) :: msg
    do k = 1, size(bcs)
      if (len_trim(bcs(k)%history) == 0) cycle
      call read_history(comm, bcs(k)%history, bcs(k)%hist_t, bcs(k)%hist_f, msg)
      if (len_trim(msg) > 0) then
        call status%set("&boundary on set '"//trim(bcs(k)%set)//"': history file '"//trim(bcs(k)%history)// &
                        "': "//trim(msg), 1)
        return
      end if
    end do
  end subroutine load_histories
end module boundary_config
