!> Deck group &material (one per region): isotropic linear elastic solid.
!>
!>   region        name of the mesh region ('domain' for a box mesh)   [required]
!>   young         drained Young's modulus E [Pa] (> 0)                [required]
!>   poisson       drained Poisson's ratio nu (-1 < nu < 0.5)          [required]
!>   body_force(3) body force per unit volume [N/m^3]                  [0,0,0]
module material_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, echo_len, unset_real
  use strings, only: rtoa
  implicit none
  private

  public :: material_config_t, read_materials

  type :: material_config_t
    character(len=name_len) :: region = ''
    real(rp) :: young = 0.0_rp
    real(rp) :: poisson = 0.0_rp
    real(rp) :: body_force(3) = 0.0_rp
  end type material_config_t

contains

  !> Read every &material group; at least one is required, regions unique.
  subroutine read_materials(d, log, mats, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(material_config_t), allocatable, intent(out) :: mats(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: region
    real(rp) :: young, poisson, body_force(3)
    integer :: k, j, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=echo_len) :: echo(16)
    namelist /material/ region, young, poisson, body_force

    allocate(mats(d%count('material')))
    if (size(mats) == 0) then
      call status%set("deck '"//trim(d%path)//"': no &material group (one per region is required)")
      return
    end if
    do k = 1, size(mats)
      region = ''; young = unset_real; poisson = unset_real; body_force = 0.0_rp
      call d%block('material', k, b)
      read(b, nml=material, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('material', k, ios, msg, status)
        return
      end if
      if (len_trim(region) == 0) call d%fail(status, 'material', k, 'region', 'required')
      if (young == unset_real) then
        call d%fail(status, 'material', k, 'young', 'required')
      else if (young <= 0.0_rp) then
        call d%fail(status, 'material', k, 'young', 'must be positive (got '//rtoa(young)//')')
      end if
      if (poisson == unset_real) then
        call d%fail(status, 'material', k, 'poisson', 'required')
      else if (poisson <= -1.0_rp .or. poisson >= 0.5_rp) then
        call d%fail(status, 'material', k, 'poisson', 'must lie in (-1, 0.5) (got '//rtoa(poisson)//')')
      end if
      do j = 1, k - 1
        if (mats(j)%region == region) &
          call d%fail(status, 'material', k, 'region', "region '"//trim(region)//"' already has a material")
      end do
      if (.not. status%ok()) return
      mats(k) = material_config_t(region, young, poisson, body_force)
      echo = ''
      write(echo, nml=material, iostat=ios)
      call d%echo(log, echo)
    end do
  end subroutine read_materials
end module material_config
