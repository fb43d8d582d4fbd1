!> Adaptive factorized sparse approximate inverse (aFSAI) of a distributed
!> symmetric positive definite matrix A: a sparse lower triangular G with
!> G^T G ~ A^-1 (Kolotilina and Yeremin's FSAI, SIAM J. Matrix Anal. Appl. 14
!> (1993); adaptive pattern after Janna and Ferronato, SIAM J. Sci. Comput. 33
!> (2011) 3357-3380, and FSAIPACK, ACM TOMS 41 (2015)).
!>
!> Row i of G, on the pattern P (entries j with key(j) < key(i)): solve the
!> dense system A[P,P] y = -A[P,i], set g~ = [y; 1] and d = g~^T A g~ =
!> A_ii + A[i,P] y, and take the row g~ / sqrt(d) (so G A G^T has a unit
!> diagonal). d is the objective of the row: minimizing it row by row
!> minimizes Kaporin's condition number of G A G^T (Janna and Ferronato
!> 2011). The pattern grows in steps: the gradient of d with respect to an
!> entry j outside P is 2 (A g~)_j, and adding j alone lowers d by
!> (A g~)_j^2 / A_jj; each step adds the step_size entries of largest
!> predicted decrease. After the last step, entries below params%drop of
!> the row's largest are dropped and the row is solved again on the kept
!> pattern (so G A G^T keeps its unit diagonal).
!>
!> Rank independence: every ordering decision uses the rows' keys, never
!> their global ids ("lower" means a smaller key; the unknowns of each dense
!> system are ordered by key, and so are the terms of every sum; scores
!> that agree to a relative tie_tol are equal and then the smaller key wins;
!> scores below a noise floor count as zero), and all rows advance one step
!> at a time, the rows needed next being fetched collectively between
!> steps. So the pattern of G is the same on any number of ranks and the
!> values agree to round-off.
!>
!> The rows this rank can see ("visible rows": its owned rows and the rows
!> fetched into a row_store_t) are numbered by a visible id: owned row i is i,
!> stored row r is n_rows + r. Visible ids change when the store grows, so
!> they only live within one step. The helpers that work on visible rows are
!> public because the decoupling factors of block_fsai use them too.
module afsai
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use status_sync, only: agree
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t, row_store_t, fetch_rows, search_gid
  use fsai_params, only: fsai_params_t
  implicit none
  private

  public :: afsai_factor
  ! machinery shared with block_fsai
  public :: check_square, visible_id, visible_gid, visible_row, visible_tables, ghost_columns, &
            fetch_neighbours, select_best, sort_by_key, merge_by_key, append_gid

  !> Relative tolerance under which two candidate scores count as equal (the
  !> smaller key wins): far above round-off, far below real differences.
  real(rp), parameter :: tie_tol = 1.0e-9_rp
  !> aFSAI scores are squared gradients: scores below this fraction of the
  !> best one (gradients below 1e-8 of the largest) are round-off noise and
  !> count as zero, so that noise does not order them.
  real(rp), parameter :: noise_floor = 1.0e-16_rp
  !> and a candidate whose predicted decrease of d is below this fraction of
  !> d is noise too (it matters when every candidate is noise)
  real(rp), parameter :: d_floor = 1.0e-20_rp

  ! LAPACK (reference interfaces, LAPACK Users' Guide 3rd ed.)
  interface
    !> Cholesky factorization A = L L^T of the leading n x n block (uplo 'L').
    subroutine dpotrf(uplo, n, a, lda, info)
      import :: rp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(rp), intent(inout) :: a(lda, *)
      integer, intent(out) :: info
    end subroutine dpotrf
    !> Solve A X = B with the factor of dpotrf.
    subroutine dpotrs(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: rp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(rp), intent(in) :: a(lda, *)
      real(rp), intent(inout) :: b(ldb, *)
      integer, intent(out) :: info
    end subroutine dpotrs
  end interface

contains

  !> G, lower triangular in key order with G^T G ~ A^-1 and G A G^T of unit
  !> diagonal, for the SPD matrix a (square: the same row and column split;
  !> keys: a partition-independent ordering id per row, all distinct). g has
  !> a's rows, columns and keys. Collective. status reports, on every rank
  !> alike, bad params, a matrix that is not square or lacks keys, and a
  !> non-positive pivot (A not SPD) with the key of the row where it showed.
  subroutine afsai_factor(a, params, g, status)
    type(global_csr_t), intent(in), target :: a
    type(fsai_params_t), intent(in) :: params
    type(global_csr_t), intent(out) :: g
    type(error_status_t), intent(inout) :: status
    type(row_store_t), target :: store
    ! pattern of each owned row (off-diagonal members, ascending key)
    integer(ip), allocatable :: pptr(:), plen(:)
    integer(gp), allocatable :: pgid(:), pkey(:)
    real(rp), allocatable :: pval(:), dval(:)      ! y of the last solve, and d
    logical, allocatable :: active(:)
    ! visible rows
    integer(gp), allocatable :: key_ext(:), newg(:), req(:)
    real(rp), allocatable :: diag_ext(:)
    integer(ip), allocatable, target :: vcol_a(:), vcol_s(:)
    ! work
    integer(ip), allocatable :: mark(:), lids(:), tlist(:), cl(:), chosen(:)
    integer(gp), allocatable :: ckey(:)
    real(rp), allocatable :: acc(:), cs(:), ad(:,:), bv(:), yv(:)
    integer(ip) :: n, i, s, nnew, ldad
    integer(gp) :: first, bad_key
    logical :: local_fail

    call params%validate(status)
    if (.not. status%ok()) return
    call check_square(a, 'afsai_factor', status)
    if (.not. status%ok()) return
    n = a%n_rows
    first = a%row_offsets(a%comm%rank)
    local_fail = .false.
    bad_key = -1

    ! the rows one step outside this rank (ghost columns), then the start
    call ghost_columns(a, req)
    call fetch_rows(a, req, store)
    call visible_tables(a, store, key_ext, diag_ext, vcol_a, vcol_s)
    call initial_pattern()
    if (.not. status%ok()) return
    call fetch_neighbours(a, store, newg(1:nnew))
    call visible_tables(a, store, key_ext, diag_ext, vcol_a, vcol_s)
    allocate(dval(n), active(n))
    dval = 0.0_rp
    active = .true.
    ldad = 0

    do s = 0, params%max_steps
      call prepare_work()
      nnew = 0
      do i = 1, n
        if (active(i)) call process_row(i, s)
      end do
      if (failed()) return
      if (s == params%max_steps) exit
      if (.not. a%comm%any_true(any(active))) exit
      call fetch_neighbours(a, store, newg(1:nnew))
      call visible_tables(a, store, key_ext, diag_ext, vcol_a, vcol_s)
    end do

    if (params%drop > 0.0_rp) then
      call prepare_work()
      do i = 1, n
        call drop_row(i)
      end do
      if (failed()) return
    end if
    call build_factor()

  contains

    !> Members of each row before the first step, their storage (room for
    !> max_steps * step_size more per row) and the non-owned members in newg.
    subroutine initial_pattern()
      integer(ip) :: k, m, t
      integer(gp) :: total, room
      allocate(pptr(n + 1), plen(n))
      room = int(params%max_steps, gp) * int(params%step_size, gp)
      total = 0
      do i = 1, n
        plen(i) = 0
        if (params%init == 'lower') then
          do k = a%row_ptr(i), a%row_ptr(i+1) - 1
            t = vcol_a(k)
            if (key_ext(t) < a%key(i)) plen(i) = plen(i) + 1
          end do
        end if
        pptr(i) = int(total, ip) + 1
        total = total + min(int(plen(i), gp) + room, a%row_offsets(a%comm%size) - 2)
      end do
      if (a%comm%any_true(total >= huge(1_ip))) then
        call status%set('afsai_factor: the patterns need more than 2^31 entries on a rank; '// &
                        'lower max_steps * step_size')
        return
      end if
      pptr(n + 1) = int(total, ip) + 1
      allocate(pgid(total), pkey(total), pval(total), newg(1024))
      pval = 0.0_rp
      nnew = 0
      do i = 1, n
        m = pptr(i) - 1
        if (params%init == 'lower') then
          do k = a%row_ptr(i), a%row_ptr(i+1) - 1
            t = vcol_a(k)
            if (key_ext(t) < a%key(i)) then
              m = m + 1
              pgid(m) = a%gcol(k)
              pkey(m) = key_ext(t)
              if (t > n) call push_new(a%gcol(k))
            end if
          end do
          call sort_by_key(pkey(pptr(i):m), pgid(pptr(i):m))
        end if
      end do
    end subroutine initial_pattern

    !> Remember a new non-owned member (its neighbours are fetched next).
    subroutine push_new(gid)
      integer(gp), intent(in) :: gid
      call append_gid(newg, nnew, gid)
    end subroutine push_new

    !> Work arrays sized for the visible rows and the largest pattern.
    subroutine prepare_work()
      integer(ip) :: n_ext, pmax
      n_ext = n + store%n
      if (allocated(mark)) deallocate(mark, acc, tlist, cl, ckey, cs)
      allocate(mark(n_ext), acc(n_ext), tlist(n_ext), cl(n_ext), ckey(n_ext), cs(n_ext))
      mark = 0
      pmax = 1
      if (n > 0) pmax = max(1, maxval(plen))
      if (pmax > ldad) then
        if (allocated(ad)) deallocate(ad, bv, yv, lids)
        ldad = pmax
        allocate(ad(ldad, ldad), bv(ldad), yv(ldad), lids(ldad))
      end if
      if (.not. allocated(chosen)) allocate(chosen(params%step_size))
    end subroutine prepare_work

    !> Solve row i on its pattern: yv(1:p) and d. Leaves mark() set for the
    !> members (1..p) and for i (p + 1); ok is false on a non-positive pivot.
    subroutine solve_row(i, d, ok)
      integer(ip), intent(in) :: i
      real(rp), intent(out) :: d
      logical, intent(out) :: ok
      integer(ip), pointer, contiguous :: cols(:)
      real(rp), pointer, contiguous :: vals(:)
      integer(ip) :: p, o, q, k, t, mq, info
      p = plen(i)
      o = pptr(i) - 1
      do q = 1, p
        lids(q) = visible_id(a, store, pgid(o + q))
        mark(lids(q)) = q
      end do
      mark(i) = p + 1
      d = diag_ext(i)
      ok = .true.
      if (p > 0) then
        ! A[P,P] and b = -A[P,i] from the members' rows (symmetry of A)
        ad(1:p, 1:p) = 0.0_rp
        bv(1:p) = 0.0_rp
        do q = 1, p
          call visible_row(a, store, vcol_a, vcol_s, lids(q), cols, vals)
          do k = 1, size(cols)
            t = cols(k)
            if (t == 0) cycle
            mq = mark(t)
            if (mq == 0) cycle
            if (mq <= p) then
              ad(q, mq) = vals(k)
            else
              bv(q) = -vals(k)
            end if
          end do
        end do
        call dpotrf('L', p, ad, ldad, info)
        if (info /= 0) then
          ok = .false.
          return
        end if
        yv(1:p) = bv(1:p)
        call dpotrs('L', p, 1, ad, ldad, yv, ldad, info)
        d = d - dot_product(yv(1:p), bv(1:p))
      end if
      ok = d > 0.0_rp .and. ieee_is_finite(d)
    end subroutine solve_row

    !> Clear the marks of row i's members and of i.
    subroutine clear_marks(i)
      integer(ip), intent(in) :: i
      mark(lids(1:plen(i))) = 0
      mark(i) = 0
    end subroutine clear_marks

    !> One step of row i: solve on the current pattern; unless the row is
    !> done, add the step_size entries of largest predicted decrease of d.
    subroutine process_row(i, s)
      integer(ip), intent(in) :: i, s
      integer(ip), pointer, contiguous :: cols(:)
      real(rp), pointer, contiguous :: vals(:)
      integer(ip) :: p, o, q, k, t, nt, nc, nch, l, mt
      real(rp) :: d, w, pred
      logical :: ok, stop_now

      p = plen(i)
      o = pptr(i) - 1
      call solve_row(i, d, ok)
      if (.not. ok) then
        call clear_marks(i)
        call record_failure(i)
        return
      end if
      ! the actual decrease of d over the last step
      stop_now = s == params%max_steps
      if (s > 0 .and. params%tol > 0.0_rp) stop_now = stop_now .or. dval(i) - d < params%tol * dval(i)
      pval(o+1:o+p) = yv(1:p)
      dval(i) = d
      if (stop_now) then
        active(i) = .false.
        call clear_marks(i)
        return
      end if

      ! (A g~)_j for every j next to the pattern, from the rows of P + {i};
      ! mark(j) < 0 flags a j seen: -1 a candidate (below i in key order),
      ! -2 not one (its sum is not needed)
      nt = 0
      do q = 1, p + 1
        if (q <= p) then
          l = lids(q)
          w = yv(q)
        else
          l = i
          w = 1.0_rp
        end if
        call visible_row(a, store, vcol_a, vcol_s, l, cols, vals)
        do k = 1, size(cols)
          t = cols(k)
          if (t == 0) error stop 'afsai_factor: internal error: a neighbour of a pattern was not fetched'
          mt = mark(t)
          if (mt == -1) then
            acc(t) = acc(t) + vals(k) * w
          else if (mt == 0) then
            nt = nt + 1
            tlist(nt) = t
            if (key_ext(t) < a%key(i)) then
              mark(t) = -1
              acc(t) = vals(k) * w
            else
              mark(t) = -2
            end if
          end if
        end do
      end do
      ! candidates: outside the pattern, below i in key order
      nc = 0
      do k = 1, nt
        t = tlist(k)
        if (mark(t) == -1) then
          nc = nc + 1
          cl(nc) = t
          ckey(nc) = key_ext(t)
          cs(nc) = 0.0_rp
          if (diag_ext(t) > 0.0_rp) cs(nc) = acc(t)**2 / diag_ext(t)
          if (cs(nc) <= d_floor * d) cs(nc) = 0.0_rp
        end if
        mark(t) = 0
      end do
      do k = 1, nc
        if (diag_ext(cl(k)) > 0.0_rp) cycle
        call clear_marks(i)
        call record_failure(cl(k))
        return
      end do
      call clear_marks(i)
      if (nc == 0) then
        active(i) = .false.
        return
      end if
      call select_best(nc, cs, ckey, params%step_size, noise_floor * maxval(cs(1:nc)), chosen, nch)
      pred = 0.0_rp
      do k = 1, nch
        pred = pred + cs(chosen(k))
      end do
      if (params%tol > 0.0_rp .and. pred < params%tol * d) then
        active(i) = .false.
        return
      end if
      ! the chosen entries join the pattern (key order kept)
      do k = 1, nch
        t = cl(chosen(k))
        pgid(o + p + k) = visible_gid(a, store, t)
        pkey(o + p + k) = ckey(chosen(k))
        if (t > n) call push_new(pgid(o + p + k))
      end do
      call merge_by_key(p, nch, pkey(o+1:o+p+nch), pgid(o+1:o+p+nch))
      plen(i) = p + nch
    end subroutine process_row

    !> After the last step: drop the small entries of row i and solve again
    !> on the kept pattern (the best row there; G A G^T keeps a unit diagonal).
    subroutine drop_row(i)
      integer(ip), intent(in) :: i
      integer(ip) :: p, o, q, m
      real(rp) :: vmax, d
      logical :: ok
      p = plen(i)
      o = pptr(i) - 1
      if (p == 0) return
      vmax = max(1.0_rp, maxval(abs(pval(o+1:o+p))))
      m = 0
      do q = 1, p
        if (abs(pval(o + q)) >= params%drop * vmax) then
          m = m + 1
          pgid(o + m) = pgid(o + q)
          pkey(o + m) = pkey(o + q)
        end if
      end do
      if (m == p) return
      plen(i) = m
      call solve_row(i, d, ok)
      call clear_marks(i)
      if (.not. ok) then
        call record_failure(i)
        return
      end if
      pval(o+1:o+m) = yv(1:m)
      dval(i) = d
    end subroutine drop_row

    !> Remember the first non-positive pivot of this rank (visible row t).
    subroutine record_failure(t)
      integer(ip), intent(in) :: t
      if (.not. local_fail) bad_key = key_ext(t)
      local_fail = .true.
      if (t <= n) active(t) = .false.
    end subroutine record_failure

    !> Collective: true (and status set alike on every rank) when some rank
    !> met a non-positive pivot.
    logical function failed()
      character(len=msg_len) :: msg
      failed = a%comm%any_true(local_fail)
      if (.not. failed) return
      if (local_fail) then
        write(msg, '(a,i0,a)') 'afsai_factor: the matrix is not symmetric positive definite '// &
          '(non-positive pivot in the dense system of the row with key ', bad_key, ')'
        call status%set(trim(msg))
      end if
      call agree(a%comm, status)
      call g%free()
    end function failed

    !> G from the patterns and values: row i = [y; 1] / sqrt(d), columns
    !> ascending by global id.
    subroutine build_factor()
      integer(ip) :: p, o, m, k, r
      integer(gp), allocatable :: cg(:)
      integer(ip), allocatable :: cp(:)
      real(rp), allocatable :: cv(:)
      real(rp) :: sc
      g%comm = a%comm
      g%row_offsets = a%row_offsets
      g%col_offsets = a%col_offsets
      g%n_rows = n
      g%key = a%key
      allocate(g%row_ptr(n + 1))
      g%row_ptr(1) = 1
      do i = 1, n
        g%row_ptr(i + 1) = g%row_ptr(i) + plen(i) + 1
      end do
      allocate(g%gcol(g%row_ptr(n + 1) - 1), g%val(g%row_ptr(n + 1) - 1))
      m = 0
      if (n > 0) m = maxval(plen)
      allocate(cg(m + 1), cp(m + 1), cv(m + 1))
      do i = 1, n
        p = plen(i)
        o = pptr(i) - 1
        sc = 1.0_rp / sqrt(dval(i))
        cg(1:p) = pgid(o+1:o+p)
        cv(1:p) = pval(o+1:o+p) * sc
        cg(p + 1) = first + i - 1
        cv(p + 1) = sc
        call sort_gids(cg(1:p+1), cp(1:p+1))
        r = g%row_ptr(i) - 1
        do k = 1, p + 1
          m = cp(k)
          g%gcol(r + k) = cg(k)
          g%val(r + k) = cv(m)
        end do
      end do
    end subroutine build_factor
  end subroutine afsai_factor

  !> Status error (alike on every rank) unless a is square (same row and
  !> column split) and has one key per owned row. Collective.
  subroutine check_square(a, who, status)
    type(global_csr_t), intent(in) :: a
    character(len=*), intent(in) :: who
    type(error_status_t), intent(inout) :: status
    logical :: bad
    if (.not. allocated(a%row_offsets) .or. .not. allocated(a%col_offsets)) then
      call status%set(who//': the matrix has no row or column split')
      return
    end if
    if (size(a%row_offsets) /= size(a%col_offsets)) then
      call status%set(who//': the matrix is not square')
    else if (any(a%row_offsets /= a%col_offsets)) then
      call status%set(who//': the matrix is not square (rows and columns split differently)')
    end if
    if (.not. status%ok()) return
    bad = .not. allocated(a%key)
    if (.not. bad) bad = size(a%key) /= a%n_rows
    if (a%comm%any_true(bad)) call status%set(who//': the matrix needs one ordering key per owned row')
  end subroutine check_square

  !> Whether global row g is owned by this rank.
  pure logical function is_owned(a, g)
    type(global_csr_t), intent(in) :: a
    integer(gp), intent(in) :: g
    is_owned = g >= a%row_offsets(a%comm%rank) .and. g < a%row_offsets(a%comm%rank + 1)
  end function is_owned

  !> Visible id of global row g (owned: its local row; fetched: n_rows + its
  !> position in the store), 0 when this rank cannot see that row.
  pure integer(ip) function visible_id(a, store, g)
    type(global_csr_t), intent(in) :: a
    type(row_store_t), intent(in) :: store
    integer(gp), intent(in) :: g
    integer(gp) :: first
    first = a%row_offsets(a%comm%rank)
    if (g >= first .and. g < a%row_offsets(a%comm%rank + 1)) then
      visible_id = int(g - first, ip) + 1
    else
      visible_id = 0
      if (store%n > 0) visible_id = search_gid(store%gid(1:store%n), g)
      if (visible_id > 0) visible_id = visible_id + a%n_rows
    end if
  end function visible_id

  !> Global id of visible row t.
  pure integer(gp) function visible_gid(a, store, t)
    type(global_csr_t), intent(in) :: a
    type(row_store_t), intent(in) :: store
    integer(ip), intent(in) :: t
    if (t <= a%n_rows) then
      visible_gid = a%row_offsets(a%comm%rank) + t - 1
    else
      visible_gid = store%gid(t - a%n_rows)
    end if
  end function visible_gid

  !> Visible column ids (see visible_tables) and values of visible row t
  !> (pointers into vcol_a and a, or vcol_s and the store).
  subroutine visible_row(a, store, vcol_a, vcol_s, t, cols, vals)
    type(global_csr_t), intent(in), target :: a
    type(row_store_t), intent(in), target :: store
    integer(ip), intent(in), target, contiguous :: vcol_a(:), vcol_s(:)
    integer(ip), intent(in) :: t
    integer(ip), pointer, contiguous, intent(out) :: cols(:)
    real(rp), pointer, contiguous, intent(out) :: vals(:)
    integer(ip) :: r
    if (t <= a%n_rows) then
      cols => vcol_a(a%row_ptr(t):a%row_ptr(t+1)-1)
      vals => a%val(a%row_ptr(t):a%row_ptr(t+1)-1)
    else
      r = t - a%n_rows
      cols => vcol_s(store%ptr(r):store%ptr(r+1)-1)
      vals => store%val(store%ptr(r):store%ptr(r+1)-1)
    end if
  end subroutine visible_row

  !> Key and diagonal entry of every visible row (by visible id), and the
  !> visible id of the column of every entry of a (vcol_a) and of the store
  !> (vcol_s), 0 for a column whose row is not visible. To be redone after
  !> every fetch (visible ids of stored rows move).
  subroutine visible_tables(a, store, key, diag, vcol_a, vcol_s)
    type(global_csr_t), intent(in) :: a
    type(row_store_t), intent(in) :: store
    integer(gp), allocatable, intent(inout) :: key(:)
    real(rp), allocatable, intent(inout) :: diag(:)
    integer(ip), allocatable, intent(inout) :: vcol_a(:), vcol_s(:)
    integer(ip) :: n, r, k, nz
    integer(gp) :: first, last
    n = a%n_rows
    first = a%row_offsets(a%comm%rank)
    last = a%row_offsets(a%comm%rank + 1) - 1
    if (allocated(key)) deallocate(key)
    if (allocated(diag)) deallocate(diag)
    if (allocated(vcol_a)) deallocate(vcol_a)
    if (allocated(vcol_s)) deallocate(vcol_s)
    nz = a%nnz()
    allocate(key(n + store%n), diag(n + store%n), vcol_a(nz), vcol_s(store%ptr(store%n + 1) - 1))
    do k = 1, nz
      if (a%gcol(k) >= first .and. a%gcol(k) <= last) then
        vcol_a(k) = int(a%gcol(k) - first, ip) + 1
      else
        vcol_a(k) = visible_id(a, store, a%gcol(k))
      end if
    end do
    do k = 1, size(vcol_s)
      vcol_s(k) = visible_id(a, store, store%gcol(k))
    end do
    key(1:n) = a%key(1:n)
    do r = 1, n
      diag(r) = 0.0_rp
      do k = a%row_ptr(r), a%row_ptr(r+1) - 1
        if (vcol_a(k) == r) diag(r) = a%val(k)
      end do
    end do
    do r = 1, store%n
      key(n + r) = store%key(r)
      diag(n + r) = 0.0_rp
      do k = store%ptr(r), store%ptr(r+1) - 1
        if (vcol_s(k) == n + r) diag(n + r) = store%val(k)
      end do
    end do
  end subroutine visible_tables

  !> The columns of a's owned rows that other ranks own (with repeats).
  subroutine ghost_columns(a, gids)
    type(global_csr_t), intent(in) :: a
    integer(gp), allocatable, intent(out) :: gids(:)
    integer(ip) :: k, m, nz
    nz = a%nnz()
    m = 0
    do k = 1, nz
      if (.not. is_owned(a, a%gcol(k))) m = m + 1
    end do
    allocate(gids(m))
    m = 0
    do k = 1, nz
      if (.not. is_owned(a, a%gcol(k))) then
        m = m + 1
        gids(m) = a%gcol(k)
      end if
    end do
  end subroutine ghost_columns

  !> Make the neighbours of the rows gids visible: fetch the columns of the
  !> fetched (non-owned) rows among gids that are neither owned nor stored.
  !> The owned rows' neighbours are visible once the ghost columns are (see
  !> ghost_columns). Every row in gids must be visible. Collective (one
  !> fetch_rows call on every rank).
  subroutine fetch_neighbours(a, store, gids)
    type(global_csr_t), intent(in) :: a
    type(row_store_t), intent(inout) :: store
    integer(gp), intent(in) :: gids(:)
    integer(gp), allocatable :: u(:), req(:)
    integer(ip), allocatable :: pos(:)
    integer(ip) :: k, nu, r, m, q
    allocate(u(size(gids)), pos(size(gids)))
    u(:) = gids
    call sort_gids(u, pos)
    nu = 0
    m = 0
    do k = 1, size(u, kind=ip)
      if (nu > 0) then
        if (u(k) == u(nu)) cycle
      end if
      if (is_owned(a, u(k))) cycle
      nu = nu + 1
      u(nu) = u(k)
      r = store%find(u(k))
      if (r == 0) error stop 'afsai%fetch_neighbours: a row to expand is not visible'
      m = m + store%ptr(r+1) - store%ptr(r)
    end do
    allocate(req(m))
    m = 0
    do k = 1, nu
      r = store%find(u(k))
      do q = store%ptr(r), store%ptr(r+1) - 1
        if (is_owned(a, store%gcol(q))) cycle
        if (store%find(store%gcol(q)) > 0) cycle
        m = m + 1
        req(m) = store%gcol(q)
      end do
    end do
    call fetch_rows(a, req(1:m), store)
  end subroutine fetch_neighbours

  !> Choose up to k of the n candidates: repeatedly, among the candidates
  !> left, the smallest key among those whose score lies within the
  !> relative tie_tol of the largest score left; scores <= floor are set to
  !> zero first (noise). chosen(1:n_chosen) are positions in 1..n. The
  !> choice depends on the set of (key, score) pairs only, not on their
  !> order, and round-off in the scores changes it only when a score lies
  !> within round-off of a threshold.
  subroutine select_best(n, score, key, k, floor, chosen, n_chosen)
    integer(ip), intent(in) :: n, k
    real(rp), intent(inout) :: score(:)
    integer(gp), intent(in) :: key(:)
    real(rp), intent(in) :: floor
    integer(ip), intent(out) :: chosen(:)
    integer(ip), intent(out) :: n_chosen
    logical :: taken(n)
    integer(ip) :: cand(n), j, best, x, y, m
    real(rp) :: top(max(1, min(k, n))), smax, thr
    where (score(1:n) <= floor) score(1:n) = 0.0_rp
    if (k >= n) then
      n_chosen = n
      chosen(1:n) = [(j, j = 1, n)]
      return
    end if
    ! every pass's largest score left is at least the k-th largest score,
    ! so no candidate below that times (1 - tie_tol) can be chosen
    top = -1.0_rp
    do x = 1, n
      if (score(x) <= top(k)) cycle
      y = k
      do while (y > 1)
        if (top(y - 1) >= score(x)) exit
        top(y) = top(y - 1)
        y = y - 1
      end do
      top(y) = score(x)
    end do
    thr = top(k) * (1.0_rp - tie_tol)
    m = 0
    do x = 1, n
      if (score(x) < thr) cycle
      m = m + 1
      cand(m) = x
    end do
    taken(cand(1:m)) = .false.
    n_chosen = k
    do j = 1, k
      smax = -1.0_rp
      do y = 1, m
        if (.not. taken(cand(y))) smax = max(smax, score(cand(y)))
      end do
      thr = smax * (1.0_rp - tie_tol)
      best = 0
      do y = 1, m
        x = cand(y)
        if (taken(x) .or. score(x) < thr) cycle
        if (best == 0) then
          best = x
        else if (key(x) < key(best)) then
          best = x
        end if
      end do
      taken(best) = .true.
      chosen(j) = best
    end do
  end subroutine select_best

  !> Sort (key, gid) pairs by ascending key.
  subroutine sort_by_key(key, gid)
    integer(gp), intent(inout) :: key(:), gid(:)
    integer(ip) :: pos(size(key))
    if (size(key) < 2) return
    call sort_gids(key, pos)
    gid = gid(pos)
  end subroutine sort_by_key

  !> key(1:n1) is ascending (gid alike): sort key(1:n1+n2) in place, by
  !> insertion for a few new entries, else by sorting and merging.
  subroutine merge_by_key(n1, n2, key, gid)
    integer(ip), intent(in) :: n1, n2
    integer(gp), intent(inout) :: key(:), gid(:)
    integer(gp) :: k1(n1), g1(n1), kb, gb
    integer(ip) :: a, b, m
    if (n2 == 0) return
    if (n2 <= 16) then
      do b = n1 + 1, n1 + n2
        kb = key(b)
        gb = gid(b)
        a = b - 1
        do while (a >= 1)
          if (key(a) <= kb) exit
          key(a + 1) = key(a)
          gid(a + 1) = gid(a)
          a = a - 1
        end do
        key(a + 1) = kb
        gid(a + 1) = gb
      end do
      return
    end if
    call sort_by_key(key(n1+1:n1+n2), gid(n1+1:n1+n2))
    k1 = key(1:n1)
    g1 = gid(1:n1)
    a = 1
    b = n1 + 1
    do m = 1, n1 + n2
      if (a > n1) exit
      if (b <= n1 + n2) then
        if (key(b) < k1(a)) then
          key(m) = key(b)
          gid(m) = gid(b)
          b = b + 1
          cycle
        end if
      end if
      key(m) = k1(a)
      gid(m) = g1(a)
      a = a + 1
    end do
  end subroutine merge_by_key

  !> list(1:n) gets gid appended (the list doubles when full).
  subroutine append_gid(list, n, gid)
    integer(gp), allocatable, intent(inout) :: list(:)
    integer(ip), intent(inout) :: n
    integer(gp), intent(in) :: gid
    integer(gp), allocatable :: tmp(:)
    if (n == size(list)) then
      allocate(tmp(max(16, 2 * size(list))))
      tmp(1:n) = list(1:n)
      call move_alloc(tmp, list)
    end if
    n = n + 1
    list(n) = gid
  end subroutine append_gid
end module afsai
