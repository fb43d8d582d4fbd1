!> Unit tests of the RT0 hexahedron (hex_rt0): unit fluxes of the reference
!> and Piola-mapped bases, divergence integrals, the mass matrix against its
!> analytic value on boxes (isotropic and anisotropic kinv, scaling with the
!> cell size), symmetry and positive definiteness on a distorted cell, frame
!> invariance, exact reproduction of constant fields on a parallelepiped, the
!> local-to-global orientation through the mesh's cell_face_sign, and the
!> report of an inverted cell.
!>
!> Analytic mass matrix of the box [0,Lx]x[0,Ly]x[0,Lz] (volume V) with
!> kinv = diag(a,b,c): the outward basis of the face x = Lx is
!> psi = (x/V, 0, 0) (normal component 1/(Ly Lz) there, so unit flux) and of the
!> face x = 0 it is psi = (-(Lx-x)/V, 0, 0). Hence
!>   m(2,2) = m(1,1) = a Ly Lz int_0^Lx x^2/V^2 dx     = a Lx^2/(3V),
!>   m(1,2)          = -a Ly Lz int_0^Lx x(Lx-x)/V^2 dx = -a Lx^2/(6V),
!> the same in y (faces 3,4; b Ly^2/V) and z (faces 5,6; c Lz^2/V), and 0
!> between different directions (orthogonal vectors). Unit cube, kinv = I:
!> three 2x2 blocks [1/3 -1/6; -1/6 1/3] (the minus sign is the outward
!> orientation: both basis functions of a pair point along -x and +x), with
!> eigenvalues 1/6 and 1/2 (three times each). A cube of side h: m = m_unit / h.
program test_rt0
  use kinds, only: rp, ip
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use assertions, only: test_suite_t
  use quadrature, only: gauss_quad
  use hex_q1, only: quad_shape, quad_area_vector
  use mesh, only: mesh_t, hex_face_nodes
  use hex_rt0, only: rt0_ref_values, rt0_values, rt0_cell_mass, rt0_cell_divergence, rt0_orient
  implicit none

  interface
    subroutine dpotrf(uplo, n, a, lda, info)
      import :: rp
      character, intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(rp), intent(inout) :: a(lda, *)
      integer, intent(out) :: info
    end subroutine dpotrf
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: rp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(rp), intent(inout) :: a(lda, *)
      real(rp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
  end interface

  real(rp), parameter :: s(3, 8) = reshape([ &
    -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1, &
    -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1], [3, 8])

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  real(rp) :: xd(3, 8), xa(3, 8), xu(3, 8), xb(3, 8), a(3, 3), rot(3, 3), kfull(3, 3)
  real(rp) :: m(6, 6), m2(6, 6), mref(6, 6), eig(6), d(6), flux(6, 6), v(3, 6), divv(6), det
  real(rp) :: work(64), x2(2, 4), w2(4), xi(3), errmax, detmin, h, lbox(3), kd(3), vol, v0(3), c(6), area(3, 6)
  integer(ip) :: j, k, q, dir
  integer :: info

  call comm%init_world()
  call suite%init('rt0', comm)
  call gauss_quad(2_ip, x2, w2)

  ! a distorted, non-affine cell with non-planar faces (corners moved by up
  ! to 15 % of the side) and an affine parallelepiped x = A xi + b
  do k = 1, 8
    xd(:, k) = s(:, k) * [1.0_rp, 0.8_rp, 1.2_rp] + 0.3_rp * [sin(1.7_rp * k), cos(2.3_rp * k), sin(0.9_rp * k + 0.4_rp)]
  end do
  a = reshape([1.5_rp, 0.3_rp, -0.2_rp, 0.4_rp, 0.9_rp, 0.1_rp, -0.3_rp, 0.2_rp, 1.2_rp], [3, 3])
  do k = 1, 8
    xa(:, k) = matmul(a, s(:, k)) + [3.0_rp, -1.0_rp, 2.0_rp]
  end do
  xu = 0.5_rp * (s + 1.0_rp)                                ! unit cube [0,1]^3
  kfull = reshape([2.0_rp, 0.3_rp, 0.1_rp, 0.3_rp, 1.0_rp, -0.2_rp, 0.1_rp, -0.2_rp, 0.5_rp], [3, 3])

  ! (1) reference basis: outward flux of psi_hat_i through the reference face j
  ! (normal +-e_d, param Jacobian 1 on [-1,1]^2) is delta_ij
  do j = 1, 6
    dir = (j + 1) / 2
    flux(:, j) = 0.0_rp
    do q = 1, 4
      xi = 0.0_rp
      xi(dir) = merge(1.0_rp, -1.0_rp, mod(j, 2) == 0)
      xi(pack([1, 2, 3], [1, 2, 3] /= dir)) = x2(:, q)
      call rt0_ref_values(xi, v, divv)
      flux(:, j) = flux(:, j) + w2(q) * xi(dir) * v(dir, :)
    end do
  end do
  call suite%assert_close(maxval(abs(flux - identity6())), 0.0_rp, 1.0e-15_rp, &
                          'reference basis: flux of psi_hat_i through face j = delta_ij')
  call rt0_ref_values([0.3_rp, -0.7_rp, 0.1_rp], v, divv)
  call suite%assert_close(maxval(abs(divv - 0.125_rp)), 0.0_rp, 1.0e-15_rp, 'reference divergences = 1/8')

  ! (2) the same after the Piola map, with the physical face area vectors
  call physical_fluxes(xd, flux, detmin)
  call suite%assert_true(detmin > 0.1_rp, 'distorted cell has det J > 0 on its faces')
  call suite%assert_close(maxval(abs(flux - identity6())), 0.0_rp, 1.0e-13_rp, &
                          'distorted cell: flux of psi_i through local face j = delta_ij')
  call physical_fluxes(xa, flux, detmin)
  call suite%assert_close(maxval(abs(flux - identity6())), 0.0_rp, 1.0e-13_rp, &
                          'parallelepiped: flux of psi_i through local face j = delta_ij')

  ! (3) divergence integrals; pointwise div psi det J = 1/8
  call rt0_cell_divergence(xd, d)
  call suite%assert_close(maxval(abs(d - 1.0_rp)), 0.0_rp, 1.0e-13_rp, 'distorted cell: int div psi_i = 1')
  call rt0_cell_divergence(xa, d)
  call suite%assert_close(maxval(abs(d - 1.0_rp)), 0.0_rp, 1.0e-13_rp, 'parallelepiped: int div psi_i = 1')
  call rt0_values(xd, [0.6_rp, -0.2_rp, -0.9_rp], v, divv, det)
  call suite%assert_close(maxval(abs(divv * det - 0.125_rp)), 0.0_rp, 1.0e-14_rp, 'div psi = (1/8) / det J')

  ! (4) unit cube, kinv = I: analytic matrix, eigenvalues 1/6 and 1/2, SPD
  call rt0_cell_mass(xu, identity3(), m)
  mref = box_mass([1.0_rp, 1.0_rp, 1.0_rp], [1.0_rp, 1.0_rp, 1.0_rp])
  call suite%assert_close(maxval(abs(m - mref)), 0.0_rp, 1.0e-14_rp, 'unit cube mass matrix = analytic (1/3, -1/6, 0)')
  m2 = m
  call dsyev('N', 'U', 6, m2, 6, eig, work, 64, info)
  call suite%assert_equal_int(info, 0, 'dsyev on the unit-cube mass matrix')
  call suite%assert_close_array(eig, [1, 1, 1, 3, 3, 3] / 6.0_rp, 1.0e-14_rp, 'unit cube eigenvalues 1/6 (x3), 1/2 (x3)')
  call rt0_cell_mass(xd, kfull, m)
  call suite%assert_close(maxval(abs(m - transpose(m))), 0.0_rp, 0.0_rp, 'distorted cell, full kinv: m symmetric')
  m2 = m
  call dpotrf('U', 6, m2, 6, info)
  call suite%assert_equal_int(info, 0, 'distorted cell, full kinv: m positive definite (dpotrf)')
  m2 = m
  call dsyev('N', 'U', 6, m2, 6, eig, work, 64, info)
  call suite%assert_true(info == 0 .and. eig(1) > 1.0e-3_rp * eig(6), 'distorted cell: smallest eigenvalue well away from 0')

  ! (5) cubes of side h, shifted: m = m_unit / h
  do k = 1, 2
    h = merge(1.0e-2_rp, 50.0_rp, k == 1)
    call rt0_cell_mass(h * (xu + spread([-7.0_rp, 3.0_rp, 11.0_rp], 2, 8)), identity3(), m)
    call suite%assert_close(maxval(abs(m * h - mref)), 0.0_rp, 1.0e-13_rp, 'cube of side h: m h = m_unit')
  end do

  ! (6) box [0,2]x[0,0.5]x[0,3] with kinv = diag(a,b,c): per-direction blocks
  ! k_d L_d^2 / V [1/3 -1/6; -1/6 1/3]
  lbox = [2.0_rp, 0.5_rp, 3.0_rp]
  kd = [1.0e3_rp, 2.0_rp, 0.1_rp]
  do k = 1, 8
    xb(:, k) = lbox * xu(:, k)
  end do
  call rt0_cell_mass(xb, diag3(kd), m)
  mref = box_mass(lbox, kd)
  call suite%assert_close(maxval(abs(m - mref)) / maxval(abs(mref)), 0.0_rp, 1.0e-14_rp, &
                          'box with kinv = diag(a,b,c): analytic blocks')
  call suite%assert_close(m(1, 1) / m(3, 3) / ((kd(1) * lbox(1)**2) / (kd(2) * lbox(2)**2)), 1.0_rp, 1.0e-14_rp, &
                          'box: (m_11 / m_33) / ((a Lx^2) / (b Ly^2)) = 1')

  ! frame invariance: rotating the cell and kinv (R K R^T) leaves m unchanged
  rot = rotation([1.0_rp, 2.0_rp, -0.5_rp], 0.7_rp)
  call rt0_cell_mass(xd, kfull, m)
  call rt0_cell_mass(matmul(rot, xd), matmul(rot, matmul(kfull, transpose(rot))), m2)
  call suite%assert_close(maxval(abs(m - m2)) / maxval(abs(m)), 0.0_rp, 1.0e-13_rp, &
                          'distorted cell: m invariant under a rotation of cell and kinv')

  ! (7) constant field on the parallelepiped: the interpolant reproduces it,
  ! and its energy c^T m c is V v0 . kinv v0
  v0 = [0.7_rp, -1.3_rp, 2.1_rp]
  do j = 1, 6
    area(:, j) = 0.0_rp
    do q = 1, 4
      area(:, j) = area(:, j) + w2(q) * quad_area_vector(xa(:, hex_face_nodes(:, j)), x2(:, q))
    end do
    c(j) = dot_product(v0, area(:, j))
  end do
  errmax = 0.0_rp
  do k = 1, 10
    xi = [sin(1.1_rp * k), cos(0.7_rp * k), sin(2.9_rp * k + 1.0_rp)]
    call rt0_values(xa, xi, v, divv, det)
    errmax = max(errmax, maxval(abs(matmul(v, c) - v0)), abs(dot_product(divv, c)))
  end do
  call suite%assert_close(errmax, 0.0_rp, 1.0e-13_rp, 'parallelepiped: sum_f (v0 . A_f) psi_f = v0, divergence 0')
  call rt0_cell_mass(xa, kfull, m)
  vol = determinant(a) * 8.0_rp
  call suite%assert_close(dot_product(c, matmul(m, c)) / (vol * dot_product(v0, matmul(kfull, v0))), 1.0_rp, &
                          1.0e-13_rp, 'parallelepiped, full kinv: c^T m c = V v0 . kinv v0')

  call test_orientation()
  call test_inverted()

  call suite%finish()

contains

  !> (8) Two distorted cells sharing a non-planar face, faces from mesh_t:
  !> the global basis cell_face_sign * local basis has the same normal
  !> component from both sides and unit flux along the global face normal;
  !> rt0_orient gives +1/-1 divergence entries for the shared face.
  subroutine test_orientation()
    type(mesh_t) :: g
    type(error_status_t) :: st
    integer(ip) :: f, lfc(2), cc, lf, nd, sgn(6)
    real(rp) :: xc(3, 8, 2), fl(2), dn(2, 4), nq(4), xiq(3), vv(3, 6), dd(6), dsum, jump, da(3)
    real(rp) :: mm(6, 6), mo(6, 6)
    g%n_nodes = 12
    g%n_cells = 2
    allocate(g%coords(3, 12), g%cell_nodes(8, 2), g%cell_region(2))
    allocate(g%sface_nodes(4, 0), g%sface_set(0))
    g%cell_region = 1
    do k = 1, 12
      ! nodes on the planes x = 0, 1, 2 (4 each), then perturbed
      g%coords(:, k) = [real((k - 1) / 4, rp), merge(1.0_rp, 0.0_rp, any(mod(k - 1, 4) == [1, 2])), &
                        merge(1.0_rp, 0.0_rp, mod(k - 1, 4) >= 2)] &
                       + 0.12_rp * [sin(1.3_rp * k), cos(1.9_rp * k), sin(0.8_rp * k + 0.2_rp)]
    end do
    ! plane i nodes: 4i+1 (y0,z0), 4i+2 (y1,z0), 4i+3 (y1,z1), 4i+4 (y0,z1)
    g%cell_nodes(:, 1) = [1, 5, 6, 2, 4, 8, 7, 3]
    g%cell_nodes(:, 2) = [5, 9, 10, 6, 8, 12, 11, 7]
    call g%build_faces(st)
    call suite%assert_true(st%ok() .and. g%n_faces == 11, 'two-cell mesh: 11 faces')
    ! the shared face: local face 2 of cell 1, local face 1 of cell 2
    f = g%cell_faces(2, 1)
    call suite%assert_true(g%cell_faces(1, 2) == f .and. g%cell_face_sign(2, 1) * g%cell_face_sign(1, 2) == -1, &
                           'shared face: opposite signs in the two cells')
    lfc = [2, 1]
    fl = 0.0_rp
    jump = 0.0_rp
    do q = 1, 4
      da = quad_area_vector(g%coords(:, g%face_nodes(:, f)), x2(:, q))
      dsum = 0.0_rp
      do cc = 1, 2
        xc(:, :, cc) = g%coords(:, g%cell_nodes(:, cc))
        ! reference point of the face point in cell cc, from the global face nodes
        call quad_shape(x2(:, q), nq, dn)
        xiq = 0.0_rp
        do k = 1, 4
          nd = findloc(g%cell_nodes(:, cc), g%face_nodes(k, f), dim=1)
          xiq = xiq + nq(k) * s(:, nd)
        end do
        call rt0_values(xc(:, :, cc), xiq, vv, dd, det)
        lf = lfc(cc)
        vv(:, lf) = g%cell_face_sign(lf, cc) * vv(:, lf)
        fl(cc) = fl(cc) + w2(q) * dot_product(vv(:, lf), da)
        dsum = dsum + merge(1.0_rp, -1.0_rp, cc == 1) * dot_product(vv(:, lf), da)
      end do
      jump = max(jump, abs(dsum))
    end do
    call suite%assert_close(jump, 0.0_rp, 1.0e-13_rp, 'global basis: normal component continuous across the face')
    call suite%assert_close_array(fl, [1.0_rp, 1.0_rp], 1.0e-13_rp, 'global basis: unit flux along the global normal')
    ! divergence rows of both cells: the shared face's column sums to 0,
    ! every boundary face enters with +1 (its normal points out of its cell)
    dsum = 0.0_rp
    jump = 0.0_rp
    do cc = 1, 2
      sgn = g%cell_face_sign(:, cc)
      call rt0_cell_divergence(xc(:, :, cc), dd)
      call rt0_orient(sgn, dd)
      do lf = 1, 6
        if (g%cell_faces(lf, cc) == f) then
          dsum = dsum + dd(lf)
        else
          jump = max(jump, abs(dd(lf) - 1.0_rp))
        end if
      end do
    end do
    call suite%assert_close(dsum, 0.0_rp, 1.0e-13_rp, 'oriented divergence: shared face +1 and -1')
    call suite%assert_close(jump, 0.0_rp, 1.0e-13_rp, 'oriented divergence: boundary faces +1')
    ! oriented mass matrix of cell 2 (sign -1 on local face 1)
    sgn = g%cell_face_sign(:, 2)
    call rt0_cell_mass(xc(:, :, 2), kfull, mm)
    mo = mm
    call rt0_orient(sgn, mo)
    call suite%assert_true(all(sgn == [-1, 1, 1, 1, 1, 1]) .and. all(mo(1, 2:) == -mm(1, 2:)) .and. &
                           all(mo(2:, 1) == -mm(2:, 1)) .and. mo(1, 1) == mm(1, 1) .and. &
                           all(mo(2:, 2:) == mm(2:, 2:)), 'oriented mass matrix: s_i s_j m_ij')
    call g%free()
  end subroutine test_orientation

  !> (9) An inverted cell is reported, not silently integrated.
  subroutine test_inverted()
    type(error_status_t) :: st
    real(rp) :: xinv(3, 8), mm(6, 6), dd(6)
    xinv = xu
    xinv(3, :) = -xinv(3, :)                 ! mirror: det J < 0 everywhere
    call rt0_values(xinv, [0.0_rp, 0.0_rp, 0.0_rp], v, divv, det)
    call suite%assert_true(det < 0.0_rp .and. all(v == 0.0_rp) .and. all(divv == 0.0_rp), &
                           'inverted cell: det < 0, values zero')
    call rt0_cell_mass(xinv, identity3(), mm, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'non-positive Jacobian') > 0, &
                           'inverted cell: rt0_cell_mass reports it')
    call st%clear()
    call rt0_cell_divergence(xinv, dd, st)
    call suite%assert_true(.not. st%ok(), 'inverted cell: rt0_cell_divergence reports it')
  end subroutine test_inverted

  !> Outward fluxes flx(i,j) of the physical basis i through local face j
  !> (2x2 Gauss on the bilinear face, area vectors from hex_face_nodes),
  !> and the smallest det J met on the faces.
  subroutine physical_fluxes(x, flx, dmin)
    real(rp), intent(in) :: x(3, 8)
    real(rp), intent(out) :: flx(6, 6), dmin
    real(rp) :: nq(4), dn(2, 4), xiq(3), vv(3, 6), dd(6), dt
    integer(ip) :: jf, qq, kk
    flx = 0.0_rp
    dmin = huge(1.0_rp)
    do jf = 1, 6
      do qq = 1, 4
        call quad_shape(x2(:, qq), nq, dn)
        xiq = 0.0_rp
        do kk = 1, 4
          xiq = xiq + nq(kk) * s(:, hex_face_nodes(kk, jf))
        end do
        call rt0_values(x, xiq, vv, dd, dt)
        dmin = min(dmin, dt)
        flx(:, jf) = flx(:, jf) + w2(qq) * matmul(quad_area_vector(x(:, hex_face_nodes(:, jf)), x2(:, qq)), vv)
      end do
    end do
  end subroutine physical_fluxes

  !> Analytic mass matrix of a box with sides l(3) and kinv = diag(kk).
  function box_mass(l, kk) result(mb)
    real(rp), intent(in) :: l(3), kk(3)
    real(rp) :: mb(6, 6), t
    integer :: dd
    mb = 0.0_rp
    do dd = 1, 3
      t = kk(dd) * l(dd)**2 / product(l)
      mb(2*dd-1:2*dd, 2*dd-1:2*dd) = t * reshape([1.0_rp/3, -1.0_rp/6, -1.0_rp/6, 1.0_rp/3], [2, 2])
    end do
  end function box_mass

  function identity3() result(e)
    real(rp) :: e(3, 3)
    e = diag3([1.0_rp, 1.0_rp, 1.0_rp])
  end function identity3

  function diag3(dg) result(e)
    real(rp), intent(in) :: dg(3)
    real(rp) :: e(3, 3)
    integer :: ii
    e = 0.0_rp
    do ii = 1, 3
      e(ii, ii) = dg(ii)
    end do
  end function diag3

  function identity6() result(e)
    real(rp) :: e(6, 6)
    integer :: ii
    e = 0.0_rp
    do ii = 1, 6
      e(ii, ii) = 1.0_rp
    end do
  end function identity6

  !> Rotation by angle t [rad] about the axis ax (Rodrigues).
  function rotation(ax, t) result(r)
    real(rp), intent(in) :: ax(3), t
    real(rp) :: r(3, 3), u(3), kx(3, 3)
    u = ax / norm2(ax)
    kx = reshape([0.0_rp, u(3), -u(2), -u(3), 0.0_rp, u(1), u(2), -u(1), 0.0_rp], [3, 3])
    r = identity3() + sin(t) * kx + (1.0_rp - cos(t)) * matmul(kx, kx)
  end function rotation

  real(rp) function determinant(mt)
    real(rp), intent(in) :: mt(3, 3)
    determinant = mt(1,1)*(mt(2,2)*mt(3,3)-mt(2,3)*mt(3,2)) - mt(1,2)*(mt(2,1)*mt(3,3)-mt(2,3)*mt(3,1)) &
                + mt(1,3)*(mt(2,1)*mt(3,2)-mt(2,2)*mt(3,1))
  end function determinant
end program test_rt0
