!> Deck group &boundary (any number): a condition on a tagged surface set.
!>
!>   set          name of the surface set ('xmin' ... 'zmax' for a box)     [required]
!>   type         'displacement' or 'traction'                             [required]
!>   ux, uy, uz   prescribed displacement components [m]; a component left
!>                out is free                                              [free]
!>   traction(3)  prescribed traction vector [Pa], for type = 'traction'   [required]
!>   type = 'pressure' (biot): pressure  prescribed fluid pressure [Pa]     [required]
!>   type = 'flux' (biot):     flux      prescribed outward normal Darcy
!>                             flux [m/s]                                  [required]
!> Boundary faces with neither a pressure nor a flux condition are
!> impermeable (no flow). Elasticity loads are scaled by the load factor of
!> the step (see &time); poromechanics applies them in full from t = 0+.
module boundary_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, echo_len, unset_real
  implicit none
  private

  public :: boundary_config_t, read_boundaries

  type :: boundary_config_t
    character(len=name_len) :: set = ''
    character(len=16) :: type = ''
    logical :: fixed(3) = .false.          !< displacement: which components are prescribed
    real(rp) :: value(3) = 0.0_rp          !< displacement [m] or traction [Pa]
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
    real(rp) :: ux, uy, uz, traction(3), pressure, flux
    integer :: k, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=echo_len) :: echo(16)
    namelist /boundary/ set, type, ux, uy, uz, traction, pressure, flux

    allocate(bcs(d%count('boundary')))
    do k = 1, size(bcs)
      set = ''; type = ''; ux = unset_real; uy = unset_real; uz = unset_real; traction = unset_real
      pressure = unset_real; flux = unset_real
      call d%block('boundary', k, b)
      read(b, nml=boundary, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('boundary', k, ios, msg, status)
        return
      end if
      if (len_trim(set) == 0) call d%fail(status, 'boundary', k, 'set', 'required')
      bcs(k)%set = set
      bcs(k)%type = type
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
      case ('pressure')
        if (pressure == unset_real) call d%fail(status, 'boundary', k, 'pressure', "required with type = 'pressure'")
        bcs(k)%value = [pressure, 0.0_rp, 0.0_rp]
      case ('flux')
        if (flux == unset_real) call d%fail(status, 'boundary', k, 'flux', "required with type = 'flux'")
        bcs(k)%value = [flux, 0.0_rp, 0.0_rp]
      case ('')
        call d%fail(status, 'boundary', k, 'type', "required: 'displacement', 'traction', 'pressure' or 'flux'")
      case default
        call d%fail(status, 'boundary', k, 'type', "must be 'displacement', 'traction', 'pressure' or 'flux' (got '"// &
                    trim(type)//"')")
      end select
      if (type /= 'pressure' .and. pressure /= unset_real) &
        call d%fail(status, 'boundary', k, 'pressure', "only used with type = 'pressure'")
      if (type /= 'flux' .and. flux /= unset_real) &
        call d%fail(status, 'boundary', k, 'flux', "only used with type = 'flux'")
      if (.not. status%ok()) return
      echo = ''
      write(echo, nml=boundary, iostat=ios)
      call d%echo(log, echo)
    end do
  end subroutine read_boundaries
end module boundary_config
