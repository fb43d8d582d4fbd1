!> Unit tests of the hypre binding (hypre_ij) and of the BoomerAMG
!> preconditioner (boomeramg_precon, amg_params). Runs on 1 or more ranks.
!>
!> The matrices are 3D 7-point Laplacians on an n^3 grid of nodes with the
!> Dirichlet boundary eliminated, nf interleaved components per node (global
!> dof nf*(node-1)+c, whole nodes per rank, contiguous in rank order), each
!> component scaled by its own factor and decoupled from the others.
program test_boomeramg
  use, intrinsic :: iso_c_binding, only: c_associated
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t, sort_gids
  use csr_matrix, only: csr_matrix_t
  use dist_vector, only: pnorm2
  use amg_params, only: amg_params_t, amg_line_len
  use boomeramg_precon, only: boomeramg_precon_t
  use precon, only: precon_t
  use inner_cg_precon, only: inner_cg_precon_t
  use global_csr, only: global_csr_t, union_to_csr, add_to_csr, add_csr_to_csr, from_csr, gcsr_multiply
  use sum_rows, only: sum_rows_t
  use hypre_ij, only: hypre_ij_t
  use assertions, only: test_suite_t
  use fixture_matrices, only: build_laplacian
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite

  call comm%init_world()
  call suite%init('boomeramg', comm)
  call test_params(suite)
  call test_scalar(suite, comm)
  call test_rows(suite, comm)
  call test_long_rows(suite, comm)
  call test_systems(suite, comm)
  call test_dof_func(suite, comm)
  call test_own_cycle(suite, comm)
  call test_lagged(suite, comm)
  call test_galerkin(suite, comm, 'double')
  call test_galerkin(suite, comm, 'single')
  call test_single(suite, comm)
  call suite%finish()

contains

  !> amg_params: defaults pass, every bad value is caught and named, the echo
  !> holds every field.
  subroutine test_params(suite)
    type(test_suite_t), intent(inout) :: suite
    type(amg_params_t) :: p, q
    type(error_status_t) :: st
    character(len=amg_line_len), allocatable :: lines(:)
    integer :: down, up

    call p%validate(st)
    call suite%assert_true(st%ok(), 'params: the defaults are valid')
    call suite%assert_equal_int(p%coarsen_id(), 10, 'params: hmis is coarsen type 10')
    call suite%assert_equal_int(p%interp_id(), 6, 'params: ext+i is interpolation 6')
    call suite%assert_equal_int(p%agg_interp_id(), 4, 'params: multipass is aggressive interpolation 4')
    call p%relax_ids(down, up)
    call suite%assert_true(down == 13 .and. up == 14, 'params: l1-gs is 13 down, 14 up')

    p%coarsen_type = 'PMIS'
    call suite%assert_equal_int(p%coarsen_id(), 8, 'params: names are case-insensitive (PMIS = 8)')

    p = amg_params_t()
    p%coarsen_type = 'foo'
    call expect_bad(suite, p, 'coarsen_type')
    p = amg_params_t()
    p%interp_type = 'ext+j'
    call expect_bad(suite, p, 'interp_type')
    p = amg_params_t()
    p%relax_type = 'sor'
    call expect_bad(suite, p, 'relax_type')
    p = amg_params_t()
    p%agg_interp_type = 'ext+i'
    call expect_bad(suite, p, 'agg_interp_type')
    p = amg_params_t()
    p%strong_threshold = 1.5_rp
    call expect_bad(suite, p, 'strong_threshold')
    p = amg_params_t()
    p%nodal = 5
    call expect_bad(suite, p, 'nodal')
    p = amg_params_t()
    p%num_functions = 1
    p%nodal = 1
    call expect_bad(suite, p, 'nodal')
    p = amg_params_t()
    p%num_functions = 0
    call expect_bad(suite, p, 'num_functions')
    p = amg_params_t()
    p%agg_num_levels = 25
    call expect_bad(suite, p, 'agg_num_levels')
    p = amg_params_t()
    p%max_row_sum = 0.0_rp
    call expect_bad(suite, p, 'max_row_sum')
    p = amg_params_t()
    p%print_level = 4
    call expect_bad(suite, p, 'print_level')
    p = amg_params_t()
    p%cycle_type = 'f'
    call expect_bad(suite, p, 'cycle_type')
    p = amg_params_t()
    p%relax_order = 'c-f'
    call expect_bad(suite, p, 'relax_order')
    p = amg_params_t()
    p%cycle_code = 'petsc'
    call expect_bad(suite, p, 'cycle_code')
    p = amg_params_t()
    p%precision = 'half'
    call expect_bad(suite, p, 'precision')
    p = amg_params_t()
    p%slab_threshold = 1.0_rp
    call expect_bad(suite, p, 'slab_threshold')
    p%slab_threshold = -0.1_rp
    call expect_bad(suite, p, 'slab_threshold')
    ! on a slab the threshold is raised to slab_threshold, never lowered,
    ! and 0 leaves it as it is; the rest is kept
    p = amg_params_t()
    q = p%for_slab()
    call suite%assert_true(q%strong_threshold == 0.8_rp .and. q%coarsen_type == p%coarsen_type .and. &
                           q%num_functions == 3, 'params: for_slab raises the default 0.5 to slab_threshold 0.8')
    p%strong_threshold = 0.95_rp
    q = p%for_slab()
    call suite%assert_true(q%strong_threshold == 0.95_rp, 'params: for_slab keeps a strong_threshold above it')
    p%strong_threshold = 0.5_rp
    p%slab_threshold = 0.0_rp
    q = p%for_slab()
    call suite%assert_true(q%strong_threshold == 0.5_rp, 'params: slab_threshold 0 leaves strong_threshold')
    p = amg_params_t()
    call suite%assert_equal_int(p%cycle_id(), 1, 'params: the default cycle is the V-cycle (1)')
    p%cycle_type = 'W'
    call suite%assert_equal_int(p%cycle_id(), 2, 'params: cycle_type W is 2')
    p = amg_params_t()
    call suite%assert_equal_int(p%relax_order_id(), 0, 'params: the default sweep order is lexicographic (0)')
    p%relax_order = 'CF'
    call suite%assert_equal_int(p%relax_order_id(), 1, 'params: relax_order CF is 1')

    p = amg_params_t()
    call p%to_lines(lines)
    call suite%assert_equal_int(size(lines), 25, 'params: one echo line per field')
    call suite%assert_true(any(lines == 'coarsen_type = hmis') .and. any(lines == 'num_functions = 3') &
                           .and. any(lines == 'strong_threshold = 0.500000') .and. any(lines == 'cycle_type = v'), &
                           'params: echo lines read "name = value"')
  end subroutine test_params

  !> p must fail validation with a message that names field.
  subroutine expect_bad(suite, p, field)
    type(test_suite_t), intent(inout) :: suite
    type(amg_params_t), intent(in) :: p
    character(len=*), intent(in) :: field
    type(error_status_t) :: st
    call p%validate(st)
    call suite%assert_true(.not. st%ok() .and. index(st%msg, field//' = ') > 0, &
                           'params: a bad '//field//' is reported by name')
  end subroutine expect_bad

  !> Scalar Laplacian, 30^3 unknowns: hypre's product equals ours; the AMG
  !> V-cycle as a stationary iteration reduces the residual by 1e-6 in at
  !> most 30 cycles; update() with 2A halves M^-1 r; a changed pattern (other
  !> rows, or one column moved) is refused.
  subroutine test_scalar(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map, row_map2, col_map2
    type(csr_matrix_t) :: a, a2, a3
    type(boomeramg_precon_t) :: amg
    type(amg_params_t) :: p
    type(error_status_t) :: st, st2, st3
    real(rp), allocatable :: x(:), y(:), yh(:), z1(:), z2(:)
    integer :: cycles, ierr
    real(rp) :: red

    call build_laplacian(comm, 30, 1, [1.0_rp], row_map, col_map, a)
    p%num_functions = 1
    ! hypre's copy is compared to the last bit: its values stay double
    ! (test_single for the floats in place)
    p%precision = 'double'
    call amg%setup(a, p, st)
    call suite%assert_true(st%ok(), 'scalar: setup succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_true(amg%name() == 'boomeramg', 'scalar: name is boomeramg')
    call amg%measure_hierarchy(st)
    call suite%assert_true(st%ok(), 'scalar: measure_hierarchy succeeds')
    call suite%assert_true(amg%num_levels >= 3 .and. amg%level_rows(1) == 27000_gp .and. &
                           amg%grid_complexity > 1.0_rp .and. amg%grid_complexity < 3.0_rp, &
                           'scalar: hierarchy of >= 3 levels, 27000 fine rows, grid complexity in (1,3)')
    call suite%assert_true(amg%setup_time > 0.0_rp, 'scalar: setup is timed')
    call report_hierarchy(comm, amg)

    allocate(x(a%n_rows), y(a%n_rows), yh(a%n_rows), z1(a%n_rows), z2(a%n_rows))
    call fill_test_vector(a, x)
    call a%apply(x, y)
    call amg%ij%matvec(x, yh, ierr)
    call suite%assert_equal_int(ierr, 0, 'scalar: hypre matvec reports no error')
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'scalar: hypre ParCSR matvec equals csr_matrix%apply')

    call stationary(comm, a, amg, y, 30, cycles, red)
    if (comm%rank == 0) write(*, '(a,i0,a,es10.3)') '  scalar Laplacian: ', cycles, &
      ' V-cycles, residual reduction ', red
    call suite%assert_true(red <= 1.0e-6_rp .and. cycles <= 30, &
                           'scalar: stationary AMG iteration reduces the residual by 1e-6 in <= 30 cycles')
    call suite%assert_equal_int(amg%apply_errors, 0, 'scalar: no hypre error while applying')

    ! new values, same pattern: M(2A)^-1 r = M(A)^-1 r / 2 (AMG is scale-invariant)
    call amg%apply(x, z1)
    a%val = 2.0_rp * a%val
    call amg%update(a, st)
    call suite%assert_true(st%ok(), 'scalar: update succeeds: '//trim(st%msg))
    call amg%apply(x, z2)
    call suite%assert_close_array(z2 / maxval(abs(z1)), 0.5_rp * z1 / maxval(abs(z1)), 1.0e-10_rp, &
                                  'scalar: after update(2A) the V-cycle gives half of before')
    call amg%update(a, st)
    call suite%assert_true(st%ok(), 'scalar: a second update with the same pattern succeeds: '//trim(st%msg))
    call a%apply(x, y)
    call amg%ij%matvec(x, yh)
    call suite%assert_close_array(yh, y, 2.0e-12_rp, 'scalar: hypre matvec equals ours after update')

    ! a different pattern is refused on every rank
    call build_laplacian(comm, 8, 1, [1.0_rp], row_map2, col_map2, a2)
    call amg%update(a2, st2)
    call suite%assert_true(.not. st2%ok() .and. index(st2%msg, 'pattern') > 0, &
                           'scalar: update with another pattern is refused')
    ! the same row lengths, one column moved on rank 0 only: refused on every rank
    a3 = a
    if (comm%rank == 0 .and. a3%n_rows > 0) a3%col(a3%row_ptr(2) - 1) = a3%col(a3%row_ptr(2) - 1) + 1
    call amg%update(a3, st3)
    call suite%assert_true(.not. st3%ok() .and. index(st3%msg, 'pattern') > 0, &
                           'scalar: update with one column moved (same row lengths) is refused')
    call amg%free()
    call suite%assert_true(.not. amg%ij%is_ready() .and. amg%num_levels == 0, &
                           'scalar: free releases the hypre objects')
    call a%free()
    call a2%free()
  end subroutine test_scalar

  !> setup_rows and update_rows on a sum given row by row (sum_rows: a
  !> scalar Laplacian A plus alpha G, G the graph Laplacian of a matching of
  !> row i with row i + n/2, whose couplings lie outside A's pattern and
  !> mostly on another rank; 27000 rows, given to hypre 997 entries at a
  !> time): hypre's product and V-cycle are those of the sum assembled
  !> (union_to_csr), so is sum_rows' diagonal; update_rows takes new values;
  !> PCG steps with the AMG's products (no matrix here) give those with the
  !> assembled sum's.
  subroutine test_rows(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t), target :: a, s
    type(global_csr_t), target :: g
    type(sum_rows_t) :: src, src3
    type(hypre_ij_t) :: ij
    type(boomeramg_precon_t) :: amg, plain
    class(precon_t), allocatable :: inner1, inner2
    type(inner_cg_precon_t) :: cg_by_inner, cg_by_s
    type(amg_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:), yh(:), z1(:), z2(:), d(:), ds(:)
    logical :: fits

    call build_laplacian(comm, 30, 1, [1.0_rp], row_map, col_map, a)
    call matching_laplacian(row_map, g)
    call union_to_csr(a, g, row_map, s)      ! A's values on the union of the patterns
    call add_to_csr(2.0_rp, g, s, fits)
    call suite%assert_true(fits, 'rows: the assembled sum A + 2 G')
    call src%init(a, g, 2.0_rp)
    p%num_functions = 1
    p%precision = 'double'   ! products compared to the last bit
    amg%ij%block_entries = 997
    call amg%setup_rows(src, p, st)
    call suite%assert_true(st%ok(), 'rows: setup_rows succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call suite%assert_true(comm%sum(int(amg%ij%nnz, gp)) == s%global_nnz(), &
                           'rows: hypre holds the non-zeros of the assembled sum')
    call plain%setup(s, p, st)
    allocate(x(s%n_rows), y(s%n_rows), yh(s%n_rows), z1(s%n_rows), z2(s%n_rows), d(s%n_rows), ds(s%n_rows))
    call fill_test_vector(s, x)
    call s%apply(x, y)
    call amg%matrix_product(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'rows: matrix_product equals the assembled sum''s')
    call amg%apply(x, z1)
    call plain%apply(x, z2)
    call suite%assert_close_array(z1, z2, 1.0e-10_rp, 'rows: the V-cycle is the one of the assembled sum''s')
    call src%diagonal(d)
    call s%diagonal(ds)
    call suite%assert_close_array(d, ds, 1.0e-14_rp, 'rows: sum_rows%diagonal is the assembled sum''s')

    ! new values: A + 5 G, against the assembled sum of the same
    src%alpha_g = 5.0_rp
    call amg%update_rows(src, st)
    call suite%assert_true(st%ok(), 'rows: update_rows succeeds: '//trim(st%msg))
    call suite%assert_true(amg%ij%overwrites == 1, 'rows: update_rows with the same pattern writes in place')
    s%val = 0.0_rp
    call add_csr_to_csr(1.0_rp, a, s, fits)
    call add_to_csr(5.0_rp, g, s, fits)
    call s%apply(x, y)
    call amg%matrix_product(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'rows: matrix_product is A + 5 G after update_rows')
    ! a third term that meets the second's appended entries: A + 6 G - G,
    ! each entry once (hypre's non-zeros) with A + 5 G's values
    call src3%init(a, g, 6.0_rp, g, -1.0_rp)
    call ij%init_rows(src3, st)
    call suite%assert_true(st%ok() .and. comm%sum(int(ij%nnz, gp)) == s%global_nnz(), &
                           'rows: A + 6 G - G has the entries of the assembled A + 5 G, each once')
    call ij%matvec(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'rows: A + 6 G - G by rows is A + 5 G')
    call ij%free()

    ! two PCG steps: products by the inner AMG (no matrix) against s's
    allocate(boomeramg_precon_t :: inner1, inner2)
    select type (inner1)
    type is (boomeramg_precon_t)
      call inner1%setup_rows(src, p, st)
    end select
    select type (inner2)
    type is (boomeramg_precon_t)
      call inner2%setup(s, p, st)
    end select
    call cg_by_inner%init_steps(inner1, 2)
    call cg_by_s%init_steps(inner2, 2, s)
    call cg_by_inner%apply(x, z1)
    call cg_by_s%apply(x, z2)
    call suite%assert_close_array(z1, z2, 1.0e-10_rp, 'rows: PCG steps by the inner AMG''s products give s''s')
    call cg_by_inner%free()
    call cg_by_s%free()

    call amg%free()
    call plain%free()
    call a%free()
    call s%free()
    call g%free()
  end subroutine test_rows

  !> sum_rows with long rows (the walk along a sorted row, taken from 8
  !> entries of g's row on): A + 0.5 A^2 - 0.25 A^2 (A^2's rows: up to 25
  !> entries, 7 in A's pattern, the rest appended by the first term and met
  !> again by the second) gives hypre the entries of the assembled
  !> A + 0.25 A^2, each once, and its product. rebuild_rows with new values
  !> of the same pattern writes them in place (hypre_ij's overwrite), to the
  !> bit as a new IJ matrix holds them; with another pattern it builds anew.
  subroutine test_long_rows(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t), target :: a, s
    type(global_csr_t), target :: ga, a2
    type(sum_rows_t) :: src
    type(hypre_ij_t) :: ij, fresh
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:), yh(:)
    logical :: fits

    call build_laplacian(comm, 12, 1, [1.0_rp], row_map, col_map, a)
    call from_csr(a, ga)
    call gcsr_multiply(ga, ga, a2)
    call suite%assert_true(comm%max(maxval(a2%row_ptr(2:) - a2%row_ptr(:a2%n_rows))) >= 20, &
                           'long rows: A^2 has rows of 20 entries and more')
    call union_to_csr(a, a2, row_map, s)
    call add_to_csr(0.25_rp, a2, s, fits)
    call suite%assert_true(fits, 'long rows: the assembled sum A + 0.25 A^2')
    call src%init(a, a2, 0.5_rp, a2, -0.25_rp)
    call ij%init_rows(src, st)
    call suite%assert_true(st%ok() .and. comm%sum(int(ij%nnz, gp)) == s%global_nnz(), &
                           'long rows: A + 0.5 A^2 - 0.25 A^2 has the entries of A + 0.25 A^2, each once')
    allocate(x(s%n_rows), y(s%n_rows), yh(s%n_rows))
    call fill_test_vector(s, x)
    call s%apply(x, y)
    call ij%matvec(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'long rows: the product by rows is A + 0.25 A^2''s')
    ! new values of the same pattern go into hypre's arrays in place, where
    ! a new IJ matrix puts them: the products agree to the last bit
    src%alpha_g = 0.7_rp
    src%alpha_h = -0.2_rp
    call ij%rebuild_rows(src, st)
    call suite%assert_true(st%ok() .and. ij%overwrites == 1, 'long rows: rebuild_rows with the same pattern '// &
                           'writes in place')
    call fresh%init_rows(src, st)
    call ij%matvec(x, yh)
    call fresh%matvec(x, y)
    call suite%assert_close_array(yh, y, 0.0_rp, 'long rows: ... the product of a new IJ matrix, bit for bit')
    ! another pattern (A alone): built anew, not written in place
    call src%init(a)
    call ij%rebuild_rows(src, st)
    call a%apply(x, y)
    call ij%matvec(x, yh)
    call suite%assert_true(st%ok() .and. ij%overwrites == 1 .and. comm%sum(int(ij%nnz, gp)) == a%global_nnz(), &
                           'long rows: rebuild_rows with another pattern builds anew')
    call suite%assert_close_array(yh, y, 1.0e-12_rp, 'long rows: ... with A''s product')
    call fresh%free()
    call ij%free()
    call a%free()
    call s%free()
    call ga%free()
    call a2%free()
  end subroutine test_long_rows

  !> G: for global row i of n, the graph Laplacian of the edge (i, i + n/2)
  !> (rows i <= n/2) or (i, i - n/2): 1 on the diagonal, -1 at the partner.
  subroutine matching_laplacian(row_map, g)
    type(index_map_t), intent(in) :: row_map
    type(global_csr_t), intent(out) :: g
    integer(gp) :: gid, half, partner
    integer(ip) :: i
    g%comm = row_map%comm
    g%row_offsets = row_map%offsets
    g%col_offsets = row_map%offsets
    g%n_rows = row_map%n_owned
    half = row_map%n_global / 2
    allocate(g%row_ptr(g%n_rows + 1), g%gcol(2 * g%n_rows), g%val(2 * g%n_rows), g%key(g%n_rows))
    do i = 1, g%n_rows
      gid = row_map%first + i - 1
      partner = merge(gid + half, gid - half, gid <= half)
      g%row_ptr(i) = 2 * i - 1
      g%gcol(2 * i - 1) = min(gid, partner)
      g%gcol(2 * i) = max(gid, partner)
      g%val(2 * i - 1:2 * i) = merge([1.0_rp, -1.0_rp], [-1.0_rp, 1.0_rp], gid < partner)
      g%key(i) = gid
    end do
    g%row_ptr(g%n_rows + 1) = 2 * g%n_rows + 1
  end subroutine matching_laplacian

  !> Three decoupled Laplacians scaled by 1, 100 and 0.01, interleaved
  !> (16^3 nodes, 12288 unknowns), with the default (elasticity) settings:
  !> the unknown approach and nodal coarsening both reduce the residual by
  !> 1e-6 in at most 30 cycles.
  subroutine test_systems(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    type(boomeramg_precon_t) :: amg
    type(amg_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), b(:)
    integer :: cycles, wcycles
    real(rp) :: red

    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a)
    allocate(x(a%n_rows), b(a%n_rows))
    call fill_test_vector(a, x)
    call a%apply(x, b)

    call amg%setup(a, p, st)
    call suite%assert_true(st%ok(), 'systems: setup with the defaults succeeds: '//trim(st%msg))
    if (.not. st%ok()) return
    call amg%measure_hierarchy(st)
    call suite%assert_true(st%ok() .and. amg%num_levels >= 3 .and. amg%level_rows(1) == 12288_gp, &
                           'systems: hierarchy of >= 3 levels over 12288 fine rows')
    call report_hierarchy(comm, amg)
    call stationary(comm, a, amg, b, 30, cycles, red)
    if (comm%rank == 0) write(*, '(a,i0,a,es10.3)') '  3 interleaved Laplacians, unknown approach: ', &
      cycles, ' V-cycles, residual reduction ', red
    call suite%assert_true(red <= 1.0e-6_rp .and. cycles <= 30, &
                           'systems: unknown approach reduces the residual by 1e-6 in <= 30 cycles')
    call amg%free()

    ! the W-cycle reaches hypre: a stronger cycle, fewer iterations than the V-cycle's
    p%cycle_type = 'w'
    call cycle_with(suite, comm, a, amg, b, p, 'cycle_type = w', wcycles, red)
    call suite%assert_true(red <= 1.0e-6_rp .and. wcycles < cycles, &
                           'systems: the W-cycle reduces the residual by 1e-6 in fewer cycles than the V-cycle')
    p%cycle_type = 'v'

    ! nodal coarsening (row-sum norm of the 3x3 nodal blocks)
    p%nodal = 4
    call cycle_with(suite, comm, a, amg, b, p, 'nodal = 4', cycles, red)
    call suite%assert_true(red <= 1.0e-6_rp .and. cycles <= 30, &
                           'systems: nodal coarsening reduces the residual by 1e-6 in <= 30 cycles')
    call a%free()
  end subroutine test_systems

  !> Set up m on a with q, run the stationary iteration on b (at most 30
  !> cycles), report n and the reduction under label, and free m.
  subroutine cycle_with(suite, comm, a, m, b, q, label, n, reduction)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    type(boomeramg_precon_t), intent(inout) :: m
    real(rp), intent(in) :: b(:)
    type(amg_params_t), intent(in) :: q
    character(len=*), intent(in) :: label
    integer, intent(out) :: n
    real(rp), intent(out) :: reduction
    type(error_status_t) :: st
    n = huge(n)
    reduction = huge(reduction)
    call m%setup(a, q, st)
    call suite%assert_true(st%ok(), 'systems: setup with '//label//' succeeds: '//trim(st%msg))
    if (st%ok()) then
      call stationary(comm, a, m, b, 30, n, reduction)
      if (comm%rank == 0) write(*, '(a,i0,a,es10.3)') '  3 interleaved Laplacians, '//label//': ', &
        n, ' cycles, residual reduction ', reduction
    end if
    call m%free()
  end subroutine cycle_with

  !> The same three Laplacians with components 1 and 2 of each node linked
  !> by -0.6: strong for component 1 if hypre took all unknowns as one
  !> function, ignored by the unknown approach (the matrix stays SPD). An
  !> explicit dof_func equal to the interleaved default gives the same
  !> V-cycle; a wrong one (all unknowns one function) gives another; a
  !> dof_func of the wrong size is refused.
  subroutine test_dof_func(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    type(boomeramg_precon_t) :: amg, amg2
    type(amg_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), b(:), z1(:), z2(:)
    integer, allocatable :: dof_func(:)
    integer :: i
    real(rp) :: diff, ref

    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a, &
                         coupling=0.6_rp)
    allocate(x(a%n_rows), b(a%n_rows), z1(a%n_rows), z2(a%n_rows))
    call fill_test_vector(a, x)
    call a%apply(x, b)
    call amg%setup(a, p, st)
    call suite%assert_true(st%ok(), 'dof_func: setup with the interleaved default succeeds')
    if (.not. st%ok()) return
    call amg%apply(b, z1)

    allocate(dof_func(a%n_rows))
    do i = 1, a%n_rows
      dof_func(i) = int(mod(a%row_map%first + i - 2, 3_gp))
    end do
    call amg2%setup(a, p, st, dof_func)
    call suite%assert_true(st%ok(), 'dof_func: setup with an explicit dof_func succeeds')
    call amg2%apply(b, z2)
    call suite%assert_close_array(z2, z1, 1.0e-12_rp * maxval(abs(z1)), &
                                  'dof_func: explicit interleaved ids = the default mapping')
    call amg2%free()

    dof_func = 0
    call amg2%setup(a, p, st, dof_func)
    call amg2%apply(b, z2)
    diff = pnorm2(comm, z2 - z1)
    ref = pnorm2(comm, z1)
    call suite%assert_true(st%ok() .and. diff > 1.0e-6_rp * ref, &
                           'dof_func: hypre uses it (all-zero ids give another V-cycle)')
    call amg2%free()

    call amg2%setup(a, p, st, dof_func(1:a%n_rows-1))
    call suite%assert_true(.not. st%ok() .and. index(st%msg, 'dof_func') > 0, &
                           'dof_func: one of the wrong size is refused')
    call amg2%free()
    call amg%free()
    call a%free()
  end subroutine test_dof_func

  !> geoblock's V-cycle (amg_cycle.c) against hypre's on the same hierarchy:
  !> 3 interleaved Laplacians scaled 1, 100, 0.01 (16^3 nodes) and a scalar
  !> one (30^3), default settings (l1-gs), and with 2 and 3 sweeps. The
  !> cycle is taken where it reproduces hypre's (cycle_code 'geoblock', the
  !> default) and M^-1 r agrees with hypre's to 1e-12 of its largest entry
  !> (only the order of the additions in a row differs), on any number of
  !> ranks (Jacobi across ranks, as hypre). Settings it does not reproduce
  !> (Chebyshev, C/F order, the W-cycle, a relaxation weight) and
  !> cycle_code = 'hypre' keep hypre's cycle.
  subroutine test_own_cycle(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map, row_map1, col_map1
    type(csr_matrix_t) :: a, a1
    type(amg_params_t) :: p

    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a)
    call build_laplacian(comm, 30, 1, [1.0_rp], row_map1, col_map1, a1)
    call compare_cycles(suite, comm, a, amg_params_t(), 'systems, defaults')
    p = amg_params_t()
    p%num_sweeps = 2
    call compare_cycles(suite, comm, a, p, 'systems, num_sweeps = 2')
    p = amg_params_t()
    p%num_functions = 1
    call compare_cycles(suite, comm, a1, p, 'scalar, defaults')
    p%num_sweeps = 3
    call compare_cycles(suite, comm, a1, p, 'scalar, num_sweeps = 3')

    p = amg_params_t()
    p%relax_type = 'chebyshev'
    call expect_hypre_cycle(suite, a, p, 'relax_type = chebyshev')
    p = amg_params_t()
    p%relax_order = 'cf'
    call expect_hypre_cycle(suite, a, p, 'relax_order = cf')
    p = amg_params_t()
    p%cycle_type = 'w'
    call expect_hypre_cycle(suite, a, p, 'cycle_type = w')
    p = amg_params_t()
    p%relax_wt = 0.8_rp
    call expect_hypre_cycle(suite, a, p, 'relax_wt = 0.8')
    p = amg_params_t()
    p%cycle_code = 'hypre'
    call expect_hypre_cycle(suite, a, p, 'cycle_code = hypre')
    call a%free()
    call a1%free()
  end subroutine test_own_cycle

  !> A lagged refresh (refresh_rows: geoblock's cycle with only the finest
  !> level renewed), on the 3 interleaved Laplacians (scaled 1, 100, 0.01,
  !> 16^3 nodes) given by rows as A + alpha A: with the same values the
  !> cycle is the one before; with alpha 0.25 the products are 1.25 A's, the
  !> cycle changes, and the stationary iteration on 1.25 A with the coarse
  !> levels of A still reduces its residual by 1e-6 in at most 30 cycles.
  !> Under hypre's cycle refresh_rows builds anew, as update_rows does.
  subroutine test_lagged(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t), target :: a, s
    type(global_csr_t), target :: g
    type(sum_rows_t) :: src
    type(boomeramg_precon_t) :: amg, fresh
    type(amg_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:), yh(:), z1(:), z2(:)
    integer :: cycles
    real(rp) :: red

    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a)
    call from_csr(a, g)
    p%precision = 'double'
    call src%init(a, g, 0.0_rp)
    call amg%setup_rows(src, p, st)
    call suite%assert_true(st%ok() .and. amg%own_cycle, "lagged: setup_rows takes geoblock's cycle: "//trim(st%msg))
    if (.not. (st%ok() .and. amg%own_cycle)) return
    allocate(x(a%n_rows), y(a%n_rows), yh(a%n_rows), z1(a%n_rows), z2(a%n_rows))
    call fill_test_vector(a, x)
    call amg%apply(x, z1)
    call amg%refresh_rows(src, st)
    call amg%apply(x, z2)
    call suite%assert_true(st%ok() .and. amg%own_cycle, 'lagged: refresh_rows succeeds: '//trim(st%msg))
    call suite%assert_close_array(z2, z1, 1.0e-14_rp * comm%max(maxval(abs(z1))), &
                                  'lagged: a refresh with the same values keeps the cycle')
    src%alpha_g = 0.25_rp
    call amg%refresh_rows(src, st)
    call amg%apply(x, z2)
    s = a
    s%val = 1.25_rp * a%val
    call s%apply(x, y)
    call amg%matrix_product(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-10_rp * comm%max(maxval(abs(y))), &
                                  'lagged: matrix_product is 1.25 A after the refresh')
    call suite%assert_true(comm%max(maxval(abs(z2 - z1))) > 1.0e-6_rp * comm%max(maxval(abs(z1))), &
                           'lagged: the cycle takes the new finest level (it changed)')
    call stationary(comm, s, amg, y, 30, cycles, red)
    if (comm%rank == 0) write(*, '(a,i0,a,es10.3)') '  1.25 A on the lagged hierarchy of A: ', &
      cycles, ' V-cycles, residual reduction ', red
    call suite%assert_true(red <= 1.0e-6_rp, 'lagged: the hierarchy reduces 1.25 A''s residual by 1e-6 '// &
                           'in <= 30 cycles')
    ! hypre's cycle: refresh_rows builds anew, as update_rows does
    p%cycle_code = 'hypre'
    call fresh%setup_rows(src, p, st)
    call fresh%refresh_rows(src, st)
    call fresh%apply(x, z1)
    call amg%update_rows(src, st)
    call amg%apply(x, z2)
    call suite%assert_true(st%ok() .and. .not. fresh%own_cycle, "lagged: under hypre's cycle refresh_rows "// &
                           'succeeds')
    call suite%assert_close_array(z1, z2, 1.0e-10_rp * comm%max(maxval(abs(z2))), &
                                  "lagged: under hypre's cycle refresh_rows builds anew (update_rows' cycle)")
    call amg%free()
    call fresh%free()
    call a%free()
    call s%free()
    call g%free()
  end subroutine test_lagged

  !> A refresh with the coarse levels made anew (refresh_rows with galerkin:
  !> P^T A P with the interpolation of the build), on the 3 interleaved
  !> Laplacians (scaled 1, 100, 0.01, 16^3 nodes) given by rows as
  !> A + alpha A. A scaled matrix has the same strength graphs, coarsening
  !> and interpolation, so the hierarchy of 1.25 A by refresh is the one a
  !> build on 1.25 A makes, each level 1.25 times A's: its cycle is A's
  !> divided by 1.25 (to round-off in double, to the floats' 1e-6 in single
  !> precision), where the finest-level refresh's is not (by more than 1 %);
  !> a second refresh back to A gives A's cycle again.
  subroutine test_galerkin(suite, comm, precision)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: precision
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t), target :: a, s
    type(global_csr_t), target :: g
    type(sum_rows_t) :: src
    type(boomeramg_precon_t) :: amg, fine
    type(amg_params_t) :: p
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), y(:), yh(:), z0(:), z1(:), z2(:)
    real(rp) :: tol, scale
    character(len=:), allocatable :: tag

    tag = 'galerkin ('//precision//'): '
    tol = merge(1.0e-12_rp, 1.0e-6_rp, precision == 'double')
    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a)
    call from_csr(a, g)
    p%precision = precision
    call src%init(a, g, 0.0_rp)
    call amg%setup_rows(src, p, st)
    call fine%setup_rows(src, p, st)
    call suite%assert_true(st%ok() .and. amg%own_cycle, tag//"setup_rows takes geoblock's cycle: "//trim(st%msg))
    if (.not. (st%ok() .and. amg%own_cycle)) return
    allocate(x(a%n_rows), y(a%n_rows), yh(a%n_rows), z0(a%n_rows), z1(a%n_rows), z2(a%n_rows))
    call fill_test_vector(a, x)
    call amg%apply(x, z0)
    scale = comm%max(maxval(abs(z0)))
    src%alpha_g = 0.25_rp
    call amg%refresh_rows(src, st, galerkin=.true.)
    call suite%assert_true(st%ok() .and. amg%own_cycle, tag//'refresh_rows succeeds: '//trim(st%msg))
    call fine%refresh_rows(src, st)
    call amg%apply(x, z1)
    call fine%apply(x, z2)
    s = a
    s%val = 1.25_rp * a%val
    call s%apply(x, y)
    call amg%matrix_product(x, yh)
    call suite%assert_close_array(yh, y, 1.0e-10_rp * comm%max(maxval(abs(y))), &
                                  tag//'matrix_product is 1.25 A after the refresh')
    call suite%assert_close_array(z1, z0 / 1.25_rp, tol * scale, tag//'the cycle is A''s / 1.25')
    call suite%assert_true(comm%max(maxval(abs(z2 - z0 / 1.25_rp))) > 1.0e-2_rp * scale, &
                           tag//'the finest-level refresh''s is not')
    src%alpha_g = 0.0_rp
    call amg%refresh_rows(src, st, galerkin=.true.)
    call amg%apply(x, z1)
    call suite%assert_close_array(z1, z0, tol * scale, tag//'a second refresh, back to A, gives A''s cycle')
    call amg%free()
    call fine%free()
    call a%free()
    call s%free()
    call g%free()
  end subroutine test_galerkin

  !> precision = 'single': geoblock's cycle on float copies of the level
  !> values. On the 3 interleaved Laplacians (scaled 1, 100, 0.01, 16^3
  !> nodes; 0.01 and the coarse levels' Galerkin values are not floats) and
  !> a scalar one scaled by 0.3: M^-1 x moves from the double cycle's by no
  !> more than 1e-6 of its largest entry (3e-8 measured) (the entries move by 6e-8 of
  !> themselves) but does move (the copies are read), and the stationary
  !> iteration takes as many cycles to reduce the residual by 1e-6. A matrix
  !> beyond single precision's range (the scalar Laplacian scaled by 1e39,
  !> and by 1e-39) keeps its double values: the cycle is the double one to
  !> 1e-13. A lagged refresh with the same values keeps the cycle; with
  !> 1.25 A the cycle is the double lagged one's to 1e-6.
  subroutine test_single(suite, comm)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(index_map_t), target :: row_map, col_map, row_map1, col_map1, row_map2, col_map2, row_map3, col_map3
    type(csr_matrix_t), target :: a, a1, big, tiny_a
    type(global_csr_t), target :: g
    type(sum_rows_t) :: src
    type(boomeramg_precon_t) :: md, ms
    type(amg_params_t) :: p, ps
    type(error_status_t) :: st
    real(rp), allocatable :: x(:), zd(:), zs(:), b(:)
    integer :: cd, cs
    real(rp) :: rd, rs

    call build_laplacian(comm, 16, 3, [1.0_rp, 100.0_rp, 0.01_rp], row_map, col_map, a)
    call build_laplacian(comm, 30, 1, [0.3_rp], row_map1, col_map1, a1)
    call build_laplacian(comm, 12, 1, [1.0e39_rp], row_map2, col_map2, big)
    call build_laplacian(comm, 12, 1, [1.0e-39_rp], row_map3, col_map3, tiny_a)
    p = amg_params_t()
    call compare_single(suite, comm, a, p, 'systems', 1.0e-6_rp, .true.)
    p%num_functions = 1
    call compare_single(suite, comm, a1, p, 'scalar', 1.0e-6_rp, .true.)
    call compare_single(suite, comm, big, p, 'scalar x 1e39 (kept double)', 1.0e-13_rp, .false.)
    call compare_single(suite, comm, tiny_a, p, 'scalar x 1e-39 (kept double)', 1.0e-13_rp, .false.)

    ! the stationary iteration on the systems
    p = amg_params_t()
    p%precision = 'double'
    ps = p
    ps%precision = 'single'
    call md%setup(a, p, st)
    call ms%setup(a, ps, st)
    allocate(b(a%n_rows))
    call fill_test_vector(a, b)
    call stationary(comm, a, md, b, 30, cd, rd)
    call stationary(comm, a, ms, b, 30, cs, rs)
    if (comm%rank == 0) write(*, '(a,i0,a,es10.3,a,i0,a,es10.3)') '  single: stationary iteration, double ', &
      cd, ' cycles (', rd, '), single ', cs, ' cycles (', rs, ')'
    call suite%assert_true(cs == cd .and. rs <= 1.0e-6_rp, 'single: the stationary iteration takes as many '// &
                           'cycles as in double')
    call md%free()
    call ms%free()
    call single_in_place(suite, comm, a1)

    ! a lagged refresh
    call from_csr(a, g)
    call src%init(a, g, 0.0_rp)
    call md%setup_rows(src, p, st)
    call ms%setup_rows(src, ps, st)
    allocate(x(a%n_rows), zd(a%n_rows), zs(a%n_rows))
    call fill_test_vector(a, x)
    call ms%apply(x, zd)
    call ms%refresh_rows(src, st)
    call ms%apply(x, zs)
    call suite%assert_true(c_single(comm, ms), 'single: a refresh keeps the single-precision values')
    call suite%assert_true(st%ok(), 'single: the refresh succeeds')
    call suite%assert_close_array(zs, zd, 1.0e-14_rp * comm%max(maxval(abs(zd))), &
                                  'single: a refresh with the same values keeps the cycle')
    src%alpha_g = 0.25_rp
    call ms%refresh_rows(src, st)
    call md%refresh_rows(src, st)
    call ms%apply(x, zs)
    call md%apply(x, zd)
    call suite%assert_close_array(zs, zd, 1.0e-6_rp * comm%max(maxval(abs(zd))), &
                                  "single: a refresh to 1.25 A gives the double lagged cycle's to 1e-6")
    call suite%assert_true(comm%max(maxval(abs(zs - zd))) > 0.0_rp, 'single: ... and reads the new float values')
    call md%free()
    call ms%free()
    call g%free()
    call a%free()
    call a1%free()
    call big%free()
    call tiny_a%free()

  end subroutine test_single

  !> The finest level's floats in place, in hypre's copy of a (no copy of
  !> their own): matrix_product is A x with A's values rounded to single
  !> precision, within the rounding's bound 2^-24 (|A| |x|) of ours and
  !> not equal to it; update(2 A) writes doubles into the same matrix
  !> again (in place), and its cycle is that of a new set-up on 2 A to the
  !> last bit (so no float is left), with the values floats again.
  subroutine single_in_place(suite, comm, a)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    type(csr_matrix_t) :: a_abs, a2
    type(boomeramg_precon_t) :: ms, fresh
    type(amg_params_t) :: ps
    type(error_status_t) :: st, st2
    real(rp), allocatable :: x(:), y(:), ys(:), w(:), z1(:), z2(:)
    real(rp) :: bound, diff

    ps = amg_params_t()
    ps%num_functions = 1
    ps%precision = 'single'
    call ms%setup(a, ps, st)
    call suite%assert_true(st%ok() .and. .not. comm%any_true(.not. ms%ij%narrowed), &
                           "single in place: the finest level's values are floats in hypre's copy")
    allocate(x(a%n_rows), y(a%n_rows), ys(a%n_rows), w(a%n_rows), z1(a%n_rows), z2(a%n_rows))
    call fill_test_vector(a, x)
    call a%apply(x, y)
    call ms%matrix_product(x, ys)
    a_abs = a
    a_abs%val = abs(a%val)
    call a_abs%apply(abs(x), w)
    bound = 1.01_rp * 2.0_rp**(-24) * comm%max(maxval(w))
    diff = comm%max(maxval(abs(ys - y)))
    if (comm%rank == 0) write(*, '(a,es10.3,a,es10.3)') '  single in place: max |A_s x - A x| ', diff, &
      ', bound ', bound
    call suite%assert_true(diff <= bound .and. diff > 0.0_rp, &
                           'single in place: matrix_product is the product with the rounded values')
    a2 = a
    a2%val = 2.0_rp * a%val
    call ms%update(a2, st)
    call fresh%setup(a2, ps, st2)
    call suite%assert_true(st%ok() .and. st2%ok() .and. ms%ij%overwrites == 1, &
                           'single in place: update(2 A) writes into the same matrix')
    call ms%apply(x, z1)
    call fresh%apply(x, z2)
    call suite%assert_close_array(z1, z2, 0.0_rp, 'single in place: after update(2 A) the cycle is a new '// &
                                  'set-up''s on 2 A, bit for bit')
    call suite%assert_true(.not. comm%any_true(.not. ms%ij%narrowed), &
                           'single in place: ... with the values floats again')
    call ms%free()
    call fresh%free()
    call a_abs%free()
    call a2%free()
  end subroutine single_in_place

  !> true on every rank when m holds single-precision values
  logical function c_single(comm, m)
    type(parallel_comm_t), intent(in) :: comm
    type(boomeramg_precon_t), intent(in) :: m
    c_single = .not. comm%any_true(.not. c_associated(m%compact))
  end function c_single

  !> M^-1 x by geoblock's cycle on m in double and in single precision:
  !> apart by at most tol of the largest entry, and apart at all (moves).
  subroutine compare_single(suite, comm, m, q, label, tol, moves)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: m
    type(amg_params_t), intent(in) :: q
    character(len=*), intent(in) :: label
    real(rp), intent(in) :: tol
    logical, intent(in) :: moves
    type(boomeramg_precon_t) :: d, s1
    type(amg_params_t) :: qs, qd
    type(error_status_t) :: sd, ss
    real(rp), allocatable :: v(:), z1(:), z2(:)
    real(rp) :: diff, scale
    allocate(v(m%n_rows), z1(m%n_rows), z2(m%n_rows))
    call fill_test_vector(m, v)
    qd = q
    qd%precision = 'double'
    qs = q
    qs%precision = 'single'
    call d%setup(m, qd, sd)
    call s1%setup(m, qs, ss)
    call suite%assert_true(sd%ok() .and. ss%ok() .and. d%own_cycle .and. s1%own_cycle, &
                           'single, '//label//": both set-ups succeed in geoblock's cycle")
    if (.not. (sd%ok() .and. ss%ok())) return
    call d%apply(v, z1)
    call s1%apply(v, z2)
    diff = comm%max(maxval(abs(z2 - z1)))
    scale = comm%max(maxval(abs(z1)))
    if (comm%rank == 0) write(*, '(a,es10.3,a,es10.3)') '  single, '//label//': max |z_single - z_double| ', &
      diff, ' of max |z_double| ', scale
    call suite%assert_true(scale > 0.0_rp .and. diff <= tol * scale, 'single, '//label//': M^-1 x agrees '// &
                           'with the double cycle''s within its tolerance')
    if (moves) call suite%assert_true(diff > 0.0_rp, 'single, '//label//': the float values are read')
    call suite%assert_true(s1%apply_errors == 0, 'single, '//label//': no hypre error while applying')
    call d%free()
    call s1%free()
  end subroutine compare_single

  !> M^-1 x by geoblock's cycle (q as given, cycle_code 'geoblock') and by
  !> hypre's (cycle_code 'hypre') on a; they agree to 1e-12.
  subroutine compare_cycles(suite, comm, a, q, label)
    type(test_suite_t), intent(inout) :: suite
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    type(amg_params_t), intent(in) :: q
    character(len=*), intent(in) :: label
    type(boomeramg_precon_t) :: own, ref
    type(amg_params_t) :: qh, qd
    type(error_status_t) :: st, sth
    real(rp), allocatable :: x(:), z(:), zh(:)
    real(rp) :: diff, scale

    allocate(x(a%n_rows), z(a%n_rows), zh(a%n_rows))
    call fill_test_vector(a, x)
    qd = q
    qd%precision = 'double'
    qh = q
    qh%cycle_code = 'hypre'
    call own%setup(a, qd, st)
    call ref%setup(a, qh, sth)
    call suite%assert_true(st%ok() .and. sth%ok(), 'own cycle, '//label//': both set-ups succeed')
    if (.not. (st%ok() .and. sth%ok())) return
    call suite%assert_true(own%own_cycle .and. .not. ref%own_cycle, &
                           "own cycle, "//label//": cycle_code 'geoblock' takes geoblock's cycle, 'hypre' hypre's")
    call own%apply(x, z)
    call ref%apply(x, zh)
    diff = comm%max(maxval(abs(z - zh)))
    scale = comm%max(maxval(abs(zh)))
    if (comm%rank == 0) write(*, '(a,es10.3,a,es10.3)') '  own cycle, '//label//': max |z - z_hypre| ', diff, &
      ' of max |z_hypre| ', scale
    call suite%assert_true(scale > 0.0_rp .and. diff <= 1.0e-12_rp * scale, &
                           'own cycle, '//label//": M^-1 x agrees with hypre's cycle to 1e-12")
    call suite%assert_true(own%apply_errors == 0 .and. ref%apply_errors == 0, &
                           'own cycle, '//label//': no hypre error while applying')
    call own%free()
    call ref%free()
  end subroutine compare_cycles

  !> Set up m on a with q: hypre's cycle is kept.
  subroutine expect_hypre_cycle(suite, a, q, label)
    type(test_suite_t), intent(inout) :: suite
    type(csr_matrix_t), intent(inout) :: a
    type(amg_params_t), intent(in) :: q
    character(len=*), intent(in) :: label
    type(boomeramg_precon_t) :: m
    type(error_status_t) :: st
    call m%setup(a, q, st)
    call suite%assert_true(st%ok() .and. .not. m%own_cycle, 'own cycle: '//label//" keeps hypre's cycle")
    call m%free()
  end subroutine expect_hypre_cycle

  ! ---- helpers ---------------------------------------------------------------

  !> x <- x + M^-1 (b - A x) from x = 0 until ||r|| <= 1e-6 ||b|| or max_cycles.
  subroutine stationary(comm, a, m, b, max_cycles, cycles, reduction)
    type(parallel_comm_t), intent(in) :: comm
    type(csr_matrix_t), intent(inout) :: a
    type(boomeramg_precon_t), intent(inout) :: m
    real(rp), intent(in) :: b(:)
    integer, intent(in) :: max_cycles
    integer, intent(out) :: cycles
    real(rp), intent(out) :: reduction
    real(rp), allocatable :: x(:), r(:), z(:), ax(:)
    real(rp) :: bnorm
    allocate(x(size(b)), r(size(b)), z(size(b)), ax(size(b)))
    x = 0.0_rp
    r = b
    bnorm = pnorm2(comm, b)
    reduction = 1.0_rp
    cycles = 0
    do while (cycles < max_cycles .and. reduction > 1.0e-6_rp)
      call m%apply(r, z)
      x = x + z
      call a%apply(x, ax)
      r = b - ax
      reduction = pnorm2(comm, r) / bnorm
      cycles = cycles + 1
    end do
  end subroutine stationary

  !> A smooth-plus-oscillating vector defined by global ids (the same on any
  !> number of ranks).
  subroutine fill_test_vector(a, x)
    type(csr_matrix_t), intent(in) :: a
    real(rp), intent(out) :: x(:)
    integer(ip) :: i
    real(rp) :: g
    do i = 1, a%n_rows
      g = real(a%row_map%first + i - 1, rp)
      x(i) = sin(0.37_rp * g) + 0.1_rp * cos(1.3_rp * g) + 1.0_rp
    end do
  end subroutine fill_test_vector

  subroutine report_hierarchy(comm, m)
    type(parallel_comm_t), intent(in) :: comm
    type(boomeramg_precon_t), intent(in) :: m
    character(len=amg_line_len), allocatable :: lines(:)
    integer :: l
    call m%hierarchy_lines(lines)
    if (comm%rank == 0) then
      write(*, '(a,a,a,a)') '  ', trim(lines(1)), ', ', trim(lines(2))
      do l = 3, size(lines)
        write(*, '(4x,a)') trim(lines(l))
      end do
    end if
  end subroutine report_hierarchy

end program test_boomeramg
