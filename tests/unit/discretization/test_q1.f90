!> Unit tests of the Q1 hexahedron and the Gauss rules: Kronecker property,
!> partition of unity, reproduction of linear fields, exactness degrees of the
!> 1D rules, volumes of mapped cells and areas of quads; the face bubbles of
!> contact's bubble space (zero on the other faces, their trace on their own,
!> derivatives, the face integral 4/9 of a parallelogram's area).
program test_q1
  use kinds, only: rp, ip
  use parallel_comm, only: parallel_comm_t
  use assertions, only: test_suite_t
  use quadrature, only: gauss_1d, gauss_quad, gauss_hex
  use hex_q1, only: hex_shape, hex_gradients, quad_shape, quad_area_vector, hex_face_bubble
  use interface_element, only: face_bubble_integral
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  real(rp), parameter :: s(3, 8) = reshape([ &
    -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1, &
    -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1], [3, 8])
  real(rp) :: n(8), dn(3, 8), g(3, 8), det, x(3, 8), a(3, 3), xi(3), errmax, v
  real(rp) :: xq(3, 27), wq(27), xp(4), wp(4), x2(2, 9), w2(9), q(3, 4), nq(4), dnq(2, 4)
  integer(ip) :: i, j, k, np
  character(len=80) :: what

  call comm%init_world()
  call suite%init('q1', comm)

  ! Kronecker property at the nodes
  errmax = 0.0_rp
  do i = 1, 8
    call hex_shape(s(:, i), n, dn)
    do j = 1, 8
      errmax = max(errmax, abs(n(j) - merge(1.0_rp, 0.0_rp, i == j)))
    end do
  end do
  call suite%assert_close(errmax, 0.0_rp, 1.0e-15_rp, 'N_a(x_b) = delta_ab')

  ! partition of unity and zero gradient sum at arbitrary points
  errmax = 0.0_rp
  do k = 1, 20
    xi = [sin(1.3_rp * k), cos(2.1_rp * k), sin(0.7_rp * k + 0.3_rp)]
    call hex_shape(xi, n, dn)
    errmax = max(errmax, abs(sum(n) - 1.0_rp), maxval(abs(sum(dn, dim=2))))
  end do
  call suite%assert_close(errmax, 0.0_rp, 1.0e-14_rp, 'sum N_a = 1 and sum dN_a = 0')

  ! an affine map x = A xi + b: the Jacobian is A, interpolated x has gradient I
  a = reshape([2.0_rp, 0.3_rp, -0.1_rp, 0.2_rp, 1.5_rp, 0.4_rp, -0.3_rp, 0.1_rp, 0.8_rp], [3, 3])
  do i = 1, 8
    x(:, i) = matmul(a, s(:, i)) + [1.0_rp, -2.0_rp, 0.5_rp]
  end do
  call hex_gradients(x, [0.2_rp, -0.4_rp, 0.7_rp], n, g, det)
  call suite%assert_close(det, determinant(a), 1.0e-13_rp, 'det J of an affine map equals det A')
  call suite%assert_close(maxval(abs(matmul(x, transpose(g)) - identity())), 0.0_rp, 1.0e-13_rp, &
                          'sum_a x_a (grad N_a)^T = I (linear fields reproduced)')

  ! 1D Gauss rules: exact up to degree 2n-1, not for degree 2n
  do np = 1, 4
    call gauss_1d(np, xp(1:np), wp(1:np))
    errmax = 0.0_rp
    do k = 0, 2 * np - 1
      errmax = max(errmax, abs(sum(wp(1:np) * xp(1:np)**k) - exact_moment(k)))
    end do
    write(what, '(a,i0,a,i0)') 'gauss_1d n = ', np, ' exact to degree ', 2 * np - 1
    call suite%assert_close(errmax, 0.0_rp, 1.0e-14_rp, what)
    v = abs(sum(wp(1:np) * xp(1:np)**(2 * np)) - exact_moment(2 * np))
    write(what, '(a,i0,a,i0)') 'gauss_1d n = ', np, ' not exact for degree ', 2 * np
    call suite%assert_true(v > 1.0e-3_rp, what)
  end do

  ! volume of a distorted (non-affine) hexahedron: 2x2x2 Gauss equals the
  ! divergence-theorem volume computed from the faces by the 3x3x3 rule
  x(:, :) = s
  x(:, 7) = [1.4_rp, 1.2_rp, 1.3_rp]
  x(:, 2) = [1.1_rp, -0.9_rp, -1.2_rp]
  call gauss_hex(2_ip, xq(:, 1:8), wq(1:8))
  v = 0.0_rp
  do k = 1, 8
    call hex_gradients(x, xq(:, k), n, g, det)
    v = v + det * wq(k)
  end do
  call gauss_hex(3_ip, xq, wq)
  errmax = 0.0_rp
  do k = 1, 27
    call hex_gradients(x, xq(:, k), n, g, det)
    errmax = errmax + det * wq(k)
  end do
  call suite%assert_close(v, errmax, 1.0e-13_rp, 'cell volume: 2x2x2 Gauss is exact (det J is degree 2 per axis)')
  call suite%assert_close(sum(wq), 8.0_rp, 1.0e-14_rp, '3x3x3 weights sum to the reference volume')

  ! quad area vector: a planar parallelogram in 3D
  q(:, 1) = [0.0_rp, 0.0_rp, 1.0_rp]
  q(:, 2) = [2.0_rp, 0.0_rp, 1.0_rp]
  q(:, 3) = [3.0_rp, 1.0_rp, 1.0_rp]
  q(:, 4) = [1.0_rp, 1.0_rp, 1.0_rp]
  call gauss_quad(3_ip, x2, w2)
  v = 0.0_rp
  do k = 1, 9
    v = v + norm2(quad_area_vector(q, x2(:, k))) * w2(k)
  end do
  call suite%assert_close(v, 2.0_rp, 1.0e-14_rp, 'quad area of a parallelogram')
  call suite%assert_close(maxval(abs(quad_area_vector(q, [0.1_rp, 0.2_rp])) * [1.0_rp, 1.0_rp, 0.0_rp]), 0.0_rp, &
                          1.0e-15_rp, 'quad normal is normal to the plane z = 1')
  call quad_shape([0.3_rp, -0.6_rp], nq, dnq)
  call suite%assert_close(sum(nq), 1.0_rp, 1.0e-15_rp, 'quad shape functions sum to 1')

  call face_bubble_checks()

  call suite%finish()

contains

  !> hex_face_bubble of every face at points of every face: zero on the
  !> other five, (1 - a^2)(1 - b^2) on its own (a, b the other two
  !> coordinates); its derivatives against central differences (exact for
  !> the quadratic factors up to round-off); the integral of the trace over
  !> a parallelogram (4/9 of its area) and over a trapezoid (2x2 x 2x2
  !> rule of the bilinear area density: 3x3 Gauss is exact).
  subroutine face_bubble_checks()
    real(rp) :: xb(3), b, db(3), bp, bm, dummy(3), e_face, e_other, e_der, h, quad(3, 4)
    integer(ip) :: f, k, d, t
    e_face = 0.0_rp
    e_other = 0.0_rp
    e_der = 0.0_rp
    h = 1.0e-4_rp
    do f = 1, 6
      do k = 1, 6
        do t = 1, 5
          xb = [sin(1.7_rp * t + k), cos(0.9_rp * t + f), sin(0.4_rp * t * k)]
          d = (k + 1) / 2
          xb(d) = merge(-1.0_rp, 1.0_rp, mod(k, 2_ip) == 1)
          call hex_face_bubble(xb, f, b, db)
          if (k == f) then
            e_face = max(e_face, abs(b - product(1.0_rp - xb**2, mask=[(i /= d, i = 1, 3)])))
          else
            e_other = max(e_other, abs(b))
          end if
        end do
      end do
      xb = [0.31_rp, -0.47_rp, 0.12_rp]
      call hex_face_bubble(xb, f, b, db)
      do d = 1, 3
        xb(d) = xb(d) + h
        call hex_face_bubble(xb, f, bp, dummy)
        xb(d) = xb(d) - 2.0_rp * h
        call hex_face_bubble(xb, f, bm, dummy)
        xb(d) = xb(d) + h
        e_der = max(e_der, abs((bp - bm) / (2.0_rp * h) - db(d)))
      end do
    end do
    call suite%assert_close(e_face, 0.0_rp, 1.0e-15_rp, 'face bubble: its trace (1-a^2)(1-b^2) on its own face')
    call suite%assert_close(e_other, 0.0_rp, 1.0e-15_rp, 'face bubble: zero on the other five faces')
    call suite%assert_close(e_der, 0.0_rp, 1.0e-9_rp, 'face bubble: derivatives = central differences')
    quad = reshape([0.0_rp, 0.0_rp, 0.0_rp, 2.0_rp, 0.0_rp, 0.5_rp, 2.5_rp, 1.0_rp, 0.5_rp, &
                    0.5_rp, 1.0_rp, 0.0_rp], [3, 4])
    v = norm2(quad_area_vector(quad, [0.0_rp, 0.0_rp])) * 4.0_rp
    call suite%assert_close(face_bubble_integral(quad), 4.0_rp / 9.0_rp * v, 1.0e-14_rp * v, &
                            'face bubble integral over a parallelogram = 4/9 area')
    ! trapezoid (0,0), (2,0), (1.5,1), (0.5,1): area density 1/4 (1.5 - 0.5 eta)
    ! in the reference square, so the integral is (4/3)(4/3)(1.5/4) = 2/3
    quad = reshape([0.0_rp, 0.0_rp, 0.0_rp, 2.0_rp, 0.0_rp, 0.0_rp, 1.5_rp, 1.0_rp, 0.0_rp, &
                    0.5_rp, 1.0_rp, 0.0_rp], [3, 4])
    call suite%assert_close(face_bubble_integral(quad), 2.0_rp / 3.0_rp, 1.0e-14_rp, &
                            'face bubble integral over a trapezoid = 2/3 (its bilinear area density)')
  end subroutine face_bubble_checks

  real(rp) function exact_moment(k)
    integer(ip), intent(in) :: k
    exact_moment = 0.0_rp
    if (mod(k, 2) == 0) exact_moment = 2.0_rp / real(k + 1, rp)
  end function exact_moment

  function identity() result(e)
    real(rp) :: e(3, 3)
    integer :: i
    e = 0.0_rp
    do i = 1, 3
      e(i, i) = 1.0_rp
    end do
  end function identity

  real(rp) function determinant(m)
    real(rp), intent(in) :: m(3, 3)
    determinant = m(1,1)*(m(2,2)*m(3,3)-m(2,3)*m(3,2)) - m(1,2)*(m(2,1)*m(3,3)-m(2,3)*m(3,1)) &
                + m(1,3)*(m(2,1)*m(3,2)-m(2,2)*m(3,1))
  end function determinant
end program test_q1
