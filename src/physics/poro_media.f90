!> The matrix's fluid and its coupling to the solid, shared by the
!> three-field Biot physics (poromechanics.f90, 'biot') and the matrix
!> flow of a composition (matrix_flow_component.f90,
!> 'poromechanics_faults'): per region the Biot coefficient b, 1/M, the
!> drained bulk modulus and mu k^-1; per cell its volume, source rate and
!> pressure-controlled sources' index and pressure;
!> per face the flux boundary data (impermeable unless a pressure or flux
!> condition says otherwise) and the weights of the pressure-jump
!> stabilization; and the cell kernels:
!>   Q_e(u_ai) = b int_c dN_a/dx_i                   (cell_coupling)
!>   A_e(f, f') = int_c psi_f . mu k^-1 psi_f',  B_e(f) = int_c div psi_f
!>                in the global face orientation     (cell_darcy)
!>   the (p, p) rows: storage |c| / M, the jumps J and the pressure-
!>   controlled sources' dt index |c| (storage_row).
!> A type that extends poro_media_t has them as its own components.
module poro_media
  use kinds, only: rp, ip, gp, name_len
  use strings, only: itoa
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use index_map, only: index_map_t
  use block_matrix, only: block_matrix_t
  use sparsity, only: element_pattern
  use dist_mesh, only: dist_mesh_t
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients, inverse3
  use hex_rt0, only: rt0_cell_mass, rt0_cell_divergence, rt0_orient, rt0_values
  use elasticity, only: lame, point_block
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use source_config, only: source_config_t
  use face_box, only: face_in_box
  implicit none
  private

  public :: poro_media_t, face_area, cell_coupling, cell_darcy, flow_patterns

  type :: poro_media_t
    real(rp), allocatable :: biot(:), inv_m(:), kdr(:), kinv(:,:,:)   !< per region
    real(rp), allocatable :: vol(:)           !< local cell volumes [m^3]
    real(rp), allocatable :: src_rate(:)      !< fluid source per local cell [1/s]
    !> pressure-controlled sources per local cell: the sum of their indices
    !> [1/(Pa s)] and of index times pressure [1/s]; the cell takes
    !> |c| (src_jp - src_index p_c) [m^3/s]
    real(rp), allocatable :: src_index(:), src_jp(:)
    !> the pressure-controlled sources: names, index, pressure, and their
    !> owned cells (psrc_cells(psrc_first(k):psrc_first(k+1)-1))
    character(len=name_len), allocatable :: psrc_name(:)
    real(rp), allocatable :: psrc_index(:), psrc_p(:)
    integer(ip), allocatable :: psrc_first(:), psrc_cells(:)
    logical, allocatable :: q_fixed(:)        !< local faces with a prescribed flux (0 = no flow)
    real(rp), allocatable :: q_value(:)       !< prescribed flux through local faces [m^3/s]
    real(rp), allocatable :: p_bc(:)          !< pressure of pressure faces [Pa], by local face
    logical, allocatable :: p_face(:)
    integer(ip), allocatable :: face_bc(:)    !< condition of a pressure or flux face (0: none)
    type(boundary_config_t), allocatable :: bcs(:)
    real(rp) :: a_scale = 1.0_rp
    real(rp), allocatable :: a_norm(:)        !< ||A(f,:)||_2 by local face (ghosts imported)
    !> Pressure-jump stabilization by local face: the weight of the step
    !> (jump_w, for the step size jump_dt), the weight of the undrained
    !> incompressible limit (jump_full), and what sizes it between the two
    !> (jump_r0, jump_fo; see jump_weights and jump_factor)
    real(rp), allocatable :: jump_w(:)        !< [m^3/Pa]
    real(rp), allocatable :: jump_full(:)     !< [m^3/Pa]
    real(rp), allocatable :: jump_r0(:)       !< (b^2/M_c) / (b^2/M_c + 1/M) [-]
    real(rp), allocatable :: jump_fo(:)       !< c_v / h_f^2, the mesh Fourier number per second [1/s]
    logical :: jump_adaptive = .true.         !< the weight follows dt (else jump_full at every step)
    real(rp) :: jump_dt = -1.0_rp             !< step size of jump_w and of the (p, p) block [s] (< 0: none)
  contains
    procedure :: init_media
    procedure :: jump_factor
    procedure :: add_jumps
    procedure :: storage_row
    procedure :: prescribed_flux
    procedure :: cell_velocity
    procedure :: source_rates
    procedure :: free_media
  end type poro_media_t

contains

  !> Materials per region (physics: the &run name, for the message), the
  !> sources, the cell volumes, the flux boundary data (box_tol: the
  !> conditions' box tolerance [m]) and the stabilization's weights
  !> (stab_beta > 0 its factor, 0: off; stab_adaptive: sized by each step).
  subroutine init_media(self, mesh, mats, bcs, srcs, stab_beta, stab_adaptive, box_tol, physics, status)
    class(poro_media_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(material_config_t), intent(in) :: mats(:)
    type(boundary_config_t), intent(in) :: bcs(:)
    type(source_config_t), intent(in) :: srcs(:)
    real(rp), intent(in) :: stab_beta, box_tol(3)
    logical, intent(in) :: stab_adaptive
    character(len=*), intent(in) :: physics
    type(error_status_t), intent(inout) :: status
    integer(ip) :: c
    call region_materials(self, mesh, mats, physics, status)
    if (status%ok()) call region_sources(self, mesh, srcs, status)
    if (.not. status%ok()) return
    allocate(self%vol(mesh%n_cells))
    do c = 1, mesh%n_cells
      self%vol(c) = mesh%cell_volume(c)
    end do
    call flux_conditions(self, mesh, bcs, box_tol, status)
    if (.not. status%ok()) return
    allocate(self%a_norm(mesh%n_faces))
    self%jump_adaptive = stab_adaptive
    call jump_weights(self, mesh, mats, stab_beta)
  end subroutine init_media

  !> b, 1/M, K_dr and mu k^-1 of every region.
  subroutine region_materials(self, mesh, mats, physics, status)
    class(poro_media_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(material_config_t), intent(in) :: mats(:)
    character(len=*), intent(in) :: physics
    type(error_status_t), intent(inout) :: status
    integer(ip) :: r, m, i, nreg
    real(rp) :: lam, mu, km(3, 3), det
    nreg = size(mesh%region_names, kind=ip)
    allocate(self%biot(nreg), self%inv_m(nreg), self%kdr(nreg), self%kinv(3, 3, nreg))
    do r = 1, nreg
      m = 0
      do i = 1, size(mats, kind=ip)
        if (mats(i)%region == mesh%region_names(r)) m = i
      end do
      if (all(mats(m)%perm == 0.0_rp)) then
        call status%set("&material of region '"//trim(mats(m)%region)// &
                        "': permeability (or permeability_tensor) is required for physics = '"//physics//"'")
        return
      end if
      self%biot(r) = mats(m)%biot
      self%inv_m(r) = mats(m)%inv_biot_modulus
      call lame(mats(m)%young, mats(m)%poisson, lam, mu)
      self%kdr(r) = lam + 2.0_rp * mu / 3.0_rp
      call inverse3(mats(m)%perm, km, det)
      self%kinv(:, :, r) = mats(m)%viscosity * km
    end do
  end subroutine region_materials

  !> The &source rates, indices and pressures per local cell (a group with
  !> a point: the cells of its region in the point's fault block; groups
  !> add up), and each pressure-controlled source's owned cells.
  !> Collective.
  subroutine region_sources(self, mesh, srcs, status)
    class(poro_media_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(source_config_t), intent(in) :: srcs(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: r, i, c, rpt, k
    integer(gp) :: blk
    integer(ip), allocatable :: cells(:)
    character(len=:), allocatable :: where
    allocate(self%src_rate(mesh%n_cells), self%src_index(mesh%n_cells), self%src_jp(mesh%n_cells))
    self%src_rate = 0.0_rp
    self%src_index = 0.0_rp
    self%src_jp = 0.0_rp
    k = count(srcs%by_pressure)
    allocate(self%psrc_name(k), self%psrc_index(k), self%psrc_p(k), self%psrc_first(k + 1), self%psrc_cells(0))
    self%psrc_first(1) = 1
    k = 0
    do i = 1, size(srcs, kind=ip)
      r = mesh%region_id(srcs(i)%region)
      if (r == 0) then
        call status%set("&source in region '"//trim(srcs(i)%region)//"', which the mesh does not have "// &
                        '(its regions: '//mesh%region_list()//')')
        return
      end if
      blk = 0
      if (srcs(i)%has_point) then
        where = '&source '//itoa(int(i))//" (region '"//trim(srcs(i)%region)//"'), variable point"
        call point_block(mesh, srcs(i)%point, blk, rpt, status, where)
        if (.not. status%ok()) return
        if (rpt /= r) then
          call status%set(where//": lies in region '"//trim(mesh%region_names(rpt))//"'")
          return
        end if
      end if
      cells = pack([(c, c = 1, mesh%n_cells)], mesh%cell_region(1:mesh%n_cells) == r)
      if (srcs(i)%has_point) cells = pack(cells, mesh%cell_block(cells) == blk)
      if (srcs(i)%by_pressure) then
        self%src_index(cells) = self%src_index(cells) + srcs(i)%index
        self%src_jp(cells) = self%src_jp(cells) + srcs(i)%index * srcs(i)%pressure
        k = k + 1
        self%psrc_name(k) = srcs(i)%name
        self%psrc_index(k) = srcs(i)%index
        self%psrc_p(k) = srcs(i)%pressure
        cells = pack(cells, cells <= mesh%cell_map%n_owned)
        self%psrc_cells = [self%psrc_cells, cells]
        self%psrc_first(k + 1) = size(self%psrc_cells, kind=ip) + 1
      else
        self%src_rate(cells) = self%src_rate(cells) + srcs(i)%rate
      end if
    end do
  end subroutine region_sources

  !> The rate each pressure-controlled source gives the rock at the owned
  !> cells' pressures p [m^3/s] (negative: production), as probe columns
  !> '<name>:rate [m3/s]'. Collective.
  subroutine source_rates(self, mesh, p, names, values)
    class(poro_media_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: p(:)
    character(len=*), allocatable, intent(inout) :: names(:)
    real(rp), allocatable, intent(inout) :: values(:)
    real(rp), allocatable :: q(:)
    integer(ip) :: k, c
    integer :: i
    allocate(q(size(self%psrc_name)))
    q = 0.0_rp
    do k = 1, size(q, kind=ip)
      do i = self%psrc_first(k), self%psrc_first(k + 1) - 1
        c = self%psrc_cells(i)
        q(k) = q(k) + self%psrc_index(k) * self%vol(c) * (self%psrc_p(k) - p(c))
      end do
    end do
    call mesh%comm%sum_all(q)
    if (.not. allocated(names)) allocate(names(0))
    if (.not. allocated(values)) allocate(values(0))
    do k = 1, size(q, kind=ip)
      names = [character(len=len(names)) :: names, trim(self%psrc_name(k))//':rate [m3/s]']
      values = [values, q(k)]
    end do
  end subroutine source_rates

  !> Flux boundary data: impermeable unless a pressure or flux condition
  !> says otherwise.
  subroutine flux_conditions(self, mesh, bcs, tol, status)
    class(poro_media_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(boundary_config_t), intent(in) :: bcs(:)
    real(rp), intent(in) :: tol(3)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: b, s, i, f
    allocate(self%q_fixed(mesh%n_faces), self%q_value(mesh%n_faces), self%p_face(mesh%n_faces), &
             self%p_bc(mesh%n_faces), self%face_bc(mesh%n_faces))
    self%face_bc = 0
    self%bcs = bcs
    self%q_fixed = mesh%face_on_boundary
    self%q_value = 0.0_rp
    self%p_face = .false.
    self%p_bc = 0.0_rp
    do b = 1, size(bcs, kind=ip)
      if (bcs(b)%type /= 'pressure' .and. bcs(b)%type /= 'flux') cycle
      s = mesh%set_id(bcs(b)%set)
      do i = 1, mesh%n_sfaces
        if (mesh%sface_set(i) /= s) cycle
        f = mesh%sface_face(i)
        if (.not. mesh%face_on_boundary(f)) then
          call status%set("&boundary type = '"//trim(bcs(b)%type)//"' on set '"//trim(bcs(b)%set)// &
                          "', which is not on the boundary")
          return
        end if
        if (.not. face_in_box(mesh, f, bcs(b)%lower, bcs(b)%upper, tol)) cycle
        self%face_bc(f) = b
        if (bcs(b)%type == 'pressure') then
          self%q_fixed(f) = .false.
          self%p_face(f) = .true.
          self%p_bc(f) = bcs(b)%value(1)
        else
          self%q_fixed(f) = .true.
          self%p_face(f) = .false.
          self%q_value(f) = bcs(b)%value(1) * face_area(mesh, f)
        end if
      end do
    end do
  end subroutine flux_conditions

  !> Weights of the pressure-jump stabilization (after Berger, Bordas, Kay
  !> and Tavener, SIAM J. Sci. Comput. 37 (2015), local pressure jumps for
  !> Q1/P0-type poroelasticity): for an interior face f between cells c1, c2,
  !>   w_f = beta h_f |f| / M_c,  h_f = |x_c1 - x_c2|,  M_c the mean constrained
  !> modulus lambda + 2 mu of the two cells,
  !> so that J(p, chi) = sum_f w_f [p]_f [chi]_f has the units of the mass
  !> balance (volume) and the size of the undrained Schur complement b^2 V / M_c
  !> times beta. It acts on the pressure increment of each step, so it
  !> vanishes at steady state and does not pollute a drained solution.
  !> That is jump_full, the weight of the undrained incompressible limit;
  !> for the adaptive size (jump_factor) each face also gets, from the face
  !> means of the two cells' b^2/M_c, 1/M and mobility k_n/mu (k_n along
  !> x_c2 - x_c1),
  !>   r0 = (b^2/M_c) / (b^2/M_c + 1/M)   and   fo = c_v / h_f^2,
  !>   c_v = (k_n/mu) / (b^2/M_c + 1/M)   (the consolidation coefficient).
  subroutine jump_weights(self, mesh, mats, beta)
    class(poro_media_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(material_config_t), intent(in) :: mats(:)
    real(rp), intent(in) :: beta
    integer(ip) :: f, c1, c2, k
    real(rp) :: x1(3), x2(3), m(2), s(2), st(2), mob(2), h, e(3)
    allocate(self%jump_w(mesh%n_faces), self%jump_full(mesh%n_faces), self%jump_r0(mesh%n_faces), &
             self%jump_fo(mesh%n_faces))
    self%jump_w = 0.0_rp
    self%jump_full = 0.0_rp
    self%jump_r0 = 1.0_rp
    self%jump_fo = 0.0_rp
    self%jump_dt = -1.0_rp
    if (beta <= 0.0_rp) return
    do f = 1, mesh%n_faces
      c1 = mesh%face_cells(1, f)
      c2 = mesh%face_cells(2, f)
      if (mesh%face_on_boundary(f) .or. c1 == 0 .or. c2 == 0) cycle
      x1 = sum(mesh%coords(:, mesh%cell_nodes(:, c1)), dim=2) / 8.0_rp
      x2 = sum(mesh%coords(:, mesh%cell_nodes(:, c2)), dim=2) / 8.0_rp
      h = norm2(x1 - x2)
      e = (x2 - x1) / h
      do k = 1, 2
        associate (r => mesh%cell_region(mesh%face_cells(k, f)))
          m(k) = constrained_modulus(mats, mesh%region_names(r))
          s(k) = self%biot(r)**2 / m(k)
          st(k) = self%inv_m(r)
          mob(k) = 1.0_rp / dot_product(e, matmul(self%kinv(:, :, r), e))
        end associate
      end do
      self%jump_full(f) = beta * h * face_area(mesh, f) / (0.5_rp * (m(1) + m(2)))
      if (sum(s) > 0.0_rp) then
        self%jump_r0(f) = sum(s) / (sum(s) + sum(st))
        self%jump_fo(f) = sum(mob) / ((sum(s) + sum(st)) * h**2)
      else
        self%jump_r0(f) = 0.0_rp
      end if
    end do
  end subroutine jump_weights

  !> The weights of a step of size dt [s] into jump_w; .true. if they or
  !> the (p, p) block (dt index |c| of a pressure-controlled source) changed
  !> since the last call. Full size: jump_full. Adaptive: jump_full r^2 with
  !>   r = r0 / (1 + dt c_v / h_f^2)
  !>     = (b^2/M_c) / (b^2/M_c + 1/M + dt (k_n/mu) / h_f^2),
  !> the undrained Schur complement's share of the (p, p) block of the Schur
  !> complement (storage plus dt times the Darcy part): 1 in the undrained
  !> step with incompressible constituents, where Q1-P0 pressures
  !> oscillate, and towards 0 where storage (1/M) or flow (the mesh Fourier
  !> number dt c_v / h^2) control the pressure. Without stabilization the
  !> first-step overshoot grows with r itself (Terzaghi, E 1e8, nu 0.25,
  !> b 1, 2 x 2 x 20 cells, the undrained step, then dt c_v / h^2 ~ 4e-3:
  !> max p / p0 - 1 = 5.2e-3, 4.7e-3, 3.8e-3, 2.5e-3 at r0 = 1, 0.89, 0.71,
  !> 0.46), while the full weight costs accuracy where r is small. Why r^2,
  !> measured on Terzaghi columns (b 0.9, 20 cells, fixed dt c_v / h^2 = 0.1,
  !> pressure relative L2 error at T = c_v t / H^2 = 0.05; without
  !> stabilization 5.8e-4): at r0 = 0.40 (full weight 4.3x that error) r
  !> gives 1.32x, r^2 0.72x, r^3 0.85x; at r0 = 0.67 (full 7.4x) r 4.3x,
  !> r^2 2.4x, r^3 1.35x. In the first step above, r^2 leaves no overshoot
  !> and a monotone profile at r0 = 0.89 (as r and the full weight), and at
  !> r0 = 0.71 a largest rise between cells of 4.7e-4 p0 (r^3: 1.1e-3 p0,
  !> none: 4.8e-3 p0, r: none). So r^2: the incompressible undrained end
  !> keeps the full weight, and a step with 1/M above b^2/M_c loses no
  !> accuracy; tests/verification/terzaghi.sh checks both ends.
  logical function jump_factor(self, dt) result(changed)
    class(poro_media_t), intent(inout) :: self
    real(rp), intent(in) :: dt
    changed = self%jump_dt < 0.0_rp .or. ((self%jump_adaptive .or. size(self%psrc_name) > 0) .and. &
                                         dt /= self%jump_dt)
    if (.not. changed) return
    self%jump_dt = dt
    if (self%jump_adaptive) then
      self%jump_w = self%jump_full * (self%jump_r0 / (1.0_rp + dt * self%jump_fo))**2
    else
      self%jump_w = self%jump_full
    end if
  end function jump_factor

  !> Row c (an owned cell) of the stabilization J with the weights of
  !> jump_w, added to m (on a pattern with the cells sharing a face).
  subroutine add_jumps(self, mesh, c, m)
    class(poro_media_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    type(csr_matrix_t), intent(inout) :: m
    integer(ip) :: j, f, other
    do j = 1, 6
      f = mesh%cell_faces(j, c)
      if (self%jump_w(f) == 0.0_rp) cycle
      other = mesh%face_cells(1, f)
      if (other == c) other = mesh%face_cells(2, f)
      call m%add_value(c, c, self%jump_w(f))
      call m%add_value(c, other, -self%jump_w(f))
    end do
  end subroutine add_jumps

  real(rp) function constrained_modulus(mats, region)
    type(material_config_t), intent(in) :: mats(:)
    character(len=*), intent(in) :: region
    integer :: i
    real(rp) :: lam, mu
    constrained_modulus = 1.0_rp
    do i = 1, size(mats)
      if (mats(i)%region /= region) cycle
      call lame(mats(i)%young, mats(i)%poisson, lam, mu)
      constrained_modulus = lam + 2.0_rp * mu
    end do
  end function constrained_modulus

  real(rp) function face_area(mesh, f)
    use hex_q1, only: quad_area_vector
    use quadrature, only: gauss_quad
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: f
    real(rp) :: xq(2, 4), wq(4)
    integer :: q
    call gauss_quad(2_ip, xq, wq)
    face_area = 0.0_rp
    do q = 1, 4
      face_area = face_area + wq(q) * norm2(quad_area_vector(mesh%coords(:, mesh%face_nodes(:, f)), xq(:, q)))
    end do
  end function face_area

  !> Prescribed flux through local face f at time t [m^3/s].
  real(rp) function prescribed_flux(self, f, t)
    class(poro_media_t), intent(in) :: self
    integer(ip), intent(in) :: f
    real(rp), intent(in) :: t
    prescribed_flux = self%q_value(f)
    if (self%face_bc(f) > 0) prescribed_flux = prescribed_flux * self%bcs(self%face_bc(f))%factor(t)
  end function prescribed_flux

  !> Row c (an owned cell) of the (p, p) block of a step of size dt [s]:
  !> storage |c| / M, the pressure-controlled sources' dt index |c| and
  !> the stabilization J with the weights of jump_w, added to m.
  subroutine storage_row(self, mesh, c, dt, m)
    class(poro_media_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    real(rp), intent(in) :: dt
    type(csr_matrix_t), intent(inout) :: m
    call m%add_value(c, c, self%vol(c) * (self%inv_m(mesh%cell_region(c)) + dt * self%src_index(c)))
    call self%add_jumps(mesh, c, m)
  end subroutine storage_row

  !> Q_e = b int_c grad N_a (24 entries, node a's x, y, z at 3a-2..3a) of
  !> the hexahedron with nodes xe [m^3].
  subroutine cell_coupling(xe, b, qe)
    real(rp), intent(in) :: xe(3, 8), b
    real(rp), intent(out) :: qe(24)
    real(rp) :: xi(3, 8), w(8), n(8), g(3, 8), det
    integer(ip) :: q, a
    call gauss_hex(2_ip, xi, w)
    qe = 0.0_rp
    do q = 1, 8
      call hex_gradients(xe, xi(:, q), n, g, det)
      do a = 1, 8
        qe(3*a-2:3*a) = qe(3*a-2:3*a) + b * g(:, a) * det * w(q)
      end do
    end do
  end subroutine cell_coupling

  !> The RT0 mass matrix A_e (with mu k^-1 = kinv) and divergence B_e of
  !> the hexahedron with nodes xe, in the global orientation of its faces
  !> (signs: the mesh's cell_face_sign of the cell).
  subroutine cell_darcy(xe, kinv, signs, ae, be, status)
    real(rp), intent(in) :: xe(3, 8), kinv(3, 3)
    integer(ip), intent(in) :: signs(6)
    real(rp), intent(out) :: ae(6, 6), be(6)
    type(error_status_t), intent(inout) :: status
    call rt0_cell_mass(xe, kinv, ae, status)
    if (.not. status%ok()) return
    call rt0_cell_divergence(xe, be, status)
    if (.not. status%ok()) return
    call rt0_orient(signs, ae)
    call rt0_orient(signs, be)
  end subroutine cell_darcy

  !> The patterns of the flow's blocks in sys, blocks b = [u, q, p] with
  !> their maps: (u, p) and (p, u) (3 dofs per node), (q, q), (q, p),
  !> (p, q), and (p, p) on the cells sharing a face (room for the
  !> stabilization).
  subroutine flow_patterns(mesh, sys, b, umap, qmap, pmap)
    type(dist_mesh_t), intent(in) :: mesh
    type(block_matrix_t), intent(inout) :: sys
    integer, intent(in) :: b(3)
    type(index_map_t), intent(in), target :: umap, qmap, pmap
    integer(ip), allocatable :: row_ptr(:), col(:), cells(:,:)
    integer(ip) :: c
    allocate(cells(1, mesh%n_cells))
    cells(1, :) = [(c, c = 1, mesh%n_cells)]
    call element_pattern(mesh%node_map%n_owned, mesh%cell_nodes, cells, 3_ip, 1_ip, row_ptr, col)
    call sys%set_pattern(b(1), b(3), umap, pmap, row_ptr, col)
    call element_pattern(mesh%cell_map%n_owned, cells, mesh%cell_nodes, 1_ip, 3_ip, row_ptr, col)
    call sys%set_pattern(b(3), b(1), pmap, umap, row_ptr, col)
    call element_pattern(mesh%face_map%n_owned, mesh%cell_faces, mesh%cell_faces, 1_ip, 1_ip, row_ptr, col)
    call sys%set_pattern(b(2), b(2), qmap, qmap, row_ptr, col)
    call element_pattern(mesh%face_map%n_owned, mesh%cell_faces, cells, 1_ip, 1_ip, row_ptr, col)
    call sys%set_pattern(b(2), b(3), qmap, pmap, row_ptr, col)
    call element_pattern(mesh%cell_map%n_owned, cells, mesh%cell_faces, 1_ip, 1_ip, row_ptr, col)
    call sys%set_pattern(b(3), b(2), pmap, qmap, row_ptr, col)
    call element_pattern(mesh%cell_map%n_owned, mesh%face_cells, mesh%face_cells, 1_ip, 1_ip, row_ptr, col)
    call sys%set_pattern(b(3), b(3), pmap, pmap, row_ptr, col)
  end subroutine flow_patterns

  !> Darcy velocity at the centre of each owned cell [m/s] from the fluxes
  !> q_loc (all local faces, ghosts up to date).
  subroutine cell_velocity(self, mesh, q_loc, v)
    class(poro_media_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: q_loc(:)
    real(rp), intent(out) :: v(:,:)
    real(rp) :: psi(3, 6), divv(6), det, qf(6)
    integer(ip) :: c
    do c = 1, mesh%cell_map%n_owned
      call rt0_values(mesh%coords(:, mesh%cell_nodes(:, c)), [0.0_rp, 0.0_rp, 0.0_rp], psi, divv, det)
      qf = q_loc(mesh%cell_faces(:, c)) * real(mesh%cell_face_sign(:, c), rp)
      v(:, c) = matmul(psi, qf)
    end do
  end subroutine cell_velocity

  subroutine free_media(self)
    class(poro_media_t), intent(inout) :: self
    if (allocated(self%biot)) deallocate(self%biot, self%inv_m, self%kdr, self%kinv)
    if (allocated(self%vol)) deallocate(self%vol)
    if (allocated(self%src_rate)) deallocate(self%src_rate, self%src_index, self%src_jp)
    if (allocated(self%psrc_name)) deallocate(self%psrc_name, self%psrc_index, self%psrc_p, self%psrc_first, &
                                              self%psrc_cells)
    if (allocated(self%q_fixed)) deallocate(self%q_fixed, self%q_value, self%p_face, self%p_bc, self%face_bc)
    if (allocated(self%bcs)) deallocate(self%bcs)
    if (allocated(self%a_norm)) deallocate(self%a_norm)
    if (allocated(self%jump_w)) deallocate(self%jump_w, self%jump_full, self%jump_r0, self%jump_fo)
  end subroutine free_media
end module poro_media
