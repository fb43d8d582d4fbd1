!> Output of the fault and fracture fields: a grid 'fractures' of the
!> HDF5 output of field_output (datasets /fractures/<field> in the step
!> files, the grid in <prefix>_mesh.h5:/fractures), described in an XDMF
!> file of its own, <prefix>_fractures.xdmf. One quadrilateral per interface
!> element (its minus-side face; 4 nodes of its own, so that elements of
!> different ranks never share a node), with the cell fields
!>   slip             (3) tangential part of the jump u_plus - u_minus, global x, y, z [m]
!>   slip_magnitude   its length [m]
!>   opening          normal jump g_N = (u_plus - u_minus) . n [m], > 0 open
!>   normal_traction  t_N on the fault [Pa], < 0 in compression (the contact
!>                    traction of the friction law, effective: with the fluid
!>                    pressure p on the faces, &fault pressure or the
!>                    fracture flow's, the total normal traction on them is
!>                    t_N - p, written by interface_contact as
!>                    total_normal_traction beside pressure)
!>   shear_traction   (3) tangential traction on the minus side, global x, y, z [Pa]
!>   shear_traction_magnitude  |tau| [Pa]
!>   cff              Coulomb failure function |tau| - (c - tan(phi) t_N) [Pa]:
!>                    0 where slipping, <= 0 in stick (up to &contact
!>                    status_tol), -c where open
!>   status           0 stick, 1 slip, 2 open
!>   fault            index of the fault (deck order of the mesh's fault names)
!>   rank             the owning rank
!>   normal, tangent1 the element frame's n (from minus to plus side) and m1
!>   center           the element centre [m]
!> The legend of status, the units and the sign conventions are written as
!> Information elements into the XDMF file.
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

  !> Add the 'fractures' grid, with its own XDMF file, to out's writer,
  !> with the legend and conventions as Information elements. Collective.
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
                             mesh%iface_map%first, conn, status, self%grid, own_file=.true.)
    if (.not. status%ok()) return
    call out%writer%add_info('status', '0 stick, 1 slip, 2 open', status, self%grid)
    call out%writer%add_info('units', 'slip, slip_magnitude, opening, center: m; normal_traction, '// &
      'total_normal_traction, pressure, shear_traction, shear_traction_magnitude, cff: Pa', status, self%grid)
    call out%writer%add_info('signs', 'jump = u_plus - u_minus, normal from the minus to the plus side; '// &
      'opening positive when open; normal_traction (effective: the contact traction of the friction law) and '// &
      'total_normal_traction (normal_traction - pressure) negative in compression; slip and shear_traction '// &
      'in global x y z', &
      status, self%grid)
    call out%writer%add_info('cff', 'Coulomb failure function |shear_traction| - (cohesion - '// &
      'tan(friction_angle) normal_traction): 0 where slipping, at most 0 in stick, -cohesion where open', status, self%grid)
  end subroutine init

  !> The fault fields of the open step of out, from the local arrays of the
  !> interface elements (owned first). Collective.
  subroutine write_step(self, out, mesh, trac, jump, state, rot, fric, coh, status)
    class(fracture_output_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: trac(:,:)        !< (3, n) traction in the element frame (t_N, t_T1, t_T2) [Pa]
    real(rp), intent(in) :: jump(:,:)        !< (3, n) mean jump in the element frame [m]
    integer, intent(in) :: state(:)          !< status: 0 stick, 1 slip, 2 open
    real(rp), intent(in) :: rot(:,:,:)       !< (3, 3, n) frame rows: normal, tangent 1, tangent 2
    real(rp), intent(in) :: fric(:), coh(:)  !< tan(phi), cohesion [Pa]
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: v(:,:), s(:)
    integer(ip), allocatable :: iv(:)
    integer(ip) :: nown, e
    nown = mesh%iface_map%n_owned
    allocate(v(3, nown), s(nown), iv(nown))
    do e = 1, nown
      v(:, e) = jump(2, e) * rot(2, :, e) + jump(3, e) * rot(3, :, e)
    end do
    call out%writer%cell_field('slip', v, status, self%grid)
    s = norm2(jump(2:3, 1:nown), dim=1)
    if (status%ok()) call out%writer%cell_field('slip_magnitude', s, status, self%grid)
    s = jump(1, 1:nown)
    if (status%ok()) call out%writer%cell_field('opening', s, status, self%grid)
    s = trac(1, 1:nown)
    if (status%ok()) call out%writer%cell_field('normal_traction', s, status, self%grid)
    do e = 1, nown
      v(:, e) = trac(2, e) * rot(2, :, e) + trac(3, e) * rot(3, :, e)
    end do
    if (status%ok()) call out%writer%cell_field('shear_traction', v, status, self%grid)
    s = norm2(trac(2:3, 1:nown), dim=1)
    if (status%ok()) call out%writer%cell_field('shear_traction_magnitude', s, status, self%grid)
    s = s - (coh(1:nown) - fric(1:nown) * trac(1, 1:nown))
    if (status%ok()) call out%writer%cell_field('cff', s, status, self%grid)
    iv = state(1:nown)
    if (status%ok()) call out%writer%cell_field('status', iv, status, self%grid)
    iv = mesh%iface_fault(1:nown)
    if (status%ok()) call out%writer%cell_field('fault', iv, status, self%grid)
    iv = mesh%comm%rank
    if (status%ok()) call out%writer%cell_field('rank', iv, status, self%grid)
    v = rot(1, :, 1:nown)
    if (status%ok()) call out%writer%cell_field('normal', v, status, self%grid)
    v = rot(2, :, 1:nown)
    if (status%ok()) call out%writer%cell_field('tangent1', v, status, self%grid)
    do e = 1, nown
      v(:, e) = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
    end do
    if (status%ok()) call out%writer%cell_field('center', v, status, self%grid)
  end subroutine write_step
end module fracture_output
