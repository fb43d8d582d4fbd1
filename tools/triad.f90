!> Memory bandwidth of this machine for 1 .. N ranks: every rank runs the
!> triad a = b + s c on its own arrays (3 x 320 MB, far beyond any cache) at
!> the same time, 20 times; the best time gives the bandwidth of a rank and
!> of all (24 bytes per element: two reads and a write, write-allocate not
!> counted). Sparse products and AMG V-cycles are bound by this bandwidth,
!> so the ratio of the aggregate figures on 2 and 1 ranks bounds what their
!> strong scaling can reach on one machine. Built and run by
!> tools/bandwidth.sh.
program triad
  use mpi
  implicit none
  integer, parameter :: n = 40000000, repeats = 20
  real(8), allocatable :: a(:), b(:), c(:)
  real(8) :: t0, best, s
  integer :: it, ierr, rank, np
  call mpi_init(ierr)
  call mpi_comm_rank(mpi_comm_world, rank, ierr)
  call mpi_comm_size(mpi_comm_world, np, ierr)
  allocate(a(n), b(n), c(n))
  b = 1.0d0
  c = 2.0d0
  a = 0.0d0
  s = 3.0d0
  best = huge(1.0d0)
  do it = 1, repeats
    call mpi_barrier(mpi_comm_world, ierr)
    t0 = mpi_wtime()
    a = b + s * c
    call mpi_barrier(mpi_comm_world, ierr)
    best = min(best, mpi_wtime() - t0)
    ! a data dependence between repeats, so that no pass can be dropped
    b(1 + mod(it, n)) = a(1 + mod(7 * it, n))
  end do
  if (rank == 0) print '(a, i0, a, f7.2, a, f7.2)', 'ranks ', np, ': triad GB/s per rank ', &
    24.0d0 * n / best / 1.0d9, ', all ranks ', 24.0d0 * n * np / best / 1.0d9
  call mpi_finalize(ierr)
end program triad
