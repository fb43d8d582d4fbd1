!> Unit tests of hypre's FSAI as a preconditioner (hypre_fsai_precon).
!> Runs on 1 or more ranks.
!>
!> The matrix is the 3D 7-point Laplacian on an n^3 grid of interior nodes
!> (Dirichlet boundary eliminated), nodes split into contiguous ranges by
!> rank. Checks: bad arguments are refused by name, a failure inside hypre
!> is reported with the call's name; max_steps = 0 gives
!> G = D^-1/2, i.e. Jacobi; the application is linear, symmetric, positive
!> and free of state; PCG with hypre's FSAI converges to 1e-8 in fewer
!> iterations than with Jacobi, and in fewer with 5 pattern steps than
!> with 1; free() and a new setup() reproduce the operator.
!>
!> Optional argument: a grid size N; then the iterations and the set-up,
!> application and solve times are also reported for the N^3 Laplacian
!> (no assertion on them).
program test_hypre_fsai
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use index_map, only: index_map_t, sort_gids
  use csr_matrix, only: csr_matrix_t
  use dist_vector, only: pdot, pnorm2
  use precon, only: precon_t
  use jacobi_precon, only: jacobi_precon_t
  use hypre_fsai_precon, only: hypre_fsai_precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  use assertions, only: test_suite_t
  use fixture_matrices, only: build_laplacian
  implicit none

  integer, parameter :: n_test = 12
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  integer :: n_large

  call comm%init_world()
  call suite%init('hypre_fsai', comm)
  call read_size_argument(n_large)
  call test_arguments(suite, comm)
  call test_operator(suite, comm)
  call test_cg(suite, comm)
  if (n_large > 0) call report_timings(comm, n_large)
  call suite%finish()

contains

  !> Bad max_steps, step_size, kap_tol are refused by name; a failure
  !> inside hypre (an indefinite matrix) names the hypre call. The object
  !> stays unusable and releasable.
  subroutine test_arguments(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map, row_map2, col_map2
    type(csr_matrix_t) :: a
    type(hypre_fsai_precon_t) :: m
    type(error_status_t) :: st
    integer(ip) :: i, k

    call build_laplacian(comm, 4, 1, [1.0_rp], row_map, col_map, a)
    call m%setup(a, -1, 5, 1.0e-3_rp, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'max_steps = -1') > 0, &
                           'arguments: max_steps < 0 is refused by name: '//trim(st%msg))
    call st%clear()
    call m%setup(a, 3, -2, 1.0e-3_rp, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'step_size = -2') > 0, &
                           'arguments: step_size < 0 is refused by name: '//trim(st%msg))
    call st%clear()
    call m%setup(a, 3, 5, -1.0_rp, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'kap_tol') > 0, &
                           'arguments: kap_tol < 0 is refused by name: '//trim(st%msg))
    call suite%assert_true(.not. m%ready .and. .not. m%ij%is_ready(), &
                           'arguments: nothing is built after a refused set-up')

    ! diagonal 1, neighbours -1: indefinite, so the Cholesky factorization
    ! of some local system A[P,P] inside hypre's set-up fails
    call a%free()
    call build_laplacian(comm, 6, 1, [1.0_rp], row_map2, col_map2, a)
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i + 1) - 1
        if (a%col(k) == i) a%val(k) = 1.0_rp
      end do
    end do
    call st%clear()
    call m%setup(a, 3, 5, 1.0e-3_rp, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'HYPRE_FSAISetup') > 0 .and. &
                           .not. m%ready .and. .not. m%ij%is_ready(), &
                           'arguments: a hypre failure names the call and builds nothing: '//trim(st%msg))
    call m%free()
    call a%free()
  end subroutine test_arguments

  !> The operator z = G^T G r on the n_test^3 Laplacian.
  subroutine test_operator(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    type(hypre_fsai_precon_t) :: m
    type(jacobi_precon_t) :: jac
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:), mx(:), my(:), mc(:), mx2(:), zj(:)
    real(rp) :: lhs, rhs, scale, err
    integer(gp) :: n_glob

    call build_laplacian(comm, n_test, 1, [1.0_rp], row_map, col_map, a)
    n_glob = int(n_test, gp)**3
    allocate(x(a%n_rows), y(a%n_rows), mx(a%n_rows), my(a%n_rows), mc(a%n_rows), mx2(a%n_rows), &
             zj(a%n_rows))
    call random_vector(a, 1, x)
    call random_vector(a, 2, y)

    ! max_steps = 0: G = diag(A)^-1/2, so G^T G = the Jacobi preconditioner
    ! (this also shows omega = 1, one step, zero guess)
    call m%setup(a, 0, 5, 1.0e-3_rp, st)
    call suite%assert_true(st%ok(), 'operator: set-up with max_steps = 0 succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call jac%setup(a, st)
    call m%apply(x, mx)
    call jac%apply(x, zj)
    err = 0.0_rp
    scale = 0.0_rp
    if (a%n_rows > 0) then
      err = maxval(abs(mx - zj))
      scale = maxval(abs(zj))
    end if
    err = comm%max(err)
    scale = comm%max(scale)
    call suite%assert_true(err <= 1.0e-14_rp * scale, 'operator: max_steps = 0 gives Jacobi')
    call jac%free()

    call m%setup(a, 3, 5, 1.0e-3_rp, st)
    call suite%assert_true(st%ok(), 'operator: set-up with hypre''s defaults (3, 5, 1e-3) succeeds: '// &
                           trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_true(m%name() == 'hypre_fsai', 'operator: name is hypre_fsai')
    call suite%assert_true(m%setup_time > 0.0_rp .and. m%factor_time > 0.0_rp .and. &
                           m%factor_time <= m%setup_time, 'operator: set-up is timed (hypre''s part inside)')
    call suite%assert_true(m%nnz_g == -1_gp .and. m%nnz_g_max == 16_gp * n_glob .and. &
                           m%n_global == n_glob, 'operator: nnz(G) unknown (-1), bound n*(3*5+1)')

    call m%apply(x, mx)
    call m%apply(y, my)
    ! symmetry: (y, M x) = (x, M y)
    lhs = pdot(comm, y, mx)
    rhs = pdot(comm, x, my)
    scale = pnorm2(comm, y) * pnorm2(comm, mx)
    if (comm%rank == 0) write(*, '(a,es10.3)') '  |(y,Mx) - (x,My)| / (|y| |Mx|) = ', abs(lhs - rhs) / scale
    call suite%assert_true(abs(lhs - rhs) <= 1.0e-12_rp * scale, 'operator: (y, M x) = (x, M y)')
    ! positive: (x, M x) = |G x|^2 > 0
    call suite%assert_true(pdot(comm, x, mx) > 0.0_rp, 'operator: (x, M x) > 0')
    ! linear: M (2x - 3y) = 2 M x - 3 M y
    call m%apply(2.0_rp * x - 3.0_rp * y, mc)
    err = pnorm2(comm, mc - (2.0_rp * mx - 3.0_rp * my))
    scale = pnorm2(comm, mc)
    call suite%assert_true(err <= 1.0e-12_rp * scale, 'operator: M (2x - 3y) = 2 M x - 3 M y')
    ! no state: the same input gives the same output after other applications
    call m%apply(x, mx2)
    call suite%assert_true(all(mx2 == mx), 'operator: repeated application is identical')
    ! not trivially Jacobi any more
    call jac%setup(a, st)
    call jac%apply(x, zj)
    call suite%assert_true(pnorm2(comm, mx - zj) > 1.0e-3_rp * pnorm2(comm, zj), &
                           'operator: with 3 steps it differs from Jacobi')
    call jac%free()
    call suite%assert_equal_int(m%apply_errors, 0, 'operator: no hypre error while applying')

    ! free, then a new set-up of the same object rebuilds the same operator
    call m%free()
    call suite%assert_true(.not. m%ready .and. .not. m%ij%is_ready() .and. m%nnz_g_max == -1_gp, &
                           'operator: free releases the hypre objects')
    call m%setup(a, 3, 5, 1.0e-3_rp, st)
    call m%apply(x, mx2)
    call suite%assert_true(st%ok() .and. all(mx2 == mx), 'operator: a new set-up reproduces M exactly')
    call m%free()
    call a%free()
  end subroutine test_operator

  !> PCG to 1e-8 on the n_test^3 Laplacian: hypre's FSAI needs fewer
  !> iterations than Jacobi, and 5 pattern steps fewer than 1.
  subroutine test_cg(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    type(hypre_fsai_precon_t) :: m
    type(jacobi_precon_t) :: jac
    type(error_status_t) :: st
    real(rp), allocatable :: b(:)
    type(solve_info_t) :: info_j, info_f, info_1, info_5
    character(len=16) :: tag

    call build_laplacian(comm, n_test, 1, [1.0_rp], row_map, col_map, a)
    allocate(b(a%n_rows))
    call make_rhs(a, b)
    write(tag, '(i0,a,i0)') comm%size, ' rank(s)'
    if (comm%rank == 0) write(*, '(a,i0,a,a)') '  PCG to 1e-8, ', n_test, '^3 Laplacian, ', trim(tag)

    call jac%setup(a, st)
    call run_cg(comm, a, jac, b, info_j)
    call print_line(comm, 'jacobi', jac, info_j, a%n_rows)
    call suite%assert_true(info_j%converged, 'cg: converges with Jacobi')

    call m%setup(a, 3, 5, 1.0e-3_rp, st)
    call suite%assert_true(st%ok(), 'cg: set-up (3, 5, 1e-3) succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call run_cg(comm, a, m, b, info_f)
    call print_line(comm, 'hypre_fsai 3x5', m, info_f, a%n_rows)
    call suite%assert_true(info_f%converged .and. info_f%rel_res <= 1.0e-8_rp, &
                           'cg: converges to 1e-8 with hypre FSAI')
    call suite%assert_true(info_f%iterations < info_j%iterations, &
                           'cg: hypre FSAI needs fewer iterations than Jacobi')

    call m%setup(a, 1, 3, 1.0e-3_rp, st)
    call run_cg(comm, a, m, b, info_1)
    call print_line(comm, 'hypre_fsai 1x3', m, info_1, a%n_rows)
    call m%setup(a, 5, 3, 1.0e-3_rp, st)
    call run_cg(comm, a, m, b, info_5)
    call print_line(comm, 'hypre_fsai 5x3', m, info_5, a%n_rows)
    call suite%assert_true(st%ok() .and. info_1%converged .and. info_5%converged, &
                           'cg: converges with max_steps 1 and 5')
    call suite%assert_true(info_5%iterations < info_1%iterations, &
                           'cg: max_steps 5 needs fewer iterations than max_steps 1')
    call suite%assert_equal_int(m%apply_errors, 0, 'cg: no hypre error while applying')
    call m%free()
    call jac%free()
    call a%free()
  end subroutine test_cg

  !> Iterations and times of PCG with Jacobi and with hypre's FSAI at a few
  !> settings on the n^3 Laplacian (report only).
  subroutine report_timings(comm, n)
    type(parallel_comm_t), intent(in) :: comm
    integer, intent(in) :: n
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    type(hypre_fsai_precon_t) :: m
    type(jacobi_precon_t) :: jac
    type(error_status_t) :: st
    type(solve_info_t) :: info
    real(rp), allocatable :: b(:)
    integer, parameter :: n_set = 5
    integer, parameter :: steps(n_set) = [1, 3, 5, 5, 10], sizes(n_set) = [3, 5, 3, 5, 5]
    character(len=32) :: label
    integer :: k

    call build_laplacian(comm, n, 1, [1.0_rp], row_map, col_map, a)
    allocate(b(a%n_rows))
    call make_rhs(a, b)
    if (comm%rank == 0) write(*, '(a,i0,a,i0,a,i0,a)') '  PCG to 1e-8, ', n, '^3 Laplacian (', &
      int(n, gp)**3, ' unknowns), ', comm%size, ' rank(s)'
    call jac%setup(a, st)
    call run_cg(comm, a, jac, b, info)
    call print_line(comm, 'jacobi', jac, info, a%n_rows)
    call jac%free()
    call report_overheads(comm, a)
    do k = 1, n_set
      call m%setup(a, steps(k), sizes(k), 1.0e-3_rp, st)
      if (.not. st%ok()) then
        if (comm%rank == 0) write(*, '(a)') '  '//trim(st%msg)
        cycle
      end if
      call run_cg(comm, a, m, b, info)
      write(label, '(a,i0,a,i0)') 'hypre_fsai ', steps(k), 'x', sizes(k)
      call print_line(comm, label, m, info, a%n_rows)
    end do
    call m%free()
    call a%free()
  end subroutine report_timings

  !> Reference times for the report: one product with A (csr_matrix), and
  !> the copy of a vector into hypre and back that every application of
  !> hypre's FSAI pays (mean of 20, slowest rank).
  subroutine report_overheads(comm, a)
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    type(hypre_fsai_precon_t) :: m
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:)
    real(rp) :: t0, t_matvec, t_copy
    integer :: k

    allocate(x(a%n_rows), y(a%n_rows))
    x = 1.0_rp
    call comm%barrier()
    t0 = wall_time()
    do k = 1, 20
      call a%apply(x, y)
    end do
    t_matvec = comm%max((wall_time() - t0) / 20.0_rp)
    call m%setup(a, 0, 0, 0.0_rp, st)
    call comm%barrier()
    t0 = wall_time()
    do k = 1, 20
      call m%ij%set_rhs(x)
      call m%ij%zero_x()
      call m%ij%get_x(y)
    end do
    t_copy = comm%max((wall_time() - t0) / 20.0_rp)
    call m%free()
    if (comm%rank == 0) write(*, '(4x,a,es9.2,a,es9.2)') 'A x [s] ', t_matvec, &
      '   vector into hypre and back, per application [s] ', t_copy
  end subroutine report_overheads

  ! ---- helpers ---------------------------------------------------------------

  !> PCG from x = 0 to 1e-8, at most 5000 iterations.
  subroutine run_cg(comm, a, m, b, info)
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    class(precon_t), intent(inout) :: m
    real(rp), intent(in) :: b(:)
    type(solve_info_t), intent(out) :: info
    type(cg_t) :: solver
    real(rp), allocatable :: x(:)
    allocate(x(size(b)))
    x = 0.0_rp
    call solver%init(comm, rtol=1.0e-8_rp, max_iter=5000)
    call solver%solve(a, m, b, x, info)
  end subroutine run_cg

  !> One line of the report: iterations, set-up time, time of one
  !> application (mean of 20, slowest rank), solve time; n: owned rows.
  subroutine print_line(comm, label, m, info, n)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: label
    integer(ip), intent(in) :: n
    class(precon_t), intent(inout) :: m
    type(solve_info_t), intent(in) :: info
    real(rp), allocatable :: r(:), z(:)
    real(rp) :: t0, t_apply, t_setup, t_solve
    integer :: k
    character(len=18) :: lab
    allocate(r(n), z(n))
    r = 1.0_rp
    call comm%barrier()
    t0 = wall_time()
    do k = 1, 20
      call m%apply(r, z)
    end do
    t_apply = comm%max((wall_time() - t0) / 20.0_rp)
    t_setup = comm%max(m%setup_time)
    t_solve = comm%max(info%solve_time)
    lab = label
    if (comm%rank == 0) write(*, '(4x,a,a,i5,a,es9.2,a,es9.2,a,es9.2,a,es9.2)') lab, &
      ' iterations ', info%iterations, '  rel.res ', info%rel_res, '  setup [s] ', t_setup, &
      '  apply [s] ', t_apply, '  solve [s] ', t_solve
  end subroutine print_line

  !> b = A x with x a pseudo-random vector (the same on any number of ranks).
  subroutine make_rhs(a, b)
    type(csr_matrix_t), intent(inout) :: a
    real(rp), intent(out) :: b(:)
    real(rp), allocatable :: x(:)
    allocate(x(size(b)))
    call random_vector(a, 3, x)
    call a%apply(x, b)
  end subroutine make_rhs

  !> Entries in [-0.5, 0.5) from a hash of the global row id and seed: the
  !> same vector on any number of ranks.
  subroutine random_vector(a, seed, x)
    type(csr_matrix_t), intent(in) :: a
    integer, intent(in) :: seed
    real(rp), intent(out) :: x(:)
    integer(ip) :: i
    real(rp) :: g, s
    do i = 1, a%n_rows
      g = real(a%row_map%first + i - 1, rp)
      s = sin(12.9898_rp * g + 78.233_rp * real(seed, rp)) * 43758.5453_rp
      x(i) = s - floor(s) - 0.5_rp
    end do
  end subroutine random_vector

  !> The grid size from the first command-line argument, or 0 without one.
  subroutine read_size_argument(n)
    integer, intent(out) :: n
    character(len=32) :: arg
    integer :: ios
    n = 0
    if (command_argument_count() < 1) return
    call get_command_argument(1, arg)
    read(arg, *, iostat=ios) n
    if (ios /= 0 .or. n < 2) error stop 'test_hypre_fsai: the argument must be a grid size >= 2'
  end subroutine read_size_argument

end program test_hypre_fsai
