!> Geometry of a zero-thickness interface element: the quadrilateral shared by
!> the two sides of a fault (mesh.f90 gives its minus-side nodes, counter-
!> clockwise seen from the plus side, so the right-hand normal points from the
!> minus into the plus side).
!>
!> The local frame is the rotation R whose rows are (n, m1, m2):
!>   n  the unit normal at the element centre (minus -> plus),
!>   m1 = n x e_z / |n x e_z|, horizontal (the strike direction; for a fault
!>      extruded along z, the in-plane direction along the fault), or e_x
!>      projected on the plane when the element is horizontal,
!>   m2 = n x m1 (the dip direction up to sign; -e_z for a vertical fault),
!> so that (m1, m2, n) is right-handed. A traction or jump vector v has local
!> components R v = (v_N, v_T1, v_T2).
module interface_element
  use kinds, only: rp, ip
  use quadrature, only: gauss_quad
  use hex_q1, only: quad_shape, quad_area_vector
  implicit none
  private

  public :: interface_geometry, interface_frame, face_bubble_integral

contains

  !> Area [m^2], nodal weights w(a) = integral of N_a over the element [m^2]
  !> (2x2 Gauss, exact for a planar quad) and local frame r of the element with
  !> minus-side node coordinates x(3,4) [m].
  subroutine interface_geometry(x, area, w, r)
    real(rp), intent(in) :: x(3, 4)
    real(rp), intent(out) :: area, w(4), r(3, 3)
    real(rp) :: xi(2, 4), wq(4), n(4), dn(2, 4), da
    integer(ip) :: q
    call gauss_quad(2_ip, xi, wq)
    w = 0.0_rp
    do q = 1, 4
      call quad_shape(xi(:, q), n, dn)
      da = norm2(quad_area_vector(x, xi(:, q))) * wq(q)
      w = w + n * da
    end do
    area = sum(w)
    call interface_frame(quad_area_vector(x, [0.0_rp, 0.0_rp]), r)
  end subroutine interface_geometry

  !> Integral [m^2] over the quad x(3,4) [m] of a face bubble's trace
  !> (1 - xi^2)(1 - eta^2) (face_bubbles.f90; the same in either cell's
  !> parametrization of the face, the trace being symmetric on the square):
  !> 3x3 Gauss, exact for a planar quad (4/9 of the area for a parallelogram).
  real(rp) function face_bubble_integral(x) result(wb)
    real(rp), intent(in) :: x(3, 4)
    real(rp) :: xi(2, 9), wq(9)
    integer(ip) :: q
    call gauss_quad(3_ip, xi, wq)
    wb = 0.0_rp
    do q = 1, 9
      wb = wb + (1.0_rp - xi(1, q)**2) * (1.0_rp - xi(2, q)**2) * norm2(quad_area_vector(x, xi(:, q))) * wq(q)
    end do
  end function face_bubble_integral

  !> Local frame r (rows n, m1, m2) from a normal vector nv of any length.
  pure subroutine interface_frame(nv, r)
    real(rp), intent(in) :: nv(3)
    real(rp), intent(out) :: r(3, 3)
    real(rp) :: n(3), m1(3), s
    n = nv / norm2(nv)
    m1 = [n(2), -n(1), 0.0_rp]                ! n x e_z
    s = norm2(m1)
    if (s < 1.0e-8_rp) then
      m1 = [1.0_rp, 0.0_rp, 0.0_rp] - n(1) * n
      s = norm2(m1)
    end if
    m1 = m1 / s
    r(1, :) = n
    r(2, :) = m1
    r(3, :) = [n(2)*m1(3) - n(3)*m1(2), n(3)*m1(1) - n(1)*m1(3), n(1)*m1(2) - n(2)*m1(1)]
  end subroutine interface_frame
end module interface_element
