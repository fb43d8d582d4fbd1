!> The distributed mesh: this rank's owned cells plus one layer of ghost cells
!> (every cell that shares a node with an owned cell), their nodes and faces.
!>
!> Ownership: a cell belongs to the rank METIS gave it; a node or a face to the
!> lowest rank among the cells that touch it. Global ids are renumbered so that
!> each rank owns a contiguous range (rank order, then the original order),
!> which is what hypre and the index maps want. Local numbering: owned first
!> (in global order), then ghosts (in global order). With this layer, every
!> cell that touches an owned node or face is local, so the matrix pattern of
!> owned rows is known without communication.
!>
!> Interface elements of faults (mesh.f90 explains their layout) belong to
!> the rank that owns their minus cell and are numbered like the cells. The
!> ghost layer grows across faults: the nodes of the owned cells are
!> "touched", and so are, for every interface element and position k, both
!> copies (k,1) and (k,2) as soon as one is (to the fixed point); a cell is
!> local when it has a touched node, an interface element when both its cells
!> are. So every interface element that touches an owned node, and every
!> interface element that shares a node with an owned one, is local with both
!> its cells: the contact rows of owned dofs are known without communication.
module dist_mesh
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use mesh, only: mesh_t
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients, hex_contains_point
  implicit none
  private

  public :: dist_mesh_t

  type :: dist_mesh_t
    type(parallel_comm_t) :: comm
    type(index_map_t) :: node_map, cell_map, face_map
    integer(ip) :: n_nodes = 0, n_cells = 0, n_faces = 0    !< local (owned + ghost)
    integer(gp) :: n_nodes_global = 0, n_cells_global = 0, n_faces_global = 0
    real(rp), allocatable :: coords(:,:)            !< (3, n_nodes)
    integer(ip), allocatable :: cell_nodes(:,:)     !< (8, n_cells) local node ids
    integer(ip), allocatable :: cell_region(:)      !< (n_cells)
    integer(ip), allocatable :: cell_owner(:)       !< (n_cells) owning rank
    !> (n_cells) the fault block of each cell: the cells of one region that
    !> faces not on a fault connect (a fault that cuts through the region
    !> seals it off; one that ends inside it does not) share a block, named
    !> by their smallest original cell id (partition-independent)
    integer(gp), allocatable :: cell_block(:)
    !> ids of the local nodes, cells and faces in the global mesh before the
    !> partition renumbered them: partition-independent ordering keys
    integer(gp), allocatable :: node_orig(:), cell_orig(:), face_orig(:)
    integer(ip), allocatable :: cell_faces(:,:)     !< (6, n_cells) local face ids
    integer(ip), allocatable :: cell_face_sign(:,:) !< (6, n_cells)
    integer(ip), allocatable :: face_nodes(:,:)     !< (4, n_faces) local node ids
    integer(ip), allocatable :: face_cells(:,:)     !< (2, n_faces) local cell ids, 0 = absent here or boundary
    logical, allocatable :: face_on_boundary(:)     !< (n_faces)
    character(len=name_len), allocatable :: region_names(:), set_names(:)
    integer(ip) :: n_sfaces = 0                     !< tagged quads whose face is local
    integer(ip), allocatable :: sface_face(:), sface_set(:)
    integer(ip), allocatable :: set_node_ptr(:), set_nodes(:)  !< local nodes on each set (CSR layout)
    ! interface elements (faults)
    type(index_map_t) :: iface_map                 !< owned interface elements, contiguous global ids
    integer(ip) :: n_ifaces = 0                    !< local (owned + ghost)
    integer(ip), allocatable :: iface_nodes(:,:,:) !< (4, 2, n_ifaces) local node ids
    integer(ip), allocatable :: iface_cells(:,:)   !< (2, n_ifaces) local cell ids: minus, plus
    integer(ip), allocatable :: iface_fault(:)     !< (n_ifaces) index into fault_names
    integer(gp), allocatable :: iface_orig(:)      !< original (pre-partition) ids: ordering keys
    character(len=name_len), allocatable :: fault_names(:)
  contains
    procedure :: build
    procedure :: n_owned_nodes
    procedure :: n_owned_cells
    procedure :: n_owned_faces
    procedure :: set_id
    procedure :: region_id
    procedure :: region_list
    procedure :: cell_volume
    procedure :: locate_point
    procedure :: node_keys
    procedure :: iface_keys
    procedure :: free
  end type dist_mesh_t

  !> Owners (ranks) and global ids, by global-mesh entity, while the mesh is
  !> distributed.
  type :: ownership_t
    integer(ip), allocatable :: node(:), face(:), iface(:)
    integer(gp), allocatable :: node_gid(:), cell_gid(:), face_gid(:), iface_gid(:)
  end type ownership_t

contains

  !> Distribute the global mesh held by rank 0 according to part (rank 0's
  !> arrays; other ranks pass an empty mesh and an unallocated part). Collective.
  subroutine build(self, comm, gmesh, part, status)
    class(dist_mesh_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_t), intent(inout) :: gmesh
    integer(ip), intent(inout), allocatable :: part(:)
    type(error_status_t), intent(inout) :: status
    type(ownership_t) :: own
    integer(ip), allocatable :: lcells(:), lnodes(:), lfaces(:)

    call self%free()
    self%comm = comm
    call bcast_mesh(comm, gmesh)
    if (.not. comm%is_root()) allocate(part(gmesh%n_cells))
    call comm%bcast(part)
    self%n_nodes_global = gmesh%n_nodes
    self%n_cells_global = gmesh%n_cells
    self%n_faces_global = gmesh%n_faces

    call find_owners(gmesh, part, comm%size, own)
    call local_entities(self, comm, gmesh, part, own, lcells, lnodes, lfaces)
    call local_topology(self, gmesh, lcells, lnodes, lfaces)
    call local_interfaces(self, comm, gmesh, own, lcells, lnodes)
    self%cell_region = gmesh%cell_region(lcells)
    self%cell_owner = part(lcells)
    self%cell_block = fault_blocks(gmesh, lcells)
    allocate(self%node_orig(self%n_nodes), self%cell_orig(self%n_cells), self%face_orig(self%n_faces))
    self%node_orig = int(lnodes, gp)
    self%cell_orig = int(lcells, gp)
    self%face_orig = int(lfaces, gp)

    if (.not. comm%is_root()) then
      call gmesh%free()
      deallocate(part)
    end if
    if (comm%any_true(self%cell_map%n_owned == 0)) &
      call status%set('distributed mesh: a rank has no cells (fewer cells than ranks?)')
  end subroutine build

  !> Owners of the nodes (the lowest rank among their cells'), faces (the
  !> lowest of their two cells'), cells (part) and interface elements (the
  !> owner of their first cell), and the contiguous global numbering by
  !> owner of each kind.
  subroutine find_owners(gmesh, part, n_ranks, own)
    type(mesh_t), intent(in) :: gmesh
    integer(ip), intent(in) :: part(:)
    integer, intent(in) :: n_ranks
    type(ownership_t), intent(out) :: own
    integer(ip) :: c, k, n, f, e
    allocate(own%node(gmesh%n_nodes), own%face(gmesh%n_faces), own%iface(gmesh%n_ifaces))
    own%node = huge(1_ip)
    do c = 1, gmesh%n_cells
      do k = 1, 8
        n = gmesh%cell_nodes(k, c)
        own%node(n) = min(own%node(n), part(c))
      end do
    end do
    do f = 1, gmesh%n_faces
      own%face(f) = part(gmesh%face_cells(1, f))
      if (gmesh%face_cells(2, f) > 0) own%face(f) = min(own%face(f), part(gmesh%face_cells(2, f)))
    end do
    do e = 1, gmesh%n_ifaces
      own%iface(e) = part(gmesh%iface_cells(1, e))
    end do
    own%node_gid = renumber(own%node, n_ranks)
    own%cell_gid = renumber(part, n_ranks)
    own%face_gid = renumber(own%face, n_ranks)
    own%iface_gid = renumber(own%iface, n_ranks)
  end subroutine find_owners

  !> The local cells (owned, then the ghosts that share a node with an owned
  !> cell, across faults too), nodes and faces (those of the local cells),
  !> as lists of global-mesh ids, owned first; their index maps.
  subroutine local_entities(self, comm, gmesh, part, own, lcells, lnodes, lfaces)
    type(dist_mesh_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_t), intent(in) :: gmesh
    integer(ip), intent(in) :: part(:)
    type(ownership_t), intent(in) :: own
    integer(ip), allocatable, intent(out) :: lcells(:), lnodes(:), lfaces(:)
    logical, allocatable :: touched(:), is_local(:)
    integer(ip) :: me, c, k, nown, i, e
    logical :: grew
    me = comm%rank
    allocate(touched(gmesh%n_nodes), is_local(gmesh%n_cells))
    touched = .false.
    do c = 1, gmesh%n_cells
      if (part(c) == me) touched(gmesh%cell_nodes(:, c)) = .true.
    end do
    ! across faults: both copies of a node position, to the fixed point
    grew = gmesh%n_ifaces > 0
    do while (grew)
      grew = .false.
      do e = 1, gmesh%n_ifaces
        do k = 1, 4
          if (touched(gmesh%iface_nodes(k, 1, e)) .neqv. touched(gmesh%iface_nodes(k, 2, e))) then
            touched(gmesh%iface_nodes(k, :, e)) = .true.
            grew = .true.
          end if
        end do
      end do
    end do
    do c = 1, gmesh%n_cells
      is_local(c) = part(c) == me .or. any(touched(gmesh%cell_nodes(:, c)))
    end do
    call ordered_local(is_local, part == me, own%cell_gid, lcells)
    nown = count(part == me)
    self%n_cells = size(lcells, kind=ip)
    call self%cell_map%init(comm, nown, own%cell_gid(lcells(nown+1:)))

    touched = .false.
    do i = 1, self%n_cells
      touched(gmesh%cell_nodes(:, lcells(i))) = .true.
    end do
    call ordered_local(touched, own%node == me, own%node_gid, lnodes)
    nown = count(own%node == me)
    self%n_nodes = size(lnodes, kind=ip)
    call self%node_map%init(comm, nown, own%node_gid(lnodes(nown+1:)))

    deallocate(is_local)
    allocate(is_local(gmesh%n_faces))
    is_local = .false.
    do i = 1, self%n_cells
      is_local(gmesh%cell_faces(:, lcells(i))) = .true.
    end do
    call ordered_local(is_local, own%face == me, own%face_gid, lfaces)
    nown = count(own%face == me)
    self%n_faces = size(lfaces, kind=ip)
    call self%face_map%init(comm, nown, own%face_gid(lfaces(nown+1:)))
  end subroutine local_entities

  !> Local coordinates and connectivity (cells, faces, node and surface
  !> sets) in local numbering.
  subroutine local_topology(self, gmesh, lcells, lnodes, lfaces)
    type(dist_mesh_t), intent(inout) :: self
    type(mesh_t), intent(in) :: gmesh
    integer(ip), intent(in) :: lcells(:), lnodes(:), lfaces(:)
    integer(ip), allocatable :: g2l(:)
    integer(ip) :: i, j, s, f
    allocate(g2l(max(gmesh%n_nodes, gmesh%n_cells, gmesh%n_faces)))
    g2l = 0
    do i = 1, self%n_nodes
      g2l(lnodes(i)) = i
    end do
    allocate(self%coords(3, self%n_nodes))
    self%coords = gmesh%coords(:, lnodes)
    allocate(self%cell_nodes(8, self%n_cells), self%face_nodes(4, self%n_faces))
    do i = 1, self%n_cells
      self%cell_nodes(:, i) = g2l(gmesh%cell_nodes(:, lcells(i)))
    end do
    do i = 1, self%n_faces
      self%face_nodes(:, i) = g2l(gmesh%face_nodes(:, lfaces(i)))
    end do
    ! node sets: local nodes on the tagged quads of each set
    self%set_names = gmesh%set_names
    self%region_names = gmesh%region_names
    allocate(self%set_node_ptr(size(gmesh%set_names) + 1))
    call node_sets(self, gmesh, g2l)

    g2l = 0
    do i = 1, self%n_faces
      g2l(lfaces(i)) = i
    end do
    allocate(self%cell_faces(6, self%n_cells), self%cell_face_sign(6, self%n_cells))
    do i = 1, self%n_cells
      self%cell_faces(:, i) = g2l(gmesh%cell_faces(:, lcells(i)))
      self%cell_face_sign(:, i) = gmesh%cell_face_sign(:, lcells(i))
    end do
    self%n_sfaces = count(g2l(gmesh%sface_face) > 0)
    allocate(self%sface_face(self%n_sfaces), self%sface_set(self%n_sfaces))
    j = 0
    do s = 1, gmesh%n_sfaces
      if (g2l(gmesh%sface_face(s)) > 0) then
        j = j + 1
        self%sface_face(j) = g2l(gmesh%sface_face(s))
        self%sface_set(j) = gmesh%sface_set(s)
      end if
    end do

    g2l = 0
    do i = 1, self%n_cells
      g2l(lcells(i)) = i
    end do
    allocate(self%face_cells(2, self%n_faces), self%face_on_boundary(self%n_faces))
    do i = 1, self%n_faces
      f = lfaces(i)
      self%face_on_boundary(i) = gmesh%face_cells(2, f) == 0
      self%face_cells(1, i) = g2l(gmesh%face_cells(1, f))
      self%face_cells(2, i) = 0
      if (gmesh%face_cells(2, f) > 0) self%face_cells(2, i) = g2l(gmesh%face_cells(2, f))
    end do
  end subroutine local_topology

  !> The local interface elements (both cells local), owned first, their
  !> index map, cells, nodes and faults.
  subroutine local_interfaces(self, comm, gmesh, own, lcells, lnodes)
    type(dist_mesh_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_t), intent(in) :: gmesh
    type(ownership_t), intent(in) :: own
    integer(ip), intent(in) :: lcells(:), lnodes(:)
    integer(ip), allocatable :: g2l(:), lifaces(:)
    logical, allocatable :: is_local(:)
    integer(ip) :: i, e, nown
    allocate(g2l(max(gmesh%n_nodes, gmesh%n_cells)))
    g2l = 0
    do i = 1, self%n_cells
      g2l(lcells(i)) = i
    end do
    allocate(is_local(gmesh%n_ifaces))
    do e = 1, gmesh%n_ifaces
      is_local(e) = all(g2l(gmesh%iface_cells(:, e)) > 0)
    end do
    call ordered_local(is_local, own%iface == comm%rank, own%iface_gid, lifaces)
    nown = count(own%iface == comm%rank)
    self%n_ifaces = size(lifaces, kind=ip)
    call self%iface_map%init(comm, nown, own%iface_gid(lifaces(nown+1:)))
    allocate(self%iface_cells(2, self%n_ifaces), self%iface_nodes(4, 2, self%n_ifaces))
    allocate(self%iface_fault(self%n_ifaces), self%iface_orig(self%n_ifaces))
    do i = 1, self%n_ifaces
      self%iface_cells(:, i) = g2l(gmesh%iface_cells(:, lifaces(i)))
      self%iface_fault(i) = gmesh%iface_fault(lifaces(i))
    end do
    self%iface_orig = int(lifaces, gp)
    g2l = 0
    do i = 1, self%n_nodes
      g2l(lnodes(i)) = i
    end do
    do i = 1, self%n_ifaces
      self%iface_nodes(:, 1, i) = g2l(gmesh%iface_nodes(:, 1, lifaces(i)))
      self%iface_nodes(:, 2, i) = g2l(gmesh%iface_nodes(:, 2, lifaces(i)))
    end do
    if (allocated(gmesh%fault_names)) then
      self%fault_names = gmesh%fault_names
    else
      allocate(self%fault_names(0))
    end if
  end subroutine local_interfaces

  !> The fault block (dist_mesh_t%cell_block) of each of the global mesh's
  !> cells lcells: components of the graph of the cells, two cells of one
  !> region joined by each face they share (faces on a fault are two
  !> boundary faces, so they join nothing), found by union-find.
  function fault_blocks(gmesh, lcells) result(blk)
    type(mesh_t), intent(in) :: gmesh
    integer(ip), intent(in) :: lcells(:)
    integer(gp), allocatable :: blk(:)
    integer(ip), allocatable :: root(:)
    integer(ip) :: f, a, b, i
    allocate(root(gmesh%n_cells))
    root = [(i, i = 1, gmesh%n_cells)]
    do f = 1, gmesh%n_faces
      if (gmesh%face_cells(2, f) == 0) cycle
      if (gmesh%cell_region(gmesh%face_cells(1, f)) /= gmesh%cell_region(gmesh%face_cells(2, f))) cycle
      a = find(gmesh%face_cells(1, f))
      b = find(gmesh%face_cells(2, f))
      ! the smaller id is the root: a block is named by its smallest cell
      if (a < b) then
        root(b) = a
      else if (b < a) then
        root(a) = b
      end if
    end do
    allocate(blk(size(lcells)))
    do i = 1, size(lcells, kind=ip)
      blk(i) = int(find(lcells(i)), gp)
    end do
  contains
    integer(ip) function find(c)
      integer(ip), intent(in) :: c
      integer(ip) :: x
      x = c
      do while (root(x) /= x)
        root(x) = root(root(x))      ! path halving
        x = root(x)
      end do
      find = x
    end function find
  end function fault_blocks

  !> Contiguous global numbering by owner: owner ranks in order, and the
  !> original order within each rank. Returns 1-based global ids.
  function renumber(owner, np) result(gid)
    integer(ip), intent(in) :: owner(:)
    integer, intent(in) :: np
    integer(gp), allocatable :: gid(:)
    integer(gp) :: next(0:np)
    integer(ip) :: i
    next = 0
    do i = 1, size(owner, kind=ip)
      next(owner(i) + 1) = next(owner(i) + 1) + 1
    end do
    next(0) = 1
    do i = 1, np
      next(i) = next(i) + next(i-1)
    end do
    allocate(gid(size(owner)))
    do i = 1, size(owner, kind=ip)
      gid(i) = next(owner(i))
      next(owner(i)) = next(owner(i)) + 1
    end do
  end function renumber

  !> Original ids of the local entities: owned ones first, then ghosts in
  !> ascending global id.
  subroutine ordered_local(is_local, is_owned, gid, ids)
    logical, intent(in) :: is_local(:), is_owned(:)
    integer(gp), intent(in) :: gid(:)
    integer(ip), allocatable, intent(out) :: ids(:)
    integer(ip), allocatable :: ghosts(:), pos(:)
    integer(gp), allocatable :: key(:)
    integer(ip) :: i, k, nown, ngh
    nown = count(is_owned)
    ngh = count(is_local .and. .not. is_owned)
    allocate(ids(nown + ngh), ghosts(ngh), key(ngh), pos(ngh))
    k = 0
    do i = 1, size(is_owned, kind=ip)
      if (is_owned(i)) then
        k = k + 1
        ids(k) = i
      end if
    end do
    k = 0
    do i = 1, size(is_owned, kind=ip)
      if (is_local(i) .and. .not. is_owned(i)) then
        k = k + 1
        ghosts(k) = i
        key(k) = gid(i)
      end if
    end do
    call sort_by_key(key, pos)
    ids(nown+1:) = ghosts(pos)
  end subroutine ordered_local

  subroutine sort_by_key(key, pos)
    use index_map, only: sort_gids
    integer(gp), intent(inout) :: key(:)
    integer(ip), intent(out) :: pos(:)
    call sort_gids(key, pos)
  end subroutine sort_by_key

  !> For each tagged set, the local nodes lying on its quads.
  subroutine node_sets(self, gmesh, g2l)
    type(dist_mesh_t), intent(inout) :: self
    type(mesh_t), intent(in) :: gmesh
    integer(ip), intent(in) :: g2l(:)
    logical, allocatable :: on(:)
    integer(ip) :: ns, s, q, k, n, total
    integer(ip), allocatable :: lists(:)
    ns = size(gmesh%set_names, kind=ip)
    allocate(on(self%n_nodes))
    allocate(lists(0))
    self%set_node_ptr(1) = 1
    total = 0
    do s = 1, ns
      on = .false.
      do q = 1, gmesh%n_sfaces
        if (gmesh%sface_set(q) /= s) cycle
        do k = 1, 4
          n = g2l(gmesh%sface_nodes(k, q))
          if (n > 0) on(n) = .true.
        end do
      end do
      lists = [lists, pack([(k, k = 1, self%n_nodes)], on)]
      total = total + count(on)
      self%set_node_ptr(s + 1) = total + 1
    end do
    self%set_nodes = lists
  end subroutine node_sets

  !> Broadcast rank 0's global mesh to every rank.
  subroutine bcast_mesh(comm, m)
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_t), intent(inout) :: m
    integer(ip) :: sizes(8), i
    integer(ip), allocatable :: buf(:,:)
    if (comm%is_root()) then
      ! a mesh without faults: empty interface arrays, so that every rank sees the same
      if (.not. allocated(m%iface_nodes)) then
        m%n_ifaces = 0
        allocate(m%iface_nodes(4, 2, 0), m%iface_cells(2, 0), m%iface_fault(0))
      end if
      if (.not. allocated(m%fault_names)) allocate(m%fault_names(0))
    end if
    if (comm%size == 1) return
    if (comm%is_root()) sizes = [m%n_nodes, m%n_cells, m%n_sfaces, m%n_faces, &
                                 size(m%region_names, kind=ip), size(m%set_names, kind=ip), &
                                 m%n_ifaces, size(m%fault_names, kind=ip)]
    call comm%bcast(sizes)
    if (.not. comm%is_root()) then
      call m%free()
      m%n_nodes = sizes(1); m%n_cells = sizes(2); m%n_sfaces = sizes(3); m%n_faces = sizes(4)
      allocate(m%coords(3, m%n_nodes), m%cell_nodes(8, m%n_cells), m%cell_region(m%n_cells))
      allocate(m%sface_nodes(4, m%n_sfaces), m%sface_set(m%n_sfaces), m%sface_face(m%n_sfaces))
      allocate(m%face_nodes(4, m%n_faces), m%face_cells(2, m%n_faces))
      allocate(m%cell_faces(6, m%n_cells), m%cell_face_sign(6, m%n_cells))
      allocate(m%region_names(sizes(5)), m%set_names(sizes(6)))
      m%n_ifaces = sizes(7)
      allocate(m%iface_nodes(4, 2, m%n_ifaces), m%iface_cells(2, m%n_ifaces), m%iface_fault(m%n_ifaces))
      allocate(m%fault_names(sizes(8)))
    end if
    call comm%bcast(m%coords)
    call comm%bcast(m%cell_nodes)
    call comm%bcast(m%cell_region)
    call comm%bcast(m%sface_nodes)
    call comm%bcast(m%sface_set)
    call comm%bcast(m%sface_face)
    call comm%bcast(m%face_nodes)
    call comm%bcast(m%face_cells)
    call comm%bcast(m%cell_faces)
    call comm%bcast(m%cell_face_sign)
    do i = 1, sizes(5)
      call comm%bcast(m%region_names(i))
    end do
    do i = 1, sizes(6)
      call comm%bcast(m%set_names(i))
    end do
    call comm%bcast(m%iface_cells)
    call comm%bcast(m%iface_fault)
    ! one message for the (4, 2, n) node ids
    allocate(buf(8, m%n_ifaces))
    if (comm%is_root()) buf = reshape(m%iface_nodes, [8_ip, m%n_ifaces])
    call comm%bcast(buf)
    m%iface_nodes = reshape(buf, [4_ip, 2_ip, m%n_ifaces])
    do i = 1, sizes(8)
      call comm%bcast(m%fault_names(i))
    end do
  end subroutine bcast_mesh

  integer(ip) function n_owned_nodes(self)
    class(dist_mesh_t), intent(in) :: self
    n_owned_nodes = self%node_map%n_owned
  end function n_owned_nodes

  integer(ip) function n_owned_cells(self)
    class(dist_mesh_t), intent(in) :: self
    n_owned_cells = self%cell_map%n_owned
  end function n_owned_cells

  integer(ip) function n_owned_faces(self)
    class(dist_mesh_t), intent(in) :: self
    n_owned_faces = self%face_map%n_owned
  end function n_owned_faces

  !> Index of the named tagged set, 0 if none.
  integer(ip) function set_id(self, name)
    class(dist_mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(ip) :: i
    set_id = 0
    do i = 1, size(self%set_names, kind=ip)
      if (self%set_names(i) == name) set_id = i
    end do
  end function set_id

  !> The region names, quoted and separated by commas (for messages).
  function region_list(self) result(s)
    class(dist_mesh_t), intent(in) :: self
    character(len=:), allocatable :: s
    integer :: r
    s = ''
    do r = 1, size(self%region_names)
      if (r > 1) s = s//', '
      s = s//"'"//trim(self%region_names(r))//"'"
    end do
  end function region_list

  !> Index of the named region, 0 if none.
  integer(ip) function region_id(self, name)
    class(dist_mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(ip) :: i
    region_id = 0
    do i = 1, size(self%region_names, kind=ip)
      if (self%region_names(i) == name) region_id = i
    end do
  end function region_id

  !> The owned cell that holds point p: of several cells holding it (a
  !> point on a face, edge or node), the first in the original numbering,
  !> so that the choice does not depend on the partition. cell is that
  !> cell's local id on the rank that owns it and 0 on the others, xi its
  !> reference coordinates of p there (0 elsewhere); found (on every rank):
  !> whether some cell holds p. Collective.
  subroutine locate_point(self, p, cell, xi, found)
    class(dist_mesh_t), intent(in) :: self
    real(rp), intent(in) :: p(3)
    integer(ip), intent(out) :: cell
    real(rp), intent(out) :: xi(3)
    logical, intent(out) :: found
    integer(ip) :: c
    integer(gp) :: best, key
    real(rp) :: xc(3)
    best = huge(1_gp)
    cell = 0
    xi = 0.0_rp
    do c = 1, self%cell_map%n_owned
      if (self%cell_orig(c) >= best) cycle
      if (.not. hex_contains_point(self%coords(:, self%cell_nodes(:, c)), p, xc)) cycle
      best = self%cell_orig(c)
      cell = c
      xi = xc
    end do
    key = -self%comm%max(-best)
    found = key /= huge(1_gp)
    if (key /= best) then
      cell = 0
      xi = 0.0_rp
    end if
  end subroutine locate_point

  !> Volume of local cell c [m^3] (2x2x2 Gauss, exact for trilinear maps).
  real(rp) function cell_volume(self, c)
    class(dist_mesh_t), intent(in) :: self
    integer(ip), intent(in) :: c
    real(rp) :: xi(3, 8), w(8), n(8), g(3, 8), det
    integer :: q
    call gauss_hex(2_ip, xi, w)
    cell_volume = 0.0_rp
    do q = 1, 8
      call hex_gradients(self%coords(:, self%cell_nodes(:, c)), xi(:, q), n, g, det)
      cell_volume = cell_volume + det * w(q)
    end do
  end function cell_volume

  subroutine free(self)
    class(dist_mesh_t), intent(inout) :: self
    call self%node_map%free()
    call self%cell_map%free()
    call self%face_map%free()
    call self%iface_map%free()
    if (allocated(self%coords)) deallocate(self%coords)
    if (allocated(self%cell_nodes)) deallocate(self%cell_nodes)
    if (allocated(self%cell_region)) deallocate(self%cell_region)
    if (allocated(self%cell_block)) deallocate(self%cell_block)
    if (allocated(self%cell_owner)) deallocate(self%cell_owner)
    if (allocated(self%cell_faces)) deallocate(self%cell_faces)
    if (allocated(self%cell_face_sign)) deallocate(self%cell_face_sign)
    if (allocated(self%face_nodes)) deallocate(self%face_nodes)
    if (allocated(self%face_cells)) deallocate(self%face_cells)
    if (allocated(self%face_on_boundary)) deallocate(self%face_on_boundary)
    if (allocated(self%region_names)) deallocate(self%region_names)
    if (allocated(self%set_names)) deallocate(self%set_names)
    if (allocated(self%sface_face)) deallocate(self%sface_face)
    if (allocated(self%sface_set)) deallocate(self%sface_set)
    if (allocated(self%set_node_ptr)) deallocate(self%set_node_ptr)
    if (allocated(self%set_nodes)) deallocate(self%set_nodes)
    if (allocated(self%node_orig)) deallocate(self%node_orig, self%cell_orig, self%face_orig)
    if (allocated(self%iface_nodes)) deallocate(self%iface_nodes)
    if (allocated(self%iface_cells)) deallocate(self%iface_cells)
    if (allocated(self%iface_fault)) deallocate(self%iface_fault)
    if (allocated(self%iface_orig)) deallocate(self%iface_orig)
    if (allocated(self%fault_names)) deallocate(self%fault_names)
    self%n_ifaces = 0
    self%n_nodes = 0
    self%n_cells = 0
    self%n_faces = 0
    self%n_sfaces = 0
  end subroutine free

  !> Partition-independent ordering keys of the dofs of the owned nodes with
  !> ncomp interleaved components: ncomp (original node id - 1) + c.
  subroutine node_keys(self, ncomp, keys)
    class(dist_mesh_t), intent(in) :: self
    integer, intent(in) :: ncomp
    integer(gp), allocatable, intent(out) :: keys(:)
    integer(ip) :: e, c
    allocate(keys(ncomp * self%node_map%n_owned))
    do e = 1, self%node_map%n_owned
      do c = 1, ncomp
        keys(ncomp*(e-1) + c) = ncomp * (self%node_orig(e) - 1) + c
      end do
    end do
  end subroutine node_keys

  !> Partition-independent ordering keys of the 3 dofs (e.g. the traction
  !> components) of each owned interface element: 3 (original id - 1) + c.
  subroutine iface_keys(self, keys)
    class(dist_mesh_t), intent(in) :: self
    integer(gp), allocatable, intent(out) :: keys(:)
    integer(ip) :: e, c
    allocate(keys(3 * self%iface_map%n_owned))
    do e = 1, self%iface_map%n_owned
      do c = 1, 3
        keys(3*(e-1) + c) = 3 * (self%iface_orig(e) - 1) + c
      end do
    end do
  end subroutine iface_keys
end module dist_mesh
