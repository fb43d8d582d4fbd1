!> Deck group &source (any number; physics = 'biot', 'poromechanics_faults'): a
!> fluid source spread
!> uniformly over a region.
!>
!>   region   name of the mesh region                                  [required]
!>   rate     volume of fluid injected per unit volume of rock and per
!>            second [1/s] (negative: extraction)                       [required]
!>   point(3) restricts the source to the fault block of the region that
!>            holds this point [m] (as &pressure_change point: the cells
!>            of the region joined to the point's cell by faces not on a
!>            fault; a production compartment)      [unset: the region]
module source_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use param_group, only: param_group_t
  implicit none
  private

  public :: source_config_t, read_sources

  type :: source_config_t
    character(len=name_len) :: region = ''
    real(rp) :: rate = 0.0_rp
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
    character(len=name_len) :: region
    real(rp) :: rate, point(3)
    integer :: k, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /source/ region, rate, point
    allocate(srcs(d%count('source')))
    do k = 1, size(srcs)
      region = ''
      rate = unset_real
      point = unset_real
      call d%block('source', k, b)
      read(b, nml=source, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('source', k, ios, msg, status)
        return
      end if
      if (len_trim(region) == 0) call d%fail(status, 'source', k, 'region', 'required')
      if (rate == unset_real) call d%fail(status, 'source', k, 'rate', 'required')
      if (any(point == unset_real) .and. any(point /= unset_real)) &
        call d%fail(status, 'source', k, 'point', 'needs its three coordinates')
      if (.not. status%ok()) return
      srcs(k) = source_config_t(region, rate, all(point /= unset_real), merge(point, 0.0_rp, all(point /= unset_real)))
    end do
  end subroutine read_sources

  subroutine describe_source(self, g)
    class(source_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('source', 'a fluid source spread uniformly over a region')
    call g%add('region', self%region, '-', 'mesh region', 'a region of the mesh')
    call g%add('rate', self%rate, '1/s', 'volume of fluid injected per unit volume of rock and second '// &
               '(negative: extraction)')
    if (self%has_point) then
      call g%add('point', self%point, 'm', 'restricts the source to the fault block of the region that holds '// &
                 'this point (a compartment)', 'inside the region')
    else
      call g%add_unset('point', '(none: all of the region)', 'm', 'restricts the source to the fault block of '// &
                       'the region that holds this point (a compartment)', 'real(3)', 'inside the region')
    end if
  end subroutine describe_source
end module source_config
