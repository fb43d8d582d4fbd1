!> The CSR product of csr_matrix%apply (the same loop: 4-byte column ids,
!> 8-byte values, one row at a time, four partial sums a row), and the same
!> with one sum a row (a chain of dependent additions), on the pattern of
!> Q1 elasticity: nodes
!> of an nx x ny x nz grid, 3 unknowns each, every row coupled to the 3
!> unknowns of the up to 27 nodes around its node (81 entries inside).
!> The grid's z layers are split among the ranks, each rank multiplying its
!> own slab's rows with no communication (the ghost exchange of a real run
!> is left out): run on 1 and 2 ranks, the ratio of the times is the strong
!> scaling of the product alone. The effective bandwidth counts 12 bytes
!> per entry (value and column id), 4 per row pointer, 8 per y entry and 8
!> per x entry read once; compare with tools/triad.f90.
!> Usage: spmv [nx ny nz]   (default 81 81 9, the nodes of Mandel at the
!> seed's size, 177,147 rows, about 14 million entries)
program spmv
  use mpi
  implicit none
  integer, parameter :: repeats = 50
  integer :: nx = 81, ny = 81, nz = 9
  integer :: ierr, rank, np, z0, z1, nloc, i, j, k, c, di, dj, dk, row, it, nnz
  integer, allocatable :: row_ptr(:), col(:)
  real(8), allocatable :: val(:), x(:), y(:)
  real(8) :: t0, best, best1, s, s0, s1, s2, s3, bytes
  integer :: k0, k1, pass
  character(len=16) :: arg
  call mpi_init(ierr)
  call mpi_comm_rank(mpi_comm_world, rank, ierr)
  call mpi_comm_size(mpi_comm_world, np, ierr)
  if (command_argument_count() == 3) then
    call get_command_argument(1, arg); read(arg, *) nx
    call get_command_argument(2, arg); read(arg, *) ny
    call get_command_argument(3, arg); read(arg, *) nz
  end if
  ! this rank's z layers of nodes
  z0 = (rank * nz) / np
  z1 = ((rank + 1) * nz) / np - 1
  nloc = 3 * nx * ny * (z1 - z0 + 1)
  allocate(row_ptr(nloc + 1), col(81 * nloc), val(81 * nloc))
  ! the product reads x on the slab and one layer of nodes either side
  allocate(x(3 * nx * ny * nz), y(nloc))
  row = 0
  nnz = 0
  row_ptr(1) = 1
  do k = z0, z1
    do j = 0, ny - 1
      do i = 0, nx - 1
        do c = 1, 3
          row = row + 1
          do dk = max(k - 1, 0), min(k + 1, nz - 1)
            do dj = max(j - 1, 0), min(j + 1, ny - 1)
              do di = max(i - 1, 0), min(i + 1, nx - 1)
                col(nnz + 1:nnz + 3) = 3 * (di + nx * (dj + ny * dk)) + [1, 2, 3]
                val(nnz + 1:nnz + 3) = 1.0d0 / real(nnz + 4 + row, 8)
                nnz = nnz + 3
              end do
            end do
          end do
          row_ptr(row + 1) = nnz + 1
        end do
      end do
    end do
  end do
  x = 1.0d0
  best = huge(1.0d0)
  best1 = huge(1.0d0)
  do it = 1, repeats
    do pass = 1, 2
      call mpi_barrier(mpi_comm_world, ierr)
      t0 = mpi_wtime()
      if (pass == 1) then
        do i = 1, nloc
          k0 = row_ptr(i)
          k1 = row_ptr(i + 1) - 1
          s0 = 0.0d0; s1 = 0.0d0; s2 = 0.0d0; s3 = 0.0d0
          do k = k0, k1 - 3, 4
            s0 = s0 + val(k) * x(col(k))
            s1 = s1 + val(k + 1) * x(col(k + 1))
            s2 = s2 + val(k + 2) * x(col(k + 2))
            s3 = s3 + val(k + 3) * x(col(k + 3))
          end do
          do k = k1 - mod(k1 - k0 + 1, 4) + 1, k1
            s0 = s0 + val(k) * x(col(k))
          end do
          y(i) = (s0 + s1) + (s2 + s3)
        end do
      else
        do i = 1, nloc
          s = 0.0d0
          do k = row_ptr(i), row_ptr(i + 1) - 1
            s = s + val(k) * x(col(k))
          end do
          y(i) = s
        end do
      end if
      call mpi_barrier(mpi_comm_world, ierr)
      if (pass == 1) best = min(best, mpi_wtime() - t0)
      if (pass == 2) best1 = min(best1, mpi_wtime() - t0)
    end do
    x(1 + mod(it, size(x))) = y(1 + mod(7 * it, nloc))
  end do
  bytes = 12.0d0 * nnz + 4.0d0 * (nloc + 1) + 8.0d0 * nloc &
        + 8.0d0 * 3 * nx * ny * (min(z1 + 1, nz - 1) - max(z0 - 1, 0) + 1)
  call mpi_allreduce(mpi_in_place, bytes, 1, mpi_double_precision, mpi_sum, mpi_comm_world, ierr)
  call mpi_allreduce(mpi_in_place, nnz, 1, mpi_integer, mpi_sum, mpi_comm_world, ierr)
  if (rank == 0) print '(a, i0, a, i0, a, f8.3, a, f7.2, a, f8.3, a, f7.2)', 'ranks ', np, ': CSR product of ', &
    nnz, ' entries, four sums a row: ms ', 1.0d3 * best, ', effective GB/s ', bytes / best / 1.0d9, &
    '; one sum a row: ms ', 1.0d3 * best1, ', GB/s ', bytes / best1 / 1.0d9
  call mpi_finalize(ierr)
end program spmv
