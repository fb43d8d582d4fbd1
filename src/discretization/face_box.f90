!> The faces of a surface set whose centres lie in a box: the part of a set
!> that a boundary condition with lower(3), upper(3) acts on (&boundary).
!> A face's centre is the mean of its 4 nodes; a centre on a bound, to 1e-9
!> of the whole mesh's extent along that axis, counts, so the selection is
!> the same on every rank and for every partition.
module face_box
  use kinds, only: rp, ip, gp
  use dist_mesh, only: dist_mesh_t
  use strings, only: rtoa
  implicit none
  private

  public :: box_tolerance, face_in_box, count_set_faces_in_box, box_text

contains

  !> The tolerance of the bounds per axis [m]: 1e-9 of the global mesh's
  !> extent. Collective.
  function box_tolerance(mesh) result(tol)
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: tol(3)
    integer :: a
    real(rp) :: lo, hi
    do a = 1, 3
      hi = -huge(1.0_rp)
      lo = huge(1.0_rp)
      if (mesh%n_nodes > 0) then
        hi = maxval(mesh%coords(a, 1:mesh%n_nodes))
        lo = minval(mesh%coords(a, 1:mesh%n_nodes))
      end if
      hi = mesh%comm%max(hi)
      lo = mesh%comm%min(lo)
      tol(a) = 1.0e-9_rp * (hi - lo)
    end do
  end function box_tolerance

  !> Whether the centre of local face f lies in [lower - tol, upper + tol].
  logical function face_in_box(mesh, f, lower, upper, tol)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: f
    real(rp), intent(in) :: lower(3), upper(3), tol(3)
    real(rp) :: x(3)
    x = sum(mesh%coords(:, mesh%face_nodes(:, f)), dim=2) / 4.0_rp
    face_in_box = all(x >= lower - tol) .and. all(x <= upper + tol)
  end function face_in_box

  !> The number of faces of set s, over all ranks, whose centres lie in the
  !> box (each face counted once, by its owner). Collective.
  integer(gp) function count_set_faces_in_box(mesh, s, lower, upper, tol) result(n)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: s
    real(rp), intent(in) :: lower(3), upper(3), tol(3)
    integer(ip) :: i, f
    n = 0
    do i = 1, mesh%n_sfaces
      if (mesh%sface_set(i) /= s) cycle
      f = mesh%sface_face(i)
      if (f > mesh%face_map%n_owned) cycle
      if (face_in_box(mesh, f, lower, upper, tol)) n = n + 1
    end do
    n = mesh%comm%sum(n)
  end function count_set_faces_in_box

  !> '[x0, y0, z0] to [x1, y1, z1]' [m], open bounds (+-huge) as -inf, inf.
  function box_text(lower, upper) result(s)
    real(rp), intent(in) :: lower(3), upper(3)
    character(len=:), allocatable :: s
    s = '['//bounds(lower)//'] to ['//bounds(upper)//']'
  end function box_text

  function bounds(v) result(s)
    real(rp), intent(in) :: v(3)
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, 3
      if (i > 1) s = s//', '
      if (v(i) <= -huge(1.0_rp)) then
        s = s//'-inf'
      else if (v(i) >= huge(1.0_rp)) then
        s = s//'inf'
      else
        s = s//rtoa(v(i))
      end if
    end do
  end function bounds
end module face_box
