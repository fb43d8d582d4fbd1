!> Three-field Biot poromechanics: displacement u (Q1, 3 per node), Darcy flux
!> q (RT0, 1 per face: total flux along the global face normal) and pressure
!> p (P0, 1 per cell), implicit Euler with gamma = dt. The block system of a
!> time step (the seed's form, third row multiplied by gamma):
!>
!>     [ K    0      -Q ] [u]   [ f                                     ]
!>     [ 0    A      -B ] [q] = [ -(p_bar on pressure faces)            ]
!>     [ Q^T  g B^T   P ] [p]   [ g*source + Q^T u_old + P p_old        ]
!>
!> K: elasticity (from elasticity_t), Q(u_ai, c) = b int_c dN_a/dx_i,
!> A(f, f') = int psi_f . mu k^-1 psi_f', B(f, c) = int_c div psi_f (= +-1),
!> P(c, c) = |c| / M, g = gamma = dt (0 for the undrained step).
!> Prescribed displacements and fluxes are eliminated symmetrically (their
!> known values go to the right-hand side; their rows get a scaled identity);
!> boundary faces without a pressure or flux condition are impermeable.
!> Blocks are numbered 1 = u, 2 = q, 3 = p.
module poromechanics
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use dist_mesh, only: dist_mesh_t
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients, inverse3
  use hex_rt0, only: rt0_cell_mass, rt0_cell_divergence, rt0_values, rt0_orient
  use elasticity, only: elasticity_t, lame
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use source_config, only: source_config_t
  use face_box, only: face_in_box
  implicit none
  private

  public :: poromechanics_t, iu, iq, ipr

  integer, parameter :: iu = 1, iq = 2, ipr = 3

  type :: poromechanics_t
    type(elasticity_t) :: mech
    type(dof_map_t) :: qd, pd                 !< flux (faces) and pressure (cells) dofs
    type(block_matrix_t) :: sys
    real(rp), allocatable :: rhs(:)           !< block vector
    real(rp), allocatable :: x(:), x_old(:)   !< state at the new and the previous time (block vectors)
    real(rp), allocatable :: biot(:), inv_m(:), kdr(:), kinv(:,:,:)   !< per region
    real(rp), allocatable :: vol(:)           !< local cell volumes [m^3]
    real(rp), allocatable :: src_rate(:)      !< fluid source per region [1/s]
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
    !> The matrix is the same at every step but for its (p, q) block, dt B,
    !> and (adaptive stabilization) its (p, p) block: assembled once
    !> (matrix_ready), then only the (p, q) block is scaled (from pq_unit,
    !> B's values), the (p, p) block made again when dt changes, and the
    !> right-hand side made again
    logical :: matrix_ready = .false.
    real(rp), allocatable :: pq_unit(:)
  contains
    procedure :: init
    procedure :: assemble
    procedure :: fixed_stress_schur
    procedure :: algebraic_schur
    procedure :: cell_velocity
    procedure :: free
  end type poromechanics_t

contains

  !> Dofs, block patterns, materials and boundary data. stab_beta > 0 turns
  !> on the pressure-jump stabilization with that factor (0: off);
  !> stab_adaptive sizes it by the closeness of each step to the undrained
  !> incompressible limit (else it has that limit's size at every step).
  !> Collective.
  subroutine init(self, mesh, mats, bcs, srcs, stab_beta, stab_adaptive, status)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(material_config_t), intent(in) :: mats(:)
    type(boundary_config_t), intent(in) :: bcs(:)
    type(source_config_t), intent(in) :: srcs(:)
    real(rp), intent(in) :: stab_beta
    logical, intent(in) :: stab_adaptive
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:), cells(:,:)
    integer(ip) :: r, m, i, c, b, s, f, nreg
    real(rp) :: lam, mu, km(3, 3), det, tol(3)

    call self%free()
    call self%mech%init(mesh, mats, bcs, status)
    if (.not. status%ok()) return
    nreg = size(mesh%region_names, kind=ip)
    allocate(self%biot(nreg), self%inv_m(nreg), self%kdr(nreg), self%kinv(3, 3, nreg))
    do r = 1, nreg
      m = 0
      do i = 1, size(mats, kind=ip)
        if (mats(i)%region == mesh%region_names(r)) m = i
      end do
      if (all(mats(m)%perm == 0.0_rp)) then
        call status%set("&material of region '"//trim(mats(m)%region)// &
                        "': permeability (or permeability_tensor) is required for physics = 'biot'")
        return
      end if
      self%biot(r) = mats(m)%biot
      self%inv_m(r) = mats(m)%inv_biot_modulus
      call lame(mats(m)%young, mats(m)%poisson, lam, mu)
      self%kdr(r) = lam + 2.0_rp * mu / 3.0_rp
      call inverse3(mats(m)%perm, km, det)
      self%kinv(:, :, r) = mats(m)%viscosity * km
    end do

    call self%qd%init('flux', mesh%face_map, 1_ip)
    call self%pd%init('pressure', mesh%cell_map, 1_ip)
    call self%sys%init([self%mech%u%n_owned(), self%qd%n_owned(), self%pd%n_owned()])
    allocate(cells(1, mesh%n_cells))
    cells(1, :) = [(c, c = 1, mesh%n_cells)]
    call element_pattern(mesh%node_map%n_owned, mesh%cell_nodes, mesh%cell_nodes, 3_ip, 3_ip, row_ptr, col)
    call self%sys%set_pattern(iu, iu, self%mech%u%map, self%mech%u%map, row_ptr, col)
    call element_pattern(mesh%node_map%n_owned, mesh%cell_nodes, cells, 3_ip, 1_ip, row_ptr, col)
    call self%sys%set_pattern(iu, ipr, self%mech%u%map, self%pd%map, row_ptr, col)
    call element_pattern(mesh%cell_map%n_owned, cells, mesh%cell_nodes, 1_ip, 3_ip, row_ptr, col)
    call self%sys%set_pattern(ipr, iu, self%pd%map, self%mech%u%map, row_ptr, col)
    call element_pattern(mesh%face_map%n_owned, mesh%cell_faces, mesh%cell_faces, 1_ip, 1_ip, row_ptr, col)
    call self%sys%set_pattern(iq, iq, self%qd%map, self%qd%map, row_ptr, col)
    call element_pattern(mesh%face_map%n_owned, mesh%cell_faces, cells, 1_ip, 1_ip, row_ptr, col)
    call self%sys%set_pattern(iq, ipr, self%qd%map, self%pd%map, row_ptr, col)
    call element_pattern(mesh%cell_map%n_owned, cells, mesh%cell_faces, 1_ip, 1_ip, row_ptr, col)
    call self%sys%set_pattern(ipr, iq, self%pd%map, self%qd%map, row_ptr, col)
    ! pressure-pressure: cells sharing a face (room for the stabilization)
    call element_pattern(mesh%cell_map%n_owned, mesh%face_cells, mesh%face_cells, 1_ip, 1_ip, row_ptr, col)
    call self%sys%set_pattern(ipr, ipr, self%pd%map, self%pd%map, row_ptr, col)
    n_check: block
      integer(ip) :: nb
      nb = self%sys%offset(4)
      allocate(self%rhs(nb), self%x(nb), self%x_old(nb))
    end block n_check
    self%x = 0.0_rp
    self%x_old = 0.0_rp

    allocate(self%src_rate(nreg))
    self%src_rate = 0.0_rp
    do i = 1, size(srcs, kind=ip)
      r = mesh%region_id(srcs(i)%region)
      if (r == 0) then
        call status%set("&source in region '"//trim(srcs(i)%region)//"', which the mesh does not have "// &
                        '(its regions: '//mesh%region_list()//')')
        return
      end if
      self%src_rate(r) = self%src_rate(r) + srcs(i)%rate
    end do
    allocate(self%vol(mesh%n_cells))
    do c = 1, mesh%n_cells
      self%vol(c) = mesh%cell_volume(c)
    end do

    ! flux boundary data: impermeable unless a pressure or flux condition says otherwise
    allocate(self%q_fixed(mesh%n_faces), self%q_value(mesh%n_faces), self%p_face(mesh%n_faces), &
             self%p_bc(mesh%n_faces), self%face_bc(mesh%n_faces))
    self%face_bc = 0
    self%bcs = bcs
    self%q_fixed = mesh%face_on_boundary
    self%q_value = 0.0_rp
    self%p_face = .false.
    self%p_bc = 0.0_rp
    tol = self%mech%box_tol
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
    allocate(self%a_norm(mesh%n_faces))
    self%jump_adaptive = stab_adaptive
    call jump_weights(self, mesh, mats, stab_beta)
  end subroutine init

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
    type(poromechanics_t), intent(inout) :: self
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

  !> The weights of a step of size dt [s] into jump_w; .true. if they changed
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
    type(poromechanics_t), intent(inout) :: self
    real(rp), intent(in) :: dt
    changed = self%jump_dt < 0.0_rp .or. (self%jump_adaptive .and. dt /= self%jump_dt)
    if (.not. changed) return
    self%jump_dt = dt
    if (self%jump_adaptive) then
      self%jump_w = self%jump_full * (self%jump_r0 / (1.0_rp + dt * self%jump_fo))**2
    else
      self%jump_w = self%jump_full
    end if
  end function jump_factor

  !> The (p, p) block: storage |c| / M and the stabilization J with the
  !> weights of jump_w. Collective.
  subroutine pressure_block(self, mesh)
    type(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip) :: c
    associate (pp => self%sys%a(ipr, ipr))
      pp%val = 0.0_rp
      do c = 1, mesh%cell_map%n_owned
        call pp%add_value(c, c, self%vol(c) * self%inv_m(mesh%cell_region(c)))
        call add_jumps(self, mesh, c, pp)
      end do
      call pp%finalize_assembly()
    end associate
  end subroutine pressure_block

  !> Row c (an owned cell) of the stabilization J with the weights of
  !> jump_w, added to m (on a pattern with the cells sharing a face).
  subroutine add_jumps(self, mesh, c, m)
    type(poromechanics_t), intent(in) :: self
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

  !> Assemble the block system and right-hand side of the step to the new
  !> time t_new with gamma = dt (0: undrained step), from the state x_old.
  !> Boundary histories are evaluated at t_new. Collective.
  subroutine assemble(self, mesh, t_new, dt, status)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: t_new, dt
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: u_old(:), q_loc(:), rhs_u(:), p_old(:)
    real(rp) :: xe(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det, qe(24), ae(6, 6), be(6), b
    integer(ip) :: c, a, q, j, dofs(24), faces(6), r, nu, nq, i, f, u0, u1, q0, q1, p0, p1
    logical :: matrix, weights, moved, fluxed

    ! the matrix once (it does not change but for dt B and the stabilization
    ! of an adaptive size); the right-hand side always
    matrix = .not. self%matrix_ready
    if (matrix) call self%sys%zero()
    weights = jump_factor(self, dt)
    call self%sys%block_range(iu, u0, u1)
    call self%sys%block_range(iq, q0, q1)
    call self%sys%block_range(ipr, p0, p1)
    ! mechanics: K and f with the displacement conditions
    call self%mech%set_time(t_new)
    allocate(rhs_u(u1 - u0 + 1))
    call self%mech%assemble_into(mesh, 1.0_rp, self%sys%a(iu, iu), rhs_u, rhs_only=.not. matrix)
    self%rhs = 0.0_rp
    self%rhs(u0:u1) = rhs_u
    ! previous displacement with ghosts (for the eliminated columns of Q^T)
    nu = self%mech%u%n_local()
    allocate(u_old(nu))
    u_old = 0.0_rp
    u_old(1:self%mech%u%n_owned()) = self%x_old(u0:u1)
    call self%mech%u%map%import(u_old)
    nq = self%qd%n_local()
    allocate(q_loc(nq))
    q_loc = 0.0_rp
    allocate(p_old(self%pd%n_local()))
    p_old = 0.0_rp
    p_old(1:self%pd%n_owned()) = self%x_old(p0:p1)
    call self%pd%map%import(p_old)

    call gauss_hex(2_ip, xi, w)
    do c = 1, mesh%cell_map%n_owned
      xe = mesh%coords(:, mesh%cell_nodes(:, c))
      r = mesh%cell_region(c)
      b = self%biot(r)
      do a = 1, 8
        dofs(3*a-2:3*a) = self%mech%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
      end do
      ! Q_e = b int grad N (for the matrix, or the columns of the known
      ! displacements that change over the step)
      moved = .false.
      do j = 1, 24
        if (self%mech%fixed(dofs(j))) moved = moved .or. self%mech%prescribed_value(dofs(j)) /= u_old(dofs(j))
      end do
      if (matrix .or. moved) then
        qe = 0.0_rp
        do q = 1, 8
          call hex_gradients(xe, xi(:, q), n, g, det)
          do a = 1, 8
            qe(3*a-2:3*a) = qe(3*a-2:3*a) + b * g(:, a) * det * w(q)
          end do
        end do
        do j = 1, 24
          if (self%mech%fixed(dofs(j))) then
            ! known displacement: Q^T column to the right-hand side (its change over the step)
            if (moved) self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) - qe(j) * (self%mech%prescribed_value(dofs(j)) - &
                                                                        u_old(dofs(j)))
          else if (matrix) then
            call self%sys%a(iu, ipr)%add_value(dofs(j), c, -qe(j))
            call self%sys%a(ipr, iu)%add_value(c, dofs(j), qe(j))
          end if
        end do
      end if
      ! Darcy: A_e and B_e in the global face orientation (for the matrix,
      ! or the columns of nonzero prescribed fluxes)
      faces = mesh%cell_faces(:, c)
      fluxed = .false.
      do j = 1, 6
        if (self%q_fixed(faces(j))) fluxed = fluxed .or. flux_value(faces(j)) /= 0.0_rp
      end do
      if (matrix .or. fluxed) then
        call rt0_cell_mass(xe, self%kinv(:, :, r), ae, status)
        if (.not. status%ok()) return
        call rt0_cell_divergence(xe, be, status)
        if (.not. status%ok()) return
        call rt0_orient(mesh%cell_face_sign(:, c), ae)
        call rt0_orient(mesh%cell_face_sign(:, c), be)
      end if
      do j = 1, 6
        f = faces(j)
        if (self%q_fixed(f)) then
          if (.not. fluxed) cycle
          do i = 1, 6
            if (.not. self%q_fixed(faces(i))) q_loc(faces(i)) = q_loc(faces(i)) - ae(i, j) * flux_value(f)
          end do
          self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) - dt * be(j) * flux_value(f)
          cycle
        end if
        if (matrix) then
          do i = 1, 6
            if (.not. self%q_fixed(faces(i))) call self%sys%a(iq, iq)%add_value(faces(i), f, ae(i, j))
          end do
          call self%sys%a(iq, ipr)%add_value(f, c, -be(j))
          call self%sys%a(ipr, iq)%add_value(c, f, be(j))      ! B; dt B below
        end if
        if (self%p_face(f)) q_loc(f) = q_loc(f) - self%p_bc(f) * self%bcs(self%face_bc(f))%factor(t_new)
      end do
      ! sources; the pressure-jump stabilization on the pressure increment
      ! (the storage and J of the (p, p) block: pressure_block)
      self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + dt * self%src_rate(r) * self%vol(c)
      do j = 1, 6
        f = faces(j)
        if (self%jump_w(f) == 0.0_rp) cycle
        i = mesh%face_cells(1, f)
        if (i == c) i = mesh%face_cells(2, f)
        self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + self%jump_w(f) * (p_old(c) - p_old(i))
      end do
    end do
    if (matrix) then
      call self%sys%finalize_assembly()
      self%pq_unit = self%sys%a(ipr, iq)%val
      self%matrix_ready = .true.
    end if
    if (weights .or. matrix) call pressure_block(self, mesh)
    self%sys%a(ipr, iq)%val = dt * self%pq_unit
    ! pressure faces appear once (one cell), counted above only for owned cells
    call self%qd%map%export_add(q_loc)
    self%rhs(q0:q1) = q_loc(1:self%qd%n_owned())

    call prescribed_flux_rows(self, t_new, q0)
    call old_state_and_norms(self, mesh, u0, u1, p0, p1)
  contains
    !> Prescribed flux through local face f at t_new [m^3/s].
    real(rp) function flux_value(f)
      integer(ip), intent(in) :: f
      flux_value = prescribed_flux(self, f, t_new)
    end function flux_value
  end subroutine assemble

  !> Prescribed flux through local face f at time t [m^3/s].
  real(rp) function prescribed_flux(self, f, t)
    type(poromechanics_t), intent(in) :: self
    integer(ip), intent(in) :: f
    real(rp), intent(in) :: t
    prescribed_flux = self%q_value(f)
    if (self%face_bc(f) > 0) prescribed_flux = prescribed_flux * self%bcs(self%face_bc(f))%factor(t)
  end function prescribed_flux

  !> Rows of prescribed fluxes: a scaled identity (the mean diagonal of the
  !> free rows of A) with the flux at t_new on the right-hand side.
  !> Collective.
  subroutine prescribed_flux_rows(self, t_new, q0)
    type(poromechanics_t), intent(inout) :: self
    real(rp), intent(in) :: t_new
    integer(ip), intent(in) :: q0
    real(rp) :: dsum, dcount
    integer(ip) :: f, k
    dsum = 0.0_rp
    dcount = 0.0_rp
    do f = 1, self%qd%n_owned()
      if (self%q_fixed(f)) cycle
      k = self%sys%a(iq, iq)%find(f, f)
      dsum = dsum + self%sys%a(iq, iq)%val(k)
      dcount = dcount + 1.0_rp
    end do
    dsum = self%qd%map%comm%sum(dsum)
    dcount = self%qd%map%comm%sum(dcount)
    self%a_scale = 1.0_rp
    if (dcount > 0.0_rp) self%a_scale = dsum / dcount
    do f = 1, self%qd%n_owned()
      if (.not. self%q_fixed(f)) cycle
      k = self%sys%a(iq, iq)%find(f, f)
      self%sys%a(iq, iq)%val(k) = self%a_scale
      self%rhs(q0 + f - 1) = self%a_scale * prescribed_flux(self, f, t_new)
    end do
  end subroutine prescribed_flux_rows

  !> The previous state's terms of the mass balance (Q^T u_old on the free
  !> columns, P p_old) and the row norms of A (for the scaled-Laplacian
  !> Schur approximation, ghosts imported). Collective.
  subroutine old_state_and_norms(self, mesh, u0, u1, p0, p1)
    type(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: u0, u1, p0, p1
    real(rp), allocatable :: tmp(:)
    integer(ip) :: c, f
    allocate(tmp(p1 - p0 + 1))
    call self%sys%apply_block(ipr, iu, self%x_old(u0:u1), tmp)
    self%rhs(p0:p1) = self%rhs(p0:p1) + tmp
    do c = 1, mesh%cell_map%n_owned
      self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + self%vol(c) * self%inv_m(mesh%cell_region(c)) * &
                             self%x_old(p0 + c - 1)
    end do
    self%a_norm = 0.0_rp
    do f = 1, self%qd%n_owned()
      associate (am => self%sys%a(iq, iq))
        self%a_norm(f) = norm2(am%val(am%row_ptr(f):am%row_ptr(f+1)-1))
      end associate
    end do
    call self%qd%map%import(self%a_norm)
  end subroutine old_state_and_norms

  !> The explicit approximation of the pressure Schur complement
  !>   S = P + S_K + dt S_A,  S_K = diag(b^2 |c| / K_dr) (fixed stress),
  !>   S_A = B^T diag(a)^-1 B with a_f = ||A(f,:)||_2 (scaled Laplacian),
  !> on the pattern of the pressure block. Call after assemble. Collective.
  subroutine fixed_stress_schur(self, mesh, dt, s)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: dt
    type(csr_matrix_t), intent(inout) :: s
    integer(ip) :: c, j, f, r, other
    real(rp) :: sgn_c, sgn_o
    associate (pp => self%sys%a(ipr, ipr))
      if (.not. allocated(s%val)) call s%init(pp%row_map, pp%col_map, pp%row_ptr, pp%col)
    end associate
    call s%zero()
    do c = 1, mesh%cell_map%n_owned
      r = mesh%cell_region(c)
      call s%add_value(c, c, self%vol(c) * (self%inv_m(r) + self%biot(r)**2 / self%kdr(r)))
      call add_jumps(self, mesh, c, s)
      if (dt <= 0.0_rp) cycle
      do j = 1, 6
        f = mesh%cell_faces(j, c)
        if (self%q_fixed(f)) cycle
        call s%add_value(c, c, dt / self%a_norm(f))
        other = mesh%face_cells(1, f)
        if (other == c) other = mesh%face_cells(2, f)
        if (other == 0 .or. mesh%face_on_boundary(f)) cycle
        sgn_c = real(mesh%cell_face_sign(j, c), rp)
        sgn_o = -sgn_c
        call s%add_value(c, other, dt * sgn_c * sgn_o / self%a_norm(f))
      end do
    end do
    call s%finalize_assembly()
  end subroutine fixed_stress_schur

  !> The pressure Schur complement approximated with the algebraic
  !> generalization of fixed stress (Ferronato, Franceschini, Janna,
  !> Castelletto and Tchelepi, J. Comput. Phys. 398 (2019)): S_K is replaced by
  !> Q^T diag(K)^-1 Q instead of the per-cell b^2 |c| / K_dr, so that it sees
  !> the actual stiffness and boundary conditions; S = P + J + Q^T diag(K)^-1 Q
  !> + dt S_A, on the pattern of cells sharing a node. Call after assemble.
  !> Collective.
  subroutine algebraic_schur(self, mesh, dt, s)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: dt
    type(csr_matrix_t), intent(inout) :: s
    integer(ip), allocatable :: node_cells(:,:), cnt(:), row_ptr(:), col(:)
    real(rp), allocatable :: qc(:,:), dk(:)
    real(rp) :: xe(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det
    integer(ip) :: c, a, k, q, i, nd, c2, a2, j, f, other, r, u0, u1
    ! Q of every local cell, and the cells around each local node
    call gauss_hex(2_ip, xi, w)
    allocate(qc(24, mesh%n_cells), cnt(mesh%n_nodes))
    cnt = 0
    do c = 1, mesh%n_cells
      cnt(mesh%cell_nodes(:, c)) = cnt(mesh%cell_nodes(:, c)) + 1
    end do
    allocate(node_cells(maxval(cnt), mesh%n_nodes))
    node_cells = 0
    cnt = 0
    do c = 1, mesh%n_cells
      xe = mesh%coords(:, mesh%cell_nodes(:, c))
      qc(:, c) = 0.0_rp
      do q = 1, 8
        call hex_gradients(xe, xi(:, q), n, g, det)
        do a = 1, 8
          qc(3*a-2:3*a, c) = qc(3*a-2:3*a, c) + self%biot(mesh%cell_region(c)) * g(:, a) * det * w(q)
        end do
      end do
      do a = 1, 8
        nd = mesh%cell_nodes(a, c)
        cnt(nd) = cnt(nd) + 1
        node_cells(cnt(nd), nd) = c
      end do
    end do
    if (.not. allocated(s%val)) then
      call element_pattern(mesh%cell_map%n_owned, node_cells, node_cells, 1_ip, 1_ip, row_ptr, col)
      call s%init(self%pd%map, self%pd%map, row_ptr, col)
    end if
    ! diagonal of K on every local dof
    allocate(dk(self%mech%u%n_local()))
    dk = 1.0_rp
    call self%sys%block_range(iu, u0, u1)
    call self%sys%a(iu, iu)%diagonal(dk(1:u1 - u0 + 1))
    call self%mech%u%map%import(dk)
    call s%zero()
    do c = 1, mesh%cell_map%n_owned
      r = mesh%cell_region(c)
      call s%add_value(c, c, self%vol(c) * self%inv_m(r))
      do a = 1, 8
        nd = mesh%cell_nodes(a, c)
        do k = 1, cnt(nd)
          c2 = node_cells(k, nd)
          a2 = findloc(mesh%cell_nodes(:, c2), nd, dim=1)
          do i = 1, 3
            j = self%mech%u%dof(nd, i)
            if (self%mech%fixed(j)) cycle
            call s%add_value(c, c2, qc(3*(a-1)+i, c) * qc(3*(a2-1)+i, c2) / dk(j))
          end do
        end do
      end do
      call add_jumps(self, mesh, c, s)
      do j = 1, 6
        f = mesh%cell_faces(j, c)
        if (dt <= 0.0_rp .or. self%q_fixed(f)) cycle
        other = mesh%face_cells(1, f)
        if (other == c) other = mesh%face_cells(2, f)
        call s%add_value(c, c, dt / self%a_norm(f))
        if (other == 0 .or. mesh%face_on_boundary(f)) cycle
        call s%add_value(c, other, -dt / self%a_norm(f))
      end do
    end do
    call s%finalize_assembly()
  end subroutine algebraic_schur

  !> Darcy velocity at the centre of each owned cell [m/s] from the fluxes
  !> q_loc (all local faces, ghosts up to date).
  subroutine cell_velocity(self, mesh, q_loc, v)
    class(poromechanics_t), intent(in) :: self
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

  subroutine free(self)
    class(poromechanics_t), intent(inout) :: self
    call self%sys%free()
    call self%mech%free()
    call self%qd%free()
    call self%pd%free()
    if (allocated(self%rhs)) deallocate(self%rhs, self%x, self%x_old)
    if (allocated(self%biot)) deallocate(self%biot, self%inv_m, self%kdr, self%kinv)
    if (allocated(self%vol)) deallocate(self%vol)
    if (allocated(self%src_rate)) deallocate(self%src_rate)
    if (allocated(self%q_fixed)) deallocate(self%q_fixed, self%q_value, self%p_face, self%p_bc, self%face_bc)
    if (allocated(self%bcs)) deallocate(self%bcs)
    if (allocated(self%a_norm)) deallocate(self%a_norm)
    if (allocated(self%jump_w)) deallocate(self%jump_w, self%jump_full, self%jump_r0, self%jump_fo)
    self%matrix_ready = .false.
  end subroutine free
end module poromechanics
