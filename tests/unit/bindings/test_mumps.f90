!> Unit test of mumps_solver_t on 1 or 2 (or more) ranks.
!>
!> Matrices: the 2D 5-point Laplacian on an nx x ny grid (Dirichlet
!> boundary eliminated), symmetric positive definite, and the same plus a
!> central-difference convection term (unsymmetric). Rows are numbered
!> lexicographically and owned in contiguous blocks per rank. With x* known,
!> b = A x* and the solver must return x* to round-off.
program test_mumps
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use mumps_solver, only: mumps_solver_t
  use assertions, only: test_suite_t
  implicit none

  integer(ip), parameter :: nx = 120, ny = 90
  real(rp), parameter :: tol = 1.0e-10_rp
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(index_map_t) :: row_map, col_map
  type(csr_matrix_t) :: a_uns, a_spd, a_sing, a_piv
  type(mumps_solver_t) :: solver
  type(error_status_t) :: status
  real(rp), allocatable :: x_ref(:), x(:), b(:), z(:)
  integer(ip) :: i

  call comm%init_world()
  call suite%init('mumps', comm)
  call build_maps(comm, row_map, col_map)
  call build_matrix(row_map, col_map, 4.0_rp, 0.35_rp, 0.15_rp, a_uns)
  call build_matrix(row_map, col_map, 4.0_rp, 0.0_rp, 0.0_rp, a_spd)
  allocate(x_ref(row_map%n_owned), x(row_map%n_owned), b(row_map%n_owned), z(row_map%n_owned))
  do i = 1, row_map%n_owned
    x_ref(i) = 1.0_rp + sin(0.37_rp * real(row_map%first + i - 1, rp))
  end do

  ! both layouts: the host (rank 0 factorizes alone) and the distributed one
  call check_layout(.true., 'host: ')
  call check_layout(.false., 'distributed: ')
  call solver%free()
  call a_uns%free()
  call a_spd%free()
  call a_sing%free()
  call a_piv%free()
  call suite%finish()

contains

  !> Every check of this test with the given MUMPS layout; lay prefixes the
  !> messages.
  subroutine check_layout(on_host, lay)
    logical, intent(in) :: on_host
    character(len=*), intent(in) :: lay
    call solver%free()
    call status%clear()
    solver%on_host = on_host
    call suite%assert_true(solver%name() == 'mumps', lay//'name() is mumps')

    ! ---- unsymmetric: LU ----
    call solver%setup(a_uns, status)
    call suite%assert_true(status%ok(), lay//'unsymmetric setup succeeds: '//trim(status%msg))
    call suite%assert_true(solver%n_global == int(nx * ny, gp), lay//'order of the matrix')
    call suite%assert_true(solver%nnz_input == a_uns%global_nnz(), lay//'all entries passed (unsymmetric)')
    call a_uns%apply(x_ref, b)
    call solver%solve(b, x, status)
    call suite%assert_true(status%ok(), lay//'unsymmetric solve succeeds')
    call suite%assert_true(rel_err(comm, x, x_ref) < tol, lay//'unsymmetric: ||x - x*|| / ||x*|| < 1e-10')
    call suite%assert_true(solver%peak_mem_max_mb > 0, lay//'unsymmetric: peak memory (max) reported > 0'// &
                             trim(stats(solver)))
    call suite%assert_true(solver%peak_mem_total_mb >= solver%peak_mem_max_mb, &
                             'unsymmetric: total peak memory >= max peak memory')
    call suite%assert_true(solver%factor_entries >= a_uns%global_nnz(), &
                             'unsymmetric: factors hold at least nnz(A) entries')
    call suite%assert_true(solver%setup_time > 0.0_rp, lay//'unsymmetric: setup time recorded')
    ! a second right-hand side reuses the redistribution plan; apply() = solve()
    do i = 1, row_map%n_owned
      x_ref(i) = cos(0.11_rp * real(row_map%first + i - 1, rp)) - 0.5_rp
    end do
    call a_uns%apply(x_ref, b)
    call solver%apply(b, z)
    call suite%assert_true(rel_err(comm, z, x_ref) < tol, lay//'unsymmetric: apply() on a second rhs')
    ! the transposed solution must not pass: the test can fail
    call a_spd%apply(x_ref, b)
    call solver%apply(b, z)
    call suite%assert_true(rel_err(comm, z, x_ref) > 1.0e-3_rp, lay//'unsymmetric factors do not solve the SPD matrix')

    ! ---- symmetric positive definite: LDL^T on the lower triangle, same object ----
    call solver%setup(a_spd, status, symmetric=.true.)
    call suite%assert_true(status%ok(), lay//'symmetric setup succeeds: '//trim(status%msg))
    call suite%assert_true(solver%nnz_input == (a_spd%global_nnz() + int(nx * ny, gp)) / 2, &
                             lay//'symmetric: only the lower triangle passed')
    do i = 1, row_map%n_owned
      x_ref(i) = real(mod(row_map%first + i - 1, 7_gp), rp) - 2.5_rp
    end do
    call a_spd%apply(x_ref, b)
    call solver%solve(b, x, status)
    call suite%assert_true(status%ok(), lay//'symmetric solve succeeds')
    call suite%assert_true(rel_err(comm, x, x_ref) < tol, lay//'symmetric: ||x - x*|| / ||x*|| < 1e-10')
    call suite%assert_true(solver%peak_mem_max_mb > 0, lay//'symmetric: peak memory (max) reported > 0'// &
                             trim(stats(solver)))
    call suite%assert_true(solver%factor_entries > 0, lay//'symmetric: factor entries reported')

    ! ---- workspace retry: the grid's adjacency matrix (zero diagonal; nonsingular for
    !      nx + 1 = 121 and ny + 1 = 91 coprime) needs pivoting beyond the analysis
    !      estimate; without relaxation the factorization fails with -9 and the one
    !      retry with a larger ICNTL(14) must cure it ----
    call build_matrix(row_map, col_map, 0.0_rp, 0.0_rp, 0.0_rp, a_piv)
    solver%mem_relax = 0
    call solver%setup(a_piv, status)
    solver%mem_relax = -1
    call suite%assert_true(status%ok(), lay//'zero diagonal: setup succeeds: '//trim(status%msg))
    call suite%assert_true(solver%retried, lay//'zero diagonal, no relaxation: the workspace retry was needed')
    call a_piv%apply(x_ref, b)
    call solver%solve(b, x, status)
    call suite%assert_true(rel_err(comm, x, x_ref) < tol, lay//'zero diagonal: ||x - x*|| / ||x*|| < 1e-10')

    ! ---- a singular matrix is reported through the status, not a stop ----
    call build_matrix(row_map, col_map, 4.0_rp, 0.0_rp, 0.0_rp, a_sing)
    call zero_row(a_sing, int(nx * ny, gp) / 2)
    call status%clear()
    call solver%setup(a_sing, status)
    call suite%assert_true(.not. status%ok(), lay//'singular matrix: setup reports an error')
    call suite%assert_true(status%code == -10 .or. status%code == -6, &
                             'singular matrix: code is INFOG(1) = -10 or -6: '//trim(status%msg))
    call suite%assert_true(index(status%msg, 'INFOG(1)') > 0, lay//'singular matrix: message names INFOG(1)')
    call status%clear()
    call solver%solve(b, x, status)
    call suite%assert_true(.not. status%ok(), lay//'solve after a failed setup reports an error')

  end subroutine check_layout

  !> Contiguous block of rows per rank; ghost columns: the grid neighbours
  !> owned by other ranks.
  subroutine build_maps(comm, row_map, col_map)
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), intent(inout) :: row_map, col_map
    integer(gp), allocatable :: no_ghost(:), ghosts(:)
    integer(gp) :: n, first, g, nb(4)
    integer(ip) :: n_owned, k
    logical, allocatable :: is_ghost(:)
    n = int(nx * ny, gp)
    n_owned = int(n / comm%size, ip)
    if (comm%rank < mod(n, int(comm%size, gp))) n_owned = n_owned + 1
    allocate(no_ghost(0))
    call row_map%init(comm, n_owned, no_ghost)
    first = row_map%first
    allocate(is_ghost(n))
    is_ghost = .false.
    do g = first, first + n_owned - 1
      nb = neighbours(g)
      do k = 1, 4
        if (nb(k) > 0 .and. (nb(k) < first .or. nb(k) >= first + n_owned)) is_ghost(nb(k)) = .true.
      end do
    end do
    allocate(ghosts(0))
    do g = 1, n
      if (is_ghost(g)) ghosts = [ghosts, g]
    end do
    call col_map%init(comm, n_owned, ghosts)
  end subroutine build_maps

  !> West, east, south, north neighbours of global id g (0 outside the grid).
  function neighbours(g) result(nb)
    integer(gp), intent(in) :: g
    integer(gp) :: nb(4)
    integer(gp) :: ix, iy
    ix = mod(g - 1, int(nx, gp))
    iy = (g - 1) / int(nx, gp)
    nb = 0
    if (ix > 0) nb(1) = g - 1
    if (ix < nx - 1) nb(2) = g + 1
    if (iy > 0) nb(3) = g - nx
    if (iy < ny - 1) nb(4) = g + nx
  end function neighbours

  !> diag on the diagonal, -1 -/+ cx to the west/east, -1 -/+ cy to the
  !> south/north (diag = 4, cx = cy = 0: the SPD Laplacian).
  subroutine build_matrix(row_map, col_map, diag, cx, cy, a)
    type(index_map_t), intent(in), target :: row_map, col_map
    real(rp), intent(in) :: diag, cx, cy
    type(csr_matrix_t), intent(inout) :: a
    integer(ip), allocatable :: row_ptr(:), col(:)
    integer(ip) :: i, k, m, lid(5)
    integer(gp) :: g, nb(4)
    real(rp) :: coef(4)
    coef = [-1.0_rp - cx, -1.0_rp + cx, -1.0_rp - cy, -1.0_rp + cy]
    allocate(row_ptr(row_map%n_owned + 1), col(5 * row_map%n_owned))
    row_ptr(1) = 1
    do i = 1, row_map%n_owned
      g = row_map%first + i - 1
      nb = neighbours(g)
      m = 1
      lid(1) = i
      do k = 1, 4
        if (nb(k) > 0) then
          m = m + 1
          lid(m) = col_map%local_id(nb(k))
        end if
      end do
      call sort_small(lid(1:m))
      col(row_ptr(i):row_ptr(i) + m - 1) = lid(1:m)
      row_ptr(i+1) = row_ptr(i) + m
    end do
    call a%init(row_map, col_map, row_ptr, col(1:row_ptr(row_map%n_owned + 1) - 1))
    do i = 1, row_map%n_owned
      g = row_map%first + i - 1
      nb = neighbours(g)
      call a%add_value(i, i, diag)
      do k = 1, 4
        if (nb(k) > 0) call a%add_value(i, col_map%local_id(nb(k)), coef(k))
      end do
    end do
  end subroutine build_matrix

  subroutine sort_small(v)
    integer(ip), intent(inout) :: v(:)
    integer(ip) :: i, j, t
    do i = 2, size(v)
      t = v(i)
      j = i - 1
      do while (j >= 1)
        if (v(j) <= t) exit
        v(j+1) = v(j)
        j = j - 1
      end do
      v(j+1) = t
    end do
  end subroutine sort_small

  !> Zero the values of global row g and of column g (keeps the pattern, so
  !> the matrix is numerically singular but symmetric in structure).
  subroutine zero_row(a, g)
    type(csr_matrix_t), intent(inout) :: a
    integer(gp), intent(in) :: g
    integer(ip) :: i, k
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        if (a%row_map%first + i - 1 == g .or. a%col_map%global_id(a%col(k)) == g) a%val(k) = 0.0_rp
      end do
    end do
  end subroutine zero_row

  !> The statistics of the last setup, for the log of the test.
  function stats(solver) result(s)
    type(mumps_solver_t), intent(in) :: solver
    character(len=200) :: s
    write(s, '(a,i0,a,i0,a,i0,a,es9.2,a,f7.3,a)') ' (', solver%peak_mem_max_mb, ' MB max, ', &
      solver%peak_mem_total_mb, ' MB total, ', solver%factor_entries, ' factor entries, ', &
      solver%factor_flops, ' flops, ', solver%setup_time, ' s)'
  end function stats

  !> ||x - y|| / ||y|| over all ranks.
  real(rp) function rel_err(comm, x, y)
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in) :: x(:), y(:)
    rel_err = sqrt(comm%sum(sum((x - y)**2)) / comm%sum(sum(y**2)))
  end function rel_err

end program test_mumps
