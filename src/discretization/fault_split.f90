!> Faults and fractures in the global mesh: tagged surfaces become interface
!> elements, and the nodes on them are split so that the two sides can open
!> and slide (layout and orientation of the interface elements: mesh.f90).
!>
!> One rule handles tips, intersections and faults that reach the boundary:
!> for each node on a fault quad, its cells are grouped into connected
!> components, two cells being connected when they share a face that contains
!> the node and is not a fault quad. The component with the lowest cell id
!> keeps the node; each further one (in order of its lowest cell id) gets a
!> new node with the same coordinates, appended after the existing nodes
!> (nodes in ascending id). A fracture tip inside the domain has one component
!> (not split), a node of a fault that cuts through to the boundary two, a
!> node on the crossing line of two faults up to four. The result depends only
!> on the input mesh.
module fault_split
  use kinds, only: rp, ip, name_len, msg_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t, hex_face_nodes
  implicit none
  private

  public :: split_faults

contains

  !> Turn the tagged surface sets fault_names(:) of mesh (faces built) into
  !> interface elements with split nodes; the other tagged quads follow their
  !> cell's new node ids, the fault sets leave the set lists, and the faces are
  !> rebuilt. Each set must exist and hold only interior faces. n_split, if
  !> present, returns the number of original nodes that were split (the
  !> number of nodes added is the growth of mesh%n_nodes).
  subroutine split_faults(mesh, fault_names, status, n_split)
    type(mesh_t), intent(inout) :: mesh
    character(len=*), intent(in) :: fault_names(:)
    type(error_status_t), intent(inout) :: status
    integer(ip), intent(out), optional :: n_split
    integer(ip), allocatable :: face_fault(:), set_fault(:), ptr(:), cells(:), new_id(:), old_cells(:,:)
    integer(ip) :: nf, i, q, f, n_added, nsplit
    character(len=msg_len) :: m

    if (present(n_split)) n_split = 0
    nf = size(fault_names, kind=ip)
    if (nf == 0) return
    if (.not. allocated(mesh%face_cells)) then
      call status%set('fault split: the mesh faces are not built')
      return
    end if
    ! which set is which fault, and which face is on which fault
    allocate(set_fault(size(mesh%set_names)), face_fault(mesh%n_faces))
    set_fault = 0
    face_fault = 0
    do i = 1, nf
      if (any(fault_names(1:i-1) == fault_names(i))) then
        call status%set('fault split: fault "'//trim(fault_names(i))//'" is named twice')
        return
      end if
      q = mesh%set_id(fault_names(i))
      if (q == 0) then
        call status%set('fault split: the mesh has no surface set "'//trim(fault_names(i))//'" for the fault of '// &
                        'that name')
        return
      end if
      set_fault(q) = i
      if (count(mesh%sface_set == q) == 0) then
        call status%set('fault split: the surface set "'//trim(fault_names(i))//'" of a fault has no quads')
        return
      end if
    end do
    do q = 1, mesh%n_sfaces
      i = set_fault(mesh%sface_set(q))
      if (i == 0) cycle
      f = mesh%sface_face(q)
      if (mesh%face_cells(2, f) == 0) then
        write(m, '(a,i0,a)') 'fault split: quad ', q, ' of the fault "'//trim(fault_names(i))// &
          '" lies on the boundary of the mesh: a fault must be made of interior faces (shared by two cells)'
        call status%set(m)
        return
      end if
      if (face_fault(f) /= 0) then
        write(m, '(a,i0,a)') 'fault split: quad ', q, ' of the fault "'//trim(fault_names(i))// &
          '" is also a quad of the fault "'//trim(fault_names(face_fault(f)))//'" (or listed twice)'
        call status%set(m)
        return
      end if
      face_fault(f) = i
      call check_area(mesh, q, fault_names(i), status)
      if (.not. status%ok()) return
    end do

    ! new node id of each (fault node, incident cell)
    call node_cells(mesh, face_fault, ptr, cells)
    call components(mesh, face_fault, ptr, cells, new_id, n_added, nsplit)
    old_cells = mesh%cell_nodes
    call apply_split(mesh, ptr, cells, new_id, n_added)
    call build_ifaces(mesh, fault_names, set_fault, old_cells)
    call drop_fault_sets(mesh, set_fault, old_cells)
    call mesh%build_faces(status)
    if (present(n_split)) n_split = nsplit
  end subroutine split_faults

  !> For every node on a fault face, its incident cells in ascending order
  !> (CSR: cells(ptr(n):ptr(n+1)-1); empty for the other nodes).
  subroutine node_cells(mesh, face_fault, ptr, cells)
    type(mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: face_fault(:)
    integer(ip), allocatable, intent(out) :: ptr(:), cells(:)
    logical, allocatable :: on_fault(:)
    integer(ip), allocatable :: fill(:)
    integer(ip) :: f, c, k, n
    allocate(on_fault(mesh%n_nodes), ptr(mesh%n_nodes + 1), fill(mesh%n_nodes))
    on_fault = .false.
    do f = 1, mesh%n_faces
      if (face_fault(f) /= 0) on_fault(mesh%face_nodes(:, f)) = .true.
    end do
    fill = 0
    do c = 1, mesh%n_cells
      do k = 1, 8
        n = mesh%cell_nodes(k, c)
        if (on_fault(n)) fill(n) = fill(n) + 1
      end do
    end do
    ptr(1) = 1
    do n = 1, mesh%n_nodes
      ptr(n + 1) = ptr(n) + fill(n)
    end do
    allocate(cells(ptr(mesh%n_nodes + 1) - 1))
    fill = ptr(1:mesh%n_nodes)
    do c = 1, mesh%n_cells
      do k = 1, 8
        n = mesh%cell_nodes(k, c)
        if (on_fault(n)) then
          cells(fill(n)) = c
          fill(n) = fill(n) + 1
        end if
      end do
    end do
  end subroutine node_cells

  !> Connected components of the cells around each fault node; new_id(j) is
  !> the node id that cell cells(j) uses after the split.
  subroutine components(mesh, face_fault, ptr, cells, new_id, n_added, n_split)
    type(mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: face_fault(:), ptr(:), cells(:)
    integer(ip), allocatable, intent(out) :: new_id(:)
    integer(ip), intent(out) :: n_added, n_split
    integer(ip), allocatable :: comp(:), stack(:)
    integer(ip) :: n, j0, nc, i, top, c, lf, f, other, ncomp, j
    allocate(new_id(size(cells)))
    n_added = 0
    n_split = 0
    do n = 1, mesh%n_nodes
      j0 = ptr(n) - 1
      nc = ptr(n + 1) - ptr(n)
      if (nc == 0) cycle
      if (allocated(comp)) deallocate(comp, stack)
      allocate(comp(nc), stack(nc))
      comp = 0
      ncomp = 0
      do i = 1, nc
        if (comp(i) /= 0) cycle
        ncomp = ncomp + 1
        comp(i) = ncomp
        top = 1
        stack(1) = i
        do while (top > 0)
          c = cells(j0 + stack(top))
          top = top - 1
          do lf = 1, 6
            if (all(mesh%cell_nodes(hex_face_nodes(:, lf), c) /= n)) cycle
            f = mesh%cell_faces(lf, c)
            if (face_fault(f) /= 0 .or. mesh%face_cells(2, f) == 0) cycle
            other = mesh%face_cells(1, f)
            if (other == c) other = mesh%face_cells(2, f)
            do j = 1, nc
              if (cells(j0 + j) == other) exit
            end do
            if (comp(j) == 0) then
              comp(j) = ncomp
              top = top + 1
              stack(top) = j
            end if
          end do
        end do
      end do
      do i = 1, nc
        if (comp(i) == 1) then
          new_id(j0 + i) = n
        else
          new_id(j0 + i) = mesh%n_nodes + n_added + comp(i) - 1
        end if
      end do
      n_added = n_added + ncomp - 1
      if (ncomp > 1) n_split = n_split + 1
    end do
  end subroutine components

  !> New nodes (copies of the split ones) and the cells' new node ids.
  subroutine apply_split(mesh, ptr, cells, new_id, n_added)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: ptr(:), cells(:), new_id(:), n_added
    real(rp), allocatable :: x(:,:)
    integer(ip) :: n, j, k, c, n_old
    n_old = mesh%n_nodes
    allocate(x(3, n_old + n_added))
    x(:, 1:n_old) = mesh%coords
    do n = 1, n_old
      do j = ptr(n), ptr(n + 1) - 1
        c = cells(j)
        if (new_id(j) /= n) x(:, new_id(j)) = mesh%coords(:, n)
        do k = 1, 8
          if (mesh%cell_nodes(k, c) == n) mesh%cell_nodes(k, c) = new_id(j)
        end do
      end do
    end do
    call move_alloc(x, mesh%coords)
    mesh%n_nodes = n_old + n_added
  end subroutine apply_split

  !> One interface element per fault quad, ordered by fault then by quad;
  !> the minus cell follows the orientation rule of mesh.f90.
  subroutine build_ifaces(mesh, fault_names, set_fault, old_cells)
    type(mesh_t), intent(inout) :: mesh
    character(len=*), intent(in) :: fault_names(:)
    integer(ip), intent(in) :: set_fault(:), old_cells(:,:)
    integer(ip) :: nf, i, q, f, e, a, b, la, lb, k, pos(4), orig(4)
    real(rp) :: x(3, 4), nrm(3)
    nf = size(fault_names, kind=ip)
    mesh%n_ifaces = count(set_fault(mesh%sface_set) /= 0)
    if (allocated(mesh%iface_nodes)) deallocate(mesh%iface_nodes, mesh%iface_cells, mesh%iface_fault)
    allocate(mesh%iface_nodes(4, 2, mesh%n_ifaces), mesh%iface_cells(2, mesh%n_ifaces))
    allocate(mesh%iface_fault(mesh%n_ifaces))
    allocate(mesh%fault_names(nf))
    mesh%fault_names = fault_names
    e = 0
    do i = 1, nf
      do q = 1, mesh%n_sfaces
        if (set_fault(mesh%sface_set(q)) /= i) cycle
        f = mesh%sface_face(q)
        e = e + 1
        a = mesh%face_cells(1, f)
        b = mesh%face_cells(2, f)
        la = local_face(mesh, a, f)
        x = mesh%coords(:, mesh%cell_nodes(hex_face_nodes(:, la), a))
        nrm = cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))
        nrm = nrm / norm2(nrm)
        if (.not. points_up(nrm)) then
          k = a; a = b; b = k
          la = local_face(mesh, a, f)
        end if
        lb = local_face(mesh, b, f)
        mesh%iface_cells(:, e) = [a, b]
        mesh%iface_fault(e) = i
        mesh%iface_nodes(:, 1, e) = mesh%cell_nodes(hex_face_nodes(:, la), a)
        ! the plus copy of each minus node: the same original node in cell b
        orig = old_cells(hex_face_nodes(:, la), a)
        do k = 1, 4
          pos(k) = findloc(old_cells(hex_face_nodes(:, lb), b), orig(k), dim=1)
        end do
        mesh%iface_nodes(:, 2, e) = mesh%cell_nodes(hex_face_nodes(pos, lb), b)
      end do
    end do
  end subroutine build_ifaces

  !> Fault quad q must have an area above round-off of its size (its normal
  !> is divided by its length when the interface elements are built): a quad
  !> whose nodes coincide or lie on a line is refused with its coordinates.
  subroutine check_area(mesh, q, fault_name, status)
    type(mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: q
    character(len=*), intent(in) :: fault_name
    type(error_status_t), intent(inout) :: status
    real(rp) :: x(3, 4), ext
    character(len=msg_len) :: m
    character(len=80) :: t
    integer :: a
    x = mesh%coords(:, mesh%sface_nodes(:, q))
    ext = maxval(maxval(x, dim=2) - minval(x, dim=2))
    if (norm2(cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))) > 64.0_rp * epsilon(1.0_rp) * ext**2) return
    write(m, '(a,i0,a)') 'fault split: quad ', q, ' of the fault "'//trim(fault_name)// &
      '" has zero area (an interface element needs a normal); its nodes:'
    do a = 1, 4
      write(t, '(a,g0.6,a,g0.6,a,g0.6,a)') ' (', x(1, a), ',', x(2, a), ',', x(3, a), ')'
      m = trim(m)//trim(t)
    end do
    call status%set(m)
  end subroutine check_area

  !> The orientation rule: n_z > 0 if |n_z| > 1e-6, else n_y > 0 if
  !> |n_y| > 1e-6, else n_x > 0.
  logical function points_up(n)
    real(rp), intent(in) :: n(3)
    real(rp), parameter :: tol = 1.0e-6_rp
    if (abs(n(3)) > tol) then
      points_up = n(3) > 0.0_rp
    else if (abs(n(2)) > tol) then
      points_up = n(2) > 0.0_rp
    else
      points_up = n(1) > 0.0_rp
    end if
  end function points_up

  integer(ip) function local_face(mesh, c, f)
    type(mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c, f
    local_face = findloc(mesh%cell_faces(:, c), f, dim=1)
  end function local_face

  pure function cross(a, b) result(c)
    real(rp), intent(in) :: a(3), b(3)
    real(rp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

  !> Remove the fault quads and the fault set names; the other quads take the
  !> node ids of their cell (the quad's nodes in the same order).
  subroutine drop_fault_sets(mesh, set_fault, old_cells)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: set_fault(:), old_cells(:,:)
    integer(ip), allocatable :: new_set(:), nodes(:,:), sets(:)
    character(len=name_len), allocatable :: names(:)
    integer(ip) :: s, ns, q, nq, c, k, p
    allocate(new_set(size(set_fault)))
    ns = 0
    do s = 1, size(set_fault, kind=ip)
      new_set(s) = 0
      if (set_fault(s) /= 0) cycle
      ns = ns + 1
      new_set(s) = ns
    end do
    allocate(names(ns))
    do s = 1, size(set_fault, kind=ip)
      if (new_set(s) > 0) names(new_set(s)) = mesh%set_names(s)
    end do
    nq = count(new_set(mesh%sface_set) > 0)
    allocate(nodes(4, nq), sets(nq))
    nq = 0
    do q = 1, mesh%n_sfaces
      if (new_set(mesh%sface_set(q)) == 0) cycle
      nq = nq + 1
      sets(nq) = new_set(mesh%sface_set(q))
      c = mesh%face_cells(1, mesh%sface_face(q))
      do k = 1, 4
        p = findloc(old_cells(:, c), mesh%sface_nodes(k, q), dim=1)
        nodes(k, nq) = mesh%cell_nodes(p, c)
      end do
    end do
    call move_alloc(names, mesh%set_names)
    call move_alloc(nodes, mesh%sface_nodes)
    call move_alloc(sets, mesh%sface_set)
    mesh%n_sfaces = nq
  end subroutine drop_fault_sets
end module fault_split
