!> Unit tests of gmsh_reader (1 rank): the hand-made meshes/box_2x2x2.msh and
!> the Gmsh-written meshes/gmsh_block.msh, then variants of the first written
!> to /tmp: inputs that must read (CRLF line ends, an unknown section, unnamed
!> or missing physical volumes, an unused node) and broken inputs that must
!> give a status error naming the file and line (version 2.2, binary, a
!> truncated $Nodes block, a missing node, a tetrahedron, a triangle on a
!> tagged surface, a missing file).
!> Run from the repository root (or from one or two levels below it).
program test_gmsh_reader
  use kinds, only: rp, ip, name_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  use gmsh_reader, only: read_gmsh
  use assertions, only: test_suite_t
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  character(len=path_len) :: box, block
  character(len=1), parameter :: nl = new_line('a')
  character(len=*), parameter :: tmp = '/tmp/test_gmsh_reader_'

  call comm%init_world()
  call suite%init('gmsh_reader', comm)
  box = find_mesh('box_2x2x2.msh')
  block = find_mesh('gmsh_block.msh')
  call suite%assert_true(len_trim(box) > 0, 'meshes/box_2x2x2.msh found (run from the repository root)')
  call suite%assert_true(len_trim(block) > 0, 'meshes/gmsh_block.msh found')
  if (len_trim(box) > 0) then
    call test_box(trim(box))
    call test_variants_that_read(trim(box))
    call test_broken_variants(trim(box))
  end if
  if (len_trim(block) > 0) call test_gmsh_block(trim(block))
  call suite%finish()

contains

  !> The hand-made 2 x 2 x 2 unit cube.
  subroutine test_box(path)
    character(len=*), intent(in) :: path
    type(mesh_t) :: m
    type(error_status_t) :: st
    character(len=name_len), parameter :: sides(6) = [character(len=name_len) :: &
      'xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    integer :: s

    call read_gmsh(path, m, st)
    call suite%assert_true(st%ok(), 'box_2x2x2 reads: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_equal_int(m%n_nodes, 27, 'box: nodes')
    call suite%assert_equal_int(m%n_cells, 8, 'box: cells')
    call suite%assert_equal_int(size(m%region_names), 2, 'box: regions (rock, cap; none unused, no default)')
    call suite%assert_equal_int(count_region(m, 'rock'), 4, 'box: cells in rock')
    call suite%assert_equal_int(count_region(m, 'cap'), 4, 'box: cells in cap')
    ! sets: six sides, the fault, and "top" sharing the entity of zmax; not the
    ! physical point and curve that share tag 1 with xmin
    call suite%assert_equal_int(size(m%set_names), 8, 'box: sets')
    call suite%assert_equal_int(m%n_sfaces, 32, 'box: tagged quads (8 sets x 4)')
    do s = 1, 6
      call suite%assert_equal_int(count_set(m, sides(s)), 4, 'box: quads in '//trim(sides(s)))
      call suite%assert_true(boundary_set(m, sides(s)), 'box: '//trim(sides(s))//' quads are boundary faces')
    end do
    call suite%assert_equal_int(count_set(m, 'top'), 4, 'box: quads in top (second physical tag of zmax)')
    call suite%assert_equal_int(count_set(m, 'fault'), 4, 'box: quads in fault')
    call suite%assert_true(interior_set(m, 'fault'), 'box: fault quads are interior faces')
    call suite%assert_equal_int(m%set_id('origin') + m%set_id('bottom_edge'), 0, &
      'box: physical point and curve are not sets')
    call suite%assert_equal_int(m%n_faces, 36, 'box: unique faces')
    call suite%assert_close(total_volume(m), 1.0_rp, 1.0e-12_rp, 'box: total volume')
    ! renumbering in the order met: node tags 3 (0,0,0) then 25 (1,0,0);
    ! first hexahedron = tags 3 51 45 41 37 31 13 21
    call suite%assert_close_array(m%coords(:, 1), [0.0_rp, 0.0_rp, 0.0_rp], 0.0_rp, 'box: node 1 = first node met')
    call suite%assert_close_array(m%coords(:, 2), [1.0_rp, 0.0_rp, 0.0_rp], 0.0_rp, 'box: node 2 = second node met')
    call suite%assert_close_array(reshape(m%coords(:, m%cell_nodes(:, 1)), [24]), &
      [0.0_rp, 0.0_rp, 0.0_rp,  0.5_rp, 0.0_rp, 0.0_rp,  0.5_rp, 0.5_rp, 0.0_rp,  0.0_rp, 0.5_rp, 0.0_rp, &
       0.0_rp, 0.0_rp, 0.5_rp,  0.5_rp, 0.0_rp, 0.5_rp,  0.5_rp, 0.5_rp, 0.5_rp,  0.0_rp, 0.5_rp, 0.5_rp], &
      0.0_rp, 'box: corners of cell 1 in Gmsh order')
    call m%free()
  end subroutine test_box

  !> The mesh Gmsh 4.8 wrote from meshes/gmsh_block.geo: 3 x 2 x (3 + 2) cells.
  subroutine test_gmsh_block(path)
    character(len=*), intent(in) :: path
    type(mesh_t) :: m
    type(error_status_t) :: st
    character(len=name_len), parameter :: sides(6) = [character(len=name_len) :: &
      'xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    integer, parameter :: side_quads(6) = [10, 10, 15, 15, 6, 6]
    integer :: s

    call read_gmsh(path, m, st)
    call suite%assert_true(st%ok(), 'gmsh_block reads: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_equal_int(m%n_nodes, 4 * 3 * 6, 'gmsh_block: nodes')
    call suite%assert_equal_int(m%n_cells, 30, 'gmsh_block: cells')
    call suite%assert_equal_int(size(m%region_names), 2, 'gmsh_block: regions')
    call suite%assert_equal_int(count_region(m, 'rock'), 18, 'gmsh_block: cells in rock')
    call suite%assert_equal_int(count_region(m, 'cap'), 12, 'gmsh_block: cells in cap')
    call suite%assert_equal_int(size(m%set_names), 7, 'gmsh_block: sets')
    do s = 1, 6
      call suite%assert_equal_int(count_set(m, sides(s)), side_quads(s), 'gmsh_block: quads in '//trim(sides(s)))
      call suite%assert_true(boundary_set(m, sides(s)), 'gmsh_block: '//trim(sides(s))//' quads are boundary faces')
    end do
    call suite%assert_equal_int(count_set(m, 'fault'), 6, 'gmsh_block: quads in fault')
    call suite%assert_true(interior_set(m, 'fault'), 'gmsh_block: fault quads are interior faces')
    ! (nx+1) ny nz + nx (ny+1) nz + nx ny (nz+1) with nx, ny, nz = 3, 2, 5
    call suite%assert_equal_int(m%n_faces, 4*2*5 + 3*3*5 + 3*2*6, 'gmsh_block: unique faces')
    call suite%assert_close(total_volume(m), 1.0_rp, 1.0e-12_rp, 'gmsh_block: total volume')
    call m%free()
  end subroutine test_gmsh_block

  !> Variants of the box that are valid and must read.
  subroutine test_variants_that_read(path)
    character(len=*), intent(in) :: path
    type(mesh_t) :: m
    type(error_status_t) :: st
    character(len=:), allocatable :: v

    ! Windows line ends and sections the reader does not know
    v = tmp//'crlf.msh'
    call write_variant(path, v, [character(len=80) :: '$EndMeshFormat', '$EndElements'], &
      [character(len=200) :: '$EndMeshFormat'//nl//'$Comments'//nl//'not $Nodes'//nl//'$EndComments', &
      '$EndElements'//nl//'$NodeData'//nl//'1'//nl//'"p"'//nl//'$EndNodeData'], crlf=.true.)
    call read_gmsh(v, m, st)
    call suite%assert_true(st%ok(), 'CRLF + unknown sections read: '//trim(st%msg))
    if (st%ok()) call suite%assert_equal_int(m%n_faces, 36, 'CRLF + unknown sections: unique faces')

    ! cap's physical group unnamed -> region_20
    v = tmp//'unnamed.msh'
    call write_variant(path, v, [character(len=80) :: '3 20 "cap"'], [character(len=200) :: '3 99 "unused"'])
    call read_gmsh(v, m, st)
    call suite%assert_true(st%ok(), 'unnamed physical volume reads: '//trim(st%msg))
    if (st%ok()) then
      call suite%assert_equal_int(count_region(m, 'region_20'), 4, 'unnamed physical volume -> region_20')
      call suite%assert_equal_int(count_region(m, 'rock'), 4, 'unnamed physical volume: rock kept')
    end if

    ! cap's volume without any physical group -> default
    v = tmp//'default.msh'
    call write_variant(path, v, [character(len=80) :: '2 0 0 0.5 1 1 1 2 20 30 6 110 111 105 106 107 108'], &
      [character(len=200) :: '2 0 0 0.5 1 1 1 0 6 110 111 105 106 107 108'])
    call read_gmsh(v, m, st)
    call suite%assert_true(st%ok(), 'volume without physical group reads: '//trim(st%msg))
    if (st%ok()) then
      call suite%assert_equal_int(count_region(m, 'default'), 4, 'volume without physical group -> default')
      call suite%assert_equal_int(size(m%region_names), 2, 'volume without physical group: 2 regions')
    end if

    ! a node that no hexahedron uses is dropped
    v = tmp//'orphan.msh'
    call write_variant(path, v, [character(len=80) :: '27 27 3 55', '$EndNodes'], &
      [character(len=200) :: '28 28 3 1001', '0 99 0 1'//nl//'1001'//nl//'5 5 5'//nl//'$EndNodes'])
    call read_gmsh(v, m, st)
    call suite%assert_true(st%ok(), 'unused node reads: '//trim(st%msg))
    if (st%ok()) then
      call suite%assert_equal_int(m%n_nodes, 27, 'unused node dropped')
      call suite%assert_close(total_volume(m), 1.0_rp, 1.0e-12_rp, 'unused node: total volume')
    end if
    call m%free()
  end subroutine test_variants_that_read

  !> Broken variants: each must give a status error that names the file and
  !> says what is wrong, and leave the mesh empty.
  subroutine test_broken_variants(path)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: v

    v = tmp//'v22.msh'
    call write_variant(path, v, [character(len=80) :: '4.1 0 8'], [character(len=200) :: '2.2 0 8'])
    call expect_error(v, [character(len=32) :: 'line 2:', 'MSH version 2.2 ASCII found'], 'version 2.2')

    v = tmp//'binary.msh'
    call write_variant(path, v, [character(len=80) :: '4.1 0 8'], [character(len=200) :: '4.1 1 8'])
    call expect_error(v, [character(len=32) :: 'line 2:', 'MSH version 4.1 binary found'], 'binary file')

    ! cut inside the $Nodes block (before the coordinates of the node tagged 51)
    v = tmp//'truncated.msh'
    call write_variant(path, v, [character(len=80) :: '0.5 0 0'], [character(len=200) :: ''], cut=.true.)
    call expect_error(v, [character(len=32) :: 'unexpected end of file', 'node coordinates'], &
      'truncated $Nodes block')

    v = tmp//'missing_node.msh'
    call write_variant(path, v, [character(len=80) :: '593 3 51 45 41 37 31 13 21'], &
      [character(len=200) :: '593 3 51 45 41 37 31 13 999'])
    call expect_error(v, [character(len=32) :: 'node tag 999', 'element 593 ', 'line 198:'], &
      'element with a missing node')

    v = tmp//'tetra.msh'
    call write_variant(path, v, [character(len=80) :: '3 1 5 4'], [character(len=200) :: '3 1 4 4'])
    call expect_error(v, [character(len=32) :: '4-node tetrahedron', 'needs 8-node hexahedra'], &
      'tetrahedral element')

    v = tmp//'triangle.msh'
    call write_variant(path, v, [character(len=80) :: '2 109 3 4'], [character(len=200) :: '2 109 2 4'])
    call expect_error(v, [character(len=32) :: '3-node triangle', 'quadrangles'], 'triangle on a tagged surface')

    call expect_error(tmp//'does_not_exist.msh', [character(len=32) :: 'cannot open'], 'missing file')
  end subroutine test_broken_variants

  !> read_gmsh(path) must fail, mention the path and every string of `want`.
  subroutine expect_error(path, want, what)
    character(len=*), intent(in) :: path, want(:), what
    type(mesh_t) :: m
    type(error_status_t) :: st
    logical :: all_found
    integer :: i
    call read_gmsh(path, m, st)
    all_found = index(st%msg, path) > 0
    do i = 1, size(want)
      all_found = all_found .and. index(st%msg, trim(want(i))) > 0
    end do
    call suite%assert_true(.not. st%ok(), trim(what)//' gives an error')
    call suite%assert_true(all_found, trim(what)//', message: '//trim(st%msg))
    call suite%assert_true(m%n_cells == 0 .and. .not. allocated(m%coords), trim(what)//': mesh left empty')
  end subroutine expect_error

  !> Copy src to dst, replacing each line equal to old(i) by new(i) (which may
  !> hold several lines), or stopping before it when cut; crlf writes "\r\n".
  subroutine write_variant(src, dst, old, new, cut, crlf)
    character(len=*), intent(in) :: src, dst, old(:), new(:)
    logical, intent(in), optional :: cut, crlf
    character(len=512) :: line
    character(len=:), allocatable :: text, eol
    integer :: uin, uout, ios, i, k
    eol = ''
    if (present(crlf)) then
      if (crlf) eol = achar(13)
    end if
    open(newunit=uin, file=src, status='old', action='read', iostat=ios)
    if (ios /= 0) error stop 'test_gmsh_reader: cannot open the source mesh'
    open(newunit=uout, file=dst, status='replace', action='write', iostat=ios)
    if (ios /= 0) error stop 'test_gmsh_reader: cannot write to /tmp'
    lines: do
      read(uin, '(a)', iostat=ios) line
      if (ios /= 0) exit lines
      text = trim(line)
      do i = 1, size(old)
        if (text == trim(old(i))) then
          if (present(cut)) then
            if (cut) exit lines
          end if
          text = trim(new(i))
        end if
      end do
      ! a replacement may span lines: each gets the line end
      do
        k = index(text, nl)
        if (k == 0) exit
        write(uout, '(a)') text(1:k-1)//eol
        text = text(k+1:)
      end do
      write(uout, '(a)') text//eol
    end do lines
    close(uin)
    close(uout)
  end subroutine write_variant

  !> Path of meshes/<name> from the repository root or one or two levels below.
  function find_mesh(name) result(path)
    character(len=*), intent(in) :: name
    character(len=path_len) :: path
    character(len=6), parameter :: up(3) = [character(len=6) :: '', '../', '../../']
    logical :: there
    integer :: i
    do i = 1, size(up)
      path = trim(up(i))//'meshes/'//name
      inquire(file=trim(path), exist=there)
      if (there) return
    end do
    path = ''
  end function find_mesh

  integer function count_region(m, name)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer(ip) :: r
    r = m%region_id(name)
    count_region = -1
    if (r > 0) count_region = count(m%cell_region == r)
  end function count_region

  integer function count_set(m, name)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer(ip) :: s
    s = m%set_id(name)
    count_set = -1
    if (s > 0) count_set = count(m%sface_set == s)
  end function count_set

  !> Every quad of the set lies on the boundary (one cell).
  logical function boundary_set(m, name)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    boundary_set = all(pack(m%face_cells(2, m%sface_face), m%sface_set == m%set_id(name)) == 0) &
      .and. m%set_id(name) > 0
  end function boundary_set

  !> Every quad of the set is shared by two cells.
  logical function interior_set(m, name)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    interior_set = all(pack(m%face_cells(2, m%sface_face), m%sface_set == m%set_id(name)) /= 0) &
      .and. m%set_id(name) > 0
  end function interior_set

  !> Sum of the cell volumes by 2 x 2 x 2 Gauss quadrature of det(dx/dxi)
  !> (exact for trilinear hexahedra).
  real(rp) function total_volume(m)
    type(mesh_t), intent(in) :: m
    real(rp), parameter :: g = 1.0_rp / sqrt(3.0_rp)
    real(rp), parameter :: s(3, 8) = reshape([ &
      -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1, &
      -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1], [3, 8])
    real(rp) :: x(3, 8), dn(3, 8), j(3, 3), xi(3)
    integer :: c, q, a
    total_volume = 0.0_rp
    do c = 1, m%n_cells
      x = m%coords(:, m%cell_nodes(:, c))
      do q = 1, 8
        xi = g * s(:, q)
        do a = 1, 8
          dn(1, a) = 0.125_rp * s(1, a) * (1 + s(2, a) * xi(2)) * (1 + s(3, a) * xi(3))
          dn(2, a) = 0.125_rp * s(2, a) * (1 + s(1, a) * xi(1)) * (1 + s(3, a) * xi(3))
          dn(3, a) = 0.125_rp * s(3, a) * (1 + s(1, a) * xi(1)) * (1 + s(2, a) * xi(2))
        end do
        j = matmul(x, transpose(dn))
        total_volume = total_volume + j(1,1) * (j(2,2) * j(3,3) - j(2,3) * j(3,2)) &
          - j(1,2) * (j(2,1) * j(3,3) - j(2,3) * j(3,1)) + j(1,3) * (j(2,1) * j(3,2) - j(2,2) * j(3,1))
      end do
    end do
  end function total_volume
end program test_gmsh_reader
