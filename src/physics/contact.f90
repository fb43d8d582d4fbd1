!> Frictional contact on faults and fractures: Q1 displacements with split
!> nodes on the faults, one traction vector per interface element (P0, in the
!> element's local frame: normal, two tangential components) as Lagrange
!> multiplier, Coulomb friction with cohesion, and the algebraic
!> stabilization H_t of Franceschini, Castelletto, White and Tchelepi (CMAME
!> 368 (2020) 113161) that the Q1-P0 pair needs.
!>
!> Unknowns and equations (block system, u and t in the order chosen at init):
!>   K u + C1 (t - t_p) = f                         momentum
!>   r_t(u, t) = 0, per element and by status:       contact
!>     stick: A g_N = 0 and A (g_T - g_T^n) = 0, each stabilized: - H v
!>     slip : A g_N - H v = 0 (normal only) and -s (t_T - tau(t_N) d) = 0,
!>            tau = c - tan(phi) t_N, d the unit direction of the slip
!>            increment g_T - g_T^n (of t_T while that is zero)
!>     open : -s t = 0
!> with g = R [[u]] the mean jump across the element in its frame ([[u]] =
!> u_plus - u_minus, so g_N > 0 opens), A the area, t the traction on the
!> minus side (t_N < 0 in compression), t_p = (p, 0, 0) the prescribed fluid
!> pressure p on the faces, v = (t_N, t_T - t_T^n) and s a per-element scale
!> (the diagonal of C2 diag(K)^-1 C1) that keeps the open and slip rows in
!> proportion with the others. C1 = integral of [[N]]^T R^T; for stick rows
!> the Jacobian block C2 is C1^T, so the stick problem is the symmetric
!> saddle point [K C1; C1^T -H_t].
!>
!> H_t: for every edge shared by two interface elements e1, e2 of a fault,
!>   M = sum over the edge's split nodes of w1 w2 diag(1/K_minus + 1/K_plus),
!> where w are the nodal areas of the node in the two elements and K_side the
!> diagonal stiffness of the node from the two cells of that side (the
!> macro-element of the two elements), and H gets R1 M R1^T, R2 M R2^T on the
!> diagonal and -sigma R1 M R2^T off it (sigma = -1 when the two elements see
!> the fault from opposite sides). Only the constrained components take part:
!> three for stick, the normal one for slip, none for open. This follows the
!> paper's macro-element argument (the jump of the multipliers between
!> neighbours is penalized by the local Schur complement) with the exact
!> element-stiffness diagonals in place of its closed-form estimate.
!>
!> Space 'bubble' (init with bubble = .true.): the displacement field also
!> has a face bubble in the cell on each side of every element
!> (face_bubbles.f90, elasticity's enriched cells), which makes the P0
!> tractions inf-sup stable. The jump operator gets the bubbles' columns
!> (+-wb R, wb the integral of the bubble over the face), so C1, C2, the
!> mean jumps and the row scales s include them, and H_t is left out: the
!> stick problem is the pure saddle point [K C1; C1^T 0].
!>
!> Newton's method works on increments: the prescribed displacements are
!> imposed at the start of every load step, so the Jacobian's columns of
!> prescribed dofs are zero.
!>
!> With the fluid (init with fcfg: physics 'fracture_flow') a third block p
!> holds one pressure per element: the faces carry t - p n (Q1 = -C1 normal,
!> t stays the effective traction of the contact conditions) and the mass
!> rows of assemble_mass_rows close the system (fracture_flow.f90 for the
!> cubic-law transmissibilities).
module contact
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use dist_mesh, only: dist_mesh_t
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use elasticity, only: elasticity_t
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use fault_config, only: fault_config_t
  use interface_element, only: interface_geometry, face_bubble_integral
  use face_bubbles, only: face_bubbles_t
  use fault_edges, only: fault_edges_t
  use fracture_flow, only: fracture_flow_t
  use flow_config, only: flow_config_t, well_config_t, pressure_bc_t
  use fracture_wells, only: well_links_t
  use dist_vector, only: pnorm2
  implicit none
  private

  public :: contact_t, state_stick, state_slip, state_open, state_names, max_flips

  integer, parameter :: state_stick = 1, state_slip = 2, state_open = 3
  character(len=5), parameter :: state_names(3) = ['stick', 'slip ', 'open ']
  !> status changes of one element in a step before it is held (update_states)
  integer, parameter :: max_flips = 4
  real(rp), parameter :: deg = acos(-1.0_rp) / 180.0_rp
  !> columns of an element's jump operator: 4 + 4 nodes and (space 'bubble')
  !> the bubbles of its two sides, 3 components each (unused ones: dof 0)
  integer(ip), parameter :: nju = 30

  type :: contact_t
    type(elasticity_t) :: mech
    type(dof_map_t) :: t                           !< 3 traction components per interface element
    type(block_matrix_t) :: sys                    !< Jacobian
    integer :: bu = 1, bt = 2                      !< block indices of u and t
    logical :: stabilized = .true.
    !> space 'bubble': the fault cells' face bubbles enrich u (no H_t then)
    logical :: bubble = .false.
    type(face_bubbles_t) :: bub
    real(rp), allocatable :: wb(:)                 !< (n) integral of a bubble over the element [m^2]
    real(rp), allocatable :: x(:)                  !< current state, owned block vector [m, Pa]
    real(rp), allocatable :: rhs(:)                !< -residual, owned block vector
    real(rp), allocatable :: f_u(:)                !< load of the momentum rows (prescribed dofs lifted)
    real(rp), allocatable :: u(:)                  !< local displacement (owned + ghosts) [m]
    ! per local interface element
    real(rp), allocatable :: area(:), wn(:,:), rot(:,:,:)  !< [m^2], (4,n) nodal areas, (3,3,n) frame rows
    real(rp), allocatable :: s(:)                  !< scale of the open and slip rows [m^3/Pa]
    real(rp), allocatable :: fric(:), coh(:), pres(:)      !< tan(phi), cohesion [Pa], fluid pressure [Pa]
    integer, allocatable :: fault(:)               !< index of the element's fault in faults(:)
    integer, allocatable :: state(:)
    integer, allocatable :: flips(:)               !< status changes of the element in this step (any)
    logical, allocatable :: fresh(:)               !< slipping since the last status update (was stick)
    logical, allocatable :: slipped(:)             !< slip at the step's start or at an update of the step
    integer(gp), allocatable :: held(:)            !< per fault (of faults(:)): elements held in their status at the last update
    integer(gp), allocatable :: held_open(:)       !< the same, held between open and closed
    real(rp) :: held_excess = 0.0_rp               !< largest violation of a held element's status at the last update
                                                   !< (a traction over the largest, or an overlap over the largest jump)
    real(rp), allocatable :: trac(:,:), trac_step(:,:)     !< (3,n) local-frame traction [Pa]
    real(rp), allocatable :: jump(:,:), jump_step(:,:)     !< (3,n) local-frame mean jump [m]
    ! stabilization edges
    type(fault_edges_t) :: edges                   !< neighbouring elements (fault_edges)
    real(rp), allocatable :: eb(:,:,:,:)           !< (3,3,3,edges%n): blocks 11, 12, 22
    real(rp) :: length = 1.0_rp                    !< mesh size scale [m] (sqrt of the mean element area)
    type(fault_config_t), allocatable :: faults(:)
    integer :: fault_of_set = 0
    ! fluid in the fractures (physics 'fracture_flow', flow = .true.): one
    ! pressure per element in block bp, the faces carry t - p n
    logical :: flow = .false.
    integer :: bp = 3                              !< block index of p
    type(dof_map_t) :: pd                          !< 1 pressure per interface element
    type(fracture_flow_t) :: ff                    !< cubic-law transmissibilities
    real(rp), allocatable :: p(:), p_step(:)       !< (pressure map's local) fluid pressure now and at the step's start [Pa]
    real(rp), allocatable :: gn_step(:)            !< (n) normal jump at the step's start [m]
    type(well_links_t) :: wl                       !< the wells' connections and rates
    integer, allocatable :: pfix(:)                !< (n) the &fracture_pressure of an element, 0: none
    real(rp), allocatable :: p_fixed(:)            !< (n) its prescribed pressure in the step [Pa]
    real(rp) :: dt = 1.0_rp                        !< time step [s]
    real(rp) :: cf = 0.0_rp                        !< fluid compressibility [1/Pa]
    ! the magnitudes the residual's rows balance, at the last assembly
    ! (field_residuals): the momentum's largest force vector [N], per mass
    ! row the sum of its terms' absolute values [m^3] (0 on rows that hold a
    ! pressure rather than balance a mass)
    real(rp) :: force_ref = 0.0_rp
    real(rp), allocatable :: mass_mag(:)
    ! the round-off of evaluating those rows: per row the sum of the
    ! absolute values of its terms' operands (|K| |u| and the like), whose
    ! eps multiple is the least residual double precision can show
    real(rp) :: force_noise = 0.0_rp
    real(rp), allocatable :: mass_noise(:)
  contains
    procedure :: init
    procedure :: assemble_stiffness
    procedure :: assemble_newton
    procedure :: take_solution
    procedure :: update_states
    procedure :: begin_step
    procedure :: count_states
    procedure :: ht_diagonal
    procedure :: tip_skew
    procedure :: nodal_u
    procedure :: begin_flow_step
    procedure :: field_residuals
    procedure :: free
  end type contact_t

contains

  !> Fields, patterns, geometry and stabilization of the faults of mesh.
  !> t_first puts the tractions in block 1 (the reordered preconditioner);
  !> p_second (with the fluid) the pressure in block 2, the displacement
  !> last (the pressure eliminated with the tractions). Collective.
  subroutine init(self, mesh, mats, bcs, faults, stabilized, t_first, status, fcfg, wells, pbcs, p_second, bubble)
    class(contact_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(material_config_t), intent(in) :: mats(:)
    type(boundary_config_t), intent(in) :: bcs(:)
    type(fault_config_t), intent(in) :: faults(:)
    logical, intent(in) :: stabilized, t_first
    type(error_status_t), intent(inout) :: status
    type(flow_config_t), intent(in), optional :: fcfg     !< with the fluid: physics 'fracture_flow'
    type(well_config_t), intent(in), optional :: wells(:)
    type(pressure_bc_t), intent(in), optional :: pbcs(:)
    logical, intent(in), optional :: p_second
    logical, intent(in), optional :: bubble        !< the face-bubble space (stabilized must be .false.)
    integer(ip), allocatable :: row_ptr(:), col(:), conn8(:,:), self_conn(:,:), pairs(:,:)
    integer(ip) :: e, n, f, nown, s

    call self%free()
    if (present(bubble)) self%bubble = bubble
    if (self%bubble) then
      call self%bub%build(mesh)
      call self%mech%init(mesh, mats, bcs, status, self%bub)
    else
      call self%mech%init(mesh, mats, bcs, status)
    end if
    if (.not. status%ok()) return
    call self%mech%k%free()                       ! the block system holds K
    self%stabilized = stabilized
    self%faults = faults
    if (t_first) then
      self%bt = 1
      self%bu = 2
    end if
    if (present(fcfg) .and. present(p_second)) then
      if (p_second) then
        self%bt = 1
        self%bp = 2
        self%bu = 3
      end if
    end if
    n = mesh%n_ifaces
    call self%t%init('traction', mesh%iface_map, 3_ip)
    nown = mesh%iface_map%n_owned
    ! the displacement entities of each element (dof_map's entity numbers):
    ! 4 + 4 nodes, then its bubbles (0: none)
    allocate(conn8(10, n), self_conn(1, n))
    conn8 = 0
    do e = 1, n
      conn8(1:4, e) = self%mech%u%entity(mesh%iface_nodes(:, 1, e))
      conn8(5:8, e) = self%mech%u%entity(mesh%iface_nodes(:, 2, e))
      if (self%bubble) then
        do s = 1, 2
          conn8(8 + s, e) = self%mech%u%extra_entity(self%bub%of_iface(s, e))
        end do
      end if
      self_conn(1, e) = e
    end do

    call geometry(self, mesh)
    call self%edges%build(mesh)
    call edge_blocks(self, mesh)

    self%flow = present(fcfg)
    if (self%flow) then
      ! a well's connections couple their elements: the pressure map has the
      ! others as ghosts on a rank that owns one
      call self%wl%locate(mesh, wells, status)
      if (.not. status%ok()) return
      call self%pd%init('pressure', mesh%iface_map, 1_ip, self%wl%extra_ghosts(mesh))
      call self%wl%set_local(self%pd%map)
    end if
    block
      integer(ip) :: no(merge(3, 2, self%flow))
      no(self%bu) = self%mech%u%n_owned()
      no(self%bt) = self%t%n_owned()
      if (self%flow) no(self%bp) = self%pd%n_owned()
      call self%sys%init(no)
    end block
    associate (umap => self%mech%u%map, tmap => self%t%map, bu => self%bu, bt => self%bt)
      call self%mech%stiffness_pattern(mesh, row_ptr, col)
      call self%sys%set_pattern(bu, bu, umap, umap, row_ptr, col)
      call element_pattern(umap%n_owned / 3, conn8, self_conn, 3_ip, 3_ip, row_ptr, col)
      call self%sys%set_pattern(bu, bt, umap, tmap, row_ptr, col)
      call element_pattern(nown, self_conn, conn8, 3_ip, 3_ip, row_ptr, col)
      call self%sys%set_pattern(bt, bu, tmap, umap, row_ptr, col)
      allocate(pairs(2, n + self%edges%n))
      pairs(:, 1:n) = spread(self_conn(1, :), 1, 2)
      pairs(:, n+1:) = self%edges%pair
      call element_pattern(nown, pairs, pairs, 3_ip, 3_ip, row_ptr, col)
      call self%sys%set_pattern(bt, bt, tmap, tmap, row_ptr, col)
    end associate
    call assemble_c1(self, mesh)
    if (self%flow) call flow_init(self, mesh, conn8(1:8, :), self_conn, fcfg, wells, pbcs)

    ! fault properties and initial state
    allocate(self%fric(n), self%coh(n), self%pres(n), self%state(n), self%fault(n), self%flips(n), self%fresh(n), &
             self%slipped(n))
    self%flips = 0
    self%fresh = .false.
    self%slipped = .false.
    do e = 1, n
      f = fault_index(self, mesh, mesh%iface_fault(e))
      self%fault(e) = f
      if (f == 0) then
        call status%set("fault '"//trim(mesh%fault_names(mesh%iface_fault(e)))//"' of the mesh has no &fault group")
        return
      end if
      self%fric(e) = tan(faults(f)%friction_angle * deg)
      self%coh(e) = faults(f)%cohesion
      self%pres(e) = 0.0_rp
      self%state(e) = state_stick
      if (faults(f)%initial_state == 'open') self%state(e) = state_open
    end do
    allocate(self%trac(3, n), self%trac_step(3, n), self%jump(3, n), self%jump_step(3, n))
    self%trac = 0.0_rp
    self%trac_step = 0.0_rp
    self%jump = 0.0_rp
    self%jump_step = 0.0_rp
    allocate(self%x(self%sys%offset(self%sys%nb + 1)), self%rhs(self%sys%offset(self%sys%nb + 1)))
    self%x = 0.0_rp
    if (self%flow) then
      block
        integer(ip) :: p0, p1
        call self%sys%block_range(self%bp, p0, p1)
        self%x(p0:p1) = fcfg%initial_pressure
      end block
    end if
    allocate(self%u(self%mech%u%n_local()), self%f_u(self%mech%u%n_owned()))
    self%u = 0.0_rp
  end subroutine init

  integer function fault_index(self, mesh, mf)
    type(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: mf
    integer :: f
    fault_index = 0
    do f = 1, size(self%faults)
      if (self%faults(f)%name == mesh%fault_names(mf)) fault_index = f
    end do
  end function fault_index

  !> Area, nodal areas and frame of every local element; the mesh size scale.
  subroutine geometry(self, mesh)
    type(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip) :: e, n, nown
    real(rp) :: a_sum, n_sum
    type(parallel_comm_t) :: comm
    n = mesh%n_ifaces
    allocate(self%area(n), self%wn(4, n), self%rot(3, 3, n), self%wb(n))
    do e = 1, n
      call interface_geometry(mesh%coords(:, mesh%iface_nodes(:, 1, e)), self%area(e), self%wn(:, e), self%rot(:, :, e))
      self%wb(e) = face_bubble_integral(mesh%coords(:, mesh%iface_nodes(:, 1, e)))
    end do
    comm = mesh%comm
    nown = mesh%iface_map%n_owned
    a_sum = comm%sum(sum(self%area(1:nown)))
    n_sum = comm%sum(real(nown, rp))
    if (n_sum > 0.0_rp) self%length = sqrt(a_sum / n_sum)
  end subroutine geometry

  !> The 3x3 blocks of H_t of every edge (see the module header).
  subroutine edge_blocks(self, mesh)
    type(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: kd(:,:)
    logical, allocatable :: done(:)
    real(rp) :: mm(3, 3), inv(3), kdm(3), kdp(3), sigma
    integer(ip) :: ed, e1, e2, q, k1, k2, nm, np, cm(2), cp(2), ks(2)
    logical :: found
    allocate(self%eb(3, 3, 3, self%edges%n))
    allocate(kd(24, mesh%n_cells), done(mesh%n_cells))
    done = .false.
    do ed = 1, self%edges%n
      e1 = self%edges%pair(1, ed)
      e2 = self%edges%pair(2, ed)
      mm = 0.0_rp
      sigma = 0.0_rp
      ks = pack([1_ip, 2_ip, 3_ip, 4_ip], self%edges%of_elem(:, e1) == ed, [0_ip, 0_ip])
      do q = 0, 1
        k1 = mod(ks(1) - 1 + q, 4) + 1
        nm = mesh%iface_nodes(k1, 1, e1)
        np = mesh%iface_nodes(k1, 2, e1)
        if (nm == np) cycle                            ! a tip: no jump there
        found = .false.
        do k2 = 1, 4
          if (mesh%iface_nodes(k2, 1, e2) == nm) then
            found = .true.
            if (sigma == 0.0_rp) sigma = 1.0_rp
            cm = [mesh%iface_cells(1, e1), mesh%iface_cells(1, e2)]
            cp = [mesh%iface_cells(2, e1), mesh%iface_cells(2, e2)]
            exit
          else if (mesh%iface_nodes(k2, 2, e2) == nm) then
            found = .true.
            if (sigma == 0.0_rp) sigma = -1.0_rp
            cm = [mesh%iface_cells(1, e1), mesh%iface_cells(2, e2)]
            cp = [mesh%iface_cells(2, e1), mesh%iface_cells(1, e2)]
            exit
          end if
        end do
        if (.not. found) cycle                         ! a junction of faults
        kdm = node_diag(cm(1), nm) + node_diag(cm(2), nm)
        kdp = node_diag(cp(1), np) + node_diag(cp(2), np)
        inv = 1.0_rp / kdm + 1.0_rp / kdp
        mm(1, 1) = mm(1, 1) + self%wn(k1, e1) * self%wn(k2, e2) * inv(1)
        mm(2, 2) = mm(2, 2) + self%wn(k1, e1) * self%wn(k2, e2) * inv(2)
        mm(3, 3) = mm(3, 3) + self%wn(k1, e1) * self%wn(k2, e2) * inv(3)
      end do
      associate (r1 => self%rot(:, :, e1), r2 => self%rot(:, :, e2))
        self%eb(:, :, 1, ed) = matmul(r1, matmul(mm, transpose(r1)))
        self%eb(:, :, 2, ed) = -sigma * matmul(r1, matmul(mm, transpose(r2)))
        self%eb(:, :, 3, ed) = matmul(r2, matmul(mm, transpose(r2)))
      end associate
      ! only the local frames' own components: the stick rows measure the
      ! normal traction whole and the tangential one from the step's start,
      ! so a normal-tangential coupling (mm is not isotropic, and a fault
      ! that is not along an axis rotates it into one) made the normal row
      ! of a step's start differ from the end of the step before by H_NT
      ! times the tangential change of that step: a dipping fault under an
      ! in-situ shear drifted by 1.6 % of its displacement per unloaded step
      do q = 1, 3
        self%eb(:, :, q, ed) = diag3(self%eb(:, :, q, ed))
      end do
    end do
  contains
    !> The diagonal of a 3 x 3 block, as a block.
    pure function diag3(a) result(b)
      real(rp), intent(in) :: a(3, 3)
      real(rp) :: b(3, 3)
      b = 0.0_rp
      b(1, 1) = a(1, 1)
      b(2, 2) = a(2, 2)
      b(3, 3) = a(3, 3)
    end function diag3
    !> Diagonal stiffness (x, y, z) of node nd from cell c alone.
    function node_diag(c, nd) result(v)
      integer(ip), intent(in) :: c, nd
      real(rp) :: v(3), ke(24, 24)
      integer(ip) :: a, i
      if (.not. done(c)) then
        call self%mech%element_stiffness(mesh, c, ke)
        kd(:, c) = [(ke(i, i), i = 1, 24)]
        done(c) = .true.
      end if
      v = 0.0_rp
      do a = 1, 8
        if (mesh%cell_nodes(a, c) == nd) v = kd(3*a-2:3*a, c)
      end do
    end function node_diag
  end subroutine edge_blocks

  !> The fluid's patterns, Q1 = -(normal column of C1) (the faces carry
  !> t - p n; assembled once), the transmissibility kernel, the wells'
  !> elements and the initial pressure. Collective.
  subroutine flow_init(self, mesh, conn8, self_conn, fcfg, wells, pbcs)
    type(contact_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: conn8(:,:), self_conn(:,:)
    type(flow_config_t), intent(in) :: fcfg
    type(well_config_t), intent(in) :: wells(:)
    type(pressure_bc_t), intent(in) :: pbcs(:)
    integer(ip), allocatable :: row_ptr(:), col(:), connp(:,:)
    integer(ip) :: n, e, k, ed, o, j, rows(nju)
    real(rp) :: be(3, nju)
    n = mesh%n_ifaces
    associate (umap => self%mech%u%map, pmap => self%pd%map, bu => self%bu, bp => self%bp)
      call element_pattern(mesh%node_map%n_owned, conn8, self_conn, 3_ip, 1_ip, row_ptr, col)
      call self%sys%set_pattern(bu, bp, umap, pmap, row_ptr, col)
      ! a mass row sees the nodes of its element and of its edge neighbours
      allocate(connp(40, n))
      connp = 0
      do e = 1, n
        connp(1:8, e) = conn8(:, e)
        do k = 1, 4
          ed = self%edges%of_elem(k, e)
          if (ed == 0) cycle
          o = self%edges%pair(1, ed) + self%edges%pair(2, ed) - e
          connp(8*k+1:8*k+8, e) = conn8(:, o)
        end do
      end do
      call element_pattern(mesh%iface_map%n_owned, self_conn, connp, 1_ip, 3_ip, row_ptr, col)
      call self%sys%set_pattern(bp, bu, pmap, umap, row_ptr, col)
      call self%ff%pattern(mesh, self%edges, row_ptr, col, self%wl%pairs())
      call self%sys%set_pattern(bp, bp, pmap, pmap, row_ptr, col)
    end associate
    associate (q1 => self%sys%a(self%bu, self%bp))
      call q1%zero()
      do e = 1, mesh%iface_map%n_owned
        call jump_operator(self, mesh, e, be, rows)
        do j = 1, 24
          if (self%mech%fixed(rows(j))) rows(j) = 0
        end do
        call q1%add_block(rows, [e], -transpose(be(1:1, :)))
      end do
      call q1%finalize_assembly()
    end associate
    call self%ff%init(mesh, self%edges, fcfg%viscosity, fcfg%residual_aperture)
    self%cf = fcfg%compressibility
    allocate(self%p(self%pd%n_local()), self%p_step(self%pd%n_local()), self%gn_step(n))
    self%p = fcfg%initial_pressure
    self%p_step = self%p
    self%gn_step = 0.0_rp
    ! prescribed pressures: the last &fracture_pressure whose box holds the centre wins
    allocate(self%pfix(n), self%p_fixed(n))
    self%pfix = 0
    self%p_fixed = 0.0_rp
    block
      real(rp) :: c(3)
      integer :: b
      do e = 1, n
        c = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
        do b = 1, size(pbcs)
          if (pbcs(b)%fault /= mesh%fault_names(mesh%iface_fault(e))) cycle
          if (all(c >= pbcs(b)%lower .and. c <= pbcs(b)%upper)) self%pfix(e) = b
        end do
      end do
    end block
  end subroutine flow_init

  !> Start a time step of the fluid: the step's pressure and normal jumps,
  !> dt [s] and the wells' rates at the step's end time t (implicit Euler).
  subroutine begin_flow_step(self, wells, pbcs, t, dt)
    class(contact_t), intent(inout) :: self
    type(well_config_t), intent(in) :: wells(:)
    type(pressure_bc_t), intent(in) :: pbcs(:)
    real(rp), intent(in) :: t, dt
    integer(ip) :: e
    self%dt = dt
    self%p_step = self%p
    self%gn_step = self%jump(1, :)
    do e = 1, size(self%pfix, kind=ip)
      if (self%pfix(e) > 0) self%p_fixed(e) = pbcs(self%pfix(e))%value_at(t)
    end do
    ! the equilibrium step 0 (dt = 0): nothing flows
    call self%wl%begin_step(wells, self%ff%aperture, self%ff%mu, t, dt)
  end subroutine begin_flow_step

  !> The mass rows of the fluid and their residual, per owned element e, in
  !> volumes over the step (the balance times dt, so that a step of size 0 is
  !> no division):
  !>   A (g_N - g_N^step) + A a c_f (p - p^step) + dt sum over edges T (p_e - p_o)
  !>     + (H_N (p - p^step))_e - dt q_e = 0,
  !> T from the cubic law at the current apertures (with its aperture
  !> derivatives in the u columns), c_f the fluid compressibility and H_N
  !> the normal-normal part of the traction stabilization's edge blocks: the
  !> pressure enters the momentum exactly as t_N does (Q1 = -C1 normal), so
  !> these rows give the stabilized saddle point of the contact block with
  !> -(dt T + storage + H_N) in place of -H_t. H_N acts on the pressure's
  !> increment: it vanishes at steady state and sums to zero over the
  !> fracture (mass is conserved exactly). A step of size 0 (&time undrained,
  !> the mechanical equilibrium at the start) keeps the pressure: p = p^step.
  !> Local.
  subroutine assemble_mass_rows(self, mesh)
    type(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: be(3, nju), bo(3, nju), r, dp, m_self, m_off, dt, stor
    real(rp), allocatable :: wq(:)
    integer(ip) :: e, k, ed, o, dofs(nju), dofo(nju), p0, p1
    integer :: s
    dt = self%dt
    if (.not. allocated(self%mass_mag)) allocate(self%mass_mag(mesh%iface_map%n_owned), &
                                                 self%mass_noise(mesh%iface_map%n_owned))
    self%mass_mag = 0.0_rp
    self%mass_noise = 0.0_rp
    associate (jpu => self%sys%a(self%bp, self%bu), jpp => self%sys%a(self%bp, self%bp))
      call jpu%zero()
      call jpp%zero()
      call self%sys%block_range(self%bp, p0, p1)
      do e = 1, mesh%iface_map%n_owned
        if (dt == 0.0_rp .or. self%pfix(e) > 0) then
          ! held (step 0) or prescribed: p = p^step or p = the prescribed value
          call jpp%add_value(e, e, 1.0_rp)
          self%rhs(p0 + e - 1) = -(self%p(e) - merge(self%p_fixed(e), self%p_step(e), dt > 0.0_rp))
          cycle
        end if
        call free_jump_operator(e, be, dofs)
        stor = self%area(e) * self%ff%aperture(e) * self%cf
        r = self%area(e) * (self%jump(1, e) - self%gn_step(e)) + stor * (self%p(e) - self%p_step(e))
        self%mass_mag(e) = abs(self%area(e) * (self%jump(1, e) - self%gn_step(e))) + &
                           abs(stor * (self%p(e) - self%p_step(e)))
        self%mass_noise(e) = self%area(e) * (abs(self%jump(1, e)) + abs(self%gn_step(e))) + &
                             stor * (abs(self%p(e)) + abs(self%p_step(e)))
        call jpu%add_block([e], dofs, be(1:1, :) * (1.0_rp + self%cf * (self%p(e) - self%p_step(e)) &
                                                    * self%ff%da_dg(e)))
        call jpp%add_value(e, e, stor)
        do k = 1, 4
          ed = self%edges%of_elem(k, e)
          if (ed == 0) cycle
          s = merge(1, 2, self%edges%pair(1, ed) == e)
          o = self%edges%pair(3 - s, ed)
          dp = self%p(e) - self%p(o)
          r = r + dt * self%ff%trans(ed) * dp
          self%mass_mag(e) = self%mass_mag(e) + abs(dt * self%ff%trans(ed) * dp)
          self%mass_noise(e) = self%mass_noise(e) + dt * self%ff%trans(ed) * (abs(self%p(e)) + abs(self%p(o)))
          call jpp%add_value(e, e, dt * self%ff%trans(ed))
          call jpp%add_value(e, o, -dt * self%ff%trans(ed))
          if (dp /= 0.0_rp .and. self%ff%da_dg(e) > 0.0_rp) &
            call jpu%add_block([e], dofs, dt * dp * self%ff%dtrans(s, ed) * self%ff%da_dg(e) * be(1:1, :) &
                                          / self%area(e))
          if (dp /= 0.0_rp .and. self%ff%da_dg(o) > 0.0_rp) then
            call free_jump_operator(o, bo, dofo)
            call jpu%add_block([e], dofo, dt * dp * self%ff%dtrans(3 - s, ed) * self%ff%da_dg(o) * bo(1:1, :) &
                                          / self%area(o))
          end if
          if (.not. self%stabilized) cycle
          m_self = self%eb(1, 1, merge(1, 3, s == 1), ed)
          m_off = self%eb(1, 1, 2, ed)
          call jpp%add_value(e, e, m_self)
          call jpp%add_value(e, o, m_off)
          r = r + m_self * (self%p(e) - self%p_step(e)) + m_off * (self%p(o) - self%p_step(o))
          self%mass_mag(e) = self%mass_mag(e) + abs(m_self * (self%p(e) - self%p_step(e))) + &
                             abs(m_off * (self%p(o) - self%p_step(o)))
          self%mass_noise(e) = self%mass_noise(e) + abs(m_self) * (abs(self%p(e)) + abs(self%p_step(e))) + &
                               abs(m_off) * (abs(self%p(o)) + abs(self%p_step(o)))
        end do
        self%rhs(p0 + e - 1) = -r
      end do
      ! the wells' rates (-dt q in r); their volumes count in the magnitudes
      wq = self%rhs(p0:p1)
      call self%wl%add_mass_terms(self%p, dt, dt > 0.0_rp .and. self%pfix == 0, jpp, self%rhs(p0:p1))
      self%mass_mag = self%mass_mag + abs(self%rhs(p0:p1) - wq)
      self%mass_noise = self%mass_noise + abs(self%rhs(p0:p1) - wq)
      call jpu%finalize_assembly()
      call jpp%finalize_assembly()
    end associate
  contains
    !> The jump operator of element ee with the prescribed dofs' columns zero.
    subroutine free_jump_operator(ee, b, d)
      integer(ip), intent(in) :: ee
      real(rp), intent(out) :: b(3, nju)
      integer(ip), intent(out) :: d(nju)
      integer(ip) :: j
      call jump_operator(self, mesh, ee, b, d)
      do j = 1, 24
        if (self%mech%fixed(d(j))) b(:, j) = 0.0_rp
      end do
    end subroutine free_jump_operator
  end subroutine assemble_mass_rows

  !> C1 = integral of [[N]]^T R^T over the owned elements (rows of the
  !> prescribed dofs left out). Constant: assembled once.
  subroutine assemble_c1(self, mesh)
    type(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: be(3, nju)
    integer(ip) :: e, j, rows(nju), cols(3)
    associate (c1 => self%sys%a(self%bu, self%bt))
      call c1%zero()
      do e = 1, mesh%iface_map%n_owned
        call jump_operator(self, mesh, e, be, rows)
        do j = 1, 24
          if (self%mech%fixed(rows(j))) rows(j) = 0
        end do
        cols = self%t%dof(e, [1_ip, 2_ip, 3_ip])
        call c1%add_block(rows, cols, transpose(be))
      end do
      call c1%finalize_assembly()
    end associate
  end subroutine assemble_c1

  !> be(3, nju) = C1^T block of element e (local frame rows; columns the x, y,
  !> z dofs of its 4 minus-side then 4 plus-side nodes, then with bubbles
  !> those of its minus-side and plus-side bubbles, else dof 0 and zero
  !> columns) and those dofs. A bubble's column is the integral of the
  !> bubble over the face, wb, where a node has its nodal area.
  subroutine jump_operator(self, mesh, e, be, dofs)
    type(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: e
    real(rp), intent(out) :: be(3, nju)
    integer(ip), intent(out) :: dofs(nju)
    integer(ip) :: a, s
    real(rp) :: sg
    do s = 1, 2
      sg = merge(-1.0_rp, 1.0_rp, s == 1)
      do a = 1, 4
        be(:, 12*(s-1) + 3*a-2 : 12*(s-1) + 3*a) = sg * self%wn(a, e) * self%rot(:, :, e)
        dofs(12*(s-1) + 3*a-2 : 12*(s-1) + 3*a) = self%mech%u%dof(mesh%iface_nodes(a, s, e), [1_ip, 2_ip, 3_ip])
      end do
      if (self%bubble) then
        be(:, 24 + 3*s-2 : 24 + 3*s) = sg * self%wb(e) * self%rot(:, :, e)
        dofs(24 + 3*s-2 : 24 + 3*s) = self%mech%u%extra_dof(self%bub%of_iface(s, e), [1_ip, 2_ip, 3_ip])
      else
        be(:, 24 + 3*s-2 : 24 + 3*s) = 0.0_rp
        dofs(24 + 3*s-2 : 24 + 3*s) = 0
      end if
    end do
  end subroutine jump_operator

  !> Assemble K and the momentum load at load factor lf (fault pressures at
  !> lf too); on the first call also the row scales s. Collective.
  subroutine assemble_stiffness(self, mesh, lf, time)
    class(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: lf
    real(rp), intent(in), optional :: time    !< the histories' time when it is not lf (a transient run)
    real(rp), allocatable :: d(:)
    real(rp) :: kn(2)
    integer(ip) :: e, a, s, nd
    if (present(time)) then
      call self%mech%set_time(time)
    else
      call self%mech%set_time(lf)
    end if
    call self%mech%assemble_into(mesh, lf, self%sys%a(self%bu, self%bu), self%f_u)
    do e = 1, mesh%n_ifaces
      associate (f => self%faults(self%fault(e)))
        self%pres(e) = lf * f%pressure * f%factor(lf)
      end associate
      ! the in-situ pore pressure (&geostatic water table) acts on the faces
      ! too, and so does a &pressure_change of the cells on either side
      if (self%mech%geo%on) self%pres(e) = self%pres(e) + &
        self%mech%geo%pore_pressure(sum(mesh%coords(3, mesh%iface_nodes(:, 1, e))) / 4.0_rp)
      self%pres(e) = self%pres(e) + 0.5_rp * lf * (self%mech%pressure_change_at(mesh, mesh%iface_cells(1, e)) + &
                                                   self%mech%pressure_change_at(mesh, mesh%iface_cells(2, e)))
    end do
    if (.not. allocated(self%s)) then
      allocate(d(self%mech%u%n_local()), self%s(mesh%n_ifaces))
      d = 0.0_rp
      call self%sys%a(self%bu, self%bu)%diagonal(d(1:self%mech%u%n_owned()))
      call self%mech%u%map%import(d)
      do e = 1, mesh%n_ifaces
        self%s(e) = 0.0_rp
        do a = 1, 4
          do s = 1, 2
            nd = mesh%iface_nodes(a, s, e)
            kn(s) = sum(d(self%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))) / 3.0_rp
          end do
          self%s(e) = self%s(e) + self%wn(a, e)**2 * (1.0_rp / kn(1) + 1.0_rp / kn(2))
        end do
        ! with bubbles, theirs too: s is the diagonal of C2 diag(K)^-1 C1
        if (.not. self%bubble) cycle
        do s = 1, 2
          kn(s) = sum(d(self%mech%u%extra_dof(self%bub%of_iface(s, e), [1_ip, 2_ip, 3_ip]))) / 3.0_rp
        end do
        self%s(e) = self%s(e) + self%wb(e)**2 * (1.0_rp / kn(1) + 1.0_rp / kn(2))
      end do
    end if
  end subroutine assemble_stiffness

  !> Start a load step at load factor lf: remember the tractions and jumps
  !> of the step's start (the stick and slip conditions are measured from
  !> them), impose the prescribed displacements. (A step cut goes back to
  !> the accepted state through the simulation's state record.) Collective.
  subroutine begin_step(self, lf)
    class(contact_t), intent(inout) :: self
    real(rp), intent(in) :: lf
    integer(ip) :: i, u0, u1
    self%trac_step = self%trac
    self%jump_step = self%jump
    self%flips = 0
    self%fresh = .false.
    self%slipped = self%state == state_slip
    do i = 1, self%mech%u%n_local()
      if (self%mech%fixed(i)) self%u(i) = lf * self%mech%prescribed_value(i)
    end do
    call self%sys%block_range(self%bu, u0, u1)
    self%x(u0:u1) = self%u(1:u1-u0+1)
  end subroutine begin_step

  !> The Jacobian blocks of the contact rows and rhs = -residual at the
  !> current state (x, u, trac, jump, state). Collective.
  subroutine assemble_newton(self, mesh)
    class(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: tp(:), w(:)
    real(rp) :: be(3, nju), jt(3, nju), r(3), v(3), hb(3, 3), dd(2), dg(2), tau, nrm, p2(2, 2), z(2), cz
    integer(ip) :: e, j, k, ed, o, dofs(nju), cols(3), ne, no, u0, u1, t0, t1, i
    associate (jtu => self%sys%a(self%bt, self%bu), jtt => self%sys%a(self%bt, self%bt))
      call jtu%zero()
      call jtt%zero()
      call self%sys%block_range(self%bu, u0, u1)
      call self%sys%block_range(self%bt, t0, t1)
      do e = 1, mesh%iface_map%n_owned
        call jump_operator(self, mesh, e, be, dofs)
        do j = 1, 24
          if (self%mech%fixed(dofs(j))) be(:, j) = 0.0_rp
        end do
        cols = self%t%dof(e, [1_ip, 2_ip, 3_ip])
        ne = ncon(self%state(e))
        r = 0.0_rp
        jt = 0.0_rp
        select case (self%state(e))
        case (state_stick)
          jt = be
          r(1) = self%area(e) * self%jump(1, e)
          r(2:3) = self%area(e) * (self%jump(2:3, e) - self%jump_step(2:3, e))
        case (state_slip)
          jt(1, :) = be(1, :)
          r(1) = self%area(e) * self%jump(1, e)
          ! the friction limit, zero where t_N > 0 (within status_tol) would
          ! make it negative
          tau = max(self%coh(e) - self%fric(e) * self%trac(1, e), 0.0_rp)
          dg = self%jump(2:3, e) - self%jump_step(2:3, e)
          hb = 0.0_rp
          ! semi-smooth Newton on t_T = tau z / |z|, z = t_T + c dg with
          ! c = A / s (a stiffness): the direction blends the traction and
          ! the slip increment of the step, so that a new slip element needs
          ! no special case and a small increment does not steer it (with
          ! dg, the old Newton direction, an element whose increment was
          ! still tiny reversed it and went back to stick, and the active
          ! set cycled). Before any increment of the step (dg = 0) the
          ! direction is held (jt = 0, t_T = tau t_T/|t_T|): the exact
          ! derivative there, rank one in t_T, cost the reordered
          ! preconditioner 3x its iterations. So is it in the first iteration
          ! of an element that was stick (fresh): its dg is the stick
          ! solution's stabilization allowance, |z| is about tau when the
          ! load crossed the limit gently, and the exact derivative then
          ! constrains the slip across the direction, t_T's component there a
          ! multiplier with no stabilization (Q1-P0 unstable, the count grows
          ! with refinement). Seed's nine fractures, first iteration after
          ! slip starts (step 3, Newton 2), FGMRES its at 4, 2, 1 m cells:
          ! 58, 116, 185 with the exact derivative; 26, 29, 32 held. The
          ! step may need one Newton iteration more (1 m: 8 against 7), but
          ! fewer iterations in all (2 m, step 3: 242 FGMRES its against 325).
          cz = self%area(e) / self%s(e)
          z = self%trac(2:3, e) + cz * dg
          nrm = norm2(z)
          dd = 0.0_rp
          if (nrm > 0.0_rp) dd = z / nrm
          p2 = -spread(dd, 2, 2) * spread(dd, 1, 2)
          p2(1, 1) = p2(1, 1) + 1.0_rp
          p2(2, 2) = p2(2, 2) + 1.0_rp
          r(2:3) = -self%s(e) * (self%trac(2:3, e) - tau * dd)
          hb(2, 2) = -self%s(e)
          hb(3, 3) = -self%s(e)
          if (nrm > 0.0_rp .and. any(dg /= 0.0_rp) .and. .not. self%fresh(e)) then
            hb(2:3, 2:3) = hb(2:3, 2:3) + self%s(e) * tau / nrm * p2
            jt(2:3, :) = self%s(e) * tau * cz / (nrm * self%area(e)) * matmul(p2, be(2:3, :))
          end if
          if (tau > 0.0_rp) hb(2:3, 1) = -self%s(e) * self%fric(e) * dd
          call jtt%add_block(cols, cols, hb)
        case (state_open)
          r = -self%s(e) * self%trac(:, e)
          hb = 0.0_rp
          hb(1, 1) = -self%s(e)
          hb(2, 2) = -self%s(e)
          hb(3, 3) = -self%s(e)
          call jtt%add_block(cols, cols, hb)
        end select
        call jtu%add_block(cols, dofs, jt)
        ! stabilization: -H restricted to the constrained components
        if (self%stabilized .and. ne > 0) then
          do k = 1, 4
            ed = self%edges%of_elem(k, e)
            if (ed == 0) cycle
            if (self%edges%pair(1, ed) == e) then
              o = self%edges%pair(2, ed)
              hb = self%eb(:, :, 1, ed)
              call add_h(hb, e)
              hb = self%eb(:, :, 2, ed)
              call add_h(hb, o)
            else
              o = self%edges%pair(1, ed)
              hb = self%eb(:, :, 3, ed)
              call add_h(hb, e)
              hb = transpose(self%eb(:, :, 2, ed))
              call add_h(hb, o)
            end if
          end do
        end if
        self%rhs(t0 + 3*(e-1) : t0 + 3*e - 1) = -r
      end do
      call jtu%finalize_assembly()
      call jtt%finalize_assembly()
      ! momentum rows: -(K u + C1 (t - t_p) - f)
      no = self%t%n_owned()
      allocate(tp(no), w(u1 - u0 + 1))
      tp = self%x(t0:t1)
      do e = 1, mesh%iface_map%n_owned
        if (self%flow) then
          tp(3*e-2) = tp(3*e-2) - self%p(e)
        else
          tp(3*e-2) = tp(3*e-2) - self%pres(e)
        end if
      end do
      call self%sys%apply_block(self%bu, self%bu, self%x(u0:u1), self%rhs(u0:u1))
      call self%sys%apply_block(self%bu, self%bt, tp, w)
      do i = 1, u1 - u0 + 1
        if (.not. self%mech%fixed(i)) cycle
        self%rhs(u0 + i - 1) = 0.0_rp
        w(i) = 0.0_rp
      end do
      call force_scales(self, mesh, self%rhs(u0:u1), w, tp)
      self%rhs(u0:u1) = self%f_u - self%rhs(u0:u1) - w
      do i = 1, u1 - u0 + 1
        if (self%mech%fixed(i)) self%rhs(u0 + i - 1) = 0.0_rp
      end do
    end associate
    if (self%flow) call assemble_mass_rows(self, mesh)
  contains
    !> Row e gets -hb(1:ne, 1:n_o) on the columns of o and the residual -hb v(o).
    subroutine add_h(hbl, oe)
      real(rp), intent(in) :: hbl(3, 3)
      integer(ip), intent(in) :: oe
      integer(ip) :: no2, cols_o(3)
      real(rp) :: blk(3, 3)
      no2 = ncon(self%state(oe))
      if (no2 == 0) return
      cols_o = self%t%dof(oe, [1_ip, 2_ip, 3_ip])
      blk = 0.0_rp
      blk(1:ne, 1:no2) = -hbl(1:ne, 1:no2)
      call self%sys%a(self%bt, self%bt)%add_block(cols(1:ne), cols_o(1:no2), blk(1:ne, 1:no2))
      v(1) = self%trac(1, oe)
      v(2:3) = self%trac(2:3, oe) - self%trac_step(2:3, oe)
      r(1:ne) = r(1:ne) - matmul(hbl(1:ne, 1:no2), v(1:no2))
    end subroutine add_h
  end subroutine assemble_newton

  !> The momentum rows' magnitudes for field_residuals, from the internal
  !> forces ku = K u and the faces' forces w = C1 (t - t_p) (free rows; tp:
  !> t - t_p): force_ref, the largest of the loads, ku and w, and
  !> force_noise, |f| + |K| |u| + |C1| |t - t_p|. Collective.
  subroutine force_scales(self, mesh, ku, w, tp)
    type(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: ku(:), w(:), tp(:)
    real(rp), allocatable :: ka(:), ca(:), rmax(:)
    integer(ip) :: u0, u1
    call self%sys%block_range(self%bu, u0, u1)
    self%force_ref = max(pnorm2(mesh%comm, pack(self%f_u, .not. self%mech%fixed(1:u1-u0+1))), &
                         pnorm2(mesh%comm, ku), pnorm2(mesh%comm, w))
    allocate(ka(u1 - u0 + 1), ca(u1 - u0 + 1), rmax(u1 - u0 + 1))
    call self%sys%a(self%bu, self%bu)%abs_apply(self%x(u0:u1), ka, rmax)
    call self%sys%a(self%bu, self%bt)%abs_apply(tp, ca, rmax)
    ka = abs(self%f_u) + ka + ca
    where (self%mech%fixed(1:u1-u0+1)) ka = 0.0_rp
    self%force_noise = pnorm2(mesh%comm, ka)
  end subroutine force_scales

  !> Constrained traction components of a status.
  pure integer(ip) function ncon(st)
    integer, intent(in) :: st
    select case (st)
    case (state_stick)
      ncon = 3
    case (state_slip)
      ncon = 1
    case default
      ncon = 0
    end select
  end function ncon

  !> Take the owned block vector x as the new state: local displacements and
  !> tractions with ghosts, mean jumps of the local elements. Collective.
  subroutine take_solution(self, mesh)
    class(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: tl(:)
    real(rp) :: be(3, nju)
    integer(ip) :: u0, u1, t0, t1, e, dofs(nju)
    call self%sys%block_range(self%bu, u0, u1)
    call self%sys%block_range(self%bt, t0, t1)
    self%u(1:u1-u0+1) = self%x(u0:u1)
    call self%mech%u%map%import(self%u)
    allocate(tl(self%t%n_local()))
    tl = 0.0_rp
    tl(1:t1-t0+1) = self%x(t0:t1)
    call self%t%map%import(tl)
    self%trac = reshape(tl, [3, mesh%n_ifaces])
    do e = 1, mesh%n_ifaces
      call jump_operator(self, mesh, e, be, dofs)
      self%jump(:, e) = matmul(be, self%u(max(dofs, 1_ip))) / self%area(e)   ! unused columns are zero
    end do
    if (self%flow) then
      call self%sys%block_range(self%bp, t0, t1)
      self%p = 0.0_rp
      self%p(1:t1-t0+1) = self%x(t0:t1)
      call self%pd%map%import(self%p)
      call self%ff%set_apertures(self%edges, self%jump(1, :), self%state == state_open)
    end if
  end subroutine take_solution

  !> The residual of the last assembly per field, in physical units, and
  !> the magnitude it is measured against (2-norms over the owned rows):
  !>   1 force [N]: the momentum rows; against the largest of the loads, the
  !>     internal forces K u and the faces' forces C1 (t - p n);
  !>   2 traction [Pa]: each contact row divided by its element's scale s
  !>     (a stick row's gap A g and a slip row's friction mismatch alike
  !>     become the traction that would close them at the element's
  !>     stiffness); against the tractions and the faces' fluid pressures;
  !>   3 fluid volume of the step [m^3] (fracture flow): the mass rows
  !>     balancing a volume; against the sum of their terms' absolute values
  !>     (opening, storage, flow to the neighbours, stabilization, wells).
  !> Rows that hold a value (a prescribed or step-0 pressure) are linear and
  !> left out. noise: per field the magnitude of the operands of its terms
  !> (|K| |u| + |C1| |t - t_p| + |f| and the like), whose eps multiple is
  !> the round-off of evaluating the residual. Collective.
  subroutine field_residuals(self, mesh, res, ref, noise)
    class(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(out) :: res(3), ref(3), noise(3)
    real(rp), allocatable :: rt(:), tp(:), nt(:)
    integer(ip) :: u0, u1, t0, t1, e, nown
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    nown = mesh%iface_map%n_owned
    call self%sys%block_range(self%bu, u0, u1)
    call self%sys%block_range(self%bt, t0, t1)
    res(1) = pnorm2(comm, self%rhs(u0:u1))
    ref(1) = self%force_ref
    noise(1) = self%force_noise
    allocate(rt(3 * nown), tp(nown), nt(3 * nown))
    do e = 1, nown
      rt(3*e-2:3*e) = self%rhs(t0 + 3*(e-1) : t0 + 3*e - 1) / self%s(e)
      tp(e) = self%pres(e)
      if (self%flow) tp(e) = self%p(e)
      nt(3*e-2:3*e) = self%area(e) * (abs(self%jump(:, e)) + abs(self%jump_step(:, e))) / self%s(e) + &
                      abs(self%trac(:, e)) + abs(self%trac_step(:, e)) + abs(tp(e))
    end do
    res(2) = pnorm2(comm, rt)
    ref(2) = pnorm2(comm, [reshape(self%trac(:, 1:nown), [3 * nown]), tp])
    noise(2) = pnorm2(comm, nt)
    res(3) = 0.0_rp
    ref(3) = 0.0_rp
    noise(3) = 0.0_rp
    if (.not. self%flow) return
    call self%sys%block_range(self%bp, t0, t1)
    if (self%dt > 0.0_rp) res(3) = pnorm2(comm, pack(self%rhs(t0:t1), self%pfix(1:nown) == 0))
    ref(3) = pnorm2(comm, self%mass_mag)
    noise(3) = pnorm2(comm, self%mass_noise)
  end subroutine field_residuals

  !> Active-set update of the owned elements from the current state, ghosts
  !> synchronized. Returns the global number of changes. Collective.
  integer(gp) function update_states(self, mesh, tol) result(changed)
    class(contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: tol                    !< relative tolerance of the checks
    integer :: f
    type(parallel_comm_t) :: comm
    real(rp) :: t_ref, g_ref, tau, dg(2), excess
    real(rp), allocatable :: st(:)
    integer(ip) :: e, nown
    integer :: new
    comm = mesh%comm
    nown = mesh%iface_map%n_owned
    t_ref = 0.0_rp
    g_ref = 0.0_rp
    if (nown > 0) then
      t_ref = maxval(abs(self%trac(:, 1:nown)))
      t_ref = max(t_ref, maxval(abs(self%pres(1:nown))), maxval(self%coh(1:nown)))
      g_ref = maxval(abs(self%jump(:, 1:nown)))
    end if
    t_ref = comm%max(t_ref)
    g_ref = max(comm%max(g_ref), 1.0e-9_rp * self%length)
    changed = 0
    if (.not. allocated(self%held)) allocate(self%held(size(self%faults)), self%held_open(size(self%faults)))
    self%held = 0
    self%held_open = 0
    self%held_excess = 0.0_rp
    do e = 1, nown
      new = self%state(e)
      tau = max(self%coh(e) - self%fric(e) * self%trac(1, e), 0.0_rp)
      dg = self%jump(2:3, e) - self%jump_step(2:3, e)
      excess = 0.0_rp
      select case (self%state(e))
      case (state_stick)
        if (self%trac(1, e) > tol * t_ref) then
          new = state_open
          excess = self%trac(1, e) / max(t_ref, tiny(1.0_rp))
        else if (norm2(self%trac(2:3, e)) > tau + tol * t_ref) then
          new = state_slip
          excess = (norm2(self%trac(2:3, e)) - tau) / max(t_ref, tiny(1.0_rp))
        end if
      case (state_slip)
        if (self%trac(1, e) > tol * t_ref) then
          new = state_open
          excess = self%trac(1, e) / max(t_ref, tiny(1.0_rp))
        else if (norm2(self%trac(2:3, e) + self%area(e) / self%s(e) * dg) < tau - tol * t_ref .or. &
                 dot_product(self%trac(2:3, e), self%area(e) / self%s(e) * dg) < &
                 -tol * t_ref * norm2(self%trac(2:3, e))) then
          ! |z| below the limit, or the slip increment against the friction
          ! traction (which the slip rows set along the last direction) by
          ! more than the tolerance, as a traction c dg: the slip turned
          ! back, and an element that reverses passes through stick. (Without
          ! it, the elements of a fault whose slip front outran the pressure
          ! swapped t_T = +tau and -tau at every Newton iteration, each
          ! increment c |dg| far above 2 tau, with no status change, for 30
          ! iterations.)
          new = state_stick
          excess = max(tau - norm2(self%trac(2:3, e) + self%area(e) / self%s(e) * dg), &
                       -dot_product(self%trac(2:3, e), self%area(e) / self%s(e) * dg) / &
                       max(norm2(self%trac(2:3, e)), tiny(1.0_rp))) / max(t_ref, tiny(1.0_rp))
        end if
      case (state_open)
        ! a closing element that slipped in this step closes slipping: its
        ! tangential jump moved while it was open, and stick would pull it
        ! back to the step's start (a tangential traction far beyond the
        ! friction limit, stick -> slip at the next update). The slip rows
        ! send it to stick once its friction holds. (Seed's nine fractures at
        ! 1 m cells, opening step: 137 of 349 elements closed into stick,
        ! and stick <-> slip changed 100-300 statuses an update for 14.)
        if (self%jump(1, e) < -tol * g_ref) new = merge(state_slip, state_stick, self%slipped(e))
        excess = -self%jump(1, e) / g_ref
      end select
      ! an element that changed max_flips times in this step sits on the
      ! friction limit (stick <-> slip) or at the opening (open <-> closed:
      ! t_N and g_N both zero) within the tolerances: it keeps its status.
      ! (Without the cap on the opening, one element of the seed's nine
      ! fractures at 1 m cells went open, stick, open, ... through 20 Newton
      ! iterations and the step was cut twice.)
      if (new /= self%state(e)) then
        if (self%flips(e) >= max_flips) then
          if (new == state_open .or. self%state(e) == state_open) then
            self%held_open(self%fault(e)) = self%held_open(self%fault(e)) + 1
          else
            self%held(self%fault(e)) = self%held(self%fault(e)) + 1
          end if
          self%held_excess = max(self%held_excess, excess)
          new = self%state(e)
        else
          self%flips(e) = self%flips(e) + 1
        end if
      end if
      if (new /= self%state(e)) changed = changed + 1
      self%fresh(e) = new == state_slip .and. self%state(e) == state_stick
      if (new == state_slip) self%slipped(e) = .true.
      self%state(e) = new
    end do
    changed = comm%sum(changed)
    self%held_excess = comm%max(self%held_excess)
    do f = 1, size(self%held)
      self%held(f) = comm%sum(self%held(f))
      self%held_open(f) = comm%sum(self%held_open(f))
    end do
    allocate(st(mesh%n_ifaces))
    st = real(self%state, rp)
    call mesh%iface_map%import(st)
    self%state = nint(st)
  end function update_states

  !> Global number of owned elements in each status. Collective.
  function count_states(self, mesh) result(n)
    class(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(gp) :: n(3)
    integer :: k
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    do k = 1, 3
      n(k) = comm%sum(int(count(self%state(1:mesh%iface_map%n_owned) == k), gp))
    end do
  end function count_states

  !> The regular diagonal H~ of the contact rows (owned t dofs): where the
  !> diagonal of -J_tt is positive, the sum of the absolute values of that
  !> row of J_tt (a dominant diagonal: H~ >= H_t, so that the eigenvalues of
  !> the traction block of the preconditioned reordered system lie in (0, 1]);
  !> elsewhere the row scale s; times scale. With use_h = .false. it is
  !> scale * s everywhere (the augmentation D).
  !> Measured on tests/decks/contact_block.nml, all stick, cubes n = 8..32,
  !> with S* solved exactly: 9, 11, 11, 11 FGMRES iterations against 11, 12,
  !> 13, 13 with the plain diagonal of -J_tt (whose spectrum reaches 2).
  !> On a slipping element's tangential rows H~ is at least slip_floor * s.
  !> There -J_tt = s (I - theta (I - d d^T)), theta = tau / |z| (assemble_
  !> newton): for an element that barely slips theta is near 1 and the row
  !> across the direction d is nearly a multiplier with no stabilization, so
  !> the row sum s (1 - theta) made C1 H~^-1 C2 a penalty on that slip,
  !> stiffer than any stick element's, and BoomerAMG on S* lost its grip.
  !> Seed's nine fractures, step 3 (slip starts), the largest FGMRES count
  !> of its Newton iterations from the second on, 4 m / 2 m cells: 34 / 54
  !> without the floor; with it 0.1: - / 41, 0.2: - / 33, 0.3: 27 / 31,
  !> 0.5: 31 / 36, 1.0: 42 / 50 (the slipping step 4: 34 / 38 either way).
  subroutine ht_diagonal(self, mesh, scale, use_h, h)
    class(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: scale
    logical, intent(in) :: use_h
    real(rp), intent(out) :: h(:)
    !> floor of H~ on a slipping element's tangential rows, times s
    real(rp), parameter :: slip_floor = 0.3_rp
    integer(ip) :: e, c, i
    if (use_h) then
      associate (a => self%sys%a(self%bt, self%bt))
        call a%diagonal(h)
        do i = 1, a%n_rows
          if (-h(i) > 0.0_rp) then
            h(i) = sum(abs(a%val(a%row_ptr(i):a%row_ptr(i + 1) - 1)))
          else
            h(i) = 0.0_rp
          end if
        end do
      end associate
    else
      h = 0.0_rp
    end if
    do e = 1, mesh%iface_map%n_owned
      do c = 1, 3
        i = 3 * (e - 1) + c
        if (.not. (h(i) > 0.0_rp)) then
          h(i) = self%s(e)
        else if (c > 1 .and. self%state(e) == state_slip) then
          h(i) = max(h(i), slip_floor * self%s(e))
        end if
      end do
    end do
    h = scale * h
  end subroutine ht_diagonal

  !> Per fault (of faults(:)), the largest angle [degrees] between its
  !> normal and the cell edges that leave its tip elements (elements with an
  !> unsplit node), 0 for a fault without tips. Where the cells on the two
  !> sides are not mirror images near a tip, Q1 couples slip to a normal
  !> force that grows under refinement (doc/contact.md, tips on skewed cells).
  !> Collective.
  function tip_skew(self, mesh) result(worst)
    class(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: worst(size(self%faults))
    integer, parameter :: hex_edges(2, 12) = reshape([1, 2, 2, 3, 3, 4, 4, 1, 5, 6, 6, 7, 7, 8, 8, 5, &
                                                      1, 5, 2, 6, 3, 7, 4, 8], [2, 12])
    integer(ip) :: e, side, c, k, na, nb
    real(rp) :: v(3), cosine
    type(parallel_comm_t) :: comm
    worst = 0.0_rp
    do e = 1, mesh%iface_map%n_owned
      if (all(mesh%iface_nodes(:, 1, e) /= mesh%iface_nodes(:, 2, e))) cycle
      do side = 1, 2
        c = mesh%iface_cells(side, e)
        do k = 1, 12
          na = mesh%cell_nodes(hex_edges(1, k), c)
          nb = mesh%cell_nodes(hex_edges(2, k), c)
          if (any(mesh%iface_nodes(:, side, e) == na) .eqv. any(mesh%iface_nodes(:, side, e) == nb)) cycle
          v = mesh%coords(:, nb) - mesh%coords(:, na)
          cosine = min(1.0_rp, abs(dot_product(v, self%rot(1, :, e))) / norm2(v))
          worst(self%fault(e)) = max(worst(self%fault(e)), acos(cosine) / deg)
        end do
      end do
    end do
    comm = mesh%comm
    do k = 1, size(worst)
      worst(k) = comm%max(worst(k))
    end do
  end function tip_skew

  !> The local displacement at the nodes, 3 per local node in node order
  !> (the bubbles left out): what the output and the probes read [m].
  function nodal_u(self, mesh) result(un)
    class(contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: un(:)
    integer(ip) :: nd
    allocate(un(3 * mesh%n_nodes))
    do nd = 1, mesh%n_nodes
      un(3*nd-2:3*nd) = self%u(self%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))
    end do
  end function nodal_u

  subroutine free(self)
    class(contact_t), intent(inout) :: self
    call self%sys%free()
    call self%mech%free()
    call self%t%free()
    if (allocated(self%x)) deallocate(self%x, self%rhs)
    if (allocated(self%f_u)) deallocate(self%f_u)
    if (allocated(self%u)) deallocate(self%u)
    if (allocated(self%area)) deallocate(self%area, self%wn, self%rot, self%wb)
    call self%bub%free()
    self%bubble = .false.
    if (allocated(self%s)) deallocate(self%s)
    if (allocated(self%fric)) deallocate(self%fric, self%coh, self%pres, self%state, &
                                                 self%fault, self%flips, self%fresh, self%slipped)
    if (allocated(self%held)) deallocate(self%held, self%held_open)
    if (allocated(self%trac)) deallocate(self%trac, self%trac_step, self%jump, self%jump_step)
    call self%edges%free()
    if (allocated(self%eb)) deallocate(self%eb)
    call self%pd%free()
    call self%ff%free()
    if (allocated(self%p)) deallocate(self%p, self%p_step, self%gn_step)
    call self%wl%free()
    if (allocated(self%pfix)) deallocate(self%pfix, self%p_fixed)
    if (allocated(self%mass_mag)) deallocate(self%mass_mag, self%mass_noise)
    self%flow = .false.
    if (allocated(self%faults)) deallocate(self%faults)
    self%bu = 1
    self%bt = 2
    self%bp = 3
  end subroutine free
end module contact
