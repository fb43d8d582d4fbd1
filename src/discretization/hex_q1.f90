!> Trilinear (Q1) hexahedron and bilinear quadrilateral shape functions.
!> Reference cube [-1,1]^3, node order as in mesh.f90 (Gmsh/VTK).
module hex_q1
  use kinds, only: rp, ip
  implicit none
  private

  public :: hex_shape, hex_gradients, hex_jacobian_det, quad_shape, quad_area_vector, inverse3, hex_face_bubble, &
            hex_contains_point

  !> Reference coordinates of the 8 nodes.
  real(rp), parameter :: s(3, 8) = reshape([ &
    -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1, &
    -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1], [3, 8])

contains

  !> Shape functions n(8) and their reference derivatives dn(3,8) at xi.
  pure subroutine hex_shape(xi, n, dn)
    real(rp), intent(in) :: xi(3)
    real(rp), intent(out) :: n(8), dn(3, 8)
    integer :: a
    real(rp) :: f(3)
    do a = 1, 8
      f = 1.0_rp + s(:, a) * xi
      n(a) = 0.125_rp * f(1) * f(2) * f(3)
      dn(1, a) = 0.125_rp * s(1, a) * f(2) * f(3)
      dn(2, a) = 0.125_rp * s(2, a) * f(1) * f(3)
      dn(3, a) = 0.125_rp * s(3, a) * f(1) * f(2)
    end do
  end subroutine hex_shape

  !> Physical gradients g(3,8) of the shape functions at xi for the cell with
  !> node coordinates x(3,8), and det J. det <= 0 means an inverted cell.
  pure subroutine hex_gradients(x, xi, n, g, det)
    real(rp), intent(in) :: x(3, 8), xi(3)
    real(rp), intent(out) :: n(8), g(3, 8), det
    real(rp) :: dn(3, 8), j(3, 3), ji(3, 3)
    call hex_shape(xi, n, dn)
    j = matmul(dn, transpose(x))      ! j(r, i) = d x_i / d xi_r
    call inverse3(j, ji, det)
    g = matmul(ji, dn)                ! g(i, a) = d n_a / d x_i
  end subroutine hex_gradients

  !> det J at xi for the cell with node coordinates x(3,8), without the
  !> inverse: the same products and sums as hex_gradients' det (so the same
  !> value), for checking a cell before anything divides by det.
  pure real(rp) function hex_jacobian_det(x, xi) result(det)
    real(rp), intent(in) :: x(3, 8), xi(3)
    real(rp) :: n(8), dn(3, 8), a(3, 3), c11, c21, c31
    call hex_shape(xi, n, dn)
    a = matmul(dn, transpose(x))
    c11 = a(2,2)*a(3,3) - a(2,3)*a(3,2)
    c21 = a(2,3)*a(3,1) - a(2,1)*a(3,3)
    c31 = a(2,1)*a(3,2) - a(2,2)*a(3,1)
    det = a(1,1)*c11 + a(1,2)*c21 + a(1,3)*c31
  end function hex_jacobian_det

  !> The bubble of local face k (1..6: xi = -1, +1, eta = -1, +1, zeta = -1,
  !> +1, mesh's hex_face_nodes) at xi: value b and reference derivatives
  !> db(3). For k = 5 (zeta = -1): b = (1 - xi^2) (1 - eta^2) (1 - zeta) / 2,
  !> zero on the other five faces.
  pure subroutine hex_face_bubble(xi, k, b, db)
    real(rp), intent(in) :: xi(3)
    integer(ip), intent(in) :: k
    real(rp), intent(out) :: b, db(3)
    real(rp) :: f(3), df(3), sg
    integer :: d, i
    d = (k + 1) / 2
    sg = merge(-1.0_rp, 1.0_rp, mod(k, 2_ip) == 1)
    do i = 1, 3
      if (i == d) then
        f(i) = 0.5_rp * (1.0_rp + sg * xi(i))
        df(i) = 0.5_rp * sg
      else
        f(i) = 1.0_rp - xi(i)**2
        df(i) = -2.0_rp * xi(i)
      end if
    end do
    b = f(1) * f(2) * f(3)
    db = [df(1) * f(2) * f(3), f(1) * df(2) * f(3), f(1) * f(2) * df(3)]
  end subroutine hex_face_bubble

  !> Inverse ai and determinant det of a 3x3 matrix a (adjugate / det).
  pure subroutine inverse3(a, ai, det)
    real(rp), intent(in) :: a(3, 3)
    real(rp), intent(out) :: ai(3, 3), det
    ai(1,1) = a(2,2)*a(3,3) - a(2,3)*a(3,2)
    ai(1,2) = a(1,3)*a(3,2) - a(1,2)*a(3,3)
    ai(1,3) = a(1,2)*a(2,3) - a(1,3)*a(2,2)
    ai(2,1) = a(2,3)*a(3,1) - a(2,1)*a(3,3)
    ai(2,2) = a(1,1)*a(3,3) - a(1,3)*a(3,1)
    ai(2,3) = a(1,3)*a(2,1) - a(1,1)*a(2,3)
    ai(3,1) = a(2,1)*a(3,2) - a(2,2)*a(3,1)
    ai(3,2) = a(1,2)*a(3,1) - a(1,1)*a(3,2)
    ai(3,3) = a(1,1)*a(2,2) - a(1,2)*a(2,1)
    det = a(1,1)*ai(1,1) + a(1,2)*ai(2,1) + a(1,3)*ai(3,1)
    ai = ai / det
  end subroutine inverse3

  !> Bilinear quadrilateral shape functions at xi in [-1,1]^2 (nodes counter-
  !> clockwise) and their reference derivatives dn(2,4).
  pure subroutine quad_shape(xi, n, dn)
    real(rp), intent(in) :: xi(2)
    real(rp), intent(out) :: n(4), dn(2, 4)
    real(rp), parameter :: t(2, 4) = reshape([-1, -1, 1, -1, 1, 1, -1, 1], [2, 4])
    integer :: a
    do a = 1, 4
      n(a) = 0.25_rp * (1 + t(1, a) * xi(1)) * (1 + t(2, a) * xi(2))
      dn(1, a) = 0.25_rp * t(1, a) * (1 + t(2, a) * xi(2))
      dn(2, a) = 0.25_rp * t(2, a) * (1 + t(1, a) * xi(1))
    end do
  end subroutine quad_shape

  !> Area vector (normal times area element) of the quad x(3,4) at xi.
  pure function quad_area_vector(x, xi) result(v)
    real(rp), intent(in) :: x(3, 4), xi(2)
    real(rp) :: v(3), n(4), dn(2, 4), a(3), b(3)
    call quad_shape(xi, n, dn)
    a = matmul(x, dn(1, :))
    b = matmul(x, dn(2, :))
    v = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function quad_area_vector

  !> Whether the hexahedron with nodes x(3, 8) contains p (up to a relative
  !> 1e-9 of its size); xi: the reference coordinates of p (Newton's method
  !> on the trilinear map).
  logical function hex_contains_point(x, p, xi)
    real(rp), intent(in) :: x(3, 8), p(3)
    real(rp), intent(out) :: xi(3)
    real(rp) :: n(8), dn(3, 8), jac(3, 3), jinv(3, 3), det, r(3), h
    integer :: it
    xi = 0.0_rp
    hex_contains_point = .false.
    h = maxval(maxval(x, dim=2) - minval(x, dim=2))
    if (any(p < minval(x, dim=2) - 1.0e-9_rp * h) .or. any(p > maxval(x, dim=2) + 1.0e-9_rp * h)) return
    do it = 1, 30
      call hex_shape(xi, n, dn)
      r = p - matmul(x, n)
      jac = matmul(x, transpose(dn))             ! jac(i, j) = d x_i / d xi_j
      call inverse3(jac, jinv, det)
      if (det == 0.0_rp) return
      xi = xi + matmul(jinv, r)
      if (maxval(abs(xi)) > 4.0_rp) return
      if (maxval(abs(matmul(jinv, r))) < 1.0e-14_rp) exit
    end do
    hex_contains_point = maxval(abs(xi)) <= 1.0_rp + 1.0e-9_rp
  end function hex_contains_point
end module hex_q1
