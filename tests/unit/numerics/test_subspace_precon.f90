!> Unit tests of subspace_precon_t (a correction in a subspace with its own
!> operator L = Y^T A Z and an approximate inverse of L, before a
!> preconditioner M), on the 7-point Laplacian of an n^3 grid shifted so
!> that its lowest modes are nearly singular (A = L - s I, s = 0.999 of the
!> smallest eigenvalue of L): Jacobi alone stalls on the smooth modes.
!>
!>   - the subspace of every unknown with Z = Y = I, L = A by BoomerAMG,
!>     M = Jacobi: FGMRES needs far fewer iterations than with Jacobi alone,
!>     and finds the same solution;
!>   - Z = 2 I, Y = -I (other scalings of the same space) with L = Y^T A Z
!>     = -2 A: the same iteration count, as the correction Z L^-1 Y^T does
!>     not depend on the scalings;
!>   - the name says what wraps what.
!> Runs on 1 and 2 ranks.
program test_subspace_precon
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  use jacobi_precon, only: jacobi_precon_t
  use precon_factory, only: precon_params_t, make_and_setup
  use subspace_precon, only: subspace_precon_t
  use fgmres, only: fgmres_t
  use krylov, only: solve_info_t
  use dist_vector, only: pnorm2
  use fixture_matrices, only: build_laplacian
  use assertions, only: test_suite_t
  implicit none

  integer, parameter :: n = 16
  real(rp), parameter :: pi = acos(-1.0_rp)
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(index_map_t) :: row_map, col_map
  type(csr_matrix_t) :: a, l2
  type(jacobi_precon_t) :: jac
  type(subspace_precon_t) :: sub
  class(precon_t), allocatable :: amg, amg2
  type(precon_params_t) :: params
  type(error_status_t) :: status
  type(fgmres_t) :: gm
  type(solve_info_t) :: info
  integer(ip), allocatable :: ptr(:), idx(:)
  real(rp), allocatable :: zval(:), yval(:), b(:), x_exact(:), x(:)
  real(rp) :: lmin, err
  integer(gp) :: first
  integer(ip) :: i, k, nown
  integer :: its_jacobi, its_sub, its_scaled

  call comm%init_world()
  call suite%init('subspace_precon', comm)

  call build_laplacian(comm, n, 1, [1.0_rp], row_map, col_map, a)
  nown = a%n_owned()
  first = comm%exscan_g(int(nown, gp))
  lmin = 3.0_rp * (2.0_rp - 2.0_rp * cos(pi / (n + 1)))
  do i = 1, nown
    do k = a%row_ptr(i), a%row_ptr(i + 1) - 1
      if (a%col(k) == i) a%val(k) = a%val(k) - 0.999_rp * lmin
    end do
  end do
  call jac%setup(a, status)
  params%amg%num_functions = 1
  call make_and_setup('boomeramg', amg, a, params, status)
  call suite%assert_true(status%ok(), 'BoomerAMG of the shifted Laplacian')

  allocate(x_exact(nown), b(nown), x(nown))
  do i = 1, nown
    x_exact(i) = 1.0_rp + 0.3_rp * sin(0.7_rp * real(first + i, rp))
  end do
  call a%apply(x_exact, b)
  call gm%init(comm, rtol=1.0e-10_rp, atol=0.0_rp, max_iter=3000, restart=60)

  x = 0.0_rp
  call gm%solve(a, jac, b, x, info)
  its_jacobi = info%iterations
  call suite%assert_true(info%converged, 'fgmres + jacobi converges')

  call subspace(1.0_rp, 1.0_rp)
  call sub%setup(jac, a, amg, ptr, idx, zval, yval, nown)
  call suite%assert_true(trim(sub%name()) == 'subspace+jacobi', 'name: '//trim(sub%name()))
  x = 0.0_rp
  call gm%solve(a, sub, b, x, info)
  its_sub = info%iterations
  call suite%assert_true(info%converged, 'fgmres + subspace(AMG) + jacobi converges')
  err = pnorm2(comm, x - x_exact) / pnorm2(comm, x_exact)
  call suite%assert_true(err < 1.0e-6_rp, 'the same solution (error '//trim(num(err))//')')
  if (comm%rank == 0) write(*, '(a,i0,a,i0)') '  iterations: jacobi ', its_jacobi, ', subspace + jacobi ', its_sub
  call suite%assert_true(4 * its_sub < its_jacobi, 'the subspace correction removes the stall (below a quarter)')

  ! Z = 2 I, Y = -I: L = -2 A
  l2 = a
  nullify(l2%owned_col_map)
  l2%val = -2.0_rp * a%val
  call make_and_setup('boomeramg', amg2, l2, params, status)
  call subspace(2.0_rp, -1.0_rp)
  call sub%setup(jac, a, amg2, ptr, idx, zval, yval, nown)
  x = 0.0_rp
  call gm%solve(a, sub, b, x, info)
  its_scaled = info%iterations
  call suite%assert_true(info%converged .and. abs(its_scaled - its_sub) <= 1, &
    'scaled vectors, L scaled alike: the same count ('//trim(num(real(its_scaled, rp)))//')')
  call suite%finish()

contains

  !> Every owned unknown its own vector: Z = zs I, Y = ys I.
  subroutine subspace(zs, ys)
    real(rp), intent(in) :: zs, ys
    allocate(ptr(nown + 1), idx(nown), zval(nown), yval(nown))
    do i = 1, nown
      ptr(i) = i
      idx(i) = i
    end do
    ptr(nown + 1) = nown + 1
    zval = zs
    yval = ys
  end subroutine subspace

  function num(v) result(s)
    real(rp), intent(in) :: v
    character(len=16) :: s
    write(s, '(es10.3)') v
  end function num
end program test_subspace_precon
