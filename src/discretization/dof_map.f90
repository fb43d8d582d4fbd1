!> Degrees of freedom of one field: ncomp unknowns on each entity (node, face
!> or cell) of an entity index map, interleaved: local dof of component c on
!> local entity e is ncomp*(e-1)+c, global dof ncomp*(g-1)+c. Owned entities
!> own their dofs, so the dof map inherits the contiguous ownership.
!>
!> init_extra adds a second kind of entity (the face bubbles of contact) to
!> the same field: the local entities are then this rank's owned entities of
!> the first kind, its owned extra ones, the ghosts of the first kind and the
!> extra ghosts, and the global ids run the same way per rank. dof(e, c)
!> still takes the first kind's local id e (so loops over nodes stay as they
!> are), extra_dof(j, c) the extra entity's local id j.
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
    !> with extra entities (init_extra): owned entities of the first kind,
    !> owned extra ones, ghosts of the first kind (else 0)
    integer(ip) :: n_a_owned = 0, n_b_owned = 0, n_a_ghost = 0
  contains
    procedure :: init
    procedure :: init_extra
    procedure :: entity
    procedure :: extra_entity
    procedure :: dof
    procedure :: extra_dof
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

  !> ncomp dofs on each entity of emap and of bmap (a second kind of entity,
  !> see the module header). Collective.
  subroutine init_extra(self, name, emap, bmap, ncomp)
    class(dof_map_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    type(index_map_t), intent(in) :: emap, bmap
    integer(ip), intent(in) :: ncomp
    type(index_map_t) :: cmap
    integer(gp), allocatable :: ghosts(:)
    integer(ip) :: i, q
    ! an entity owned by rank q moves up by the other kind's entities of
    ! the ranks before q (and, extra, by q's own of the first kind)
    allocate(ghosts(emap%n_ghost + bmap%n_ghost))
    do i = 1, emap%n_ghost
      q = emap%ghost_owner(i)
      ghosts(i) = emap%ghost_gid(i) + bmap%offsets(q) - 1
    end do
    do i = 1, bmap%n_ghost
      q = bmap%ghost_owner(i)
      ghosts(emap%n_ghost + i) = bmap%ghost_gid(i) + emap%offsets(q + 1) - 1
    end do
    call cmap%init(emap%comm, emap%n_owned + bmap%n_owned, ghosts)
    call self%init(name, cmap, ncomp)
    call cmap%free()
    self%n_a_owned = emap%n_owned
    self%n_b_owned = bmap%n_owned
    self%n_a_ghost = emap%n_ghost
  end subroutine init_extra

  !> Local entity of the dof layout of local entity e of the first kind.
  elemental integer(ip) function entity(self, e)
    class(dof_map_t), intent(in) :: self
    integer(ip), intent(in) :: e
    entity = e
    if (e > self%n_a_owned .and. self%n_b_owned > 0) entity = e + self%n_b_owned
  end function entity

  !> Local entity of the dof layout of local extra entity j (init_extra).
  elemental integer(ip) function extra_entity(self, j)
    class(dof_map_t), intent(in) :: self
    integer(ip), intent(in) :: j
    if (j <= self%n_b_owned) then
      extra_entity = self%n_a_owned + j
    else
      extra_entity = self%n_a_owned + self%n_a_ghost + j
    end if
  end function extra_entity

  !> Local dof of component c on local entity e (of the first kind).
  elemental integer(ip) function dof(self, e, c)
    class(dof_map_t), intent(in) :: self
    integer(ip), intent(in) :: e, c
    dof = self%ncomp * (self%entity(e) - 1) + c
  end function dof

  !> Local dof of component c on local extra entity j (init_extra).
  elemental integer(ip) function extra_dof(self, j, c)
    class(dof_map_t), intent(in) :: self
    integer(ip), intent(in) :: j, c
    extra_dof = self%ncomp * (self%extra_entity(j) - 1) + c
  end function extra_dof

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
    self%n_a_owned = 0
    self%n_b_owned = 0
    self%n_a_ghost = 0
  end subroutine free
end module dof_map
