!> The global hexahedral mesh as rank 0 holds it before partitioning.
!>
!> Cells are 8-node hexahedra in the Gmsh/VTK order: nodes 1-4 the bottom
!> face counter-clockwise seen from above, 5-8 the top face above them.
!> Regions and tagged surfaces (boundary sets, and internal surfaces kept for
!> faults) carry names. build_faces() derives the unique faces with their
!> orientation (for RT0 fluxes) and matches each tagged surface quad to its face.
!>
!> Faults and fractures (filled by fault_split): zero-thickness interface
!> elements between two cells whose shared nodes have been split, so that the
!> two sides can move apart. Interface element e joins the minus cell
!> iface_cells(1,e) and the plus cell iface_cells(2,e):
!> - iface_nodes(:,1,e) are the minus cell's nodes of the shared face in that
!>   cell's hex_face_nodes order (counter-clockwise seen from outside the minus
!>   cell), so the right-hand normal (x3-x1) x (x4-x2) points from the minus
!>   side into the plus side;
!> - iface_nodes(k,2,e) is the plus-side copy of iface_nodes(k,1,e): the same
!>   coordinates, and the same id where the node is not split (a fracture tip);
!> - the minus cell is the one that makes the unit normal n point "up":
!>   n_z > 0 if |n_z| > 1e-6; otherwise n_y > 0 if |n_y| > 1e-6; otherwise n_x > 0.
!> iface_fault(e) indexes fault_names. After the split the two sides of a
!> fault are two boundary faces of faces/face_cells (no flux across them), and
!> the fault surfaces are no longer tagged sets.
module mesh
  use kinds, only: rp, ip, gp, name_len, msg_len
  use error_status, only: error_status_t
  use hex_q1, only: hex_jacobian_det
  implicit none
  private

  public :: mesh_t, hex_face_nodes

  !> Local faces of the hexahedron (local node ids, counter-clockwise seen
  !> from outside, so the right-hand normal points out):
  !> 1: xi=-1, 2: xi=+1, 3: eta=-1, 4: eta=+1, 5: zeta=-1, 6: zeta=+1.
  integer(ip), parameter :: hex_face_nodes(4, 6) = reshape([ &
    1, 5, 8, 4, &
    2, 3, 7, 6, &
    1, 2, 6, 5, &
    4, 8, 7, 3, &
    1, 4, 3, 2, &
    5, 6, 7, 8], [4, 6])

  type :: mesh_t
    integer(ip) :: n_nodes = 0
    integer(ip) :: n_cells = 0
    real(rp), allocatable :: coords(:,:)            !< (3, n_nodes) [m]
    integer(ip), allocatable :: cell_nodes(:,:)     !< (8, n_cells)
    integer(ip), allocatable :: cell_region(:)      !< (n_cells) index into region_names
    character(len=name_len), allocatable :: region_names(:)
    integer(gp), allocatable :: cell_tag(:)         !< (n_cells) element tag in the mesh file (Gmsh);
                                                    !< not allocated for a generated mesh
    ! tagged surface quads (boundary sets and internal surfaces)
    integer(ip) :: n_sfaces = 0
    integer(ip), allocatable :: sface_nodes(:,:)    !< (4, n_sfaces)
    integer(ip), allocatable :: sface_set(:)        !< (n_sfaces) index into set_names
    character(len=name_len), allocatable :: set_names(:)
    ! derived by build_faces
    integer(ip) :: n_faces = 0
    integer(ip), allocatable :: face_nodes(:,:)     !< (4, n_faces), as seen from face_cells(1,f)
    integer(ip), allocatable :: face_cells(:,:)     !< (2, n_faces); second is 0 on the boundary
    integer(ip), allocatable :: cell_faces(:,:)     !< (6, n_cells)
    integer(ip), allocatable :: cell_face_sign(:,:) !< (6, n_cells): +1 if the face normal points out of the cell
    integer(ip), allocatable :: sface_face(:)       !< (n_sfaces) face id of each tagged quad
    ! interface elements of faults (see the module header)
    integer(ip) :: n_ifaces = 0
    integer(ip), allocatable :: iface_nodes(:,:,:)  !< (4, 2, n_ifaces): (:,1,e) minus-side nodes,
                                                    !< (:,2,e) plus-side nodes at the same positions
    integer(ip), allocatable :: iface_cells(:,:)    !< (2, n_ifaces): minus cell, plus cell
    integer(ip), allocatable :: iface_fault(:)      !< (n_ifaces) index into fault_names
    character(len=name_len), allocatable :: fault_names(:)
  contains
    procedure :: build_faces
    procedure :: check
    procedure :: set_id
    procedure :: region_id
    procedure :: free
  end type mesh_t

contains

  !> Unique faces from the cells, their orientation, and the face of each
  !> tagged surface quad. A tagged quad that matches no cell face is an error.
  subroutine build_faces(self, status)
    class(mesh_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: key(:,:), order(:)
    integer(ip) :: n, c, lf, k, f, i, nf
    character(len=msg_len) :: m

    n = 6 * self%n_cells
    allocate(key(5, n), order(n))
    k = 0
    do c = 1, self%n_cells
      do lf = 1, 6
        k = k + 1
        key(1:4, k) = sorted4(self%cell_nodes(hex_face_nodes(:, lf), c))
        key(5, k) = k
      end do
    end do
    call sort_keys(key, order)
    if (allocated(self%face_nodes)) deallocate(self%face_nodes, self%face_cells, self%cell_faces, self%cell_face_sign)
    allocate(self%face_nodes(4, n), self%face_cells(2, n))
    allocate(self%cell_faces(6, self%n_cells), self%cell_face_sign(6, self%n_cells))
    nf = 0
    i = 1
    do while (i <= n)
      k = key(5, order(i))
      c = (k - 1) / 6 + 1
      lf = k - 6 * (c - 1)
      nf = nf + 1
      self%face_nodes(:, nf) = self%cell_nodes(hex_face_nodes(:, lf), c)
      self%face_cells(:, nf) = [c, 0]
      self%cell_faces(lf, c) = nf
      self%cell_face_sign(lf, c) = 1
      if (i < n) then
        if (all(key(1:4, order(i+1)) == key(1:4, order(i)))) then
          k = key(5, order(i+1))
          c = (k - 1) / 6 + 1
          lf = k - 6 * (c - 1)
          self%face_cells(2, nf) = c
          self%cell_faces(lf, c) = nf
          self%cell_face_sign(lf, c) = -1
          if (i + 1 < n) then
            if (all(key(1:4, order(i+2)) == key(1:4, order(i)))) then
              write(m, '(a,i0,a)') 'mesh: a face is shared by more than two cells (cell ', c, ')'
              call status%set(m)
              return
            end if
          end if
          i = i + 1
        end if
      end if
      i = i + 1
    end do
    self%n_faces = nf
    self%face_nodes = self%face_nodes(:, 1:nf)
    self%face_cells = self%face_cells(:, 1:nf)

    ! tagged quads -> faces (binary search among the sorted cell-face keys)
    if (allocated(self%sface_face)) deallocate(self%sface_face)
    allocate(self%sface_face(self%n_sfaces))
    do i = 1, self%n_sfaces
      f = find_key(sorted4(self%sface_nodes(:, i)))
      if (f == 0) then
        write(m, '(a,i0,a,a,a)') 'mesh: tagged surface quad ', i, ' of set "', &
          trim(self%set_names(self%sface_set(i))), '" is not a face of any cell'
        call status%set(m)
        return
      end if
      k = key(5, order(f))
      c = (k - 1) / 6 + 1
      lf = k - 6 * (c - 1)
      self%sface_face(i) = self%cell_faces(lf, c)
    end do
  contains
    integer(ip) function find_key(q)
      integer(ip), intent(in) :: q(4)
      integer(ip) :: lo, hi, mid, s
      lo = 1
      hi = n
      find_key = 0
      do while (lo <= hi)
        mid = (lo + hi) / 2
        s = compare4(key(1:4, order(mid)), q)
        if (s == 0) then
          find_key = mid
          return
        else if (s < 0) then
          lo = mid + 1
        else
          hi = mid - 1
        end if
      end do
    end function find_key
  end subroutine build_faces

  pure function sorted4(a) result(b)
    integer(ip), intent(in) :: a(4)
    integer(ip) :: b(4), t, i, j
    b = a
    do i = 2, 4
      t = b(i)
      j = i - 1
      do while (j >= 1)
        if (b(j) <= t) exit
        b(j+1) = b(j)
        j = j - 1
      end do
      b(j+1) = t
    end do
  end function sorted4

  pure integer(ip) function compare4(a, b)
    integer(ip), intent(in) :: a(4), b(4)
    integer :: i
    compare4 = 0
    do i = 1, 4
      if (a(i) < b(i)) then
        compare4 = -1
        return
      else if (a(i) > b(i)) then
        compare4 = 1
        return
      end if
    end do
  end function compare4

  !> Order the columns of key(1:4,:) lexicographically (merge sort, stable).
  subroutine sort_keys(key, order)
    integer(ip), intent(in) :: key(:,:)
    integer(ip), intent(out) :: order(:)
    integer(ip), allocatable :: tmp(:)
    integer(ip) :: n, width, lo, mid, hi, i, j, k
    n = size(order, kind=ip)
    do i = 1, n
      order(i) = i
    end do
    allocate(tmp(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width - 1, n)
        hi = min(lo + 2 * width - 1, n)
        i = lo
        j = mid + 1
        k = lo
        do while (i <= mid .and. j <= hi)
          if (compare4(key(1:4, order(j)), key(1:4, order(i))) < 0) then
            tmp(k) = order(j)
            j = j + 1
          else
            tmp(k) = order(i)
            i = i + 1
          end if
          k = k + 1
        end do
        do while (i <= mid)
          tmp(k) = order(i); i = i + 1; k = k + 1
        end do
        do while (j <= hi)
          tmp(k) = order(j); j = j + 1; k = k + 1
        end do
        lo = hi + 1
      end do
      order = tmp
      width = 2 * width
    end do
  end subroutine sort_keys

  !> Sanity checks of a mesh before any arithmetic divides by a cell's
  !> Jacobian: node ids in range, and every cell valid: det J at the 8
  !> corners and the centre positive and above round-off of the cell's size
  !> (det J > 64 eps L^3 / 8, L the largest extent of its nodes along an axis;
  !> J maps the reference cube of side 2). A collapsed, inverted or flat cell,
  !> or one whose nodes coincide, is refused with its number (the element tag
  !> of the mesh file when there is one, else the cell index) and its node
  !> coordinates.
  subroutine check(self, status)
    class(mesh_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    integer(ip) :: c, k
    character(len=msg_len) :: m
    real(rp) :: x(3, 8), det, ext
    real(rp), parameter :: corner(3, 9) = reshape([ &
      -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1, &
      -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,  0, 0, 0], [3, 9])
    if (self%n_cells == 0) then
      call status%set('mesh: no hexahedral cells')
      return
    end if
    do c = 1, self%n_cells
      if (any(self%cell_nodes(:, c) < 1) .or. any(self%cell_nodes(:, c) > self%n_nodes)) then
        write(m, '(a,a,a)') 'mesh: ', cell_name(self, c), ' refers to a node that does not exist'
        call status%set(m)
        return
      end if
      x = self%coords(:, self%cell_nodes(:, c))
      ext = maxval(maxval(x, dim=2) - minval(x, dim=2))
      do k = 1, 9
        det = hex_jacobian_det(x, corner(:, k))
        if (det <= 8.0_rp * epsilon(1.0_rp) * ext**3) then
          write(m, '(g0.4)') det
          call status%set('mesh: '//cell_name(self, c)//' is degenerate or inverted (Jacobian determinant '// &
            trim(m)//' at '//where(k)// &
            '; collapsed, flat, inverted or with coinciding nodes); its nodes: '//node_list(x))
          return
        end if
      end do
    end do
  contains
    !> Where point k of corner(:, k) is: a node of the cell or its centre.
    function where(i) result(t)
      integer(ip), intent(in) :: i
      character(len=:), allocatable :: t
      if (i == 9) then
        t = 'its centre'
      else
        t = 'its node '//achar(iachar('0') + i)
      end if
    end function where
  end subroutine check

  !> "element <tag>" (mesh file) or "cell <index>" (generated mesh).
  function cell_name(self, c) result(s)
    class(mesh_t), intent(in) :: self
    integer(ip), intent(in) :: c
    character(len=:), allocatable :: s
    character(len=24) :: t
    if (allocated(self%cell_tag)) then
      write(t, '(i0)') self%cell_tag(c)
      s = 'element '//trim(t)
    else
      write(t, '(i0)') c
      s = 'cell '//trim(t)
    end if
  end function cell_name

  !> The 8 node coordinates of a cell as "(x,y,z) ..." for messages.
  function node_list(x) result(s)
    real(rp), intent(in) :: x(3, 8)
    character(len=:), allocatable :: s
    character(len=80) :: t
    integer :: a
    s = ''
    do a = 1, 8
      write(t, '(a,g0.6,a,g0.6,a,g0.6,a)') '(', x(1, a), ',', x(2, a), ',', x(3, a), ')'
      s = s//trim(t)
      if (a < 8) s = s//' '
    end do
  end function node_list

  !> Index of the named tagged-surface set, 0 if none has that name.
  integer(ip) function set_id(self, name)
    class(mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(ip) :: i
    set_id = 0
    if (.not. allocated(self%set_names)) return
    do i = 1, size(self%set_names, kind=ip)
      if (self%set_names(i) == name) then
        set_id = i
        return
      end if
    end do
  end function set_id

  !> Index of the named region, 0 if none has that name.
  integer(ip) function region_id(self, name)
    class(mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(ip) :: i
    region_id = 0
    if (.not. allocated(self%region_names)) return
    do i = 1, size(self%region_names, kind=ip)
      if (self%region_names(i) == name) then
        region_id = i
        return
      end if
    end do
  end function region_id

  subroutine free(self)
    class(mesh_t), intent(inout) :: self
    if (allocated(self%coords)) deallocate(self%coords)
    if (allocated(self%cell_nodes)) deallocate(self%cell_nodes)
    if (allocated(self%cell_region)) deallocate(self%cell_region)
    if (allocated(self%region_names)) deallocate(self%region_names)
    if (allocated(self%cell_tag)) deallocate(self%cell_tag)
    if (allocated(self%sface_nodes)) deallocate(self%sface_nodes)
    if (allocated(self%sface_set)) deallocate(self%sface_set)
    if (allocated(self%set_names)) deallocate(self%set_names)
    if (allocated(self%face_nodes)) deallocate(self%face_nodes)
    if (allocated(self%face_cells)) deallocate(self%face_cells)
    if (allocated(self%cell_faces)) deallocate(self%cell_faces)
    if (allocated(self%cell_face_sign)) deallocate(self%cell_face_sign)
    if (allocated(self%sface_face)) deallocate(self%sface_face)
    if (allocated(self%iface_nodes)) deallocate(self%iface_nodes)
    if (allocated(self%iface_cells)) deallocate(self%iface_cells)
    if (allocated(self%iface_fault)) deallocate(self%iface_fault)
    if (allocated(self%fault_names)) deallocate(self%fault_names)
    self%n_nodes = 0
    self%n_cells = 0
    self%n_sfaces = 0
    self%n_faces = 0
    self%n_ifaces = 0
  end subroutine free
end module mesh
