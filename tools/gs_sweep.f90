!> One sweep of Gauss-Seidel against the same loop without Gauss-Seidel's
!> order, on the pattern of Q1 elasticity (as tools/spmv.f90: the nodes of
!> an nx x ny x nz grid, 3 unknowns each, every row coupled to the 3
!> unknowns of the up to 27 nodes around its node; 4-byte column ids,
!> 8-byte values, one row at a time, one accumulator per row):
!>   gauss-seidel : x(i) = x(i) + (b(i) - sum_j a(i,j) x(j)) / d(i), in place,
!>                  so row i reads the x(i-1), x(i-2), ... just written;
!>   jacobi       : the same sum into a second vector y(i), rows independent.
!> Both move the same bytes (12 per entry, 4 per row pointer, 8 per b, d,
!> x and y entry read or written once). If Gauss-Seidel's order bound the
!> sweep (each row waiting on its predecessor's division), its time would
!> exceed the Jacobi loop's; compare both with tools/triad.f90 on one rank.
!> Usage: gs_sweep [nx ny nz]   (default 65 65 65: 823,875 rows, the
!> nodes of the clamped cube of bench/run_bench.sh at n = 64)
program gs_sweep
  implicit none
  integer, parameter :: dp = kind(1.0d0), repeats = 10
  integer :: nx = 65, ny = 65, nz = 65
  integer :: n, i, j, k, c, di, dj, dk, row, node, nnz, it, mode
  integer, allocatable :: row_ptr(:), col(:)
  real(dp), allocatable :: val(:), x(:), y(:), b(:), d(:)
  real(dp) :: s, best(2), bytes
  integer(8) :: t0, t1, rate
  character(len=16) :: arg
  if (command_argument_count() == 3) then
    call get_command_argument(1, arg); read(arg, *) nx
    call get_command_argument(2, arg); read(arg, *) ny
    call get_command_argument(3, arg); read(arg, *) nz
  end if
  n = 3 * nx * ny * nz
  allocate(row_ptr(n + 1), col(81 * n), val(81 * n), x(n), y(n), b(n), d(n))
  nnz = 0
  row_ptr(1) = 1
  do row = 1, n
    node = (row - 1) / 3
    i = mod(node, nx); j = mod(node / nx, ny); k = node / (nx * ny)
    do dk = -1, 1
      do dj = -1, 1
        do di = -1, 1
          if (i + di < 0 .or. i + di >= nx .or. j + dj < 0 .or. j + dj >= ny .or. &
              k + dk < 0 .or. k + dk >= nz) cycle
          do c = 1, 3
            nnz = nnz + 1
            col(nnz) = 3 * ((i + di) + nx * ((j + dj) + ny * (k + dk))) + c
            val(nnz) = -0.01_dp
            if (col(nnz) == row) val(nnz) = 1.0_dp
          end do
        end do
      end do
    end do
    row_ptr(row + 1) = nnz + 1
  end do
  b = 1.0_dp
  d = 1.0_dp
  x = 0.0_dp
  y = 0.0_dp
  best = huge(1.0_dp)
  call system_clock(count_rate=rate)
  do it = 1, repeats
    do mode = 1, 2
      call system_clock(t0)
      if (mode == 1) then
        do row = 1, n
          s = b(row)
          do k = row_ptr(row), row_ptr(row + 1) - 1
            s = s - val(k) * x(col(k))
          end do
          x(row) = x(row) + s / d(row)
        end do
      else
        do row = 1, n
          s = b(row)
          do k = row_ptr(row), row_ptr(row + 1) - 1
            s = s - val(k) * x(col(k))
          end do
          y(row) = x(row) + s / d(row)
        end do
      end if
      call system_clock(t1)
      best(mode) = min(best(mode), real(t1 - t0, dp) / real(rate, dp))
    end do
  end do
  bytes = 12.0_dp * nnz + 4.0_dp * (n + 1) + 8.0_dp * 4 * n
  print '(a, i0, a, i0, a)', 'rows ', n, ', entries ', nnz, ' (best of 10 sweeps each)'
  print '(a, f8.4, a, f7.2, a)', 'gauss-seidel sweep ', best(1), ' s  ', bytes / best(1) / 1.0e9_dp, ' GB/s'
  print '(a, f8.4, a, f7.2, a)', 'jacobi loop        ', best(2), ' s  ', bytes / best(2) / 1.0e9_dp, ' GB/s'
  print '(a, f6.3)', 'gauss-seidel / jacobi ', best(1) / best(2)
  if (sum(x) /= sum(x) .or. sum(y) /= sum(y)) print '(a)', 'not finite'
end program gs_sweep
