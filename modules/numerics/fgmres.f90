!> Restarted flexible GMRES (Saad, SIAM J. Sci. Comput. 14, 1993), right
!> preconditioned: the preconditioned vectors z_j = M_j^-1 v_j are stored, so
!> the preconditioner may change from one iteration to the next (an inner
!> Krylov solve, an AMG cycle with a loose tolerance, a block preconditioner
!> whose sub-solvers are themselves iterative) and x = x0 + Z y stays right.
!>
!> Arnoldi by classical Gram-Schmidt applied twice (CGS2: one reduction per
!> pass for all the products, BLAS-2 locally), least squares by Givens
!> rotations. The Arnoldi estimate of the
!> residual drives the inner loop; convergence is decided on the TRUE
!> residual b - A x, computed at every restart and at the end:
!>   ||b - A x|| <= max(rtol ||b||, atol).
module fgmres
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  use krylov, only: krylov_t, solve_info_t
  use dist_vector, only: pdot, pnorm2
  implicit none
  private

  public :: fgmres_t

  !> FGMRES(restart). restart (inherited) is the Krylov dimension of one
  !> cycle; the memory is 2 restart + 1 vectors of the owned size.
  type, extends(krylov_t) :: fgmres_t
    !> Orthogonalize a second time when the first classical Gram-Schmidt
    !> pass shrinks the new vector below reorth_drop times its norm. One
    !> pass of CGS loses orthogonality like the square of the condition of
    !> the basis, so the default runs the second pass always (CGS2).
    logical :: reorthogonalize = .true.
    real(rp) :: reorth_drop = 2.0_rp
  contains
    procedure :: init => fgmres_init
    procedure :: solve => fgmres_solve
    procedure :: name => fgmres_name
  end type fgmres_t

  !> Why an Arnoldi cycle ended before its full length.
  interface
    !> BLAS y = alpha op(A) x + beta y
    subroutine dgemv(trans, m, n, alpha, a, lda, x, incx, beta, y, incy)
      import :: rp
      character(len=1), intent(in) :: trans
      integer, intent(in) :: m, n, lda, incx, incy
      real(rp), intent(in) :: alpha, beta, a(lda, *), x(*)
      real(rp), intent(inout) :: y(*)
    end subroutine dgemv
  end interface

  integer, parameter :: cycle_full = 0, cycle_converged = 1, cycle_not_finite = 2, &
                        cycle_breakdown = 3, cycle_singular = 4

contains

  !> Set the communicator and the parameters. rtol, atol: tolerances of the
  !> residual norm (relative to ||b||, absolute); max_iter: total iterations
  !> over all cycles; restart: Krylov dimension of a cycle. Omitted values
  !> keep the defaults of krylov_t. Bad values (rtol or atol < 0, max_iter
  !> < 0, restart < 1) set status, or stop when status is absent (the deck
  !> readers range-check them first, so then it is a programming error).
  subroutine fgmres_init(self, comm, rtol, atol, max_iter, restart, status)
    class(fgmres_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in), optional :: rtol, atol
    integer, intent(in), optional :: max_iter, restart
    type(error_status_t), intent(inout), optional :: status
    character(len=msg_len) :: m
    if (.not. self%configure(comm, rtol, atol, max_iter, status)) return
    if (present(restart)) self%restart = restart
    if (self%restart >= 1) return
    write(m, '(a,i0,a)') 'fgmres%init: restart = ', self%restart, ' must be >= 1'
    if (.not. present(status)) error stop 'fgmres%init: bad parameters (see the status message)'
    call status%set(trim(m))
  end subroutine fgmres_init

  function fgmres_name(self) result(s)
    class(fgmres_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'fgmres'
  end function fgmres_name

  !> Solve A x = b with the (possibly variable) right preconditioner m; x
  !> holds the initial guess on entry and the answer on exit. Collective.
  !> info: iterations (Arnoldi steps in all), res0 = ||b - A x0||, rel_res =
  !> true ||b - A x|| / ||b|| (huge() when not finite), history(0:iterations)
  !> = Arnoldi estimates of the relative residual with the true value at the
  !> end of each cycle, msg = why it stopped when not converged.
  subroutine fgmres_solve(self, a, m, b, x, info)
    class(fgmres_t), intent(inout) :: self
    class(linear_operator_t), intent(inout) :: a
    class(precon_t), intent(inout) :: m
    real(rp), intent(in) :: b(:)
    real(rp), intent(inout) :: x(:)
    type(solve_info_t), intent(out) :: info
    real(rp), allocatable :: r(:), w(:), v(:,:), z(:,:), h(:,:), cs(:), sn(:), g(:)
    real(rp) :: t0, bnorm, tol, rnorm, rnorm_new
    integer :: n, mr, its, k, why

    t0 = wall_time()
    n = size(b)
    allocate(info%history(0:max(self%max_iter, 0)))
    info%history = 0.0_rp
    its = 0
    bnorm = pnorm2(self%comm, b)
    if (.not. ieee_is_finite(bnorm)) then
      info%msg = 'fgmres: NaN or Inf in the right-hand side'
      info%rel_res = huge(1.0_rp)
      call info%finish(its, t0)
      return
    end if
    if (bnorm == 0.0_rp) then
      ! the answer is known: do not let rtol * 0 ask for the impossible
      x = 0.0_rp
      info%converged = .true.
      call info%finish(its, t0)
      return
    end if
    tol = max(self%rtol * bnorm, self%atol)

    allocate(r(n), w(n))
    call residual(a, b, x, r, w)
    rnorm = pnorm2(self%comm, r)
    info%res0 = rnorm
    if (.not. ieee_is_finite(rnorm)) then
      info%msg = 'fgmres: NaN or Inf in the initial residual (matrix or initial guess broken)'
      info%rel_res = huge(1.0_rp)
      call info%finish(its, t0)
      return
    end if
    info%rel_res = rnorm / bnorm
    info%history(0) = info%rel_res
    if (rnorm <= tol) then
      info%converged = .true.
      call info%finish(its, t0)
      return
    end if

    mr = max(1, min(self%restart, self%max_iter))
    allocate(v(n, mr+1), z(n, mr), h(mr+1, mr), cs(mr), sn(mr), g(mr+1))
    do
      if (its >= self%max_iter) then
        write(info%msg, '(a,i0,a,es10.3)') 'fgmres: reached max_iter = ', self%max_iter, &
          ' with relative residual ', info%rel_res
        exit
      end if
      v(:, 1) = r / rnorm
      call arnoldi_cycle(self, a, m, min(mr, self%max_iter - its), rnorm, bnorm, tol, v, z, h, cs, sn, g, w, &
                         its, k, why, info%history)
      if (k > 0) call update_solution(h, g, z, k, x)
      call residual(a, b, x, r, w)
      rnorm_new = pnorm2(self%comm, r)
      if (.not. ieee_is_finite(rnorm_new)) then
        write(info%msg, '(a,i0)') 'fgmres: NaN or Inf in the residual (preconditioner or matrix broken) '// &
          'at iteration ', its
        info%rel_res = huge(1.0_rp)
        exit
      end if
      info%rel_res = rnorm_new / bnorm
      info%history(its) = info%rel_res
      if (rnorm_new <= tol) then
        info%converged = .true.
        exit
      end if
      select case (why)
      case (cycle_not_finite)
        call stop_msg(info, 'NaN or Inf in the residual (preconditioner or matrix broken) at', &
                      its, info%rel_res)
        exit
      case (cycle_singular)
        call stop_msg(info, 'breakdown: the preconditioned operator is singular on the Krylov space at', &
                      its, info%rel_res)
        exit
      end select
      if (rnorm_new >= rnorm) then
        ! a whole cycle without progress: with a fixed preconditioner the
        ! next cycle would repeat it exactly
        call stop_msg(info, 'stagnation (a restart cycle did not reduce the true residual) at', &
                      its, info%rel_res)
        exit
      end if
      rnorm = rnorm_new
    end do
    call info%finish(its, t0)
  end subroutine fgmres_solve

  !> One Arnoldi cycle of at most mr steps from v(:,1) = r / rnorm. Returns k,
  !> the number of usable columns of the least-squares problem, and why the
  !> cycle ended (cycle_*). history(its) gets the relative residual estimates.
  subroutine arnoldi_cycle(self, a, m, mr, rnorm, bnorm, tol, v, z, h, cs, sn, g, w, its, k, why, history)
    class(fgmres_t), intent(in) :: self
    class(linear_operator_t), intent(inout) :: a
    class(precon_t), intent(inout) :: m
    integer, intent(in) :: mr
    real(rp), intent(in) :: rnorm, bnorm, tol
    real(rp), intent(inout) :: v(:,:), z(:,:), h(:,:), cs(:), sn(:), g(:), w(:)
    integer, intent(inout) :: its
    integer, intent(out) :: k, why
    real(rp), intent(inout) :: history(0:)
    real(rp), parameter :: breakdown_tol = 10.0_rp * epsilon(1.0_rp)
    real(rp) :: wnorm0, hnorm, est
    integer :: j
    logical :: finite

    h = 0.0_rp
    g = 0.0_rp
    g(1) = rnorm
    k = 0
    why = cycle_full
    do j = 1, mr
      call arnoldi_step(self, a, m, j, v, z, h, w, wnorm0, hnorm, finite)
      its = its + 1
      if (.not. finite) then
        ! column j is poisoned; the first j-1 are still a valid update
        why = cycle_not_finite
        exit
      end if
      call givens_step(h(1:j+1, j), cs, sn, j, g)
      k = j
      if (abs(h(j, j)) <= breakdown_tol * wnorm0) then
        ! A z_j adds nothing to the span of A z_1..A z_{j-1} (possible in
        ! flexible GMRES, or z_j = 0): R is singular, drop column j
        k = j - 1
        why = cycle_singular
        exit
      end if
      est = abs(g(j+1))
      history(its) = est / bnorm
      if (est <= tol) then
        why = cycle_converged
        exit
      end if
      if (hnorm <= breakdown_tol * wnorm0) then
        ! happy breakdown: the Krylov space is invariant, y solves exactly
        why = cycle_breakdown
        exit
      end if
      if (j < mr) v(:, j+1) = w / hnorm
    end do
  end subroutine arnoldi_cycle

  !> Arnoldi step j: z_j = M^-1 v_j, w = A z_j orthogonalized against
  !> v_1..v_j by classical Gram-Schmidt (twice when the norm drops below
  !> reorth_drop). h(1:j+1, j) gets the coefficients, hnorm = ||w||, wnorm0 the
  !> norm of A z_j. Each pass's reduction carries the squared norm of the
  !> vector it projects (wnorm0 comes with the first); the norm after the
  !> first pass, needed only for the test, is sqrt(||w||^2 - ||c||^2)
  !> (Pythagoras), and with reorth_drop >= 1 (the default: always twice) it
  !> is not needed at all. Three reductions per step with two passes, where
  !> a norm per pass took five.
  !> finite is false when NaN or Inf appeared (then nothing is compared).
  subroutine arnoldi_step(self, a, m, j, v, z, h, w, wnorm0, hnorm, finite)
    class(fgmres_t), intent(in) :: self
    class(linear_operator_t), intent(inout) :: a
    class(precon_t), intent(inout) :: m
    integer, intent(in) :: j
    real(rp), intent(inout) :: v(:,:), z(:,:), h(:,:), w(:)
    real(rp), intent(out) :: wnorm0, hnorm
    logical, intent(out) :: finite
    real(rp) :: c(j), ww
    logical :: second

    call m%apply(v(:, j), z(:, j))
    call a%apply(z(:, j), w)
    call project_out(self, v, j, w, h(1:j, j), ww)
    wnorm0 = sqrt(max(ww, 0.0_rp))
    finite = ieee_is_finite(ww) .and. all(ieee_is_finite(h(1:j, j)))
    if (.not. finite) return
    second = self%reorthogonalize
    if (second .and. self%reorth_drop < 1.0_rp) &
      second = sqrt(max(ww - sum(h(1:j, j)**2), 0.0_rp)) < self%reorth_drop * wnorm0
    if (second) then
      call project_out(self, v, j, w, c, ww)
      h(1:j, j) = h(1:j, j) + c
    end if
    hnorm = pnorm2(self%comm, w)
    finite = ieee_is_finite(hnorm)
    if (.not. finite) return
    h(j+1, j) = hnorm
  end subroutine arnoldi_step

  !> One pass of classical Gram-Schmidt against v(:, 1:j): c = V^T w and
  !> ww = w . w in one reduction (BLAS-2 locally), then w = w - V c. Two
  !> passes of it are as good as modified Gram-Schmidt with
  !> re-orthogonalization ("twice is enough", Giraud, Langou and Rozloznik,
  !> Comput. Math. Appl. 50 (2005)), with j times fewer reductions.
  subroutine project_out(self, v, j, w, c, ww)
    class(fgmres_t), intent(in) :: self
    real(rp), intent(in) :: v(:,:)
    integer, intent(in) :: j
    real(rp), intent(inout) :: w(:)
    real(rp), intent(out) :: c(:), ww
    real(rp) :: cw(j + 1)
    integer :: n
    n = size(w)
    cw = 0.0_rp
    if (n > 0) call dgemv('T', n, j, 1.0_rp, v, size(v, 1), w, 1, 0.0_rp, cw, 1)
    cw(j + 1) = dot_product(w, w)
    call self%comm%sum_all(cw)
    c = cw(1:j)
    ww = cw(j + 1)
    if (n > 0) call dgemv('N', n, j, -1.0_rp, v, size(v, 1), c, 1, 1.0_rp, w, 1)
  end subroutine project_out

  !> Apply the previous rotations to column j of H (hj = h(1:j+1, j)), then
  !> the new rotation that zeroes hj(j+1), to the right-hand side g too.
  pure subroutine givens_step(hj, cs, sn, j, g)
    real(rp), intent(inout) :: hj(:), cs(:), sn(:), g(:)
    integer, intent(in) :: j
    real(rp) :: t, p, q, c, s
    integer :: i
    do i = 1, j - 1
      t = cs(i) * hj(i) + sn(i) * hj(i+1)
      hj(i+1) = -sn(i) * hj(i) + cs(i) * hj(i+1)
      hj(i) = t
    end do
    p = hj(j)
    q = hj(j+1)
    ! scaled forms avoid overflow in sqrt(p**2 + q**2)
    if (q == 0.0_rp) then
      c = 1.0_rp
      s = 0.0_rp
    else if (abs(q) > abs(p)) then
      t = p / q
      s = 1.0_rp / sqrt(1.0_rp + t * t)
      c = t * s
    else
      t = q / p
      c = 1.0_rp / sqrt(1.0_rp + t * t)
      s = t * c
    end if
    cs(j) = c
    sn(j) = s
    hj(j) = c * p + s * q
    hj(j+1) = 0.0_rp
    g(j+1) = -s * g(j)
    g(j) = c * g(j)
  end subroutine givens_step

  !> x = x + Z(:, 1:k) y with R(1:k, 1:k) y = g(1:k) (R: the rotated H).
  subroutine update_solution(h, g, z, k, x)
    real(rp), intent(in) :: h(:,:), g(:), z(:,:)
    integer, intent(in) :: k
    real(rp), intent(inout) :: x(:)
    real(rp) :: y(k)
    integer :: i
    do i = k, 1, -1
      y(i) = (g(i) - dot_product(h(i, i+1:k), y(i+1:k))) / h(i, i)
    end do
    do i = 1, k
      x = x + y(i) * z(:, i)
    end do
  end subroutine update_solution

  !> r = b - A x (w: work of the same size).
  subroutine residual(a, b, x, r, w)
    class(linear_operator_t), intent(inout) :: a
    real(rp), intent(in) :: b(:), x(:)
    real(rp), intent(inout) :: r(:), w(:)
    call a%apply(x, w)
    r = b - w
  end subroutine residual

  !> Message of a solve that stopped unconverged after its iterations.
  subroutine stop_msg(info, why, its, rel_res)
    type(solve_info_t), intent(inout) :: info
    character(len=*), intent(in) :: why
    integer, intent(in) :: its
    real(rp), intent(in) :: rel_res
    write(info%msg, '(a,a,a,i0,a,es10.3)') 'fgmres: ', why, ' iteration ', its, &
      ' with relative residual ', rel_res
  end subroutine stop_msg
end module fgmres
