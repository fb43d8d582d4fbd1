!> The connected pieces of a distributed mesh: two cells are in the same
!> piece when they share a node. Interface elements do not connect (their
!> two sides have their own nodes after the split), so a fault that cuts a
!> block in two makes two pieces; whether they act as one depends on the
!> state of the interface elements between them (rigid_modes.f90).
!>
!> Each local node gets the label of its piece: the smallest original node
!> id in it (the mesh's numbering before the partition), the same on every
!> rank and for any number of ranks. Built by a local union-find over the owned
!> cells, then label exchanges between ranks (owners take the minimum of the
!> ghost copies, ghosts take the owner's value) until no label changes; the
!> number of rounds grows with the number of ranks a piece crosses, not with
!> the mesh size.
module mesh_pieces
  use kinds, only: rp, ip, gp
  use dist_mesh, only: dist_mesh_t
  implicit none
  private

  public :: mesh_pieces_t

  type :: mesh_pieces_t
    integer(gp), allocatable :: label(:)   !< (n_nodes) piece of each local node
    integer(ip), allocatable :: comp(:)    !< (n_nodes) local component (1..n_comp): nodes joined by owned cells
    integer(ip) :: n_comp = 0              !< local components
    integer :: rounds = 0                  !< label exchanges the build needed
  contains
    procedure :: build
    procedure :: free
  end type mesh_pieces_t

contains

  !> Label every local node of mesh with its piece. Collective.
  subroutine build(self, mesh)
    class(mesh_pieces_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), allocatable :: parent(:), root_comp(:)
    real(rp), allocatable :: lab(:), low(:), old(:)
    integer(ip) :: c, k, i, r
    call self%free()
    allocate(parent(mesh%n_nodes), root_comp(mesh%n_nodes), self%comp(mesh%n_nodes))
    parent = [(i, i = 1, mesh%n_nodes)]
    do c = 1, mesh%n_owned_cells()
      do k = 2, 8
        call join(parent, mesh%cell_nodes(1, c), mesh%cell_nodes(k, c))
      end do
    end do
    root_comp = 0
    self%n_comp = 0
    do i = 1, mesh%n_nodes
      r = find(parent, i)
      if (root_comp(r) == 0) then
        self%n_comp = self%n_comp + 1
        root_comp(r) = self%n_comp
      end if
      self%comp(i) = root_comp(r)
    end do
    ! labels as reals (exact below 2**53) for the node map's exchanges
    allocate(lab(mesh%n_nodes), low(self%n_comp))
    do i = 1, mesh%n_nodes
      lab(i) = real(mesh%node_orig(i), rp)
    end do
    self%rounds = 0
    do
      low = huge(1.0_rp)
      do i = 1, mesh%n_nodes
        low(self%comp(i)) = min(low(self%comp(i)), lab(i))
      end do
      old = lab
      lab = low(self%comp)
      call mesh%node_map%export_min(lab)
      call mesh%node_map%import(lab)
      self%rounds = self%rounds + 1
      if (.not. mesh%comm%any_true(any(lab /= old))) exit
    end do
    self%label = int(lab, gp)
  end subroutine build

  integer(ip) function find(parent, i) result(r)
    integer(ip), intent(inout) :: parent(:)
    integer(ip), intent(in) :: i
    integer(ip) :: j, nxt
    r = i
    do while (parent(r) /= r)
      r = parent(r)
    end do
    j = i
    do while (parent(j) /= r)
      nxt = parent(j)
      parent(j) = r
      j = nxt
    end do
  end function find

  subroutine join(parent, a, b)
    integer(ip), intent(inout) :: parent(:)
    integer(ip), intent(in) :: a, b
    integer(ip) :: ra, rb
    ra = find(parent, a)
    rb = find(parent, b)
    if (ra /= rb) parent(max(ra, rb)) = min(ra, rb)
  end subroutine join

  subroutine free(self)
    class(mesh_pieces_t), intent(inout) :: self
    if (allocated(self%label)) deallocate(self%label)
    if (allocated(self%comp)) deallocate(self%comp)
    self%n_comp = 0
    self%rounds = 0
  end subroutine free
end module mesh_pieces
