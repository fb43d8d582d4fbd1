!> Deck group &material (one per region): isotropic linear elastic solid.
!>
!>   region        name of the mesh region ('domain' for a box mesh)   [required]
!>   young         drained Young's modulus E [Pa] (> 0)                [required]
!>   poisson       drained Poisson's ratio nu (-1 < nu < 0.5)          [required]
!>   body_force(3) body force per unit volume [N/m^3]                  [0,0,0]
!> Poromechanics (physics = 'biot'; refused by the other physics, except
!> biot, which weighs a &pressure_change in elasticity and contact):
!>   biot          Biot coefficient b, 0 <= b <= 1                      [1]
!>   biot_modulus  Biot modulus M [Pa] (> 0); leave it out for
!>                 incompressible fluid and grains (1/M = 0)           [1/M = 0]
!>   permeability  isotropic permeability k [m^2] (> 0)                [required for biot]
!>   permeability_tensor(6)  full tensor xx, yy, zz, xy, yz, xz [m^2],
!>                 symmetric positive definite; replaces permeability
!>   viscosity     fluid viscosity mu [Pa s] (> 0)                     [1e-3]
!> In-situ state (&geostatic; refused without it):
!>   density       density of the (saturated) rock [kg/m^3] (>= 0)    [required with &geostatic]
!>   k0            ratio of horizontal to vertical effective stress in
!>                 situ (> 0); with k0_max, the ratio of the least
!>                 horizontal one                        [nu / (1 - nu), uniaxial strain]
!>   k0_max        ratio of the largest horizontal effective stress (along
!>                 &geostatic sh_max_azimuth) to the vertical one, >= k0
!>                                                       [k0: the same in every direction]
module material_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use strings, only: rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: material_config_t, read_materials

  type :: material_config_t
    character(len=name_len) :: region = ''
    real(rp) :: young = 0.0_rp
    real(rp) :: poisson = 0.0_rp
    real(rp) :: body_force(3) = 0.0_rp
    real(rp) :: biot = 1.0_rp
    real(rp) :: inv_biot_modulus = 0.0_rp      !< 1/M [1/Pa]
    real(rp) :: perm(3, 3) = 0.0_rp            !< permeability tensor [m^2]; 0 = not given
    real(rp) :: viscosity = 1.0e-3_rp
    ! as the deck gave them (unset_real: not given), for describe
    real(rp) :: biot_modulus = unset_real
    real(rp) :: permeability = unset_real
    real(rp) :: permeability_tensor(6) = unset_real
    real(rp) :: density = unset_real           !< [kg/m^3]; unset: not given
    real(rp) :: k0 = unset_real                !< unset: nu / (1 - nu)
    real(rp) :: k0_max = unset_real            !< unset: k0
  contains
    procedure :: describe => describe_material
  end type material_config_t

contains

  !> Read every &material group; at least one is required, regions unique.
  subroutine read_materials(d, log, mats, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(material_config_t), allocatable, intent(out) :: mats(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: region
    real(rp) :: young, poisson, body_force(3), biot, biot_modulus, permeability, permeability_tensor(6), viscosity
    real(rp) :: density, k0, k0_max
    real(rp) :: t(3, 3), ev(3)
    integer :: k, j, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /material/ region, young, poisson, body_force, biot, biot_modulus, permeability, permeability_tensor, &
                        viscosity, density, k0, k0_max

    allocate(mats(d%count('material')))
    if (size(mats) == 0) then
      call status%set("deck '"//trim(d%path)//"': no &material group (one per region is required)")
      return
    end if
    do k = 1, size(mats)
      region = ''; young = unset_real; poisson = unset_real; body_force = 0.0_rp
      biot = 1.0_rp; biot_modulus = unset_real; permeability = unset_real; permeability_tensor = unset_real
      viscosity = 1.0e-3_rp; density = unset_real; k0 = unset_real; k0_max = unset_real
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
      if (.not. (biot >= 0.0_rp .and. biot <= 1.0_rp)) &
        call d%fail(status, 'material', k, 'biot', 'must lie in [0, 1] (got '//rtoa(biot)//')')
      if (biot_modulus /= unset_real .and. .not. biot_modulus > 0.0_rp) &
        call d%fail(status, 'material', k, 'biot_modulus', 'must be positive (got '//rtoa(biot_modulus)//')')
      if (.not. viscosity > 0.0_rp) &
        call d%fail(status, 'material', k, 'viscosity', 'must be positive (got '//rtoa(viscosity)//')')
      if (density /= unset_real .and. .not. density >= 0.0_rp) &
        call d%fail(status, 'material', k, 'density', 'must be >= 0 (got '//rtoa(density)//')')
      if (k0 /= unset_real .and. .not. k0 > 0.0_rp) &
        call d%fail(status, 'material', k, 'k0', 'must be > 0 (got '//rtoa(k0)//')')
      if (k0_max /= unset_real) then
        if (.not. k0_max > 0.0_rp) then
          call d%fail(status, 'material', k, 'k0_max', 'must be > 0 (got '//rtoa(k0_max)//')')
        else if (k0 /= unset_real .and. k0_max < k0) then
          call d%fail(status, 'material', k, 'k0_max', 'must be >= k0, the least horizontal ratio (got '// &
                      rtoa(k0_max)//' < '//rtoa(k0)//')')
        else if (k0 == unset_real .and. poisson /= unset_real .and. poisson > -1.0_rp .and. poisson < 0.5_rp) then
          if (k0_max < poisson / (1.0_rp - poisson)) call d%fail(status, 'material', k, 'k0_max', &
            'must be >= k0, here nu / (1 - nu) = '//rtoa(poisson / (1.0_rp - poisson))//' (got '//rtoa(k0_max)//')')
        end if
      end if
      t = 0.0_rp
      if (any(permeability_tensor /= unset_real)) then
        if (any(permeability_tensor == unset_real)) then
          call d%fail(status, 'material', k, 'permeability_tensor', 'needs 6 values: xx, yy, zz, xy, yz, xz')
        else
          t = reshape([permeability_tensor(1), permeability_tensor(4), permeability_tensor(6), &
                       permeability_tensor(4), permeability_tensor(2), permeability_tensor(5), &
                       permeability_tensor(6), permeability_tensor(5), permeability_tensor(3)], [3, 3])
          call sym_eigenvalues(t, ev)
          if (.not. minval(ev) > 0.0_rp) &
            call d%fail(status, 'material', k, 'permeability_tensor', 'must be positive definite')
        end if
        if (permeability /= unset_real) &
          call d%fail(status, 'material', k, 'permeability', 'give permeability or permeability_tensor, not both')
      else if (permeability /= unset_real) then
        if (.not. permeability > 0.0_rp) then
          call d%fail(status, 'material', k, 'permeability', 'must be positive (got '//rtoa(permeability)//')')
        else
          t = 0.0_rp
          t(1, 1) = permeability; t(2, 2) = permeability; t(3, 3) = permeability
        end if
      end if
      if (.not. status%ok()) return
      mats(k) = material_config_t(region=region, young=young, poisson=poisson, body_force=body_force, biot=biot, &
        inv_biot_modulus=merge(0.0_rp, 1.0_rp / max(biot_modulus, tiny(1.0_rp)), biot_modulus == unset_real), &
        perm=t, viscosity=viscosity, biot_modulus=biot_modulus, permeability=permeability, &
        permeability_tensor=permeability_tensor, density=density, k0=k0, k0_max=k0_max)
    end do
  end subroutine read_materials

  subroutine describe_material(self, g)
    class(material_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('material', 'the rock of one region: an isotropic linear elastic solid, and for biot its '// &
                'pores and fluid (one group per region)')
    call g%add('region', self%region, '-', "mesh region: 'domain' for a box without &region, a &region name, "// &
               'or a Gmsh physical volume', 'one group per region')
    call g%add('young', self%young, 'Pa', "drained Young's modulus E", '> 0')
    call g%add('poisson', self%poisson, '-', "drained Poisson's ratio nu", '(-1, 0.5)')
    call g%add('body_force', self%body_force, 'N/m^3', 'body force per unit volume, e.g. 0, 0, -rho g (not with '// &
               '&geostatic, whose gravity acts on density)')
    call g%add('biot', self%biot, '-', 'Biot coefficient b (elasticity, contact: weighs a &pressure_change)', &
               '[0, 1]')
    if (self%biot_modulus /= unset_real) then
      call g%add('biot_modulus', self%biot_modulus, 'Pa', 'Biot modulus M', '> 0')
    else
      call g%add_unset('biot_modulus', '(not set: 1/M = 0)', 'Pa', 'Biot modulus M (left out: incompressible '// &
                       'fluid and grains)', 'real', '> 0')
    end if
    if (self%permeability /= unset_real) then
      call g%add('permeability', self%permeability, 'm^2', 'isotropic permeability k (this or '// &
                 'permeability_tensor is required)', '> 0')
    else
      call g%add_unset('permeability', '(not set)', 'm^2', 'isotropic permeability k (this or '// &
                       'permeability_tensor is required)', 'real', '> 0')
    end if
    if (all(self%permeability_tensor /= unset_real)) then
      call g%add('permeability_tensor', self%permeability_tensor, 'm^2', 'full permeability tensor xx, yy, zz, '// &
                 'xy, yz, xz (instead of permeability)', 'symmetric positive definite')
    else
      call g%add_unset('permeability_tensor', '(not set)', 'm^2', 'full permeability tensor xx, yy, zz, xy, yz, '// &
                       'xz (instead of permeability)', 'real(6)', 'symmetric positive definite')
    end if
    call g%add('viscosity', self%viscosity, 'Pa s', 'fluid viscosity mu', '> 0')
    if (self%density /= unset_real) then
      call g%add('density', self%density, 'kg/m^3', 'rock density, saturated below a water table (with '// &
                 '&geostatic, where it is required)', '>= 0')
    else
      call g%add_unset('density', '(not set)', 'kg/m^3', 'rock density, saturated below a water table (with '// &
                       '&geostatic, where it is required)', 'real', '>= 0')
    end if
    if (self%k0 /= unset_real) then
      call g%add('k0', self%k0, '-', 'in-situ ratio of horizontal to vertical effective stress; with k0_max, of '// &
                 'the least horizontal one (&geostatic)', '> 0')
    else
      call g%add_unset('k0', '(not set: nu / (1 - nu))', '-', 'in-situ ratio of horizontal to vertical '// &
                       'effective stress; with k0_max, of the least horizontal one (&geostatic)', 'real', '> 0')
    end if
    if (self%k0_max /= unset_real) then
      call g%add('k0_max', self%k0_max, '-', 'in-situ ratio of the largest horizontal effective stress, along '// &
                 '&geostatic sh_max_azimuth, to the vertical one (&geostatic)', '>= k0')
    else
      call g%add_unset('k0_max', '(not set: k0 in every direction)', '-', 'in-situ ratio of the largest '// &
                       'horizontal effective stress, along &geostatic sh_max_azimuth, to the vertical one '// &
                       '(&geostatic)', 'real', '>= k0')
    end if
  end subroutine describe_material

  !> Eigenvalues of a symmetric 3x3 matrix (Jacobi rotations).
  subroutine sym_eigenvalues(a_in, ev)
    real(rp), intent(in) :: a_in(3, 3)
    real(rp), intent(out) :: ev(3)
    real(rp) :: a(3, 3), th, c, s, t, app, aqq, apq
    integer :: sweep, p, q, r
    a = a_in
    do sweep = 1, 50
      if (abs(a(1,2)) + abs(a(1,3)) + abs(a(2,3)) <= 1.0e-15_rp * (abs(a(1,1)) + abs(a(2,2)) + abs(a(3,3)))) exit
      do p = 1, 2
        do q = p + 1, 3
          if (a(p, q) == 0.0_rp) cycle
          app = a(p, p); aqq = a(q, q); apq = a(p, q)
          th = (aqq - app) / (2.0_rp * apq)
          t = sign(1.0_rp, th) / (abs(th) + sqrt(th * th + 1.0_rp))
          c = 1.0_rp / sqrt(t * t + 1.0_rp)
          s = t * c
          do r = 1, 3
            if (r == p .or. r == q) cycle
            th = a(r, p)
            a(r, p) = c * th - s * a(r, q); a(p, r) = a(r, p)
            a(r, q) = s * th + c * a(r, q); a(q, r) = a(r, q)
          end do
          a(p, p) = app - t * apq
          a(q, q) = aqq + t * apq
          a(p, q) = 0.0_rp; a(q, p) = 0.0_rp
        end do
      end do
    end do
    ev = [a(1,1), a(2,2), a(3,3)]
  end subroutine sym_eigenvalues
end module material_config
