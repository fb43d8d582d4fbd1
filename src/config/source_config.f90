!> Deck group &source (any number; physics = 'biot', 'poromechanics_faults'): a
!> fluid source in the cells of a region, rate or pressure controlled.
!>
!>   region   name of the mesh region                                  [required]
!>   rate     volume of fluid injected per unit volume of rock and per
!>            second [1/s] (negative: extraction)     [one of rate, pressure]
!>   pressure a well's pressure p_w [Pa]: each cell c of the source takes
!>            q_c = index |c| (p_w - p_c) [m^3/s] (a producer where the
!>            rock's pressure is above p_w, an injector where below); the
!>            same reference as the pressure unknown (with &geostatic, the
!>            change from the in-situ state)        [one of rate, pressure]
!>   index    with pressure: the productivity index per unit volume of
!>            rock [1/(Pa s)], > 0. An index well above k / (mu h^2) (h the
!>            cell size) holds the cells at p_w; a smaller one is a
!>            resistance between the well and the rock.        [required]
!>   name     the source's name: the probe file's column of a pressure
!>            controlled source is '<name>:rate [m3/s]', the rate it
!>            gives the rock                             [source<k>]
!>   point(3) restricts the source to the fault block of the region that
!>            holds this point [m] (as &pressure_change point: the cells
!>            of the region joined to the point's cell by faces not on a
!>            fault; a production compartment)      [unset: the region]
!> Several sources add up in a cell.
module source_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa
  use deck, only: deck_t, line_len, unset_real
  use param_group, only: param_group_t
  implicit none
  private

  public :: source_config_t, read_sources

  type :: source_config_t
    character(len=name_len) :: region = ''
    character(len=name_len) :: name = ''
    real(rp) :: rate = 0.0_rp               !< [1/s] (rate controlled)
    logical :: by_pressure = .false.        !< pressure controlled: pressure and index
    real(rp) :: pressure = 0.0_rp           !< [Pa] p_w
    real(rp) :: index = 0.0_rp              !< [1/(Pa s)] per unit volume of rock
    logical :: has_point = .false.          !< point given: one fault block of the region
    real(rp) :: point(3) = 0.0_rp           !< [m] a point of that block
  contains
    procedure :: describe => describe_source
  end type source_config_t

contains

  !> Read every &source group.
  subroutine read_sources(d, log, srcs, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(source_config_t), allocatable, intent(out) :: srcs(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: region, name
    real(rp) :: rate, pressure, index, point(3)
    integer :: k, j, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /source/ region, rate, pressure, index, point, name
    allocate(srcs(d%count('source')))
    do k = 1, size(srcs)
      region = ''
      name = ''
      rate = unset_real
      pressure = unset_real
      index = unset_real
      point = unset_real
      call d%block('source', k, b)
      read(b, nml=source, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('source', k, ios, msg, status)
        return
      end if
      if (len_trim(region) == 0) call d%fail(status, 'source', k, 'region', 'required')
      if (rate == unset_real .and. pressure == unset_real) then
        call d%fail(status, 'source', k, 'rate', 'required (or pressure with index, a pressure-controlled source)')
      else if (rate /= unset_real .and. pressure /= unset_real) then
        call d%fail(status, 'source', k, 'pressure', 'not with rate: a source is rate or pressure controlled')
      end if
      if (pressure /= unset_real .and. index == unset_real) &
        call d%fail(status, 'source', k, 'index', 'required with pressure [1/(Pa s)]')
      if (pressure /= unset_real .and. index /= unset_real .and. .not. index > 0.0_rp) &
        call d%fail(status, 'source', k, 'index', 'must be > 0 [1/(Pa s)]')
      if (pressure == unset_real .and. index /= unset_real) &
        call d%fail(status, 'source', k, 'index', 'belongs to a pressure-controlled source (set pressure, not rate)')
      if (any(point == unset_real) .and. any(point /= unset_real)) &
        call d%fail(status, 'source', k, 'point', 'needs its three coordinates')
      if (len_trim(name) == 0) name = 'source'//itoa(k)
      if (scan(trim(name), ' ,:"') > 0) &
        call d%fail(status, 'source', k, 'name', "'"//trim(name)//"' has a blank, a comma, a colon or a quote")
      do j = 1, k - 1
        if (srcs(j)%name == name) call d%fail(status, 'source', k, 'name', "'"//trim(name)// &
                                              "' is the name of &source number "//itoa(j)//' already')
      end do
      if (.not. status%ok()) return
      srcs(k)%region = region
      srcs(k)%name = name
      srcs(k)%by_pressure = pressure /= unset_real
      if (srcs(k)%by_pressure) then
        srcs(k)%pressure = pressure
        srcs(k)%index = index
      else
        srcs(k)%rate = rate
      end if
      srcs(k)%has_point = all(point /= unset_real)
      if (srcs(k)%has_point) srcs(k)%point = point
    end do
  end subroutine read_sources

  subroutine describe_source(self, g)
    class(source_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    character(len=*), parameter :: rate_text = 'rate control: volume of fluid injected per unit volume of rock '// &
      'and second (negative: extraction)'
    character(len=*), parameter :: pressure_text = "pressure control: the well's pressure p_w; each cell c "// &
      'takes index |c| (p_w - p_c) (the reference of the pressure unknown)'
    character(len=*), parameter :: index_text = 'pressure control: productivity index per unit volume of rock '// &
      '(well above k / (mu h^2): the cells held at p_w)'
    call g%init('source', 'a fluid source in the cells of a region, rate or pressure controlled')
    call g%add('region', self%region, '-', 'mesh region', 'a region of the mesh')
    call g%add('name', self%name, '-', "the source's name (the probe file's column of a pressure-controlled "// &
               "source: '<name>:rate [m3/s]')", "no blank, comma, colon or quote; one per source")
    if (self%by_pressure) then
      call g%add_unset('rate', '(not set: pressure controlled)', '1/s', rate_text, 'real')
      call g%add('pressure', self%pressure, 'Pa', pressure_text)
      call g%add('index', self%index, '1/(Pa s)', index_text, '> 0')
    else
      call g%add('rate', self%rate, '1/s', rate_text)
      call g%add_unset('pressure', '(not set: rate controlled)', 'Pa', pressure_text, 'real')
      call g%add_unset('index', '(not set: rate controlled)', '1/(Pa s)', index_text, 'real', '> 0')
    end if
    call g%add_optional('point', self%has_point, self%point, '(none: all of the region)', 'm', 'restricts the '// &
                        'source to the fault block of the region that holds this point (a compartment)', &
                        'inside the region')
  end subroutine describe_source
end module source_config
