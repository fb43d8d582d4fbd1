!> Structured hexahedral box generator.
!>
!> nx*ny*nz cells on [x0,x1]x[y0,y1]x[z0,z1]; along each axis the cell sizes
!> may grow geometrically (grading = ratio of the last to the first cell size,
!> 1 = uniform). One region named "domain"; six boundary sets named
!> xmin, xmax, ymin, ymax, zmin, zmax.
!>
!> Core refinement (optional), per axis i with core_n(i) > 0: the interval
!> [core_lower(i), core_upper(i)] gets core_n(i) uniform cells of size h; the
!> other n(i) - core_n(i) cells are shared by the parts below and above the
!> core in proportion to their lengths (at least one each when the part has a
!> positive length). Each part grows geometrically away from the core, its
!> cell next to the core being of size h; a part with too many cells to grow
!> (k h >= its length) or with a single cell is uniform. On an axis with a
!> core, grading(i) is ignored: the core wins.
!>
!> Planar faults (optional, fault_config_t with the box geometry): a fault
!> lies on the node layer nearest to `position` along its normal axis. That
!> layer is moved onto the plane through `position` (at the middle u_c of the
!> box along dip_axis) with inclination dip: every node's coordinate along the
!> normal axis moves by phi(layer) * (position + (u - u_c) tan(dip) - x_l),
!> where u is the node's coordinate along dip_axis, x_l the current coordinate
!> of the fault layer's node in the same column, and phi is piecewise linear
!> in the layer's (generated, unmapped) coordinate along the normal axis: 1 on
!> the fault's layer and 0 on the first and last layers and on the layers of
!> the other faults with the same normal axis. So the box boundary stays the
!> box, and faults with the same normal axis are exactly planar whatever their
!> order. phi is linear in the coordinate rather than in the layer index so
!> that every cell of a part is stretched by the same factor 1 +- |shift| /
!> (length of the part): a core refinement around an inclined fault does not
!> invert its small cells, and the map is valid exactly when the largest
!> shift, |tan(dip)| times the largest distance from u_c along dip_axis, is
!> shorter than the distance from the fault to the box ends (or the next
!> fault) along the normal axis. Faults are applied in deck order; a
!> fault with another normal axis moves the nodes of an earlier inclined fault
!> along its own normal, so two inclined faults with different normal axes
!> are not exactly planar (vertical ones placed on existing node layers are).
!> The fault's quads are the faces of its layer whose centres (before the
!> maps) lie within [lower, upper] in the two in-plane coordinates and, for
!> a circular fault (radius > 0, dip = 0), within radius of its centre in
!> the plane (a staircase disc); they form a tagged set named after the
!> fault (split later by fault_split). A map
!> that inverts a cell (a non-positive Jacobian at a 2x2x2 Gauss point) is an
!> error naming the fault: the dip is too steep for the box's aspect ratio.
!> A dipped fracture with tips along dip_axis then has the cells around it
!> squared up (square_up): the lines crossing it become perpendicular to it,
!> so that the cells on its two sides are mirror images near its tips.
module box_mesh
  use kinds, only: rp, ip, msg_len, name_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  use fault_config, only: fault_config_t
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_jacobian_det
  use strings, only: itoa, rtoa
  implicit none
  private

  public :: build_box_mesh, graded_points, core_points

  character(len=*), parameter :: axis_name = 'xyz'

contains

  !> Fill mesh with the box; n(3) cells per axis, lo(3)/hi(3) extents [m],
  !> grading(3) last/first cell size ratio per axis. Optional: a core
  !> refinement (core_lower(3), core_upper(3) [m], core_n(3) cells, 0 = no
  !> core on that axis; all three or none) and planar faults (see the module
  !> header), whose quads become tagged sets named after the faults.
  subroutine build_box_mesh(mesh, n, lo, hi, grading, status, core_lower, core_upper, core_n, faults)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: lo(3), hi(3), grading(3)
    type(error_status_t), intent(inout) :: status
    real(rp), intent(in), optional :: core_lower(3), core_upper(3)
    integer(ip), intent(in), optional :: core_n(3)
    type(fault_config_t), intent(in), optional :: faults(:)
    real(rp), allocatable :: px(:), py(:), pz(:)
    integer(ip) :: i, j, k, c, s, nxp, nyp, cn(3)
    real(rp) :: cl(3), cu(3)
    character(len=msg_len) :: m

    if (any(n < 1)) then
      call status%set('box mesh: nx, ny and nz must be at least 1')
      return
    end if
    if (any(hi <= lo)) then
      call status%set('box mesh: each upper extent must exceed the lower one')
      return
    end if
    if (any(grading <= 0.0_rp)) then
      call status%set('box mesh: grading must be positive')
      return
    end if
    if (real(n(1)+1, rp) * real(n(2)+1, rp) * real(n(3)+1, rp) > real(huge(1_ip), rp)) then
      write(m, '(a)') 'box mesh: too many nodes for 32-bit local ids'
      call status%set(m)
      return
    end if
    cn = 0
    cl = lo
    cu = hi
    if (present(core_n) .neqv. (present(core_lower) .and. present(core_upper))) then
      call status%set('box mesh: a core needs core_lower, core_upper and core_n together')
      return
    end if
    if (present(core_n)) then
      cn = core_n
      cl = core_lower
      cu = core_upper
    end if
    call mesh%free()
    call axis_points(1_ip, px)
    call axis_points(2_ip, py)
    call axis_points(3_ip, pz)
    if (.not. status%ok()) return
    nxp = n(1) + 1
    nyp = n(2) + 1
    mesh%n_nodes = nxp * nyp * (n(3) + 1)
    mesh%n_cells = n(1) * n(2) * n(3)
    allocate(mesh%coords(3, mesh%n_nodes))
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          mesh%coords(:, node(i, j, k)) = [px(i+1), py(j+1), pz(k+1)]
        end do
      end do
    end do
    allocate(mesh%cell_nodes(8, mesh%n_cells), mesh%cell_region(mesh%n_cells))
    c = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        do i = 0, n(1) - 1
          c = c + 1
          mesh%cell_nodes(:, c) = [node(i, j, k), node(i+1, j, k), node(i+1, j+1, k), node(i, j+1, k), &
                                   node(i, j, k+1), node(i+1, j, k+1), node(i+1, j+1, k+1), node(i, j+1, k+1)]
        end do
      end do
    end do
    mesh%cell_region = 1
    allocate(mesh%region_names(1))
    mesh%region_names(1) = 'domain'

    allocate(mesh%set_names(6))
    mesh%set_names = [character(len=len(mesh%set_names)) :: 'xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    mesh%n_sfaces = 2 * (n(2)*n(3) + n(1)*n(3) + n(1)*n(2))
    allocate(mesh%sface_nodes(4, mesh%n_sfaces), mesh%sface_set(mesh%n_sfaces))
    s = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        call add(1, [node(0, j, k), node(0, j, k+1), node(0, j+1, k+1), node(0, j+1, k)])
        call add(2, [node(n(1), j, k), node(n(1), j+1, k), node(n(1), j+1, k+1), node(n(1), j, k+1)])
      end do
    end do
    do k = 0, n(3) - 1
      do i = 0, n(1) - 1
        call add(3, [node(i, 0, k), node(i+1, 0, k), node(i+1, 0, k+1), node(i, 0, k+1)])
        call add(4, [node(i, n(2), k), node(i, n(2), k+1), node(i+1, n(2), k+1), node(i+1, n(2), k)])
      end do
    end do
    do j = 0, n(2) - 1
      do i = 0, n(1) - 1
        call add(5, [node(i, j, 0), node(i, j+1, 0), node(i+1, j+1, 0), node(i+1, j, 0)])
        call add(6, [node(i, j, n(3)), node(i+1, j, n(3)), node(i+1, j+1, n(3)), node(i, j+1, n(3))])
      end do
    end do
    if (present(faults)) then
      if (size(faults) > 0) call add_faults(mesh, n, lo, hi, px, py, pz, faults, status)
      if (.not. status%ok()) then
        call mesh%free()
        return
      end if
    end if
    ! cells squeezed to nothing by an extreme grading or core are refused here
    call mesh%check(status)
    if (status%ok()) call mesh%build_faces(status)
  contains
    pure integer(ip) function node(i, j, k)
      integer(ip), intent(in) :: i, j, k
      node = 1 + i + nxp * (j + nyp * k)
    end function node
    subroutine add(set, q)
      integer(ip), intent(in) :: set, q(4)
      s = s + 1
      mesh%sface_nodes(:, s) = q
      mesh%sface_set(s) = set
    end subroutine add
    !> The node coordinates along axis a: core, else grading.
    subroutine axis_points(a, p)
      integer(ip), intent(in) :: a
      real(rp), allocatable, intent(out) :: p(:)
      allocate(p(n(a) + 1))
      if (cn(a) > 0) then
        if (status%ok()) call core_points(n(a), lo(a), hi(a), cl(a), cu(a), cn(a), p, status)
      else
        p = graded_points(n(a), lo(a), hi(a), grading(a))
      end if
    end subroutine axis_points
  end subroutine build_box_mesh

  !> n+1 points from a to b whose spacing grows geometrically so that the last
  !> interval is `ratio` times the first.
  function graded_points(n, a, b, ratio) result(p)
    integer(ip), intent(in) :: n
    real(rp), intent(in) :: a, b, ratio
    real(rp) :: p(n+1)
    real(rp) :: q, h, w
    integer(ip) :: i
    p(1) = a
    if (n == 1 .or. abs(ratio - 1.0_rp) < 1.0e-12_rp) then
      do i = 1, n
        p(i+1) = a + (b - a) * real(i, rp) / real(n, rp)
      end do
    else
      q = ratio ** (1.0_rp / real(n - 1, rp))
      w = (q ** n - 1.0_rp) / (q - 1.0_rp)
      h = (b - a) / w
      do i = 1, n
        p(i+1) = p(i) + h * q ** (i - 1)
      end do
    end if
    p(n+1) = b
  end function graded_points

  !> n+1 points from a to b with nc uniform cells on the core [ca, cb] and the
  !> rest graded away from it (see the module header). status reports a core
  !> outside [a, b] or too many core cells for the parts outside it.
  subroutine core_points(n, a, b, ca, cb, nc, p, status)
    integer(ip), intent(in) :: n, nc
    real(rp), intent(in) :: a, b, ca, cb
    real(rp), intent(out) :: p(n+1)
    type(error_status_t), intent(inout) :: status
    real(rp) :: h, len_below, len_above, tol
    integer(ip) :: m, nb, na, n_parts, i
    real(rp), allocatable :: s(:)

    tol = 1.0e-12_rp * (b - a)
    if (nc < 1 .or. ca < a - tol .or. cb > b + tol .or. cb <= ca) then
      call status%set('box mesh: the core ['//rtoa(ca)//', '//rtoa(cb)//'] must lie inside ['//rtoa(a)//', '// &
                      rtoa(b)//'] with at least one cell')
      return
    end if
    len_below = max(ca - a, 0.0_rp)
    len_above = max(b - cb, 0.0_rp)
    if (len_below <= tol) len_below = 0.0_rp
    if (len_above <= tol) len_above = 0.0_rp
    n_parts = count([len_below, len_above] > 0.0_rp)
    m = n - nc
    if (m < n_parts .or. (n_parts == 0 .and. m /= 0)) then
      call status%set('box mesh: '//itoa(nc)//' core cells of '//itoa(n)//' leave too few (or too many) for the '// &
                      itoa(n_parts)//' part(s) outside the core')
      return
    end if
    h = (cb - ca) / real(nc, rp)
    if (n_parts == 2) then
      nb = nint(real(m, rp) * len_below / (len_below + len_above), ip)
      nb = max(1_ip, min(m - 1_ip, nb))
    else if (len_below > 0.0_rp) then
      nb = m
    else
      nb = 0
    end if
    na = m - nb
    ! below: cell sizes from the core outwards
    call part_sizes(nb, h, len_below, s)
    p(nb + 1) = merge(ca, a, nb > 0)
    do i = 1, nb
      p(nb + 1 - i) = p(nb + 2 - i) - s(i)
    end do
    p(1) = a
    do i = 1, nc
      p(nb + 1 + i) = p(nb + 1) + h * real(i, rp)
    end do
    p(nb + nc + 1) = merge(cb, b, na > 0)
    call part_sizes(na, h, len_above, s)
    do i = 1, na
      p(nb + nc + 1 + i) = p(nb + nc + i) + s(i)
    end do
    p(n + 1) = b
  end subroutine core_points

  !> Sizes of the k cells of a part of length len next to a core of cell size
  !> h, from the core outwards: h q^(i-1) with q >= 1 by bisection, or
  !> uniform when the part cannot grow (k = 1 or k h >= len).
  subroutine part_sizes(k, h, len, s)
    integer(ip), intent(in) :: k
    real(rp), intent(in) :: h, len
    real(rp), allocatable, intent(out) :: s(:)
    real(rp) :: q, qlo, qhi
    integer(ip) :: i, it
    allocate(s(k))
    if (k == 0) return
    if (k == 1 .or. real(k, rp) * h >= len) then
      s = len / real(k, rp)
      return
    end if
    qlo = 1.0_rp
    qhi = (len / h) ** (1.0_rp / real(k - 1, rp))
    do it = 1, 200
      q = 0.5_rp * (qlo + qhi)
      if (h * geometric_sum(q, k) > len) then
        qhi = q
      else
        qlo = q
      end if
      if (qhi - qlo <= 4.0_rp * epsilon(1.0_rp) * qhi) exit
    end do
    q = 0.5_rp * (qlo + qhi)
    do i = 1, k
      s(i) = h * q ** (i - 1)
    end do
  end subroutine part_sizes

  pure real(rp) function geometric_sum(q, k)
    real(rp), intent(in) :: q
    integer(ip), intent(in) :: k
    integer(ip) :: i
    geometric_sum = 0.0_rp
    do i = k - 1, 0, -1
      geometric_sum = geometric_sum * q + 1.0_rp
    end do
  end function geometric_sum

  !> Move the node layers of the faults onto their planes and tag their quads.
  subroutine add_faults(mesh, n, lo, hi, px, py, pz, faults, status)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: lo(3), hi(3), px(:), py(:), pz(:)
    type(fault_config_t), intent(in) :: faults(:)
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: layer(:), quads(:,:)
    integer(ip) :: nf, f, g, a, nq
    real(rp) :: pts(maxval(n) + 1, 3)
    character(len=name_len), allocatable :: names(:)
    character(len=msg_len) :: m

    nf = size(faults, kind=ip)
    pts = 0.0_rp
    pts(1:n(1)+1, 1) = px
    pts(1:n(2)+1, 2) = py
    pts(1:n(3)+1, 3) = pz
    allocate(layer(nf))
    do f = 1, nf
      a = int(faults(f)%normal_index(), ip)
      if (a < 1 .or. faults(f)%dip_index() == a .or. faults(f)%dip_index() < 1) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': bad normal_axis or dip_axis")
        return
      end if
      if (faults(f)%radius > 0.0_rp .and. faults(f)%dip /= 0.0_rp) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': a circular fault (radius) must have dip = 0")
        return
      end if
      if (.not. (faults(f)%position > lo(a) .and. faults(f)%position < hi(a))) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': position "//rtoa(faults(f)%position)// &
                        ' lies outside the box along '//axis_name(a:a)//' ('//rtoa(lo(a))//' to '//rtoa(hi(a))//')')
        return
      end if
      layer(f) = int(minloc(abs(pts(1:n(a)+1, a) - faults(f)%position), dim=1), ip) - 1
      if (layer(f) == 0 .or. layer(f) == n(a)) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': the node layer nearest to position "// &
                        rtoa(faults(f)%position)//' is the box boundary; move the fault or refine along '// &
                        axis_name(a:a))
        return
      end if
      if (mesh%set_id(faults(f)%name) > 0) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': a boundary set already has that name")
        return
      end if
      do g = 1, f - 1
        if (faults(g)%normal_index() == a .and. layer(g) == layer(f)) then
          call status%set("box mesh: faults '"//trim(faults(g)%name)//"' and '"//trim(faults(f)%name)// &
                          "' lie on the same node layer; refine along "//axis_name(a:a)//' or move one')
          return
        end if
      end do
    end do
    do f = 1, nf
      call move_layer(mesh, n, lo, hi, pts(:, faults(f)%normal_index()), faults, layer, f)
      if (.not. cells_valid(mesh)) then
        write(m, '(a)') "box mesh: fault '"//trim(faults(f)%name)//"': cells invert: the dip ("// &
          rtoa(faults(f)%dip)//" degrees) is too steep for the box's aspect ratio: tan(dip) times the "// &
          'half-length of the box along dip_axis must be less than the distance from the fault to the box ends '// &
          '(or the next fault) along normal_axis'
        call status%set(m)
        return
      end if
    end do
    ! the tagged quads of the faults
    allocate(names(size(mesh%set_names) + nf))
    names(1:size(mesh%set_names)) = mesh%set_names
    do f = 1, nf
      names(size(mesh%set_names) + f) = faults(f)%name
      call fault_quads(n, pts, faults(f), layer(f), quads)
      nq = size(quads, 2, kind=ip)
      if (nq == 0 .and. faults(f)%radius > 0.0_rp) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': no cell face of its node layer has its "// &
                        'centre within lower..upper and within radius '//rtoa(faults(f)%radius)// &
                        ' of centre; move the disc or refine the mesh')
        return
      else if (nq == 0) then
        call status%set("box mesh: fault '"//trim(faults(f)%name)//"': no cell face of its node layer has its "// &
                        'centre within lower..upper')
        return
      end if
      mesh%sface_nodes = reshape([mesh%sface_nodes, quads], [4_ip, mesh%n_sfaces + nq])
      mesh%sface_set = [mesh%sface_set, spread(size(mesh%set_names, kind=ip) + f, 1, nq)]
      mesh%n_sfaces = mesh%n_sfaces + nq
    end do
    call move_alloc(names, mesh%set_names)
  end subroutine add_faults

  !> Apply fault f's map to the coordinates along its normal axis (layer
  !> coordinates p before any map).
  subroutine move_layer(mesh, n, lo, hi, p, faults, layer, f)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: n(3), layer(:), f
    real(rp), intent(in) :: lo(3), hi(3), p(:)     !< p: generated coordinates of the layers along the normal axis
    type(fault_config_t), intent(in) :: faults(:)
    real(rp), allocatable :: phi(:), saved(:,:)
    integer(ip) :: a, d, l, below, above, g, i, j, k, ijk(3), col(3), id
    real(rp) :: uc, slope, delta
    real(rp), parameter :: deg = acos(-1.0_rp) / 180.0_rp

    a = int(faults(f)%normal_index(), ip)
    d = int(faults(f)%dip_index(), ip)
    l = layer(f)
    ! phi: hat function on layer l (in the coordinate), zero at the box ends and the other faults' layers
    below = 0
    above = n(a)
    do g = 1, size(faults, kind=ip)
      if (g == f .or. faults(g)%normal_index() /= a) cycle
      if (layer(g) < l) below = max(below, layer(g))
      if (layer(g) > l) above = min(above, layer(g))
    end do
    allocate(phi(0:n(a)))
    phi = 0.0_rp
    do i = below, l
      phi(i) = (p(i+1) - p(below+1)) / (p(l+1) - p(below+1))
    end do
    do i = l, above
      phi(i) = (p(above+1) - p(i+1)) / (p(above+1) - p(l+1))
    end do
    uc = 0.5_rp * (lo(d) + hi(d))
    slope = tan(faults(f)%dip * deg)
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          ijk = [i, j, k]
          if (phi(ijk(a)) == 0.0_rp) cycle
          col = ijk
          col(a) = l
          id = box_node(n, col)
          delta = faults(f)%position + (mesh%coords(d, id) - uc) * slope - mesh%coords(a, id)
          ! the fault layer itself last: the other nodes of the column read its old coordinate
          if (ijk(a) /= l) mesh%coords(a, box_node(n, ijk)) = mesh%coords(a, box_node(n, ijk)) + phi(ijk(a)) * delta
        end do
      end do
    end do
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          ijk = [i, j, k]
          if (ijk(a) /= l) cycle
          id = box_node(n, ijk)
          mesh%coords(a, id) = faults(f)%position + (mesh%coords(d, id) - uc) * slope
        end do
      end do
    end do
    ! a dipped fracture with a tip along dip_axis: square the cells up
    ! around it, unless another fault is normal to dip_axis or a cell inverts
    if (faults(f)%dip == 0.0_rp .or. any([(faults(g)%normal_index() == d, g = 1, size(faults))])) return
    if (.not. (faults(f)%lower(d) > lo(d) .or. faults(f)%upper(d) < hi(d))) return
    if (.not. cells_valid(mesh)) return                ! add_faults reports it
    saved = mesh%coords
    call square_up(mesh, n, lo, hi, p, faults(f), a, d, l, below, above)
    if (.not. cells_valid(mesh)) call move_alloc(saved, mesh%coords)
  end subroutine move_layer

  !> Near a dipped fault, make the mesh lines that cross it perpendicular to
  !> it: a node at generated distance s from the fault's layer goes to
  !> X_f + s nv, X_f the fault node of its column and nv the fault's unit
  !> normal, blended with its sheared position by the weight w(s) psi(u).
  !> w is 1 on the fault's layer and falls linearly (in the coordinate) to 0
  !> on the next layer that stays (box end or another fault with the same
  !> normal axis); psi along dip_axis is 1 over the fault's extent (at most
  !> up to an eighth of the box from its ends) and falls linearly to 0 at the
  !> ends. So the box keeps its faces, the fault stays planar (its own nodes
  !> do not move) and, near the fault and its tips, the cells on either side
  !> are mirror images up to second-order terms (w and psi differ from 1 by
  !> O(h / box) there, the correction they scale is O(h)). Why: with the
  !> sheared cells alone the two sides are translates, not mirror images,
  !> and Q1 couples a slip to a normal force; next to the tip of a slipping
  !> fracture that coupling grows as the mesh is refined, and the tip
  !> elements' normal traction fell to 0.31, 0.09 and 0 of the exact value on
  !> 30, 60 and 120 elements of the inclined-crack benchmark
  !> (input/single_fracture.nml); with this map every element is within
  !> 0.4 % (tests/verification/contact.sh). A plateau of w = 1 over half the
  !> distance to the box ends was as accurate but distorted the blend region
  !> enough to cost BoomerAMG two iterations on the contact benchmark.
  !> Applied to faults with a tip along dip_axis (lower or upper inside the
  !> box) only; where it would invert a cell (a coarse box, a steep dip) the
  !> sheared cells are kept.
  subroutine square_up(mesh, n, lo, hi, p, fault, a, d, l, below, above)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: n(3), a, d, l, below, above
    real(rp), intent(in) :: lo(3), hi(3), p(:)
    type(fault_config_t), intent(in) :: fault
    real(rp), parameter :: deg = acos(-1.0_rp) / 180.0_rp
    real(rp) :: nv(2), w(0:n(a)), s, psi, u, len_d, p_lo, p_hi, wt
    integer(ip) :: i, j, k, ijk(3), col(3), id, fid
    nv = [cos(fault%dip * deg), -sin(fault%dip * deg)]
    w = 0.0_rp
    do i = below, above
      s = p(i + 1) - p(l + 1)
      if (s < 0.0_rp) then
        w(i) = (p(i + 1) - p(below + 1)) / (p(l + 1) - p(below + 1))
      else
        w(i) = (p(above + 1) - p(i + 1)) / (p(above + 1) - p(l + 1))
      end if
    end do
    len_d = hi(d) - lo(d)
    p_lo = min(max(lo(d) + 0.125_rp * len_d, fault%lower(d)), 0.5_rp * (lo(d) + hi(d)))
    p_hi = max(min(hi(d) - 0.125_rp * len_d, fault%upper(d)), 0.5_rp * (lo(d) + hi(d)))
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          ijk = [i, j, k]
          if (ijk(a) == l .or. w(ijk(a)) == 0.0_rp) cycle
          col = ijk
          col(a) = l
          id = box_node(n, ijk)
          fid = box_node(n, col)
          u = mesh%coords(d, id)
          if (u < p_lo) then
            psi = (u - lo(d)) / (p_lo - lo(d))
          else if (u > p_hi) then
            psi = (hi(d) - u) / (hi(d) - p_hi)
          else
            psi = 1.0_rp
          end if
          wt = w(ijk(a)) * max(0.0_rp, min(1.0_rp, psi))
          s = p(ijk(a) + 1) - p(l + 1)
          mesh%coords(a, id) = mesh%coords(a, id) + wt * (mesh%coords(a, fid) + s * nv(1) - mesh%coords(a, id))
          mesh%coords(d, id) = mesh%coords(d, id) + wt * (mesh%coords(d, fid) + s * nv(2) - mesh%coords(d, id))
        end do
      end do
    end do
  end subroutine square_up

  pure integer(ip) function box_node(n, ijk)
    integer(ip), intent(in) :: n(3), ijk(3)
    box_node = 1 + ijk(1) + (n(1) + 1) * (ijk(2) + (n(2) + 1) * ijk(3))
  end function box_node

  !> The quads of fault f on node layer l whose centres (of the undisplaced
  !> grid pts) lie within [lower, upper] in the in-plane coordinates and,
  !> for a circular fault (radius > 0), within radius of its centre; a
  !> centre on a bound or on the circle (to 1e-9 of the box) counts. Nodes
  !> counter-clockwise about the normal axis.
  subroutine fault_quads(n, pts, fault, l, quads)
    integer(ip), intent(in) :: n(3), l
    real(rp), intent(in) :: pts(:,:)
    type(fault_config_t), intent(in) :: fault
    integer(ip), allocatable, intent(out) :: quads(:,:)
    integer(ip) :: a, b1, b2, i1, i2, nq, ijk(3)
    real(rp) :: c1, c2, tol1, tol2, tol_r
    a = int(fault%normal_index(), ip)
    b1 = 1 + mod(a, 3_ip)
    b2 = 1 + mod(a + 1, 3_ip)
    tol1 = 1.0e-9_rp * (pts(n(b1)+1, b1) - pts(1, b1))
    tol2 = 1.0e-9_rp * (pts(n(b2)+1, b2) - pts(1, b2))
    tol_r = max(tol1, tol2)
    allocate(quads(4, n(b1) * n(b2)))
    nq = 0
    do i2 = 0, n(b2) - 1
      do i1 = 0, n(b1) - 1
        c1 = 0.5_rp * (pts(i1+1, b1) + pts(i1+2, b1))
        c2 = 0.5_rp * (pts(i2+1, b2) + pts(i2+2, b2))
        if (c1 < fault%lower(b1) - tol1 .or. c1 > fault%upper(b1) + tol1) cycle
        if (c2 < fault%lower(b2) - tol2 .or. c2 > fault%upper(b2) + tol2) cycle
        if (fault%radius > 0.0_rp) then
          if (hypot(c1 - fault%centre(b1), c2 - fault%centre(b2)) > fault%radius + tol_r) cycle
        end if
        nq = nq + 1
        ijk(a) = l
        ijk(b1) = i1; ijk(b2) = i2
        quads(1, nq) = box_node(n, ijk)
        ijk(b1) = i1 + 1
        quads(2, nq) = box_node(n, ijk)
        ijk(b2) = i2 + 1
        quads(3, nq) = box_node(n, ijk)
        ijk(b1) = i1
        quads(4, nq) = box_node(n, ijk)
      end do
    end do
    quads = quads(:, 1:nq)
  end subroutine fault_quads

  !> True when every cell has a positive Jacobian at the 2x2x2 Gauss points.
  logical function cells_valid(mesh)
    type(mesh_t), intent(in) :: mesh
    real(rp) :: xi(3, 8), w(8)
    integer(ip) :: c, q
    call gauss_hex(2_ip, xi, w)
    cells_valid = .true.
    do c = 1, mesh%n_cells
      do q = 1, 8
        if (hex_jacobian_det(mesh%coords(:, mesh%cell_nodes(:, c)), xi(:, q)) <= 0.0_rp) then
          cells_valid = .false.
          return
        end if
      end do
    end do
  end function cells_valid
end module box_mesh
