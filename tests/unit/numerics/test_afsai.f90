!> Unit tests of geoblock's adaptive FSAI (fsai_params, afsai, afsai_precon).
!> Any number of ranks.
!>
!> The matrices live on structured grids of nodes whose keys are the
!> natural (lexicographic, x fastest) node ids, as the mesh's original ids
!> would be; the nodes are split among the ranks in x slabs (rank =
!> floor(np x / nx)) and numbered contiguously per rank, so the global ids
!> depend on the rank count and the keys do not. The values carry a
!> perturbation of a few ulps that depends on the rank count (symmetric),
!> as assembly on different rank counts would leave.
!>
!> Checks: bad settings are refused by name; a non-positive pivot is
!> reported on every rank with the key of its row, and an indefinite matrix
!> is refused; (a) with a pattern
!> growing to the full lower triangle, G is the exact inverse Cholesky
!> factor L^-1 (A = L L^T in key order) to 1e-10; (b) PCG iterations on a
!> 20^3 Laplacian with jumping coefficients do not increase from 0 to 3 to 6
!> adaptive steps and fall overall, and G stays lower triangular by key;
!> (c) the preconditioner is symmetric, (y, M x) = (x, M y) to 1e-12; the
!> set-up without keys (global ids as keys) works too.
!>
!> Arguments: [file [scale]]. file: write the factors (adaptive, jumping
!> coefficients; default settings on the constant-coefficient Laplacian,
!> where candidates tie; diagonal start with dropping; default settings on
!> a vector Laplacian with 81 entries per row) as "key_row key_col
!> value" lines sorted by keys, one block per factor after a "# name" line
!> (tests/unit/numerics/fsai_ranks.sh compares them over rank counts). scale s > 0:
!> also time the set-up on a 3-component 27-point "vector Laplacian" on
!> (10s+1) x (10s+1) x (s+1) nodes (s = 8: 177,147 rows, the size of the
!> Mandel benchmark's K); no assertion on the times.
program test_afsai
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use index_map, only: index_map_t, sort_gids
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, to_csr, from_csr
  use dist_vector, only: pdot
  use fsai_params, only: fsai_params_t
  use afsai, only: afsai_factor
  use afsai_precon, only: afsai_precon_t
  use jacobi_precon, only: jacobi_precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  use assertions, only: test_suite_t
  use fixture_matrices, only: test_arguments, write_entries, wiggle, q1_entry, q1_mass
  implicit none

  !> A structured grid of nodes with nc unknowns per node, split in x slabs.
  type :: grid_t
    integer :: nx = 0, ny = 0, nz = 0, nc = 1
    integer, allocatable :: part(:)           !< rank of each node (by node key)
    integer(gp), allocatable :: node_gid(:)   !< global node number of each node key
    integer(gp), allocatable :: gid_key(:)    !< dof key of each dof global id
    integer(gp), allocatable :: offsets(:)    !< (0:np) dof split
  end type grid_t

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  character(len=512) :: path
  integer :: scale

  call comm%init_world()
  call suite%init('afsai', comm)
  call test_arguments(path, scale)
  call test_settings()
  call test_not_spd()
  call test_exact()
  call test_adaptive()
  if (len_trim(path) > 0) call write_factors()
  if (scale > 0) call report_timings(scale)
  call suite%finish()

contains

  ! ---- grids and matrices --------------------------------------------------

  !> nx x ny x nz nodes, nc unknowns per node (interleaved), x slabs.
  subroutine make_grid(nx, ny, nz, nc, gr)
    integer, intent(in) :: nx, ny, nz, nc
    type(grid_t), intent(out) :: gr
    integer(gp), allocatable :: node_first(:), cnt(:)
    integer :: np, p, key, c
    integer(gp) :: g
    np = comm%size
    gr%nx = nx
    gr%ny = ny
    gr%nz = nz
    gr%nc = nc
    allocate(gr%part(nx*ny*nz), gr%node_gid(nx*ny*nz), node_first(0:np), cnt(0:np-1))
    cnt = 0
    do key = 1, nx*ny*nz
      gr%part(key) = min(np - 1, (np * mod(key - 1, nx)) / nx)
      cnt(gr%part(key)) = cnt(gr%part(key)) + 1
    end do
    node_first(0) = 1
    do p = 1, np
      node_first(p) = node_first(p-1) + cnt(p-1)
    end do
    cnt = 0
    do key = 1, nx*ny*nz
      p = gr%part(key)
      gr%node_gid(key) = node_first(p) + cnt(p)
      cnt(p) = cnt(p) + 1
    end do
    allocate(gr%offsets(0:np), gr%gid_key(int(nx, gp)*ny*nz*nc))
    gr%offsets = nc * (node_first - 1) + 1
    do key = 1, nx*ny*nz
      do c = 1, nc
        g = nc * (gr%node_gid(key) - 1) + c
        gr%gid_key(g) = int(nc, gp) * (key - 1) + c
      end do
    end do
  end subroutine make_grid

  !> Node coefficient of the Laplacians: 1, or jump in a checkerboard of
  !> 4^3 blocks.
  real(rp) function coefficient(gr, key, jump)
    type(grid_t), intent(in) :: gr
    integer, intent(in) :: key
    real(rp), intent(in) :: jump
    integer :: ix, iy, iz
    ix = mod(key - 1, gr%nx)
    iy = mod((key - 1) / gr%nx, gr%ny)
    iz = (key - 1) / (gr%nx * gr%ny)
    coefficient = 1.0_rp
    if (mod(ix / 4 + iy / 4 + iz / 4, 2) == 1) coefficient = jump
  end function coefficient

  !> The matrix of problem kind on grid gr, owned rows of this rank, with
  !> keys. kind 'lap7': 7-point Laplacian (nc = 1), Dirichlet outside the
  !> grid, node coefficients (harmonic means on the links), jump: see
  !> coefficient(). kind 'vec27': Q1 Laplacian plus 0.01 times the Q1 mass
  !> matrix (unit cells, 27 points), times a 3 x 3 SPD coupling of the
  !> components (nc = 3): 81 entries per interior row like Q1 elasticity.
  subroutine build_matrix(gr, kind, jump, a)
    type(grid_t), intent(in) :: gr
    character(len=*), intent(in) :: kind
    real(rp), intent(in) :: jump
    type(global_csr_t), intent(out) :: a
    real(rp), parameter :: m3(3,3) = reshape([2.0_rp, 0.5_rp, 0.2_rp, 0.5_rp, 2.0_rp, 0.3_rp, &
                                              0.2_rp, 0.3_rp, 2.0_rp], [3, 3])
    integer(gp), allocatable :: cols(:)
    real(rp), allocatable :: vals(:), w(:)
    integer(ip), allocatable :: pos(:)
    integer :: key, nb, ix, iy, iz, dx, dy, dz, jx, jy, jz, c, c2, m, me, cap, i
    integer(gp) :: row, rkey, ckey
    real(rp) :: s, ci, cn
    me = comm%rank
    a%comm = comm
    a%row_offsets = gr%offsets
    a%col_offsets = gr%offsets
    a%n_rows = int(gr%offsets(me+1) - gr%offsets(me), ip)
    cap = a%n_rows * 27 * gr%nc + 1
    allocate(a%row_ptr(a%n_rows + 1), a%gcol(cap), a%val(cap), a%key(a%n_rows))
    allocate(cols(27 * gr%nc), vals(27 * gr%nc), w(27 * gr%nc), pos(27 * gr%nc))
    a%row_ptr(1) = 1
    do key = 1, gr%nx * gr%ny * gr%nz
      if (gr%part(key) /= me) cycle
      ix = mod(key - 1, gr%nx)
      iy = mod((key - 1) / gr%nx, gr%ny)
      iz = (key - 1) / (gr%nx * gr%ny)
      do c = 1, gr%nc
        row = gr%nc * (gr%node_gid(key) - 1) + c
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
              if (kind == 'lap7') then
                if (abs(dx) + abs(dy) + abs(dz) > 1) cycle
                if (nb == key) then
                  s = lap7_diagonal(gr, ix, iy, iz, jump)
                else
                  ci = coefficient(gr, key, jump)
                  cn = coefficient(gr, nb, jump)
                  s = -2.0_rp * ci * cn / (ci + cn)
                end if
                m = m + 1
                cols(m) = gr%node_gid(nb)
                ckey = nb
                vals(m) = s * wiggle(rkey, ckey, comm%size)
              else
                s = q1_entry(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz) + &
                    q1_mass(ix, jx, gr%nx) * q1_entry(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz) + &
                    q1_mass(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_entry(iz, jz, gr%nz) + &
                    0.01_rp * q1_mass(ix, jx, gr%nx) * q1_mass(iy, jy, gr%ny) * q1_mass(iz, jz, gr%nz)
                do c2 = 1, gr%nc
                  m = m + 1
                  cols(m) = gr%nc * (gr%node_gid(nb) - 1) + c2
                  ckey = gr%gid_key(cols(m))
                  vals(m) = s * m3(c, c2) * wiggle(rkey, ckey, comm%size)
                end do
              end if
            end do
          end do
        end do
        call sort_gids(cols(1:m), pos(1:m))
        w(1:m) = vals(pos(1:m))
        i = int(row - a%row_offsets(me), ip) + 1
        a%gcol(a%row_ptr(i):a%row_ptr(i) + m - 1) = cols(1:m)
        a%val(a%row_ptr(i):a%row_ptr(i) + m - 1) = w(1:m)
        a%row_ptr(i + 1) = a%row_ptr(i) + m
        a%key(i) = rkey
      end do
    end do
    a%gcol = a%gcol(1:a%row_ptr(a%n_rows + 1) - 1)
    a%val = a%val(1:a%row_ptr(a%n_rows + 1) - 1)
  end subroutine build_matrix

  !> Diagonal of the 7-point row of node (ix, iy, iz): the sum of its six
  !> links (harmonic means; a link leaving the grid goes to a Dirichlet node
  !> with this node's coefficient).
  real(rp) function lap7_diagonal(gr, ix, iy, iz, jump)
    type(grid_t), intent(in) :: gr
    integer, intent(in) :: ix, iy, iz
    real(rp), intent(in) :: jump
    integer, parameter :: dirs(3, 6) = reshape([-1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1], [3, 6])
    integer :: d, jx, jy, jz
    real(rp) :: ci, cn
    ci = coefficient(gr, 1 + ix + gr%nx * (iy + gr%ny * iz), jump)
    lap7_diagonal = 0.0_rp
    do d = 1, 6
      jx = ix + dirs(1, d)
      jy = iy + dirs(2, d)
      jz = iz + dirs(3, d)
      if (jx < 0 .or. jx >= gr%nx .or. jy < 0 .or. jy >= gr%ny .or. jz < 0 .or. jz >= gr%nz) then
        lap7_diagonal = lap7_diagonal + ci
      else
        cn = coefficient(gr, 1 + jx + gr%nx * (jy + gr%ny * jz), jump)
        lap7_diagonal = lap7_diagonal + 2.0_rp * ci * cn / (ci + cn)
      end if
    end do
  end function lap7_diagonal

  !> Dense copy (by keys, n x n, the same on every rank) of a square
  !> matrix whose column keys are those of gr.
  subroutine gather_dense(gr, a, d)
    type(grid_t), intent(in) :: gr
    type(global_csr_t), intent(in) :: a
    real(rp), intent(out) :: d(:,:)
    real(rp), allocatable :: flat(:)
    integer :: n, i, k
    n = size(d, 1)
    allocate(flat(n * n))
    flat = 0.0_rp
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        flat(int(a%key(i) - 1) * n + int(gr%gid_key(a%gcol(k)))) = a%val(k)
      end do
    end do
    call comm%sum_all(flat)
    d = transpose(reshape(flat, [n, n]))
  end subroutine gather_dense

  !> csr_matrix_t of a on the row map rmap (no ghosts; to_csr builds the
  !> column map).
  subroutine make_operator(a, rmap, m)
    type(global_csr_t), intent(in) :: a
    type(index_map_t), intent(inout), target :: rmap
    type(csr_matrix_t), intent(inout) :: m
    integer(gp) :: none(0)
    call rmap%init(comm, a%n_rows, none)
    call to_csr(a, rmap, m)
  end subroutine make_operator

  ! ---- tests ---------------------------------------------------------------

  !> Bad settings are refused by name.
  subroutine test_settings()
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    call p%validate(st)
    call suite%assert_true(st%ok(), 'settings: the defaults are valid')
    p%max_steps = -1
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'max_steps = -1') > 0, &
                           'settings: max_steps < 0 refused by name: '//trim(st%msg))
    call st%clear()
    p = fsai_params_t()
    p%step_size = 0
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'step_size = 0') > 0, &
                           'settings: step_size = 0 refused by name')
    call st%clear()
    p = fsai_params_t()
    p%init = 'upper'
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'init = ''upper''') > 0, &
                           'settings: init = ''upper'' refused by name')
    call st%clear()
    p = fsai_params_t()
    p%tol = -1.0_rp
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'tol') > 0, 'settings: tol < 0 refused by name')
    call st%clear()
    p = fsai_params_t()
    p%drop = 1.5_rp
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'drop') > 0, 'settings: drop >= 1 refused by name')
  end subroutine test_settings

  !> A negative diagonal entry in the last node's row: every rank reports
  !> it with that row's key; so does a matrix that is indefinite in a 2 x 2
  !> principal block (lower start).
  subroutine test_not_spd()
    type(grid_t) :: gr
    type(global_csr_t) :: a, g
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    integer :: i, k
    character(len=msg_len) :: want
    call make_grid(4, 4, 4, 1, gr)
    call build_matrix(gr, 'lap7', 1.0_rp, a)
    do i = 1, a%n_rows
      if (a%key(i) /= 64) cycle
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        if (gr%gid_key(a%gcol(k)) == 64) a%val(k) = -1.0_rp
      end do
    end do
    p%init = 'diagonal'
    p%max_steps = 0
    call afsai_factor(a, p, g, st)
    write(want, '(a)') 'with key 64)'
    call suite%assert_true(.not. st%ok() .and. index(st%msg, trim(want)) > 0, &
                           'not SPD: a negative diagonal is reported on every rank: '//trim(st%msg))
    ! off-diagonal links stronger than the diagonal: A[P,P] or d fails
    call build_matrix(gr, 'lap7', 1.0_rp, a)
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        if (gr%gid_key(a%gcol(k)) /= a%key(i)) a%val(k) = -5.0_rp
      end do
    end do
    call st%clear()
    p = fsai_params_t()
    call afsai_factor(a, p, g, st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'not symmetric positive definite') > 0, &
                           'not SPD: an indefinite matrix is reported (lower start)')
  end subroutine test_not_spd

  !> (a) 5^3 Laplacian with jumping coefficients, a pattern that grows to
  !> the full lower triangle: G = L^-1.
  subroutine test_exact()
    integer, parameter :: ns = 5, n = ns**3
    interface
      subroutine dpotrf(uplo, n, a, lda, info)
        import :: rp
        character(len=1), intent(in) :: uplo
        integer, intent(in) :: n, lda
        real(rp), intent(inout) :: a(lda, *)
        integer, intent(out) :: info
      end subroutine dpotrf
      subroutine dtrtri(uplo, diag, n, a, lda, info)
        import :: rp
        character(len=1), intent(in) :: uplo, diag
        integer, intent(in) :: n, lda
        real(rp), intent(inout) :: a(lda, *)
        integer, intent(out) :: info
      end subroutine dtrtri
    end interface
    type(grid_t) :: gr
    type(global_csr_t) :: a, g
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: ad(:,:), gd(:,:)
    real(rp) :: err
    integer :: info, i
    call make_grid(ns, ns, ns, 1, gr)
    call build_matrix(gr, 'lap7', 30.0_rp, a)
    p%init = 'lower'
    p%step_size = n
    p%max_steps = 3 * ns
    p%tol = 0.0_rp
    call afsai_factor(a, p, g, st)
    call suite%assert_true(st%ok(), 'exact: afsai_factor succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_equal_int(int(g%global_nnz()), n * (n + 1) / 2, &
                                'exact: the pattern grows to the full lower triangle')
    allocate(ad(n, n), gd(n, n))
    call gather_dense(gr, a, ad)
    call gather_dense(gr, g, gd)
    call dpotrf('L', n, ad, n, info)
    call dtrtri('L', 'N', n, ad, n, info)
    do i = 1, n
      ad(i, i+1:n) = 0.0_rp
    end do
    err = maxval(abs(gd - ad)) / maxval(abs(ad))
    call suite%assert_close(err, 0.0_rp, 1.0e-10_rp, 'exact: G = L^-1 (A = L L^T in key order), relative')
  end subroutine test_exact

  !> (b) PCG on a 20^3 Laplacian with coefficient jumps 1 : 1000, with
  !> 0, 3, 6 adaptive steps; (c) symmetry of M.
  subroutine test_adaptive()
    integer, parameter :: steps(3) = [0, 3, 6]
    type(grid_t) :: gr
    type(global_csr_t) :: a, gb
    type(index_map_t), target :: rmap
    type(csr_matrix_t) :: m
    type(afsai_precon_t) :: pre
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    type(cg_t) :: solver
    type(solve_info_t) :: info
    real(rp), allocatable :: b(:), x(:), y(:), mx(:), my(:)
    integer :: its(3), t, i, k, bad
    real(rp) :: s1, s2
    character(len=msg_len) :: line
    call make_grid(20, 20, 20, 1, gr)
    call build_matrix(gr, 'lap7', 1000.0_rp, a)
    call make_operator(a, rmap, m)
    allocate(b(a%n_rows), x(a%n_rows), y(a%n_rows), mx(a%n_rows), my(a%n_rows))
    do i = 1, a%n_rows
      b(i) = sin(real(a%key(i), rp))
      y(i) = cos(3.0_rp * real(a%key(i), rp))
    end do
    call solver%init(comm, rtol=1.0e-8_rp, max_iter=3000)
    do t = 1, 3
      p = fsai_params_t()
      p%max_steps = steps(t)
      call pre%setup(m, p, st, a%key)
      call suite%assert_true(st%ok(), 'adaptive: set-up succeeds: '//trim(st%msg))
      if (.not. st%ok()) return
      x = 0.0_rp
      call solver%solve(m, pre, b, x, info)
      its(t) = info%iterations
      write(line, '(a,i0,a,i0,a,f6.2,a,f8.4,a)') 'adaptive: max_steps = ', steps(t), ': ', its(t), &
        ' PCG iterations, nnz(G)/n = ', real(pre%nnz_factor(), rp) / 8000.0_rp, ', set-up ', pre%setup_time, ' s'
      call suite%assert_true(info%converged, trim(line))
      ! G lower triangular by key
      call from_csr(pre%g, gb)
      bad = 0
      do i = 1, gb%n_rows
        do k = gb%row_ptr(i), gb%row_ptr(i+1) - 1
          if (gr%gid_key(gb%gcol(k)) > a%key(i)) bad = bad + 1
          if (gr%gid_key(gb%gcol(k)) == a%key(i) .and. .not. (gb%val(k) > 0.0_rp)) bad = bad + 1
        end do
      end do
      call suite%assert_true(comm%sum(bad) == 0, 'adaptive: G is lower triangular by key with a positive diagonal')
      if (t == 3) then
        ! (c) symmetry
        call pre%apply(b, mx)
        call pre%apply(y, my)
        s1 = pdot(comm, y, mx)
        s2 = pdot(comm, b, my)
        call suite%assert_close(abs(s1 - s2) / max(abs(s1), abs(s2)), 0.0_rp, 1.0e-12_rp, &
                                'symmetric: (y, M x) = (x, M y), relative')
      end if
      call pre%free()
    end do
    call suite%assert_true(its(2) <= its(1) .and. its(3) <= its(2) .and. its(3) < its(1), &
                           'adaptive: iterations do not increase with the steps and fall overall')
    ! without keys (the global ids order the rows): still a working preconditioner
    call pre%setup(m, fsai_params_t(), st)
    x = 0.0_rp
    if (st%ok()) call solver%solve(m, pre, b, x, info)
    call suite%assert_true(st%ok() .and. info%converged, 'adaptive: set-up without keys (global ids) works')
    call pre%free()
    call m%free()
  end subroutine test_adaptive

  ! ---- factors for the rank comparison ---------------------------------------

  subroutine write_factors()
    type(grid_t) :: gr
    type(global_csr_t) :: a, g
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    logical :: all_ok
    call make_grid(20, 20, 20, 1, gr)
    call build_matrix(gr, 'lap7', 1000.0_rp, a)
    p%max_steps = 3
    call afsai_factor(a, p, g, st)
    call write_entries(comm, g, gr%gid_key, path, 'jumping coefficients, lower start, 3 steps', .true.)
    all_ok = st%ok()
    call make_grid(12, 11, 10, 1, gr)
    call build_matrix(gr, 'lap7', 1.0_rp, a)
    p = fsai_params_t()
    call afsai_factor(a, p, g, st)
    call write_entries(comm, g, gr%gid_key, path, 'constant coefficients, default settings', .false.)
    all_ok = all_ok .and. st%ok()
    p%init = 'diagonal'
    p%max_steps = 8
    p%step_size = 3
    p%drop = 0.05_rp
    call afsai_factor(a, p, g, st)
    call write_entries(comm, g, gr%gid_key, path, 'constant coefficients, diagonal start, 8 steps of 3, drop 0.05', .false.)
    all_ok = all_ok .and. st%ok()
    call make_grid(6, 5, 4, 3, gr)
    call build_matrix(gr, 'vec27', 0.0_rp, a)
    p = fsai_params_t()
    call afsai_factor(a, p, g, st)
    call write_entries(comm, g, gr%gid_key, path, 'vector Laplacian (81 per row), default settings', .false.)
    all_ok = all_ok .and. st%ok()
    call suite%assert_true(all_ok, 'factors written to '//trim(path))
  end subroutine write_factors

  ! ---- timings -----------------------------------------------------------

  !> Set-up of the preconditioner (defaults) on the vector Laplacian of
  !> (10s+1) x (10s+1) x (s+1) nodes, and PCG with it and with Jacobi.
  subroutine report_timings(s)
    integer, intent(in) :: s
    type(grid_t) :: gr
    type(global_csr_t) :: a
    type(index_map_t), target :: rmap
    type(csr_matrix_t) :: m
    type(afsai_precon_t) :: pre
    type(jacobi_precon_t) :: jac
    type(fsai_params_t) :: p
    type(error_status_t) :: st
    type(cg_t) :: solver
    type(solve_info_t) :: info
    type(global_csr_t) :: g
    real(rp), allocatable :: b(:), x(:)
    real(rp) :: t0, tb, tf
    integer :: i
    t0 = wall_time()
    call make_grid(10*s + 1, 10*s + 1, s + 1, 3, gr)
    call build_matrix(gr, 'vec27', 0.0_rp, a)
    call make_operator(a, rmap, m)
    tb = wall_time() - t0
    allocate(b(a%n_rows), x(a%n_rows))
    do i = 1, a%n_rows
      b(i) = sin(real(a%key(i), rp))
    end do
    t0 = wall_time()
    call afsai_factor(a, p, g, st)
    tf = wall_time() - t0
    call g%free()
    call pre%setup(m, p, st, a%key)
    if (comm%rank == 0) then
      write(output_unit, '(a,f8.3,a)') 'timing: afsai_factor alone (defaults) ', tf, ' s'
      write(output_unit, '(a,i0,a,i0,a,f6.2,a)') 'timing: vector Laplacian, ', gr%offsets(comm%size) - 1, &
        ' rows on ', comm%size, ' ranks (built in ', tb, ' s)'
      write(output_unit, '(a,f8.3,a,f6.2,a,a)') 'timing: afsai set-up (defaults) ', pre%setup_time, &
        ' s, nnz(G)/n = ', real(pre%nnz_factor(), rp) / real(gr%offsets(comm%size) - 1, rp), ', ', trim(st%msg)
    end if
    call solver%init(comm, rtol=1.0e-8_rp, max_iter=5000)
    x = 0.0_rp
    call solver%solve(m, pre, b, x, info)
    if (comm%rank == 0) write(output_unit, '(a,i0,a,f8.3,a)') 'timing: PCG + afsai: ', info%iterations, &
      ' iterations, ', info%solve_time, ' s'
    call jac%setup(m, st)
    x = 0.0_rp
    call solver%solve(m, jac, b, x, info)
    if (comm%rank == 0) write(output_unit, '(a,i0,a,f8.3,a)') 'timing: PCG + jacobi: ', info%iterations, &
      ' iterations, ', info%solve_time, ' s'
    flush(output_unit)
    call pre%free()
    call m%free()
  end subroutine report_timings
end program test_afsai
