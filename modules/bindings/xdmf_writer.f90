!> Parallel HDF5 + XDMF output of unstructured meshes and their fields, for ParaView.
!>
!> The writer takes plain arrays (no mesh type): every rank owns a contiguous
!> block of global node ids and of global cell ids, in rank order (as
!> index_map_t), and writes its block with a collective hyperslab write through
!> MPI-IO. Files, all in one directory <dir>:
!>
!>   <prefix>_mesh.h5  written once per grid (init, add_grid). The first grid
!>       lives at the root: /coords (3 x n_nodes in Fortran order, that is
!>       n_nodes x 3 in the row-major view of XDMF and h5py), /connectivity
!>       (nodes_per_cell x n_cells in Fortran order, 0-BASED global node ids,
!>       32-bit, or 64-bit once the node count needs it) and the root attributes
!>       n_nodes, n_cells, nodes_per_cell (int64). Each further grid has the
!>       same datasets and attributes in the group /<grid name>.
!>   <prefix>_NNNN.h5  one file per output time (NNNN = step number from 0, four
!>       digits, more past 9999), so that a crashed run leaves the earlier steps
!>       readable. Root attributes time (float64) and step (int32); the first
!>       grid's fields at /<field>, a further grid's fields at /<grid>/<field>.
!>       A field of ncomp components is an ncomp x n dataset in Fortran order
!>       (n x ncomp row-major); a 1-D dataset of n values when ncomp = 1.
!>   <prefix>.xdmf     rewritten by rank 0 at every end_step (to a temporary file
!>       renamed over the old one, so that a crash mid-write keeps the previous
!>       version): a Temporal collection with one entry per step, each with
!>       <Time Value=.../>; the entry is the grid itself for a one-grid writer
!>       and a Spatial collection of the grids (a multiblock in ParaView) for a
!>       writer with several. HDF5 files are referenced relative to the XDMF file.
!>   <prefix>_<grid>.xdmf  the same for a grid added with own_file: that grid
!>       is left out of <prefix>.xdmf and gets a Temporal collection of its
!>       own (its data stay in the files above), so that readers that want
!>       one mesh per file (meshio) open it.
!> add_info attaches <Information Name=... Value=.../> elements (legends,
!> units, sign conventions) to the Domain of the XDMF file showing a grid;
!> readers skip them, ParaView shows them in the XML.
!>
!> Cell type from the first dimension of conn: 8 -> Hexahedron, 4 -> Quadrilateral;
!> both in the Gmsh / VTK node order, which is also XDMF's.
!> Attribute type from the number of components: 1 Scalar, 3 Vector, 6 Tensor6
!> (symmetric tensor; the caller passes the components in the order ParaView
!> labels them, XX YY ZZ XY YZ XZ: ParaView's XDMF reader hands the six values
!> to VTK unchanged, and VTK names a 6-component symmetric tensor so), 9 Tensor
!> (full, row by row: xx, xy, xz, yx, yy, yz, zx, zy, zz), any other Matrix.
!>
!> Every public procedure is collective and returns the same status on all
!> ranks (errors name the file). HDF5 is opened (h5open_f) by init and never
!> closed here, since other parts of the program may use it too; parallel HDF5
!> closes itself at MPI_Finalize.
module xdmf_writer
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_null_ptr
  use mpi_f08, only: MPI_INFO_NULL
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, &
                  H5F_ACC_TRUNC_F, H5F_ACC_RDWR_F, h5pcreate_f, h5pclose_f, &
                  H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, h5pset_fapl_mpio_f, &
                  h5pset_dxpl_mpio_f, H5FD_MPIO_COLLECTIVE_F, h5screate_simple_f, &
                  h5screate_f, H5S_SCALAR_F, h5sclose_f, h5sselect_hyperslab_f, &
                  h5sselect_none_f, H5S_SELECT_SET_F, h5dcreate_f, h5dclose_f, &
                  h5dwrite_f, h5eset_auto_f, h5acreate_f, h5awrite_f, h5aclose_f, h5gcreate_f, &
                  h5gclose_f, h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND, &
                  H5T_IEEE_F64LE, H5T_STD_I32LE, H5T_STD_I64LE
  use kinds, only: rp, ip, gp, name_len, path_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use os_services, only: rename_path, path_kind, path_file, make_directory
  use state_record, only: state_record_t
  use status_sync, only: agree_all => agree
  implicit none
  private

  public :: xdmf_writer_t

  integer, parameter :: center_node = 1, center_cell = 2

  !> One mesh of the output: volume hexahedra or interface quadrilaterals.
  type :: xdmf_grid_t
    character(len=name_len) :: name = ''
    character(len=name_len) :: group = ''   !< HDF5 group in mesh and step files, '' = root
    integer :: nodes_per_cell = 0
    integer :: conn_bytes = 4               !< 4 or 8: integer size of /connectivity
    integer(gp) :: n_nodes_global = 0, n_cells_global = 0
    integer(gp) :: node_first = 1, cell_first = 1
    integer(ip) :: n_nodes = 0, n_cells = 0 !< owned on this rank
    integer :: first_step = 0               !< first step that shows this grid
    logical :: own_file = .false.           !< in <prefix>_<name>.xdmf, not <prefix>.xdmf
  end type xdmf_grid_t

  !> One Information element of the XDMF file of a grid.
  type :: xdmf_info_t
    integer :: grid = 1
    character(len=name_len) :: name = ''
    character(len=:), allocatable :: value
  end type xdmf_info_t

  !> What the XDMF needs to know of one field written in one step.
  type :: xdmf_field_t
    character(len=name_len) :: name = ''
    integer :: step = 0, grid = 0, center = 0, ncomp = 0
    logical :: is_int = .false.
  end type xdmf_field_t

  !> Writer of one output series (one XDMF file), with one or several grids.
  type :: xdmf_writer_t
    private
    type(parallel_comm_t) :: comm
    character(len=path_len) :: dir = ''
    character(len=path_len) :: prefix = ''
    logical :: ready = .false.
    integer :: n_grids = 0
    type(xdmf_grid_t), allocatable :: grids(:)
    integer :: n_steps = 0                      !< completed steps
    real(rp), allocatable :: times(:)           !< (n_steps) time of each step
    integer :: n_fields = 0
    type(xdmf_field_t), allocatable :: fields(:) !< in step order
    logical :: in_step = .false.
    integer(hid_t) :: step_file = -1
    integer :: step_field_first = 1             !< first record of the open step
    type(xdmf_info_t), allocatable :: infos(:)  !< Information elements, in the order added
  contains
    procedure :: init
    procedure :: add_grid
    procedure :: add_info
    procedure :: begin_step
    procedure, private :: node_field_r2, node_field_r1
    generic :: node_field => node_field_r2, node_field_r1
    procedure, private :: cell_field_r2, cell_field_r1, cell_field_i1
    generic :: cell_field => cell_field_r2, cell_field_r1, cell_field_i1
    procedure :: end_step
    procedure :: xdmf_path
    procedure :: n_outputs
    procedure :: save_index
    procedure :: resume
    procedure :: free
    procedure, private :: write_field
    procedure, private :: agree
    procedure, private :: open_h5
    procedure, private :: write_xdmf
  end type xdmf_writer_t

contains

  !> Start a series and write its first grid (collective).
  !>   comm            ranks that share the output
  !>   dir, prefix     output directory (created if missing) and file name prefix
  !>                   (letters, digits, '_', '-', '.')
  !>   n_nodes_global  number of nodes of the grid
  !>   node_first      global id (1-based) of this rank's first owned node
  !>   coords(3, n)    coordinates of the owned nodes node_first..node_first+n-1 (m)
  !>   n_cells_global, cell_first   the same for the cells
  !>   conn(k, m)      owned cells, 1-BASED GLOBAL node ids, Gmsh/VTK order;
  !>                   k = 8 hexahedra, k = 4 quadrilaterals
  !>   status          failure (directory, file, HDF5, bad arguments), same on all ranks
  !>   grid_name       name of the grid in ParaView (default 'mesh')
  subroutine init(self, comm, dir, prefix, n_nodes_global, node_first, coords, &
                  n_cells_global, cell_first, conn, status, grid_name)
    class(xdmf_writer_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: dir, prefix
    integer(gp), intent(in) :: n_nodes_global, node_first, n_cells_global, cell_first
    real(rp), intent(in), target, contiguous :: coords(:,:)
    integer(gp), intent(in), contiguous :: conn(:,:)
    type(error_status_t), intent(out) :: status
    character(len=*), intent(in), optional :: grid_name
    character(len=path_len) :: mesh_file
    character(len=name_len) :: gname
    integer :: err, id
    integer(hid_t) :: file_id

    call self%free()
    self%comm = comm
    if (len_trim(dir) == 0) then
      self%dir = '.'
    else
      self%dir = dir
    end if
    if (.not. valid_name(prefix)) then
      call status%set('xdmf_writer: invalid file prefix "'//trim(prefix)// &
                      '" (letters, digits, _ - . only)')
      return
    end if
    if (index(dir, "'") > 0 .or. len_trim(dir) > path_len - 2*name_len) then
      call status%set('xdmf_writer: unusable output directory "'//trim(dir)//'"')
      return
    end if
    self%prefix = prefix

    call h5open_f(err)
    if (err /= 0) call status%set('xdmf_writer: cannot initialise HDF5')
    ! HDF5's own error stack is not printed: every failure becomes one
    ! message of ours naming the file
    if (err == 0) call h5eset_auto_f(0, err)
    call self%agree(status, 'HDF5 initialisation')
    if (.not. status%ok()) return

    ! Rank 0 creates the directory (no shell); everybody learns whether it worked.
    if (self%comm%is_root()) call make_directory(trim(self%dir), status)
    call agree_all(self%comm, status)
    if (.not. status%ok()) return

    ! Check the grid before any file is made; add_grid then fills the empty
    ! mesh file (one code path for all grids).
    gname = 'mesh'
    if (present(grid_name)) gname = grid_name
    call check_grid(self, make_grid(gname, n_nodes_global, node_first, n_cells_global, &
                                    cell_first, coords, conn), coords, conn, status)
    call self%agree(status, 'checking grid')
    if (.not. status%ok()) return
    mesh_file = mesh_path(self)
    call self%open_h5(mesh_file, .true., file_id, status)
    if (status%ok()) then
      call h5fclose_f(file_id, err)
      if (err /= 0) call status%set('xdmf_writer: cannot close '//trim(mesh_file))
    end if
    call self%agree(status, 'creating '//trim(mesh_file))
    if (.not. status%ok()) return

    self%ready = .true.
    allocate(self%grids(2), self%times(16), self%fields(16))
    call self%add_grid(gname, n_nodes_global, node_first, coords, n_cells_global, &
                       cell_first, conn, status, id)
    if (.not. status%ok()) call self%free()
  end subroutine init

  !> Add a further grid (e.g. the fracture surface, conn(4, :)) to the series:
  !> written to the mesh file under /<name>, shown from the next step on. Same
  !> arguments as init; grid_id is what the field routines take as grid=.
  !> own_file: the grid is described in <prefix>_<name>.xdmf instead of
  !> <prefix>.xdmf. Collective; not allowed between begin_step and end_step.
  subroutine add_grid(self, name, n_nodes_global, node_first, coords, n_cells_global, &
                      cell_first, conn, status, grid_id, own_file)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer(gp), intent(in) :: n_nodes_global, node_first, n_cells_global, cell_first
    real(rp), intent(in), target, contiguous :: coords(:,:)
    integer(gp), intent(in), contiguous :: conn(:,:)
    type(error_status_t), intent(out) :: status
    integer, intent(out) :: grid_id
    logical, intent(in), optional :: own_file
    type(xdmf_grid_t) :: g
    type(xdmf_grid_t), allocatable :: tmp(:)
    integer(gp), allocatable, target :: conn0(:,:)
    character(len=path_len) :: mesh_file
    integer(hid_t) :: file_id, loc_id, conn_type
    integer :: err

    grid_id = 0
    if (.not. self%ready) then
      call status%set('xdmf_writer: add_grid before init')
      return
    end if
    if (self%in_step) then
      call status%set('xdmf_writer: add_grid "'//trim(name)//'" inside a step')
      return
    end if
    g = make_grid(name, n_nodes_global, node_first, n_cells_global, cell_first, coords, conn)
    ! The first grid lives at the root of the files, the others in their group.
    if (self%n_grids > 0) g%group = name
    g%first_step = self%n_steps
    if (present(own_file)) g%own_file = own_file .and. self%n_grids > 0
    call check_grid(self, g, coords, conn, status)
    call self%agree(status, 'checking grid "'//trim(name)//'"')
    if (.not. status%ok()) return

    mesh_file = mesh_path(self)
    allocate(conn0(g%nodes_per_cell, g%n_cells))
    conn0 = conn - 1_gp
    conn_type = H5T_STD_I32LE
    if (g%conn_bytes == 8) conn_type = H5T_STD_I64LE
    call self%open_h5(mesh_file, .false., file_id, status)
    if (status%ok()) then
      loc_id = file_id
      if (len_trim(g%group) > 0) then
        call h5gcreate_f(file_id, trim(g%group), loc_id, err)
        if (err /= 0) call status%set('xdmf_writer: cannot create group /'//trim(g%group)// &
                                      ' in '//trim(mesh_file))
      end if
      ! every call below is collective: a rank that failed (e.g. a full disk
      ! seen by one rank only) must not leave the others inside the next one
      call self%agree(status, 'writing grid "'//trim(name)//'" to '//trim(mesh_file))
      if (status%ok()) then
        call write_block(loc_id, 'coords', 3, n_nodes_global, node_first, g%n_nodes, &
                         h5kind_to_type(rp, H5_REAL_KIND), H5T_IEEE_F64LE, ptr_r2(coords), &
                         mesh_file, status)
        call self%agree(status, 'writing grid "'//trim(name)//'" to '//trim(mesh_file))
      end if
      if (status%ok()) then
        call write_block(loc_id, 'connectivity', g%nodes_per_cell, n_cells_global, cell_first, &
                         g%n_cells, h5kind_to_type(gp, H5_INTEGER_KIND), conn_type, &
                         ptr_g2(conn0), mesh_file, status)
        call self%agree(status, 'writing grid "'//trim(name)//'" to '//trim(mesh_file))
      end if
      if (status%ok()) call write_attr_g(loc_id, 'n_nodes', n_nodes_global, mesh_file, status)
      if (status%ok()) call write_attr_g(loc_id, 'n_cells', n_cells_global, mesh_file, status)
      if (status%ok()) call write_attr_g(loc_id, 'nodes_per_cell', int(g%nodes_per_cell, gp), &
                                         mesh_file, status)
      call self%agree(status, 'writing grid "'//trim(name)//'" to '//trim(mesh_file))
      if (loc_id /= file_id) call h5gclose_f(loc_id, err)
      call h5fclose_f(file_id, err)
      if (err /= 0 .and. status%ok()) call status%set('xdmf_writer: cannot close '//trim(mesh_file))
    end if
    call self%agree(status, 'writing grid "'//trim(name)//'" to '//trim(mesh_file))
    if (.not. status%ok()) return

    if (self%n_grids == size(self%grids)) then
      allocate(tmp(2*self%n_grids))
      tmp(1:self%n_grids) = self%grids(1:self%n_grids)
      call move_alloc(tmp, self%grids)
    end if
    self%n_grids = self%n_grids + 1
    self%grids(self%n_grids) = g
    grid_id = self%n_grids
  end subroutine add_grid

  !> An Information element (name, value: plain text without quotes, < or &)
  !> in the XDMF file that shows grid (default: the first). The same call on
  !> every rank; no communication (rank 0 writes the XDMF files).
  subroutine add_info(self, name, value, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name, value
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: grid
    type(xdmf_info_t), allocatable :: tmp(:)
    integer :: g, n
    g = 1
    if (present(grid)) g = grid
    if (.not. self%ready .or. g < 1 .or. g > self%n_grids) then
      call status%set('xdmf_writer: information "'//trim(name)//'" for no grid')
      return
    end if
    if (scan(name//value, '"<>&') > 0 .or. .not. valid_name(name)) then
      call status%set('xdmf_writer: information "'//trim(name)//'" has characters XML does not take')
      return
    end if
    if (.not. allocated(self%infos)) allocate(self%infos(0))
    n = size(self%infos)
    allocate(tmp(n + 1))
    tmp(1:n) = self%infos
    tmp(n + 1)%grid = g
    tmp(n + 1)%name = name
    tmp(n + 1)%value = value
    call move_alloc(tmp, self%infos)
  end subroutine add_info

  !> Open the file of a new output step at time (s), collectively; the fields
  !> follow, then end_step.
  subroutine begin_step(self, time, status)
    class(xdmf_writer_t), intent(inout) :: self
    real(rp), intent(in) :: time
    type(error_status_t), intent(out) :: status
    character(len=path_len) :: file
    integer(hid_t) :: grp
    integer :: err, g

    if (.not. self%ready) then
      call status%set('xdmf_writer: begin_step before init')
      return
    end if
    if (self%in_step) then
      call status%set('xdmf_writer: begin_step while a step is open')
      return
    end if
    file = step_path(self, self%n_steps)
    call self%open_h5(file, .true., self%step_file, status)
    if (status%ok()) call write_attr_r(self%step_file, 'time', time, file, status)
    if (status%ok()) call write_attr_i(self%step_file, 'step', int(self%n_steps, ip), file, status)
    do g = 2, self%n_grids
      if (.not. status%ok()) exit
      call h5gcreate_f(self%step_file, trim(self%grids(g)%group), grp, err)
      if (err /= 0) then
        call status%set('xdmf_writer: cannot create group /'//trim(self%grids(g)%group)// &
                        ' in '//trim(file))
      else
        call h5gclose_f(grp, err)
      end if
    end do
    call self%agree(status, 'opening '//trim(file))
    if (.not. status%ok()) then
      if (self%step_file >= 0) call h5fclose_f(self%step_file, err)
      self%step_file = -1
      return
    end if
    self%in_step = .true.
    self%step_field_first = self%n_fields + 1
    if (self%n_steps == size(self%times)) call grow_times(self%times)
    self%times(self%n_steps + 1) = time
  end subroutine begin_step

  !> Node field of the open step: values(ncomp, n_owned_nodes) of the grid
  !> (default: the first), in the node order of init/add_grid. Collective:
  !> every rank passes the same name and ncomp, also a rank that owns no node
  !> (values(ncomp, 0)). A field name is used once per grid and step.
  subroutine node_field_r2(self, name, values, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in), target, contiguous :: values(:,:)
    type(error_status_t), intent(out) :: status
    integer, intent(in), optional :: grid
    call self%write_field(name, center_node, size(values, 1), size(values, 2), &
                          ptr_r2(values), .false., status, grid)
  end subroutine node_field_r2

  !> Scalar node field: values(n_owned_nodes).
  subroutine node_field_r1(self, name, values, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in), target, contiguous :: values(:)
    type(error_status_t), intent(out) :: status
    integer, intent(in), optional :: grid
    call self%write_field(name, center_node, 1, size(values), ptr_r1(values), .false., &
                          status, grid)
  end subroutine node_field_r1

  !> Cell field of the open step: values(ncomp, n_owned_cells). Collective.
  subroutine cell_field_r2(self, name, values, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in), target, contiguous :: values(:,:)
    type(error_status_t), intent(out) :: status
    integer, intent(in), optional :: grid
    call self%write_field(name, center_cell, size(values, 1), size(values, 2), &
                          ptr_r2(values), .false., status, grid)
  end subroutine cell_field_r2

  !> Scalar cell field: values(n_owned_cells).
  subroutine cell_field_r1(self, name, values, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in), target, contiguous :: values(:)
    type(error_status_t), intent(out) :: status
    integer, intent(in), optional :: grid
    call self%write_field(name, center_cell, 1, size(values), ptr_r1(values), .false., &
                          status, grid)
  end subroutine cell_field_r1

  !> Integer cell field (region id, rank id): values(n_owned_cells), int32.
  subroutine cell_field_i1(self, name, values, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer(ip), intent(in), target, contiguous :: values(:)
    type(error_status_t), intent(out) :: status
    integer, intent(in), optional :: grid
    call self%write_field(name, center_cell, 1, size(values), ptr_i1(values), .true., &
                          status, grid)
  end subroutine cell_field_i1

  !> Close the step file and rewrite the XDMF file (rank 0) with all steps so far.
  subroutine end_step(self, status)
    class(xdmf_writer_t), intent(inout) :: self
    type(error_status_t), intent(out) :: status
    character(len=path_len) :: file
    integer :: err

    if (.not. self%in_step) then
      call status%set('xdmf_writer: end_step without begin_step')
      return
    end if
    file = step_path(self, self%n_steps)
    call h5fclose_f(self%step_file, err)
    self%step_file = -1
    self%in_step = .false.
    if (err /= 0) call status%set('xdmf_writer: cannot close '//trim(file))
    call self%agree(status, 'closing '//trim(file))
    if (.not. status%ok()) then
      ! The step is dropped: its records must not reach the XDMF file.
      self%n_fields = self%step_field_first - 1
      return
    end if
    self%n_steps = self%n_steps + 1

    ! Only rank 0 writes the XDMF file; its verdict is everybody's.
    if (self%comm%is_root()) call self%write_xdmf(status)
    call root_verdict(self, status)
  end subroutine end_step

  !> Path of the XDMF file of the series (to open in ParaView); with grid,
  !> the file that shows that grid.
  function xdmf_path(self, grid) result(path)
    class(xdmf_writer_t), intent(in) :: self
    integer, intent(in), optional :: grid
    character(len=:), allocatable :: path
    path = trim(self%dir)//'/'//trim(self%prefix)//'.xdmf'
    if (present(grid)) then
      if (grid >= 1 .and. grid <= self%n_grids) then
        if (self%grids(grid)%own_file) path = trim(self%dir)//'/'//trim(self%prefix)//'_'// &
                                              trim(self%grids(grid)%name)//'.xdmf'
      end if
    end if
  end function xdmf_path

  !> Number of output steps written (the next step file's number).
  integer function n_outputs(self)
    class(xdmf_writer_t), intent(in) :: self
    n_outputs = self%n_steps
  end function n_outputs

  !> The series' index as a record (what resume needs to continue it):
  !> times of the steps, grid names and first steps, and per field record
  !> its name, step, grid, centre, components and integer flag.
  subroutine save_index(self, st)
    class(xdmf_writer_t), intent(in) :: self
    type(state_record_t), intent(inout) :: st
    integer :: f
    call st%clear()
    call st%put('times', self%times(1:self%n_steps))
    call st%put('grid_name', self%grids(1:self%n_grids)%name)
    call st%put('grid_first_step', self%grids(1:self%n_grids)%first_step)
    call st%put('field_name', self%fields(1:self%n_fields)%name)
    call st%put('field_step', self%fields(1:self%n_fields)%step)
    call st%put('field_grid', self%fields(1:self%n_fields)%grid)
    call st%put('field_center', self%fields(1:self%n_fields)%center)
    call st%put('field_ncomp', self%fields(1:self%n_fields)%ncomp)
    call st%put('field_int', [(merge(1, 0, self%fields(f)%is_int), f = 1, self%n_fields)])
  end subroutine save_index

  !> Continue the series of an earlier run from its index st (save_index):
  !> after init and add_grid of the same grids, the earlier steps are taken
  !> over (their step files, in dir, are not touched), the next step gets the
  !> next number, and the XDMF file is rewritten at once with the earlier
  !> steps. missing: how many of the earlier step files are not in dir (the
  !> XDMF still lists them). Collective; status agrees.
  subroutine resume(self, st, missing, status)
    class(xdmf_writer_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    integer, intent(out) :: missing
    type(error_status_t), intent(inout) :: status
    integer :: k, f, n, s
    missing = 0
    call check_index(self, st, status)
    if (.not. status%ok()) return
    associate (e => st%e)
      n = size(e(st%find('times'))%r)
      if (size(self%times) < n) then
        deallocate(self%times)
        allocate(self%times(max(16, n)))
      end if
      self%n_steps = n
      self%times(1:n) = e(st%find('times'))%r
      do k = 1, self%n_grids
        self%grids(k)%first_step = e(st%find('grid_first_step'))%i(k)
      end do
      n = size(e(st%find('field_name'))%s)
      deallocate(self%fields)
      allocate(self%fields(max(16, n)))
      do f = 1, n
        self%fields(f) = xdmf_field_t(name=e(st%find('field_name'))%s(f), step=e(st%find('field_step'))%i(f), &
          grid=e(st%find('field_grid'))%i(f), center=e(st%find('field_center'))%i(f), &
          ncomp=e(st%find('field_ncomp'))%i(f), is_int=e(st%find('field_int'))%i(f) == 1)
      end do
      self%n_fields = n
    end associate
    if (self%comm%is_root()) then
      do s = 0, self%n_steps - 1
        if (path_kind(step_path(self, s)) /= path_file) missing = missing + 1
      end do
      call self%write_xdmf(status)
    end if
    call self%comm%bcast(missing)
    call root_verdict(self, status)
  end subroutine resume

  !> Rank 0's status becomes every rank's (after a write only rank 0 made).
  subroutine root_verdict(self, status)
    type(xdmf_writer_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    integer(ip) :: code
    code = int(status%code, ip)
    call self%comm%bcast(code)
    if (code /= 0) then
      call self%comm%bcast(status%msg)
      status%code = code
    end if
  end subroutine root_verdict

  !> The index has every entry resume reads, with consistent sizes, and the
  !> grids of this series (same names, same order).
  subroutine check_index(self, st, status)
    type(xdmf_writer_t), intent(in) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    character(len=16), parameter :: ints(6) = [character(len=16) :: 'grid_first_step', 'field_step', 'field_grid', &
      'field_center', 'field_ncomp', 'field_int']
    integer :: k, nf
    if (self%in_step .or. .not. self%ready) then
      call status%set('xdmf_writer: resume needs an initialised series outside a step')
      return
    end if
    if (st%find('times') == 0 .or. st%find('grid_name') == 0 .or. st%find('field_name') == 0) then
      call status%set('output index: times, grid_name or field_name missing')
      return
    end if
    if (.not. allocated(st%e(st%find('times'))%r) .or. .not. allocated(st%e(st%find('grid_name'))%s) .or. &
        .not. allocated(st%e(st%find('field_name'))%s)) then
      call status%set('output index: times, grid_name or field_name of the wrong type')
      return
    end if
    nf = size(st%e(st%find('field_name'))%s)
    do k = 1, size(ints)
      if (st%find(ints(k)) == 0) then
        call status%set('output index: no entry '//trim(ints(k)))
      else if (.not. allocated(st%e(st%find(ints(k)))%i)) then
        call status%set('output index: entry '//trim(ints(k))//' is not an integer array')
      else if (size(st%e(st%find(ints(k)))%i) /= merge(self%n_grids, nf, k == 1)) then
        call status%set('output index: entry '//trim(ints(k))//' has the wrong size')
      end if
      if (.not. status%ok()) return
    end do
    associate (names => st%e(st%find('grid_name'))%s)
      if (size(names) /= self%n_grids) then
        call status%set('output index: the earlier run had another number of grids')
      else if (any(names /= self%grids(1:self%n_grids)%name)) then
        call status%set('output index: the earlier run had other grids')
      end if
    end associate
  end subroutine check_index

  !> Close an open step file (collective) and forget everything; the files stay.
  subroutine free(self)
    class(xdmf_writer_t), intent(inout) :: self
    integer :: err
    if (self%in_step .and. self%step_file >= 0) call h5fclose_f(self%step_file, err)
    self%step_file = -1
    self%in_step = .false.
    self%ready = .false.
    self%n_grids = 0
    self%n_steps = 0
    self%n_fields = 0
    self%step_field_first = 1
    if (allocated(self%grids)) deallocate(self%grids)
    if (allocated(self%times)) deallocate(self%times)
    if (allocated(self%fields)) deallocate(self%fields)
    if (allocated(self%infos)) deallocate(self%infos)
  end subroutine free

  ! ---- private ---------------------------------------------------------------

  !> Common part of the field routines: checks, collective write, record.
  subroutine write_field(self, name, center, ncomp, n_local, buf, is_int, status, grid)
    class(xdmf_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: center, ncomp, n_local
    type(c_ptr), intent(in) :: buf
    logical, intent(in) :: is_int
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: grid
    character(len=path_len) :: file
    character(len=name_len) :: name0
    character(len=2*name_len+1) :: dset
    type(xdmf_field_t), allocatable :: tmp(:)
    integer :: g, f, n_owned
    integer(ip) :: nmax, nmin
    integer(gp) :: n_global, first
    integer(hid_t) :: mem_type, file_type

    if (.not. self%in_step) then
      call status%set('xdmf_writer: field "'//trim(name)//'" written outside a step')
      return
    end if
    g = 1
    if (present(grid)) g = grid
    file = step_path(self, self%n_steps)
    ! Checks of the arguments (same on all ranks or caught by agree).
    if (g < 1 .or. g > self%n_grids) then
      call status%set('xdmf_writer: field "'//trim(name)//'": no such grid')
    else if (.not. valid_name(name)) then
      call status%set('xdmf_writer: invalid field name "'//trim(name)// &
                      '" (letters, digits, _ - . only)')
    end if
    if (status%ok()) then
      if (center == center_node) then
        n_owned = self%grids(g)%n_nodes
        n_global = self%grids(g)%n_nodes_global
        first = self%grids(g)%node_first
      else
        n_owned = self%grids(g)%n_cells
        n_global = self%grids(g)%n_cells_global
        first = self%grids(g)%cell_first
      end if
      if (n_local /= n_owned) then
        call status%set('xdmf_writer: field "'//trim(name)//'" has the wrong number of '// &
                        'entries for grid "'//trim(self%grids(g)%name)//'"')
      else if (ncomp < 1) then
        call status%set('xdmf_writer: field "'//trim(name)//'" has no components')
      end if
      do f = self%step_field_first, self%n_fields
        if (self%fields(f)%grid == g .and. self%fields(f)%name == name) &
          call status%set('xdmf_writer: field "'//trim(name)//'" written twice in '//trim(file))
      end do
    end if
    ! All ranks must pass the same name and number of components.
    name0 = name
    call self%comm%bcast(name0)
    nmax = self%comm%max(int(ncomp, ip))
    nmin = self%comm%min(int(ncomp, ip))
    if (status%ok() .and. (name0 /= name .or. nmax /= nmin)) &
      call status%set('xdmf_writer: field "'//trim(name)//'" differs between ranks')
    call self%agree(status, 'checking field "'//trim(name)//'"')
    if (.not. status%ok()) return

    if (len_trim(self%grids(g)%group) > 0) then
      dset = trim(self%grids(g)%group)//'/'//trim(name)
    else
      dset = name
    end if
    if (is_int) then
      mem_type = h5kind_to_type(ip, H5_INTEGER_KIND)
      file_type = H5T_STD_I32LE
    else
      mem_type = h5kind_to_type(rp, H5_REAL_KIND)
      file_type = H5T_IEEE_F64LE
    end if
    call write_block(self%step_file, trim(dset), ncomp, n_global, first, int(n_local, ip), &
                     mem_type, file_type, buf, file, status)
    call self%agree(status, 'writing field "'//trim(name)//'" to '//trim(file))
    if (.not. status%ok()) return

    if (self%n_fields == size(self%fields)) then
      allocate(tmp(2*self%n_fields))
      tmp(1:self%n_fields) = self%fields(1:self%n_fields)
      call move_alloc(tmp, self%fields)
    end if
    self%n_fields = self%n_fields + 1
    self%fields(self%n_fields) = xdmf_field_t(name=name, step=self%n_steps, grid=g, &
                                              center=center, ncomp=ncomp, is_int=is_int)
  end subroutine write_field

  !> Make the status the same on all ranks: a rank that saw nothing wrong
  !> learns that another one failed in `what`.
  subroutine agree(self, status, what)
    class(xdmf_writer_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in) :: what
    type(error_status_t) :: mine
    ! every rank gets the first failing rank's own message (e.g. its write
    ! error), with what was being done
    mine = status
    call agree_all(self%comm, status)
    if (.not. status%ok() .and. mine%ok()) status%msg = trim(status%msg)//' ('//what//', on another rank)'
  end subroutine agree

  !> Create (truncating) or open read-write an HDF5 file for MPI-IO on self%comm.
  subroutine open_h5(self, path, create, file_id, status)
    class(xdmf_writer_t), intent(in) :: self
    character(len=*), intent(in) :: path
    logical, intent(in) :: create
    integer(hid_t), intent(out) :: file_id
    type(error_status_t), intent(inout) :: status
    integer(hid_t) :: fapl
    integer :: err, err2
    file_id = -1
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
    if (err /= 0) then
      call status%set('xdmf_writer: HDF5 property list failure for '//trim(path))
      return
    end if
    ! MPI_INFO_NULL is only a constant here: all MPI calls stay in parallel_comm.
    call h5pset_fapl_mpio_f(fapl, self%comm%f_handle(), MPI_INFO_NULL%MPI_VAL, err)
    if (err == 0) then
      if (create) then
        call h5fcreate_f(trim(path), H5F_ACC_TRUNC_F, file_id, err, access_prp=fapl)
      else
        call h5fopen_f(trim(path), H5F_ACC_RDWR_F, file_id, err, access_prp=fapl)
      end if
    end if
    call h5pclose_f(fapl, err2)
    if (err /= 0) then
      file_id = -1
      if (create) then
        call status%set('xdmf_writer: cannot create '//trim(path))
      else
        call status%set('xdmf_writer: cannot open '//trim(path))
      end if
    end if
  end subroutine open_h5

  !> Rank 0: write the XDMF files of all steps so far (the series' file and
  !> one per grid with a file of its own), each atomically.
  subroutine write_xdmf(self, status)
    class(xdmf_writer_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    integer :: g
    call write_xdmf_file(self, 0, status)
    do g = 2, self%n_grids
      if (status%ok() .and. self%grids(g)%own_file) call write_xdmf_file(self, g, status)
    end do
  end subroutine write_xdmf

  !> Rank 0: one XDMF file, atomically: only = 0 the series' file (the grids
  !> without a file of their own), else the file of grid only.
  subroutine write_xdmf_file(self, only, status)
    type(xdmf_writer_t), intent(in) :: self
    integer, intent(in) :: only
    type(error_status_t), intent(inout) :: status
    character(len=path_len) :: path, tmp
    character(len=msg_len) :: iom
    logical :: shown(self%n_grids)
    integer :: u, ios, s, g, f0, f1, k
    logical :: multi

    if (only == 0) then
      path = self%xdmf_path()
      shown = .not. self%grids(1:self%n_grids)%own_file
    else
      path = self%xdmf_path(only)
      shown = .false.
      shown(only) = .true.
    end if
    tmp = trim(path)//'.tmp'
    open(newunit=u, file=trim(tmp), status='replace', action='write', form='formatted', &
         iostat=ios, iomsg=iom)
    if (ios /= 0) then
      call status%set('xdmf_writer: cannot write '//trim(tmp)//': '//trim(iom))
      return
    end if
    multi = count(shown) > 1
    call put(u, ios, '<?xml version="1.0" ?>')
    call put(u, ios, '<Xdmf Version="3.0">')
    call put(u, ios, ' <Domain>')
    if (allocated(self%infos)) then
      do k = 1, size(self%infos)
        if (shown(self%infos(k)%grid)) call put(u, ios, '  <Information Name="'//trim(self%infos(k)%name)// &
                                                   '" Value="'//self%infos(k)%value//'"/>')
      end do
    end if
    call put(u, ios, '  <Grid Name="'//trim(self%prefix)// &
                     '" GridType="Collection" CollectionType="Temporal">')
    f0 = 1
    do s = 0, self%n_steps - 1
      ! Records are in step order: those of step s are f0..f1.
      f1 = f0 - 1
      do while (f1 < self%n_fields)
        if (self%fields(f1 + 1)%step /= s) exit
        f1 = f1 + 1
      end do
      if (multi) then
        call put(u, ios, '   <Grid Name="step_'//int_str(int(s, gp))// &
                         '" GridType="Collection" CollectionType="Spatial">')
        call put(u, ios, '    <Time Value="'//real_str(self%times(s + 1))//'"/>')
      end if
      do g = 1, self%n_grids
        if (self%grids(g)%first_step > s .or. .not. shown(g)) cycle
        if (multi) then
          call write_xdmf_grid(self, u, ios, s, g, f0, f1, .false., ' ')
        else
          call write_xdmf_grid(self, u, ios, s, g, f0, f1, .true., '')
        end if
      end do
      if (multi) call put(u, ios, '   </Grid>')
      f0 = f1 + 1
    end do
    call put(u, ios, '  </Grid>')
    call put(u, ios, ' </Domain>')
    call put(u, ios, '</Xdmf>')
    if (ios /= 0) then
      close(u, iostat=ios)
      call status%set('xdmf_writer: cannot write '//trim(tmp))
      return
    end if
    close(u, iostat=ios)
    if (ios /= 0) then
      call status%set('xdmf_writer: cannot close '//trim(tmp))
      return
    end if
    call rename_path(tmp, path, status)
    if (.not. status%ok()) status%msg = 'xdmf_writer: '//trim(status%msg)
  end subroutine write_xdmf_file

  !> One Uniform grid of step s with the fields f0..f1 that belong to it.
  subroutine write_xdmf_grid(self, u, ios, s, g, f0, f1, with_time, pad)
    type(xdmf_writer_t), intent(in) :: self
    integer, intent(in) :: u, s, g, f0, f1
    integer, intent(inout) :: ios
    logical, intent(in) :: with_time
    character(len=*), intent(in) :: pad      !< extra indentation inside a Spatial collection
    type(xdmf_grid_t) :: gr
    character(len=:), allocatable :: mesh_file, step_file, where, topo, atype, center
    character(len=:), allocatable :: dims
    integer(gp) :: n
    integer :: f

    gr = self%grids(g)
    mesh_file = trim(self%prefix)//'_mesh.h5'
    step_file = base_name(step_path(self, s))
    where = '/'
    if (len_trim(gr%group) > 0) where = '/'//trim(gr%group)//'/'
    if (gr%nodes_per_cell == 8) then
      topo = 'Hexahedron'
    else
      topo = 'Quadrilateral'
    end if
    call put(u, ios, pad//'   <Grid Name="'//trim(gr%name)//'" GridType="Uniform">')
    if (with_time) call put(u, ios, pad//'    <Time Value="'//real_str(self%times(s + 1))//'"/>')
    call put(u, ios, pad//'    <Topology TopologyType="'//topo//'" NumberOfElements="'// &
                     int_str(gr%n_cells_global)//'">')
    call put(u, ios, pad//'     '//data_item(int_str(gr%n_cells_global)//' '// &
                     int_str(int(gr%nodes_per_cell, gp)), 'Int', gr%conn_bytes, &
                     mesh_file//':'//where//'connectivity'))
    call put(u, ios, pad//'    </Topology>')
    call put(u, ios, pad//'    <Geometry GeometryType="XYZ">')
    call put(u, ios, pad//'     '//data_item(int_str(gr%n_nodes_global)//' 3', 'Float', 8, &
                     mesh_file//':'//where//'coords'))
    call put(u, ios, pad//'    </Geometry>')
    do f = f0, f1
      if (self%fields(f)%grid /= g) cycle
      if (self%fields(f)%center == center_node) then
        center = 'Node'
        n = gr%n_nodes_global
      else
        center = 'Cell'
        n = gr%n_cells_global
      end if
      select case (self%fields(f)%ncomp)
      case (1)
        atype = 'Scalar'
      case (3)
        atype = 'Vector'
      case (6)
        atype = 'Tensor6'
      case (9)
        atype = 'Tensor'
      case default
        atype = 'Matrix'
      end select
      if (self%fields(f)%ncomp == 1) then
        dims = int_str(n)
      else
        dims = int_str(n)//' '//int_str(int(self%fields(f)%ncomp, gp))
      end if
      call put(u, ios, pad//'    <Attribute Name="'//trim(self%fields(f)%name)//'" AttributeType="'// &
                       atype//'" Center="'//center//'">')
      if (self%fields(f)%is_int) then
        call put(u, ios, pad//'     '//data_item(dims, 'Int', 4, step_file//':'//where// &
                         trim(self%fields(f)%name)))
      else
        call put(u, ios, pad//'     '//data_item(dims, 'Float', 8, step_file//':'//where// &
                         trim(self%fields(f)%name)))
      end if
      call put(u, ios, pad//'    </Attribute>')
    end do
    call put(u, ios, pad//'   </Grid>')
  end subroutine write_xdmf_grid

  !> Grid record from the arguments of init / add_grid.
  function make_grid(name, n_nodes_global, node_first, n_cells_global, cell_first, coords, &
                     conn) result(g)
    character(len=*), intent(in) :: name
    integer(gp), intent(in) :: n_nodes_global, node_first, n_cells_global, cell_first
    real(rp), intent(in) :: coords(:,:)
    integer(gp), intent(in) :: conn(:,:)
    type(xdmf_grid_t) :: g
    g%name = name
    g%nodes_per_cell = size(conn, 1)
    g%n_nodes_global = n_nodes_global
    g%n_cells_global = n_cells_global
    g%node_first = node_first
    g%cell_first = cell_first
    g%n_nodes = int(size(coords, 2), ip)
    g%n_cells = int(size(conn, 2), ip)
    ! 0-based ids up to n_nodes_global - 1 must fit the file's integers.
    g%conn_bytes = 4
    if (n_nodes_global > int(huge(1_ip), gp)) g%conn_bytes = 8
  end function make_grid

  !> Argument checks of a grid (local; the caller makes them collective).
  subroutine check_grid(self, g, coords, conn, status)
    type(xdmf_writer_t), intent(in) :: self
    type(xdmf_grid_t), intent(in) :: g
    real(rp), intent(in) :: coords(:,:)
    integer(gp), intent(in) :: conn(:,:)
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: what
    integer :: k
    integer(gp) :: before_nodes, before_cells, total_nodes, total_cells

    what = 'xdmf_writer: grid "'//trim(g%name)//'": '
    ! Collective sums first, so that every rank makes the same calls.
    before_nodes = self%comm%exscan_g(int(g%n_nodes, gp))
    before_cells = self%comm%exscan_g(int(g%n_cells, gp))
    total_nodes = self%comm%sum(int(g%n_nodes, gp))
    total_cells = self%comm%sum(int(g%n_cells, gp))
    if (.not. valid_name(g%name)) then
      call status%set('xdmf_writer: invalid grid name "'//trim(g%name)// &
                      '" (letters, digits, _ - . only)')
      return
    end if
    do k = 1, self%n_grids
      if (self%grids(k)%name == g%name) then
        call status%set(what//'name already used')
        return
      end if
    end do
    ! A further grid becomes a group beside the first grid's datasets.
    if (self%n_grids > 0 .and. (g%name == 'coords' .or. g%name == 'connectivity')) then
      call status%set(what//'name reserved for the datasets of the first grid')
      return
    end if
    if (size(coords, 1) /= 3) then
      call status%set(what//'coords must be coords(3, n_owned_nodes)')
    else if (g%nodes_per_cell /= 8 .and. g%nodes_per_cell /= 4) then
      call status%set(what//'conn must be conn(8, n) (hexahedra) or conn(4, n) (quadrilaterals)')
    else if (g%n_nodes_global < 1 .or. g%n_cells_global < 1) then
      call status%set(what//'no nodes or no cells')
    else if (total_nodes /= g%n_nodes_global .or. before_nodes + 1 /= g%node_first) then
      call status%set(what//'owned nodes are not contiguous blocks in rank order '// &
                      'adding up to n_nodes_global')
    else if (total_cells /= g%n_cells_global .or. before_cells + 1 /= g%cell_first) then
      call status%set(what//'owned cells are not contiguous blocks in rank order '// &
                      'adding up to n_cells_global')
    else if (size(conn) > 0) then
      if (minval(conn) < 1 .or. maxval(conn) > g%n_nodes_global) &
        call status%set(what//'node id out of 1..n_nodes_global in conn')
    end if
  end subroutine check_grid

  !> Collective write of a distributed ncomp x n_global array (Fortran order):
  !> this rank's columns first..first+n_local-1 come from buf (ncomp x n_local,
  !> unused when n_local = 0). A 1-D dataset when ncomp = 1.
  subroutine write_block(loc_id, name, ncomp, n_global, first, n_local, mem_type, file_type, &
                         buf, file, status)
    integer(hid_t), intent(in) :: loc_id, mem_type, file_type
    character(len=*), intent(in) :: name, file
    integer, intent(in) :: ncomp
    integer(gp), intent(in) :: n_global, first
    integer(ip), intent(in) :: n_local
    type(c_ptr), intent(in) :: buf
    type(error_status_t), intent(inout) :: status
    integer(hsize_t) :: dims(2), start(2), count(2)
    integer(hid_t) :: fspace, mspace, dset, xfer
    integer :: nd, err, err2
    real(rp), target :: dummy(1)
    type(c_ptr) :: p

    fspace = -1
    mspace = -1
    dset = -1
    xfer = -1
    if (ncomp == 1) then
      nd = 1
      dims(1) = int(n_global, hsize_t)
      start(1) = int(first - 1, hsize_t)
      count(1) = int(n_local, hsize_t)
    else
      nd = 2
      dims = [int(ncomp, hsize_t), int(n_global, hsize_t)]
      start = [0_hsize_t, int(first - 1, hsize_t)]
      count = [int(ncomp, hsize_t), int(n_local, hsize_t)]
    end if
    steps: block
      call h5screate_simple_f(nd, dims(1:nd), fspace, err)
      if (err /= 0) exit steps
      call h5dcreate_f(loc_id, name, file_type, fspace, dset, err)
      if (err /= 0) exit steps
      ! A rank without entries still takes part in the collective write,
      ! with empty selections.
      if (n_local > 0) then
        call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, start(1:nd), count(1:nd), err)
        if (err /= 0) exit steps
        call h5screate_simple_f(nd, count(1:nd), mspace, err)
        if (err /= 0) exit steps
        p = buf
      else
        call h5sselect_none_f(fspace, err)
        if (err /= 0) exit steps
        call h5screate_simple_f(1, [1_hsize_t], mspace, err)
        if (err /= 0) exit steps
        call h5sselect_none_f(mspace, err)
        if (err /= 0) exit steps
        p = c_loc(dummy)
      end if
      call h5pcreate_f(H5P_DATASET_XFER_F, xfer, err)
      if (err /= 0) exit steps
      call h5pset_dxpl_mpio_f(xfer, H5FD_MPIO_COLLECTIVE_F, err)
      if (err /= 0) exit steps
      call h5dwrite_f(dset, mem_type, p, err, mem_space_id=mspace, file_space_id=fspace, &
                      xfer_prp=xfer)
    end block steps
    if (err /= 0) call status%set('xdmf_writer: cannot write dataset '//name//' to '//trim(file)// &
                                  ' (is the disk full, or the file system read-only?)')
    if (xfer >= 0) call h5pclose_f(xfer, err2)
    if (mspace >= 0) call h5sclose_f(mspace, err2)
    if (dset >= 0) call h5dclose_f(dset, err2)
    if (fspace >= 0) call h5sclose_f(fspace, err2)
  end subroutine write_block

  !> Scalar attribute of an object; buf points to one value of mem_type.
  subroutine write_attr(loc_id, name, mem_type, file_type, buf, file, status)
    integer(hid_t), intent(in) :: loc_id, mem_type, file_type
    character(len=*), intent(in) :: name, file
    type(c_ptr), intent(in) :: buf
    type(error_status_t), intent(inout) :: status
    integer(hid_t) :: space, attr
    integer :: err, err2
    space = -1
    attr = -1
    steps: block
      call h5screate_f(H5S_SCALAR_F, space, err)
      if (err /= 0) exit steps
      call h5acreate_f(loc_id, name, file_type, space, attr, err)
      if (err /= 0) exit steps
      call h5awrite_f(attr, mem_type, buf, err)
    end block steps
    if (err /= 0) call status%set('xdmf_writer: cannot write attribute '//name//' to '//trim(file))
    if (attr >= 0) call h5aclose_f(attr, err2)
    if (space >= 0) call h5sclose_f(space, err2)
  end subroutine write_attr

  subroutine write_attr_g(loc_id, name, value, file, status)
    integer(hid_t), intent(in) :: loc_id
    character(len=*), intent(in) :: name, file
    integer(gp), intent(in) :: value
    type(error_status_t), intent(inout) :: status
    integer(gp), target :: v
    v = value
    call write_attr(loc_id, name, h5kind_to_type(gp, H5_INTEGER_KIND), H5T_STD_I64LE, c_loc(v), &
                    file, status)
  end subroutine write_attr_g

  subroutine write_attr_i(loc_id, name, value, file, status)
    integer(hid_t), intent(in) :: loc_id
    character(len=*), intent(in) :: name, file
    integer(ip), intent(in) :: value
    type(error_status_t), intent(inout) :: status
    integer(ip), target :: v
    v = value
    call write_attr(loc_id, name, h5kind_to_type(ip, H5_INTEGER_KIND), H5T_STD_I32LE, c_loc(v), &
                    file, status)
  end subroutine write_attr_i

  subroutine write_attr_r(loc_id, name, value, file, status)
    integer(hid_t), intent(in) :: loc_id
    character(len=*), intent(in) :: name, file
    real(rp), intent(in) :: value
    type(error_status_t), intent(inout) :: status
    real(rp), target :: v
    v = value
    call write_attr(loc_id, name, h5kind_to_type(rp, H5_REAL_KIND), H5T_IEEE_F64LE, c_loc(v), &
                    file, status)
  end subroutine write_attr_r

  ! C addresses of the callers' arrays (C_LOC wants a nonzero size; the
  ! address of an empty block is never used, see write_block).
  function ptr_r2(a) result(p)
    real(rp), intent(in), target, contiguous :: a(:,:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a)
  end function ptr_r2

  function ptr_r1(a) result(p)
    real(rp), intent(in), target, contiguous :: a(:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a)
  end function ptr_r1

  function ptr_i1(a) result(p)
    integer(ip), intent(in), target, contiguous :: a(:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a)
  end function ptr_i1

  function ptr_g2(a) result(p)
    integer(gp), intent(in), target, contiguous :: a(:,:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a)
  end function ptr_g2

  !> Names go into HDF5 paths and XML attributes: keep them plain.
  logical function valid_name(name)
    character(len=*), intent(in) :: name
    character(len=*), parameter :: allowed = 'abcdefghijklmnopqrstuvwxyz' // &
      'ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.'
    valid_name = len_trim(name) > 0 .and. len_trim(name) <= name_len
    if (valid_name) valid_name = verify(trim(name), allowed) == 0 .and. name(1:1) /= '.'
  end function valid_name

  function mesh_path(self) result(path)
    type(xdmf_writer_t), intent(in) :: self
    character(len=path_len) :: path
    path = trim(self%dir)//'/'//trim(self%prefix)//'_mesh.h5'
  end function mesh_path

  function step_path(self, step) result(path)
    type(xdmf_writer_t), intent(in) :: self
    integer, intent(in) :: step
    character(len=path_len) :: path
    character(len=24) :: num
    if (step < 10000) then
      write(num, '(i4.4)') step
    else
      write(num, '(i0)') step
    end if
    path = trim(self%dir)//'/'//trim(self%prefix)//'_'//trim(num)//'.h5'
  end function step_path

  function base_name(path) result(b)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: b
    b = trim(path(index(path, '/', back=.true.) + 1:))
  end function base_name

  function data_item(dims, number_type, precision, ref) result(line)
    character(len=*), intent(in) :: dims, number_type, ref
    integer, intent(in) :: precision
    character(len=:), allocatable :: line
    line = '<DataItem Dimensions="'//dims//'" NumberType="'//number_type//'" Precision="'// &
           int_str(int(precision, gp))//'" Format="HDF">'//ref//'</DataItem>'
  end function data_item

  function int_str(i) result(s)
    integer(gp), intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function int_str

  !> Enough digits to give back the same double.
  function real_str(x) result(s)
    real(rp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(es24.16e3)') x
    s = trim(adjustl(buf))
  end function real_str

  !> Write one line unless an earlier write failed (ios keeps the first error).
  subroutine put(u, ios, line)
    integer, intent(in) :: u
    integer, intent(inout) :: ios
    character(len=*), intent(in) :: line
    if (ios /= 0) return
    write(u, '(a)', iostat=ios) line
  end subroutine put

  subroutine grow_times(t)
    real(rp), allocatable, intent(inout) :: t(:)
    real(rp), allocatable :: tmp(:)
    allocate(tmp(2*size(t)))
    tmp(1:size(t)) = t
    call move_alloc(tmp, t)
  end subroutine grow_times

end module xdmf_writer
