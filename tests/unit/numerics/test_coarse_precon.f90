!> Unit tests of coarse_precon_t (a preconditioner with a least-squares
!> coarse correction), on the 7-point Laplacian of an n^3 grid shifted so
!> that its lowest mode is nearly singular (A = L - s I, s = 0.9999 of L's
!> smallest eigenvalue): the mode is known in closed form (a product of
!> sines), so it can be put into the coarse space exactly.
!>
!>   - a right-hand side in the range of A Z gives back Z c exactly;
!>   - FGMRES with Jacobi stalls on the near-null mode, with the coarse
!>     space it does not: fewer iterations, the same solution;
!>   - a zero column makes the coarse matrix singular: an error, no NaN.
!> Runs on 1 and 2 ranks (the coarse sums go over the ranks).
program test_coarse_precon
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use jacobi_precon, only: jacobi_precon_t
  use coarse_precon, only: coarse_precon_t
  use fgmres, only: fgmres_t
  use krylov, only: solve_info_t
  use dist_vector, only: pnorm2
  use fixture_matrices, only: build_laplacian
  use assertions, only: test_suite_t
  implicit none

  integer, parameter :: n = 14
  real(rp), parameter :: pi = acos(-1.0_rp)
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(index_map_t) :: row_map, col_map
  type(csr_matrix_t) :: a
  type(jacobi_precon_t) :: jac
  type(coarse_precon_t) :: cc
  type(error_status_t) :: status
  type(fgmres_t) :: gm
  type(solve_info_t) :: info
  real(rp), allocatable :: z(:,:), zc(:,:), w(:), r(:), y(:), b(:), x_exact(:), x1(:), x2(:)
  real(rp) :: lmin, err
  integer(gp) :: first
  integer(ip) :: i, k, nown
  integer :: its_jacobi, its_coarse

  call comm%init_world()
  call suite%init('coarse_precon', comm)

  call build_laplacian(comm, n, 1, [1.0_rp], row_map, col_map, a)
  nown = a%n_owned()
  first = comm%exscan_g(int(nown, gp))
  ! shift: the lowest eigenvalue of L is 3 (2 - 2 cos(pi / (n + 1)))
  lmin = 3.0_rp * (2.0_rp - 2.0_rp * cos(pi / (n + 1)))
  do i = 1, nown
    do k = a%row_ptr(i), a%row_ptr(i + 1) - 1
      if (a%col(k) == i) a%val(k) = a%val(k) - 0.9999_rp * lmin
    end do
  end do
  call jac%setup(a, status)

  ! the two lowest modes: sin(k1 pi x) sin(pi y) sin(pi z), k1 = 1, 2
  allocate(z(nown, 2), w(nown), r(nown), y(nown))
  do i = 1, nown
    z(i, 1) = mode(first + i, 1)
    z(i, 2) = mode(first + i, 2)
  end do
  zc = z
  w = 1.0_rp
  call cc%setup(jac, a, comm, zc, w, status)
  call suite%assert_true(status%ok(), 'set-up with two modes')

  ! 1. r = A Z c0 -> z = Z c0, up to the round-off of the normal equations:
  ! A's eigenvalues on the two modes are about 1.4e-5 and 0.13, so E has a
  ! condition number near 1e8 and the coefficients carry about 1e8 eps
  y = z(:, 1) - 0.5_rp * z(:, 2)
  call a%apply(y, r)
  call cc%apply(r, w)
  err = pnorm2(comm, w - y) / pnorm2(comm, y)
  call suite%assert_true(err < 1.0e-7_rp, 'a right-hand side in A Z gives Z c back (error '//trim(num(err))//')')

  ! 2. FGMRES: Jacobi alone against Jacobi with the coarse space
  allocate(x_exact(nown), b(nown), x1(nown), x2(nown))
  do i = 1, nown
    x_exact(i) = 1.0_rp + 0.3_rp * sin(0.7_rp * real(first + i, rp))
  end do
  call a%apply(x_exact, b)
  call gm%init(comm, rtol=1.0e-10_rp, atol=0.0_rp, max_iter=2000, restart=60)
  x1 = 0.0_rp
  call gm%solve(a, jac, b, x1, info)
  its_jacobi = info%iterations
  call suite%assert_true(info%converged, 'fgmres + jacobi converges')
  x2 = 0.0_rp
  call gm%solve(a, cc, b, x2, info)
  its_coarse = info%iterations
  call suite%assert_true(info%converged, 'fgmres + coarse(jacobi) converges')
  if (comm%rank == 0) write(*, '(a,i0,a,i0)') '  iterations: jacobi ', its_jacobi, ', coarse + jacobi ', its_coarse
  call suite%assert_true(its_coarse * 2 < its_jacobi, 'the coarse space removes the stall (fewer than half the iterations)')
  err = pnorm2(comm, x2 - x_exact) / pnorm2(comm, x_exact)
  call suite%assert_true(err < 1.0e-6_rp, 'the same solution (error '//trim(num(err))//')')

  ! 3. a zero column: singular coarse matrix, an error on every rank
  zc = z
  zc(:, 2) = 0.0_rp
  w = 1.0_rp
  call cc%setup(jac, a, comm, zc, w, status)
  call suite%assert_true(.not. status%ok() .and. index(status%msg, 'singular') > 0, &
                         'a zero column is reported: '//trim(status%msg))
  call suite%finish()

contains

  real(rp) function mode(g, k1)
    integer(gp), intent(in) :: g
    integer, intent(in) :: k1
    integer(gp) :: node
    integer :: ix, iy, iz
    node = g - 1
    ix = int(mod(node, int(n, gp)))
    iy = int(mod(node / n, int(n, gp)))
    iz = int(node / (int(n, gp) * n))
    mode = sin(k1 * pi * (ix + 1) / (n + 1)) * sin(pi * (iy + 1) / (n + 1)) * sin(pi * (iz + 1) / (n + 1))
  end function mode

  function num(x) result(s)
    real(rp), intent(in) :: x
    character(len=16) :: s
    write(s, '(es10.3)') x
  end function num
end program test_coarse_precon
