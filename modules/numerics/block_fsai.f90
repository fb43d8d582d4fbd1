!> Decoupling factors of the block preconditioning framework (seed text,
!> "General framework" and "Approximate inverses"): a sparse F ~ K^-1 C for
!> an SPD block K and a coupling block C, e.g. F_3^(1) = K^-1 Q of the
!> three-field Biot system, computed column by column with an adaptive
!> pattern in the manner of block FSAI (Janna, Ferronato, Gambolati, SIAM
!> J. Sci. Comput. 32 (2010); adaptive choice after Janna and Ferronato,
!> SIAM J. Sci. Comput. 33 (2011), and the seed's references [NFA20, FCF21]).
!>
!> Column j of F, on the pattern J (rows of K's space): solve the dense
!> system K[J,J] F[J,j] = C[J,j], which gives the best approximation of
!> K^-1 C(:,j) in the K-norm among the vectors supported on J. J starts as
!> the pattern of C(:,j); each step computes the residual r = C(:,j) -
!> K(:,J) F[J,j] (by the symmetry of K, from the rows of J; r vanishes on J)
!> and adds the step_size rows l outside J of largest |r_l| / sqrt(K_ll):
!> adding l alone lowers the squared K-norm error by r_l^2 / K_ll, the
!> counterpart of the aFSAI gradient. It stops at ||r|| <= tol ||C(:,j)|| or
!> after max_steps; then entries below params%drop of the column's largest
!> are dropped and the column is solved again on the kept pattern.
!>
!> A column is computed by the rank that owns it in C's column space; its
!> entries reach the owners of their rows through a transpose. The steps,
!> the key-ordered choices (the pattern of F is the same on any number of
!> ranks, the values agree to round-off) and the drop pass are the engine
!> of adaptive_pattern, shared with afsai; this module gives the
!> column-specific parts: the right-hand side C(:,j), the residual as the
!> vector that scores the candidates, and the residual stopping test.
module block_fsai
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t, gcsr_transpose, gcsr_multiply, gcsr_add
  use fsai_params, only: fsai_params_t
  use visible_rows, only: check_square
  use adaptive_pattern, only: adaptive_pattern_t, sort_by_key
  implicit none
  private

  public :: decoupling_factor

  !> Scores below this fraction of the best candidate's are round-off noise
  !> and count as zero (they are then ordered by key alone) ...
  real(rp), parameter :: noise_floor = 1.0e-8_rp
  !> ... and so are residual entries below this fraction of ||C(:,j)||.
  real(rp), parameter :: r_floor = 1.0e-12_rp

  !> The columns of F as items of the adaptive engine.
  type, extends(adaptive_pattern_t) :: factor_columns_t
    !> the columns of C as rows, on the ranks that own them
    type(global_csr_t) :: ct
    !> global id of this rank's first column
    integer(gp) :: first_col = 0
  contains
    procedure :: self_row => column_self
    procedure :: key_limit => column_key_limit
    procedure :: label => column_label
    procedure :: add_rhs => column_rhs
    procedure :: finish_solve => column_finish
    procedure :: accept => column_accept
    procedure :: score => column_score
    procedure :: worth => column_worth
    procedure :: drop_scale => column_drop_scale
    procedure :: failure_message => column_failure
    procedure :: weight_sign => column_sign
  end type factor_columns_t

contains

  !> F ~ K^-1 C. k: SPD, n x n (the same row and column split), with one
  !> partition-independent key per owned row (all distinct); c: n x m, its
  !> rows split like k's, its columns split by c%col_offsets. f: n x m, rows
  !> split like k (with k's keys), columns like c. resid (optional): the
  !> global ||K F - C||_F / ||C||_F. Collective. status reports, on every
  !> rank alike, bad params, mismatched or key-less matrices, and a
  !> non-positive pivot (K not SPD).
  subroutine decoupling_factor(k, c, params, f, status, resid)
    type(global_csr_t), intent(in), target :: k
    type(global_csr_t), intent(in) :: c
    type(fsai_params_t), intent(in) :: params
    type(global_csr_t), intent(out) :: f
    type(error_status_t), intent(inout) :: status
    real(rp), intent(out), optional :: resid
    type(factor_columns_t), target :: cols

    if (present(resid)) resid = huge(1.0_rp)
    call params%validate(status)
    if (.not. status%ok()) return
    call check_square(k, 'decoupling_factor (K)', status)
    if (.not. status%ok()) return
    call check_coupling(k, c, status)
    if (.not. status%ok()) return
    cols%params = params
    cols%noise_floor = noise_floor
    cols%first_col = c%col_offsets(c%comm%rank)
    call gcsr_transpose(c, cols%ct)
    ! visible: the ghost columns of k and the rows of the columns' patterns
    call cols%vis%start(k, cols%ct%gcol(1:cols%ct%nnz()))
    call initial_pattern(cols, k, status)
    if (.not. status%ok()) return
    call cols%grow(status)
    if (.not. status%ok()) return
    call build_factor(cols, k, c, f)
    if (present(resid)) call residual_norm(k, c, f, resid)
  end subroutine decoupling_factor

  !> c's rows must be split like k's (status alike on every rank).
  subroutine check_coupling(k, c, status)
    type(global_csr_t), intent(in) :: k, c
    type(error_status_t), intent(inout) :: status
    if (.not. allocated(c%row_offsets) .or. .not. allocated(c%col_offsets)) then
      call status%set('decoupling_factor: C has no row or column split')
    else if (size(c%row_offsets) /= size(k%row_offsets)) then
      call status%set('decoupling_factor: C and K live on different communicators')
    else if (any(c%row_offsets /= k%row_offsets)) then
      call status%set('decoupling_factor: the rows of C are not split like those of K')
    end if
  end subroutine check_coupling

  !> Pattern of each column before the first step (that of C(:,j)), with
  !> room for max_steps * step_size more; the non-owned members are pushed
  !> as new.
  subroutine initial_pattern(cols, k, status)
    type(factor_columns_t), intent(inout) :: cols
    type(global_csr_t), intent(in) :: k
    type(error_status_t), intent(inout) :: status
    integer(ip) :: j, q, m, t, ncol
    integer(ip), allocatable :: len0(:)
    integer(gp), allocatable :: cap(:)
    integer(gp) :: room
    ncol = cols%ct%n_rows
    allocate(len0(ncol), cap(ncol))
    room = int(cols%params%max_steps, gp) * int(cols%params%step_size, gp)
    do j = 1, ncol
      len0(j) = cols%ct%row_ptr(j+1) - cols%ct%row_ptr(j)
      cap(j) = max(int(len0(j), gp), min(int(len0(j), gp) + room, k%row_offsets(k%comm%size) - 1))
    end do
    call cols%reserve(len0, cap, 'decoupling_factor', status)
    if (.not. status%ok()) return
    do j = 1, ncol
      m = cols%pptr(j) - 1
      do q = cols%ct%row_ptr(j), cols%ct%row_ptr(j+1) - 1
        t = cols%vis%id(cols%ct%gcol(q))
        m = m + 1
        cols%pgid(m) = cols%ct%gcol(q)
        cols%pkey(m) = cols%vis%key(t)
        if (t > k%n_rows) call cols%push_new(cols%ct%gcol(q))
      end do
      call sort_by_key(cols%pkey(cols%pptr(j):m), cols%pgid(cols%pptr(j):m))
    end do
  end subroutine initial_pattern

  !> A column has no row of K of its own.
  integer(ip) function column_self(self, j)
    class(factor_columns_t), intent(in) :: self
    integer(ip), intent(in) :: j
    column_self = 0
  end function column_self

  !> Every row of K may join a column.
  integer(gp) function column_key_limit(self, j)
    class(factor_columns_t), intent(in) :: self
    integer(ip), intent(in) :: j
    column_key_limit = huge(1_gp)
  end function column_key_limit

  !> Failures are named by the column's global id.
  integer(gp) function column_label(self, j)
    class(factor_columns_t), intent(in) :: self
    integer(ip), intent(in) :: j
    column_label = self%first_col + j - 1
  end function column_label

  !> b = C[J,j].
  subroutine column_rhs(self, j)
    class(factor_columns_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    integer(ip) :: q, t
    do q = self%ct%row_ptr(j), self%ct%row_ptr(j+1) - 1
      t = self%vis%id(self%ct%gcol(q))
      if (t == 0) cycle
      if (self%mark(t) > 0) self%bv(self%mark(t)) = self%ct%val(q)
    end do
  end subroutine column_rhs

  !> The solution must be finite.
  subroutine column_finish(self, j, ok)
    class(factor_columns_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    logical, intent(inout) :: ok
    ok = ok .and. all(ieee_is_finite(self%yv(1:self%plen(j))))
  end subroutine column_finish

  !> A column is done after the last step.
  logical function column_accept(self, j, s)
    class(factor_columns_t), intent(inout), target :: self
    integer(ip), intent(in) :: j, s
    column_accept = s == self%params%max_steps
  end function column_accept

  !> The residual r = C(:,j) - K(:,J) F[J,j] on the rows next to J (it
  !> vanishes on J, which holds the pattern of C(:,j)): done when ||r|| <=
  !> tol ||C(:,j)||; else every row seen is a candidate, scored by
  !> |r_l| / sqrt(K_ll) (entries below r_floor ||C(:,j)|| are noise). A
  !> candidate with a non-positive diagonal entry is a failure.
  logical function column_score(self, j)
    class(factor_columns_t), intent(inout), target :: self
    integer(ip), intent(in) :: j
    integer(ip) :: q, kk, t
    real(rp) :: rnorm, cnorm
    cnorm = 0.0_rp
    do q = self%ct%row_ptr(j), self%ct%row_ptr(j+1) - 1
      cnorm = cnorm + self%ct%val(q)**2
    end do
    cnorm = sqrt(cnorm)
    rnorm = 0.0_rp
    do kk = 1, self%nt
      rnorm = rnorm + self%acc(self%tlist(kk))**2
    end do
    rnorm = sqrt(rnorm)
    column_score = self%params%tol > 0.0_rp .and. rnorm <= self%params%tol * cnorm
    if (column_score) return
    self%nc = 0
    do kk = 1, self%nt
      t = self%tlist(kk)
      if (.not. (self%vis%diag(t) > 0.0_rp)) then
        call self%record_failure(j, self%label(j))
        column_score = .true.
        return
      end if
      self%nc = self%nc + 1
      self%cl(self%nc) = t
      self%ckey(self%nc) = self%vis%key(t)
      self%cs(self%nc) = 0.0_rp
      if (abs(self%acc(t)) > r_floor * cnorm) self%cs(self%nc) = abs(self%acc(t)) / sqrt(self%vis%diag(t))
    end do
  end function column_score

  !> Every step that finds candidates is taken.
  logical function column_worth(self, j, nch)
    class(factor_columns_t), intent(inout), target :: self
    integer(ip), intent(in) :: j, nch
    column_worth = .true.
  end function column_worth

  !> Entries are dropped relative to the column's largest.
  real(rp) function column_drop_scale(self, vmax)
    class(factor_columns_t), intent(in) :: self
    real(rp), intent(in) :: vmax
    column_drop_scale = vmax
  end function column_drop_scale

  !> x enters the residual with a minus sign: v = -K(:,J) f.
  real(rp) function column_sign(self)
    class(factor_columns_t), intent(in) :: self
    column_sign = -1.0_rp
  end function column_sign

  function column_failure(self, lab) result(msg)
    class(factor_columns_t), intent(in) :: self
    integer(gp), intent(in) :: lab
    character(len=msg_len) :: msg
    write(msg, '(a,i0,a)') 'decoupling_factor: K is not symmetric positive definite '// &
      '(non-positive pivot in the dense system of column ', lab, ' of C)'
  end function column_failure

  !> F^T from the columns (rows ascending by global id), then F.
  subroutine build_factor(cols, k, c, f)
    type(factor_columns_t), intent(in) :: cols
    type(global_csr_t), intent(in) :: k, c
    type(global_csr_t), intent(inout) :: f
    type(global_csr_t) :: ft
    integer(ip) :: j, ncol, p, o, q, r, m
    integer(gp), allocatable :: cg(:)
    integer(ip), allocatable :: cp(:)
    ncol = cols%n_items
    m = 0
    if (ncol > 0) m = maxval(cols%plen)
    allocate(cg(m), cp(m))
    ft%comm = c%comm
    ft%row_offsets = c%col_offsets
    ft%col_offsets = k%row_offsets
    ft%n_rows = ncol
    allocate(ft%row_ptr(ncol + 1))
    ft%row_ptr(1) = 1
    do j = 1, ncol
      ft%row_ptr(j + 1) = ft%row_ptr(j) + cols%plen(j)
    end do
    allocate(ft%gcol(ft%row_ptr(ncol + 1) - 1), ft%val(ft%row_ptr(ncol + 1) - 1), ft%key(ncol))
    do j = 1, ncol
      p = cols%plen(j)
      o = cols%pptr(j) - 1
      r = ft%row_ptr(j) - 1
      cg(1:p) = cols%pgid(o+1:o+p)
      call sort_gids(cg(1:p), cp(1:p))
      do q = 1, p
        ft%gcol(r + q) = cg(q)
        ft%val(r + q) = cols%pval(o + cp(q))
      end do
      ft%key(j) = cols%first_col + j - 1
    end do
    call gcsr_transpose(ft, f)
    f%key = k%key
  end subroutine build_factor

  !> resid = ||K F - C||_F / ||C||_F (0 when C = 0). Collective.
  subroutine residual_norm(k, c, f, resid)
    type(global_csr_t), intent(in) :: k, c, f
    real(rp), intent(out) :: resid
    type(global_csr_t) :: kf, e
    real(rp) :: num, den
    call gcsr_multiply(k, f, kf)
    call gcsr_add(1.0_rp, kf, -1.0_rp, c, e)
    num = k%comm%sum(sum(e%val(1:e%nnz())**2))
    den = k%comm%sum(sum(c%val(1:c%nnz())**2))
    resid = 0.0_rp
    if (den > 0.0_rp) resid = sqrt(num / den)
  end subroutine residual_norm
end module block_fsai
