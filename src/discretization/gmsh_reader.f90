!> Reader of Gmsh MSH 4.1 ASCII files holding 8-node hexahedral meshes.
!>
!> Fills the global serial mesh_t on rank 0:
!> - cells: the 8-node hexahedra (element type 5) of the volume entities; Gmsh's
!>   node order is the one mesh_t uses. Each cell's region is the first physical
!>   group (dimension 3) of its volume entity, named from $PhysicalNames, or
!>   "region_<tag>" when unnamed; cells in a volume without a physical group go
!>   to a region named "default".
!> - tagged surfaces: the 4-node quadrangles (type 3) of the surface entities that
!>   carry physical groups (boundary sets and internal surfaces such as faults).
!>   A quad belongs to every physical group of its entity; sets are named from
!>   $PhysicalNames, or "set_<tag>" when unnamed.
!> - nodes: renumbered 1..n in the order the file lists them, keeping only the
!>   nodes that some hexahedron uses (an unused node would become a degree of
!>   freedom without any equation).
!> Points and lines are ignored, as is everything on untagged surfaces; any other
!> element in a volume (tetrahedra, prisms, pyramids, second-order elements) and
!> any non-quad on a tagged surface is an error. Sections the reader does not
!> need ($Periodic, $NodeData, ...) are skipped; partitioned files are refused.
!> Errors name the file, the line and what was expected there. Node
!> coordinates are checked as text before conversion (nan, inf, 1e400 and
!> garbage refused; magnitudes beyond 1e30 m too), and every count of a
!> header is checked against the size of the file before anything is
!> allocated for it; mesh%check then refuses degenerate hexahedra.
module gmsh_reader
  use kinds, only: rp, ip, gp, name_len, msg_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  use os_services, only: path_kind, path_directory
  use number_text, only: real_token_problem
  implicit none
  private

  public :: read_gmsh

  integer(ip), parameter :: type_quad4 = 3
  integer(ip), parameter :: type_hex8 = 5

  !> Region/set key of elements whose entity has no physical group; the largest
  !> value so that "default" comes after the physical groups.
  integer(ip), parameter :: no_physical = huge(1_ip)

  !> Nodes of the Gmsh element types 1..19 (type_name lists their names).
  integer(ip), parameter :: type_nodes(19) = [2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20, 15, 13]

  !> The fewest bytes an entry of a section can take in the file, to refuse
  !> a count no file of this size can hold before anything is allocated for
  !> it: a node is a tag line and a coordinate line ("1", "0 0 0"), a node
  !> or element block header four numbers, a physical name "d t n", an
  !> entity at least five numbers; an element line its tag and node tags.
  !> Largest coordinate magnitude accepted [m]: far beyond any geometry, and
  !> small enough that products of a few lengths (volumes, det J) stay finite.
  real(rp), parameter :: max_coord = 1.0e30_rp

  integer(gp), parameter :: node_bytes = 8, block_bytes = 8, name_bytes = 6, entity_bytes = 10

  !> The open file and the current line, for error messages.
  type :: msh_file_t
    integer :: unit = -1
    integer(gp) :: line_no = 0
    character(len=:), allocatable :: path
    character(len=:), allocatable :: line   !< current line, without a trailing carriage return
    integer(gp) :: bytes = 0                !< size of the file [bytes]
  end type msh_file_t

  !> Physical tags of the geometric entities of one dimension (from $Entities).
  type :: entity_table_t
    integer(ip) :: n = 0
    integer(ip), allocatable :: tag(:)      !< (n) entity tags
    integer(ip), allocatable :: first(:)    !< (n+1) physical tags of entity i: phys(first(i):first(i+1)-1)
    integer(ip), allocatable :: phys(:)
  end type entity_table_t

  !> What the sections of the file hold, before it becomes a mesh_t.
  type :: msh_content_t
    logical :: seen_format = .false.
    logical :: seen_names = .false.
    logical :: seen_entities = .false.
    logical :: seen_nodes = .false.
    logical :: seen_elements = .false.
    ! $PhysicalNames
    integer(ip) :: n_names = 0
    integer(ip), allocatable :: name_dim(:), name_tag(:)
    character(len=name_len), allocatable :: name_str(:)
    ! $Entities, by dimension (only surfaces and volumes are looked up)
    type(entity_table_t) :: entities(0:3)
    ! $Nodes, in the order met; node_sorted_tag/node_sorted_id map a tag to its index
    integer(ip) :: n_nodes = 0
    real(rp), allocatable :: coords(:,:)
    integer(gp), allocatable :: node_sorted_tag(:)
    integer(ip), allocatable :: node_sorted_id(:)
    ! hexahedra (node indices in the order met) and their region key
    integer(ip) :: n_hex = 0
    integer(ip), allocatable :: hex_nodes(:,:), hex_key(:)
    integer(gp), allocatable :: hex_tag(:)
    ! tagged quads, one entry per (quad, physical tag); element tags for messages
    integer(ip) :: n_quad = 0
    integer(ip), allocatable :: quad_nodes(:,:), quad_key(:)
    integer(gp), allocatable :: quad_elem(:)
  end type msh_content_t

contains

  !> Read the Gmsh MSH 4.1 ASCII file `path` into `mesh` (serial; rank 0),
  !> then check the mesh and build its faces. On failure status holds a message
  !> naming the file and, where it applies, the line.
  subroutine read_gmsh(path, mesh, status)
    character(len=*), intent(in) :: path
    type(mesh_t), intent(inout) :: mesh
    type(error_status_t), intent(inout) :: status
    type(msh_file_t) :: f
    type(msh_content_t) :: c
    type(error_status_t) :: st
    integer :: ios
    character(len=msg_len) :: iom

    call mesh%free()
    f%path = trim(path)
    if (path_kind(f%path) == path_directory) then
      call status%set('gmsh reader: cannot open "'//f%path//'": it is a directory, not a mesh file')
      return
    end if
    open(newunit=f%unit, file=f%path, status='old', action='read', form='formatted', &
      access='sequential', iostat=ios, iomsg=iom)
    if (ios /= 0) then
      call status%set('gmsh reader: cannot open "'//f%path//'": '//trim(iom))
      return
    end if
    inquire(unit=f%unit, size=f%bytes, iostat=ios)
    if (ios /= 0) f%bytes = huge(1_gp)
    call read_sections(f, c, st)
    close(f%unit)
    if (st%ok()) call fill_mesh(f, c, mesh, st)
    if (st%ok()) then
      call mesh%check(st)
      if (st%ok()) call mesh%build_faces(st)
      if (.not. st%ok()) call st%set('gmsh reader: '//f%path//': '//trim(st%msg))
    end if
    if (.not. st%ok()) then
      call mesh%free()
      call status%set(trim(st%msg))
    end if
  end subroutine read_gmsh

  ! ---------------------------------------------------------------- sections

  !> Dispatch on the section headers until the end of the file.
  subroutine read_sections(f, c, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: head
    logical :: at_end

    do
      call next_line(f, 'a section header', status, at_end)
      if (at_end .or. .not. status%ok()) exit
      head = trim(adjustl(f%line))
      if (len(head) == 0) cycle
      if (.not. c%seen_format .and. head /= '$MeshFormat') then
        call bad_line(f, 'expected $MeshFormat: this is not a Gmsh MSH file', status)
        return
      end if
      select case (head)
      case ('$MeshFormat')
        call once(c%seen_format)
        if (status%ok()) call read_format(f, status)
      case ('$PhysicalNames')
        call once(c%seen_names)
        if (status%ok()) call read_physical_names(f, c, status)
      case ('$Entities')
        call once(c%seen_entities)
        if (c%seen_elements) call bad_line(f, '$Entities must come before $Elements', status)
        if (status%ok()) call read_entities(f, c, status)
      case ('$PartitionedEntities')
        call bad_line(f, 'partitioned mesh files are not supported: save the mesh unpartitioned', status)
      case ('$Nodes')
        call once(c%seen_nodes)
        if (status%ok()) call read_nodes(f, c, status)
      case ('$Elements')
        call once(c%seen_elements)
        if (.not. c%seen_nodes) call bad_line(f, '$Nodes must come before $Elements', status)
        if (status%ok()) call read_elements(f, c, status)
      case default
        if (head(1:1) == '$' .and. index(head, '$End') /= 1) then
          call skip_section(f, head, status)
        else
          call bad_line(f, 'expected a section header such as $Nodes', status)
        end if
      end select
      if (.not. status%ok()) return
    end do
    if (.not. status%ok()) return
    if (.not. c%seen_format) then
      call fail(f, 'empty file: expected a Gmsh MSH file', status)
    else if (.not. c%seen_nodes) then
      call fail(f, 'no $Nodes section', status)
    else if (.not. c%seen_elements) then
      call fail(f, 'no $Elements section', status)
    end if
  contains
    subroutine once(seen)
      logical, intent(inout) :: seen
      if (seen) call bad_line(f, 'the section '//head//' appears twice', status)
      seen = .true.
    end subroutine once
  end subroutine read_sections

  !> $MeshFormat: only version 4.1 in ASCII (file-type 0) is accepted.
  subroutine read_format(f, status)
    type(msh_file_t), intent(inout) :: f
    type(error_status_t), intent(inout) :: status
    character(len=16) :: version
    character(len=24) :: form
    integer :: file_type, data_size, ios
    character(len=msg_len) :: iom

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    call next_line(f, 'the format line "4.1 0 8"', status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) version, file_type, data_size
    if (ios /= 0) then
      call bad_line(f, 'expected the format line "version file-type data-size", e.g. "4.1 0 8"', status, iom)
      return
    end if
    if (trim(version) /= '4.1' .or. file_type /= 0) then
      if (file_type == 0) then
        form = 'ASCII'
      else if (file_type == 1) then
        form = 'binary'
      else
        write(form, '(a,i0)') 'file-type ', file_type
      end if
      call bad_line(f, 'MSH version '//trim(version)//' '//trim(form)//' found, but geoblock reads '// &
        'MSH 4.1 ASCII only (in Gmsh: Mesh.MshFileVersion = 4.1; Mesh.Binary = 0;)', status)
      return
    end if
    call expect_line(f, '$EndMeshFormat', status)
  end subroutine read_format

  !> $PhysicalNames: "dimension tag "name"" per line.
  subroutine read_physical_names(f, c, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    type(error_status_t), intent(inout) :: status
    integer(ip) :: n, i
    integer :: ios
    character(len=msg_len) :: iom
    character(len=256) :: name

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    call next_line(f, 'the number of physical names', status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) n
    if (ios /= 0) then
      call bad_line(f, 'expected the number of physical names', status, iom)
      return
    end if
    call check_count(f, int(n, gp), name_bytes, 'physical names', status)
    if (.not. status%ok()) return
    c%n_names = n
    allocate(c%name_dim(n), c%name_tag(n), c%name_str(n))
    do i = 1, n
      call next_line(f, 'a physical name: dimension tag "name"', status)
      if (.not. status%ok()) return
      name = ''
      read(f%line, *, iostat=ios, iomsg=iom) c%name_dim(i), c%name_tag(i), name
      if (ios /= 0) then
        call bad_line(f, 'expected a physical name: dimension tag "name"', status, iom)
        return
      end if
      if (len_trim(name) > name_len) then
        call bad_line(f, 'physical name longer than the allowed characters', status)
        return
      end if
      c%name_str(i) = name(1:name_len)
    end do
    call expect_line(f, '$EndPhysicalNames', status)
  end subroutine read_physical_names

  !> $Entities: the physical tags of each surface and volume.
  subroutine read_entities(f, c, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    type(error_status_t), intent(inout) :: status
    integer(ip) :: counts(0:3), dim, i, tag, n_box, n_phys
    integer(ip), allocatable :: phys(:)
    integer :: ios
    character(len=64) :: box(6)   ! bounding boxes are not used: read as text, never converted
    character(len=msg_len) :: iom
    character(len=*), parameter :: what(0:3) = [character(len=70) :: &
      'a point entity: tag x y z numPhysicalTags physicalTags', &
      'a curve entity: tag bounding-box(6) numPhysicalTags physicalTags ...', &
      'a surface entity: tag bounding-box(6) numPhysicalTags physicalTags ...', &
      'a volume entity: tag bounding-box(6) numPhysicalTags physicalTags ...']

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    call next_line(f, 'the entity counts', status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) counts
    if (ios /= 0) then
      call bad_line(f, 'expected the entity counts "numPoints numCurves numSurfaces numVolumes"', status, iom)
      return
    end if
    do dim = 0, 3
      call check_count(f, int(counts(dim), gp), entity_bytes, 'entities of dimension '//str(int(dim, gp)), status)
    end do
    if (status%ok()) call check_count(f, sum(int(counts, gp)), entity_bytes, 'entities', status)
    if (.not. status%ok()) return
    do dim = 0, 3
      call table_init(c%entities(dim), counts(dim))
    end do
    do dim = 0, 3
      n_box = merge(3_ip, 6_ip, dim == 0)
      do i = 1, counts(dim)
        call next_line(f, trim(what(dim)), status)
        if (.not. status%ok()) return
        allocate(phys(0))
        read(f%line, *, iostat=ios, iomsg=iom) tag, box(1:n_box), n_phys
        if (ios == 0 .and. n_phys > len(f%line) / 2) then
          call bad_line(f, 'the entity claims '//str(int(n_phys, gp))//' physical tags, more than its line holds', &
            status)
          return
        end if
        if (ios == 0 .and. n_phys > 0) then
          deallocate(phys)
          allocate(phys(n_phys))
          read(f%line, *, iostat=ios, iomsg=iom) tag, box(1:n_box), n_phys, phys
        end if
        if (ios /= 0 .or. n_phys < 0) then
          call bad_line(f, 'expected '//trim(what(dim)), status, iom)
          return
        end if
        call table_add(c%entities(dim), tag, phys)
        deallocate(phys)
      end do
    end do
    call expect_line(f, '$EndEntities', status)
  end subroutine read_entities

  !> $Nodes: blocks of tags then coordinates; the map tag -> index is built at the end.
  subroutine read_nodes(f, c, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    type(error_status_t), intent(inout) :: status
    integer(gp) :: n_blocks, n_total, tag_range(2), n_in, b, k, i
    integer(gp), allocatable :: tags(:)
    integer(ip) :: entity(3)
    integer :: ios
    character(len=msg_len) :: iom, m

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    call next_line(f, 'the $Nodes header', status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) n_blocks, n_total, tag_range
    if (ios /= 0) then
      call bad_line(f, 'expected the $Nodes header "numEntityBlocks numNodes minNodeTag maxNodeTag" '// &
        '(four integers)', status, iom)
      return
    end if
    call check_count(f, n_blocks, block_bytes, 'node blocks', status)
    if (status%ok()) call check_count(f, n_total, node_bytes, 'nodes', status)
    if (.not. status%ok()) return
    if (n_total > huge(1_ip)) then
      call bad_line(f, 'too many nodes for 32-bit local indices', status)
      return
    end if
    c%n_nodes = int(n_total, ip)
    allocate(c%coords(3, c%n_nodes), tags(c%n_nodes))
    k = 0
    do b = 1, n_blocks
      call next_line(f, 'a node block header', status)
      if (.not. status%ok()) return
      read(f%line, *, iostat=ios, iomsg=iom) entity, n_in
      if (ios /= 0) then
        call bad_line(f, 'expected a node block header "entityDim entityTag parametric numNodesInBlock" '// &
          '(four integers)', status, iom)
        return
      end if
      call check_count(f, n_in, node_bytes, 'nodes in the block', status)
      if (.not. status%ok()) return
      if (k + n_in > n_total) then
        write(m, '(a,i0,a)') 'the node blocks hold more nodes than the $Nodes header says (', n_total, ')'
        call bad_line(f, trim(m), status)
        return
      end if
      do i = k + 1, k + n_in
        call next_line(f, 'a node tag', status)
        if (.not. status%ok()) return
        read(f%line, *, iostat=ios, iomsg=iom) tags(i)
        if (ios /= 0 .or. tags(i) < 1) then
          call bad_line(f, 'expected a node tag (a positive integer)', status, iom)
          return
        end if
      end do
      do i = k + 1, k + n_in
        call next_line(f, 'node coordinates "x y z"', status)
        if (.not. status%ok()) return
        call read_coords(f, tags(i), c%coords(:, i), status)
        if (.not. status%ok()) return
      end do
      k = k + n_in
    end do
    call next_line(f, '$EndNodes', status)
    if (.not. status%ok()) return
    if (k /= n_total) then
      write(m, '(a,i0,a,i0,a)') 'the node blocks hold ', k, ' nodes, but the $Nodes header says ', n_total, &
        ' (expected $EndNodes here)'
      call bad_line(f, trim(m), status)
      return
    end if
    if (trim(adjustl(f%line)) /= '$EndNodes') then
      call bad_line(f, 'expected $EndNodes', status)
      return
    end if
    call build_node_map(f, c, tags, status)
  end subroutine read_nodes

  !> Sort the node tags for lookup; a tag defined twice is an error.
  subroutine build_node_map(f, c, tags, status)
    type(msh_file_t), intent(in) :: f
    type(msh_content_t), intent(inout) :: c
    integer(gp), intent(in) :: tags(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i
    character(len=msg_len) :: m

    allocate(c%node_sorted_id(c%n_nodes))
    call sort_order(tags, c%node_sorted_id)
    c%node_sorted_tag = tags(c%node_sorted_id)
    do i = 2, c%n_nodes
      if (c%node_sorted_tag(i) == c%node_sorted_tag(i-1)) then
        write(m, '(a,i0,a)') 'node tag ', c%node_sorted_tag(i), ' is defined twice in $Nodes'
        call bad_line(f, trim(m), status)
        return
      end if
    end do
  end subroutine build_node_map

  !> Index (order met) of node tag `tag`, 0 if $Nodes does not define it.
  integer(ip) function node_index(c, tag)
    type(msh_content_t), intent(in) :: c
    integer(gp), intent(in) :: tag
    integer(ip) :: lo, hi, mid
    node_index = 0
    lo = 1
    hi = c%n_nodes
    do while (lo <= hi)
      mid = lo + (hi - lo) / 2
      if (c%node_sorted_tag(mid) == tag) then
        node_index = c%node_sorted_id(mid)
        return
      else if (c%node_sorted_tag(mid) < tag) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function node_index

  !> $Elements: blocks of elements of one type on one entity.
  subroutine read_elements(f, c, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    type(error_status_t), intent(inout) :: status
    integer(gp) :: n_blocks, n_total, tag_range(2), n_in, b, k
    integer(ip) :: entity_dim, entity_tag, elem_type
    integer :: ios
    character(len=msg_len) :: iom, m

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    call next_line(f, 'the $Elements header', status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) n_blocks, n_total, tag_range
    if (ios /= 0) then
      call bad_line(f, 'expected the $Elements header "numEntityBlocks numElements minElementTag maxElementTag" '// &
        '(four integers)', status, iom)
      return
    end if
    call check_count(f, n_blocks, block_bytes, 'element blocks', status)
    if (status%ok()) call check_count(f, n_total, 4_gp, 'elements', status)
    if (.not. status%ok()) return
    k = 0
    do b = 1, n_blocks
      call next_line(f, 'an element block header', status)
      if (.not. status%ok()) return
      read(f%line, *, iostat=ios, iomsg=iom) entity_dim, entity_tag, elem_type, n_in
      if (ios /= 0 .or. entity_dim < 0 .or. entity_dim > 3) then
        call bad_line(f, 'expected an element block header "entityDim entityTag elementType numElementsInBlock"', &
          status, iom)
        return
      end if
      call check_count(f, n_in, element_bytes(elem_type), 'elements in the block', status)
      if (.not. status%ok()) return
      if (n_in > huge(1_ip)) then
        call bad_line(f, 'too many elements for 32-bit local indices', status)
        return
      end if
      select case (entity_dim)
      case (3)
        call read_hex_block(f, c, entity_tag, elem_type, int(n_in, ip), status)
      case (2)
        call read_quad_block(f, c, entity_tag, elem_type, int(n_in, ip), status)
      case default
        call skip_elements(f, int(n_in, ip), status)
      end select
      if (.not. status%ok()) return
      k = k + n_in
    end do
    call next_line(f, '$EndElements', status)
    if (.not. status%ok()) return
    if (k /= n_total) then
      write(m, '(a,i0,a,i0,a)') 'the element blocks hold ', k, ' elements, but the $Elements header says ', &
        n_total, ' (expected $EndElements here)'
      call bad_line(f, trim(m), status)
    else if (trim(adjustl(f%line)) /= '$EndElements') then
      call bad_line(f, 'expected $EndElements', status)
    end if
  end subroutine read_elements

  !> A block on a volume entity: only 8-node hexahedra are accepted.
  subroutine read_hex_block(f, c, entity_tag, elem_type, n_in, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    integer(ip), intent(in) :: entity_tag, elem_type, n_in
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: phys(:)
    integer(ip) :: e, key
    character(len=msg_len) :: m

    if (elem_type /= type_hex8) then
      write(m, '(a,i0,a,a,a,i0,a)') 'element type ', elem_type, ' (', trim(type_name(elem_type)), &
        ') in volume entity ', entity_tag, ': geoblock needs 8-node hexahedra (type 5; in Gmsh use '// &
        'Transfinite + Recombine or extrusion with Layers + Recombine)'
      call bad_line(f, trim(m), status)
      return
    end if
    call entity_physicals(f, c, 3_ip, entity_tag, phys, status)
    if (.not. status%ok()) return
    key = no_physical
    if (size(phys) > 0) key = phys(1)
    if (int(c%n_hex, gp) + n_in > huge(1_ip)) then
      call bad_line(f, 'too many hexahedra for 32-bit local indices', status)
      return
    end if
    call reserve_i2(c%hex_nodes, 8_ip, c%n_hex + n_in)
    call reserve_i1(c%hex_key, c%n_hex + n_in)
    call reserve_g1(c%hex_tag, c%n_hex + n_in)
    do e = 1, n_in
      c%n_hex = c%n_hex + 1
      call read_element_line(f, c, 'a hexahedron "elementTag node1 ... node8"', c%hex_nodes(:, c%n_hex), status, &
        c%hex_tag(c%n_hex))
      if (.not. status%ok()) return
      c%hex_key(c%n_hex) = key
    end do
  end subroutine read_hex_block

  !> A block on a surface entity: kept (as quadrangles) only when the entity
  !> carries physical groups; one entry per physical group.
  subroutine read_quad_block(f, c, entity_tag, elem_type, n_in, status)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(inout) :: c
    integer(ip), intent(in) :: entity_tag, elem_type, n_in
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: phys(:)
    integer(ip) :: e, p, n_new, nodes(4)
    integer(gp) :: elem_tag
    character(len=msg_len) :: m

    call entity_physicals(f, c, 2_ip, entity_tag, phys, status)
    if (.not. status%ok()) return
    if (size(phys) == 0) then
      call skip_elements(f, n_in, status)
      return
    end if
    if (elem_type /= type_quad4) then
      write(m, '(a,i0,a,a,a,i0,a)') 'element type ', elem_type, ' (', trim(type_name(elem_type)), &
        ') on surface entity ', entity_tag, ', which carries physical groups: geoblock needs 4-node '// &
        'quadrangles (type 3) on tagged surfaces'
      call bad_line(f, trim(m), status)
      return
    end if
    if (int(c%n_quad, gp) + int(n_in, gp) * size(phys) > huge(1_ip)) then
      call bad_line(f, 'too many surface quadrangles for 32-bit local indices', status)
      return
    end if
    n_new = c%n_quad + n_in * size(phys, kind=ip)
    call reserve_i2(c%quad_nodes, 4_ip, n_new)
    call reserve_i1(c%quad_key, n_new)
    call reserve_g1(c%quad_elem, n_new)
    do e = 1, n_in
      call read_element_line(f, c, 'a quadrangle "elementTag node1 ... node4"', nodes, status, elem_tag)
      if (.not. status%ok()) return
      do p = 1, size(phys, kind=ip)
        c%n_quad = c%n_quad + 1
        c%quad_nodes(:, c%n_quad) = nodes
        c%quad_key(c%n_quad) = phys(p)
        c%quad_elem(c%n_quad) = elem_tag
      end do
    end do
  end subroutine read_quad_block

  !> Read one element line "elementTag nodeTag..." and map the node tags to
  !> indices; a tag that $Nodes does not define is an error.
  subroutine read_element_line(f, c, what, nodes, status, elem_tag)
    type(msh_file_t), intent(inout) :: f
    type(msh_content_t), intent(in) :: c
    character(len=*), intent(in) :: what
    integer(ip), intent(out) :: nodes(:)
    type(error_status_t), intent(inout) :: status
    integer(gp), intent(out), optional :: elem_tag
    integer(gp) :: tag, node_tags(size(nodes))
    integer :: ios, i
    character(len=msg_len) :: iom, m

    iom = ''   ! iomsg is left alone by successful reads; messages may quote it
    nodes = 0
    if (present(elem_tag)) elem_tag = 0
    call next_line(f, what, status)
    if (.not. status%ok()) return
    read(f%line, *, iostat=ios, iomsg=iom) tag, node_tags
    if (ios /= 0) then
      call bad_line(f, 'expected '//what, status, iom)
      return
    end if
    if (present(elem_tag)) elem_tag = tag
    do i = 1, size(nodes)
      nodes(i) = node_index(c, node_tags(i))
      if (nodes(i) == 0) then
        write(m, '(a,i0,a,i0,a)') 'element ', tag, ' refers to node tag ', node_tags(i), &
          ', which $Nodes does not define'
        call bad_line(f, trim(m), status)
        return
      end if
    end do
  end subroutine read_element_line

  !> Skip n element lines of a block the reader ignores (still checking that
  !> the block is complete).
  subroutine skip_elements(f, n, status)
    type(msh_file_t), intent(inout) :: f
    integer(ip), intent(in) :: n
    type(error_status_t), intent(inout) :: status
    integer(ip) :: e
    do e = 1, n
      call next_line(f, 'an element line', status)
      if (.not. status%ok()) return
      if (index(adjustl(f%line), '$') == 1) then
        call bad_line(f, 'expected an element line: the element block is shorter than its header says', status)
        return
      end if
    end do
  end subroutine skip_elements

  !> Physical tags of entity (dim, tag); none when the file has no $Entities.
  subroutine entity_physicals(f, c, dim, tag, phys, status)
    type(msh_file_t), intent(in) :: f
    type(msh_content_t), intent(in) :: c
    integer(ip), intent(in) :: dim, tag
    integer(ip), allocatable, intent(out) :: phys(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i
    character(len=msg_len) :: m

    allocate(phys(0))
    if (.not. c%seen_entities) return
    i = table_find(c%entities(dim), tag)
    if (i == 0) then
      write(m, '(a,i0,a,i0,a)') 'the element block refers to entity ', tag, ' of dimension ', dim, &
        ', which $Entities does not list'
      call bad_line(f, trim(m), status)
      return
    end if
    phys = c%entities(dim)%phys(c%entities(dim)%first(i):c%entities(dim)%first(i+1) - 1)
  end subroutine entity_physicals

  !> Skip a section the reader does not use, up to its $End line.
  subroutine skip_section(f, head, status)
    type(msh_file_t), intent(inout) :: f
    character(len=*), intent(in) :: head
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: end_tag
    end_tag = '$End'//head(2:)
    do
      call next_line(f, end_tag, status)
      if (.not. status%ok()) return
      if (trim(adjustl(f%line)) == end_tag) return
    end do
  end subroutine skip_section

  ! ---------------------------------------------------------------- mesh_t

  !> Turn the file content into the mesh: drop nodes no hexahedron uses,
  !> renumber, and name regions and sets.
  subroutine fill_mesh(f, c, mesh, status)
    type(msh_file_t), intent(in) :: f
    type(msh_content_t), intent(in) :: c
    type(mesh_t), intent(inout) :: mesh
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: new_id(:)
    integer(ip) :: i, k

    if (c%n_hex == 0) then
      call fail(f, 'no 8-node hexahedra in the file', status)
      return
    end if
    allocate(new_id(c%n_nodes))
    new_id = 0
    do i = 1, c%n_hex
      do k = 1, 8
        new_id(c%hex_nodes(k, i)) = 1
      end do
    end do
    k = 0
    do i = 1, c%n_nodes
      if (new_id(i) /= 0) then
        k = k + 1
        new_id(i) = k
      end if
    end do
    mesh%n_nodes = k
    allocate(mesh%coords(3, k))
    do i = 1, c%n_nodes
      if (new_id(i) /= 0) mesh%coords(:, new_id(i)) = c%coords(:, i)
    end do
    mesh%n_cells = c%n_hex
    mesh%cell_tag = c%hex_tag(1:c%n_hex)
    allocate(mesh%cell_nodes(8, c%n_hex))
    do i = 1, c%n_hex
      mesh%cell_nodes(:, i) = new_id(c%hex_nodes(:, i))
    end do
    call name_groups(c, 3_ip, c%hex_key(1:c%n_hex), mesh%region_names, mesh%cell_region)

    mesh%n_sfaces = c%n_quad
    allocate(mesh%sface_nodes(4, c%n_quad))
    do i = 1, c%n_quad
      mesh%sface_nodes(:, i) = new_id(c%quad_nodes(:, i))
      if (any(mesh%sface_nodes(:, i) == 0)) then
        call fail(f, 'surface quadrangle '//str(c%quad_elem(i))//' uses a node that belongs to no hexahedron', &
          status)
        return
      end if
    end do
    if (c%n_quad > 0) then
      call name_groups(c, 2_ip, c%quad_key(1:c%n_quad), mesh%set_names, mesh%sface_set)
    else
      allocate(mesh%set_names(0), mesh%sface_set(0))
    end if
  end subroutine fill_mesh

  !> Names of the groups (regions or sets) and the group index of each
  !> element, from the physical tags `keys` of dimension `dim`. Groups come in
  !> increasing physical tag, "default" last; two tags with the same name merge.
  subroutine name_groups(c, dim, keys, names, group)
    type(msh_content_t), intent(in) :: c
    integer(ip), intent(in) :: dim, keys(:)
    character(len=name_len), allocatable, intent(out) :: names(:)
    integer(ip), allocatable, intent(out) :: group(:)
    integer(ip), allocatable :: order(:), distinct(:), slot(:)
    character(len=name_len), allocatable :: all_names(:)
    integer(ip) :: i, j, n, nd

    n = size(keys, kind=ip)
    allocate(order(n), distinct(n))
    call sort_order(int(keys, gp), order)
    nd = 0
    do i = 1, n
      if (nd > 0) then
        if (keys(order(i)) == distinct(nd)) cycle
      end if
      nd = nd + 1
      distinct(nd) = keys(order(i))
    end do
    allocate(all_names(nd), slot(nd))
    j = 0
    do i = 1, nd
      all_names(i) = physical_name(c, dim, distinct(i))
      slot(i) = findloc(all_names(1:i), all_names(i), dim=1, kind=ip)
      if (slot(i) == i) then
        j = j + 1
        all_names(j) = all_names(i)
        slot(i) = j
      end if
    end do
    names = all_names(1:j)
    allocate(group(n))
    do i = 1, n
      group(i) = slot(findloc(distinct(1:nd), keys(i), dim=1))
    end do
  end subroutine name_groups

  !> Name of physical group (dim, tag): from $PhysicalNames, else
  !> region_<tag> / set_<tag>; "default" for elements without a group.
  function physical_name(c, dim, tag) result(name)
    type(msh_content_t), intent(in) :: c
    integer(ip), intent(in) :: dim, tag
    character(len=name_len) :: name
    integer(ip) :: i
    if (tag == no_physical) then
      name = 'default'
      return
    end if
    do i = 1, c%n_names
      if (c%name_dim(i) == dim .and. c%name_tag(i) == tag .and. len_trim(c%name_str(i)) > 0) then
        name = c%name_str(i)
        return
      end if
    end do
    if (dim == 3) then
      write(name, '(a,i0)') 'region_', tag
    else
      write(name, '(a,i0)') 'set_', tag
    end if
  end function physical_name

  ! ---------------------------------------------------------------- lines and errors

  !> A count read from a header (the current line) must not be negative and
  !> must fit in the file: n entries of at least `bytes` bytes each. Checked
  !> before anything is allocated for them.
  subroutine check_count(f, n, bytes, what, status)
    type(msh_file_t), intent(in) :: f
    integer(gp), intent(in) :: n, bytes
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    if (.not. status%ok()) return
    if (n < 0) then
      call bad_line(f, 'the header claims '//str(n)//' '//what//': a count must not be negative', status)
    else if (n > f%bytes / bytes) then
      call bad_line(f, 'the header claims '//str(n)//' '//what//', more than the file ('//str(f%bytes)// &
        ' bytes) can hold at '//str(bytes)//' bytes or more each: the file is cut short or the header is wrong', &
        status)
    end if
  end subroutine check_count

  !> The fewest bytes an element line of Gmsh type elem_type takes: its tag
  !> and node tags, one digit and one separator each.
  pure integer(gp) function element_bytes(elem_type)
    integer(ip), intent(in) :: elem_type
    element_bytes = 4
    if (elem_type >= 1 .and. elem_type <= size(type_nodes)) element_bytes = 2 * (1 + type_nodes(elem_type))
  end function element_bytes

  !> The coordinates x(3) of the node tagged `tag` from the current line:
  !> the first three fields, each checked as text to be a finite double
  !> before it is converted (further fields, parametric coordinates, are
  !> ignored).
  subroutine read_coords(f, tag, x, status)
    type(msh_file_t), intent(in) :: f
    integer(gp), intent(in) :: tag
    real(rp), intent(out) :: x(3)
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: tok, why
    integer :: i, b, e, n, ios
    character(len=1), parameter :: axis(3) = ['x', 'y', 'z']

    x = 0.0_rp
    e = 0
    n = len(f%line)
    do i = 1, 3
      b = e + 1
      do while (b <= n)
        if (f%line(b:b) /= ' ' .and. f%line(b:b) /= achar(9)) exit
        b = b + 1
      end do
      if (b > n) then
        call bad_line(f, 'node tag '//str(tag)//': expected node coordinates "x y z", found '//str(int(i - 1, gp))// &
          ' number(s)', status)
        return
      end if
      e = b
      do while (e < n)
        if (f%line(e+1:e+1) == ' ' .or. f%line(e+1:e+1) == achar(9)) exit
        e = e + 1
      end do
      tok = f%line(b:e)
      why = real_token_problem(tok)
      if (len(why) > 0) then
        call bad_line(f, 'node tag '//str(tag)//': coordinate '//axis(i)//' "'//tok//'" '//why, status)
        return
      end if
      read(tok, *, iostat=ios) x(i)
      if (abs(x(i)) > max_coord) then
        call bad_line(f, 'node tag '//str(tag)//': coordinate '//axis(i)//' "'//tok//'" is beyond 1e30 m in '// &
          'magnitude (the element integrals would overflow)', status)
        return
      end if
    end do
  end subroutine read_coords

  !> Next line of the file into f%line. At the end of the file: at_end = .true.
  !> when the caller allows it, else an error saying `what` was expected.
  subroutine next_line(f, what, status, at_end)
    type(msh_file_t), intent(inout) :: f
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    logical, intent(out), optional :: at_end
    character(len=256) :: chunk
    integer :: ios, n
    character(len=msg_len) :: iom

    if (present(at_end)) at_end = .false.
    f%line = ''
    do
      read(f%unit, '(a)', advance='no', size=n, iostat=ios, iomsg=iom) chunk
      if (ios == 0 .or. is_iostat_eor(ios)) f%line = f%line//chunk(1:n)
      if (ios == 0) cycle
      if (is_iostat_eor(ios)) exit
      if (is_iostat_end(ios) .and. len(f%line) > 0) exit
      if (is_iostat_end(ios)) then
        if (present(at_end)) then
          at_end = .true.
        else
          call status%set('gmsh reader: '//f%path//', after line '//str(f%line_no)// &
            ': unexpected end of file, expected '//what)
        end if
      else
        call status%set('gmsh reader: '//f%path//', line '//str(f%line_no + 1)//': read error: '//trim(iom))
      end if
      return
    end do
    f%line_no = f%line_no + 1
    n = len(f%line)
    if (n > 0) then
      if (f%line(n:n) == achar(13)) f%line = f%line(1:n-1)
    end if
  end subroutine next_line

  !> The next line must be `expected` (e.g. "$EndNodes").
  subroutine expect_line(f, expected, status)
    type(msh_file_t), intent(inout) :: f
    character(len=*), intent(in) :: expected
    type(error_status_t), intent(inout) :: status
    call next_line(f, expected, status)
    if (.not. status%ok()) return
    if (trim(adjustl(f%line)) /= expected) call bad_line(f, 'expected '//expected, status)
  end subroutine expect_line

  !> Error at the current line: file, line number, what was wrong, and the
  !> start of the line found (and the run-time's message when there is one).
  subroutine bad_line(f, what, status, iom)
    type(msh_file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in), optional :: iom
    character(len=msg_len) :: m
    character(len=:), allocatable :: found
    found = trim(adjustl(f%line))
    if (len(found) > 80) found = found(1:77)//'...'
    ! assignment (not an internal write) so that a long path truncates instead of failing
    m = 'gmsh reader: '//f%path//', line '//str(f%line_no)//': '//what//' (found "'//found//'")'
    if (present(iom)) then
      if (len_trim(iom) > 0 .and. len_trim(m) + len_trim(iom) + 3 < msg_len) m = trim(m)//' ['//trim(iom)//']'
    end if
    call status%set(m)
  end subroutine bad_line

  !> Error about the file as a whole (no line to point at).
  subroutine fail(f, what, status)
    type(msh_file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    call status%set('gmsh reader: '//f%path//': '//what)
  end subroutine fail

  !> Human name of a Gmsh element type, for error messages.
  function type_name(elem_type) result(name)
    integer(ip), intent(in) :: elem_type
    character(len=32) :: name
    character(len=20), parameter :: names(19) = [character(len=20) :: &
      '2-node line', '3-node triangle', '4-node quadrangle', '4-node tetrahedron', &
      '8-node hexahedron', '6-node prism', '5-node pyramid', '3-node line', '6-node triangle', &
      '9-node quadrangle', '10-node tetrahedron', '27-node hexahedron', '18-node prism', &
      '14-node pyramid', '1-node point', '8-node quadrangle', '20-node hexahedron', &
      '15-node prism', '13-node pyramid']
    if (elem_type >= 1 .and. elem_type <= size(names)) then
      name = names(elem_type)
    else
      name = 'an element type unknown here'
    end if
  end function type_name

  ! ---------------------------------------------------------------- small helpers

  !> Decimal text of an integer.
  function str(i) result(s)
    integer(gp), intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function str

  subroutine table_init(t, n)
    type(entity_table_t), intent(inout) :: t
    integer(ip), intent(in) :: n
    t%n = 0
    allocate(t%tag(n), t%first(n + 1), t%phys(0))
    t%first(1) = 1
  end subroutine table_init

  subroutine table_add(t, tag, phys)
    type(entity_table_t), intent(inout) :: t
    integer(ip), intent(in) :: tag, phys(:)
    t%n = t%n + 1
    t%tag(t%n) = tag
    t%phys = [t%phys, phys]
    t%first(t%n + 1) = size(t%phys, kind=ip) + 1
  end subroutine table_add

  !> Index of entity `tag` in the table, 0 if absent (tables are short).
  integer(ip) function table_find(t, tag)
    type(entity_table_t), intent(in) :: t
    integer(ip), intent(in) :: tag
    integer(ip) :: i
    table_find = 0
    do i = 1, t%n
      if (t%tag(i) == tag) then
        table_find = i
        return
      end if
    end do
  end function table_find

  !> Grow a(rows, :) to hold at least `need` columns, keeping its content.
  subroutine reserve_i2(a, rows, need)
    integer(ip), allocatable, intent(inout) :: a(:,:)
    integer(ip), intent(in) :: rows, need
    integer(ip), allocatable :: tmp(:,:)
    integer(ip) :: cap
    if (.not. allocated(a)) then
      allocate(a(rows, max(need, 16_ip)))
    else if (size(a, 2) < need) then
      cap = int(min(max(int(need, gp), 2_gp * size(a, 2)), int(huge(1_ip), gp)), ip)
      allocate(tmp(rows, cap))
      tmp(:, 1:size(a, 2)) = a
      call move_alloc(tmp, a)
    end if
  end subroutine reserve_i2

  subroutine reserve_i1(a, need)
    integer(ip), allocatable, intent(inout) :: a(:)
    integer(ip), intent(in) :: need
    integer(ip), allocatable :: tmp(:)
    integer(ip) :: cap
    if (.not. allocated(a)) then
      allocate(a(max(need, 16_ip)))
    else if (size(a) < need) then
      cap = int(min(max(int(need, gp), 2_gp * size(a)), int(huge(1_ip), gp)), ip)
      allocate(tmp(cap))
      tmp(1:size(a)) = a
      call move_alloc(tmp, a)
    end if
  end subroutine reserve_i1

  subroutine reserve_g1(a, need)
    integer(gp), allocatable, intent(inout) :: a(:)
    integer(ip), intent(in) :: need
    integer(gp), allocatable :: tmp(:)
    integer(ip) :: cap
    if (.not. allocated(a)) then
      allocate(a(max(need, 16_ip)))
    else if (size(a) < need) then
      cap = int(min(max(int(need, gp), 2_gp * size(a)), int(huge(1_ip), gp)), ip)
      allocate(tmp(cap))
      tmp(1:size(a)) = a
      call move_alloc(tmp, a)
    end if
  end subroutine reserve_g1

  !> order = the permutation that sorts key ascending (stable merge sort).
  subroutine sort_order(key, order)
    integer(gp), intent(in) :: key(:)
    integer(ip), intent(out) :: order(:)
    integer(ip), allocatable :: tmp(:)
    integer(ip) :: n, width, lo, mid, hi, i, j, k
    n = size(key, kind=ip)
    order = [(i, i = 1, n)]
    allocate(tmp(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width - 1, n)
        hi = min(lo + 2 * width - 1, n)
        i = lo
        j = mid + 1
        do k = lo, hi
          if (j > hi) then
            tmp(k) = order(i); i = i + 1
          else if (i > mid) then
            tmp(k) = order(j); j = j + 1
          else if (key(order(j)) < key(order(i))) then
            tmp(k) = order(j); j = j + 1
          else
            tmp(k) = order(i); i = i + 1
          end if
        end do
        lo = hi + 1
      end do
      order = tmp
      width = 2 * width
    end do
  end subroutine sort_order
end module gmsh_reader
