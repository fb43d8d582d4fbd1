!> Unit tests of the block-FSAI decoupling factors (block_fsai). Any number
!> of ranks.
!>
!> K is a 3-component "vector Laplacian" on a structured grid of nodes (the
!> Q1 Laplacian plus 0.01 times the Q1 mass matrix on unit cells, times a
!> 3 x 3 SPD coupling of the components: 81 entries per interior row, like
!> Q1 elasticity); C has one column per cell with entries on the 3 unknowns
!> of its 8 corner nodes, the integrals of the shape functions' derivatives
!> over the cell, like the Biot coupling Q. Keys are the natural
!> (lexicographic, x fastest) ids of the dofs (3 per node, interleaved) and
!> of the cells; nodes and cells are split among the ranks in x slabs
!> (rank = floor(np x / n)) and numbered contiguously per rank, so global
!> ids depend on the rank count and keys do not. The values carry a
!> perturbation of a few ulps that depends on the rank count, as assembly
!> on different rank counts would leave.
!>
!> Checks: mismatched inputs are refused; (a) ||K F - C||_F / ||C||_F falls
!> strictly as max_steps grows through 0, 2, 4, 8; (b) on a tiny problem,
!> with a pattern that can hold whole columns, F = K^-1 C to 1e-10.
!>
!> Arguments: [file [scale]]. file: write factors F ("key_row key_col
!> value" lines sorted by keys, one block per factor after a "# name" line;
!> tests/unit/numerics/fsai_ranks.sh compares them over rank counts). scale s > 0:
!> also time decoupling_factor (defaults) on (10s+1) x (10s+1) x (s+1)
!> nodes and 10s x 10s x s cells (s = 8: the Mandel benchmark's sizes,
!> 177,147 rows and 51,200 columns); no assertion on the times.
program test_block_fsai
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t
  use fsai_params, only: fsai_params_t
  use block_fsai, only: decoupling_factor
  use assertions, only: test_suite_t
  use fixture_matrices, only: test_arguments, write_entries, wiggle, q1_entry, q1_mass
  implicit none

  !> A structured grid of nodes (3 unknowns each) and its cells, split in
  !> x slabs.
  type :: grid_t
    integer :: nx = 0, ny = 0, nz = 0
    integer, allocatable :: part(:)           !< rank of each node (by node key)
    integer(gp), allocatable :: node_gid(:)   !< global node number of each node key
    integer(gp), allocatable :: gid_key(:)    !< dof key of each dof global id
    integer(gp), allocatable :: offsets(:)    !< (0:np) dof split
    integer, allocatable :: cell_part(:)      !< rank of each cell (by cell key)
    integer(gp), allocatable :: cell_gid(:)   !< global cell number of each cell key
    integer(gp), allocatable :: cell_key(:)   !< cell key of each cell global id
    integer(gp), allocatable :: cell_offsets(:)   !< (0:np) cell split
  end type grid_t

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  character(len=512) :: path
  integer :: scale

  call comm%init_world()
  call suite%init('block_fsai', comm)
  call test_arguments(path, scale)
  call test_inputs()
  call test_steps()
  call test_exact()
  if (len_trim(path) > 0) call write_factors()
  if (scale > 0) call report_timings(scale)
  call suite%finish()

contains

  ! ---- grids and matrices --------------------------------------------------

  !> nx x ny x nz nodes and their cells; nodes and cells in x slabs,
  !> numbered contiguously per rank in key order.
  subroutine make_grid(nx, ny, nz, gr)
    integer, intent(in) :: nx, ny, nz
    type(grid_t), intent(out) :: gr
    integer :: key, c, ncell
    integer(gp) :: g
    gr%nx = nx
    gr%ny = ny
    gr%nz = nz
    call split(nx, nx*ny*nz, gr%part, gr%node_gid, gr%offsets)
    gr%offsets = 3 * (gr%offsets - 1) + 1
    allocate(gr%gid_key(3_gp*nx*ny*nz))
    do key = 1, nx*ny*nz
      do c = 1, 3
        g = 3 * (gr%node_gid(key) - 1) + c
        gr%gid_key(g) = 3_gp * (key - 1) + c
      end do
    end do
    ncell = (nx - 1) * (ny - 1) * (nz - 1)
    call split(nx - 1, ncell, gr%cell_part, gr%cell_gid, gr%cell_offsets)
    allocate(gr%cell_key(ncell))
    do key = 1, ncell
      gr%cell_key(gr%cell_gid(key)) = key
    end do
  end subroutine make_grid

  !> Entities 1..n (keys, x fastest with period nxe) split in x slabs:
  !> part, contiguous global number per rank in key order, offsets.
  subroutine split(nxe, n, part, gid, offsets)
    integer, intent(in) :: nxe, n
    integer, allocatable, intent(out) :: part(:)
    integer(gp), allocatable, intent(out) :: gid(:), offsets(:)
    integer(gp), allocatable :: cnt(:)
    integer :: np, key, p
    np = comm%size
    allocate(part(n), gid(n), offsets(0:np), cnt(0:np-1))
    cnt = 0
    do key = 1, n
      part(key) = min(np - 1, (np * mod(key - 1, nxe)) / nxe)
      cnt(part(key)) = cnt(part(key)) + 1
    end do
    offsets(0) = 1
    do p = 1, np
      offsets(p) = offsets(p-1) + cnt(p-1)
    end do
    cnt = 0
    do key = 1, n
      p = part(key)
      gid(key) = offsets(p) + cnt(p)
      cnt(p) = cnt(p) + 1
    end do
  end subroutine split

  !> Empty distributed matrix with this rank's rows of the row split ro and
  !> the column split co, room for cap entries.
  subroutine start_matrix(ro, co, cap, a)
    integer(gp), intent(in) :: ro(0:), co(0:)
    integer, intent(in) :: cap
    type(global_csr_t), intent(out) :: a
    a%comm = comm
    a%row_offsets = ro
    a%col_offsets = co
    a%n_rows = int(ro(comm%rank + 1) - ro(comm%rank), ip)
    allocate(a%row_ptr(a%n_rows + 1), a%gcol(cap), a%val(cap), a%key(a%n_rows))
    a%row_ptr(1) = 1
  end subroutine start_matrix

  !> Append row i (the next one) with unsorted columns and values.
  subroutine put_row(a, i, key, cols, vals)
    type(global_csr_t), intent(inout) :: a
    integer(ip), intent(in) :: i
    integer(gp), intent(in) :: key
    integer(gp), intent(inout) :: cols(:)
    real(rp), intent(in) :: vals(:)
    integer(ip) :: pos(size(cols))
    integer :: m
    m = size(cols)
    call sort_gids(cols, pos)
    a%gcol(a%row_ptr(i):a%row_ptr(i) + m - 1) = cols
    a%val(a%row_ptr(i):a%row_ptr(i) + m - 1) = vals(pos)
    a%row_ptr(i + 1) = a%row_ptr(i) + m
    a%key(i) = key
  end subroutine put_row

  !> Trim the arrays of a finished matrix.
  subroutine end_matrix(a)
    type(global_csr_t), intent(inout) :: a
    a%gcol = a%gcol(1:a%row_ptr(a%n_rows + 1) - 1)
    a%val = a%val(1:a%row_ptr(a%n_rows + 1) - 1)
  end subroutine end_matrix

  !> K: the Q1 Laplacian + 0.01 Q1 mass (unit cells) times a 3 x 3 SPD
  !> coupling of the components; this rank's rows, with keys.
  subroutine build_k(gr, k)
    type(grid_t), intent(in) :: gr
    type(global_csr_t), intent(out) :: k
    real(rp), parameter :: m3(3,3) = reshape([2.0_rp, 0.5_rp, 0.2_rp, 0.5_rp, 2.0_rp, 0.3_rp, &
                                              0.2_rp, 0.3_rp, 2.0_rp], [3, 3])
    integer(gp) :: cols(81), row, rkey
    real(rp) :: vals(81), s
    integer :: key, nb, ix, iy, iz, dx, dy, dz, jx, jy, jz, c, c2, m
    integer(ip) :: i
    call start_matrix(gr%offsets, gr%offsets, 81 * (int(gr%offsets(comm%rank+1) - gr%offsets(comm%rank)) + 1), k)
    do key = 1, gr%nx * gr%ny * gr%nz
      if (gr%part(key) /= comm%rank) cycle
      ix = mod(key - 1, gr%nx)
      iy = mod((key - 1) / gr%nx, gr%ny)
      iz = (key - 1) / (gr%nx * gr%ny)
      do c = 1, 3
        row = 3 * (gr%node_gid(key) - 1) + c
        rkey = gr%gid_key(row)
        m = 0
        do dz = -1, 1
          do dy = -1, 1
            do dx = -1, 1
              jx = ix + dx
              jy = iy + dy
              jz = iz + dz
              if (jx < 0 .or. jx >= gr%nx .or. jy < 0 .or. jy >= gr%ny .or. jz < 0 .or. jz >= gr%nz) cycle
              nb = 1 + jx + gr%nx * (jy + gr%ny * jz)
              s = q1_entry(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz) + &
                  q1_mass(ix, jx, gr%nx) * q1_entry(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz) + &
                  q1_mass(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_entry(iz, jz, gr%nz) + &
                  0.01_rp * q1_mass(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz)
              do c2 = 1, 3
                m = m + 1
                cols(m) = 3 * (gr%node_gid(nb) - 1) + c2
                vals(m) = s * m3(c, c2) * wiggle(rkey, gr%gid_key(cols(m)), comm%size)
              end do
            end do
          end do
        end do
        i = int(row - k%row_offsets(comm%rank), ip) + 1
        call put_row(k, i, rkey, cols(1:m), vals(1:m))
      end do
    end do
    call end_matrix(k)
  end subroutine build_k

  !> C: column = cell, rows = the 3 unknowns of its 8 corners, value = the
  !> integral over the (unit) cell of the derivative of the corner's shape
  !> function along the unknown's direction, +-1/4; this rank's rows.
  subroutine build_c(gr, cm)
    type(grid_t), intent(in) :: gr
    type(global_csr_t), intent(out) :: cm
    integer(gp) :: cols(8), row, rkey
    real(rp) :: vals(8)
    integer :: key, ix, iy, iz, cx, cy, cz, c, m, side(3), cell
    integer(ip) :: i
    call start_matrix(gr%offsets, gr%cell_offsets, 8 * (int(gr%offsets(comm%rank+1) - gr%offsets(comm%rank)) + 1), &
                      cm)
    do key = 1, gr%nx * gr%ny * gr%nz
      if (gr%part(key) /= comm%rank) cycle
      ix = mod(key - 1, gr%nx)
      iy = mod((key - 1) / gr%nx, gr%ny)
      iz = (key - 1) / (gr%nx * gr%ny)
      do c = 1, 3
        row = 3 * (gr%node_gid(key) - 1) + c
        rkey = gr%gid_key(row)
        m = 0
        do cz = iz - 1, iz
          do cy = iy - 1, iy
            do cx = ix - 1, ix
              if (cx < 0 .or. cx >= gr%nx - 1 .or. cy < 0 .or. cy >= gr%ny - 1 .or. cz < 0 .or. &
                  cz >= gr%nz - 1) cycle
              ! the node is the cell's corner on the upper side along x if ix = cx + 1
              side = [ix - cx, iy - cy, iz - cz]
              cell = 1 + cx + (gr%nx - 1) * (cy + (gr%ny - 1) * cz)
              m = m + 1
              cols(m) = gr%cell_gid(cell)
              vals(m) = merge(0.25_rp, -0.25_rp, side(c) == 1) * wiggle(rkey, int(cell, gp) + 1000000_gp, comm%size)
            end do
          end do
        end do
        i = int(row - cm%row_offsets(comm%rank), ip) + 1
        call put_row(cm, i, rkey, cols(1:m), vals(1:m))
      end do
    end do
    call end_matrix(cm)
  end subroutine build_c

  !> Dense copy (rows by dof key, columns by column key through ckey) of a
  !> distributed matrix, the same on every rank.
  subroutine gather_dense(a, ckey, d)
    type(global_csr_t), intent(in) :: a
    integer(gp), intent(in) :: ckey(:)
    real(rp), intent(out) :: d(:,:)
    real(rp), allocatable :: flat(:)
    integer :: nr, i, k
    nr = size(d, 1)
    allocate(flat(size(d)))
    flat = 0.0_rp
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        flat((ckey(a%gcol(k)) - 1) * nr + a%key(i)) = a%val(k)
      end do
    end do
    call comm%sum_all(flat)
    d = reshape(flat, shape(d))
  end subroutine gather_dense

  ! ---- tests ---------------------------------------------------------------

  !> A C whose rows are split unlike K's, and a K without keys, are refused.
  subroutine test_inputs()
    type(grid_t) :: gr
    type(global_csr_t) :: k, cm, f
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    call make_grid(4, 4, 3, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    cm%row_offsets(comm%size) = cm%row_offsets(comm%size) + 1
    call decoupling_factor(k, cm, p, f, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'rows of C') > 0, &
                           'inputs: C split unlike K is refused: '//trim(st%msg))
    call build_c(gr, cm)
    deallocate(k%key)
    call st%clear()
    call decoupling_factor(k, cm, p, f, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'key') > 0, &
                           'inputs: K without keys is refused: '//trim(st%msg))
    call build_k(gr, k)
    call st%clear()
    p%step_size = 0
    call decoupling_factor(k, cm, p, f, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'step_size') > 0, &
                           'inputs: bad settings are refused by name')
  end subroutine test_inputs

  !> (a) ||K F - C|| / ||C|| falls strictly with max_steps = 0, 2, 4, 8.
  subroutine test_steps()
    integer, parameter :: steps(4) = [0, 2, 4, 8]
    type(grid_t) :: gr
    type(global_csr_t) :: k, cm, f
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    real(rp) :: res(4)
    integer :: t
    character(len=256) :: line
    call make_grid(9, 9, 5, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    do t = 1, 4
      p%max_steps = steps(t)
      p%tol = 0.0_rp
      call decoupling_factor(k, cm, p, f, st, res(t))
      write(line, '(a,i0,a,es10.3,a,f6.2)') 'steps: max_steps = ', steps(t), ': ||K F - C|| / ||C|| = ', &
        res(t), ', nnz(F) per column = ', real(f%global_nnz(), rp) / real(gr%cell_offsets(comm%size) - 1, rp)
      call suite%assert_true(st%ok(), trim(line)//' '//trim(st%msg))
    end do
    call suite%assert_true(res(2) < res(1) .and. res(3) < res(2) .and. res(4) < res(3), &
                           'steps: the residual falls strictly as max_steps grows')
  end subroutine test_steps

  !> (b) 3 x 3 x 2 nodes (54 rows), 4 cells: a pattern that can hold whole
  !> columns gives F = K^-1 C.
  subroutine test_exact()
    interface
      subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
        import :: rp
        character(len=1), intent(in) :: uplo
        integer, intent(in) :: n, nrhs, lda, ldb
        real(rp), intent(inout) :: a(lda, *), b(ldb, *)
        integer, intent(out) :: info
      end subroutine dposv
    end interface
    type(grid_t) :: gr
    type(global_csr_t) :: k, cm, f
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: kd(:,:), cd(:,:), fd(:,:)
    real(rp) :: res, err
    integer :: n, ncell, info
    call make_grid(3, 3, 2, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    n = 54
    ncell = 4
    p%step_size = n
    p%max_steps = 10
    p%tol = 0.0_rp
    call decoupling_factor(k, cm, p, f, st, res)
    call suite%assert_true(st%ok(), 'exact: decoupling_factor succeeds '//trim(st%msg))
    if (.not. st%ok()) return
    allocate(kd(n, n), cd(n, ncell), fd(n, ncell))
    call gather_dense(k, gr%gid_key, kd)
    call gather_dense(cm, gr%cell_key, cd)
    call gather_dense(f, gr%cell_key, fd)
    call dposv('L', n, ncell, kd, n, cd, n, info)
    err = maxval(abs(fd - cd)) / maxval(abs(cd))
    call suite%assert_close(err, 0.0_rp, 1.0e-10_rp, 'exact: F = K^-1 C, relative')
    call suite%assert_close(res, 0.0_rp, 1.0e-12_rp, 'exact: ||K F - C|| / ||C|| vanishes')
    call suite%assert_equal_int(int(f%global_nnz()), n * ncell, 'exact: the columns are full')
  end subroutine test_exact

  ! ---- factors for the rank comparison -------------------------------------

  subroutine write_factors()
    type(grid_t) :: gr
    type(global_csr_t) :: k, cm, f
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    logical :: all_ok
    call make_grid(9, 9, 5, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    p%max_steps = 4
    p%tol = 0.0_rp
    call decoupling_factor(k, cm, p, f, st)
    all_ok = st%ok()
    call write_entries(comm, f, gr%cell_key, path, 'max_steps 4, tol 0', .true.)
    call make_grid(13, 12, 6, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    p = fsai_params_t()
    call decoupling_factor(k, cm, p, f, st)
    all_ok = all_ok .and. st%ok()
    call write_entries(comm, f, gr%cell_key, path, 'default settings', .false.)
    p%max_steps = 6
    p%step_size = 5
    p%tol = 1.0e-2_rp
    p%drop = 0.02_rp
    call decoupling_factor(k, cm, p, f, st)
    all_ok = all_ok .and. st%ok()
    call write_entries(comm, f, gr%cell_key, path, '6 steps of 5, tol 1e-2, drop 0.02', .false.)
    call suite%assert_true(all_ok, 'factors written to '//trim(path))
  end subroutine write_factors

  ! ---- timings -------------------------------------------------------------

  !> decoupling_factor (defaults) on (10s+1)^2 x (s+1) nodes, 10s^2 x s cells.
  subroutine report_timings(s)
    integer, intent(in) :: s
    type(grid_t) :: gr
    type(global_csr_t) :: k, cm, f
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    real(rp) :: t0, tb, tf, tr, res
    integer(gp) :: nnz
    t0 = wall_time()
    call make_grid(10*s + 1, 10*s + 1, s + 1, gr)
    call build_k(gr, k)
    call build_c(gr, cm)
    tb = wall_time() - t0
    t0 = wall_time()
    call decoupling_factor(k, cm, p, f, st)
    tf = wall_time() - t0
    t0 = wall_time()
    call decoupling_factor(k, cm, p, f, st, res)
    tr = wall_time() - t0 - tf
    nnz = f%global_nnz()
    if (comm%rank == 0) then
      write(output_unit, '(a,i0,a,i0,a,i0,a,f6.2,a)') 'timing: K ', gr%offsets(comm%size) - 1, ' rows, C ', &
        gr%cell_offsets(comm%size) - 1, ' columns, on ', comm%size, ' ranks (built in ', tb, ' s)'
      write(output_unit, '(a,f8.3,a,f6.2,a,es10.3,1x,a)') 'timing: decoupling_factor (defaults) ', tf, &
        ' s, nnz(F) per column ', real(nnz, rp) / real(gr%cell_offsets(comm%size) - 1, rp), &
        ', ||K F - C|| / ||C|| = ', res, trim(st%msg)
      write(output_unit, '(a,f8.3,a)') 'timing: the optional resid (gcsr_multiply, gcsr_add) adds ', tr, ' s'
      flush(output_unit)
    end if
  end subroutine report_timings
end program test_block_fsai
