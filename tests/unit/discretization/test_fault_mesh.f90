!> Unit tests of faults in the mesh: node splitting and interface elements
!> (fault_split), planar and inclined faults and the core refinement of the
!> box generator, a Gmsh fracture with tips, the distributed interface
!> elements and their ghost layer, and the &fault / &mesh deck checks.
!> Run on 1, 2 and 3 ranks; the global meshes are small and every rank builds
!> its own copy, so global expectations are checked on every rank.
program test_fault_mesh
  use strings, only: rtoa, itoa
  use kinds, only: rp, ip, gp, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use assertions, only: test_suite_t
  use deck_files, only: write_lines
  use logger, only: logger_t
  use deck, only: deck_t
  use mesh, only: mesh_t, hex_face_nodes
  use box_mesh, only: build_box_mesh, core_points
  use fault_config, only: fault_config_t, read_faults
  use fault_split, only: split_faults
  use gmsh_reader, only: read_gmsh
  use partition, only: partition_cells
  use dist_mesh, only: dist_mesh_t
  use mesh_config, only: mesh_config_t
  use mesh_builder, only: build_mesh
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(logger_t) :: log
  type(mesh_t) :: g
  type(error_status_t) :: st
  type(fault_config_t) :: flt(2)
  real(rp), parameter :: zero3(3) = 0.0_rp, one3(3) = 1.0_rp, pi = acos(-1.0_rp)
  integer(ip) :: e, k, n_split
  real(rp) :: worst, slope, e_len(2)
  logical :: ok

  call comm%init_world()
  call suite%init('fault_mesh', comm)
  call log%init(comm, 0)

  ! ---- a horizontal fault cutting a 4x4x2 box --------------------------------------------------
  flt(1) = fault_config_t(name='horizontal', normal_axis='z', position=0.5_rp)
  call box_with_faults(g, [4_ip, 4_ip, 2_ip], one3, flt(1:1), st, n_split)
  call suite%assert_true(st%ok(), 'horizontal fault: box built and split: '//trim(st%msg))
  call suite%assert_equal_int(g%n_nodes, 75 + 25, 'horizontal fault: 25 nodes added')
  call suite%assert_equal_int(n_split, 25, 'horizontal fault: 25 nodes split')
  call suite%assert_equal_int(g%n_ifaces, 16, 'horizontal fault: 16 interface elements')
  call suite%assert_equal_int(iface_violations(g), 0, 'horizontal fault: interface elements consistent '// &
                              '(minus face order, plus copies, equal coordinates, orientation rule)')
  ok = .true.
  do e = 1, g%n_ifaces
    ok = ok .and. abs(unit_normal(g, e) - 1.0_rp) < 1.0e-14_rp .and. abs(unit_normal(g, e, 1)) < 1.0e-14_rp &
         .and. abs(unit_normal(g, e, 2)) < 1.0e-14_rp
    ok = ok .and. centroid(g, g%iface_cells(1, e), 3) < 0.5_rp .and. centroid(g, g%iface_cells(2, e), 3) > 0.5_rp
    ok = ok .and. all(g%iface_nodes(:, 1, e) /= g%iface_nodes(:, 2, e)) .and. g%iface_fault(e) == 1
  end do
  call suite%assert_true(ok, 'horizontal fault: normals +z, minus cell below, every node split')
  ok = size(g%set_names) == 6 .and. g%set_id('horizontal') == 0 .and. size(g%fault_names) == 1
  if (ok) ok = g%fault_names(1) == 'horizontal'
  call suite%assert_true(ok, 'horizontal fault: fault set removed from the surface sets, fault_names set')
  call suite%assert_equal_int(count(g%face_cells(2, :) == 0), 2 * (16 + 8 + 8) + 2 * 16, &
                              'horizontal fault: the two sides are boundary faces')
  call suite%assert_equal_int(boundary_sets_off_plane(g, zero3, one3), 0, &
                              'horizontal fault: boundary quads renamed, still faces on their planes')
  call g%check(st)
  call suite%assert_true(st%ok(), 'horizontal fault: mesh check passes')

  ! ---- a fracture with tips: 2x2 quads inside a 4x4 layer -------------------------------------
  flt(1) = fault_config_t(name='tips', normal_axis='z', position=0.5_rp, lower=[0.25_rp, 0.25_rp, 0.0_rp], &
                          upper=[0.75_rp, 0.75_rp, 0.0_rp])
  call box_with_faults(g, [4_ip, 4_ip, 2_ip], one3, flt(1:1), st, n_split)
  call suite%assert_true(st%ok(), 'fracture with tips: built and split: '//trim(st%msg))
  call suite%assert_equal_int(g%n_ifaces, 4, 'fracture with tips: 4 interface elements')
  call suite%assert_equal_int(g%n_nodes, 75 + 1, 'fracture with tips: 1 node added (the centre)')
  call suite%assert_equal_int(count(g%iface_nodes(:, 1, :) == g%iface_nodes(:, 2, :)), 12, &
                              'fracture with tips: the 12 positions on the tip line keep one node')
  call suite%assert_equal_int(iface_violations(g), 0, 'fracture with tips: interface elements consistent')

  ! ---- an inclined fault: dip 25 degrees, normal y, dip axis x, 10x8x1 box ---------------------
  flt(1) = fault_config_t(name='inclined', normal_axis='y', position=4.0_rp, dip=25.0_rp, dip_axis='x')
  call box_with_faults(g, [10_ip, 8_ip, 1_ip], [10.0_rp, 8.0_rp, 1.0_rp], flt(1:1), st, n_split)
  call suite%assert_true(st%ok(), 'inclined fault: built and split: '//trim(st%msg))
  call suite%assert_equal_int(g%n_ifaces, 10, 'inclined fault: 10 interface elements')
  slope = tan(25.0_rp * pi / 180.0_rp)
  worst = 0.0_rp
  do e = 1, g%n_ifaces
    do k = 1, 4
      worst = max(worst, abs(g%coords(2, g%iface_nodes(k, 1, e)) - (4.0_rp + (g%coords(1, g%iface_nodes(k, 1, e)) - &
                                                                               5.0_rp) * slope)))
    end do
  end do
  call suite%assert_close(worst, 0.0_rp, 1.0e-12_rp, 'inclined fault: fault nodes on the plane')
  call suite%assert_equal_int(boundary_sets_off_plane(g, zero3, [10.0_rp, 8.0_rp, 1.0_rp]), 0, &
                              'inclined fault: box boundary unchanged')
  call suite%assert_close(mesh_volume(g) / 80.0_rp, 1.0_rp, 1.0e-12_rp, 'inclined fault: volume = box volume')
  call g%check(st)
  call suite%assert_true(st%ok(), 'inclined fault: all Jacobians positive')
  call suite%assert_equal_int(iface_violations(g), 0, 'inclined fault: interface elements consistent')
  ok = .true.
  do e = 1, g%n_ifaces
    ok = ok .and. abs(unit_normal(g, e, 2) - cos(25.0_rp * pi / 180.0_rp)) < 1.0e-12_rp
  end do
  call suite%assert_true(ok, 'inclined fault: normals tilted by the dip, pointing +y')
  flt(1)%dip = 60.0_rp
  call box_with_faults(g, [10_ip, 8_ip, 1_ip], [10.0_rp, 8.0_rp, 1.0_rp], flt(1:1), st, n_split)
  call suite%assert_true(.not. st%ok() .and. index(st%msg, 'too steep') > 0 .and. index(st%msg, 'inclined') > 0, &
                         'too steep a dip is an error naming the fault: '//trim(st%msg))

  ! ---- an inclined fracture in a core refinement (small cells next to the fault) ---------------
  ! box [-2,2]^2 x [0,0.1], 20 x 20 x 1, core x in [-0.1,0.1] of 4 cells of 0.05; the fault (x = 0,
  ! dip 20 along y, y in [-0.5,0.5]) shifts its layer by up to 2 tan(20) = 0.73 at y = +-2: fine
  ! for a map linear in the coordinate (stretch 1 +- 0.73/2), not for one linear in the layer index
  flt(1) = fault_config_t(name='cored', normal_axis='x', position=0.0_rp, dip=20.0_rp, dip_axis='y', &
                          lower=[0.0_rp, -0.5_rp, -1.0_rp], upper=[0.0_rp, 0.5_rp, 1.0_rp])
  call st%clear()
  call build_box_mesh(g, [20_ip, 20_ip, 1_ip], [-2.0_rp, -2.0_rp, 0.0_rp], [2.0_rp, 2.0_rp, 0.1_rp], one3, st, &
                      [-0.1_rp, 0.0_rp, 0.0_rp], [0.1_rp, 0.0_rp, 0.0_rp], [4_ip, 0_ip, 0_ip], flt(1:1))
  if (st%ok()) call split_faults(g, ['cored'], st)
  call suite%assert_true(st%ok(), 'cored fault: built and split: '//trim(st%msg))
  if (st%ok()) then
    call suite%assert_equal_int(g%n_ifaces, 6, 'cored fault: 6 interface elements (centres on the bounds count)')
    slope = tan(20.0_rp * pi / 180.0_rp)
    worst = 0.0_rp
    do e = 1, g%n_ifaces
      do k = 1, 4
        worst = max(worst, abs(g%coords(1, g%iface_nodes(k, 2, e)) - g%coords(2, g%iface_nodes(k, 2, e)) * slope))
      end do
    end do
    call suite%assert_close(worst, 0.0_rp, 1.0e-12_rp, 'cored fault: fault nodes on the plane x = y tan(20)')
    call suite%assert_close(mesh_volume(g) / 1.6_rp, 1.0_rp, 1.0e-12_rp, 'cored fault: volume = box volume')
    call g%check(st)
    call suite%assert_true(st%ok(), 'cored fault: all Jacobians positive')
    call suite%assert_equal_int(iface_violations(g), 0, 'cored fault: interface elements consistent')
    ! squared up around the fracture (box_mesh square_up): the cell edges leaving it cross it within
    ! 3 degrees of its normal (20 when sheared; the 5-degree tip warning of contact is not reached)
    ! and are 0.05 long to 2 % on both sides (the blend leaves second-order differences)
    call crossing_edges(g, [sin(20.0_rp * pi / 180.0_rp), cos(20.0_rp * pi / 180.0_rp), 0.0_rp], worst, e_len)
    call suite%assert_true(worst <= sin(3.0_rp * pi / 180.0_rp), 'cored fault: the cells crossing it are within '// &
                           '3 degrees of its normal: '//rtoa(asin(worst) * 180.0_rp / pi)//' degrees')
    call suite%assert_close(e_len(1), 0.05_rp, 1.0e-3_rp, 'cored fault: crossing edges 0.05 long (shortest)')
    call suite%assert_close(e_len(2), 0.05_rp, 1.0e-3_rp, 'cored fault: crossing edges 0.05 long (longest)')
  end if

  ! ---- two crossing vertical faults through the whole box --------------------------------------
  flt(1) = fault_config_t(name='fx', normal_axis='x', position=0.5_rp)
  flt(2) = fault_config_t(name='fy', normal_axis='y', position=0.5_rp)
  call box_with_faults(g, [4_ip, 4_ip, 2_ip], one3, flt, st, n_split)
  call suite%assert_true(st%ok(), 'crossing faults: built and split: '//trim(st%msg))
  call suite%assert_equal_int(g%n_ifaces, 16, 'crossing faults: 16 interface elements')
  call suite%assert_equal_int(g%n_nodes, 75 + 3 * 3 + 2 * 12, 'crossing faults: 33 nodes added')
  ok = .true.
  do k = 0, 2
    ok = ok .and. count(all(abs(g%coords - spread([0.5_rp, 0.5_rp, 0.5_rp * k], 2, g%n_nodes)) < 1.0e-14_rp, &
                            dim=1)) == 4
  end do
  call suite%assert_true(ok, 'crossing faults: each node on the crossing line split into 4')
  call suite%assert_equal_int(iface_violations(g), 0, 'crossing faults: interface elements consistent')
  ok = all(g%iface_fault(1:8) == 1) .and. all(g%iface_fault(9:16) == 2)
  call suite%assert_true(ok, 'crossing faults: elements ordered by fault')

  call test_disc()
  call test_core()
  call test_split_errors()
  call test_gmsh()
  call test_distributed()
  call test_decks()
  call suite%finish()

contains

  !> Box on [0, hi] with faults, then split them.
  !> Over the edges of the interface elements' cells that leave the fault
  !> (one end on the element's face): the largest |cos| of their angle with
  !> the fault direction tang, and their shortest and longest length.
  subroutine crossing_edges(g, tang, worst, len_range)
    type(mesh_t), intent(in) :: g
    real(rp), intent(in) :: tang(3)
    real(rp), intent(out) :: worst, len_range(2)
    integer, parameter :: edges(2, 12) = reshape([1, 2, 2, 3, 3, 4, 4, 1, 5, 6, 6, 7, 7, 8, 8, 5, &
                                                  1, 5, 2, 6, 3, 7, 4, 8], [2, 12])
    integer(ip) :: e, side, c, k, na, nb
    real(rp) :: v(3)
    logical :: ina, inb
    worst = 0.0_rp
    len_range = [huge(1.0_rp), 0.0_rp]
    do e = 1, g%n_ifaces
      do side = 1, 2
        c = g%iface_cells(side, e)
        do k = 1, 12
          na = g%cell_nodes(edges(1, k), c)
          nb = g%cell_nodes(edges(2, k), c)
          ina = any(g%iface_nodes(:, side, e) == na)
          inb = any(g%iface_nodes(:, side, e) == nb)
          if (ina .eqv. inb) cycle
          v = g%coords(:, nb) - g%coords(:, na)
          worst = max(worst, abs(dot_product(v, tang)) / norm2(v))
          len_range = [min(len_range(1), norm2(v)), max(len_range(2), norm2(v))]
        end do
      end do
    end do
  end subroutine crossing_edges

  subroutine box_with_faults(g, n, hi, faults, st, n_split)
    type(mesh_t), intent(inout) :: g
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: hi(3)
    type(fault_config_t), intent(in) :: faults(:)
    type(error_status_t), intent(out) :: st
    integer(ip), intent(out) :: n_split
    integer(ip) :: i
    n_split = -1
    call build_box_mesh(g, n, zero3, hi, one3, st, faults=faults)
    if (st%ok()) call split_faults(g, [(faults(i)%name, i = 1, size(faults))], st, n_split)
  end subroutine box_with_faults

  !> Component c (default 3) of the unit normal (x3-x1) x (x4-x2) of interface element e.
  real(rp) function unit_normal(g, e, c)
    type(mesh_t), intent(in) :: g
    integer(ip), intent(in) :: e
    integer, intent(in), optional :: c
    real(rp) :: x(3, 4), v(3)
    x = g%coords(:, g%iface_nodes(:, 1, e))
    v = cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))
    v = v / norm2(v)
    unit_normal = v(3)
    if (present(c)) unit_normal = v(c)
  end function unit_normal

  pure function cross(a, b) result(c)
    real(rp), intent(in) :: a(3), b(3)
    real(rp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

  real(rp) function centroid(g, c, i)
    type(mesh_t), intent(in) :: g
    integer(ip), intent(in) :: c
    integer, intent(in) :: i
    centroid = sum(g%coords(i, g%cell_nodes(:, c))) / 8.0_rp
  end function centroid

  !> Violations of the interface layout of mesh.f90, counted independently of
  !> fault_split: the minus nodes are a face of the minus cell in its
  !> hex_face_nodes order, the plus nodes the same face of the plus cell,
  !> the copies coincide, the normal points from the minus into the plus cell
  !> and obeys the "up" rule.
  integer function iface_violations(g) result(bad)
    type(mesh_t), intent(in) :: g
    integer(ip) :: e, a, b, lf, k
    logical :: found
    real(rp) :: v(3), x(3, 4), d(3)
    bad = 0
    do e = 1, g%n_ifaces
      a = g%iface_cells(1, e)
      b = g%iface_cells(2, e)
      found = .false.
      do lf = 1, 6
        found = found .or. all(g%cell_nodes(hex_face_nodes(:, lf), a) == g%iface_nodes(:, 1, e))
      end do
      if (.not. found) bad = bad + 1
      found = .false.
      do lf = 1, 6
        found = found .or. same_set(g%cell_nodes(hex_face_nodes(:, lf), b), g%iface_nodes(:, 2, e))
      end do
      if (.not. found) bad = bad + 1
      do k = 1, 4
        if (any(g%coords(:, g%iface_nodes(k, 1, e)) /= g%coords(:, g%iface_nodes(k, 2, e)))) bad = bad + 1
      end do
      x = g%coords(:, g%iface_nodes(:, 1, e))
      v = cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))
      v = v / norm2(v)
      d = [(centroid(g, b, k) - centroid(g, a, k), k = 1, 3)]
      if (dot_product(v, d) <= 0.0_rp) bad = bad + 1
      if (abs(v(3)) > 1.0e-6_rp) then
        if (v(3) <= 0.0_rp) bad = bad + 1
      else if (abs(v(2)) > 1.0e-6_rp) then
        if (v(2) <= 0.0_rp) bad = bad + 1
      else
        if (v(1) <= 0.0_rp) bad = bad + 1
      end if
      if (g%iface_fault(e) < 1 .or. g%iface_fault(e) > size(g%fault_names)) bad = bad + 1
    end do
  end function iface_violations

  logical function same_set(p, q)
    integer(ip), intent(in) :: p(4), q(4)
    integer :: i
    same_set = .true.
    do i = 1, 4
      same_set = same_set .and. any(p == q(i)) .and. any(q == p(i))
    end do
  end function same_set

  !> Boundary quads (sets xmin..zmax) that are not boundary faces or whose
  !> nodes are off their plane of the box [lo, hi].
  integer function boundary_sets_off_plane(g, lo, hi) result(bad)
    type(mesh_t), intent(in) :: g
    real(rp), intent(in) :: lo(3), hi(3)
    character(len=4), parameter :: names(6) = ['xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    integer(ip) :: q, s, a
    real(rp) :: plane
    bad = 0
    do q = 1, g%n_sfaces
      s = findloc(names, trim(g%set_names(g%sface_set(q))), dim=1)
      if (s == 0) cycle
      a = (s + 1) / 2
      plane = merge(lo(a), hi(a), mod(s, 2_ip) == 1)
      if (any(abs(g%coords(a, g%sface_nodes(:, q)) - plane) > 1.0e-12_rp)) bad = bad + 1
      if (g%face_cells(2, g%sface_face(q)) /= 0) bad = bad + 1
    end do
    if (any(g%coords < spread(lo, 2, g%n_nodes) - 1.0e-12_rp) .or. &
        any(g%coords > spread(hi, 2, g%n_nodes) + 1.0e-12_rp)) bad = bad + 1
  end function boundary_sets_off_plane

  real(rp) function mesh_volume(g)
    type(mesh_t), intent(in) :: g
    real(rp) :: xi(3, 8), w(8), sh(8), gr(3, 8), det
    integer(ip) :: c, q
    call gauss_hex(2_ip, xi, w)
    mesh_volume = 0.0_rp
    do c = 1, g%n_cells
      do q = 1, 8
        call hex_gradients(g%coords(:, g%cell_nodes(:, c)), xi(:, q), sh, gr, det)
        mesh_volume = mesh_volume + det * w(q)
      end do
    end do
  end function mesh_volume

  ! ---- circular faults (&fault radius, centre): staircase discs ----------------------------------
  !> A disc inside the box, the same disc cut by upper(1) (a chord), and the
  !> quarter disc of tests/decks/flow_penny.nml (centre on the box corner,
  !> reaching the faces xmin and ymin), each on a uniform grid.
  subroutine test_disc()
    call one_disc('disc', [20_ip, 20_ip, 2_ip], [2.0_rp, 2.0_rp, 1.0_rp], 0.73_rp, [0.95_rp, 1.05_rp], huge(1.0_rp))
    call one_disc('chord', [20_ip, 20_ip, 2_ip], [2.0_rp, 2.0_rp, 1.0_rp], 0.73_rp, [0.95_rp, 1.05_rp], 1.2_rp)
    call one_disc('quarter', [15_ip, 15_ip, 2_ip], [1.5_rp, 1.5_rp, 1.0_rp], 1.0_rp, [0.0_rp, 0.0_rp], huge(1.0_rp))
  end subroutine test_disc

  !> Fault 'name' normal to z at mid-height of the box [0, hi] of n cells,
  !> radius r about (c(1), c(2)), x <= x_max. Counted here from the grid
  !> alone: the selected quads (centre within r of c and x <= x_max), the
  !> split layer nodes (those whose every quad around them in the box, 4
  !> inside, 2 on a face, 1 on an edge, is selected; the cells around the
  !> others stay joined through a quad that is not the fault's) and the tip
  !> positions of the elements (their nodes that are not split). The mesh
  !> must have exactly these, and consistent interface elements.
  subroutine one_disc(name, n, hi, r, c, x_max)
    character(len=*), intent(in) :: name
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: hi(3), r, c(2), x_max
    type(mesh_t) :: g
    type(error_status_t) :: st
    type(fault_config_t) :: f(1)
    logical :: sel(0:n(1)-1, 0:n(2)-1), split(0:n(1), 0:n(2)), seen(0:n(1)-1, 0:n(2)-1)
    real(rp) :: h(2), x(3)
    integer(ip) :: i, j, e, k, n_split, n_tips, bad
    h = hi(1:2) / real(n(1:2), rp)
    do j = 0, n(2) - 1
      do i = 0, n(1) - 1
        sel(i, j) = hypot((i + 0.5_rp) * h(1) - c(1), (j + 0.5_rp) * h(2) - c(2)) <= r .and. &
                    (i + 0.5_rp) * h(1) <= x_max
      end do
    end do
    do j = 0, n(2)
      do i = 0, n(1)
        split(i, j) = all(sel(max(i - 1, 0_ip):min(i, n(1) - 1), max(j - 1, 0_ip):min(j, n(2) - 1)))
      end do
    end do
    n_tips = 0
    do j = 0, n(2) - 1
      do i = 0, n(1) - 1
        if (sel(i, j)) n_tips = n_tips + count(.not. [split(i, j), split(i + 1, j), split(i, j + 1), split(i + 1, j + 1)])
      end do
    end do
    f(1) = fault_config_t(name=name, normal_axis='z', position=0.5_rp * hi(3), radius=r, centre=[c(1), c(2), 0.0_rp], &
                          upper=[x_max, huge(1.0_rp), huge(1.0_rp)])
    call box_with_faults(g, n, hi, f, st, n_split)
    call suite%assert_true(st%ok(), name//': built and split: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_equal_int(g%n_ifaces, count(sel), name//': interface elements = quads with centres in the disc '// &
                                '(counted: '//itoa(count(sel))//')')
    ! the same quads: every element's centre falls in a selected quad, each quad once
    seen = .false.
    bad = 0
    do e = 1, g%n_ifaces
      x = sum(g%coords(:, g%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
      i = int(x(1) / h(1), ip)
      j = int(x(2) / h(2), ip)
      if (i < 0 .or. i >= n(1) .or. j < 0 .or. j >= n(2)) then
        bad = bad + 1
      else
        if (.not. sel(i, j) .or. seen(i, j)) bad = bad + 1
        seen(i, j) = .true.
      end if
    end do
    call suite%assert_equal_int(bad, 0, name//': the elements are the selected quads, each once')
    call suite%assert_equal_int(n_split, count(split), name//': split nodes (counted: '//itoa(count(split))//')')
    call suite%assert_equal_int(g%n_nodes, product(n + 1) + count(split), name//': one node added per split node')
    call suite%assert_equal_int(count(g%iface_nodes(:, 1, :) == g%iface_nodes(:, 2, :)), n_tips, &
                                name//': element nodes on the tip line keep one node (counted: '//itoa(n_tips)//')')
    ! node by node: split exactly where counted
    bad = 0
    do e = 1, g%n_ifaces
      do k = 1, 4
        x = g%coords(:, g%iface_nodes(k, 1, e))
        i = nint(x(1) / h(1), ip)
        j = nint(x(2) / h(2), ip)
        if (split(i, j) .neqv. g%iface_nodes(k, 1, e) /= g%iface_nodes(k, 2, e)) bad = bad + 1
      end do
    end do
    call suite%assert_equal_int(bad, 0, name//': each element node split exactly where counted')
    call suite%assert_equal_int(iface_violations(g), 0, name//': interface elements consistent')
    call suite%assert_true(count(split) > 0 .and. n_tips > 0, name//': the disc has split nodes and tips')
    call g%check(st)
    call suite%assert_true(st%ok(), name//': mesh check passes')
  end subroutine one_disc

  ! ---- core refinement --------------------------------------------------------------------------
  subroutine test_core()
    real(rp) :: p(21), h, q
    type(error_status_t) :: st
    type(mesh_t) :: g
    integer(ip) :: i, nb
    real(rp), allocatable :: xs(:)
    logical :: ok
    ! symmetric core [4, 6] with 8 cells in 20 on [0, 10]
    call core_points(20_ip, 0.0_rp, 10.0_rp, 4.0_rp, 6.0_rp, 8_ip, p, st)
    call suite%assert_true(st%ok(), 'core: points built')
    h = 0.25_rp
    call suite%assert_close(maxval(abs(p(8:15) - p(7:14) - h)), 0.0_rp, 1.0e-12_rp, 'core: 8 uniform core cells')
    call suite%assert_close(p(7), 4.0_rp, 1.0e-12_rp, 'core: starts at core_lower')
    call suite%assert_close(p(15), 6.0_rp, 1.0e-12_rp, 'core: ends at core_upper')
    call suite%assert_close(p(7) - p(6), h, 1.0e-10_rp, 'core: first cell below = core size')
    call suite%assert_close(p(16) - p(15), h, 1.0e-10_rp, 'core: first cell above = core size')
    ok = p(1) == 0.0_rp .and. p(21) == 10.0_rp
    do i = 1, 5
      ok = ok .and. p(i+1) - p(i) > p(i+2) - p(i+1)              ! below: shrinking towards the core
    end do
    do i = 15, 19
      ok = ok .and. p(i+2) - p(i+1) > p(i+1) - p(i)              ! above: growing away from it
    end do
    call suite%assert_true(ok, 'core: ends exact, cell sizes grow monotonically away from the core')
    ! the growth ratio solves h (1 + q + ... + q^5) = 4 on each side
    q = (p(18) - p(17)) / (p(17) - p(16))
    call suite%assert_close(h * (q**6 - 1.0_rp) / (q - 1.0_rp), 4.0_rp, 1.0e-9_rp, &
                            'core: geometric ratio fills the part')
    ! asymmetric core [1, 3]: 12 outer cells by length 1 : 7 -> 2 below (q = 3 exactly), 10 above
    call core_points(20_ip, 0.0_rp, 10.0_rp, 1.0_rp, 3.0_rp, 8_ip, p, st)
    nb = 2
    call suite%assert_close(p(nb + 1), 1.0_rp, 1.0e-12_rp, 'core: asymmetric, 2 cells below the core')
    call suite%assert_close(p(nb + 1) - p(nb), 0.25_rp, 1.0e-10_rp, 'core: asymmetric, first cell below = core size')
    call suite%assert_close(p(2) - p(1), 0.75_rp, 1.0e-10_rp, 'core: asymmetric, ratio 3 below')
    ! a part with too many cells to grow is uniform
    call core_points(20_ip, 0.0_rp, 10.0_rp, 4.0_rp, 6.0_rp, 4_ip, p, st)
    call suite%assert_close(maxval(abs(p(2:21) - p(1:20) - 0.5_rp)), 0.0_rp, 1.0e-12_rp, &
                            'core: parts that cannot grow are uniform')
    ! a core touching the lower end
    call core_points(10_ip, 0.0_rp, 10.0_rp, 0.0_rp, 2.0_rp, 4_ip, p(1:11), st)
    call suite%assert_close(p(6) - p(5), 0.5_rp, 1.0e-10_rp, 'core: touching an end, first outer cell = core size')
    ! too many core cells
    call core_points(10_ip, 0.0_rp, 10.0_rp, 4.0_rp, 6.0_rp, 9_ip, p(1:11), st)
    call suite%assert_true(.not. st%ok(), 'core: 9 core cells of 10 with two outer parts is an error')
    ! through the box generator: x has a core, grading ignored there, y graded
    call st%clear()
    call build_box_mesh(g, [20_ip, 3_ip, 1_ip], zero3, [10.0_rp, 1.0_rp, 1.0_rp], [5.0_rp, 2.0_rp, 1.0_rp], st, &
                        [4.0_rp, 0.0_rp, 0.0_rp], [6.0_rp, 0.0_rp, 0.0_rp], [8_ip, 0_ip, 0_ip])
    call suite%assert_true(st%ok(), 'core: box mesh with a core built')
    xs = g%coords(1, 1:21)
    call core_points(20_ip, 0.0_rp, 10.0_rp, 4.0_rp, 6.0_rp, 8_ip, p, st)
    call suite%assert_close_array(xs, p, 0.0_rp, 'core: box x coordinates = the core points')
    ! nodes (i, j, k) = 1 + i + 21 (j + 4 k): y at j = 0..3 are nodes 1, 22, 43, 64
    call suite%assert_close((g%coords(2, 64) - g%coords(2, 43)) / (g%coords(2, 22) - g%coords(2, 1)), 2.0_rp, &
                            1.0e-12_rp, 'core: y still graded')
  end subroutine test_core

  ! ---- split errors -------------------------------------------------------------------------------
  subroutine test_split_errors()
    type(mesh_t) :: g
    type(error_status_t) :: st
    call build_box_mesh(g, [2_ip, 2_ip, 2_ip], zero3, one3, one3, st)
    call split_faults(g, ['nothing'], st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, '"nothing"') > 0, &
                           'split: an unknown set is an error naming it: '//trim(st%msg))
    call st%clear()
    call split_faults(g, ['xmin'], st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, '"xmin"') > 0 .and. index(st%msg, 'boundary') > 0, &
                           'split: a boundary set is not a fault: '//trim(st%msg))
  end subroutine test_split_errors

  ! ---- gmsh: a fracture with two tip lines ---------------------------------------------------------
  subroutine test_gmsh()
    type(mesh_t) :: g
    type(error_status_t) :: st
    integer(ip) :: ns
    call read_gmsh('meshes/fault_tip.msh', g, st)
    call suite%assert_true(st%ok(), 'gmsh: meshes/fault_tip.msh read (run from the repository root): '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_equal_int(g%n_nodes, 125, 'gmsh: 125 nodes before the split')
    call split_faults(g, ['fault'], st, ns)
    call suite%assert_true(st%ok(), 'gmsh: fault split: '//trim(st%msg))
    call suite%assert_equal_int(g%n_nodes, 131, 'gmsh: 6 nodes added')
    call suite%assert_equal_int(g%n_ifaces, 6, 'gmsh: 6 interface elements')
    call suite%assert_equal_int(count(g%iface_nodes(:, 1, :) == g%iface_nodes(:, 2, :)), 9, &
                                'gmsh: 9 positions on the tip lines keep one node')
    call suite%assert_equal_int(iface_violations(g), 0, 'gmsh: interface elements consistent')
    call suite%assert_true(size(g%set_names) == 6 .and. g%set_id('fault') == 0, 'gmsh: six boundary sets remain')
    call suite%assert_true(all(abs(g%coords(1, reshape(g%iface_nodes, [8 * g%n_ifaces])) - 0.5_rp) < 1.0e-15_rp), &
                           'gmsh: interface nodes on x = 0.5')
  end subroutine test_gmsh

  ! ---- distributed interface elements ------------------------------------------------------------
  subroutine test_distributed()
    type(fault_config_t) :: f(2)
    type(mesh_t) :: gfull, groot
    type(error_status_t) :: st
    integer(ip) :: ns
    f(1) = fault_config_t(name='a', normal_axis='x', position=0.5_rp, dip=10.0_rp, dip_axis='y')
    f(2) = fault_config_t(name='b', normal_axis='z', position=0.5_rp, lower=[0.1_rp, 0.1_rp, 0.0_rp], &
                          upper=[0.9_rp, 0.6_rp, 0.0_rp])
    call box_with_faults(gfull, [6_ip, 6_ip, 4_ip], one3, f, st, ns)
    call suite%assert_true(st%ok(), 'distributed: global mesh with a dipping fault and a crossing fracture')
    call suite%assert_equal_int(gfull%n_ifaces, 24 + 12, 'distributed: 36 interface elements')
    call suite%assert_equal_int(iface_violations(gfull), 0, 'distributed: global interface elements consistent')
    call box_with_faults(groot, [6_ip, 6_ip, 4_ip], one3, f, st, ns)
    call check_distributed('box', gfull, groot, 2_ip)
    call read_gmsh('meshes/fault_tip.msh', gfull, st)
    if (st%ok()) call split_faults(gfull, ['fault'], st)
    groot = gfull
    call suite%assert_true(st%ok(), 'distributed: gmsh mesh read and split')
    call check_distributed('gmsh', gfull, groot, 1_ip)
  end subroutine test_distributed

  !> Distribute groot (consumed) and check the interface elements against
  !> gfull, and the fault blocks: n_blocks of them (one region), each named
  !> by its smallest cell.
  subroutine check_distributed(what, gfull, groot, n_blocks)
    character(len=*), intent(in) :: what
    type(mesh_t), intent(in) :: gfull
    type(mesh_t), intent(inout) :: groot
    integer(ip), intent(in) :: n_blocks
    type(dist_mesh_t) :: dm
    type(error_status_t) :: st
    integer(ip), allocatable :: part(:), iface_l(:), cell_l(:), node_l(:), hits(:)
    integer(gp), allocatable :: keys(:)
    integer(ip) :: i, e, e2, k, bad_touch, bad_edge, bad_map, bad_coord, bad_own, n3, ids(8)
    integer(gp) :: total
    logical :: ok

    if (comm%is_root()) then
      allocate(part(groot%n_cells))
      call partition_cells(groot, int(comm%size, ip), part, st)
    end if
    call dm%build(comm, groot, part, st)
    call suite%assert_true(st%ok(), what//' distributed: built')
    total = comm%sum(int(dm%iface_map%n_owned, gp))
    call suite%assert_true(total == int(gfull%n_ifaces, gp) .and. dm%iface_map%n_global == gfull%n_ifaces, &
                           what//' distributed: owned interface elements add up to the global count')
    ! global -> local lookups
    allocate(iface_l(gfull%n_ifaces), cell_l(gfull%n_cells), node_l(gfull%n_nodes))
    iface_l = 0; cell_l = 0; node_l = 0
    do i = 1, dm%n_ifaces
      iface_l(dm%iface_orig(i)) = i
    end do
    do i = 1, dm%n_cells
      cell_l(dm%cell_orig(i)) = i
    end do
    do i = 1, dm%n_nodes
      node_l(dm%node_orig(i)) = i
    end do
    ! local arrays = the global ones through the original ids; minus cell owned iff element owned
    bad_map = 0
    bad_coord = 0
    bad_own = 0
    do i = 1, dm%n_ifaces
      e = int(dm%iface_orig(i), ip)
      if (any(dm%cell_orig(dm%iface_cells(:, i)) /= gfull%iface_cells(:, e))) bad_map = bad_map + 1
      if (any(dm%node_orig(dm%iface_nodes(:, 1, i)) /= gfull%iface_nodes(:, 1, e))) bad_map = bad_map + 1
      if (any(dm%node_orig(dm%iface_nodes(:, 2, i)) /= gfull%iface_nodes(:, 2, e))) bad_map = bad_map + 1
      if (dm%iface_fault(i) /= gfull%iface_fault(e)) bad_map = bad_map + 1
      do k = 1, 4
        if (any(dm%coords(:, dm%iface_nodes(k, 1, i)) /= dm%coords(:, dm%iface_nodes(k, 2, i)))) &
          bad_coord = bad_coord + 1
      end do
      if ((i <= dm%iface_map%n_owned) .neqv. (dm%iface_cells(1, i) <= dm%cell_map%n_owned)) bad_own = bad_own + 1
    end do
    call suite%assert_equal_int(comm%sum(bad_map), 0, what//' distributed: local interface elements match the '// &
                                'global ones (cells, nodes, fault)')
    call suite%assert_equal_int(comm%sum(bad_coord), 0, what//' distributed: minus and plus coordinates coincide')
    call suite%assert_equal_int(comm%sum(bad_own), 0, what//' distributed: an element is owned with its minus cell')
    ok = dm%iface_map%first == 1 + comm%exscan_g(int(dm%iface_map%n_owned, gp))
    if (dm%iface_map%n_ghost > 1) ok = ok .and. all(dm%iface_map%ghost_gid(2:) > dm%iface_map%ghost_gid(:size(&
                                       dm%iface_map%ghost_gid) - 1))
    call suite%assert_true(ok, what//' distributed: contiguous owned ranges, ghosts in global order')
    ! every interface element touching an owned node is local with both cells
    bad_touch = 0
    do e = 1, gfull%n_ifaces
      ids = node_l(reshape(gfull%iface_nodes(:, :, e), [8]))
      if (.not. any(ids >= 1 .and. ids <= dm%node_map%n_owned)) cycle
      if (iface_l(e) == 0 .or. any(cell_l(gfull%iface_cells(:, e)) == 0)) bad_touch = bad_touch + 1
    end do
    call suite%assert_equal_int(comm%sum(bad_touch), 0, what//' distributed: every interface element of an owned '// &
                                'node is local, with both cells')
    ! edge neighbours (two shared node ids) of owned elements are local, with both cells
    bad_edge = 0
    do i = 1, dm%iface_map%n_owned
      e = int(dm%iface_orig(i), ip)
      do e2 = 1, gfull%n_ifaces
        if (shared_nodes(gfull, e, e2) < 2) cycle
        if (iface_l(e2) == 0 .or. any(cell_l(gfull%iface_cells(:, e2)) == 0)) bad_edge = bad_edge + 1
      end do
    end do
    call suite%assert_equal_int(comm%sum(bad_edge), 0, what//' distributed: edge neighbours of owned elements are local')
    ! keys: every key 1..3 n_ifaces exactly once over the ranks
    call dm%iface_keys(keys)
    n3 = 3 * gfull%n_ifaces
    allocate(hits(n3))
    hits = 0
    ok = all(keys >= 1 .and. keys <= n3)
    if (ok) then
      do i = 1, size(keys)
        hits(keys(i)) = hits(keys(i)) + 1
      end do
    end if
    call comm%sum_all(hits)
    call suite%assert_true(ok .and. all(hits == 1), what//' distributed: iface_keys are 1..3n, each on one rank '// &
                           '(the same set on any number of ranks)')
    ok = size(dm%fault_names) == size(gfull%fault_names)
    if (ok) ok = all(dm%fault_names == gfull%fault_names)
    call suite%assert_true(ok, what//' distributed: fault names')
    call check_blocks(what, gfull, dm, n_blocks)
    call dm%free()
  end subroutine check_distributed

  !> The fault blocks of dm (one region): the owned cells' blocks gathered
  !> by original id; n_blocks distinct ones, each named by its smallest
  !> cell; ghosts carry their owner's block; with the box's dipping fault
  !> (what = 'box'), the cells with x < 0.3 form one block and those with
  !> x > 0.7 the other (the fracture, which ends inside, seals nothing).
  subroutine check_blocks(what, gfull, dm, n_blocks)
    character(len=*), intent(in) :: what
    type(mesh_t), intent(in) :: gfull
    type(dist_mesh_t), intent(in) :: dm
    integer(ip), intent(in) :: n_blocks
    integer(ip), allocatable :: blk(:)
    integer(ip) :: i, c, bad
    real(rp) :: xc
    allocate(blk(gfull%n_cells))
    blk = 0
    do i = 1, dm%cell_map%n_owned
      blk(dm%cell_orig(i)) = int(dm%cell_block(i), ip)
    end do
    call comm%sum_all(blk)
    bad = 0
    do i = dm%cell_map%n_owned + 1, dm%n_cells
      if (int(dm%cell_block(i), ip) /= blk(dm%cell_orig(i))) bad = bad + 1
    end do
    call suite%assert_equal_int(comm%sum(bad), 0, what//' fault blocks: ghost cells carry their owner''s block')
    bad = 0
    do c = 1, gfull%n_cells
      if (blk(c) < 1 .or. blk(c) > c) then
        bad = bad + 1
      else if (blk(blk(c)) /= blk(c)) then
        bad = bad + 1
      end if
    end do
    call suite%assert_equal_int(bad, 0, what//' fault blocks: each named by its smallest cell')
    call suite%assert_equal_int(int(count([(blk(c) == c, c = 1, gfull%n_cells)]), ip), n_blocks, &
                                what//' fault blocks: '//itoa(n_blocks)//' of them')
    if (what /= 'box') return
    bad = 0
    do c = 1, gfull%n_cells
      xc = sum(gfull%coords(1, gfull%cell_nodes(:, c))) / 8.0_rp
      if (xc < 0.3_rp .and. blk(c) /= 1) bad = bad + 1
      if (xc > 0.7_rp .and. blk(c) == 1) bad = bad + 1
    end do
    call suite%assert_equal_int(bad, 0, what//' fault blocks: the dipping fault parts x < 0.3 from x > 0.7')
  end subroutine check_blocks

  !> Number of distinct node ids of interface element e1 that e2 also uses.
  integer function shared_nodes(g, e1, e2)
    type(mesh_t), intent(in) :: g
    integer(ip), intent(in) :: e1, e2
    integer(ip) :: a(8), b(8)
    integer :: k
    a = reshape(g%iface_nodes(:, :, e1), [8])
    b = reshape(g%iface_nodes(:, :, e2), [8])
    shared_nodes = 0
    do k = 1, 8
      if (any(a(1:k-1) == a(k))) cycle
      if (any(b == a(k))) shared_nodes = shared_nodes + 1
    end do
  end function shared_nodes

  ! ---- decks: the bad &fault decks, a bad core, and a good deck through build_mesh --------------
  subroutine test_decks()
    character(len=*), parameter :: bad(13) = [character(len=16) :: 'dip', 'dip_axis', 'duplicate', 'friction', &
                                             'position', 'steep', 'gmsh_geometry', 'no_set', 'radius', 'radius_dip', &
                                             'radius_gmsh', 'centre_alone', 'disc_empty']
    character(len=path_len) :: path
    character(len=msg_len) :: expect, msg
    type(error_status_t) :: st
    type(dist_mesh_t) :: dm
    type(fault_config_t), allocatable :: faults(:)
    integer :: i, u, ios
    character(len=64) :: tmp_deck
    write(tmp_deck, '(a,i0,a)') '/tmp/test_fault_mesh_', comm%size, '.nml'
    do i = 1, size(bad)
      path = 'tests/decks/bad_fault_'//trim(bad(i))//'.nml'
      expect = ''
      if (comm%is_root()) then
        open(newunit=u, file=trim(path), status='old', action='read', iostat=ios)
        if (ios == 0) then
          read(u, '(a)', iostat=ios) expect
          close(u)
          expect = expect(index(expect, ':') + 2:)
        end if
      end if
      call comm%bcast(expect)
      call deck_run(path, st, dm, faults)
      msg = st%msg
      call suite%assert_true(.not. st%ok() .and. len_trim(expect) > 0 .and. index(msg, trim(expect)) > 0, &
                             'deck bad_fault_'//trim(bad(i))//': '//trim(msg))
    end do
    ! &mesh core checks
    call write_deck(tmp_deck, [character(len=120) :: &
      "&mesh source = 'box', nx = 10, ny = 2, nz = 2, core_n = 9, 0, 0, core_lower = 0.4, core_upper = 0.6 /"])
    call deck_run(tmp_deck, st, dm, faults)
    call suite%assert_true(index(st%msg, 'variable core_n(1): must be at most n - 2 = 8') > 0, &
                           'deck: too many core cells: '//trim(st%msg))
    call write_deck(tmp_deck, [character(len=120) :: &
      "&mesh source = 'box', nx = 10, ny = 2, nz = 2, core_n = 4, 0, 0, core_lower = 0.4, core_upper = 1.6 /"])
    call deck_run(tmp_deck, st, dm, faults)
    call suite%assert_true(index(st%msg, 'must be a non-empty interval inside') > 0, &
                           'deck: core outside the box: '//trim(st%msg))
    call write_deck(tmp_deck, [character(len=120) :: &
      "&mesh source = 'box', nx = 10, ny = 2, nz = 2, core_n = 0, 0, 0, core_lower = 0.4 /"])
    call deck_run(tmp_deck, st, dm, faults)
    call suite%assert_true(index(st%msg, 'variable core_n: core_lower and core_upper need core_n > 0') > 0, &
                           'deck: core bounds without core cells: '//trim(st%msg))
    ! a good deck: core + a dipping fault + a fracture with tips, through build_mesh
    call write_deck(tmp_deck, [character(len=120) :: &
      "&mesh source = 'box', nx = 8, ny = 4, nz = 6, core_n = 4, 0, 2,", &
      "      core_lower = 0.25, 0, 0.4, core_upper = 0.75, 0, 0.6 /", &
      "&fault name = 'main', normal_axis = 'z', position = 0.5, dip = 15 /", &
      "&fault name = 'frac', normal_axis = 'x', position = 0.5, lower = 0, 0.25, 0, upper = 0, 0.75, 0.5 /"])
    call deck_run(tmp_deck, st, dm, faults)
    call suite%assert_true(st%ok(), 'deck: good fault deck through build_mesh: '//trim(st%msg))
    if (st%ok()) then
      call suite%assert_true(dm%iface_map%n_global == 8 * 4 + 2 * 3 .and. size(dm%fault_names) == 2, &
                             'deck: 38 interface elements on 2 faults')
      call suite%assert_close(faults(1)%friction_angle, 30.0_rp, 0.0_rp, 'deck: friction angle default')
      call suite%assert_true(faults(2)%initial_state == 'stick' .and. faults(2)%dip_axis == 'y', &
                             'deck: initial state and dip axis defaults')
    end if
    call dm%free()
  end subroutine test_decks

  !> Load deck path, read &mesh and &fault, build the distributed mesh.
  subroutine deck_run(path, st, dm, faults)
    character(len=*), intent(in) :: path
    type(error_status_t), intent(out) :: st
    type(dist_mesh_t), intent(inout) :: dm
    type(fault_config_t), allocatable, intent(out) :: faults(:)
    type(deck_t) :: d
    type(mesh_config_t) :: cfg
    call d%load(comm, path, st)
    if (st%ok()) call cfg%read(d, log, st)
    if (st%ok()) call read_faults(d, log, faults, st, cfg%source)
    if (st%ok()) call build_mesh(comm, cfg, log, dm, st, faults)
  end subroutine deck_run

  subroutine write_deck(path, lines)
    character(len=*), intent(in) :: path, lines(:)
    call write_lines(comm, path, lines)
  end subroutine write_deck
end program test_fault_mesh
