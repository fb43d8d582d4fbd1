!> Distributed sparse matrices with global column ids, for sparse algebra
!> (transpose, product, sum, dropping) and for algorithms that need rows owned
!> by other ranks (FSAI and the block-FSAI decoupling factors).
!>
!> A global_csr_t holds the owned rows of a distributed matrix; its columns
!> are global ids (ascending in each row), its row and column spaces are
!> split among ranks by offsets as in index_map_t (offsets(p) is the first
!> global id of rank p, offsets(np) the global size + 1). Every row may carry
!> an ordering key (e.g. the dof's id in the original mesh numbering, which
!> does not depend on the partition): algorithms that need an order of the
!> unknowns (triangular factors, tie breaks) use keys, so that their result
!> does not depend on the number of ranks.
!>
!> A row_store_t holds a set of rows fetched from their owners (by global id,
!> ascending) with their keys; fetch_rows() extends one, collectively.
!> to_csr() turns a global_csr_t into a csr_matrix_t (which owns the column
!> map it builds) for fast application; from_csr() goes the other way;
!> add_to_csr() adds one into a csr_matrix_t whose pattern holds it;
!> gcsr_stack() makes one matrix of a square array of blocks (a block of a
!> block system's Schur complement that spans several fields).
module global_csr
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t, sort_gids, rank_of, insertion_sort
  use csr_matrix, only: csr_matrix_t
  implicit none
  private

  public :: global_csr_t, row_store_t
  public :: from_csr, to_csr, fetch_rows, gcsr_transpose, gcsr_multiply, gcsr_add, drop_small, search_gid
  public :: add_to_csr, add_csr_to_csr, gcsr_stack, union_to_csr

  type :: global_csr_t
    type(parallel_comm_t) :: comm
    integer(gp), allocatable :: row_offsets(:)   !< (0:np) row space split
    integer(gp), allocatable :: col_offsets(:)   !< (0:np) column space split
    integer(ip) :: n_rows = 0                    !< owned rows
    integer(ip), allocatable :: row_ptr(:)       !< (n_rows+1)
    integer(gp), allocatable :: gcol(:)          !< global column ids, ascending per row
    real(rp), allocatable :: val(:)
    integer(gp), allocatable :: key(:)           !< (n_rows) ordering key of each owned row
  contains
    procedure :: first_row
    procedure :: nnz
    procedure :: global_nnz
    procedure :: set_keys
    procedure :: scale
    procedure :: free
  end type global_csr_t

  type :: row_store_t
    integer(ip) :: n = 0                         !< rows held
    integer(gp), allocatable :: gid(:)           !< (n) global row ids, ascending
    integer(gp), allocatable :: key(:)           !< (n) their keys
    integer(ip), allocatable :: ptr(:)           !< (n+1)
    integer(gp), allocatable :: gcol(:)          !< global column ids, ascending per row
    real(rp), allocatable :: val(:)
  contains
    procedure :: find => store_find
    procedure :: free => store_free
  end type row_store_t

contains

  !> Global id of the first owned row.
  integer(gp) function first_row(self)
    class(global_csr_t), intent(in) :: self
    first_row = self%row_offsets(self%comm%rank)
  end function first_row

  integer(ip) function nnz(self)
    class(global_csr_t), intent(in) :: self
    nnz = self%row_ptr(self%n_rows + 1) - 1
  end function nnz

  !> Non-zeros over all ranks. Collective.
  integer(gp) function global_nnz(self)
    class(global_csr_t), intent(in) :: self
    global_nnz = self%comm%sum(int(self%nnz(), gp))
  end function global_nnz

  !> Keys of the owned rows (default: the global row id).
  subroutine set_keys(self, key)
    class(global_csr_t), intent(inout) :: self
    integer(gp), intent(in) :: key(:)
    if (size(key) /= self%n_rows) error stop 'global_csr%set_keys: one key per owned row expected'
    self%key = key
  end subroutine set_keys

  subroutine scale(self, alpha)
    class(global_csr_t), intent(inout) :: self
    real(rp), intent(in) :: alpha
    self%val = alpha * self%val
  end subroutine scale

  subroutine free(self)
    class(global_csr_t), intent(inout) :: self
    if (allocated(self%row_offsets)) deallocate(self%row_offsets)
    if (allocated(self%col_offsets)) deallocate(self%col_offsets)
    if (allocated(self%row_ptr)) deallocate(self%row_ptr)
    if (allocated(self%gcol)) deallocate(self%gcol)
    if (allocated(self%val)) deallocate(self%val)
    if (allocated(self%key)) deallocate(self%key)
    self%n_rows = 0
  end subroutine free

  !> Position of global row g in the store, 0 if absent.
  integer(ip) function store_find(self, g)
    class(row_store_t), intent(in) :: self
    integer(gp), intent(in) :: g
    store_find = 0
    if (self%n > 0) store_find = search_gid(self%gid(1:self%n), g)
  end function store_find

  subroutine store_free(self)
    class(row_store_t), intent(inout) :: self
    if (allocated(self%gid)) deallocate(self%gid, self%key, self%ptr, self%gcol, self%val)
    self%n = 0
  end subroutine store_free

  !> Position of g in the ascending list a, 0 if absent (binary search).
  pure integer(ip) function search_gid(a, g)
    integer(gp), intent(in) :: a(:)
    integer(gp), intent(in) :: g
    integer(ip) :: lo, hi, mid
    lo = 1
    hi = size(a, kind=ip)
    search_gid = 0
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (a(mid) == g) then
        search_gid = mid
        return
      else if (a(mid) < g) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function search_gid

  !> The owned rows of m with global column ids; keys are the global row ids.
  subroutine from_csr(m, g)
    type(csr_matrix_t), intent(in) :: m
    type(global_csr_t), intent(out) :: g
    integer(ip) :: i, k
    g%comm = m%row_map%comm
    g%row_offsets = m%row_map%offsets
    g%col_offsets = m%col_map%offsets
    g%n_rows = m%n_rows
    g%row_ptr = m%row_ptr
    allocate(g%gcol(size(m%col)), g%val(size(m%col)), g%key(g%n_rows))
    do i = 1, g%n_rows
      do k = m%row_ptr(i), m%row_ptr(i+1) - 1
        g%gcol(k) = m%col_map%global_id(m%col(k))
        g%val(k) = m%val(k)
      end do
      call sort_row(g%gcol(m%row_ptr(i):m%row_ptr(i+1)-1), g%val(m%row_ptr(i):m%row_ptr(i+1)-1))
      g%key(i) = g%row_offsets(g%comm%rank) + i - 1
    end do
  end subroutine from_csr

  !> A csr_matrix_t with the rows of g, on row_map (whose owned part must be
  !> g's owned rows), and a column map built here from the columns g uses
  !> (m owns it and frees it). Collective.
  subroutine to_csr(g, row_map, m)
    type(global_csr_t), intent(in) :: g
    type(index_map_t), intent(in), target :: row_map
    type(csr_matrix_t), intent(inout) :: m
    type(index_map_t), pointer :: cmap
    integer(gp), allocatable :: ghosts(:)
    integer(ip), allocatable :: col(:)
    real(rp), allocatable :: v(:)
    integer(gp) :: c0, c1
    integer(ip) :: i, k, n, nown, me
    if (row_map%n_owned /= g%n_rows) error stop 'global_csr%to_csr: the row map does not match the rows'
    me = g%comm%rank
    c0 = g%col_offsets(me)
    c1 = g%col_offsets(me + 1) - 1
    nown = int(c1 - c0 + 1, ip)
    ! ghost columns: distinct columns outside the owned range, ascending
    n = g%nnz()
    ghosts = distinct(pack(g%gcol(1:n), g%gcol(1:n) < c0 .or. g%gcol(1:n) > c1))
    allocate(cmap)
    call cmap%init(g%comm, nown, ghosts)
    allocate(col(n), v(n))
    do i = 1, g%n_rows
      do k = g%row_ptr(i), g%row_ptr(i+1) - 1
        if (g%gcol(k) >= c0 .and. g%gcol(k) <= c1) then
          col(k) = int(g%gcol(k) - c0 + 1, ip)
        else
          col(k) = nown + search_gid(ghosts, g%gcol(k))
        end if
      end do
      call sort_local_row(col(g%row_ptr(i):g%row_ptr(i+1)-1), g%val(g%row_ptr(i):g%row_ptr(i+1)-1), &
                          v(g%row_ptr(i):g%row_ptr(i+1)-1))
    end do
    call m%init(row_map, cmap, g%row_ptr, col)
    m%val = v
    m%owned_col_map => cmap
  end subroutine to_csr

  !> A csr_matrix_t s on row_map (m's owned rows) whose pattern is the union
  !> of m's and g's (and h's), holding m's values (zero at the other
  !> entries), with a column map built here from its columns (s owns it and
  !> frees it); g and h have m's owned rows and global columns of m's column
  !> space. S* = K + C1 H~^-1 C2 is formed this way from K and the product
  !> added in place, without a global copy of K and of the sum: on the
  !> nine fractures at 2 m cells those copies set the run's peak resident
  !> memory (492 MB of its 851 MB). Collective.
  subroutine union_to_csr(m, g, row_map, s, h)
    type(csr_matrix_t), intent(in) :: m
    type(global_csr_t), intent(in) :: g
    type(index_map_t), intent(in), target :: row_map
    type(csr_matrix_t), intent(inout) :: s
    type(global_csr_t), intent(in), optional :: h
    type(index_map_t), pointer :: cmap
    integer(gp), allocatable :: ghosts(:), tmp(:), row(:)
    integer(ip), allocatable :: row_ptr(:), col(:)
    integer(gp) :: c0, c1
    integer(ip) :: i, k, nown, me, nr, at
    if (row_map%n_owned /= m%n_rows .or. g%n_rows /= m%n_rows) &
      error stop 'global_csr%union_to_csr: the rows do not match'
    me = g%comm%rank
    c0 = g%col_offsets(me)
    c1 = g%col_offsets(me + 1) - 1
    nown = int(c1 - c0 + 1, ip)
    ! ghost columns: m's, g's and h's outside the owned range, ascending
    allocate(tmp(m%col_map%n_local() - m%col_map%n_owned))
    do k = 1, size(tmp, kind=ip)
      tmp(k) = m%col_map%global_id(m%col_map%n_owned + k)
    end do
    tmp = [tmp, pack(g%gcol(1:g%nnz()), g%gcol(1:g%nnz()) < c0 .or. g%gcol(1:g%nnz()) > c1)]
    if (present(h)) tmp = [tmp, pack(h%gcol(1:h%nnz()), h%gcol(1:h%nnz()) < c0 .or. h%gcol(1:h%nnz()) > c1)]
    ghosts = distinct(tmp)
    deallocate(tmp)
    allocate(cmap)
    call cmap%init(g%comm, nown, ghosts)
    ! the rows' lengths, then their local columns (ascending) and m's values
    allocate(row_ptr(m%n_rows + 1))
    row_ptr(1) = 1
    do i = 1, m%n_rows
      call merged_row(i, row, nr)
      row_ptr(i + 1) = row_ptr(i) + nr
    end do
    allocate(col(row_ptr(m%n_rows + 1) - 1))
    do i = 1, m%n_rows
      call merged_row(i, row, nr)
      associate (c => col(row_ptr(i):row_ptr(i + 1) - 1))
        do k = 1, nr
          c(k) = local_col(row(k))
        end do
        call sort_ints(c)
      end associate
    end do
    call s%free()
    call s%init(row_map, cmap, row_ptr, col)
    deallocate(col)
    do i = 1, m%n_rows
      do k = m%row_ptr(i), m%row_ptr(i + 1) - 1
        at = s%find(i, local_col(m%col_map%global_id(m%col(k))))
        s%val(at) = s%val(at) + m%val(k)
      end do
    end do
    s%owned_col_map => cmap
  contains
    !> The distinct global columns of row i of m, g and h (ascending).
    subroutine merged_row(i, r, nr)
      integer(ip), intent(in) :: i
      integer(gp), allocatable, intent(inout) :: r(:)
      integer(ip), intent(out) :: nr
      integer(ip) :: k, j, nm, total
      nm = m%row_ptr(i + 1) - m%row_ptr(i)
      total = nm + g%row_ptr(i + 1) - g%row_ptr(i)
      if (present(h)) total = total + h%row_ptr(i + 1) - h%row_ptr(i)
      if (allocated(r)) deallocate(r)
      allocate(r(total))
      j = 0
      do k = m%row_ptr(i), m%row_ptr(i + 1) - 1
        j = j + 1
        r(j) = m%col_map%global_id(m%col(k))
      end do
      do k = g%row_ptr(i), g%row_ptr(i + 1) - 1
        j = j + 1
        r(j) = g%gcol(k)
      end do
      if (present(h)) then
        do k = h%row_ptr(i), h%row_ptr(i + 1) - 1
          j = j + 1
          r(j) = h%gcol(k)
        end do
      end if
      r = distinct(r(1:j))
      nr = size(r, kind=ip)
    end subroutine merged_row

    integer(ip) function local_col(gc)
      integer(gp), intent(in) :: gc
      if (gc >= c0 .and. gc <= c1) then
        local_col = int(gc - c0 + 1, ip)
      else
        local_col = nown + search_gid(ghosts, gc)
      end if
    end function local_col
  end subroutine union_to_csr

  !> The distinct values of a, ascending.
  function distinct(a) result(d)
    integer(gp), intent(in) :: a(:)
    integer(gp), allocatable :: d(:)
    integer(ip), allocatable :: pos(:)
    integer(ip) :: k, n
    d = a
    allocate(pos(size(d)))
    call sort_gids(d, pos)
    n = 0
    do k = 1, size(d, kind=ip)
      if (n > 0) then
        if (d(k) == d(n)) cycle
      end if
      n = n + 1
      d(n) = d(k)
    end do
    d = d(1:n)
  end function distinct

  !> m%val += alpha g%val at g's entries, where g has m's owned rows and
  !> global columns: a new sum into a matrix whose pattern holds it (S* =
  !> K + C1 H^-1 C2 refreshed in place). fits = .false. when an entry of g
  !> has no place in m (m then holds part of the sum: rebuild it). Local.
  subroutine add_to_csr(alpha, g, m, fits)
    real(rp), intent(in) :: alpha
    type(global_csr_t), intent(in) :: g
    type(csr_matrix_t), intent(inout) :: m
    logical, intent(out) :: fits
    integer(ip) :: i
    fits = g%n_rows == m%n_rows
    do i = 1, g%n_rows
      if (.not. fits) return
      call add_row(alpha, g%gcol(g%row_ptr(i):g%row_ptr(i + 1) - 1), g%val(g%row_ptr(i):g%row_ptr(i + 1) - 1), &
                   i, m, fits)
    end do
  end subroutine add_to_csr

  !> As add_to_csr, for a csr_matrix_t a (its own column map) with m's
  !> owned rows.
  subroutine add_csr_to_csr(alpha, a, m, fits)
    real(rp), intent(in) :: alpha
    type(csr_matrix_t), intent(in) :: a
    type(csr_matrix_t), intent(inout) :: m
    logical, intent(out) :: fits
    integer(gp), allocatable :: gcol(:)
    integer(ip) :: i, k
    fits = a%n_rows == m%n_rows
    allocate(gcol(max(0, maxval(a%row_ptr(2:a%n_rows + 1) - a%row_ptr(1:a%n_rows)))))
    do i = 1, a%n_rows
      if (.not. fits) return
      associate (r0 => a%row_ptr(i), r1 => a%row_ptr(i + 1) - 1)
        do k = r0, r1
          gcol(k - r0 + 1) = a%col_map%global_id(a%col(k))
        end do
        call add_row(alpha, gcol(1:r1 - r0 + 1), a%val(r0:r1), i, m, fits)
      end associate
    end do
  end subroutine add_csr_to_csr

  !> m%val(row i, columns gcol) += alpha v; fits = .false. at the first
  !> column not in the row's pattern.
  subroutine add_row(alpha, gcol, v, i, m, fits)
    real(rp), intent(in) :: alpha
    integer(gp), intent(in) :: gcol(:)
    real(rp), intent(in) :: v(:)
    integer(ip), intent(in) :: i
    type(csr_matrix_t), intent(inout) :: m
    logical, intent(inout) :: fits
    integer(ip) :: k, pos
    do k = 1, size(gcol, kind=ip)
      pos = m%find(i, m%col_map%local_id(gcol(k)))
      if (pos == 0) then
        fits = .false.
        return
      end if
      m%val(pos) = m%val(pos) + alpha * v(k)
    end do
  end subroutine add_row

  !> Sort one row by global column (values follow). Rows that are in order
  !> already (most: a column map numbers owned columns first, in order) are
  !> left as they are: the heap sort of every row of K was 4 % of a contact
  !> run's profile.
  subroutine sort_row(c, v)
    integer(gp), intent(inout) :: c(:)
    real(rp), intent(inout) :: v(:)
    integer(ip), allocatable :: pos(:)
    if (ascending(c)) return
    allocate(pos(size(c)))
    call sort_gids(c, pos)
    v = v(pos)
  end subroutine sort_row

  !> Sort one row by local column: c in place, w = v in the new order.
  subroutine sort_local_row(c, v, w)
    integer(ip), intent(inout) :: c(:)
    real(rp), intent(in) :: v(:)
    real(rp), intent(out) :: w(:)
    integer(gp), allocatable :: cg(:)
    integer(ip), allocatable :: pos(:)
    if (ascending(int(c, gp))) then
      w = v
      return
    end if
    allocate(pos(size(c)), cg(size(c)))
    cg = int(c, gp)
    call sort_gids(cg, pos)
    c = int(cg, ip)
    w = v(pos)
  end subroutine sort_local_row

  !> c(1) < c(2) < ... (strictly: a repeated column is left to the sort's caller).
  pure logical function ascending(c)
    integer(gp), intent(in) :: c(:)
    integer :: i
    ascending = .true.
    do i = 2, size(c)
      if (c(i) <= c(i - 1)) then
        ascending = .false.
        return
      end if
    end do
  end function ascending

  !> Extend store with the rows of a whose global ids are in gids and that
  !> the store does not hold yet (owned rows are copied, the others fetched
  !> from their owners). Collective: every rank calls, with its own gids.
  subroutine fetch_rows(a, gids, store)
    type(global_csr_t), intent(in) :: a
    integer(gp), intent(in) :: gids(:)
    type(row_store_t), intent(inout) :: store
    integer(gp), allocatable :: want(:), rreq(:), sg(:), rg(:)
    integer(ip), allocatable :: pos(:), scount(:), rcount(:), owner(:), slen(:), rlen(:), sc2(:), rc2(:)
    real(rp), allocatable :: sv(:), rv(:)
    integer(ip) :: np, p, k, nw, i, li, nreq, m, j
    integer(gp) :: first

    np = a%comm%size
    first = a%row_offsets(a%comm%rank)
    ! distinct wanted ids not in the store, ascending (hence grouped by owner)
    allocate(want(size(gids)), pos(size(gids)))
    want = gids
    call sort_gids(want, pos)
    nw = 0
    do k = 1, size(want, kind=ip)
      if (nw > 0) then
        if (want(k) == want(nw)) cycle
      end if
      if (store%find(want(k)) > 0) cycle
      nw = nw + 1
      want(nw) = want(k)
    end do
    allocate(owner(nw), scount(0:np-1), rcount(0:np-1))
    scount = 0
    do k = 1, nw
      owner(k) = rank_of(a%row_offsets, want(k))
      scount(owner(k)) = scount(owner(k)) + 1
    end do
    call a%comm%alltoall_i(scount, rcount)
    nreq = sum(rcount)
    allocate(rreq(nreq))
    call a%comm%alltoallv(want(1:nw), scount, rreq, rcount)
    ! answer: per requested row its key and length, then columns and values
    m = 0
    do k = 1, nreq
      li = int(rreq(k) - first + 1, ip)
      m = m + a%row_ptr(li+1) - a%row_ptr(li)
    end do
    allocate(slen(nreq), sg(nreq + m), sv(m), sc2(0:np-1), rc2(0:np-1))
    sc2 = 0
    j = 0
    i = 0
    do p = 0, np - 1
      do k = i + 1, i + rcount(p)
        li = int(rreq(k) - first + 1, ip)
        slen(k) = a%row_ptr(li+1) - a%row_ptr(li)
        sc2(p) = sc2(p) + slen(k)
      end do
      i = i + rcount(p)
    end do
    ! sg: keys of all answered rows first, then all columns (same order as sv)
    do k = 1, nreq
      li = int(rreq(k) - first + 1, ip)
      sg(k) = a%key(li)
    end do
    do k = 1, nreq
      li = int(rreq(k) - first + 1, ip)
      sg(nreq + j + 1:nreq + j + slen(k)) = a%gcol(a%row_ptr(li):a%row_ptr(li+1)-1)
      sv(j + 1:j + slen(k)) = a%val(a%row_ptr(li):a%row_ptr(li+1)-1)
      j = j + slen(k)
    end do
    allocate(rlen(nw))
    call a%comm%alltoallv(slen, rcount, rlen, scount)
    call a%comm%alltoall_i(sc2, rc2)
    allocate(rg(nw + sum(rc2)), rv(sum(rc2)))
    call a%comm%alltoallv(sg(1:nreq), rcount, rg(1:nw), scount)
    call a%comm%alltoallv(sg(nreq+1:), sc2, rg(nw+1:), rc2)
    call a%comm%alltoallv(sv, sc2, rv, rc2)
    call merge_store(store, nw, want(1:nw), rg(1:nw), rlen, rg(nw+1:), rv)
  end subroutine fetch_rows

  !> Merge new rows (ids ascending, none already held) into the store.
  subroutine merge_store(store, nn, ids, keys, lens, cols, vals)
    type(row_store_t), intent(inout) :: store
    integer(ip), intent(in) :: nn
    integer(gp), intent(in) :: ids(:), keys(:), cols(:)
    integer(ip), intent(in) :: lens(:)
    real(rp), intent(in) :: vals(:)
    type(row_store_t) :: s
    integer(ip), allocatable :: nptr(:)
    integer(ip) :: a, b, k, n, m0, m1, l
    if (.not. allocated(store%gid)) then
      allocate(store%gid(0), store%key(0), store%ptr(1), store%gcol(0), store%val(0))
      store%ptr(1) = 1
      store%n = 0
    end if
    if (nn == 0) return
    allocate(nptr(nn + 1))
    nptr(1) = 1
    do k = 1, nn
      nptr(k+1) = nptr(k) + lens(k)
    end do
    n = store%n + nn
    allocate(s%gid(n), s%key(n), s%ptr(n + 1), s%gcol(size(store%gcol) + size(cols)), &
             s%val(size(store%val) + size(vals)))
    s%ptr(1) = 1
    a = 1
    b = 1
    do k = 1, n
      if (b > nn) then
        call take_old()
      else if (a > store%n) then
        call take_new()
      else if (store%gid(a) < ids(b)) then
        call take_old()
      else
        call take_new()
      end if
    end do
    s%n = n
    call store%free()
    call move_alloc(s%gid, store%gid)
    call move_alloc(s%key, store%key)
    call move_alloc(s%ptr, store%ptr)
    call move_alloc(s%gcol, store%gcol)
    call move_alloc(s%val, store%val)
    store%n = n
  contains
    subroutine take_old()
      m0 = store%ptr(a)
      m1 = store%ptr(a+1) - 1
      l = m1 - m0 + 1
      s%gid(k) = store%gid(a)
      s%key(k) = store%key(a)
      s%gcol(s%ptr(k):s%ptr(k)+l-1) = store%gcol(m0:m1)
      s%val(s%ptr(k):s%ptr(k)+l-1) = store%val(m0:m1)
      s%ptr(k+1) = s%ptr(k) + l
      a = a + 1
    end subroutine take_old
    subroutine take_new()
      m0 = nptr(b)
      m1 = nptr(b+1) - 1
      l = m1 - m0 + 1
      s%gid(k) = ids(b)
      s%key(k) = keys(b)
      s%gcol(s%ptr(k):s%ptr(k)+l-1) = cols(m0:m1)
      s%val(s%ptr(k):s%ptr(k)+l-1) = vals(m0:m1)
      s%ptr(k+1) = s%ptr(k) + l
      b = b + 1
    end subroutine take_new
  end subroutine merge_store

  !> t = a^T: rows of t split as the columns of a. Keys of t are its global
  !> row ids. Collective.
  subroutine gcsr_transpose(a, t)
    type(global_csr_t), intent(in) :: a
    type(global_csr_t), intent(out) :: t
    integer(ip), allocatable :: scount(:), rcount(:), order(:), pos(:)
    integer(gp), allocatable :: sidx(:), ridx(:)
    real(rp), allocatable :: sv(:), rv(:)
    integer(ip) :: np, me, p, i, k, n, nin
    integer(gp) :: first
    np = a%comm%size
    me = a%comm%rank
    n = a%nnz()
    allocate(scount(0:np-1), rcount(0:np-1), order(n), pos(0:np))
    scount = 0
    do k = 1, n
      order(k) = rank_of(a%col_offsets, a%gcol(k))
      scount(order(k)) = scount(order(k)) + 1
    end do
    pos(0) = 0
    do p = 1, np
      pos(p) = pos(p-1) + scount(p-1)
    end do
    allocate(sidx(2*n), sv(n))
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        p = order(k)
        pos(p) = pos(p) + 1
        sidx(2*pos(p)-1) = a%gcol(k)
        sidx(2*pos(p)) = a%row_offsets(me) + i - 1
        sv(pos(p)) = a%val(k)
      end do
    end do
    call a%comm%alltoall_i(scount, rcount)
    nin = sum(rcount)
    allocate(ridx(2*nin), rv(nin))
    call a%comm%alltoallv(sidx, 2*scount, ridx, 2*rcount)
    call a%comm%alltoallv(sv, scount, rv, rcount)
    t%comm = a%comm
    t%row_offsets = a%col_offsets
    t%col_offsets = a%row_offsets
    t%n_rows = int(a%col_offsets(me+1) - a%col_offsets(me), ip)
    first = t%row_offsets(me)
    call from_triplets(t, nin, ridx(1:2*nin:2) - first + 1, ridx(2:2*nin:2), rv)
  end subroutine gcsr_transpose

  !> Fill rows, columns and values of t (n_rows set) from triplets with local
  !> rows; repeated (row, column) pairs are summed. Keys = global row ids.
  subroutine from_triplets(t, n, lrow, gc, v)
    type(global_csr_t), intent(inout) :: t
    integer(ip), intent(in) :: n
    integer(gp), intent(in) :: lrow(:), gc(:)
    real(rp), intent(in) :: v(:)
    integer(ip), allocatable :: cnt(:), fill(:)
    integer(gp), allocatable :: c(:)
    real(rp), allocatable :: w(:)
    integer(ip) :: i, k, m, q, r0
    allocate(cnt(t%n_rows + 1), fill(t%n_rows))
    cnt = 0
    do k = 1, n
      cnt(lrow(k) + 1) = cnt(lrow(k) + 1) + 1
    end do
    cnt(1) = 1
    do i = 1, t%n_rows
      cnt(i+1) = cnt(i+1) + cnt(i)
    end do
    allocate(c(n), w(n))
    fill = cnt(1:t%n_rows)
    do k = 1, n
      i = int(lrow(k), ip)
      c(fill(i)) = gc(k)
      w(fill(i)) = v(k)
      fill(i) = fill(i) + 1
    end do
    ! sort each row, sum repeats, compact
    allocate(t%row_ptr(t%n_rows + 1), t%gcol(n), t%val(n))
    t%row_ptr(1) = 1
    m = 0
    do i = 1, t%n_rows
      r0 = cnt(i)
      if (cnt(i+1) > r0) call sort_row(c(r0:cnt(i+1)-1), w(r0:cnt(i+1)-1))
      do q = r0, cnt(i+1) - 1
        if (q > r0) then
          if (c(q) == t%gcol(m)) then
            t%val(m) = t%val(m) + w(q)
            cycle
          end if
        end if
        m = m + 1
        t%gcol(m) = c(q)
        t%val(m) = w(q)
      end do
      t%row_ptr(i+1) = m + 1
    end do
    t%gcol = t%gcol(1:m)
    t%val = t%val(1:m)
    allocate(t%key(t%n_rows))
    do i = 1, t%n_rows
      t%key(i) = t%row_offsets(t%comm%rank) + i - 1
    end do
  end subroutine from_triplets

  !> c = a b (the columns of a are the rows of b). Rows of b that other
  !> ranks own are fetched. Keys of c are a's. Collective.
  subroutine gcsr_multiply(a, b, c)
    type(global_csr_t), intent(in) :: a, b
    type(global_csr_t), intent(out) :: c
    type(row_store_t) :: store
    integer(gp), allocatable :: cols(:)
    integer(ip), allocatable :: pos(:), marker(:), bcid(:), scid(:)
    real(rp), allocatable :: acc(:)
    integer(ip), allocatable :: list(:)
    integer(ip) :: i, k, q, r, nc, nl, cap, m, kk
    integer(gp) :: first_b

    call fetch_rows(b, pack(a%gcol(1:a%nnz()), .not. owned(b, a%gcol(1:a%nnz()))), store)
    ! compact numbering of every column that can appear in c
    first_b = b%row_offsets(b%comm%rank)
    allocate(cols(b%nnz() + size(store%gcol)))
    cols(1:b%nnz()) = b%gcol(1:b%nnz())
    cols(b%nnz()+1:) = store%gcol
    allocate(pos(size(cols)))
    call sort_gids(cols, pos)
    nc = 0
    do k = 1, size(cols, kind=ip)
      if (nc > 0) then
        if (cols(k) == cols(nc)) cycle
      end if
      nc = nc + 1
      cols(nc) = cols(k)
    end do
    ! compact column of every entry of b and of the fetched rows, found once
    allocate(bcid(b%nnz()), scid(size(store%gcol)))
    do k = 1, b%nnz()
      bcid(k) = search_gid(cols(1:nc), b%gcol(k))
    end do
    do k = 1, size(store%gcol, kind=ip)
      scid(k) = search_gid(cols(1:nc), store%gcol(k))
    end do
    allocate(marker(nc), acc(nc), list(nc))
    marker = 0
    c%comm = a%comm
    c%row_offsets = a%row_offsets
    c%col_offsets = b%col_offsets
    c%n_rows = a%n_rows
    c%key = a%key
    cap = max(16, 2 * a%nnz())
    allocate(c%row_ptr(c%n_rows + 1), c%gcol(cap), c%val(cap))
    c%row_ptr(1) = 1
    m = 0
    do i = 1, a%n_rows
      nl = 0
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        if (owned(b, a%gcol(k))) then
          r = int(a%gcol(k) - first_b + 1, ip)
          do q = b%row_ptr(r), b%row_ptr(r+1) - 1
            call accumulate(bcid(q), a%val(k) * b%val(q))
          end do
        else
          r = store%find(a%gcol(k))
          do q = store%ptr(r), store%ptr(r+1) - 1
            call accumulate(scid(q), a%val(k) * store%val(q))
          end do
        end if
      end do
      ! this row's entries in ascending column order (most rows, away from
      ! the faults, have none)
      if (nl > 0) then
        call sort_ints(list(1:nl))
        if (m + nl > cap) call grow(m + nl)
        do kk = 1, nl
          m = m + 1
          c%gcol(m) = cols(list(kk))
          c%val(m) = acc(list(kk))
          marker(list(kk)) = 0
        end do
      end if
      c%row_ptr(i+1) = m + 1
    end do
    c%gcol = c%gcol(1:m)
    c%val = c%val(1:m)
  contains
    subroutine accumulate(j, x)
      integer(ip), intent(in) :: j
      real(rp), intent(in) :: x
      if (marker(j) == 0) then
        marker(j) = 1
        nl = nl + 1
        list(nl) = j
        acc(j) = x
      else
        acc(j) = acc(j) + x
      end if
    end subroutine accumulate
    subroutine grow(need)
      integer(ip), intent(in) :: need
      integer(gp), allocatable :: gc(:)
      real(rp), allocatable :: gv(:)
      cap = max(2 * cap, need)
      allocate(gc(cap), gv(cap))
      gc(1:m) = c%gcol(1:m)
      gv(1:m) = c%val(1:m)
      call move_alloc(gc, c%gcol)
      call move_alloc(gv, c%val)
    end subroutine grow
  end subroutine gcsr_multiply

  elemental logical function owned(a, g)
    type(global_csr_t), intent(in) :: a
    integer(gp), intent(in) :: g
    owned = g >= a%row_offsets(a%comm%rank) .and. g < a%row_offsets(a%comm%rank + 1)
  end function owned

  !> Sort distinct x ascending: by insertion up to 32 entries (a row of a
  !> product; no work arrays), else by sort_gids.
  subroutine sort_ints(x)
    integer(ip), intent(inout) :: x(:)
    integer(gp), allocatable :: g(:)
    integer(ip), allocatable :: pos(:)
    if (size(x) <= 32) then
      call insertion_sort(x)
      return
    end if
    allocate(pos(size(x)), g(size(x)))
    g = int(x, gp)
    call sort_gids(g, pos)
    x = int(g, ip)
  end subroutine sort_ints

  !> c = alpha a + beta b (same row and column splits). Keys are a's.
  subroutine gcsr_add(alpha, a, beta, b, c)
    real(rp), intent(in) :: alpha, beta
    type(global_csr_t), intent(in) :: a, b
    type(global_csr_t), intent(out) :: c
    integer(ip) :: i, ka, kb, m
    if (a%n_rows /= b%n_rows) error stop 'global_csr%add: the matrices have different rows'
    c%comm = a%comm
    c%row_offsets = a%row_offsets
    c%col_offsets = a%col_offsets
    c%n_rows = a%n_rows
    c%key = a%key
    allocate(c%row_ptr(c%n_rows + 1), c%gcol(a%nnz() + b%nnz()), c%val(a%nnz() + b%nnz()))
    c%row_ptr(1) = 1
    m = 0
    do i = 1, a%n_rows
      ka = a%row_ptr(i)
      kb = b%row_ptr(i)
      do while (ka < a%row_ptr(i+1) .or. kb < b%row_ptr(i+1))
        m = m + 1
        if (kb >= b%row_ptr(i+1)) then
          c%gcol(m) = a%gcol(ka); c%val(m) = alpha * a%val(ka); ka = ka + 1
        else if (ka >= a%row_ptr(i+1)) then
          c%gcol(m) = b%gcol(kb); c%val(m) = beta * b%val(kb); kb = kb + 1
        else if (a%gcol(ka) < b%gcol(kb)) then
          c%gcol(m) = a%gcol(ka); c%val(m) = alpha * a%val(ka); ka = ka + 1
        else if (b%gcol(kb) < a%gcol(ka)) then
          c%gcol(m) = b%gcol(kb); c%val(m) = beta * b%val(kb); kb = kb + 1
        else
          c%gcol(m) = a%gcol(ka); c%val(m) = alpha * a%val(ka) + beta * b%val(kb)
          ka = ka + 1; kb = kb + 1
        end if
      end do
      c%row_ptr(i+1) = m + 1
    end do
    c%gcol = c%gcol(1:m)
    c%val = c%val(1:m)
  end subroutine gcsr_add

  !> The nb x nb blocks b (b(i,j) used where has(i,j); block row and column
  !> k share one split among ranks, taken from a present block of row k) as
  !> one matrix c over the combined space in which each rank owns its blocks'
  !> owned parts in block order: owned row i of block k is owned row
  !> (rows of blocks 1..k-1) + i, the layout of a block vector's part.
  !> Keys are the combined global ids. Collective (for c's keys: local).
  subroutine gcsr_stack(b, has, c)
    type(global_csr_t), intent(in) :: b(:,:)
    logical, intent(in) :: has(:,:)
    type(global_csr_t), intent(out) :: c
    integer(gp), allocatable :: off(:,:), first(:)
    integer(ip) :: nb, i, j, k, r, m, np, p, me, n
    integer(gp) :: g
    nb = int(size(b, 1), ip)
    ! the split of every block's space, and the combined first ids
    j = int(findloc(has(1, :), .true., dim=1), ip)
    if (j == 0) error stop 'global_csr%gcsr_stack: a block row has no block'
    c%comm = b(1, j)%comm
    np = c%comm%size
    allocate(off(nb, 0:np), first(0:np))
    do i = 1, nb
      j = int(findloc(has(i, :), .true., dim=1), ip)
      if (j == 0) error stop 'global_csr%gcsr_stack: a block row has no block'
      off(i, :) = b(i, j)%row_offsets
    end do
    me = c%comm%rank
    first(0) = 1
    do p = 1, np
      first(p) = first(p - 1) + sum(off(:, p) - off(:, p - 1))
    end do
    c%row_offsets = first
    c%col_offsets = first
    c%n_rows = int(first(me + 1) - first(me), ip)
    n = 0
    do j = 1, nb
      do i = 1, nb
        if (has(i, j)) n = n + b(i, j)%nnz()
      end do
    end do
    allocate(c%row_ptr(c%n_rows + 1), c%gcol(n), c%val(n), c%key(c%n_rows))
    c%row_ptr(1) = 1
    m = 0
    r = 0
    do i = 1, nb
      do k = 1, int(off(i, me + 1) - off(i, me), ip)
        r = r + 1
        do j = 1, nb
          if (.not. has(i, j)) cycle
          do n = b(i, j)%row_ptr(k), b(i, j)%row_ptr(k + 1) - 1
            g = b(i, j)%gcol(n)
            p = rank_of(off(j, :), g)
            m = m + 1
            c%gcol(m) = first(p) + sum(off(1:j-1, p + 1) - off(1:j-1, p)) + (g - off(j, p))
            c%val(m) = b(i, j)%val(n)
          end do
        end do
        call sort_row(c%gcol(c%row_ptr(r):m), c%val(c%row_ptr(r):m))
        c%row_ptr(r + 1) = m + 1
        c%key(r) = first(me) + r - 1
      end do
    end do
  end subroutine gcsr_stack

  !> Drop the entries of a square matrix with |a_ij| < tol sqrt(|a_ii a_jj|)
  !> (the diagonal is always kept). The diagonals of the columns are fetched
  !> from their owners. tol <= 0 keeps everything. Collective.
  subroutine drop_small(a, tol)
    type(global_csr_t), intent(inout) :: a
    real(rp), intent(in) :: tol
    type(row_store_t) :: store
    real(rp), allocatable :: d(:)
    integer(ip) :: i, k, m, r
    integer(gp) :: g, first
    real(rp) :: dj
    if (tol <= 0.0_rp) return
    first = a%row_offsets(a%comm%rank)
    allocate(d(a%n_rows))
    do i = 1, a%n_rows
      d(i) = row_value(a%gcol(a%row_ptr(i):a%row_ptr(i+1)-1), a%val(a%row_ptr(i):a%row_ptr(i+1)-1), first + i - 1)
    end do
    call fetch_rows(a, pack(a%gcol(1:a%nnz()), .not. owned(a, a%gcol(1:a%nnz()))), store)
    m = 0
    do i = 1, a%n_rows
      k = a%row_ptr(i)
      a%row_ptr(i) = m + 1
      do while (k < a%row_ptr(i+1))
        g = a%gcol(k)
        if (owned(a, g)) then
          dj = d(int(g - first + 1, ip))
        else
          r = store%find(g)
          dj = row_value(store%gcol(store%ptr(r):store%ptr(r+1)-1), store%val(store%ptr(r):store%ptr(r+1)-1), g)
        end if
        if (g == first + i - 1 .or. abs(a%val(k)) >= tol * sqrt(abs(d(i) * dj))) then
          m = m + 1
          a%gcol(m) = g
          a%val(m) = a%val(k)
        end if
        k = k + 1
      end do
    end do
    a%row_ptr(a%n_rows + 1) = m + 1
    a%gcol = a%gcol(1:m)
    a%val = a%val(1:m)
  end subroutine drop_small

  !> Value in column g of a row given by its columns and values (0 if absent).
  pure real(rp) function row_value(cols, vals, g)
    integer(gp), intent(in) :: cols(:)
    real(rp), intent(in) :: vals(:)
    integer(gp), intent(in) :: g
    integer(ip) :: k
    k = search_gid(cols, g)
    row_value = 0.0_rp
    if (k > 0) row_value = vals(k)
  end function row_value
end module global_csr
