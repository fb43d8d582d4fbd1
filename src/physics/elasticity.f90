!> Isotropic linear elasticity on Q1 hexahedra: the displacement field, its
!> stiffness block K, right-hand side, boundary conditions and cell stresses.
!>
!> Dirichlet conditions are imposed symmetrically: the element matrices lose the
!> rows and columns of prescribed dofs (their known values move to the right-
!> hand side), and after assembly each prescribed row gets a diagonal entry equal
!> to the mean diagonal of K, so the matrix stays symmetric positive definite and
!> well scaled for AMG. Stresses are positive in tension. Surface loads are a
!> constant traction vector ('traction') or a traction along the outward unit
!> normal ('normal_traction', evaluated at each quadrature point of the face:
!> t dA = value * the face's area vector, which points out of its cell).
!>
!> Enriched (init with bubbles, contact's face-bubble space): the cells on
!> the faults also carry face bubbles (face_bubbles.f90), 3 dofs each in the
!> displacement field after the nodes (dof_map's init_extra). Their element
!> matrices, Q1 and bubbles together, take 3x3x3 Gauss points (2x2x2 is not
!> exact for the bubble's products); the other cells keep 2x2x2. The bubbles
!> vanish on the boundary faces, so only the body force loads them; stresses
!> are from the nodal part.
module elasticity
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use dist_mesh, only: dist_mesh_t
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use quadrature, only: gauss_hex, gauss_quad
  use hex_q1, only: hex_gradients, quad_shape, quad_area_vector, hex_face_bubble, hex_shape, inverse3
  use face_bubbles, only: face_bubbles_t
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use vector_function, only: vector_function_t
  use mesh_pieces, only: mesh_pieces_t
  use rigid_modes, only: check_rigid_modes
  use geostatic, only: geostatic_t
  use geostatic_config, only: geostatic_config_t
  use pressure_change_config, only: pressure_change_config_t
  use face_box, only: box_tolerance, face_in_box, count_set_faces_in_box, box_text
  use strings, only: itoa, rtoa
  implicit none
  private

  public :: elasticity_t, lame, point_block

  type :: elasticity_t
    type(dof_map_t) :: u                     !< 3 dofs per node, interleaved
    type(csr_matrix_t) :: k
    real(rp), allocatable :: rhs(:)          !< owned dofs
    real(rp), allocatable :: lambda(:), mu(:), body(:,:)   !< per region [Pa], [N/m^3]
    logical, allocatable :: fixed(:)         !< per local dof
    real(rp), allocatable :: fixed_value(:)  !< per local dof, at full load [m]
    integer(ip), allocatable :: trac_face(:) !< local boundary faces with a traction, on owned cells
    real(rp), allocatable :: trac_value(:,:) !< (3, n) traction at full load [Pa]; normal: (value, 0, 0)
    logical, allocatable :: trac_normal(:)   !< (n) the traction is along the outward normal
    real(rp) :: diag_scale = 1.0_rp
    integer(ip), allocatable :: fixed_bc(:)  !< per local dof: the condition that prescribes it
    integer(ip), allocatable :: trac_bc(:)   !< per traction face: its condition
    type(boundary_config_t), allocatable :: bcs(:)
    real(rp), allocatable :: bc_factor(:)    !< history factor of each condition at the current time
    type(geostatic_t) :: geo                 !< the in-situ state (&geostatic), if any
    real(rp), allocatable :: geo_load(:)     !< (local dofs, before export_add) the in-situ load: it does not change
    real(rp) :: box_tol(3) = 0.0_rp          !< tolerance of the conditions' boxes [m] (face_box)
    type(pressure_change_config_t), allocatable :: pcs(:)   !< &pressure_change groups
    integer(ip), allocatable :: dp_cell(:)   !< per local cell: its &pressure_change group, 0: none
    real(rp), allocatable :: dp_biot(:)      !< per region: Biot coefficient of its rock
    real(rp), allocatable :: dp_now(:)       !< per group: pore pressure change at the current time, at full load [Pa]
    logical :: enriched = .false.            !< the fault cells carry face bubbles
    type(face_bubbles_t) :: bub              !< the bubbles (enriched)
  contains
    procedure :: init
    procedure :: init_in_situ
    procedure :: init_pressure_changes
    procedure :: pressure_change_at
    procedure :: pressure_change_field
    procedure :: in_situ_imbalance
    procedure :: assemble
    procedure :: assemble_into
    procedure :: element_stiffness
    procedure :: cell_dofs
    procedure :: stiffness_pattern
    procedure :: cell_stress
    procedure :: set_time
    procedure :: prescribed_value
    procedure :: check_anchored
    procedure :: rigid_body_modes
    procedure :: free
  end type elasticity_t

contains

  !> Lame parameters from E [Pa] and nu.
  pure subroutine lame(e, nu, lambda, mu)
    real(rp), intent(in) :: e, nu
    real(rp), intent(out) :: lambda, mu
    lambda = e * nu / ((1.0_rp + nu) * (1.0_rp - 2.0_rp * nu))
    mu = e / (2.0_rp * (1.0_rp + nu))
  end subroutine lame

  !> Dofs, pattern of K, materials per region and boundary data. Collective.
  !> Every region needs a material; every condition's set must exist.
  subroutine init(self, mesh, mats, bcs, status, bubbles)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(material_config_t), intent(in) :: mats(:)
    type(boundary_config_t), intent(in) :: bcs(:)
    type(error_status_t), intent(inout) :: status
    type(face_bubbles_t), intent(in), optional :: bubbles   !< enrich the fault cells with these
    integer(ip), allocatable :: row_ptr(:), col(:)
    integer(ip) :: r, m, b, s, i, n, c, f, nt
    real(rp) :: tol(3)
    character(len=msg_len) :: msg

    call self%free()
    n = size(mesh%region_names, kind=ip)
    allocate(self%lambda(n), self%mu(n), self%body(3, n))
    ! no pore pressure change until init_pressure_changes says where
    allocate(self%dp_cell(mesh%n_cells), self%dp_biot(n), self%dp_now(0), self%pcs(0))
    self%dp_cell = 0
    self%dp_biot = 1.0_rp
    do r = 1, n
      m = 0
      do i = 1, size(mats, kind=ip)
        if (mats(i)%region == mesh%region_names(r)) m = i
      end do
      if (m == 0) then
        write(msg, '(a)') "region '"//trim(mesh%region_names(r))//"' of the mesh has no &material group"
        call status%set(msg)
        return
      end if
      call lame(mats(m)%young, mats(m)%poisson, self%lambda(r), self%mu(r))
      self%body(:, r) = mats(m)%body_force
    end do
    do i = 1, size(mats, kind=ip)
      if (mesh%region_id(mats(i)%region) == 0) then
        call status%set("&material for region '"//trim(mats(i)%region)//"', which the mesh does not have "// &
                        '(its regions: '//mesh%region_list()//')')
        return
      end if
    end do

    self%enriched = present(bubbles)
    if (self%enriched) then
      self%bub = bubbles
      call self%u%init_extra('displacement', mesh%node_map, bubbles%map, 3)
    else
      call self%u%init('displacement', mesh%node_map, 3)
    end if
    call self%stiffness_pattern(mesh, row_ptr, col)
    call self%k%init(self%u%map, self%u%map, row_ptr, col)
    allocate(self%rhs(self%u%n_owned()))

    allocate(self%fixed(self%u%n_local()), self%fixed_value(self%u%n_local()), self%fixed_bc(self%u%n_local()))
    self%fixed = .false.
    self%fixed_value = 0.0_rp
    self%fixed_bc = 0
    self%bcs = bcs
    allocate(self%bc_factor(size(bcs)))
    self%bc_factor = 1.0_rp
    tol = box_tolerance(mesh)
    self%box_tol = tol
    call check_boxes(mesh, bcs, tol, status)
    if (.not. status%ok()) return
    nt = 0
    do b = 1, size(bcs, kind=ip)
      s = mesh%set_id(bcs(b)%set)
      if (bcs(b)%type == 'displacement' .and. bcs(b)%has_box()) then
        call fix_faces_in_box(self, mesh, bcs(b), b, s, tol)
      else if (bcs(b)%type == 'displacement') then
        do i = mesh%set_node_ptr(s), mesh%set_node_ptr(s+1) - 1
          call fix_node(self, mesh%set_nodes(i), bcs(b), b)
        end do
      else if (is_traction(bcs(b)%type)) then
        do i = 1, mesh%n_sfaces
          if (mesh%sface_set(i) /= s) cycle
          if (face_in_box(mesh, mesh%sface_face(i), bcs(b)%lower, bcs(b)%upper, tol)) nt = nt + 1
        end do
      end if
    end do
    ! a node of a face in a box may be a ghost here whose face this rank does
    ! not hold: the owner's decision is the one
    if (any([(bcs(b)%has_box(), b = 1, size(bcs, kind=ip))])) call import_fixed(self)
    ! traction faces: boundary faces of the set whose cell this rank owns
    allocate(self%trac_face(nt), self%trac_value(3, nt), self%trac_bc(nt), self%trac_normal(nt))
    nt = 0
    do b = 1, size(bcs, kind=ip)
      if (.not. is_traction(bcs(b)%type)) cycle
      s = mesh%set_id(bcs(b)%set)
      do i = 1, mesh%n_sfaces
        if (mesh%sface_set(i) /= s) cycle
        f = mesh%sface_face(i)
        if (.not. mesh%face_on_boundary(f)) then
          call status%set("traction on set '"//trim(bcs(b)%set)//"', which is not on the boundary")
          return
        end if
        if (.not. face_in_box(mesh, f, bcs(b)%lower, bcs(b)%upper, tol)) cycle
        c = mesh%face_cells(1, f)
        if (c < 1 .or. c > mesh%cell_map%n_owned) cycle
        nt = nt + 1
        self%trac_face(nt) = f
        self%trac_value(:, nt) = bcs(b)%value
        self%trac_bc(nt) = b
        self%trac_normal(nt) = bcs(b)%type == 'normal_traction'
      end do
    end do
    self%trac_face = self%trac_face(1:nt)
    self%trac_value = self%trac_value(:, 1:nt)
    self%trac_bc = self%trac_bc(1:nt)
    self%trac_normal = self%trac_normal(1:nt)
  contains
    logical function is_traction(type)
      character(len=*), intent(in) :: type
      is_traction = type == 'traction' .or. type == 'normal_traction'
    end function is_traction
  end subroutine init

  !> Every condition's set must exist, and a condition with a box must
  !> select a face of it (counted over all ranks). Collective: the same
  !> status on every rank.
  subroutine check_boxes(mesh, bcs, tol, status)
    type(dist_mesh_t), intent(in) :: mesh
    type(boundary_config_t), intent(in) :: bcs(:)
    real(rp), intent(in) :: tol(3)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: b, s
    do b = 1, size(bcs, kind=ip)
      s = mesh%set_id(bcs(b)%set)
      if (s == 0) then
        call status%set("&boundary on set '"//trim(bcs(b)%set)//"', which the mesh does not have")
        return
      end if
      if (.not. bcs(b)%has_box()) cycle
      if (count_set_faces_in_box(mesh, s, bcs(b)%lower, bcs(b)%upper, tol) == 0) then
        call status%set("&boundary number "//itoa(int(b))//" (type '"//trim(bcs(b)%type)//"' on set '"// &
          trim(bcs(b)%set)//"'): no face of the set has its centre in lower..upper "//box_text(bcs(b)%lower, bcs(b)%upper)// &
          '; widen the box or refine the mesh')
        return
      end if
    end do
  end subroutine check_boxes

  !> Prescribe the components of displacement condition bc (number b) at
  !> local node n.
  subroutine fix_node(self, n, bc, b)
    type(elasticity_t), intent(inout) :: self
    integer(ip), intent(in) :: n, b
    type(boundary_config_t), intent(in) :: bc
    integer(ip) :: c
    do c = 1, 3
      if (.not. bc%fixed(c)) cycle
      self%fixed(self%u%dof(n, c)) = .true.
      self%fixed_value(self%u%dof(n, c)) = bc%value(c)
      self%fixed_bc(self%u%dof(n, c)) = b
    end do
  end subroutine fix_node

  !> Displacement condition bc (number b) on the nodes of the faces of set s
  !> whose centres lie in its box.
  subroutine fix_faces_in_box(self, mesh, bc, b, s, tol)
    type(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(boundary_config_t), intent(in) :: bc
    integer(ip), intent(in) :: b, s
    real(rp), intent(in) :: tol(3)
    integer(ip) :: i, f, k
    do i = 1, mesh%n_sfaces
      if (mesh%sface_set(i) /= s) cycle
      f = mesh%sface_face(i)
      if (.not. face_in_box(mesh, f, bc%lower, bc%upper, tol)) cycle
      do k = 1, 4
        call fix_node(self, mesh%face_nodes(k, f), bc, b)
      end do
    end do
  end subroutine fix_faces_in_box

  !> The prescribed flags, values and conditions of ghost dofs from their
  !> owners. Collective.
  subroutine import_fixed(self)
    type(elasticity_t), intent(inout) :: self
    real(rp), allocatable :: w(:)
    allocate(w(self%u%n_local()))
    w = merge(1.0_rp, 0.0_rp, self%fixed)
    call self%u%map%import(w)
    self%fixed = w > 0.5_rp
    w = self%fixed_value
    call self%u%map%import(w)
    self%fixed_value = w
    w = real(self%fixed_bc, rp)
    call self%u%map%import(w)
    self%fixed_bc = nint(w, ip)
  end subroutine import_fixed

  !> Evaluate the conditions' histories at time t (the load factor for a
  !> static run, the physical time for poromechanics).
  subroutine set_time(self, t)
    class(elasticity_t), intent(inout) :: self
    real(rp), intent(in) :: t
    integer :: b
    do b = 1, size(self%bcs)
      self%bc_factor(b) = self%bcs(b)%factor(t)
    end do
    do b = 1, size(self%pcs)
      self%dp_now(b) = self%pcs(b)%value * self%pcs(b)%factor(t)
    end do
  end subroutine set_time

  !> Value of prescribed local dof at the current time (without load factor).
  real(rp) function prescribed_value(self, dof)
    class(elasticity_t), intent(in) :: self
    integer(ip), intent(in) :: dof
    prescribed_value = 0.0_rp
    if (self%fixed_bc(dof) > 0) prescribed_value = self%fixed_value(dof) * self%bc_factor(self%fixed_bc(dof))
  end function prescribed_value

  !> Assemble the stiffness self%k and right-hand side self%rhs (see assemble_into).
  subroutine assemble(self, mesh, lf, body, dirichlet)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: lf
    class(vector_function_t), intent(in), optional :: body, dirichlet
    call self%assemble_into(mesh, lf, self%k, self%rhs, body=body, dirichlet=dirichlet)
  end subroutine assemble

  !> Element stiffness ke(24,24) of local cell c (dofs node by node, x y z).
  subroutine element_stiffness(self, mesh, c, ke)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    real(rp), intent(out) :: ke(24, 24)
    real(rp) :: x(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det
    integer(ip) :: q, r
    call gauss_hex(2_ip, xi, w)
    x = mesh%coords(:, mesh%cell_nodes(:, c))
    r = mesh%cell_region(c)
    ke = 0.0_rp
    do q = 1, 8
      call hex_gradients(x, xi(:, q), n, g, det)
      call add_point_stiffness(ke, g, det * w(q), self%lambda(r), self%mu(r))
    end do
  end subroutine element_stiffness

  !> ke += wd * B^T D B at one point for the shape function gradients g(3, m)
  !> (dofs function by function, x y z).
  pure subroutine add_point_stiffness(ke, g, wd, lam, mu)
    real(rp), intent(inout) :: ke(:,:)
    real(rp), intent(in) :: g(:,:), wd, lam, mu
    integer(ip) :: a, bb, i, j
    do bb = 1, size(g, 2, kind=ip)
      do a = 1, size(g, 2, kind=ip)
        do j = 1, 3
          do i = 1, 3
            ke(3*(a-1)+i, 3*(bb-1)+j) = ke(3*(a-1)+i, 3*(bb-1)+j) + wd * &
              (lam * g(i, a) * g(j, bb) + mu * g(j, a) * g(i, bb))
          end do
          ke(3*(a-1)+j, 3*(bb-1)+j) = ke(3*(a-1)+j, 3*(bb-1)+j) + wd * mu * dot_product(g(:, a), g(:, bb))
        end do
      end do
    end do
  end subroutine add_point_stiffness

  !> The local dofs of owned or ghost cell c: its 8 nodes, then its bubbles
  !> (enriched); nd of them.
  subroutine cell_dofs(self, mesh, c, dofs, nd)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    integer(ip), intent(out) :: dofs(:), nd
    integer(ip) :: a, j
    do a = 1, 8
      dofs(3*a-2:3*a) = self%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
    end do
    nd = 24
    if (.not. self%enriched) return
    do j = self%bub%cell_ptr(c), self%bub%cell_ptr(c + 1) - 1
      dofs(nd+1:nd+3) = self%u%extra_dof(j, [1_ip, 2_ip, 3_ip])
      nd = nd + 3
    end do
  end subroutine cell_dofs

  !> CSR pattern (local dofs) of K's owned rows: every cell couples its
  !> nodes and bubbles.
  subroutine stiffness_pattern(self, mesh, row_ptr, col)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), allocatable, intent(out) :: row_ptr(:), col(:)
    integer(ip), allocatable :: conn(:,:)
    integer(ip) :: c, j
    if (.not. self%enriched) then
      call element_pattern(mesh%node_map%n_owned, mesh%cell_nodes, mesh%cell_nodes, 3_ip, 3_ip, row_ptr, col)
      return
    end if
    allocate(conn(14, mesh%n_cells))
    conn = 0
    do c = 1, mesh%n_cells
      conn(1:8, c) = self%u%entity(mesh%cell_nodes(:, c))
      do j = self%bub%cell_ptr(c), self%bub%cell_ptr(c + 1) - 1
        conn(8 + j - self%bub%cell_ptr(c) + 1, c) = self%u%extra_entity(j)
      end do
    end do
    call element_pattern(self%u%map%n_owned / 3, conn, conn, 3_ip, 3_ip, row_ptr, col)
  end subroutine stiffness_pattern

  !> Element stiffness ke(nd, nd) and body load fe(nd) (at full load) of
  !> local cell c with its bubbles (enriched), by 3x3x3 Gauss points; dofs
  !> as cell_dofs gives them. body: added to the region's body force.
  subroutine enriched_element(self, mesh, c, ke, fe, loaded, body)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    real(rp), intent(out) :: ke(:,:), fe(:)
    logical, intent(in) :: loaded
    class(vector_function_t), intent(in), optional :: body
    real(rp) :: x(3, 8), xi(3, 27), w(27), n(8), dn(3, 8), jm(3, 3), ji(3, 3), det, b, db(3), bf(3)
    real(rp), allocatable :: g(:,:), nv(:)
    integer(ip) :: q, r, m, k, a
    call gauss_hex(3_ip, xi, w)
    x = mesh%coords(:, mesh%cell_nodes(:, c))
    r = mesh%cell_region(c)
    m = 8 + self%bub%cell_ptr(c + 1) - self%bub%cell_ptr(c)
    allocate(g(3, m), nv(m))
    ke = 0.0_rp
    fe = 0.0_rp
    do q = 1, 27
      call hex_shape(xi(:, q), n, dn)
      jm = matmul(dn, transpose(x))
      call inverse3(jm, ji, det)
      g(:, 1:8) = matmul(ji, dn)
      nv(1:8) = n
      do k = 9, m
        call hex_face_bubble(xi(:, q), self%bub%face(self%bub%cell_ptr(c) + k - 9), b, db)
        g(:, k) = matmul(ji, db)
        nv(k) = b
      end do
      call add_point_stiffness(ke, g, det * w(q), self%lambda(r), self%mu(r))
      if (.not. loaded) cycle
      bf = self%body(:, r)
      if (present(body)) bf = bf + body%eval(matmul(x, n))
      do a = 1, m
        fe(3*a-2:3*a) = fe(3*a-2:3*a) + nv(a) * bf * det * w(q)
      end do
    end do
  end subroutine enriched_element

  !> Assemble K into k (pattern of self%k) and the right-hand side into rhs
  !> (owned dofs) at load factor lf (loads and prescribed displacements scaled
  !> by lf). Optional body (added to the materials' body forces) and dirichlet
  !> (replacing the prescribed values) are functions of position, for
  !> manufactured solutions. rhs_only: k holds this K already (assembled by
  !> an earlier call), only the right-hand side is made: the element
  !> stiffness only of cells with nonzero prescribed values (their lifting).
  !> Collective.
  subroutine assemble_into(self, mesh, lf, k, rhs, body, dirichlet, rhs_only)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: lf
    type(csr_matrix_t), intent(inout) :: k
    real(rp), intent(out) :: rhs(:)
    class(vector_function_t), intent(in), optional :: body, dirichlet
    logical, intent(in), optional :: rhs_only
    real(rp), allocatable :: f_loc(:)
    real(rp) :: x(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det, ke(42, 42), fe(42), ue(42), xq(3), bf(3), dp
    real(rp) :: xiq(2, 4), wq(4), nq(4), dnq(2, 4), xf(3, 4), da, av(3)
    integer(ip) :: c, q, a, i, j, dofs(42), r, t, f, nown, nd
    type(parallel_comm_t) :: comm
    real(rp) :: dsum, dcount
    logical :: matrix, loaded, lifted, bubbles

    matrix = .true.
    if (present(rhs_only)) matrix = .not. rhs_only
    if (matrix) call k%zero()
    allocate(f_loc(self%u%n_local()))
    f_loc = 0.0_rp
    call gauss_hex(2_ip, xi, w)
    do c = 1, mesh%cell_map%n_owned
      x = mesh%coords(:, mesh%cell_nodes(:, c))
      r = mesh%cell_region(c)
      call self%cell_dofs(mesh, c, dofs, nd)
      bubbles = nd > 24
      dp = self%pressure_change_at(mesh, c)
      loaded = present(body) .or. any(self%body(:, r) /= 0.0_rp) .or. dp /= 0.0_rp
      ! known values of the prescribed dofs (nodes only: bubbles are free);
      ! only nonzero ones lift the right-hand side
      lifted = .false.
      ue = 0.0_rp
      do j = 1, 24
        if (.not. self%fixed(dofs(j))) cycle
        a = (j - 1) / 3 + 1
        i = mod(j - 1, 3) + 1
        ue(j) = prescribed(dofs(j), mesh%coords(:, mesh%cell_nodes(a, c)), i)
        lifted = lifted .or. ue(j) /= 0.0_rp
      end do
      if (.not. (matrix .or. lifted .or. loaded)) cycle
      fe = 0.0_rp
      if (bubbles) then
        ! (&geostatic and &pressure_change are refused with the bubble space)
        call enriched_element(self, mesh, c, ke(1:nd, 1:nd), fe(1:nd), loaded, body)
      else
        if (matrix .or. lifted) call self%element_stiffness(mesh, c, ke(1:24, 1:24))
        if (loaded) then
          do q = 1, 8
            call hex_gradients(x, xi(:, q), n, g, det)
            det = det * w(q)
            bf = self%body(:, r)
            if (present(body)) then
              xq = matmul(x, n)
              bf = bf + body%eval(xq)
            end if
            do a = 1, 8
              ! the pore pressure change: b dp div(eta)
              fe(3*a-2:3*a) = fe(3*a-2:3*a) + n(a) * bf * det + self%dp_biot(r) * dp * g(:, a) * det
            end do
          end do
        end if
      end if
      fe = lf * fe
      ! prescribed dofs: move their known values to the right-hand side
      do j = 1, 24
        if (.not. self%fixed(dofs(j))) cycle
        if (matrix .or. lifted) then
          fe(1:nd) = fe(1:nd) - ke(1:nd, j) * ue(j)
          ke(1:nd, j) = 0.0_rp
          ke(j, 1:nd) = 0.0_rp
        end if
        fe(j) = 0.0_rp
      end do
      if (matrix) call k%add_block(dofs(1:nd), dofs(1:nd), ke(1:nd, 1:nd))
      f_loc(dofs(1:nd)) = f_loc(dofs(1:nd)) + fe(1:nd)
    end do

    ! tractions
    call gauss_quad(2_ip, xiq, wq)
    do t = 1, size(self%trac_face, kind=ip)
      f = self%trac_face(t)
      xf = mesh%coords(:, mesh%face_nodes(:, f))
      do q = 1, 4
        call quad_shape(xiq(:, q), nq, dnq)
        av = quad_area_vector(xf, xiq(:, q))      ! outward (the face as its cell sees it), |av| dxi = dA
        da = norm2(av) * wq(q)
        do a = 1, 4
          do i = 1, 3
            j = self%u%dof(mesh%face_nodes(a, f), i)
            if (self%fixed(j)) cycle
            if (self%trac_normal(t)) then
              f_loc(j) = f_loc(j) + lf * self%bc_factor(self%trac_bc(t)) * nq(a) * self%trac_value(1, t) * av(i) * wq(q)
            else
              f_loc(j) = f_loc(j) + lf * self%bc_factor(self%trac_bc(t)) * nq(a) * self%trac_value(i, t) * da
            end if
          end do
        end do
      end do
    end do

    if (self%geo%on) f_loc = f_loc + self%geo_load
    if (matrix) call k%finalize_assembly()
    call self%u%map%export_add(f_loc)
    nown = self%u%n_owned()
    rhs = f_loc(1:nown)

    ! prescribed rows: mean diagonal of the free rows, scaled value
    if (matrix) then
      comm = mesh%comm
      dsum = 0.0_rp
      dcount = 0.0_rp
      do i = 1, nown
        if (self%fixed(i)) cycle
        dsum = dsum + k%val(k%find(i, i))
        dcount = dcount + 1.0_rp
      end do
      dsum = comm%sum(dsum)
      dcount = comm%sum(dcount)
      self%diag_scale = 1.0_rp
      if (dcount > 0.0_rp) self%diag_scale = dsum / dcount
    end if
    do i = 1, nown
      if (.not. self%fixed(i)) cycle
      if (matrix) k%val(k%find(i, i)) = self%diag_scale
      a = (i - 1) / 3 + 1
      j = mod(i - 1, 3) + 1
      rhs(i) = self%diag_scale * prescribed(i, mesh%coords(:, a), j)
    end do
  contains
    real(rp) function prescribed(dof, xn, comp)
      integer(ip), intent(in) :: dof, comp
      real(rp), intent(in) :: xn(3)
      real(rp) :: v(3)
      if (present(dirichlet)) then
        v = dirichlet%eval(xn)
        prescribed = v(comp)
      else
        prescribed = lf * self%prescribed_value(dof)
      end if
    end function prescribed
  end subroutine assemble_into

  !> The in-situ state of cfg (&geostatic; nothing when it is off): the
  !> state itself and its load (in_situ_cell over the owned cells,
  !> in_situ_faces over the boundary faces its stress holds: every boundary
  !> face of an owned cell but the two sides of a fault, where the
  !> tractions are unknowns), made once: assemble_into adds it at every
  !> load factor. Call after init. Collective.
  subroutine init_in_situ(self, mesh, cfg, mats, status)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(geostatic_config_t), intent(in) :: cfg
    type(material_config_t), intent(in) :: mats(:)
    type(error_status_t), intent(inout) :: status
    logical, allocatable :: fault_side(:)
    integer(ip), allocatable :: faces(:)
    real(rp) :: fe(24)
    integer(ip) :: e, s, c, k, f, n, a, dofs(24)
    call self%geo%init(cfg, mats, mesh, status)
    if (.not. (self%geo%on .and. status%ok())) return
    allocate(fault_side(mesh%n_faces))
    fault_side = .false.
    do e = 1, mesh%n_ifaces
      do s = 1, 2
        c = mesh%iface_cells(s, e)
        if (c < 1) cycle
        do k = 1, 6
          f = mesh%cell_faces(k, c)
          if (f < 1) cycle
          if (all([(any(mesh%face_nodes(:, f) == mesh%iface_nodes(n, s, e)), n = 1, 4)])) fault_side(f) = .true.
        end do
      end do
    end do
    allocate(faces(mesh%n_faces))
    n = 0
    do f = 1, mesh%n_faces
      if (.not. mesh%face_on_boundary(f) .or. fault_side(f)) cycle
      c = mesh%face_cells(1, f)
      if (c < 1 .or. c > mesh%cell_map%n_owned) cycle
      n = n + 1
      faces(n) = f
    end do
    allocate(self%geo_load(self%u%n_local()))
    self%geo_load = 0.0_rp
    do c = 1, mesh%cell_map%n_owned
      do a = 1, 8
        dofs(3*a-2:3*a) = self%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
      end do
      fe = 0.0_rp
      call in_situ_cell(self, mesh, c, fe)
      self%geo_load(dofs) = self%geo_load(dofs) + fe
    end do
    call in_situ_faces(self, mesh, faces(1:n), self%geo_load)
  end subroutine init_in_situ

  !> The &pressure_change groups pcs on mesh, with the Biot coefficients of
  !> the regions' materials: which group each local cell takes (a group
  !> with a point: the cells of its region in the point's fault block).
  !> status names a group whose region the mesh does not have, whose point
  !> lies outside the mesh or in another region, or two groups in one
  !> block. Call after init (every physics calls it: without groups, no
  !> change anywhere). Collective.
  subroutine init_pressure_changes(self, mesh, pcs, mats, status)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(pressure_change_config_t), intent(in) :: pcs(:)
    type(material_config_t), intent(in) :: mats(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: r, k, j, n, c, rpt
    integer(gp), allocatable :: blk(:)
    character(len=:), allocatable :: where
    n = size(mesh%region_names, kind=ip)
    self%pcs = pcs
    self%dp_now = [(0.0_rp, k = 1, size(pcs))]
    allocate(blk(size(pcs)))
    blk = 0
    do k = 1, size(pcs, kind=ip)
      where = "&pressure_change "//itoa(k)//" (region '"//trim(pcs(k)%region)//"'), variable point"
      r = mesh%region_id(pcs(k)%region)
      if (r == 0) then
        call status%set("&pressure_change on region '"//trim(pcs(k)%region)//"', which the mesh does not have "// &
                        "(its regions: "//mesh%region_list()//")")
        return
      end if
      if (pcs(k)%has_point) then
        call point_block(mesh, pcs(k)%point, blk(k), rpt, status, where)
        if (.not. status%ok()) return
        if (rpt /= r) then
          call status%set(where//": lies in region '"//trim(mesh%region_names(rpt))//"'")
          return
        end if
        do j = 1, k - 1
          if (blk(j) == blk(k) .and. pcs(j)%region == pcs(k)%region) then
            call status%set(where//": lies in the fault block of &pressure_change "//itoa(j)//"'s point")
            return
          end if
        end do
      end if
      do c = 1, mesh%n_cells
        if (mesh%cell_region(c) /= r) cycle
        if (pcs(k)%has_point .and. mesh%cell_block(c) /= blk(k)) cycle
        self%dp_cell(c) = k
      end do
    end do
    do r = 1, n
      do k = 1, size(mats, kind=ip)
        if (mats(k)%region == mesh%region_names(r)) self%dp_biot(r) = mats(k)%biot
      end do
    end do
  end subroutine init_pressure_changes

  !> The fault block blk and region reg of the cell that holds point p
  !> (the same on every rank); status: the point lies outside the mesh.
  !> Collective.
  subroutine point_block(mesh, p, blk, reg, status, where)
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: p(3)
    integer(gp), intent(out) :: blk
    integer(ip), intent(out) :: reg
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in) :: where
    integer(ip) :: c
    real(rp) :: xi(3)
    logical :: found
    call mesh%locate_point(p, c, xi, found)
    blk = 0
    reg = 0
    if (.not. found) then
      call status%set(where//": ("//trim(rtoa(p(1)))//', '//trim(rtoa(p(2)))//', '// &
                      trim(rtoa(p(3)))//') lies outside the mesh')
      return
    end if
    if (c > 0) then
      blk = mesh%cell_block(c)
      reg = mesh%cell_region(c)
    end if
    blk = mesh%comm%max(blk)
    reg = mesh%comm%max(reg)
  end subroutine point_block

  !> The pore pressure change at full load of local cell c [Pa] (0 outside
  !> the &pressure_change regions).
  real(rp) function pressure_change_at(self, mesh, c) result(dp)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    dp = 0.0_rp
    if (c < 1 .or. c > mesh%n_cells) return
    if (self%dp_cell(c) > 0) dp = self%dp_now(self%dp_cell(c))
  end function pressure_change_at

  !> The pore pressure change of every owned cell at load factor lf [Pa]
  !> (the output field 'pressure_change' of elasticity and contact).
  function pressure_change_field(self, mesh, lf) result(v)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: lf
    real(rp), allocatable :: v(:)
    integer(ip) :: c
    allocate(v(mesh%cell_map%n_owned))
    do c = 1, mesh%cell_map%n_owned
      v(c) = lf * self%pressure_change_at(mesh, c)
    end do
  end function pressure_change_field

  !> fe(24) += the in-situ load of owned cell c: its weight less the work of
  !> the in-situ total stress, integral of N rho g - B^T sigma_0 (not scaled
  !> by the load factor: the state is there before any load).
  subroutine in_situ_cell(self, mesh, c, fe)
    type(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c
    real(rp), intent(inout) :: fe(24)
    real(rp) :: x(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det, sig(3, 3), wt
    integer(ip) :: q, a, r
    call gauss_hex(2_ip, xi, w)
    x = mesh%coords(:, mesh%cell_nodes(:, c))
    r = mesh%cell_region(c)
    wt = self%geo%weight(r)
    do q = 1, 8
      call hex_gradients(x, xi(:, q), n, g, det)
      det = det * w(q)
      sig = self%geo%total_stress(r, dot_product(x(3, :), n))
      do a = 1, 8
        fe(3*a-2:3*a) = fe(3*a-2:3*a) - det * matmul(sig, g(:, a))
        fe(3*a) = fe(3*a) - det * n(a) * wt
      end do
    end do
  end subroutine in_situ_cell

  !> f_loc += the in-situ tractions sigma_0 n on the boundary faces the
  !> surrounding rock holds (faces): a model cut out of the ground stays
  !> in place under its own state whatever its boundary conditions.
  subroutine in_situ_faces(self, mesh, faces, f_loc)
    type(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: faces(:)
    real(rp), intent(inout) :: f_loc(:)
    real(rp) :: xiq(2, 4), wq(4), nq(4), dnq(2, 4), xf(3, 4), av(3), tr(3)
    integer(ip) :: k, f, q, a, r
    call gauss_quad(2_ip, xiq, wq)
    do k = 1, size(faces, kind=ip)
      f = faces(k)
      r = mesh%cell_region(mesh%face_cells(1, f))
      xf = mesh%coords(:, mesh%face_nodes(:, f))
      do q = 1, 4
        call quad_shape(xiq(:, q), nq, dnq)
        av = quad_area_vector(xf, xiq(:, q))
        tr = matmul(self%geo%total_stress(r, dot_product(xf(3, :), nq)), av) * wq(q)
        do a = 1, 4
          associate (d => self%u%dof(mesh%face_nodes(a, f), [1_ip, 2_ip, 3_ip]))
            f_loc(d) = f_loc(d) + nq(a) * tr
          end associate
        end do
      end do
    end do
  end subroutine in_situ_faces

  !> How far the in-situ state is from equilibrium on this mesh: the
  !> largest nodal force of its load (geo_load, free dofs only) over the
  !> largest nodal weight. Round-off for layers bounded
  !> by horizontal planes; with faults, the forces their tractions must carry.
  !> Collective.
  real(rp) function in_situ_imbalance(self, mesh) result(ratio)
    class(elasticity_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: f_loc(:), w_loc(:)
    real(rp) :: we(24), wmax
    integer(ip) :: c, a, dofs(24)
    type(parallel_comm_t) :: comm
    ratio = 0.0_rp
    if (.not. self%geo%on) return
    comm = mesh%comm
    f_loc = self%geo_load
    allocate(w_loc(self%u%n_local()))
    w_loc = 0.0_rp
    do c = 1, mesh%cell_map%n_owned
      do a = 1, 8
        dofs(3*a-2:3*a) = self%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
      end do
      we = 0.0_rp
      we(3::3) = self%geo%weight(mesh%cell_region(c)) * mesh%cell_volume(c) / 8.0_rp
      w_loc(dofs) = w_loc(dofs) + we
    end do
    call self%u%map%export_add(f_loc)
    call self%u%map%export_add(w_loc)
    associate (nown => self%u%n_owned())
      where (self%fixed(1:nown)) f_loc(1:nown) = 0.0_rp
      wmax = comm%max(maxval(abs(w_loc(1:nown)), dim=1))
      ratio = comm%max(maxval(abs(f_loc(1:nown)), dim=1)) / max(wmax, tiny(1.0_rp))
    end associate
  end function in_situ_imbalance

  !> Cauchy stress at the centre of each owned cell, from the displacement
  !> u_loc (all local dofs, ghosts up to date). Components in the order
  !> ParaView labels a 6-component symmetric tensor: xx, yy, zz, xy, yz, xz [Pa].
  subroutine cell_stress(self, mesh, u_loc, stress)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: u_loc(:)
    real(rp), intent(out) :: stress(:,:)
    real(rp) :: x(3, 8), n(8), g(3, 8), det, grad(3, 3), eps(3, 3), sig(3, 3), ue(3, 8)
    integer(ip) :: c, a, r
    do c = 1, mesh%cell_map%n_owned
      x = mesh%coords(:, mesh%cell_nodes(:, c))
      call hex_gradients(x, [0.0_rp, 0.0_rp, 0.0_rp], n, g, det)
      do a = 1, 8
        ue(:, a) = u_loc(self%u%dof(mesh%cell_nodes(a, c), [1, 2, 3]))
      end do
      grad = matmul(ue, transpose(g))          ! grad(i, j) = d u_i / d x_j
      eps = 0.5_rp * (grad + transpose(grad))
      r = mesh%cell_region(c)
      sig = 2.0_rp * self%mu(r) * eps
      do a = 1, 3
        sig(a, a) = sig(a, a) + self%lambda(r) * (eps(1,1) + eps(2,2) + eps(3,3))
      end do
      if (self%geo%on) sig = sig + self%geo%effective_stress(r, sum(x(3, :)) / 8.0_rp)
      stress(:, c) = [sig(1,1), sig(2,2), sig(3,3), sig(1,2), sig(2,3), sig(1,3)]
    end do
  end subroutine cell_stress

  !> Set status (the same on every rank) when a piece of the mesh, or a
  !> group of pieces joined by interface elements that hold (joins: pairs
  !> of piece labels, see rigid_modes), can move as a rigid body under the
  !> prescribed displacements. Collective.
  subroutine check_anchored(self, mesh, pieces, status, joins)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(mesh_pieces_t), intent(in) :: pieces
    type(error_status_t), intent(inout) :: status
    integer(gp), intent(in), optional :: joins(:,:)
    logical, allocatable :: fixed(:,:)
    integer(ip) :: i
    integer :: c
    allocate(fixed(3, mesh%n_nodes))
    do i = 1, mesh%n_nodes
      do c = 1, 3
        fixed(c, i) = self%fixed(self%u%dof(i, c))
      end do
    end do
    call check_rigid_modes(mesh, pieces, fixed, status, joins)
  end subroutine check_anchored

  !> The six rigid-body motions on the owned displacement dofs, (owned dofs,
  !> 6): translations in x, y, z, rotations about x, y, z around the centre
  !> of the mesh's bounding box, scaled by its size; zero on the prescribed
  !> dofs (the near-null space of the constrained K, for BoomerAMG's
  !> interpolation). Collective (the bounding box).
  function rigid_body_modes(self, mesh) result(m)
    class(elasticity_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: m(:,:)
    real(rp) :: lo(3), hi(3), x0(3), size_, y(3)
    integer(ip) :: nd, c, i
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    do c = 1, 3
      lo(c) = -comm%max(-minval(mesh%coords(c, :)))
      hi(c) = comm%max(maxval(mesh%coords(c, :)))
    end do
    x0 = (lo + hi) / 2.0_rp
    size_ = max(maxval(hi - lo), tiny(1.0_rp))
    allocate(m(self%u%n_owned(), 6))
    m = 0.0_rp
    do nd = 1, mesh%node_map%n_owned
      y = (mesh%coords(:, nd) - x0) / size_
      do c = 1, 3
        i = self%u%dof(nd, c)
        m(i, c) = 1.0_rp
      end do
      ! rotations: w x y for w = e_x, e_y, e_z
      m(self%u%dof(nd, 2_ip), 4) = -y(3)
      m(self%u%dof(nd, 3_ip), 4) = y(2)
      m(self%u%dof(nd, 1_ip), 5) = y(3)
      m(self%u%dof(nd, 3_ip), 5) = -y(1)
      m(self%u%dof(nd, 1_ip), 6) = -y(2)
      m(self%u%dof(nd, 2_ip), 6) = y(1)
    end do
    do i = 1, self%u%n_owned()
      if (self%fixed(i)) m(i, :) = 0.0_rp
    end do
  end function rigid_body_modes

  subroutine free(self)
    class(elasticity_t), intent(inout) :: self
    if (allocated(self%geo_load)) deallocate(self%geo_load)
    self%geo = geostatic_t()
    if (allocated(self%dp_cell)) deallocate(self%dp_cell, self%dp_biot, self%dp_now)
    if (allocated(self%pcs)) deallocate(self%pcs)
    call self%k%free()
    call self%u%free()
    if (allocated(self%rhs)) deallocate(self%rhs)
    if (allocated(self%lambda)) deallocate(self%lambda, self%mu, self%body)
    if (allocated(self%fixed)) deallocate(self%fixed, self%fixed_value, self%fixed_bc)
    if (allocated(self%trac_face)) deallocate(self%trac_face, self%trac_value, self%trac_bc, self%trac_normal)
    if (allocated(self%bcs)) deallocate(self%bcs, self%bc_factor)
  end subroutine free
end module elasticity
