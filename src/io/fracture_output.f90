!> Output of the fault fields as a grid of their own ('fractures') in the
!> HDF5/XDMF series of field_output: one quadrilateral per interface element
!> (its minus-side face; 4 nodes of its own, so that elements of different
!> ranks never share a node), with the cell fields
!>   traction  (t_N, t_T1, t_T2) in the element frame [Pa] (t_N < 0: compression)
!>   jump      (g_N, g_T1, g_T2) mean jump u_plus - u_minus in the frame [m]
!>   status    1 stick, 2 slip, 3 open
!>   fault     index of the fault (deck order of the mesh's fault names)
!>   rank      the owning rank
!>   normal, tangent1   the frame's n and m1 (interface_element.f90)
!>   center    the element centre [m]
module fracture_output
  use kinds, only: rp, ip, gp
  use error_status, only: error_status_t
  use dist_mesh, only: dist_mesh_t
  use field_output, only: field_output_t
  implicit none
  private

  public :: fracture_output_t

  type :: fracture_output_t
    integer :: grid = 0
  contains
    procedure :: init
    procedure :: write_step
  end type fracture_output_t

contains

  !> Add the 'fractures' grid to out's writer. Collective.
  subroutine init(self, out, mesh, status)
    class(fracture_output_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: x(:,:)
    integer(gp), allocatable :: conn(:,:)
    integer(ip) :: e, k, nown
    integer(gp) :: first
    nown = mesh%iface_map%n_owned
    first = 4 * (mesh%iface_map%first - 1) + 1
    allocate(x(3, 4 * nown), conn(4, nown))
    do e = 1, nown
      do k = 1, 4
        x(:, 4*(e-1) + k) = mesh%coords(:, mesh%iface_nodes(k, 1, e))
        conn(k, e) = first + 4 * (e - 1) + k - 1
      end do
    end do
    call out%writer%add_grid('fractures', 4 * mesh%iface_map%n_global, first, x, mesh%iface_map%n_global, &
                             mesh%iface_map%first, conn, status, self%grid)
  end subroutine init

  !> The fault fields of the open step of out, from the local arrays of the
  !> interface elements (owned first). Collective.
  subroutine write_step(self, out, mesh, trac, jump, state, rot, status)
    class(fracture_output_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: trac(:,:)        !< (3, n) traction in the element frame [Pa]
    real(rp), intent(in) :: jump(:,:)        !< (3, n) mean jump in the element frame [m]
    integer, intent(in) :: state(:)          !< status: 1 stick, 2 slip, 3 open
    real(rp), intent(in) :: rot(:,:,:)       !< (3, 3, n) frame rows: normal, tangent 1, tangent 2
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: v(:,:)
    integer(ip), allocatable :: iv(:)
    integer(ip) :: nown, e
    nown = mesh%iface_map%n_owned
    allocate(v(3, nown), iv(nown))
    v = trac(:, 1:nown)
    call out%writer%cell_field('traction', v, status, self%grid)
    if (status%ok()) then
      v = jump(:, 1:nown)
      call out%writer%cell_field('jump', v, status, self%grid)
    end if
    if (status%ok()) then
      iv = state(1:nown)
      call out%writer%cell_field('status', iv, status, self%grid)
    end if
    if (status%ok()) then
      iv = mesh%iface_fault(1:nown)
      call out%writer%cell_field('fault', iv, status, self%grid)
    end if
    if (status%ok()) then
      iv = mesh%comm%rank
      call out%writer%cell_field('rank', iv, status, self%grid)
    end if
    if (status%ok()) then
      v = rot(1, :, 1:nown)
      call out%writer%cell_field('normal', v, status, self%grid)
    end if
    if (status%ok()) then
      v = rot(2, :, 1:nown)
      call out%writer%cell_field('tangent1', v, status, self%grid)
    end if
    if (status%ok()) then
      do e = 1, nown
        v(:, e) = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
      end do
      call out%writer%cell_field('center', v, status, self%grid)
    end if
  end subroutine write_step
end module fracture_output
