!> Degrees of freedom of one field: ncomp unknowns on each entity (node, face
!> or cell) of an entity index map, interleaved: local dof of component c on
!> local entity e is ncomp*(e-1)+c, global dof ncomp*(g-1)+c. Owned entities
!> own their dofs, so the dof map inherits the contiguous ownership.
module dof_map
  use kinds, only: ip, gp, name_len
  use index_map, only: index_map_t
  implicit none
  private

  public :: dof_map_t

  type :: dof_map_t
    character(len=name_len) :: name = ''
    integer(ip) :: ncomp = 1
    type(index_map_t) :: map                 !< over dofs
  contains
    procedure :: init
    procedure :: dof
    procedure :: n_owned
    procedure :: n_local
    procedure :: free
  end type dof_map_t

contains

  !> ncomp dofs on each entity of emap; extra: global ids of further
  !> entities owned elsewhere whose dofs this rank needs as ghosts (after
  !> emap's, in that order). Collective.
  subroutine init(self, name, emap, ncomp, extra)
    class(dof_map_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    type(index_map_t), intent(in) :: emap
    integer(ip), intent(in) :: ncomp
    integer(gp), intent(in), optional :: extra(:)
    integer(gp), allocatable :: ghosts(:), ents(:)
    integer(ip) :: i, c
    self%name = name
    self%ncomp = ncomp
    if (present(extra)) then
      allocate(ents(emap%n_ghost + size(extra)))
      ents(emap%n_ghost+1:) = extra
    else
      allocate(ents(emap%n_ghost))
    end if
    ents(1:emap%n_ghost) = emap%ghost_gid(1:emap%n_ghost)
    allocate(ghosts(ncomp * size(ents)))
    do i = 1, size(ents, kind=ip)
      do c = 1, ncomp
        ghosts(ncomp*(i-1)+c) = ncomp * (ents(i) - 1) + c
      end do
    end do
    call self%map%init(emap%comm, ncomp * emap%n_owned, ghosts)
  end subroutine init

  !> Local dof of component c on local entity e.
  elemental integer(ip) function dof(self, e, c)
    class(dof_map_t), intent(in) :: self
    integer(ip), intent(in) :: e, c
    dof = self%ncomp * (e - 1) + c
  end function dof

  integer(ip) function n_owned(self)
    class(dof_map_t), intent(in) :: self
    n_owned = self%map%n_owned
  end function n_owned

  integer(ip) function n_local(self)
    class(dof_map_t), intent(in) :: self
    n_local = self%map%n_local()
  end function n_local

  subroutine free(self)
    class(dof_map_t), intent(inout) :: self
    call self%map%free()
  end subroutine free
end module dof_map
