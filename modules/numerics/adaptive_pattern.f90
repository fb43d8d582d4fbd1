!> The adaptive-pattern engine shared by geoblock's sparse approximate
!> inverses: the rows of the aFSAI factor G (afsai) and the columns of the
!> block-FSAI decoupling factors F ~ K^-1 C (block_fsai). Both grow, for
!> every "item" (a row of G or a column of F), a pattern J of rows of an SPD
!> matrix A in steps (Janna and Ferronato, SIAM J. Sci. Comput. 33 (2011)
!> 3357-3380; FSAIPACK, ACM TOMS 41 (2015)):
!>
!>   solve the dense system A[J,J] x = b_J (Cholesky, LAPACK);
!>   form the vector v = sum_q x_q A(:,J_q) (+ A(:,i) for a row i of G) on
!>     the rows next to J;
!>   score the candidates outside J from v and add the step_size best;
!>
!> then, after the last step, drop the small entries and solve again on the
!> kept pattern. What differs is passed in by extending adaptive_pattern_t:
!> the right-hand side b (the item's own row of A, or a column of C), the
!> sign of x in v, which rows may join (below the item's key, or any), the
!> scores and stopping tests, and the failure message.
!>
!> Rank independence: every ordering decision uses the rows' keys, never
!> their global ids (members are kept in key order, so the dense systems and
!> every sum are in key order; scores that agree to a relative tie_tol are
!> equal and then the smaller key wins; scores below a noise floor count as
!> zero), and all items advance one step at a time, the rows needed next
!> being fetched collectively between steps. So the patterns are the same on
!> any number of ranks and the values agree to round-off.
module adaptive_pattern
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use status_sync, only: agree
  use index_map, only: sort_gids
  use fsai_params, only: fsai_params_t
  use visible_rows, only: visible_rows_t
  implicit none
  private

  public :: adaptive_pattern_t, select_best, sort_by_key

  !> Relative tolerance under which two candidate scores count as equal (the
  !> smaller key wins): far above round-off, far below real differences.
  real(rp), parameter :: tie_tol = 1.0e-9_rp

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

  !> Patterns of all items of this rank and the state of the search. An
  !> extension sets noise_floor, fills the initial patterns (reserve, then
  !> pgid/pkey/plen and push_new) and calls grow.
  type, abstract :: adaptive_pattern_t
    type(fsai_params_t) :: params
    !> rows of the SPD matrix this rank sees
    type(visible_rows_t) :: vis
    !> candidate scores below noise_floor times the best are set to zero
    real(rp) :: noise_floor = 0.0_rp
    !> pattern of item j: pgid/pkey(pptr(j) : pptr(j)+plen(j)-1), ascending
    !> key, with the values of its last solve in pval
    integer(ip) :: n_items = 0
    integer(ip), allocatable :: pptr(:), plen(:)
    integer(gp), allocatable :: pgid(:), pkey(:)
    real(rp), allocatable :: pval(:)
    logical, allocatable :: active(:)
    !> non-owned rows that joined a pattern during this step
    integer(gp), allocatable :: newg(:)
    integer(ip) :: nnew = 0
    !> work, by visible id: mark (> 0 member position, -1 candidate, -2 seen
    !> but not a candidate), the accumulated v, and the seen rows tlist(1:nt)
    integer(ip), allocatable :: mark(:), tlist(:)
    real(rp), allocatable :: acc(:)
    integer(ip) :: nt = 0
    !> the candidates of the current item: visible id, key, score
    integer(ip), allocatable :: cl(:), chosen(:)
    integer(gp), allocatable :: ckey(:)
    real(rp), allocatable :: cs(:)
    integer(ip) :: nc = 0
    !> dense system of the current item: matrix, right-hand side, solution
    !> (x), and the members' visible ids
    real(rp), allocatable :: ad(:,:), bv(:), yv(:)
    integer(ip), allocatable :: lids(:)
    integer(ip) :: ldad = 0
    !> first failure of this rank (its label, see failure_message)
    logical :: local_fail = .false.
    integer(gp) :: bad_label = -1
  contains
    procedure(visible_int), deferred :: self_row
    procedure(item_gp), deferred :: key_limit
    procedure(item_gp), deferred :: label
    procedure(item_sub), deferred :: add_rhs
    procedure(item_ok), deferred :: finish_solve
    procedure(item_accept), deferred :: accept
    procedure(item_stop), deferred :: score
    procedure(item_worth), deferred :: worth
    procedure(scale_real), deferred :: drop_scale
    procedure(label_msg), deferred :: failure_message
    procedure :: reserve
    procedure :: push_new
    procedure :: grow
    procedure :: record_failure
    procedure :: weight_sign
  end type adaptive_pattern_t

  abstract interface
    !> Visible id of the item's own row of A (a row of G), or 0.
    integer(ip) function visible_int(self, j)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(in) :: self
      integer(ip), intent(in) :: j
    end function visible_int
    !> A key or label of item j.
    integer(gp) function item_gp(self, j)
      import :: adaptive_pattern_t, ip, gp
      class(adaptive_pattern_t), intent(in) :: self
      integer(ip), intent(in) :: j
    end function item_gp
    !> Add to bv(1:plen(j)) the item's own part of the right-hand side
    !> (mark(visible id) gives the member position).
    subroutine item_sub(self, j)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(inout), target :: self
      integer(ip), intent(in) :: j
    end subroutine item_sub
    !> After the dense solve (yv(1:plen(j)) = x): whether the solve is
    !> acceptable (ok comes in true when the Cholesky factor exists).
    subroutine item_ok(self, j, ok)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(inout), target :: self
      integer(ip), intent(in) :: j
      logical, intent(inout) :: ok
    end subroutine item_ok
    !> After a successful solve at step s (its values are in pval): keep what
    !> the item needs, and say whether the item is done.
    logical function item_accept(self, j, s)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(inout), target :: self
      integer(ip), intent(in) :: j, s
    end function item_accept
    !> From the seen rows (tlist(1:nt), acc, mark): the candidates cl, ckey,
    !> cs (1:nc); true when the item is done (or failed: record_failure).
    logical function item_stop(self, j)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(inout), target :: self
      integer(ip), intent(in) :: j
    end function item_stop
    !> Whether the nch chosen candidates are worth a step.
    logical function item_worth(self, j, nch)
      import :: adaptive_pattern_t, ip
      class(adaptive_pattern_t), intent(inout), target :: self
      integer(ip), intent(in) :: j, nch
    end function item_worth
    !> The scale of the drop test from the largest |value| of an item.
    real(rp) function scale_real(self, vmax)
      import :: adaptive_pattern_t, rp
      class(adaptive_pattern_t), intent(in) :: self
      real(rp), intent(in) :: vmax
    end function scale_real
    !> The message of a failure with this label.
    function label_msg(self, lab) result(msg)
      import :: adaptive_pattern_t, gp, msg_len
      class(adaptive_pattern_t), intent(in) :: self
      integer(gp), intent(in) :: lab
      character(len=msg_len) :: msg
    end function label_msg
  end interface

contains

  !> Storage for n_items patterns of initial lengths len0 with room for
  !> cap(j) members each; plen = len0 (the extension fills the members).
  !> status (alike on every rank) when the patterns would exceed 2^31
  !> entries on some rank.
  subroutine reserve(self, len0, cap, who, status)
    class(adaptive_pattern_t), intent(inout) :: self
    integer(ip), intent(in) :: len0(:)
    integer(gp), intent(in) :: cap(:)
    character(len=*), intent(in) :: who
    type(error_status_t), intent(inout) :: status
    integer(gp) :: total
    integer(ip) :: j
    self%n_items = size(len0)
    allocate(self%pptr(self%n_items + 1), self%plen(self%n_items))
    total = 0
    do j = 1, self%n_items
      self%plen(j) = len0(j)
      self%pptr(j) = int(total, ip) + 1
      total = total + cap(j)
    end do
    if (self%vis%a%comm%any_true(total >= huge(1_ip))) then
      call status%set(who//': the patterns need more than 2^31 entries on a rank; '// &
                      'lower max_steps * step_size')
      return
    end if
    self%pptr(self%n_items + 1) = int(total, ip) + 1
    allocate(self%pgid(total), self%pkey(total), self%pval(total), self%newg(1024))
    self%pval = 0.0_rp
    self%nnew = 0
  end subroutine reserve

  !> Remember a non-owned row that joined a pattern (its neighbours are
  !> fetched before the next step).
  subroutine push_new(self, gid)
    class(adaptive_pattern_t), intent(inout) :: self
    integer(gp), intent(in) :: gid
    integer(gp), allocatable :: tmp(:)
    if (self%nnew == size(self%newg)) then
      allocate(tmp(max(16, 2 * size(self%newg))))
      tmp(1:self%nnew) = self%newg(1:self%nnew)
      call move_alloc(tmp, self%newg)
    end if
    self%nnew = self%nnew + 1
    self%newg(self%nnew) = gid
  end subroutine push_new

  !> The adaptive search on the initial patterns: steps 0..max_steps, then
  !> the drop pass. Collective. status (alike on every rank) on a failure.
  subroutine grow(self, status)
    class(adaptive_pattern_t), intent(inout), target :: self
    type(error_status_t), intent(inout) :: status
    integer(ip) :: j, s
    call self%vis%expand(self%newg(1:self%nnew))
    allocate(self%active(self%n_items))
    self%active = .true.
    self%ldad = 0
    do s = 0, self%params%max_steps
      call prepare_work(self)
      self%nnew = 0
      do j = 1, self%n_items
        if (self%active(j)) call step(self, j, s)
      end do
      if (failed(self, status)) return
      if (s == self%params%max_steps) exit
      if (.not. self%vis%a%comm%any_true(any(self%active))) exit
      call self%vis%expand(self%newg(1:self%nnew))
    end do
    if (self%params%drop > 0.0_rp) then
      call prepare_work(self)
      do j = 1, self%n_items
        call drop(self, j)
      end do
      if (failed(self, status)) return
    end if
  end subroutine grow

  !> Work arrays sized for the visible rows and the largest pattern.
  subroutine prepare_work(self)
    class(adaptive_pattern_t), intent(inout) :: self
    integer(ip) :: n_ext, pmax
    n_ext = self%vis%count()
    if (allocated(self%mark)) deallocate(self%mark, self%acc, self%tlist, self%cl, self%ckey, self%cs)
    allocate(self%mark(n_ext), self%acc(n_ext), self%tlist(n_ext), self%cl(n_ext), self%ckey(n_ext), &
             self%cs(n_ext))
    self%mark = 0
    pmax = 1
    if (self%n_items > 0) pmax = max(1, maxval(self%plen))
    if (pmax > self%ldad) then
      if (allocated(self%ad)) deallocate(self%ad, self%bv, self%yv, self%lids)
      self%ldad = pmax
      allocate(self%ad(pmax, pmax), self%bv(pmax), self%yv(pmax), self%lids(pmax))
    end if
    if (.not. allocated(self%chosen)) allocate(self%chosen(self%params%step_size))
  end subroutine prepare_work

  !> Solve item j on its pattern: yv(1:p). A[J,J] and, for a row i of G,
  !> b = -A[J,i] come from the members' rows (symmetry of A); the extension
  !> adds the rest of b. Leaves mark() set for the members (1..p) and the
  !> item's own row (p + 1); ok is false on a non-positive pivot.
  subroutine solve(self, j, ok)
    class(adaptive_pattern_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    logical, intent(out) :: ok
    integer(ip), pointer, contiguous :: cols(:)
    real(rp), pointer, contiguous :: vals(:)
    integer(ip) :: p, o, q, k, t, mq, info, i
    p = self%plen(j)
    o = self%pptr(j) - 1
    do q = 1, p
      self%lids(q) = self%vis%id(self%pgid(o + q))
      self%mark(self%lids(q)) = q
    end do
    i = self%self_row(j)
    if (i > 0) self%mark(i) = p + 1
    ok = .true.
    if (p > 0) then
      self%ad(1:p, 1:p) = 0.0_rp
      self%bv(1:p) = 0.0_rp
      do q = 1, p
        call self%vis%row(self%lids(q), cols, vals)
        do k = 1, size(cols)
          t = cols(k)
          if (t == 0) cycle
          mq = self%mark(t)
          if (mq == 0) cycle
          if (mq <= p) then
            self%ad(q, mq) = vals(k)
          else
            self%bv(q) = -vals(k)
          end if
        end do
      end do
      call self%add_rhs(j)
      call dpotrf('L', p, self%ad, self%ldad, info)
      if (info /= 0) then
        ok = .false.
        return
      end if
      self%yv(1:p) = self%bv(1:p)
      call dpotrs('L', p, 1, self%ad, self%ldad, self%yv, self%ldad, info)
    end if
    call self%finish_solve(j, ok)
  end subroutine solve

  !> Clear the marks of item j's members and own row.
  subroutine clear_marks(self, j)
    class(adaptive_pattern_t), intent(inout) :: self
    integer(ip), intent(in) :: j
    integer(ip) :: i
    self%mark(self%lids(1:self%plen(j))) = 0
    i = self%self_row(j)
    if (i > 0) self%mark(i) = 0
  end subroutine clear_marks

  !> One step of item j: solve on the current pattern; unless the item is
  !> done, add the step_size best candidates.
  subroutine step(self, j, s)
    class(adaptive_pattern_t), intent(inout), target :: self
    integer(ip), intent(in) :: j, s
    integer(ip) :: p, o, k, t, nch
    logical :: ok
    p = self%plen(j)
    o = self%pptr(j) - 1
    call solve(self, j, ok)
    if (.not. ok) then
      call clear_marks(self, j)
      call self%record_failure(j, self%label(j))
      return
    end if
    self%pval(o+1:o+p) = self%yv(1:p)
    if (self%accept(j, s)) then
      self%active(j) = .false.
      call clear_marks(self, j)
      return
    end if
    call neighbours(self, j)
    self%nc = 0
    if (self%score(j)) self%active(j) = .false.
    self%mark(self%tlist(1:self%nt)) = 0
    call clear_marks(self, j)
    if (.not. self%active(j)) return
    if (self%nc == 0) then
      self%active(j) = .false.
      return
    end if
    call select_best(self%nc, self%cs, self%ckey, self%params%step_size, &
                     self%noise_floor * maxval(self%cs(1:self%nc)), self%chosen, nch)
    if (.not. self%worth(j, nch)) then
      self%active(j) = .false.
      return
    end if
    ! the chosen rows join the pattern (key order kept)
    do k = 1, nch
      t = self%cl(self%chosen(k))
      self%pgid(o + p + k) = self%vis%gid(t)
      self%pkey(o + p + k) = self%ckey(self%chosen(k))
      if (t > self%vis%a%n_rows) call self%push_new(self%pgid(o + p + k))
    end do
    call merge_by_key(p, nch, self%pkey(o+1:o+p+nch), self%pgid(o+1:o+p+nch))
    self%plen(j) = p + nch
  end subroutine step

  !> v = sum_q (sign x_q) A(:,J_q) (+ A(:,i) for a row i of G) on every row
  !> next to the pattern outside it, accumulated in key order of the
  !> members: acc(t) for the seen rows tlist(1:nt), mark(t) = -1 for a row
  !> below key_limit (a candidate), -2 for the others.
  subroutine neighbours(self, j)
    class(adaptive_pattern_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    integer(ip), pointer, contiguous :: cols(:)
    real(rp), pointer, contiguous :: vals(:)
    integer(ip) :: p, q, k, t, l, mt, i, last
    integer(gp) :: klim
    real(rp) :: w, sgn
    p = self%plen(j)
    i = self%self_row(j)
    klim = self%key_limit(j)
    sgn = self%weight_sign()
    last = p
    if (i > 0) last = p + 1
    self%nt = 0
    do q = 1, last
      if (q <= p) then
        l = self%lids(q)
        w = sgn * self%yv(q)
      else
        l = i
        w = 1.0_rp
      end if
      call self%vis%row(l, cols, vals)
      do k = 1, size(cols)
        t = cols(k)
        if (t == 0) error stop 'adaptive_pattern: internal error: a neighbour of a pattern was not fetched'
        mt = self%mark(t)
        if (mt == -1) then
          self%acc(t) = self%acc(t) + vals(k) * w
        else if (mt == 0) then
          self%nt = self%nt + 1
          self%tlist(self%nt) = t
          if (self%vis%key(t) < klim) then
            self%mark(t) = -1
            self%acc(t) = vals(k) * w
          else
            self%mark(t) = -2
          end if
        end if
      end do
    end do
  end subroutine neighbours

  !> The sign of x in v: +1 (a row of G: v = A g~), overridden by the
  !> decoupling factors (-1: v = -K f, the residual off the pattern).
  real(rp) function weight_sign(self)
    class(adaptive_pattern_t), intent(in) :: self
    weight_sign = 1.0_rp
  end function weight_sign

  !> After the last step: drop the entries of item j below params%drop
  !> times its drop scale and solve again on the kept pattern.
  subroutine drop(self, j)
    class(adaptive_pattern_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    integer(ip) :: p, o, q, m
    real(rp) :: vmax
    logical :: ok, done
    p = self%plen(j)
    o = self%pptr(j) - 1
    if (p == 0) return
    vmax = self%drop_scale(maxval(abs(self%pval(o+1:o+p))))
    m = 0
    do q = 1, p
      if (abs(self%pval(o + q)) >= self%params%drop * vmax) then
        m = m + 1
        self%pgid(o + m) = self%pgid(o + q)
        self%pkey(o + m) = self%pkey(o + q)
      end if
    end do
    if (m == p) return
    self%plen(j) = m
    call solve(self, j, ok)
    call clear_marks(self, j)
    if (.not. ok) then
      call self%record_failure(j, self%label(j))
      return
    end if
    self%pval(o+1:o+m) = self%yv(1:m)
    done = self%accept(j, self%params%max_steps)
  end subroutine drop

  !> Remember the first failure of this rank (label lab); item j stops.
  subroutine record_failure(self, j, lab)
    class(adaptive_pattern_t), intent(inout) :: self
    integer(ip), intent(in) :: j
    integer(gp), intent(in) :: lab
    if (.not. self%local_fail) self%bad_label = lab
    self%local_fail = .true.
    self%active(j) = .false.
  end subroutine record_failure

  !> Collective: true (and status set alike on every rank) when some rank
  !> met a failure.
  logical function failed(self, status)
    class(adaptive_pattern_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    failed = self%vis%a%comm%any_true(self%local_fail)
    if (.not. failed) return
    if (self%local_fail) call status%set(trim(self%failure_message(self%bad_label)))
    call agree(self%vis%a%comm, status)
  end function failed

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
end module adaptive_pattern
