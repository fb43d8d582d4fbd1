!> The in-situ state of &geostatic (geostatic_config.f90): the weight of
!> horizontal layers under gravity along -z, a hydrostatic pore pressure
!> below a water table, and the effective stress with a K0 ratio per region.
!>
!> Layers: each region of the mesh is one horizontal layer, spanning the z
!> range of its cells; the regions may not overlap in depth and must fill
!> the column from the mesh bottom to its top with no gap (checked, with the
!> regions and depths named). The overburden at depth z is then the sum over
!> the regions of density x gravity x the part of the region above z: exact
!> for layers bounded by horizontal planes, and linear in z inside each layer,
!> so that 2 x 2 x 2 Gauss points integrate its work exactly on hexahedra
!> with horizontal top and bottom faces.
module geostatic
  use kinds, only: rp, ip, name_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use strings, only: rtoa
  use dist_mesh, only: dist_mesh_t
  use material_config, only: material_config_t
  use geostatic_config, only: geostatic_config_t
  use deck, only: unset_real
  implicit none
  private

  public :: geostatic_t

  real(rp), parameter :: deg = acos(-1.0_rp) / 180.0_rp   !< one degree [rad]

  type :: geostatic_t
    logical :: on = .false.
    logical :: wet = .false.               !< a water table: pore pressure below it
    real(rp) :: g = 0.0_rp                 !< gravity [m/s^2]
    real(rp) :: surface = 0.0_rp           !< vertical stress on the top [Pa], compression positive
    real(rp) :: zw = 0.0_rp                !< water table [m]
    real(rp) :: rho_f = 0.0_rp             !< fluid density [kg/m^3]
    real(rp) :: top = 0.0_rp, bottom = 0.0_rp   !< z of the mesh top and bottom [m]
    real(rp), allocatable :: rho(:), k0(:)      !< per mesh region [kg/m^3], [-]
    real(rp), allocatable :: k0_max(:)          !< per mesh region: along sh_dir [-]
    real(rp) :: sh_dir(2) = [0.0_rp, 1.0_rp]    !< (x, y) of the largest horizontal stress's direction
    real(rp), allocatable :: b(:)               !< per mesh region: Biot coefficient of the effective stress
    real(rp), allocatable :: zlo(:), zhi(:)     !< per mesh region: its depth range [m]
  contains
    procedure :: init
    procedure :: vertical_stress
    procedure :: pore_pressure
    procedure :: effective_stress
    procedure :: total_stress
    procedure :: weight
  end type geostatic_t

contains

  !> The state of cfg on mesh with the regions' materials (matched by name;
  !> a region without one is left to the physics' own check). Collective;
  !> status names the regions when the layers overlap or leave a gap.
  subroutine init(self, cfg, mats, mesh, status)
    class(geostatic_t), intent(inout) :: self
    type(geostatic_config_t), intent(in) :: cfg
    type(material_config_t), intent(in) :: mats(:)
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    type(parallel_comm_t) :: comm
    integer(ip) :: r, i, c, n
    real(rp) :: zc(8), tol

    self%on = cfg%on
    if (.not. self%on) return
    comm = mesh%comm
    self%g = cfg%gravity
    self%wet = cfg%wet()
    self%zw = cfg%water_table
    self%rho_f = cfg%fluid_density
    n = size(mesh%region_names, kind=ip)
    allocate(self%rho(n), self%k0(n), self%k0_max(n), self%b(n), self%zlo(n), self%zhi(n))
    self%sh_dir = [sin(cfg%sh_max_azimuth * deg), cos(cfg%sh_max_azimuth * deg)]
    self%rho = 0.0_rp
    self%k0 = 0.0_rp
    self%b = 1.0_rp
    do r = 1, n
      do i = 1, size(mats, kind=ip)
        if (mats(i)%region /= mesh%region_names(r)) cycle
        self%rho(r) = mats(i)%density
        self%k0(r) = mats(i)%k0
        self%b(r) = mats(i)%biot
        if (self%k0(r) == unset_real) self%k0(r) = mats(i)%poisson / (1.0_rp - mats(i)%poisson)
        self%k0_max(r) = mats(i)%k0_max
        if (self%k0_max(r) == unset_real) self%k0_max(r) = self%k0(r)
      end do
    end do
    self%zlo = huge(1.0_rp)
    self%zhi = -huge(1.0_rp)
    do c = 1, mesh%cell_map%n_owned
      r = mesh%cell_region(c)
      zc = mesh%coords(3, mesh%cell_nodes(:, c))
      self%zlo(r) = min(self%zlo(r), minval(zc))
      self%zhi(r) = max(self%zhi(r), maxval(zc))
    end do
    do r = 1, n
      self%zlo(r) = comm%min(self%zlo(r))
      self%zhi(r) = -comm%min(-self%zhi(r))
    end do
    self%top = maxval(self%zhi, mask=self%zhi > -huge(1.0_rp))
    self%bottom = minval(self%zlo, mask=self%zlo < huge(1.0_rp))
    tol = 1.0e-9_rp * (self%top - self%bottom)
    call check_layers(self, mesh, tol, status)
    if (cfg%surface_stress /= unset_real) then
      self%surface = cfg%surface_stress
    else if (self%wet) then
      self%surface = self%rho_f * self%g * max(self%zw - self%top, 0.0_rp)
    else
      self%surface = 0.0_rp
    end if
  end subroutine init

  !> The regions as layers: no two overlap in depth (beyond tol), and below
  !> each region's bottom (but the mesh bottom) another region starts.
  subroutine check_layers(self, mesh, tol, status)
    type(geostatic_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: tol
    type(error_status_t), intent(inout) :: status
    integer(ip) :: a, b
    logical :: below
    do a = 1, size(self%zlo, kind=ip)
      if (self%zlo(a) > self%zhi(a)) cycle          ! a region with no cell
      below = self%zlo(a) <= self%bottom + tol
      do b = 1, size(self%zlo, kind=ip)
        if (b == a .or. self%zlo(b) > self%zhi(b)) cycle
        if (abs(self%zhi(b) - self%zlo(a)) <= tol) below = .true.
        if (b > a .and. min(self%zhi(a), self%zhi(b)) - max(self%zlo(a), self%zlo(b)) > tol) then
          call status%set("&geostatic: regions '"//trim(mesh%region_names(a))//"' (z from "// &
            trim(rtoa(self%zlo(a)))//' to '//trim(rtoa(self%zhi(a)))//") and '"//trim(mesh%region_names(b))// &
            "' (z from "//trim(rtoa(self%zlo(b)))//' to '//trim(rtoa(self%zhi(b)))//') overlap in depth: '// &
            'the overburden is the weight of horizontal layers, one region each (give each layer its own region)')
          return
        end if
      end do
      if (.not. below) then
        call status%set("&geostatic: no region lies just below region '"//trim(mesh%region_names(a))// &
          "' (its bottom is z = "//trim(rtoa(self%zlo(a)))//', the mesh bottom z = '//trim(rtoa(self%bottom))// &
          '): the layers must fill the column, one region each')
        return
      end if
    end do
  end subroutine check_layers

  !> Total vertical stress at depth z [Pa] (negative: compression).
  pure real(rp) function vertical_stress(self, z)
    class(geostatic_t), intent(in) :: self
    real(rp), intent(in) :: z
    integer(ip) :: r
    vertical_stress = self%surface
    do r = 1, size(self%rho, kind=ip)
      vertical_stress = vertical_stress + self%g * self%rho(r) * max(0.0_rp, self%zhi(r) - max(self%zlo(r), z))
    end do
    vertical_stress = -vertical_stress
  end function vertical_stress

  !> Pore pressure at z [Pa]: hydrostatic below the water table, 0 above
  !> (and everywhere in a dry column).
  pure real(rp) function pore_pressure(self, z)
    class(geostatic_t), intent(in) :: self
    real(rp), intent(in) :: z
    pore_pressure = 0.0_rp
    if (self%wet) pore_pressure = self%rho_f * self%g * max(self%zw - z, 0.0_rp)
  end function pore_pressure

  !> Effective stress at z in region r, as a 3 x 3 tensor [Pa] (tension
  !> positive): k0_max sigma'_v along sh_dir and k0 sigma'_v across it
  !> horizontally (one K0 when the region has no k0_max), sigma'_v =
  !> sigma_v + b p0 vertically (b the region's Biot coefficient: 1,
  !> Terzaghi's effective stress, unless its &material says otherwise).
  pure function effective_stress(self, r, z) result(s)
    class(geostatic_t), intent(in) :: self
    integer(ip), intent(in) :: r
    real(rp), intent(in) :: z
    real(rp) :: s(3, 3), sv, d(2), e(2)
    integer :: i, j
    sv = self%vertical_stress(z) + self%b(r) * self%pore_pressure(z)
    d = self%sh_dir
    e = [d(2), -d(1)]
    s = 0.0_rp
    do j = 1, 2
      do i = 1, 2
        s(i, j) = sv * (self%k0_max(r) * d(i) * d(j) + self%k0(r) * e(i) * e(j))
      end do
    end do
    s(3, 3) = sv
  end function effective_stress

  !> Total stress at z in region r: the effective stress less b p0.
  pure function total_stress(self, r, z) result(s)
    class(geostatic_t), intent(in) :: self
    integer(ip), intent(in) :: r
    real(rp), intent(in) :: z
    real(rp) :: s(3, 3), p
    integer :: i
    s = self%effective_stress(r, z)
    p = self%b(r) * self%pore_pressure(z)
    do i = 1, 3
      s(i, i) = s(i, i) - p
    end do
  end function total_stress

  !> Weight per unit volume of region r [N/m^3] (acting along -z).
  pure real(rp) function weight(self, r)
    class(geostatic_t), intent(in) :: self
    integer(ip), intent(in) :: r
    weight = self%rho(r) * self%g
  end function weight
end module geostatic
