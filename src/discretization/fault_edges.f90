!> The edges shared by two interface elements of the same fault surface, and
!> their geometry: the neighbour relation of the fault's P0 fields. The
!> traction stabilization H_t couples the two elements of an edge (contact),
!> and the fracture flow's two-point fluxes cross it (fracture_flow).
!>
!> An edge is the side k (nodes k and k+1 of the minus-side quad) of an
!> element. Positions on a fault are identified by the smaller of the
!> original (pre-partition) ids of their two nodes, so that the two sides
!> and either orientation give the same key on any number of ranks.
!> Kept: edges with exactly two elements on them, both of the same fault, at
!> least one owned (a tip edge has one element; a junction of three or more
!> fault elements is left out, the faults do not exchange there). Where
!> faults cross or meet, a node has up to four copies and two elements of
!> different faults can share a key: such a pair is no edge (it once was,
!> and with local ids the pairs there depended on the partition). Geometry from the minus-side
!> coordinates of the mesh as read (small deformations):
!>   length(ed)    the edge's length [m];
!>   dist(s, ed)   distance [m] from the centre of element pair(s, ed) (the
!>                 mean of its four nodes) to the edge's line, measured
!>                 along the element's in-plane direction normal to the
!>                 edge: the two-point flux distance (exact for rectangles
!>                 and parallelograms split along the edge, an
!>                 approximation on distorted quads).
module fault_edges
  use kinds, only: rp, ip
  use dist_mesh, only: dist_mesh_t
  implicit none
  private

  public :: fault_edges_t

  type :: fault_edges_t
    integer(ip) :: n = 0                          !< number of edges
    integer(ip), allocatable :: pair(:,:)         !< (2, n) local elements, pair(1) < pair(2)
    integer(ip), allocatable :: side(:,:)         !< (2, n) the side (1..4) of the edge in each element
    integer(ip), allocatable :: of_elem(:,:)      !< (4, n_ifaces) edge on each side of an element (0: none)
    real(rp), allocatable :: length(:)            !< (n) [m]
    real(rp), allocatable :: dist(:,:)            !< (2, n) centre-to-edge distances [m]
  contains
    procedure :: build
    procedure :: free
  end type fault_edges_t

contains

  !> Find the edges of the local interface elements of mesh and their
  !> geometry. Local: every rank finds the edges of its own elements.
  subroutine build(self, mesh)
    class(fault_edges_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), allocatable :: key(:,:), order(:)
    integer(ip) :: n, e, k, i, a, b, m, nown, e1, e2, j
    call self%free()
    n = mesh%n_ifaces
    nown = mesh%iface_map%n_owned
    allocate(key(4, 4*n), order(4*n))
    m = 0
    do e = 1, n
      do k = 1, 4
        a = orig_min(mesh, mesh%iface_nodes(k, :, e))
        b = orig_min(mesh, mesh%iface_nodes(mod(k, 4) + 1, :, e))
        m = m + 1
        key(:, m) = [min(a, b), max(a, b), e, k]
      end do
    end do
    call sort_pairs(key, order)
    allocate(self%pair(2, 2*n), self%side(2, 2*n), self%of_elem(4, n))
    self%of_elem = 0
    self%n = 0
    i = 1
    do while (i <= m)
      j = i
      do while (j < m)
        if (any(key(1:2, order(j+1)) /= key(1:2, order(i)))) exit
        j = j + 1
      end do
      if (j == i + 1) then
        e1 = key(3, order(i))
        e2 = key(3, order(j))
        if (e1 /= e2 .and. (e1 <= nown .or. e2 <= nown) .and. mesh%iface_fault(e1) == mesh%iface_fault(e2)) then
          self%n = self%n + 1
          if (e1 > e2) then
            self%pair(:, self%n) = [e2, e1]
            self%side(:, self%n) = [key(4, order(j)), key(4, order(i))]
          else
            self%pair(:, self%n) = [e1, e2]
            self%side(:, self%n) = [key(4, order(i)), key(4, order(j))]
          end if
          self%of_elem(key(4, order(i)), e1) = self%n
          self%of_elem(key(4, order(j)), e2) = self%n
        end if
      end if
      i = j + 1
    end do
    self%pair = self%pair(:, 1:self%n)
    self%side = self%side(:, 1:self%n)
    call geometry(self, mesh)
  end subroutine build

  !> The smaller original id of the two copies nodes(1:2) of a fault node.
  integer(ip) function orig_min(mesh, nodes)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: nodes(2)
    orig_min = int(min(mesh%node_orig(nodes(1)), mesh%node_orig(nodes(2))), ip)
  end function orig_min

  !> Edge lengths and the centre-to-edge distances (the distance from the
  !> centre to the edge's line: in the element's plane, along its normal to
  !> the edge).
  subroutine geometry(self, mesh)
    type(fault_edges_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: x(3, 4), v(3), t(3)
    integer(ip) :: ed, s, e, k
    allocate(self%length(self%n), self%dist(2, self%n))
    do ed = 1, self%n
      do s = 1, 2
        e = self%pair(s, ed)
        k = self%side(s, ed)
        x = mesh%coords(:, mesh%iface_nodes(:, 1, e))
        t = x(:, mod(k, 4) + 1) - x(:, k)
        self%length(ed) = norm2(t)
        t = t / norm2(t)
        v = sum(x, dim=2) / 4.0_rp - x(:, k)
        self%dist(s, ed) = norm2(v - dot_product(v, t) * t)
      end do
    end do
  end subroutine geometry

  !> Sort the columns of key(4, m) by (key(1), key(2)); order(i) is the
  !> column of rank i. Heap sort (no recursion, O(m log m)).
  subroutine sort_pairs(key, order)
    integer(ip), intent(in) :: key(:,:)
    integer(ip), intent(out) :: order(:)
    integer(ip) :: m, i, root, child, t, last
    m = size(order, kind=ip)
    order = [(i, i = 1, m)]
    do i = m / 2, 1, -1
      call sift(i, m)
    end do
    do last = m, 2, -1
      t = order(1); order(1) = order(last); order(last) = t
      call sift(1_ip, last - 1)
    end do
  contains
    logical function less(p, q)
      integer(ip), intent(in) :: p, q
      less = key(1, p) < key(1, q) .or. (key(1, p) == key(1, q) .and. key(2, p) < key(2, q))
    end function less
    subroutine sift(start, n)
      integer(ip), intent(in) :: start, n
      root = start
      do while (2 * root <= n)
        child = 2 * root
        if (child < n) then
          if (less(order(child), order(child + 1))) child = child + 1
        end if
        if (.not. less(order(root), order(child))) return
        t = order(root); order(root) = order(child); order(child) = t
        root = child
      end do
    end subroutine sift
  end subroutine sort_pairs

  subroutine free(self)
    class(fault_edges_t), intent(inout) :: self
    if (allocated(self%pair)) deallocate(self%pair, self%side, self%of_elem)
    if (allocated(self%length)) deallocate(self%length, self%dist)
    self%n = 0
  end subroutine free
end module fault_edges
