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
!> entries reach the owners of their rows through a transpose. Ordering
!> decisions use the rows' keys (k%key) as in afsai, so the pattern of F
!> is the same on any number of ranks and the values agree to round-off.
module block_fsai
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use status_sync, only: agree
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t, row_store_t, fetch_rows, gcsr_transpose, gcsr_multiply, gcsr_add
  use fsai_params, only: fsai_params_t
  use afsai, only: check_square, visible_id, visible_gid, visible_row, visible_tables, ghost_columns, &
    fetch_neighbours, select_best, sort_by_key, merge_by_key, append_gid
  implicit none
  private

  public :: decoupling_factor

  !> Scores below this fraction of the best candidate's are round-off noise
  !> and count as zero (they are then ordered by key alone) ...
  real(rp), parameter :: noise_floor = 1.0e-8_rp
  !> ... and so are residual entries below this fraction of ||C(:,j)||.
  real(rp), parameter :: r_floor = 1.0e-12_rp

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
    type(global_csr_t) :: ct
    type(row_store_t), target :: store
    ! pattern of each owned column (rows of K's space, ascending key)
    integer(ip), allocatable :: pptr(:), plen(:)
    integer(gp), allocatable :: pgid(:), pkey(:)
    real(rp), allocatable :: pval(:)
    logical, allocatable :: active(:)
    ! visible rows of k
    integer(gp), allocatable :: key_ext(:), newg(:), req(:)
    real(rp), allocatable :: diag_ext(:)
    integer(ip), allocatable, target :: vcol_a(:), vcol_s(:)
    ! work
    integer(ip), allocatable :: mark(:), lids(:), tlist(:), cl(:), chosen(:)
    integer(gp), allocatable :: ckey(:)
    real(rp), allocatable :: acc(:), cs(:), ad(:,:), bv(:), fv(:)
    integer(ip) :: n, ncol, j, s, nnew, ldad, nt
    integer(gp) :: bad_col
    logical :: local_fail

    if (present(resid)) resid = huge(1.0_rp)
    call params%validate(status)
    if (.not. status%ok()) return
    call check_square(k, 'decoupling_factor (K)', status)
    if (.not. status%ok()) return
    call check_coupling()
    if (.not. status%ok()) return
    n = k%n_rows
    local_fail = .false.
    bad_col = -1

    ! the columns of c as rows, on the ranks that own them
    call gcsr_transpose(c, ct)
    ncol = ct%n_rows
    ! visible: the ghost columns of k and the rows of the columns' patterns
    call start_rows()
    call fetch_rows(k, req, store)
    call visible_tables(k, store, key_ext, diag_ext, vcol_a, vcol_s)
    call initial_pattern()
    if (.not. status%ok()) return
    call fetch_neighbours(k, store, newg(1:nnew))
    call visible_tables(k, store, key_ext, diag_ext, vcol_a, vcol_s)
    allocate(pval(size(pgid)), active(ncol))
    pval = 0.0_rp
    active = .true.
    ldad = 0

    do s = 0, params%max_steps
      call prepare_work()
      nnew = 0
      do j = 1, ncol
        if (active(j)) call process_column(j, s)
      end do
      if (failed()) return
      if (s == params%max_steps) exit
      if (.not. k%comm%any_true(any(active))) exit
      call fetch_neighbours(k, store, newg(1:nnew))
      call visible_tables(k, store, key_ext, diag_ext, vcol_a, vcol_s)
    end do

    if (params%drop > 0.0_rp) then
      call prepare_work()
      do j = 1, ncol
        call drop_column(j)
      end do
      if (failed()) return
    end if
    call build_factor()
    if (present(resid)) call residual_norm()

  contains

    !> c's rows must be split like k's (status alike on every rank).
    subroutine check_coupling()
      if (.not. allocated(c%row_offsets) .or. .not. allocated(c%col_offsets)) then
        call status%set('decoupling_factor: C has no row or column split')
      else if (size(c%row_offsets) /= size(k%row_offsets)) then
        call status%set('decoupling_factor: C and K live on different communicators')
      else if (any(c%row_offsets /= k%row_offsets)) then
        call status%set('decoupling_factor: the rows of C are not split like those of K')
      end if
    end subroutine check_coupling

    !> req: k's ghost columns and the non-owned rows of the columns of c.
    subroutine start_rows()
      integer(gp), allocatable :: gh(:)
      integer(ip) :: q, m
      integer(gp) :: first, last
      first = k%row_offsets(k%comm%rank)
      last = k%row_offsets(k%comm%rank + 1) - 1
      call ghost_columns(k, gh)
      allocate(req(size(gh) + ct%nnz()))
      m = size(gh)
      req(1:m) = gh
      do q = 1, ct%nnz()
        if (ct%gcol(q) < first .or. ct%gcol(q) > last) then
          m = m + 1
          req(m) = ct%gcol(q)
        end if
      end do
      req = req(1:m)
    end subroutine start_rows

    !> Pattern of each column before the first step (that of C(:,j)), its
    !> storage (room for max_steps * step_size more) and the non-owned
    !> members in newg.
    subroutine initial_pattern()
      integer(ip) :: q, m, t
      integer(gp) :: total, room
      allocate(pptr(ncol + 1), plen(ncol))
      room = int(params%max_steps, gp) * int(params%step_size, gp)
      total = 0
      do j = 1, ncol
        plen(j) = ct%row_ptr(j+1) - ct%row_ptr(j)
        pptr(j) = int(total, ip) + 1
        total = total + max(int(plen(j), gp), min(int(plen(j), gp) + room, k%row_offsets(k%comm%size) - 1))
      end do
      if (k%comm%any_true(total >= huge(1_ip))) then
        call status%set('decoupling_factor: the patterns need more than 2^31 entries on a rank; '// &
                        'lower max_steps * step_size')
        return
      end if
      pptr(ncol + 1) = int(total, ip) + 1
      allocate(pgid(total), pkey(total), newg(1024))
      nnew = 0
      do j = 1, ncol
        m = pptr(j) - 1
        do q = ct%row_ptr(j), ct%row_ptr(j+1) - 1
          t = visible_id(k, store, ct%gcol(q))
          m = m + 1
          pgid(m) = ct%gcol(q)
          pkey(m) = key_ext(t)
          if (t > n) call push_new(ct%gcol(q))
        end do
        call sort_by_key(pkey(pptr(j):m), pgid(pptr(j):m))
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
      if (ncol > 0) pmax = max(1, maxval(plen))
      if (pmax > ldad) then
        if (allocated(ad)) deallocate(ad, bv, fv, lids)
        ldad = pmax
        allocate(ad(ldad, ldad), bv(ldad), fv(ldad), lids(ldad))
      end if
      if (.not. allocated(chosen)) allocate(chosen(params%step_size))
    end subroutine prepare_work

    !> Solve column j on its pattern: fv(1:p). Leaves mark() set for the
    !> members (1..p); ok is false on a non-positive pivot.
    subroutine solve_column(j, ok)
      integer(ip), intent(in) :: j
      logical, intent(out) :: ok
      integer(ip), pointer, contiguous :: cols(:)
      real(rp), pointer, contiguous :: vals(:)
      integer(ip) :: p, o, q, kk, t, mq, info
      p = plen(j)
      o = pptr(j) - 1
      do q = 1, p
        lids(q) = visible_id(k, store, pgid(o + q))
        mark(lids(q)) = q
      end do
      ok = .true.
      if (p == 0) return
      ad(1:p, 1:p) = 0.0_rp
      bv(1:p) = 0.0_rp
      do q = 1, p
        call visible_row(k, store, vcol_a, vcol_s, lids(q), cols, vals)
        do kk = 1, size(cols)
          t = cols(kk)
          if (t == 0) cycle
          mq = mark(t)
          if (mq > 0) ad(q, mq) = vals(kk)
        end do
      end do
      do q = ct%row_ptr(j), ct%row_ptr(j+1) - 1
        t = visible_id(k, store, ct%gcol(q))
        if (t == 0) cycle
        if (mark(t) > 0) bv(mark(t)) = ct%val(q)
      end do
      call dpotrf('L', p, ad, ldad, info)
      if (info /= 0) then
        ok = .false.
        return
      end if
      fv(1:p) = bv(1:p)
      call dpotrs('L', p, 1, ad, ldad, fv, ldad, info)
      ok = all(ieee_is_finite(fv(1:p)))
    end subroutine solve_column

    subroutine clear_marks(j)
      integer(ip), intent(in) :: j
      mark(lids(1:plen(j))) = 0
    end subroutine clear_marks

    !> One step of column j: solve on the current pattern; unless the column
    !> is done, add the step_size rows of largest scaled residual.
    subroutine process_column(j, s)
      integer(ip), intent(in) :: j, s
      integer(ip), pointer, contiguous :: cols(:)
      real(rp), pointer, contiguous :: vals(:)
      integer(ip) :: p, o, q, kk, t, nc, nch, mt
      real(rp) :: rnorm, cnorm
      logical :: ok

      p = plen(j)
      o = pptr(j) - 1
      call solve_column(j, ok)
      if (.not. ok) then
        call clear_marks(j)
        call record_failure(j)
        return
      end if
      pval(o+1:o+p) = fv(1:p)
      if (s == params%max_steps) then
        active(j) = .false.
        call clear_marks(j)
        return
      end if

      ! r = C(:,j) - K(:,J) F[J,j] on the rows next to J outside it (r
      ! vanishes on J, which holds the pattern of C(:,j)); mark(l) = -1
      ! flags a row seen
      cnorm = 0.0_rp
      do q = ct%row_ptr(j), ct%row_ptr(j+1) - 1
        cnorm = cnorm + ct%val(q)**2
      end do
      cnorm = sqrt(cnorm)
      nt = 0
      do q = 1, p
        call visible_row(k, store, vcol_a, vcol_s, lids(q), cols, vals)
        do kk = 1, size(cols)
          t = cols(kk)
          if (t == 0) error stop 'decoupling_factor: internal error: a neighbour of a pattern was not fetched'
          mt = mark(t)
          if (mt == -1) then
            acc(t) = acc(t) - vals(kk) * fv(q)
          else if (mt == 0) then
            mark(t) = -1
            nt = nt + 1
            tlist(nt) = t
            acc(t) = -vals(kk) * fv(q)
          end if
        end do
      end do
      mark(tlist(1:nt)) = 0
      rnorm = 0.0_rp
      do kk = 1, nt
        rnorm = rnorm + acc(tlist(kk))**2
      end do
      rnorm = sqrt(rnorm)
      if (params%tol > 0.0_rp .and. rnorm <= params%tol * cnorm) then
        active(j) = .false.
        call clear_marks(j)
        return
      end if
      ! candidates: every row seen
      nc = 0
      do kk = 1, nt
        t = tlist(kk)
        if (.not. (diag_ext(t) > 0.0_rp)) then
          call clear_marks(j)
          call record_failure(j)
          return
        end if
        nc = nc + 1
        cl(nc) = t
        ckey(nc) = key_ext(t)
        cs(nc) = 0.0_rp
        if (abs(acc(t)) > r_floor * cnorm) cs(nc) = abs(acc(t)) / sqrt(diag_ext(t))
      end do
      call clear_marks(j)
      if (nc == 0) then
        active(j) = .false.
        return
      end if
      call select_best(nc, cs, ckey, params%step_size, noise_floor * maxval(cs(1:nc)), chosen, nch)
      do kk = 1, nch
        t = cl(chosen(kk))
        pgid(o + p + kk) = visible_gid(k, store, t)
        pkey(o + p + kk) = ckey(chosen(kk))
        if (t > n) call push_new(pgid(o + p + kk))
      end do
      call merge_by_key(p, nch, pkey(o+1:o+p+nch), pgid(o+1:o+p+nch))
      plen(j) = p + nch
    end subroutine process_column


    !> After the last step: drop the small entries of column j and solve
    !> again on the kept pattern (the best column there in the K-norm).
    subroutine drop_column(j)
      integer(ip), intent(in) :: j
      integer(ip) :: p, o, q, m
      real(rp) :: vmax
      logical :: ok
      p = plen(j)
      o = pptr(j) - 1
      if (p == 0) return
      vmax = maxval(abs(pval(o+1:o+p)))
      m = 0
      do q = 1, p
        if (abs(pval(o + q)) >= params%drop * vmax) then
          m = m + 1
          pgid(o + m) = pgid(o + q)
          pkey(o + m) = pkey(o + q)
        end if
      end do
      if (m == p) return
      plen(j) = m
      call solve_column(j, ok)
      call clear_marks(j)
      if (.not. ok) then
        call record_failure(j)
        return
      end if
      pval(o+1:o+m) = fv(1:m)
    end subroutine drop_column

    subroutine record_failure(j)
      integer(ip), intent(in) :: j
      if (.not. local_fail) bad_col = c%col_offsets(c%comm%rank) + j - 1
      local_fail = .true.
      active(j) = .false.
    end subroutine record_failure

    !> Collective: true (and status set alike on every rank) when some rank
    !> met a non-positive pivot.
    logical function failed()
      character(len=msg_len) :: msg
      failed = k%comm%any_true(local_fail)
      if (.not. failed) return
      if (local_fail) then
        write(msg, '(a,i0,a)') 'decoupling_factor: K is not symmetric positive definite '// &
          '(non-positive pivot in the dense system of column ', bad_col, ' of C)'
        call status%set(trim(msg))
      end if
      call agree(k%comm, status)
      call f%free()
    end function failed

    !> F^T from the columns (rows ascending by global id), then F.
    subroutine build_factor()
      type(global_csr_t) :: ft
      integer(ip) :: p, o, q, r, m
      integer(gp), allocatable :: cg(:)
      integer(ip), allocatable :: cp(:)
      m = 0
      if (ncol > 0) m = maxval(plen)
      allocate(cg(m), cp(m))
      ft%comm = c%comm
      ft%row_offsets = c%col_offsets
      ft%col_offsets = k%row_offsets
      ft%n_rows = ncol
      allocate(ft%row_ptr(ncol + 1))
      ft%row_ptr(1) = 1
      do j = 1, ncol
        ft%row_ptr(j + 1) = ft%row_ptr(j) + plen(j)
      end do
      allocate(ft%gcol(ft%row_ptr(ncol + 1) - 1), ft%val(ft%row_ptr(ncol + 1) - 1), ft%key(ncol))
      do j = 1, ncol
        p = plen(j)
        o = pptr(j) - 1
        r = ft%row_ptr(j) - 1
        cg(1:p) = pgid(o+1:o+p)
        call sort_gids(cg(1:p), cp(1:p))
        do q = 1, p
          ft%gcol(r + q) = cg(q)
          ft%val(r + q) = pval(o + cp(q))
        end do
        ft%key(j) = c%col_offsets(c%comm%rank) + j - 1
      end do
      call gcsr_transpose(ft, f)
      f%key = k%key
    end subroutine build_factor

    !> resid = ||K F - C||_F / ||C||_F (0 when C = 0). Collective.
    subroutine residual_norm()
      type(global_csr_t) :: kf, e
      real(rp) :: num, den
      call gcsr_multiply(k, f, kf)
      call gcsr_add(1.0_rp, kf, -1.0_rp, c, e)
      num = k%comm%sum(sum(e%val(1:e%nnz())**2))
      den = k%comm%sum(sum(c%val(1:c%nnz())**2))
      resid = 0.0_rp
      if (den > 0.0_rp) resid = sqrt(num / den)
    end subroutine residual_norm
  end subroutine decoupling_factor
end module block_fsai
