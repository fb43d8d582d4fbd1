!> Deck group &biot: discretization options of three-field poromechanics.
!>
!>   stabilization  pressure-jump stabilization of the undrained /
!>                  incompressible limit (see poromechanics.f90)          [.true.]
!>   stab_factor    its factor beta (> 0)                                  [1.0]
!>   stab_mode      'adaptive': the weight scaled by how close the step is to
!>                  the undrained incompressible limit (0 far from it);
!>                  'full': the weight of that limit at every step     ['adaptive']
module biot_config
  use kinds, only: rp, msg_len, name_len
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
    character(len=name_len) :: stab_mode = 'adaptive'
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
    character(len=name_len) :: stab_mode
    integer :: ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /biot/ stabilization, stab_factor, stab_mode
    stabilization = self%stabilization
    stab_factor = self%stab_factor
    stab_mode = self%stab_mode
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
    if (stab_mode /= 'adaptive' .and. stab_mode /= 'full') call d%fail(status, 'biot', 1, 'stab_mode', &
      "must be 'adaptive' or 'full' (got '"//trim(stab_mode)//"')")
    if (.not. status%ok()) return
    self%stabilization = stabilization
    self%stab_factor = stab_factor
    self%stab_mode = stab_mode
  end subroutine read_biot_config

  !> The stabilization factor to use (0 when switched off).
  real(rp) function beta(self)
    class(biot_config_t), intent(in) :: self
    beta = merge(self%stab_factor, 0.0_rp, self%stabilization)
  end function beta

  subroutine describe_biot_config(self, g)
    class(biot_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('biot', 'discretization options of three-field poromechanics: the pressure-jump stabilization')
    call g%add('stabilization', self%stabilization, '-', 'pressure-jump stabilization of the undrained, '// &
               'incompressible limit')
    call g%add('stab_factor', self%stab_factor, '-', 'its factor beta', '> 0')
    call g%add('stab_mode', self%stab_mode, '-', "its size: 'adaptive' (the full weight times r^2, r the "// &
               "closeness of the step to the undrained incompressible limit) or 'full' (that limit's weight at "// &
               "every step)", "'adaptive' or 'full'")
  end subroutine describe_biot_config
end module biot_config
