!> Deck group &biot: discretization options of three-field poromechanics.
!>
!>   stabilization  pressure-jump stabilization of the undrained /
!>                  incompressible limit (see poromechanics.f90)          [.true.]
!>   stab_factor    its factor beta (> 0)                                  [1.0]
module biot_config
  use kinds, only: rp, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use strings, only: rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: biot_config_t

  type :: biot_config_t
    logical :: stabilization = .true.
    real(rp) :: stab_factor = 1.0_rp
  contains
    procedure :: read => read_biot_config
    procedure :: beta
    procedure :: describe => describe_biot_config
  end type biot_config_t

contains

  !> Read and check &biot (optional group).
  subroutine read_biot_config(self, d, log, status)
    class(biot_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    logical :: stabilization
    real(rp) :: stab_factor
    integer :: ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /biot/ stabilization, stab_factor
    stabilization = self%stabilization
    stab_factor = self%stab_factor
    if (d%count('biot') > 0) then
      call d%block('biot', 1, b)
      read(b, nml=biot, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('biot', 1, ios, msg, status)
        return
      end if
    end if
    if (.not. stab_factor > 0.0_rp) &
      call d%fail(status, 'biot', 1, 'stab_factor', 'must be positive (got '//rtoa(stab_factor)//')')
    if (.not. status%ok()) return
    self%stabilization = stabilization
    self%stab_factor = stab_factor
  end subroutine read_biot_config

  !> The stabilization factor to use (0 when switched off).
  real(rp) function beta(self)
    class(biot_config_t), intent(in) :: self
    beta = merge(self%stab_factor, 0.0_rp, self%stabilization)
  end function beta

  !> The resolved &biot group.
  subroutine describe_biot_config(self, g)
    class(biot_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('biot')
    call g%add('stabilization', self%stabilization, '-', 'pressure-jump stabilization of the undrained limit')
    call g%add('stab_factor', self%stab_factor, '-', 'its factor beta')
  end subroutine describe_biot_config
end module biot_config
