!> Deck group &geostatic: the in-situ state a run starts from (elasticity,
!> contact, biot; fracture_flow refuses it). Gravity acts along -z; the densities and the ratios K0 are per
!> region (&material density, k0). The state, at depth below the mesh top:
!>
!>   total vertical stress  sigma_v(z) = -(surface_stress + gravity * integral
!>                          from z to the top of the density)
!>   pore pressure          p0(z) = fluid_density * gravity * (water_table - z)
!>                          below the water table, 0 above (none when the
!>                          water table is not given: a dry column)
!>   effective stress       sigma'_v = sigma_v + b p0 (b: &material biot),
!>                          sigma'_h = K0 sigma'_v,
!>                          no shear (the solid carries the effective stress;
!>                          the pore pressure acts on the faults' faces); with
!>                          &material k0_max, sigma'_H = k0_max sigma'_v along
!>                          the azimuth sh_max_azimuth and sigma'_h = k0
!>                          sigma'_v across it (principal axes horizontal and
!>                          vertical)
!>
!> Elasticity and contact start with a step 0 that puts the model in
!> equilibrium under this state with zero displacement (see the physics);
!> biot has no such step: its pressure unknown, boundary pressures and
!> sources are changes from the hydrostatic p0.
!>
!>   gravity        acceleration of gravity [m/s^2], > 0               [9.81]
!>   surface_stress vertical stress on the mesh top from what lies above it
!>                  (an overburden not meshed, sea water) [Pa], >= 0, as a
!>                  magnitude (compression)        [the water above the top]
!>   water_table    z of the free water surface [m] (above the mesh top:
!>                  offshore, the sea bed under water)          [none: dry]
!>   fluid_density  density of the pore fluid [kg/m^3], > 0             [1000]
!>   sh_max_azimuth azimuth of the largest horizontal stress [degrees
!>                  clockwise from north, +y, towards east, +x], in
!>                  [0, 180); used where a &material gives k0_max       [0]
module geostatic_config
  use kinds, only: rp, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use strings, only: rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: geostatic_config_t

  type :: geostatic_config_t
    logical :: on = .false.                    !< the deck has &geostatic
    real(rp) :: gravity = 9.81_rp              !< [m/s^2]
    real(rp) :: surface_stress = unset_real    !< [Pa]; unset: the water above the top
    real(rp) :: water_table = unset_real       !< [m]; unset: no pore pressure
    real(rp) :: fluid_density = 1000.0_rp      !< [kg/m^3]
    real(rp) :: sh_max_azimuth = 0.0_rp        !< [degrees] clockwise from +y
  contains
    procedure :: read => read_geostatic_config
    procedure :: describe => describe_geostatic_config
    procedure :: wet
  end type geostatic_config_t

contains

  !> Read and check &geostatic (optional group).
  subroutine read_geostatic_config(self, d, log, status)
    class(geostatic_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    real(rp) :: gravity, surface_stress, water_table, fluid_density, sh_max_azimuth
    integer :: ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /geostatic/ gravity, surface_stress, water_table, fluid_density, sh_max_azimuth

    self%on = d%count('geostatic') > 0
    if (.not. self%on) return
    gravity = self%gravity; surface_stress = self%surface_stress; water_table = self%water_table
    fluid_density = self%fluid_density; sh_max_azimuth = self%sh_max_azimuth
    call d%block('geostatic', 1, b)
    read(b, nml=geostatic, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call d%read_error('geostatic', 1, ios, msg, status)
      return
    end if
    if (.not. gravity > 0.0_rp) call d%fail(status, 'geostatic', 1, 'gravity', &
      'must be > 0 (got '//rtoa(gravity)//')')
    if (surface_stress /= unset_real .and. .not. surface_stress >= 0.0_rp) call d%fail(status, 'geostatic', 1, &
      'surface_stress', 'must be >= 0, a magnitude of compression (got '//rtoa(surface_stress)//')')
    if (.not. fluid_density > 0.0_rp) call d%fail(status, 'geostatic', 1, 'fluid_density', &
      'must be > 0 (got '//rtoa(fluid_density)//')')
    if (.not. (sh_max_azimuth >= 0.0_rp .and. sh_max_azimuth < 180.0_rp)) call d%fail(status, 'geostatic', 1, &
      'sh_max_azimuth', 'must lie in [0, 180) degrees (got '//rtoa(sh_max_azimuth)//')')
    if (.not. status%ok()) return
    self%gravity = gravity; self%surface_stress = surface_stress; self%water_table = water_table
    self%fluid_density = fluid_density
    self%sh_max_azimuth = sh_max_azimuth
  end subroutine read_geostatic_config

  !> A water table was given: the pores hold water below it.
  logical function wet(self)
    class(geostatic_config_t), intent(in) :: self
    wet = self%water_table /= unset_real
  end function wet

  subroutine describe_geostatic_config(self, g)
    class(geostatic_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('geostatic', 'start from the in-situ state of horizontally layered rock: gravity, a water '// &
                'table, K0 (with &material density, k0, k0_max)')
    call g%add('gravity', self%gravity, 'm/s^2', 'acceleration of gravity, along -z', '> 0')
    if (self%surface_stress /= unset_real) then
      call g%add('surface_stress', self%surface_stress, 'Pa', 'vertical stress on the mesh top from what lies '// &
                 'above it (an overburden not meshed, the sea), a magnitude', '>= 0')
    else
      call g%add_unset('surface_stress', '(not set: the water above the top)', 'Pa', 'vertical stress on the '// &
                       'mesh top from what lies above it (an overburden not meshed, the sea), a magnitude', &
                       'real', '>= 0')
    end if
    if (self%wet()) then
      call g%add('water_table', self%water_table, 'm', 'z of the free water surface: hydrostatic pore pressure '// &
                 'below it')
    else
      call g%add_unset('water_table', '(not set: dry, no pore pressure)', 'm', 'z of the free water surface: '// &
                       'hydrostatic pore pressure below it', 'real')
    end if
    call g%add('fluid_density', self%fluid_density, 'kg/m^3', 'density of the pore water', '> 0')
    call g%add('sh_max_azimuth', self%sh_max_azimuth, 'degrees', 'azimuth of the largest horizontal stress, '// &
               'clockwise from north (+y) towards east (+x); where a &material gives k0_max', '[0, 180)')
  end subroutine describe_geostatic_config
end module geostatic_config
