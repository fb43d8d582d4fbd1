!> Unit tests of the mesh layer: unique faces and their orientation, surface
!> sets and grading of the box generator, and the distributed mesh (ownership
!> sums, the ghost layer, contiguous global numbering), and which meshes are
!> slabs with flat cells (slab_geometry).
program test_mesh
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use assertions, only: test_suite_t
  use mesh, only: mesh_t
  use box_mesh, only: build_box_mesh, graded_points
  use partition, only: partition_cells
  use dist_mesh, only: dist_mesh_t
  use hex_q1, only: quad_area_vector
  use slab_geometry, only: slab_t, find_slab
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(mesh_t) :: g
  type(dist_mesh_t) :: dm
  type(slab_t) :: slab
  type(error_status_t) :: st
  integer(ip), allocatable :: part(:)
  integer(ip), parameter :: n(3) = [4, 3, 2]
  real(rp) :: p(6), closed, worst, v
  integer(ip) :: f, c, lf, s, k, bad
  integer(gp) :: total
  logical :: ok

  call comm%init_world()
  call suite%init('mesh', comm)

  if (comm%is_root()) then
    call build_box_mesh(g, n, [0.0_rp, 0.0_rp, 0.0_rp], [2.0_rp, 1.5_rp, 1.0_rp], [2.0_rp, 1.0_rp, 0.5_rp], st)
  end if
  call suite%assert_true(st%ok(), 'box mesh built: '//trim(st%msg))

  ! faces: count, orientation, closure
  ok = .true.
  bad = 0
  worst = 0.0_rp
  if (comm%is_root()) then
    ok = g%n_faces == (n(1)+1)*n(2)*n(3) + n(1)*(n(2)+1)*n(3) + n(1)*n(2)*(n(3)+1)
    do f = 1, g%n_faces
      ! the face normal points out of face_cells(1): from its centre to the face centre
      v = dot_product(quad_area_vector(g%coords(:, g%face_nodes(:, f)), [0.0_rp, 0.0_rp]), &
                      sum(g%coords(:, g%face_nodes(:, f)), dim=2) / 4 - &
                      sum(g%coords(:, g%cell_nodes(:, g%face_cells(1, f))), dim=2) / 8)
      if (v <= 0.0_rp) bad = bad + 1
    end do
    do c = 1, g%n_cells
      ! signed face area vectors of a cell close: sum = 0
      closed = 0.0_rp
      do lf = 1, 6
        f = g%cell_faces(lf, c)
        if (g%face_cells(1 + (1 - g%cell_face_sign(lf, c)) / 2, f) /= c) bad = bad + 1
        closed = closed + sum(g%cell_face_sign(lf, c) * quad_area_vector(g%coords(:, g%face_nodes(:, f)), &
                                                                          [0.0_rp, 0.0_rp]))
      end do
      worst = max(worst, abs(closed))
    end do
  end if
  call suite%assert_true(ok, 'number of unique faces of a 4x3x2 box')
  call suite%assert_equal_int(bad, 0, 'face normals point out of face_cells(1); signs match the cells')
  call suite%assert_close(worst, 0.0_rp, 1.0e-12_rp, 'signed face area vectors of every cell sum to zero')

  ! surface sets: number of quads, all on the boundary, on the right plane
  ok = .true.
  if (comm%is_root()) then
    do s = 1, 6
      k = count(g%sface_set == s)
      ok = ok .and. k == merge(n(2)*n(3), merge(n(1)*n(3), n(1)*n(2), s <= 4), s <= 2)
    end do
    do k = 1, g%n_sfaces
      ok = ok .and. g%face_cells(2, g%sface_face(k)) == 0
    end do
    do k = 1, g%n_sfaces
      if (g%sface_set(k) == 2) ok = ok .and. all(abs(g%coords(1, g%sface_nodes(:, k)) - 2.0_rp) < 1.0e-14_rp)
    end do
  end if
  call suite%assert_true(ok, 'six boundary sets with the right quads')

  ! grading: last/first spacing ratio
  p = graded_points(5_ip, 0.0_rp, 1.0_rp, 3.0_rp)
  call suite%assert_close((p(6) - p(5)) / (p(2) - p(1)), 3.0_rp, 1.0e-12_rp, 'graded spacing ratio')
  call suite%assert_close(p(6), 1.0_rp, 0.0_rp, 'graded points end at the extent')

  ! distributed mesh
  if (comm%is_root()) then
    allocate(part(g%n_cells))
    call partition_cells(g, int(comm%size, ip), part, st)
  end if
  call dm%build(comm, g, part, st)
  call suite%assert_true(st%ok(), 'distributed mesh built')
  total = comm%sum(int(dm%cell_map%n_owned, gp))
  call suite%assert_true(total == dm%n_cells_global, 'owned cells add up to the global count')
  total = comm%sum(int(dm%node_map%n_owned, gp))
  call suite%assert_true(total == dm%n_nodes_global, 'owned nodes add up to the global count')
  total = comm%sum(int(dm%face_map%n_owned, gp))
  call suite%assert_true(total == dm%n_faces_global, 'owned faces add up to the global count')
  ! ghost layer: every local cell touching an owned node is local; count the
  ! cells touching each owned node and compare with the structured count
  bad = 0
  do k = 1, dm%node_map%n_owned
    c = count(any(dm%cell_nodes == k, dim=1))
    if (c /= expected_cells(dm%coords(:, k))) bad = bad + 1
  end do
  call suite%assert_equal_int(comm%sum(bad), 0, 'every cell touching an owned node is local (ghost layer)')
  ! global ids: contiguous owned ranges, ghosts owned elsewhere
  ok = dm%node_map%first == 1 + comm%exscan_g(int(dm%node_map%n_owned, gp))
  ok = ok .and. all(dm%node_map%ghost_owner /= comm%rank)
  call suite%assert_true(ok, 'contiguous owned node ranges, ghosts owned by other ranks')
  ! tagged quads known locally: all boundary, local face ids in range
  ok = all(dm%sface_face >= 1 .and. dm%sface_face <= dm%n_faces)
  ok = ok .and. all(dm%face_on_boundary(dm%sface_face))
  call suite%assert_true(ok, 'local surface quads are boundary faces')
  ! node sets: nodes of set xmax lie on x = 2
  s = dm%set_id('xmax')
  ok = s > 0
  if (ok) ok = all(abs(dm%coords(1, dm%set_nodes(dm%set_node_ptr(s):dm%set_node_ptr(s+1)-1)) - 2.0_rp) < 1.0e-14_rp)
  call suite%assert_true(ok, 'node set xmax lies on x = 2')
  call suite%assert_close(comm%sum(sum([(dm%cell_volume(c), c = 1, dm%cell_map%n_owned)])), 3.0_rp, 1.0e-12_rp, &
                          'owned cell volumes add up to the box volume')

  ! slabs: thin along an axis (1/10 of the others at most) with a flat cell
  ! (4 times wider than thick at least)
  slab = find_slab(dm)
  call suite%assert_equal_int(slab%axis, 0, 'slab: the 4x3x2 box is none')
  slab = box_slab([8_ip, 6_ip, 1_ip], [40.0_rp, 30.0_rp, 0.1_rp])
  call suite%assert_true(slab%axis == 3 .and. abs(slab%thickness - 0.1_rp) < 1.0e-12_rp .and. &
                         abs(slab%width - 30.0_rp) < 1.0e-12_rp .and. abs(slab%flatness - 50.0_rp) < 1.0e-9_rp, &
                         'slab: 8x6x1 cells on 40 x 30 x 0.1 m is a slab along z, cells flat 1:50')
  slab = box_slab([1_ip, 8_ip, 6_ip], [0.1_rp, 40.0_rp, 30.0_rp])
  call suite%assert_equal_int(slab%axis, 1, 'slab: the same across x is a slab along x')
  slab = box_slab([20_ip, 20_ip, 1_ip], [1.0_rp, 1.0_rp, 0.05_rp])
  call suite%assert_equal_int(slab%axis, 0, 'slab: a thin plate of cubic cells (Mandel) is none')
  slab = box_slab([8_ip, 6_ip, 2_ip], [40.0_rp, 30.0_rp, 5.0_rp])
  call suite%assert_equal_int(slab%axis, 0, 'slab: flat cells in a plate 1/6 as thick as wide are none')
  call suite%finish()

contains

  !> find_slab of the box [0, hi] with n cells, distributed over comm.
  function box_slab(n, hi) result(sl)
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: hi(3)
    type(slab_t) :: sl
    type(mesh_t) :: gb
    type(dist_mesh_t) :: db
    type(error_status_t) :: stb
    integer(ip), allocatable :: pb(:)
    if (comm%is_root()) then
      call build_box_mesh(gb, n, [0.0_rp, 0.0_rp, 0.0_rp], hi, [1.0_rp, 1.0_rp, 1.0_rp], stb)
      allocate(pb(gb%n_cells))
      if (stb%ok()) call partition_cells(gb, int(comm%size, ip), pb, stb)
    end if
    call db%build(comm, gb, pb, stb)
    call suite%assert_true(stb%ok(), 'slab: box mesh built and distributed: '//trim(stb%msg))
    sl = find_slab(db)
  end function box_slab

  !> Cells touching a node of the structured 4x3x2 box at position x.
  integer function expected_cells(x)
    real(rp), intent(in) :: x(3)
    real(rp), parameter :: hi(3) = [2.0_rp, 1.5_rp, 1.0_rp]
    integer :: i
    expected_cells = 1
    do i = 1, 3
      if (x(i) > 1.0e-12_rp .and. x(i) < hi(i) - 1.0e-12_rp) expected_cells = expected_cells * 2
    end do
  end function expected_cells
end program test_mesh
