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
!> The adaptive steps, the key-ordered choices that make the pattern the same
!> on any number of ranks, and the drop pass are the engine of
!> adaptive_pattern (shared with the decoupling factors of block_fsai); this
!> module gives its row-specific parts: the right-hand side -A[P,i], the
!> objective d, the scores (A g~)_j^2 / A_jj of the entries below i, and the
!> stopping tests on d.
module afsai
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t
  use fsai_params, only: fsai_params_t
  use visible_rows, only: check_square
  use adaptive_pattern, only: adaptive_pattern_t, sort_by_key
  implicit none
  private

  public :: afsai_factor

  !> aFSAI scores are squared gradients: scores below this fraction of the
  !> best one (gradients below 1e-8 of the largest) are round-off noise and
  !> count as zero, so that noise does not order them.
  real(rp), parameter :: noise_floor = 1.0e-16_rp
  !> and a candidate whose predicted decrease of d is below this fraction of
  !> d is noise too (it matters when every candidate is noise)
  real(rp), parameter :: d_floor = 1.0e-20_rp

  !> The rows of G as items of the adaptive engine.
  type, extends(adaptive_pattern_t) :: fsai_rows_t
    !> d of every owned row after its last solve, and of the current solve
    real(rp), allocatable :: dval(:)
    real(rp) :: d = 0.0_rp
  contains
    procedure :: self_row => row_self
    procedure :: key_limit => row_key
    procedure :: label => row_key
    procedure :: add_rhs => row_rhs
    procedure :: finish_solve => row_finish
    procedure :: accept => row_accept
    procedure :: score => row_score
    procedure :: worth => row_worth
    procedure :: drop_scale => row_drop_scale
    procedure :: failure_message => row_failure
  end type fsai_rows_t

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
    type(fsai_rows_t), target :: rows
    integer(gp) :: none(0)

    call params%validate(status)
    if (.not. status%ok()) return
    call check_square(a, 'afsai_factor', status)
    if (.not. status%ok()) return
    rows%params = params
    rows%noise_floor = noise_floor
    ! the rows one step outside this rank, then the start and the steps
    call rows%vis%start(a, none)
    call initial_pattern(rows, a, status)
    if (.not. status%ok()) return
    allocate(rows%dval(a%n_rows))
    rows%dval = 0.0_rp
    call rows%grow(status)
    if (.not. status%ok()) return
    call build_factor(rows, a, g)
  end subroutine afsai_factor

  !> Members of each row before the first step (init 'lower': the entries
  !> of A's row below it in key order), with room for max_steps * step_size
  !> more per row; the non-owned members are pushed as new.
  subroutine initial_pattern(rows, a, status)
    type(fsai_rows_t), intent(inout) :: rows
    type(global_csr_t), intent(in) :: a
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i, k, m, t, n
    integer(ip), allocatable :: len0(:)
    integer(gp), allocatable :: cap(:)
    integer(gp) :: room
    logical :: lower
    n = a%n_rows
    lower = rows%params%init == 'lower'
    allocate(len0(n), cap(n))
    room = int(rows%params%max_steps, gp) * int(rows%params%step_size, gp)
    do i = 1, n
      len0(i) = 0
      if (lower) then
        do k = a%row_ptr(i), a%row_ptr(i+1) - 1
          if (rows%vis%key(rows%vis%vcol_a(k)) < a%key(i)) len0(i) = len0(i) + 1
        end do
      end if
      cap(i) = min(int(len0(i), gp) + room, a%row_offsets(a%comm%size) - 2)
    end do
    call rows%reserve(len0, cap, 'afsai_factor', status)
    if (.not. status%ok() .or. .not. lower) return
    do i = 1, n
      m = rows%pptr(i) - 1
      do k = a%row_ptr(i), a%row_ptr(i+1) - 1
        t = rows%vis%vcol_a(k)
        if (rows%vis%key(t) < a%key(i)) then
          m = m + 1
          rows%pgid(m) = a%gcol(k)
          rows%pkey(m) = rows%vis%key(t)
          if (t > n) call rows%push_new(a%gcol(k))
        end if
      end do
      call sort_by_key(rows%pkey(rows%pptr(i):m), rows%pgid(rows%pptr(i):m))
    end do
  end subroutine initial_pattern

  !> A row's own row of A is i itself.
  integer(ip) function row_self(self, j)
    class(fsai_rows_t), intent(in) :: self
    integer(ip), intent(in) :: j
    row_self = j
  end function row_self

  !> Row i: only entries of smaller key may join; its failures are named by
  !> its key.
  integer(gp) function row_key(self, j)
    class(fsai_rows_t), intent(in) :: self
    integer(ip), intent(in) :: j
    row_key = self%vis%a%key(j)
  end function row_key

  !> b = -A[P,i] came from the members' rows already.
  subroutine row_rhs(self, j)
    class(fsai_rows_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
  end subroutine row_rhs

  !> d = A_ii + A[i,P] y (= A_ii - b^T y), which must be positive.
  subroutine row_finish(self, j, ok)
    class(fsai_rows_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    logical, intent(inout) :: ok
    integer(ip) :: p
    p = self%plen(j)
    self%d = self%vis%diag(j)
    if (p > 0) self%d = self%d - dot_product(self%yv(1:p), self%bv(1:p))
    ok = self%d > 0.0_rp .and. ieee_is_finite(self%d)
  end subroutine row_finish

  !> The row is done after the last step or when the last step lowered d
  !> by less than tol; d is kept.
  logical function row_accept(self, j, s)
    class(fsai_rows_t), intent(inout), target :: self
    integer(ip), intent(in) :: j, s
    row_accept = s == self%params%max_steps
    if (s > 0 .and. self%params%tol > 0.0_rp) &
      row_accept = row_accept .or. self%dval(j) - self%d < self%params%tol * self%dval(j)
    self%dval(j) = self%d
  end function row_accept

  !> Candidates: the rows below i next to the pattern, scored by the
  !> predicted decrease of d, (A g~)_t^2 / A_tt (noise below d_floor d is
  !> zero). A candidate with a non-positive diagonal entry is a failure.
  logical function row_score(self, j)
    class(fsai_rows_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    integer(ip) :: k, t
    row_score = .false.
    self%nc = 0
    do k = 1, self%nt
      t = self%tlist(k)
      if (self%mark(t) /= -1) cycle
      self%nc = self%nc + 1
      self%cl(self%nc) = t
      self%ckey(self%nc) = self%vis%key(t)
      self%cs(self%nc) = 0.0_rp
      if (self%vis%diag(t) > 0.0_rp) self%cs(self%nc) = self%acc(t)**2 / self%vis%diag(t)
      if (self%cs(self%nc) <= d_floor * self%d) self%cs(self%nc) = 0.0_rp
    end do
    do k = 1, self%nc
      if (self%vis%diag(self%cl(k)) > 0.0_rp) cycle
      call self%record_failure(j, self%vis%key(self%cl(k)))
      row_score = .true.
      return
    end do
  end function row_score

  !> A step is worth taking unless its predicted decrease of d is below tol.
  logical function row_worth(self, j, nch)
    class(fsai_rows_t), intent(inout), target :: self
    integer(ip), intent(in) :: j, nch
    real(rp) :: pred
    integer(ip) :: k
    pred = 0.0_rp
    do k = 1, nch
      pred = pred + self%cs(self%chosen(k))
    end do
    row_worth = .not. (self%params%tol > 0.0_rp .and. pred < self%params%tol * self%d)
  end function row_worth

  !> Entries are dropped relative to max(1, largest |y|) (the 1 stands for
  !> the unit diagonal of g~).
  real(rp) function row_drop_scale(self, vmax)
    class(fsai_rows_t), intent(in) :: self
    real(rp), intent(in) :: vmax
    row_drop_scale = max(1.0_rp, vmax)
  end function row_drop_scale

  function row_failure(self, lab) result(msg)
    class(fsai_rows_t), intent(in) :: self
    integer(gp), intent(in) :: lab
    character(len=msg_len) :: msg
    write(msg, '(a,i0,a)') 'afsai_factor: the matrix is not symmetric positive definite '// &
      '(non-positive pivot in the dense system of the row with key ', lab, ')'
  end function row_failure

  !> G from the patterns and values: row i = [y; 1] / sqrt(d), columns
  !> ascending by global id.
  subroutine build_factor(rows, a, g)
    type(fsai_rows_t), intent(in) :: rows
    type(global_csr_t), intent(in) :: a
    type(global_csr_t), intent(inout) :: g
    integer(ip) :: i, n, p, o, m, k, r
    integer(gp), allocatable :: cg(:)
    integer(ip), allocatable :: cp(:)
    real(rp), allocatable :: cv(:)
    real(rp) :: sc
    n = a%n_rows
    g%comm = a%comm
    g%row_offsets = a%row_offsets
    g%col_offsets = a%col_offsets
    g%n_rows = n
    g%key = a%key
    allocate(g%row_ptr(n + 1))
    g%row_ptr(1) = 1
    do i = 1, n
      g%row_ptr(i + 1) = g%row_ptr(i) + rows%plen(i) + 1
    end do
    allocate(g%gcol(g%row_ptr(n + 1) - 1), g%val(g%row_ptr(n + 1) - 1))
    m = 0
    if (n > 0) m = maxval(rows%plen)
    allocate(cg(m + 1), cp(m + 1), cv(m + 1))
    do i = 1, n
      p = rows%plen(i)
      o = rows%pptr(i) - 1
      sc = 1.0_rp / sqrt(rows%dval(i))
      cg(1:p) = rows%pgid(o+1:o+p)
      cv(1:p) = rows%pval(o+1:o+p) * sc
      cg(p + 1) = a%row_offsets(a%comm%rank) + i - 1
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
end module afsai
