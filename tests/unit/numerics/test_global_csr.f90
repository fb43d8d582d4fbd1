!> Unit tests of global_csr: every rank builds the same small dense matrices
!> (deterministic sparse patterns), takes its block of rows as a
!> global_csr_t, and checks transpose, multiply, add, drop_small, fetch_rows
!> to_csr (+ apply), the sums in place (add_to_csr, add_csr_to_csr) and
!> the union of patterns (union_to_csr)
!> against the dense reference. Any number of ranks.
program test_global_csr
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, row_store_t, gcsr_transpose, gcsr_multiply, gcsr_add, drop_small, fetch_rows, &
    to_csr, from_csr, add_to_csr, add_csr_to_csr, union_to_csr
  use assertions, only: test_suite_t
  implicit none

  integer, parameter :: n1 = 17, n2 = 13, n3 = 11
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  real(rp) :: da(n1, n2), db(n2, n3), ds(n1, n1), ds0(n1, n1)
  type(global_csr_t) :: a, b, s, t, c, e
  type(row_store_t) :: store
  type(index_map_t), target :: rmap
  type(csr_matrix_t) :: m, ms, me, mu
  type(global_csr_t) :: back
  real(rp), allocatable :: x(:), y(:)
  integer(gp), allocatable :: want(:)
  integer :: i, k
  integer(gp) :: o1(0:64), o2(0:64), o3(0:64)
  logical :: ok, ok2

  call comm%init_world()
  call suite%init('global_csr', comm)
  call make_dense(da, 3, 0.3_rp)
  call make_dense(db, 5, 0.7_rp)
  call make_dense(ds, 7, 0.2_rp)
  ds = ds + transpose(ds)
  do i = 1, n1
    ds(i, i) = 10.0_rp + i
  end do
  ds0 = ds
  call split(n1, o1)
  call split(n2, o2)
  call split(n3, o3)
  call from_dense(da, o1, o2, a)
  call from_dense(db, o2, o3, b)
  call from_dense(ds, o1, o1, s)

  call gcsr_transpose(a, t)
  call suite%assert_true(matches(t, transpose(da), o2), 'transpose of a 17 x 13 matrix')
  call gcsr_multiply(a, b, c)
  call suite%assert_true(matches(c, matmul(da, db), o1), 'product of 17 x 13 and 13 x 11 matrices')
  call gcsr_multiply(t, s, e)
  call suite%assert_true(matches(e, matmul(transpose(da), ds), o2), 'product a^T s (rows fetched from every rank)')
  call gcsr_add(2.0_rp, s, -0.5_rp, s, e)
  call suite%assert_true(matches(e, 1.5_rp * ds, o1), 'add: 2 s - 0.5 s')
  call suite%assert_equal_int(int(c%global_nnz()), count(abs(matmul(da, db)) > 0.0_rp), &
    'product keeps exactly the structural non-zeros (positive entries)')

  ! dropping relative to the diagonals
  e = s
  call drop_small(e, 0.05_rp)
  ok = .true.
  do i = 1, n1
    do k = 1, n1
      if (i /= k .and. abs(ds(i, k)) < 0.05_rp * sqrt(ds(i, i) * ds(k, k))) ds(i, k) = 0.0_rp
    end do
  end do
  call suite%assert_true(matches(e, ds, o1), 'drop_small with tol 0.05 keeps what the dense filter keeps')
  call suite%assert_true(e%global_nnz() < s%global_nnz(), 'drop_small drops something')

  ! fetching every row from every rank, twice (the second fetch adds nothing)
  want = [(int(k, gp), k = n1, 1, -1)]
  call fetch_rows(s, want, store)
  call fetch_rows(s, want(1:5), store)
  ok = store%n == n1
  do k = 1, store%n
    ok = ok .and. store%gid(k) == k .and. store%key(k) == 1000 + k
    do i = store%ptr(k), store%ptr(k+1) - 1
      ok = ok .and. abs(store%val(i) - ds0(k, store%gcol(i))) == 0.0_rp
    end do
  end do
  call suite%assert_true(ok, 'fetch_rows returns every row with its key, once')

  ! to_csr: apply equals the dense product; from_csr gives the rows back
  call rmap%init(comm, int(o1(comm%rank+1) - o1(comm%rank), ip), [integer(gp) ::])
  call to_csr(a, rmap, m)
  allocate(x(m%col_map%n_owned), y(m%n_rows))
  do i = 1, m%col_map%n_owned
    x(i) = sin(real(o2(comm%rank) + i - 1, rp))
  end do
  call m%apply(x, y)
  ok = .true.
  do i = 1, m%n_rows
    ok = ok .and. abs(y(i) - dot_product(da(o1(comm%rank) + i - 1, :), [(sin(real(k, rp)), k = 1, n2)])) < 1.0e-13_rp
  end do
  call suite%assert_true(comm%sum(merge(0, 1, ok)) == 0, 'to_csr: apply equals the dense product')
  call from_csr(m, back)
  call suite%assert_true(matches(back, da, o1), 'from_csr(to_csr(a)) = a')
  call m%free()

  ! sums in place: into s's pattern (ghost columns on more ranks than one),
  ! 2 e (e: s with entries dropped, its own csr column map) - s
  call to_csr(s, rmap, ms)
  call to_csr(e, rmap, me)
  ms%val = 0.0_rp
  call add_csr_to_csr(2.0_rp, me, ms, ok)
  call add_to_csr(-1.0_rp, s, ms, ok2)
  call suite%assert_true(comm%sum(merge(0, 1, ok .and. ok2)) == 0, 'add_to_csr, add_csr_to_csr: the sums fit s''s pattern')
  call from_csr(ms, back)
  call suite%assert_true(matches(back, 2.0_rp * ds - ds0, o1), 'add_to_csr, add_csr_to_csr: 2 e - s in place')
  ! s does not fit the pattern of e, which lacks the dropped entries
  call add_to_csr(1.0_rp, s, me, ok)
  call suite%assert_true(comm%sum(merge(0, 1, ok)) > 0, 'add_to_csr: an entry outside the pattern is refused')
  ! union_to_csr: e's values on the union of e's and s's patterns (s's,
  ! with ghost columns e lacks), then s added there: e + s (me afresh: the
  ! refused sum above left part of s in it)
  call to_csr(e, rmap, me)
  call union_to_csr(me, s, rmap, mu)
  call suite%assert_true(mu%global_nnz() == s%global_nnz(), 'union_to_csr: the pattern is the union (s''s)')
  call add_to_csr(1.0_rp, s, mu, ok)
  call suite%assert_true(comm%sum(merge(0, 1, ok)) == 0, 'union_to_csr: s fits the union')
  call from_csr(mu, back)
  call suite%assert_true(matches(back, ds + ds0, o1), 'union_to_csr: e + s')
  call mu%free()
  ! with a third pattern: e's values, the union of e, e and s
  call union_to_csr(me, e, rmap, mu, s)
  call from_csr(mu, back)
  ok = matches(back, ds, o1)
  call suite%assert_true(mu%global_nnz() == s%global_nnz(), 'union_to_csr with h: the union of three patterns')
  call suite%assert_true(ok, 'union_to_csr with h: e''s values')
  call mu%free()
  call ms%free()
  call me%free()
  call suite%finish()
  call comm%finalize()

contains

  !> Deterministic sparse pattern: entry (i,j) present when mod(i*seed+j*j, 4) == 0
  !> or on the "diagonal" i == j; positive values.
  subroutine make_dense(d, seed, w)
    real(rp), intent(out) :: d(:,:)
    integer, intent(in) :: seed
    real(rp), intent(in) :: w
    integer :: i, j
    d = 0.0_rp
    do j = 1, size(d, 2)
      do i = 1, size(d, 1)
        if (mod(i * seed + j * j, 4) == 0 .or. i == j) d(i, j) = w + 0.01_rp * i + 0.001_rp * j
      end do
    end do
  end subroutine make_dense

  !> Contiguous split of n rows over the ranks (the last ones may be empty).
  subroutine split(n, off)
    integer, intent(in) :: n
    integer(gp), intent(out) :: off(0:)
    integer :: p, np
    np = comm%size
    do p = 0, np
      off(p) = 1 + (int(n, gp) * p) / np
    end do
  end subroutine split

  subroutine from_dense(d, ro, co, g)
    real(rp), intent(in) :: d(:,:)
    integer(gp), intent(in) :: ro(0:), co(0:)
    type(global_csr_t), intent(out) :: g
    integer :: i, j, m
    integer(gp) :: r0
    g%comm = comm
    allocate(g%row_offsets(0:comm%size), g%col_offsets(0:comm%size))
    g%row_offsets = ro(0:comm%size)
    g%col_offsets = co(0:comm%size)
    r0 = ro(comm%rank)
    g%n_rows = int(ro(comm%rank + 1) - r0, ip)
    allocate(g%row_ptr(g%n_rows + 1), g%gcol(count(d(r0:r0+g%n_rows-1, :) /= 0.0_rp)))
    allocate(g%val(size(g%gcol)), g%key(g%n_rows))
    g%row_ptr(1) = 1
    m = 0
    do i = 1, g%n_rows
      do j = 1, size(d, 2)
        if (d(r0 + i - 1, j) /= 0.0_rp) then
          m = m + 1
          g%gcol(m) = j
          g%val(m) = d(r0 + i - 1, j)
        end if
      end do
      g%row_ptr(i+1) = m + 1
      g%key(i) = 1000 + r0 + i - 1
    end do
  end subroutine from_dense

  !> The owned rows of g equal those of d (structure and values to 1e-14).
  logical function matches(g, d, ro)
    type(global_csr_t), intent(in) :: g
    real(rp), intent(in) :: d(:,:)
    integer(gp), intent(in) :: ro(0:)
    real(rp), allocatable :: row(:)
    integer :: i, k, bad
    integer(gp) :: r0
    r0 = ro(comm%rank)
    bad = 0
    if (g%n_rows /= ro(comm%rank + 1) - r0) bad = 1
    allocate(row(size(d, 2)))
    do i = 1, g%n_rows
      row = 0.0_rp
      do k = g%row_ptr(i), g%row_ptr(i+1) - 1
        if (k > g%row_ptr(i)) then
          if (g%gcol(k) <= g%gcol(k-1)) bad = bad + 1
        end if
        row(g%gcol(k)) = g%val(k)
      end do
      if (any(abs(row - d(r0 + i - 1, :)) > 1.0e-14_rp * maxval(abs(d)))) bad = bad + 1
    end do
    matches = comm%sum(bad) == 0
  end function matches
end program test_global_csr
