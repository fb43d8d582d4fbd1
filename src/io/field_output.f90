!> Output of the fields on the distributed mesh: HDF5 files and the XDMF
!> index that ParaView opens (through xdmf_writer), one step per output time.
module field_output
  use kinds, only: rp, ip, gp
  use error_status, only: error_status_t
  use dist_mesh, only: dist_mesh_t
  use xdmf_writer, only: xdmf_writer_t
  implicit none
  private

  public :: field_output_t

  type :: field_output_t
    type(xdmf_writer_t) :: writer
    logical :: active = .false.
  contains
    procedure :: init
    procedure :: write_step
    procedure :: path
    procedure :: free
  end type field_output_t

contains

  !> Write the mesh (owned nodes and cells of every rank). Collective.
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
    self%active = status%ok()
  end subroutine init

  !> One output time: displacement per node [m], stress per cell [Pa] (Tensor6,
  !> xx xy xz yy yz zz), region id and rank per cell. With keep_open the step
  !> stays open for further grids' fields (the caller ends it with
  !> self%writer%end_step). Collective.
  subroutine write_step(self, mesh, time, u_loc, stress, status, keep_open)
    class(field_output_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: time
    real(rp), intent(in) :: u_loc(:)          !< displacement, 3 per local node (interleaved)
    real(rp), intent(in) :: stress(:,:)       !< (6, owned cells)
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: keep_open
    real(rp), allocatable :: u(:,:)
    integer(ip) :: nn, nc
    integer(ip), allocatable :: ids(:)
    nn = mesh%node_map%n_owned
    nc = mesh%cell_map%n_owned
    u = reshape(u_loc(1:3*nn), [3, nn])
    call self%writer%begin_step(time, status)
    if (status%ok()) call self%writer%node_field('displacement', u, status)
    if (status%ok()) call self%writer%cell_field('stress', stress(:, 1:nc), status)
    if (status%ok()) then
      ids = mesh%cell_region(1:nc)
      call self%writer%cell_field('region', ids, status)
    end if
    if (status%ok()) then
      ids = mesh%cell_owner(1:nc)
      call self%writer%cell_field('rank', ids, status)
    end if
    if (present(keep_open)) then
      if (keep_open) return
    end if
    if (status%ok()) call self%writer%end_step(status)
  end subroutine write_step

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
