!> Unit tests of csr_matrix_t: element-by-element assembly on a small 2D
!> "mesh" of quadrilaterals (4 nodes, one unknown per node) whose elements
!> are dealt to ranks independently of the node ownership, so that elements
!> on a partition boundary add to rows owned by another rank (ghost rows ->
!> stash -> finalize_assembly). Every rank also builds the dense global
!> matrix from the same element matrices: the independent reference for the
!> entries, apply(), diagonal() and the MatrixMarket file. 1 or 2 ranks
!> (more work as well).
program test_csr
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use assertions, only: test_suite_t
  implicit none

  integer, parameter :: nex = 5, ney = 4                  !< elements in x and y
  integer, parameter :: nnx = nex + 1, nny = ney + 1      !< nodes in x and y
  integer, parameter :: n_nodes = nnx * nny, n_elems = nex * ney
  integer, parameter :: by_blocks = 1, round_robin = 2

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  real(rp) :: dense(n_nodes, n_nodes)

  call comm%init_world()
  call suite%init('csr', comm)
  call build_dense(dense)
  call check_matrix(by_blocks, 'elements in rank blocks')
  call check_matrix(round_robin, 'elements dealt round robin')
  call suite%finish()

contains

  !> Global node ids of element e (counter-clockwise).
  function element_nodes(e) result(nodes)
    integer, intent(in) :: e
    integer(gp) :: nodes(4)
    integer :: ie, je
    ie = mod(e - 1, nex) + 1
    je = (e - 1) / nex + 1
    nodes(1) = ie + (je - 1) * nnx
    nodes(2) = nodes(1) + 1
    nodes(3) = nodes(2) + nnx
    nodes(4) = nodes(1) + nnx
  end function element_nodes

  !> A made-up element matrix: unsymmetric, strictly positive entries (so no
  !> sum cancels and the nonzero pattern of the sum is the graph), different
  !> for every element (so a misplaced contribution changes the result).
  function element_matrix(e) result(ke)
    integer, intent(in) :: e
    real(rp) :: ke(4, 4)
    integer :: a, b
    do b = 1, 4
      do a = 1, 4
        ke(a, b) = 1.0_rp + 0.01_rp * e + 0.1_rp * a + 0.013_rp * b
        if (a == b) ke(a, b) = ke(a, b) + 4.0_rp
      end do
    end do
  end function element_matrix

  subroutine build_dense(g)
    real(rp), intent(out) :: g(:,:)
    integer(gp) :: nodes(4)
    real(rp) :: ke(4, 4)
    integer :: e, a, b
    g = 0.0_rp
    do e = 1, n_elems
      nodes = element_nodes(e)
      ke = element_matrix(e)
      do b = 1, 4
        do a = 1, 4
          g(nodes(a), nodes(b)) = g(nodes(a), nodes(b)) + ke(a, b)
        end do
      end do
    end do
  end subroutine build_dense

  !> Rank that assembles element e.
  integer function element_rank(e, how, np)
    integer, intent(in) :: e, how, np
    if (how == by_blocks) then
      element_rank = ((e - 1) * np) / n_elems
    else
      element_rank = mod(e, np)
    end if
  end function element_rank

  !> Global ids whose mask is set, outside [first, last], ascending.
  subroutine masked_outside(mask, first, last, ids)
    logical, intent(in) :: mask(:)
    integer(gp), intent(in) :: first, last
    integer(gp), allocatable, intent(out) :: ids(:)
    integer(gp) :: g
    integer :: n
    allocate(ids(count(mask)))
    n = 0
    do g = 1, size(mask)
      if (mask(g) .and. (g < first .or. g > last)) then
        n = n + 1
        ids(n) = g
      end if
    end do
    ids = ids(1:n)
  end subroutine masked_outside

  subroutine check_matrix(how, label)
    integer, intent(in) :: how
    character(len=*), intent(in) :: label
    type(index_map_t), target :: row_map, col_map
    type(csr_matrix_t) :: a
    integer(gp), allocatable :: row_ghosts(:), col_ghosts(:), gcols(:)
    integer(ip), allocatable :: row_ptr(:), col(:)
    logical :: in_rows(n_nodes), in_cols(n_nodes), adj(n_nodes, n_nodes)
    real(rp), allocatable :: x(:), y(:), d(:), expect(:)
    real(rp) :: xg(n_nodes), yg(n_nodes), err
    integer(gp) :: first, last, nodes(4), g
    integer(ip) :: nown, i, k, n, n_stashed
    integer :: e, np, me
    logical :: ok

    np = comm%size
    me = comm%rank
    ! contiguous node ownership, as even as possible
    nown = int(n_nodes / np + merge(1, 0, me < mod(n_nodes, np)), ip)
    first = 1 + int(me, gp) * (n_nodes / np) + min(me, mod(n_nodes, np))
    last = first + nown - 1

    ! graph of the mesh (node a ~ node b when they share an element)
    adj = .false.
    do e = 1, n_elems
      nodes = element_nodes(e)
      adj(nodes, nodes) = .true.
    end do
    ! rows: my elements' nodes; columns: those and every neighbour of an owned node
    in_rows = .false.
    do e = 1, n_elems
      if (element_rank(e, how, np) == me) in_rows(element_nodes(e)) = .true.
    end do
    in_cols = in_rows
    do g = first, last
      in_cols = in_cols .or. adj(:, g)
    end do
    call masked_outside(in_rows, first, last, row_ghosts)
    call masked_outside(in_cols, first, last, col_ghosts)
    ! give the ghosts in descending order: the maps must not rely on sorted input
    row_ghosts = row_ghosts(size(row_ghosts):1:-1)
    col_ghosts = col_ghosts(size(col_ghosts):1:-1)
    call row_map%init(comm, nown, row_ghosts)
    call col_map%init(comm, nown, col_ghosts)

    ! CSR pattern of the owned rows, local column ids ascending
    allocate(row_ptr(nown + 1), col(count(adj(:, first:last))))
    row_ptr(1) = 1
    do i = 1, nown
      g = first + i - 1
      n = int(count(adj(:, g)), ip)
      gcols = pack([(int(k, gp), k = 1, n_nodes)], adj(:, g))
      do k = 1, n
        col(row_ptr(i) + k - 1) = col_map%local_id(gcols(k))
      end do
      call sort_local(col(row_ptr(i):row_ptr(i) + n - 1))
      row_ptr(i + 1) = row_ptr(i) + n
    end do
    call a%init(row_map, col_map, row_ptr, col)

    ! assemble twice around a zero(): the stash must be emptied and reused
    call assemble(a, how, n_stashed)
    call a%zero()
    call assemble(a, how, n_stashed)
    call assemble(a, how, n_stashed)
    ok = .true.
    err = 0.0_rp
    do i = 1, nown
      g = first + i - 1
      ok = ok .and. a%row_ptr(i + 1) - a%row_ptr(i) == count(dense(g, :) /= 0.0_rp)
      do k = a%row_ptr(i), a%row_ptr(i + 1) - 1
        err = max(err, abs(a%val(k) - 2.0_rp * dense(g, col_map%global_id(a%col(k)))))
      end do
    end do
    call suite%assert_true(ok, 'row lengths equal the nonzeros of the global rows: '//label)
    call suite%assert_close(err, 0.0_rp, 1.0e-12_rp, 'entries equal the global matrix (twice assembled): '//label)
    call suite%assert_true(a%global_nnz() == count(dense /= 0.0_rp), 'global_nnz: '//label)
    call suite%assert_true(a%n_stash == 0, 'stash empty after finalize_assembly: '//label)
    if (np > 1) call suite%assert_true(comm%sum(n_stashed) > 0, &
                                       'some contributions went through the stash: '//label)

    ! y = A x against the dense product (x: a smooth, non-constant field)
    call a%zero()
    call assemble(a, how, n_stashed)
    do g = 1, n_nodes
      xg(g) = sin(0.3_rp * g) + 0.01_rp * g
    end do
    yg = matmul(dense, xg)
    allocate(x(nown), y(nown), d(nown), expect(nown))
    x = xg(first:last)
    call a%apply(x, y)
    call suite%assert_close_array(y, yg(first:last), 1.0e-12_rp, 'apply against the dense product: '//label)
    call a%apply(x, y)
    call suite%assert_close_array(y, yg(first:last), 1.0e-12_rp, 'apply again (work halo reused): '//label)

    call a%diagonal(d)
    do i = 1, nown
      expect(i) = dense(first + i - 1, first + i - 1)
    end do
    ! (the owners add the stashed contributions last: round-off only)
    call suite%assert_close_array(d, expect, 1.0e-12_rp, 'diagonal: '//label)

    call check_matrix_market(a, how, label)
    call a%free()
    call col_map%free()
    call row_map%free()
  end subroutine check_matrix

  !> Add my elements to a and finish the assembly; n_stashed: how many
  !> contributions were stashed for other ranks.
  subroutine assemble(a, how, n_stashed)
    type(csr_matrix_t), intent(inout) :: a
    integer, intent(in) :: how
    integer(ip), intent(out) :: n_stashed
    integer(gp) :: nodes(4)
    integer(ip) :: rows(4), cols(4)
    integer :: e, k
    do e = 1, n_elems
      if (element_rank(e, how, comm%size) /= comm%rank) cycle
      nodes = element_nodes(e)
      do k = 1, 4
        rows(k) = a%row_map%local_id(nodes(k))
        cols(k) = a%col_map%local_id(nodes(k))
      end do
      call a%add_block(rows, cols, element_matrix(e))
    end do
    n_stashed = a%n_stash
    call a%finalize_assembly()
  end subroutine assemble

  !> Ascending sort of a short integer list (insertion sort).
  subroutine sort_local(v)
    integer(ip), intent(inout) :: v(:)
    integer(ip) :: t
    integer :: i, j
    do i = 2, size(v)
      t = v(i)
      j = i - 1
      do while (j >= 1)
        if (v(j) <= t) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = t
    end do
  end subroutine sort_local

  !> Write the matrix, read it back on rank 0 and compare with the dense one.
  subroutine check_matrix_market(a, how, label)
    type(csr_matrix_t), intent(in) :: a
    integer, intent(in) :: how
    character(len=*), intent(in) :: label
    character(len=128) :: path, line
    integer :: ios, u, nr, nc, nz, i, j, k
    real(rp) :: v, err
    logical :: ok_header, ok_entries, seen(n_nodes, n_nodes)

    write(path, '(a,i0,a,i0,a)') '/tmp/geoblock_test_csr_np', comm%size, '_', how, '.mtx'
    call a%write_matrix_market(trim(path), ios)
    call suite%assert_true(ios == 0, 'write_matrix_market succeeds: '//label)
    ok_header = .true.
    ok_entries = .true.
    err = 0.0_rp
    if (comm%rank == 0) then
      open(newunit=u, file=trim(path), status='old', action='read', iostat=ios)
      ok_header = ios == 0
      if (ok_header) then
        read(u, '(a)', iostat=ios) line
        ok_header = ios == 0 .and. line(1:14) == '%%MatrixMarket' .and. index(line, 'coordinate real general') > 0
        do
          read(u, '(a)', iostat=ios) line
          if (ios /= 0 .or. line(1:1) /= '%') exit
        end do
        read(line, *, iostat=ios) nr, nc, nz
        ok_header = ok_header .and. ios == 0 .and. nr == n_nodes .and. nc == n_nodes .and. &
                    nz == count(dense /= 0.0_rp)
        seen = .false.
        do k = 1, nz
          read(u, *, iostat=ios) i, j, v
          if (ios /= 0 .or. i < 1 .or. i > n_nodes .or. j < 1 .or. j > n_nodes) then
            ok_entries = .false.
            exit
          end if
          ok_entries = ok_entries .and. .not. seen(i, j)
          seen(i, j) = .true.
          err = max(err, abs(v - dense(i, j)))
        end do
        read(u, *, iostat=ios) i
        ok_entries = ok_entries .and. ios /= 0          ! nothing after the nz entries
        close(u, status='delete')
      end if
    end if
    call suite%assert_true(ok_header, 'MatrixMarket header: banner, size and nnz: '//label)
    call suite%assert_true(ok_entries, 'MatrixMarket: nnz distinct entries, nothing more: '//label)
    call suite%assert_close(err, 0.0_rp, 1.0e-12_rp, 'MatrixMarket entries read back: '//label)
  end subroutine check_matrix_market
end program test_csr
