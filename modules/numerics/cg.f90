!> Preconditioned conjugate gradients, for symmetric positive definite A
!> with a symmetric positive definite (and fixed) preconditioner M.
!>
!> The recursively updated residual drives the iteration; when it says
!> "converged", the TRUE residual b - A x is computed and decides:
!>   ||b - A x|| <= max(rtol ||b||, atol).
!> If the true residual is not there yet, the recurrence restarts from it.
!> Loss of definiteness (p^T A p <= 0 or r^T M^-1 r <= 0) stops the solve
!> with a message instead of producing garbage.
module cg
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

  public :: cg_t

  !> Preconditioned CG; restart (inherited) is not used.
  type, extends(krylov_t) :: cg_t
  contains
    procedure :: init => cg_init
    procedure :: solve => cg_solve
    procedure :: name => cg_name
  end type cg_t

contains

  !> Set the communicator and the parameters. rtol, atol: tolerances of the
  !> residual norm (relative to ||b||, absolute); max_iter: iterations.
  !> Omitted values keep the defaults of krylov_t. Bad values (rtol or atol
  !> < 0, max_iter < 0) set status, or stop when status is absent (the deck
  !> readers range-check them first, so then it is a programming error).
  subroutine cg_init(self, comm, rtol, atol, max_iter, status)
    class(cg_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in), optional :: rtol, atol
    integer, intent(in), optional :: max_iter
    type(error_status_t), intent(inout), optional :: status

    if (.not. self%configure(comm, rtol, atol, max_iter, status)) return
  end subroutine cg_init

  function cg_name(self) result(s)
    class(cg_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'cg'
  end function cg_name

  !> Solve A x = b with preconditioner m; x holds the initial guess on entry
  !> and the answer on exit. Collective. info: iterations, res0 = ||b - A x0||,
  !> rel_res = true ||b - A x|| / ||b|| (huge() when not finite),
  !> history(0:iterations) = recursive relative residuals (true ones where
  !> they were checked), msg = why it stopped when not converged.
  subroutine cg_solve(self, a, m, b, x, info)
    class(cg_t), intent(inout) :: self
    class(linear_operator_t), intent(inout) :: a
    class(precon_t), intent(inout) :: m
    real(rp), intent(in) :: b(:)
    real(rp), intent(inout) :: x(:)
    type(solve_info_t), intent(out) :: info
    real(rp), allocatable :: r(:), z(:), p(:), q(:)
    real(rp) :: t0, bnorm, tol, rnorm, rz, rz_new, pq, alpha, last_true
    integer :: n, its
    logical :: fresh, done

    t0 = wall_time()
    n = size(b)
    allocate(info%history(0:max(self%max_iter, 0)))
    info%history = 0.0_rp
    its = 0
    bnorm = pnorm2(self%comm, b)
    if (.not. ieee_is_finite(bnorm)) then
      info%msg = 'cg: NaN or Inf in the right-hand side'
      info%rel_res = huge(1.0_rp)
      call info%finish(its, t0)
      return
    end if
    if (bnorm == 0.0_rp) then
      x = 0.0_rp
      info%converged = .true.
      call info%finish(its, t0)
      return
    end if
    tol = max(self%rtol * bnorm, self%atol)

    allocate(r(n), z(n), p(n), q(n))
    call a%apply(x, q)
    r = b - q
    rnorm = pnorm2(self%comm, r)
    info%res0 = rnorm
    if (.not. ieee_is_finite(rnorm)) then
      info%msg = 'cg: NaN or Inf in the initial residual (matrix or initial guess broken)'
      info%rel_res = huge(1.0_rp)
      call info%finish(its, t0)
      return
    end if
    info%rel_res = rnorm / bnorm
    info%history(0) = info%rel_res
    last_true = rnorm
    done = rnorm <= tol
    info%converged = done
    fresh = .true.
    rz = 0.0_rp
    p = 0.0_rp
    do while (.not. done)
      if (its >= self%max_iter) then
        write(info%msg, '(a,i0,a)') 'cg: reached max_iter = ', self%max_iter, ' with relative residual'
        exit
      end if
      ! new direction (from the preconditioned residual)
      call m%apply(r, z)
      rz_new = pdot(self%comm, r, z)
      if (.not. ieee_is_finite(rz_new)) then
        call stop_msg(info, 'NaN or Inf in the preconditioned residual (preconditioner broken)', its)
        exit
      end if
      if (rz_new <= 0.0_rp) then
        call stop_msg(info, 'breakdown: r^T M^-1 r <= 0, the preconditioner is not SPD', its, rz_new)
        exit
      end if
      if (fresh) then
        p = z
      else
        p = z + (rz_new / rz) * p
      end if
      rz = rz_new
      fresh = .false.

      ! step along p
      call a%apply(p, q)
      pq = pdot(self%comm, p, q)
      its = its + 1
      if (.not. ieee_is_finite(pq)) then
        call stop_msg(info, 'NaN or Inf in A p (matrix or preconditioner broken)', its)
        exit
      end if
      if (pq <= 0.0_rp) then
        call stop_msg(info, 'breakdown: p^T A p <= 0, the matrix or the preconditioner is not SPD', its, pq)
        exit
      end if
      alpha = rz / pq
      x = x + alpha * p
      r = r - alpha * q
      rnorm = pnorm2(self%comm, r)
      if (.not. ieee_is_finite(rnorm)) then
        call stop_msg(info, 'NaN or Inf in the residual (preconditioner or matrix broken)', its)
        exit
      end if
      info%history(its) = rnorm / bnorm
      if (rnorm > tol) cycle

      ! the recurrence says converged: the true residual decides
      call a%apply(x, q)
      r = b - q
      rnorm = pnorm2(self%comm, r)
      if (.not. ieee_is_finite(rnorm)) then
        call stop_msg(info, 'NaN or Inf in the residual (preconditioner or matrix broken)', its)
        exit
      end if
      info%history(its) = rnorm / bnorm
      done = rnorm <= tol
      info%converged = done
      if (.not. done .and. rnorm >= last_true) then
        call stop_msg(info, 'stagnation (the true residual no longer decreases, tolerance below the '// &
                      'attainable accuracy?)', its)
        exit
      end if
      last_true = rnorm
      ! restart the recurrence from the true residual
      fresh = .true.
    end do
    if (info%converged) then
      info%rel_res = rnorm / bnorm
    else
      call final_residual(self, a, b, x, q, bnorm, info)
    end if
    call info%finish(its, t0)
  end subroutine cg_solve

  !> rel_res from the true residual at the end (huge() when not finite); the
  !> message of an unconverged solve ends with "relative residual" and gets
  !> the value appended.
  subroutine final_residual(self, a, b, x, w, bnorm, info)
    class(cg_t), intent(in) :: self
    class(linear_operator_t), intent(inout) :: a
    real(rp), intent(in) :: b(:), x(:), bnorm
    real(rp), intent(inout) :: w(:)
    type(solve_info_t), intent(inout) :: info
    real(rp) :: rn
    call a%apply(x, w)
    w = b - w
    rn = pnorm2(self%comm, w)
    if (ieee_is_finite(rn)) then
      info%rel_res = rn / bnorm
    else
      info%rel_res = huge(1.0_rp)
    end if
    if (.not. info%converged) write(info%msg, '(a,1x,es10.3)') trim(info%msg), info%rel_res
  end subroutine final_residual

  !> Message of a solve that stopped unconverged; value (if present) is the
  !> offending quantity.
  subroutine stop_msg(info, why, its, value)
    type(solve_info_t), intent(inout) :: info
    character(len=*), intent(in) :: why
    integer, intent(in) :: its
    real(rp), intent(in), optional :: value
    if (present(value)) then
      write(info%msg, '(a,a,a,es10.3,a,i0,a)') 'cg: ', why, ' (value ', value, ') at iteration ', its, &
        ', relative residual'
    else
      write(info%msg, '(a,a,a,i0,a)') 'cg: ', why, ' at iteration ', its, ', relative residual'
    end if
  end subroutine stop_msg
end module cg
