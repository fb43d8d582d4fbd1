!> Is the mesh a slab with flat cells? The usual way to run a 2D case in a 3D
!> code (plane strain: one cell, or a few, across a thin dimension, graded
!> out in the plane), where BoomerAMG of the displacement block needs a
!> strength threshold above 1/2 (amg_params.f90, slab_threshold, says why).
!>
!> A slab along coordinate axis c: the mesh's extent along c is at most
!> 1/slab_ratio of its extent along each of the two other axes, and at least
!> one cell is flat along c (its bounding box at least flat_ratio times
!> wider, along both other axes, than thick along c). Mandel's deck (cubic
!> cells in a 1 x 1 x 0.05 plate) is thin but has no flat cell; a cube or a
!> 3D box with a core refinement is not thin.
module slab_geometry
  use kinds, only: rp, ip
  use dist_mesh, only: dist_mesh_t
  implicit none
  private

  public :: slab_t, find_slab

  !> a slab's extent along its axis: at most 1/slab_ratio of the others'
  real(rp), parameter :: slab_ratio = 10.0_rp
  !> a flat cell: both in-plane sizes at least flat_ratio times its thickness
  real(rp), parameter :: flat_ratio = 4.0_rp

  !> What find_slab found (the same on every rank).
  type :: slab_t
    integer :: axis = 0                  !< 1, 2, 3 (x, y, z): the slab's thin axis; 0: not a slab
    real(rp) :: thickness = 0.0_rp       !< the mesh's extent along axis [m]
    real(rp) :: width = 0.0_rp           !< the smaller of its extents along the other axes [m]
    real(rp) :: flatness = 0.0_rp        !< largest in-plane size / thickness of a cell (the smaller in-plane size)
  end type slab_t

contains

  !> The slab of mesh, if it is one (slab%axis > 0). Collective.
  function find_slab(mesh) result(slab)
    type(dist_mesh_t), intent(in) :: mesh
    type(slab_t) :: slab
    real(rp) :: lo(3), hi(3), ext(3), e(3), flat(3), width
    integer :: a, b1, b2
    integer(ip) :: c

    do a = 1, 3
      lo(a) = huge(1.0_rp)
      hi(a) = -huge(1.0_rp)
      if (mesh%n_nodes > 0) then
        lo(a) = minval(mesh%coords(a, 1:mesh%n_nodes))
        hi(a) = maxval(mesh%coords(a, 1:mesh%n_nodes))
      end if
      lo(a) = mesh%comm%min(lo(a))
      hi(a) = mesh%comm%max(hi(a))
    end do
    ext = hi - lo
    flat = 0.0_rp
    do c = 1, mesh%n_cells
      do a = 1, 3
        e(a) = maxval(mesh%coords(a, mesh%cell_nodes(:, c))) - minval(mesh%coords(a, mesh%cell_nodes(:, c)))
      end do
      do a = 1, 3
        call others(a, b1, b2)
        if (e(a) > 0.0_rp) flat(a) = max(flat(a), min(e(b1), e(b2)) / e(a))
      end do
    end do
    do a = 1, 3
      flat(a) = mesh%comm%max(flat(a))
    end do
    do a = 1, 3
      call others(a, b1, b2)
      width = min(ext(b1), ext(b2))
      if (ext(a) > 0.0_rp .and. slab_ratio * ext(a) <= width .and. flat(a) >= flat_ratio) then
        slab = slab_t(axis=a, thickness=ext(a), width=width, flatness=flat(a))
        return
      end if
    end do
  contains
    !> The two axes other than a.
    subroutine others(a, b1, b2)
      integer, intent(in) :: a
      integer, intent(out) :: b1, b2
      b1 = mod(a, 3) + 1
      b2 = mod(a + 1, 3) + 1
    end subroutine others
  end function find_slab
end module slab_geometry
