!> Face bubbles on the interface faces of the faults: one vector-valued
!> bubble per (cell, interface face of that cell), so two per interface
!> element, one in the cell on each side. For the face at zeta = -1 of the
!> reference cube the bubble is
!>   b = (1 - xi^2) (1 - eta^2) (1 - zeta) / 2,
!> zero on the cell's other five faces and (1 - xi^2)(1 - eta^2) on its own
!> (the other faces by symmetry, hex_q1's hex_face_bubble). Enriching Q1 with
!> them makes the P0 tractions inf-sup stable (the Bernardi-Raugel idea).
!>
!> A bubble belongs to the rank that owns its cell; bubbles are numbered
!> like the cells (owned first, in cell order and within a cell by local
!> face 1..6, then the ghosts in the same order), with contiguous global
!> ids per rank. Every local cell knows its bubbles, the ghost cells too:
!> the owner of a cell sees all interface elements on its faces (dist_mesh
!> grows the ghost layer across the faults), and the ghost cells get their
!> face masks and first ids from it (one cell import each).
module face_bubbles
  use kinds, only: rp, ip, gp
  use index_map, only: index_map_t
  use dist_mesh, only: dist_mesh_t
  use mesh, only: hex_face_nodes
  implicit none
  private

  public :: face_bubbles_t

  type :: face_bubbles_t
    type(index_map_t) :: map                   !< over bubbles (owned, then ghosts)
    integer(ip), allocatable :: cell_ptr(:)    !< (n_cells + 1) bubbles of local cell c: cell_ptr(c) .. cell_ptr(c+1)-1
    integer(ip), allocatable :: face(:)        !< local face (1..6, mesh's hex_face_nodes) of each bubble
    integer(ip), allocatable :: of_iface(:,:)  !< (2, n_ifaces) the bubble of each side of a local interface element
  contains
    procedure :: build
    procedure :: free
  end type face_bubbles_t

contains

  !> The bubbles of the interface faces of mesh. Collective.
  subroutine build(self, mesh)
    class(face_bubbles_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), allocatable :: lface(:,:), mask(:)
    real(rp), allocatable :: rv(:)
    integer(gp), allocatable :: ghosts(:)
    integer(ip) :: e, s, c, k, n, nown, ncell, ng
    integer(gp) :: first
    type(index_map_t) :: tmp
    call self%free()
    ncell = mesh%n_cells
    allocate(lface(2, mesh%n_ifaces), mask(ncell))
    mask = 0
    do e = 1, mesh%n_ifaces
      do s = 1, 2
        c = mesh%iface_cells(s, e)
        lface(s, e) = local_face(mesh, c, mesh%iface_nodes(:, s, e))
        mask(c) = ior(mask(c), ishft(1, lface(s, e) - 1))
      end do
    end do
    ! the owners' masks are complete: the ghost cells take them
    allocate(rv(ncell))
    rv = real(mask, rp)
    call mesh%cell_map%import(rv)
    mask = nint(rv)
    allocate(self%cell_ptr(ncell + 1))
    self%cell_ptr(1) = 1
    do c = 1, ncell
      self%cell_ptr(c + 1) = self%cell_ptr(c) + popcnt(mask(c))
    end do
    n = self%cell_ptr(ncell + 1) - 1
    nown = self%cell_ptr(mesh%cell_map%n_owned + 1) - 1
    allocate(self%face(n))
    do c = 1, ncell
      n = self%cell_ptr(c)
      do k = 1, 6
        if (btest(mask(c), k - 1)) then
          self%face(n) = k
          n = n + 1
        end if
      end do
    end do
    ! global ids: the owned ones from this rank's first on; a ghost cell's
    ! first bubble id from its owner
    call tmp%init(mesh%comm, nown, [integer(gp) ::])
    first = tmp%first
    call tmp%free()
    rv = 0.0_rp
    do c = 1, mesh%cell_map%n_owned
      rv(c) = real(first + self%cell_ptr(c) - 1, rp)
    end do
    call mesh%cell_map%import(rv)
    ng = self%cell_ptr(ncell + 1) - 1 - nown
    allocate(ghosts(ng))
    ng = 0
    do c = mesh%cell_map%n_owned + 1, ncell
      do k = 0, self%cell_ptr(c + 1) - self%cell_ptr(c) - 1
        ng = ng + 1
        ghosts(ng) = nint(rv(c), gp) + k
      end do
    end do
    call self%map%init(mesh%comm, nown, ghosts)
    allocate(self%of_iface(2, mesh%n_ifaces))
    do e = 1, mesh%n_ifaces
      do s = 1, 2
        c = mesh%iface_cells(s, e)
        self%of_iface(s, e) = self%cell_ptr(c) + findloc(self%face(self%cell_ptr(c):self%cell_ptr(c + 1) - 1), &
                                                         lface(s, e), dim=1) - 1
      end do
    end do
  end subroutine build

  !> The local face (1..6) of cell c whose nodes are nodes(4) (any order).
  integer(ip) function local_face(mesh, c, nodes) result(k)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: c, nodes(4)
    integer(ip) :: a
    do k = 1, 6
      if (all([(any(mesh%cell_nodes(hex_face_nodes(a, k), c) == nodes), a = 1, 4)])) return
    end do
    error stop 'face_bubbles: an interface element is not a face of its cell'
  end function local_face

  subroutine free(self)
    class(face_bubbles_t), intent(inout) :: self
    call self%map%free()
    if (allocated(self%cell_ptr)) deallocate(self%cell_ptr, self%face)
    if (allocated(self%of_iface)) deallocate(self%of_iface)
  end subroutine free
end module face_bubbles
