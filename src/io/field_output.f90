!> Output of the fields on the distributed mesh: HDF5 files and the XDMF
!> index that ParaView opens (through xdmf_writer), one step per output time.
!> The driver opens the output and each step (begin_step, end_step); the
!> physics write their fields in between, through the helpers here or the
!> writer itself (other grids, e.g. the fractures, through their grid id).
module field_output
  use kinds, only: rp, ip, gp
  use error_status, only: error_status_t
  use dist_mesh, only: dist_mesh_t
  use xdmf_writer, only: xdmf_writer_t
  use strings, only: itoa
  implicit none
  private

  public :: field_output_t

  type :: field_output_t
    type(xdmf_writer_t) :: writer
    logical :: active = .false.
  contains
    procedure :: init
    procedure :: begin_step
    procedure :: end_step
    procedure :: write_displacement
    procedure :: write_mesh_ids
    procedure :: path
    procedure :: free
  end type field_output_t

contains

  !> Create the files in dir with prefix and write the mesh (owned nodes and
  !> cells of every rank). Collective.
  subroutine init(self, mesh, dir, prefix, status)
    class(field_output_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: dir, prefix
    type(error_status_t), intent(inout) :: status
    integer(gp), allocatable :: conn(:,:)
    integer(ip) :: c, a, nc
    nc = mesh%cell_map%n_owned
    allocate(conn(8, nc))
    do c = 1, nc
      do a = 1, 8
        conn(a, c) = mesh%node_map%global_id(mesh%cell_nodes(a, c))
      end do
    end do
    call self%writer%init(mesh%comm, dir, prefix, mesh%n_nodes_global, mesh%node_map%first, &
                          mesh%coords(:, 1:mesh%node_map%n_owned), mesh%n_cells_global, &
                          mesh%cell_map%first, conn, status)
    if (status%ok()) call self%writer%add_info('stress', 'cell field, Pa, tension positive, components '// &
                                               'XX YY ZZ XY YZ XZ (ParaView order of a Tensor6)', status)
    if (status%ok()) call self%writer%add_info('region', 'cell field, region id: '//region_legend(mesh), status)
    self%active = status%ok()
  end subroutine init

  !> Open the output step of time t [s, or load factor]. Collective.
  subroutine begin_step(self, t, status)
    class(field_output_t), intent(inout) :: self
    real(rp), intent(in) :: t
    type(error_status_t), intent(inout) :: status
    call self%writer%begin_step(t, status)
  end subroutine begin_step

  !> Close the output step (the XDMF index gets it). Collective.
  subroutine end_step(self, status)
    class(field_output_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    call self%writer%end_step(status)
  end subroutine end_step

  !> Node field 'displacement' [m] from a local vector of 3 interleaved
  !> components per node (owned nodes first). Collective.
  subroutine write_displacement(self, mesh, u_loc, status)
    class(field_output_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: u_loc(:)
    type(error_status_t), intent(inout) :: status
    integer(ip) :: nn
    nn = mesh%node_map%n_owned
    if (status%ok()) call self%writer%node_field('displacement', reshape(u_loc(1:3*nn), [3, nn]), status)
  end subroutine write_displacement

  !> Cell fields 'region' (region id) and 'rank' (owning rank). Collective.
  subroutine write_mesh_ids(self, mesh, status)
    class(field_output_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: ids(:)
    integer(ip) :: nc
    nc = mesh%cell_map%n_owned
    allocate(ids(nc))
    ids(:) = mesh%cell_region(1:nc)
    if (status%ok()) call self%writer%cell_field('region', ids, status)
    ids(:) = mesh%cell_owner(1:nc)
    if (status%ok()) call self%writer%cell_field('rank', ids, status)
  end subroutine write_mesh_ids

  !> '1 = name1, 2 = name2, ...': the region ids of the 'region' field
  !> (characters XML does not take in a name shown as '_').
  function region_legend(mesh) result(s)
    type(dist_mesh_t), intent(in) :: mesh
    character(len=:), allocatable :: s
    character(len=:), allocatable :: nm
    integer :: r, i
    s = ''
    do r = 1, size(mesh%region_names)
      nm = trim(mesh%region_names(r))
      do i = 1, len(nm)
        if (scan(nm(i:i), '"<>&') > 0) nm(i:i) = '_'
      end do
      if (r > 1) s = s//', '
      s = s//itoa(r)//' = '//nm
    end do
  end function region_legend

  !> Path of the XDMF file.
  function path(self) result(p)
    class(field_output_t), intent(in) :: self
    character(len=:), allocatable :: p
    p = self%writer%xdmf_path()
  end function path

  subroutine free(self)
    class(field_output_t), intent(inout) :: self
    if (self%active) call self%writer%free()
    self%active = .false.
  end subroutine free
end module field_output
