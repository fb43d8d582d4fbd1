!> Unit test of xdmf_writer_t (runs on any number of ranks; meant for 2).
!>
!> A 3 x 2 x 2 hexahedral box whose nodes and cells are split between the ranks
!> in contiguous blocks, plus a quadrilateral "fracture" grid (the plane z = 0.25)
!> owned by rank 0 alone, so that the other ranks take part in the collective
!> writes with nothing to write. Two output times. Rank 0 then reads every
!> dataset and attribute back with the serial HDF5 API and compares them exactly
!> with the values that were written (which are functions of the global ids),
!> lets python3 parse the XDMF file as XML and list its times and grids, and
!> checks the quadrilateral-only variant and the error paths.
program test_xdmf_writer
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fopen_f, h5fclose_f, H5F_ACC_RDONLY_F, &
                  h5dopen_f, h5dclose_f, h5dread_f, h5dget_space_f, h5sclose_f, &
                  h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5aopen_f, &
                  h5aread_f, h5aclose_f, h5gopen_f, h5gclose_f, h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND
  use kinds, only: rp, ip, gp, path_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use assertions, only: test_suite_t
  use xdmf_writer, only: xdmf_writer_t
  implicit none

  integer, parameter :: nx = 3, ny = 2, nz = 2
  integer, parameter :: nnx = nx + 1, nny = ny + 1, nnz = nz + 1
  integer(gp), parameter :: n_nodes = nnx*nny*nnz, n_cells = nx*ny*nz
  integer(gp), parameter :: n_fnodes = nnx*nny, n_fcells = nx*ny
  ! Under build/ (ignored by git) when run from the repository root, as run_tests.sh does.
  character(len=*), parameter :: dir = 'build/test-output/xdmf_writer'
  real(rp), parameter :: times(2) = [0.5_rp, 1.25_rp]
  integer, parameter :: max_checks = 64

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(xdmf_writer_t) :: w, wq, wbad
  type(error_status_t) :: st
  integer(gp) :: node_first, cell_first, ffirst_node, ffirst_cell, c
  integer(ip) :: n_own_nodes, n_own_cells, n_fown_nodes, n_fown_cells, nchk
  real(rp), allocatable :: coords(:,:), u(:,:), p(:), sig(:,:), fcoords(:,:), ap(:), tr(:,:)
  real(rp), allocatable :: pf(:)
  integer(gp), allocatable :: conn(:,:), fconn(:,:)
  integer(ip), allocatable :: rank_id(:), region(:)
  integer :: s, k, fgrid
  logical :: res(max_checks)
  character(len=msg_len) :: lab(max_checks)

  call comm%init_world()
  call suite%init('xdmf_writer', comm)

  ! ---- this rank's part of the box and of the fracture ----------------------
  call block_range(n_nodes, comm%size, comm%rank, node_first, n_own_nodes)
  call block_range(n_cells, comm%size, comm%rank, cell_first, n_own_cells)
  allocate(coords(3, n_own_nodes), conn(8, n_own_cells))
  do k = 1, n_own_nodes
    coords(:, k) = node_xyz(node_first + k - 1)
  end do
  do k = 1, n_own_cells
    conn(:, k) = hex_nodes(cell_first + k - 1)
  end do
  ! The fracture belongs to rank 0: the others own empty blocks at the end.
  if (comm%rank == 0) then
    n_fown_nodes = int(n_fnodes, ip)
    n_fown_cells = int(n_fcells, ip)
    ffirst_node = 1
    ffirst_cell = 1
  else
    n_fown_nodes = 0
    n_fown_cells = 0
    ffirst_node = n_fnodes + 1
    ffirst_cell = n_fcells + 1
  end if
  allocate(fcoords(3, n_fown_nodes), fconn(4, n_fown_cells))
  do k = 1, n_fown_nodes
    fcoords(:, k) = frac_xyz(int(k, gp))
  end do
  do k = 1, n_fown_cells
    fconn(:, k) = quad_nodes(int(k, gp))
  end do

  ! ---- write --------------------------------------------------------------
  call w%init(comm, dir, 'box', n_nodes, node_first, coords, n_cells, cell_first, conn, st, &
              grid_name='volume')
  call suite%assert_true(st%ok(), 'init box writer'//why(st))
  call w%add_grid('fracture', n_fnodes, ffirst_node, fcoords, n_fcells, ffirst_cell, fconn, &
                  st, fgrid)
  call suite%assert_true(st%ok() .and. fgrid == 2, 'add quadrilateral grid'//why(st))

  allocate(u(3, n_own_nodes), p(n_own_cells), sig(6, n_own_cells), rank_id(n_own_cells), &
           region(n_own_cells), ap(n_fown_cells), tr(3, n_fown_cells))
  call w%cell_field('p', p, st)
  call suite%assert_true(.not. st%ok(), 'field outside a step is refused')
  do s = 1, 2
    do k = 1, n_own_nodes
      u(:, k) = u_val(node_first + k - 1, times(s))
    end do
    do k = 1, n_own_cells
      c = cell_first + k - 1
      p(k) = p_val(c, times(s))
      sig(:, k) = sig_val(c, times(s))
      region(k) = region_val(c)
    end do
    rank_id = int(comm%rank, ip)
    do k = 1, n_fown_cells
      ap(k) = ap_val(int(k, gp), times(s))
      tr(:, k) = [real(k, rp), -real(k, rp), times(s)]
    end do
    call w%begin_step(times(s), st)
    call suite%assert_true(st%ok(), 'begin_step'//why(st))
    if (s == 1) then
      ! Bad calls inside a step: refused, and the step goes on.
      call w%node_field('u', u(:, 1:n_own_nodes - 1), st)
      call suite%assert_true(.not. st%ok() .and. index(st%msg, 'wrong number') > 0, &
                             'field of the wrong size is refused')
      call w%node_field('u/x', u, st)
      call suite%assert_true(.not. st%ok(), 'field name with a slash is refused')
      call w%cell_field('p', p, st, grid=3)
      call suite%assert_true(.not. st%ok(), 'field of a grid that does not exist is refused')
    end if
    call w%node_field('u', u, st)
    call suite%assert_true(st%ok(), 'node vector field'//why(st))
    call w%cell_field('p', p, st)
    call suite%assert_true(st%ok(), 'cell scalar field'//why(st))
    call w%cell_field('p', p, st)
    call suite%assert_true(.not. st%ok(), 'the same field twice in a step is refused')
    call w%cell_field('stress', sig, st)
    call suite%assert_true(st%ok(), 'cell Tensor6 field'//why(st))
    call w%cell_field('rank', rank_id, st)
    call suite%assert_true(st%ok(), 'integer cell field (rank)'//why(st))
    call w%cell_field('region', region, st)
    call suite%assert_true(st%ok(), 'integer cell field (region)'//why(st))
    call w%cell_field('aperture', ap, st, grid=fgrid)
    call suite%assert_true(st%ok(), 'fracture cell scalar field'//why(st))
    call w%cell_field('traction', tr, st, grid=fgrid)
    call suite%assert_true(st%ok(), 'fracture cell vector field'//why(st))
    call w%end_step(st)
    call suite%assert_true(st%ok(), 'end_step'//why(st))
  end do
  call suite%assert_true(w%xdmf_path() == dir//'/box.xdmf', 'xdmf_path')
  call w%free()

  ! A writer whose only grid is the quadrilateral surface.
  call wq%init(comm, dir, 'surf', n_fnodes, ffirst_node, fcoords, n_fcells, ffirst_cell, fconn, st)
  call suite%assert_true(st%ok(), 'init quadrilateral-only writer'//why(st))
  allocate(pf(n_fown_nodes))
  do k = 1, n_fown_nodes
    pf(k) = 2.0_rp*k + 0.125_rp
  end do
  call wq%begin_step(0.0_rp, st)
  if (st%ok()) call wq%node_field('pf', pf, st)
  if (st%ok()) call wq%end_step(st)
  call suite%assert_true(st%ok(), 'quadrilateral writer step'//why(st))
  call wq%free()

  ! Errors: a directory that cannot be created, an inconsistent partition.
  call wbad%init(comm, '/proc/geoblock_no_such_dir/out', 'x', n_nodes, node_first, coords, &
                 n_cells, cell_first, conn, st)
  call suite%assert_true(.not. st%ok() .and. index(st%msg, '/proc/geoblock_no_such_dir/out') > 0, &
                         'uncreatable directory is reported with its name: '//trim(st%msg))
  call wbad%init(comm, dir, 'bad', n_nodes + 1, node_first, coords, n_cells, cell_first, conn, st)
  call suite%assert_true(.not. st%ok() .and. index(st%msg, 'contiguous') > 0, &
                         'node count not matching the blocks is refused')
  call wbad%free()

  ! ---- read back (rank 0) ------------------------------------------------------
  nchk = 0
  res = .true.
  lab = ''
  if (comm%rank == 0) call read_back(res, lab, nchk)
  call comm%bcast(nchk)
  do k = 1, nchk
    call suite%assert_true(res(k), lab(k))
  end do

  call suite%finish()

contains

  !> ': message' after a failure, nothing after a success.
  function why(st) result(m)
    type(error_status_t), intent(in) :: st
    character(len=:), allocatable :: m
    m = ''
    if (.not. st%ok()) m = ': '//trim(st%msg)
  end function why

  !> n entries split in contiguous blocks, the first mod(n, np) ranks one longer.
  pure subroutine block_range(n, np, r, first, cnt)
    integer(gp), intent(in) :: n
    integer, intent(in) :: np, r
    integer(gp), intent(out) :: first
    integer(ip), intent(out) :: cnt
    integer(gp) :: q, m
    q = n / np
    m = mod(n, int(np, gp))
    cnt = int(q, ip)
    if (r < m) cnt = cnt + 1
    first = 1 + r*q + min(int(r, gp), m)
  end subroutine block_range

  pure integer function owner_of_cell(cc) result(r)
    integer(gp), intent(in) :: cc
    integer(gp) :: f
    integer(ip) :: n
    do r = 0, comm%size - 1
      call block_range(n_cells, comm%size, r, f, n)
      if (cc >= f .and. cc < f + n) return
    end do
    r = -1
  end function owner_of_cell

  pure function node_xyz(gid) result(x)
    integer(gp), intent(in) :: gid
    real(rp) :: x(3)
    integer :: i, j, kk
    i = int(mod(gid - 1, int(nnx, gp)))
    j = int(mod((gid - 1)/nnx, int(nny, gp)))
    kk = int((gid - 1)/(nnx*nny))
    x = [1.0_rp*i + 0.125_rp*j, 0.5_rp*j, 0.25_rp*kk + 0.0625_rp*i]
  end function node_xyz

  !> Nodes of cell cid in Gmsh/VTK hexahedron order.
  pure function hex_nodes(cid) result(v)
    integer(gp), intent(in) :: cid
    integer(gp) :: v(8)
    integer(gp) :: i, j, kk, b
    i = mod(cid - 1, int(nx, gp))
    j = mod((cid - 1)/nx, int(ny, gp))
    kk = (cid - 1)/(nx*ny)
    b = 1 + i + nnx*j + nnx*nny*kk
    v(1:4) = [b, b + 1, b + 1 + nnx, b + nnx]
    v(5:8) = v(1:4) + nnx*nny
  end function hex_nodes

  pure function frac_xyz(fid) result(x)
    integer(gp), intent(in) :: fid
    real(rp) :: x(3)
    x = [1.0_rp*mod(fid - 1, int(nnx, gp)), 0.5_rp*((fid - 1)/nnx), 0.25_rp]
  end function frac_xyz

  pure function quad_nodes(cid) result(v)
    integer(gp), intent(in) :: cid
    integer(gp) :: v(4)
    integer(gp) :: b
    b = 1 + mod(cid - 1, int(nx, gp)) + nnx*((cid - 1)/nx)
    v = [b, b + 1, b + 1 + nnx, b + nnx]
  end function quad_nodes

  pure function u_val(gid, t) result(v)
    integer(gp), intent(in) :: gid
    real(rp), intent(in) :: t
    real(rp) :: v(3)
    v = [real(gid, rp) + t, -2.0_rp*gid*t, 3.0_rp + t*t]
  end function u_val

  pure real(rp) function p_val(cid, t)
    integer(gp), intent(in) :: cid
    real(rp), intent(in) :: t
    p_val = 100.0_rp*cid + t
  end function p_val

  pure function sig_val(cid, t) result(v)
    integer(gp), intent(in) :: cid
    real(rp), intent(in) :: t
    real(rp) :: v(6)
    integer :: m
    v = [(real(cid, rp) + 0.125_rp*m - t, m = 1, 6)]
  end function sig_val

  pure integer(ip) function region_val(cid)
    integer(gp), intent(in) :: cid
    region_val = int(1 + mod(cid, 3_gp), ip)
  end function region_val

  pure real(rp) function ap_val(cid, t)
    integer(gp), intent(in) :: cid
    real(rp), intent(in) :: t
    ap_val = 0.001_rp*cid + t
  end function ap_val

  subroutine note(ok, what, res, lab, n)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    logical, intent(inout) :: res(:)
    character(len=*), intent(inout) :: lab(:)
    integer(ip), intent(inout) :: n
    n = n + 1
    res(n) = ok
    lab(n) = what
  end subroutine note

  !> Rank 0: read the files back with the serial HDF5 API and compare.
  !> (buffers pass by sequence association: the readers take buf(*))
  subroutine read_back(res, lab, n)
    logical, intent(inout) :: res(:)
    character(len=*), intent(inout) :: lab(:)
    integer(ip), intent(inout) :: n
    integer(hid_t) :: fid
    integer :: err, ss, m
    logical :: ok
    real(rp), allocatable :: r2(:,:), r1(:), e2(:,:)
    integer(gp), allocatable :: g2(:,:), eg(:,:)
    integer(ip), allocatable :: i1(:)
    character(len=path_len) :: file
    real(rp) :: t
    integer(ip) :: istep
    integer(gp) :: gv, g, c

    call h5open_f(err)
    ! mesh file: volume at the root, fracture in /fracture
    call h5fopen_f(dir//'/box_mesh.h5', H5F_ACC_RDONLY_F, fid, err)
    call note(err == 0, 'open box_mesh.h5', res, lab, n)
    if (err /= 0) return
    allocate(r2(3, n_nodes), e2(3, n_nodes), g2(8, n_cells), eg(8, n_cells))
    do g = 1, n_nodes
      e2(:, g) = node_xyz(g)
    end do
    do c = 1, n_cells
      eg(:, c) = hex_nodes(c) - 1
    end do
    call read_r(fid, 'coords', [3_hsize_t, int(n_nodes, hsize_t)], r2, ok)
    call note(ok .and. all(r2 == e2), '/coords exact, 3 x n_nodes', res, lab, n)
    call read_g(fid, 'connectivity', [8_hsize_t, int(n_cells, hsize_t)], g2, ok)
    call note(ok .and. all(g2 == eg), '/connectivity exact and 0-based, 8 x n_cells', res, lab, n)
    call read_attr_g(fid, 'n_nodes', gv, ok)
    call note(ok .and. gv == n_nodes, 'attribute n_nodes', res, lab, n)
    call read_attr_g(fid, 'n_cells', gv, ok)
    call note(ok .and. gv == n_cells, 'attribute n_cells', res, lab, n)
    deallocate(r2, e2, g2, eg)
    allocate(r2(3, n_fnodes), e2(3, n_fnodes), g2(4, n_fcells), eg(4, n_fcells))
    do g = 1, n_fnodes
      e2(:, g) = frac_xyz(g)
    end do
    do c = 1, n_fcells
      eg(:, c) = quad_nodes(c) - 1
    end do
    call read_r(fid, 'fracture/coords', [3_hsize_t, int(n_fnodes, hsize_t)], r2, ok)
    call note(ok .and. all(r2 == e2), '/fracture/coords exact', res, lab, n)
    call read_g(fid, 'fracture/connectivity', [4_hsize_t, int(n_fcells, hsize_t)], g2, ok)
    call note(ok .and. all(g2 == eg), '/fracture/connectivity exact, 4 x n_cells', res, lab, n)
    call read_attr_g(fid, 'fracture/n_cells', gv, ok)
    call note(ok .and. gv == n_fcells, 'attribute /fracture n_cells', res, lab, n)
    call h5fclose_f(fid, err)
    deallocate(r2, e2, g2, eg)

    ! step files
    do ss = 1, 2
      write(file, '(a,i4.4,a)') dir//'/box_', ss - 1, '.h5'
      call h5fopen_f(trim(file), H5F_ACC_RDONLY_F, fid, err)
      call note(err == 0, 'open '//trim(file), res, lab, n)
      if (err /= 0) cycle
      call read_attr_r(fid, 'time', t, ok)
      call note(ok .and. t == times(ss), 'time attribute of '//trim(file), res, lab, n)
      call read_attr_i(fid, 'step', istep, ok)
      call note(ok .and. istep == ss - 1, 'step attribute of '//trim(file), res, lab, n)

      allocate(r2(3, n_nodes), e2(3, n_nodes))
      do g = 1, n_nodes
        e2(:, g) = u_val(g, times(ss))
      end do
      call read_r(fid, 'u', [3_hsize_t, int(n_nodes, hsize_t)], r2, ok)
      call note(ok .and. all(r2 == e2), 'node vector u exact in '//trim(file), res, lab, n)
      deallocate(r2, e2)

      allocate(r1(n_cells))
      call read_r(fid, 'p', [int(n_cells, hsize_t)], r1, ok)
      call note(ok .and. all(r1 == [(p_val(c, times(ss)), c = 1, n_cells)]), &
                'cell scalar p exact (1-D) in '//trim(file), res, lab, n)
      deallocate(r1)

      allocate(r2(6, n_cells), e2(6, n_cells))
      do c = 1, n_cells
        e2(:, c) = sig_val(c, times(ss))
      end do
      call read_r(fid, 'stress', [6_hsize_t, int(n_cells, hsize_t)], r2, ok)
      call note(ok .and. all(r2 == e2), 'cell tensor stress exact in '//trim(file), res, lab, n)
      deallocate(r2, e2)

      allocate(i1(n_cells))
      call read_i(fid, 'rank', [int(n_cells, hsize_t)], i1, ok)
      call note(ok .and. all(i1 == [(int(owner_of_cell(c), ip), c = 1, n_cells)]), &
                'integer cell field rank exact in '//trim(file), res, lab, n)
      call read_i(fid, 'region', [int(n_cells, hsize_t)], i1, ok)
      call note(ok .and. all(i1 == [(region_val(c), c = 1, n_cells)]), &
                'integer cell field region exact in '//trim(file), res, lab, n)
      deallocate(i1)

      allocate(r1(n_fcells), r2(3, n_fcells))
      call read_r(fid, 'fracture/aperture', [int(n_fcells, hsize_t)], r1, ok)
      call note(ok .and. all(r1 == [(ap_val(c, times(ss)), c = 1, n_fcells)]), &
                'fracture aperture exact in '//trim(file), res, lab, n)
      call read_r(fid, 'fracture/traction', [3_hsize_t, int(n_fcells, hsize_t)], r2, ok)
      ok = ok .and. all(r2(1, :) == [(real(m, rp), m = 1, int(n_fcells))]) &
              .and. all(r2(2, :) == [(-real(m, rp), m = 1, int(n_fcells))]) &
              .and. all(r2(3, :) == times(ss))
      call note(ok, 'fracture traction exact in '//trim(file), res, lab, n)
      deallocate(r1, r2)
      call h5fclose_f(fid, err)
    end do

    ! quadrilateral-only writer
    call h5fopen_f(dir//'/surf_mesh.h5', H5F_ACC_RDONLY_F, fid, err)
    call note(err == 0, 'open surf_mesh.h5', res, lab, n)
    if (err == 0) then
      allocate(g2(4, n_fcells), eg(4, n_fcells))
      do c = 1, n_fcells
        eg(:, c) = quad_nodes(c) - 1
      end do
      call read_g(fid, 'connectivity', [4_hsize_t, int(n_fcells, hsize_t)], g2, ok)
      call note(ok .and. all(g2 == eg), 'surf /connectivity exact, 4 x n_cells', res, lab, n)
      call h5fclose_f(fid, err)
    end if
    call h5fopen_f(dir//'/surf_0000.h5', H5F_ACC_RDONLY_F, fid, err)
    if (err == 0) then
      allocate(r1(n_fnodes))
      call read_r(fid, 'pf', [int(n_fnodes, hsize_t)], r1, ok)
      call note(ok .and. all(r1 == [(2.0_rp*m + 0.125_rp, m = 1, int(n_fnodes))]), &
                'surf node scalar pf exact', res, lab, n)
      call h5fclose_f(fid, err)
    else
      call note(.false., 'open surf_0000.h5', res, lab, n)
    end if

    ! XDMF files
    call note(python_ok(dir//'/box.xdmf', '[0.5, 1.25]', 4), &
              'box.xdmf parses as XML (python3), times 0.5 and 1.25, 2 x 2 grids', res, lab, n)
    call note(python_ok(dir//'/surf.xdmf', '[0.0]', 1), &
              'surf.xdmf parses as XML (python3), one time, one grid', res, lab, n)
    ok = file_has(dir//'/box.xdmf', 'TopologyType="Hexahedron"')
    ok = file_has(dir//'/box.xdmf', 'TopologyType="Quadrilateral"') .and. ok
    ok = file_has(dir//'/box.xdmf', 'AttributeType="Tensor6"') .and. ok
    ok = file_has(dir//'/box.xdmf', 'AttributeType="Vector" Center="Node"') .and. ok
    ok = file_has(dir//'/box.xdmf', 'box_0001.h5:/fracture/aperture') .and. ok
    ok = file_has(dir//'/box.xdmf', 'box_mesh.h5:/connectivity') .and. ok
    call note(ok, 'box.xdmf names both topologies, the attribute types and the datasets', &
              res, lab, n)
    ok = file_has(dir//'/surf.xdmf', 'TopologyType="Quadrilateral"')
    ok = .not. file_has(dir//'/surf.xdmf', 'Hexahedron') .and. ok
    call note(ok, 'surf.xdmf is a Quadrilateral grid', res, lab, n)
  end subroutine read_back

  !> Open a dataset, check its dimensions (Fortran order), return its id.
  subroutine open_checked(fid, path, dims, dset, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t), intent(out) :: dset
    logical, intent(out) :: ok
    integer(hid_t) :: space
    integer(hsize_t) :: d(7), maxd(7)
    integer :: err, nd
    ok = .false.
    call h5dopen_f(fid, path, dset, err)
    if (err /= 0) return
    call h5dget_space_f(dset, space, err)
    call h5sget_simple_extent_ndims_f(space, nd, err)
    if (nd == size(dims)) then
      call h5sget_simple_extent_dims_f(space, d(1:nd), maxd(1:nd), err)
      ok = err == nd .and. all(d(1:nd) == dims)
    end if
    call h5sclose_f(space, err)
  end subroutine open_checked

  subroutine read_r(fid, path, dims, buf, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hsize_t), intent(in) :: dims(:)
    real(rp), intent(out), target :: buf(*)
    logical, intent(out) :: ok
    integer(hid_t) :: dset
    integer :: err
    type(c_ptr) :: ptr
    call open_checked(fid, path, dims, dset, ok)
    if (ok) then
      ptr = c_loc(buf(1))
      call h5dread_f(dset, h5kind_to_type(rp, H5_REAL_KIND), ptr, err)
      ok = err == 0
    end if
    call h5dclose_f(dset, err)
  end subroutine read_r

  subroutine read_g(fid, path, dims, buf, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hsize_t), intent(in) :: dims(:)
    integer(gp), intent(out), target :: buf(*)
    logical, intent(out) :: ok
    integer(hid_t) :: dset
    integer :: err
    type(c_ptr) :: ptr
    call open_checked(fid, path, dims, dset, ok)
    if (ok) then
      ptr = c_loc(buf(1))
      call h5dread_f(dset, h5kind_to_type(gp, H5_INTEGER_KIND), ptr, err)
      ok = err == 0
    end if
    call h5dclose_f(dset, err)
  end subroutine read_g

  subroutine read_i(fid, path, dims, buf, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hsize_t), intent(in) :: dims(:)
    integer(ip), intent(out), target :: buf(*)
    logical, intent(out) :: ok
    integer(hid_t) :: dset
    integer :: err
    type(c_ptr) :: ptr
    call open_checked(fid, path, dims, dset, ok)
    if (ok) then
      ptr = c_loc(buf(1))
      call h5dread_f(dset, h5kind_to_type(ip, H5_INTEGER_KIND), ptr, err)
      ok = err == 0
    end if
    call h5dclose_f(dset, err)
  end subroutine read_i

  subroutine read_attr_r(fid, name, v, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: name
    real(rp), intent(out), target :: v
    logical, intent(out) :: ok
    integer(hid_t) :: attr
    integer :: err
    type(c_ptr) :: ptr
    v = -1.0_rp
    call h5aopen_f(fid, name, attr, err)
    ok = err == 0
    if (.not. ok) return
    ptr = c_loc(v)
    call h5aread_f(attr, h5kind_to_type(rp, H5_REAL_KIND), ptr, err)
    ok = err == 0
    call h5aclose_f(attr, err)
  end subroutine read_attr_r

  subroutine read_attr_i(fid, name, v, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: name
    integer(ip), intent(out), target :: v
    logical, intent(out) :: ok
    integer(hid_t) :: attr
    integer :: err
    type(c_ptr) :: ptr
    v = -1
    call h5aopen_f(fid, name, attr, err)
    ok = err == 0
    if (.not. ok) return
    ptr = c_loc(v)
    call h5aread_f(attr, h5kind_to_type(ip, H5_INTEGER_KIND), ptr, err)
    ok = err == 0
    call h5aclose_f(attr, err)
  end subroutine read_attr_i

  !> Attribute of the root ('name') or of a group ('group/name').
  subroutine read_attr_g(fid, path, v, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(gp), intent(out), target :: v
    logical, intent(out) :: ok
    integer(hid_t) :: attr, obj
    integer :: err, slash
    type(c_ptr) :: ptr
    v = -1
    slash = index(path, '/', back=.true.)
    if (slash > 0) then
      call open_group(fid, path(1:slash - 1), obj, ok)
      if (.not. ok) return
    else
      obj = fid
    end if
    call h5aopen_f(obj, path(slash + 1:), attr, err)
    ok = err == 0
    if (ok) then
      ptr = c_loc(v)
      call h5aread_f(attr, h5kind_to_type(gp, H5_INTEGER_KIND), ptr, err)
      ok = err == 0
      call h5aclose_f(attr, err)
    end if
    if (slash > 0) call close_group(obj)
  end subroutine read_attr_g

  subroutine open_group(fid, path, obj, ok)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hid_t), intent(out) :: obj
    logical, intent(out) :: ok
    integer :: err
    call h5gopen_f(fid, path, obj, err)
    ok = err == 0
  end subroutine open_group

  subroutine close_group(obj)
    integer(hid_t), intent(in) :: obj
    integer :: err
    call h5gclose_f(obj, err)
  end subroutine close_group

  !> python3 parses the XDMF file as XML and finds the expected list of times
  !> and number of Uniform grids; false if python3 fails or disagrees.
  logical function python_ok(path, times_list, n_uniform)
    character(len=*), intent(in) :: path, times_list
    integer, intent(in) :: n_uniform
    character(len=1024) :: cmd
    character(len=8) :: nu
    integer :: estat, cstat
    write(nu, '(i0)') n_uniform
    cmd = 'python3 -c "import sys, xml.dom.minidom as m; d = m.parse(sys.argv[1]); ' // &
          't = [float(e.getAttribute(''Value'')) for e in d.getElementsByTagName(''Time'')]; ' // &
          'g = [e for e in d.getElementsByTagName(''Grid'') if e.getAttribute(''GridType'') == ' // &
          '''Uniform'']; sys.exit(0 if t == '//times_list//' and len(g) == '//trim(nu)// &
          ' else 1)" '//path
    estat = -1
    cstat = -1
    call execute_command_line(trim(cmd), wait=.true., exitstat=estat, cmdstat=cstat)
    python_ok = cstat == 0 .and. estat == 0
  end function python_ok

  !> True if some line of the text file contains str.
  logical function file_has(path, str)
    character(len=*), intent(in) :: path, str
    character(len=4096) :: line
    integer :: u, ios
    file_has = .false.
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, str) > 0) then
        file_has = .true.
        exit
      end if
    end do
    close(u)
  end function file_has

end program test_xdmf_writer
