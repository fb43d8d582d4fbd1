!> Operators and preconditioners made for the Krylov tests only: a variable
!> preconditioner (the reason flexible GMRES exists), broken ones (NaN after
!> a few calls, zero), and two matrix-free operators with known Krylov
!> behaviour (a rotation, a diagonal with three distinct values).
module krylov_test_precons
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use kinds, only: rp, ip, name_len
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  use csr_matrix, only: csr_matrix_t
  use jacobi_precon, only: jacobi_precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  implicit none
  private

  public :: inner_cg_precon_t, nan_precon_t, zero_precon_t, rotation_op_t, diagonal_op_t

  !> z = a few Jacobi-preconditioned CG iterations on A z = r from z = 0,
  !> with 2, 3, 4, 5, 2, ... iterations on successive calls: a nonlinear
  !> operator that changes from call to call.
  type, extends(precon_t) :: inner_cg_precon_t
    type(csr_matrix_t), pointer :: a => null()
    type(jacobi_precon_t), pointer :: jacobi => null()
    type(cg_t) :: inner
    integer :: n_calls = 0
  contains
    procedure :: apply => inner_cg_apply
    procedure :: name => inner_cg_name
  end type inner_cg_precon_t

  !> z = r for the first good_calls calls, then NaN.
  type, extends(precon_t) :: nan_precon_t
    integer :: good_calls = 2
    integer :: n_calls = 0
  contains
    procedure :: apply => nan_apply
    procedure :: name => nan_name
  end type nan_precon_t

  !> z = 0: M^-1 is singular.
  type, extends(precon_t) :: zero_precon_t
  contains
    procedure :: apply => zero_apply
    procedure :: name => zero_name
  end type zero_precon_t

  !> Quarter turn of each pair of owned entries: (x1, x2) -> (-x2, x1).
  !> r is orthogonal to A r, so GMRES(1) stagnates, while A^2 = -I makes
  !> two Krylov steps exact; p^T A p = 0 breaks CG down.
  type, extends(linear_operator_t) :: rotation_op_t
    integer(ip) :: n = 0                   !< owned entries (even)
  contains
    procedure :: apply => rotation_apply
    procedure :: n_owned => rotation_n_owned
  end type rotation_op_t

  !> y = d x: with three distinct values in d, Krylov methods end in three steps.
  type, extends(linear_operator_t) :: diagonal_op_t
    real(rp), allocatable :: d(:)
  contains
    procedure :: apply => diagonal_apply
    procedure :: n_owned => diagonal_n_owned
  end type diagonal_op_t

contains

  subroutine zero_apply(self, r, z)
    class(zero_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    z = 0.0_rp
  end subroutine zero_apply

  function zero_name(self) result(s)
    class(zero_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'zero'
  end function zero_name

  subroutine rotation_apply(self, x, y)
    class(rotation_op_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer(ip) :: i
    do i = 1, self%n - 1, 2
      y(i) = -x(i + 1)
      y(i + 1) = x(i)
    end do
  end subroutine rotation_apply

  integer(ip) function rotation_n_owned(self)
    class(rotation_op_t), intent(in) :: self
    rotation_n_owned = self%n
  end function rotation_n_owned

  subroutine diagonal_apply(self, x, y)
    class(diagonal_op_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    y = self%d * x
  end subroutine diagonal_apply

  integer(ip) function diagonal_n_owned(self)
    class(diagonal_op_t), intent(in) :: self
    diagonal_n_owned = size(self%d, kind=ip)
  end function diagonal_n_owned

  subroutine inner_cg_apply(self, r, z)
    class(inner_cg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    type(solve_info_t) :: info
    self%inner%max_iter = 2 + mod(self%n_calls, 4)
    self%n_calls = self%n_calls + 1
    z = 0.0_rp
    call self%inner%solve(self%a, self%jacobi, r, z, info)
  end subroutine inner_cg_apply

  function inner_cg_name(self) result(s)
    class(inner_cg_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'inner_cg'
  end function inner_cg_name

  subroutine nan_apply(self, r, z)
    class(nan_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    self%n_calls = self%n_calls + 1
    if (self%n_calls <= self%good_calls) then
      z = r
    else
      z = ieee_value(1.0_rp, ieee_quiet_nan)
    end if
  end subroutine nan_apply

  function nan_name(self) result(s)
    class(nan_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'nan'
  end function nan_name
end module krylov_test_precons

!> Unit tests of the Krylov solvers (cg_t, fgmres_t) and of jacobi_precon_t
!> on distributed cell-centred finite-volume problems on the unit square:
!> diffusion with a coefficient jump of 100 (SPD), plus upwind convection
!> (unsymmetric). The matrices are assembled face by face, so faces on the
!> partition boundary add to rows owned by the other rank (ghost rows and
!> the stash). The exact solution is chosen and b = A x_exact.
!> Two partitions are solved in the same run: rows spread evenly over the
!> ranks, and all rows on rank 0: on 2 ranks that compares 1-rank and 2-rank
!> arithmetic, whose iteration counts must be equal. 1 or 2 ranks.
program test_krylov
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: identity_precon_t
  use krylov, only: solve_info_t
  use cg, only: cg_t
  use fgmres, only: fgmres_t
  use jacobi_precon, only: jacobi_precon_t
  use dist_vector, only: pnorm2
  use assertions, only: test_suite_t, max_rel_diff
  use precon, only: precon_t
  use inner_cg_precon, only: steps_precon_t => inner_cg_precon_t
  use strings, only: itoa
  use krylov_test_precons, only: inner_cg_precon_t, nan_precon_t, zero_precon_t, rotation_op_t, &
                                 diagonal_op_t
  implicit none

  !> One distributed test problem: maps, matrix, exact solution, rhs.
  type :: problem_t
    type(index_map_t) :: row_map, col_map
    type(csr_matrix_t) :: a
    real(rp), allocatable :: x_exact(:), b(:)
  end type problem_t

  real(rp), parameter :: rtol = 1.0e-10_rp
  integer, parameter :: n_side = 24
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  integer :: its_even(3), its_root(3)

  call comm%init_world()
  call suite%init('krylov', comm)

  call check_spd(.false., its_even)
  call check_spd(.true., its_root)
  call suite%assert_true(all(its_even == its_root), &
    'iteration counts equal on the even and the all-on-rank-0 partitions (1 vs N ranks)')
  if (comm%rank == 0) write(*, '(a,3(1x,i0),a,3(1x,i0))') '  iterations cg+jacobi, fgmres+jacobi, '// &
    'fgmres+none: even partition', its_even, ', all on rank 0', its_root
  call check_unsymmetric()
  call check_restart_and_limits()
  call check_flexible()
  call check_fixed_steps()
  call check_failures()
  call check_breakdowns()
  call suite%finish()

contains

  ! ---- problem set-up ----------------------------------------------------------

  !> Diffusion coefficient of a cell in column i of n: with jump, 1 on the
  !> left half and 100 on the right; else 1.
  real(rp) function coefficient(i, n, jump)
    integer, intent(in) :: i, n
    logical, intent(in) :: jump
    coefficient = 1.0_rp
    if (jump .and. 2 * i > n) coefficient = 100.0_rp
  end function coefficient

  !> Build the n x n cell problem on comm: all_on_root puts every row on
  !> rank 0, else rows are spread evenly. convection: upwind flux number
  !> (velocity times h) in +x, 0 for pure diffusion; jump: use the
  !> coefficient jump (else coefficient 1).
  subroutine build_problem(p, n, all_on_root, convection, jump)
    type(problem_t), intent(inout), target :: p
    integer, intent(in) :: n
    logical, intent(in) :: all_on_root, jump
    real(rp), intent(in) :: convection
    integer(gp) :: n_cells, first, last, c, nb(4), cl, cr
    integer(gp), allocatable :: row_ghosts(:), col_ghosts(:)
    integer(ip), allocatable :: row_ptr(:), col(:)
    integer(ip) :: nown, i, k, m
    integer :: ic, q
    real(rp) :: t, kl, kr, blk(2, 2)

    n_cells = int(n, gp)**2
    if (all_on_root) then
      nown = merge(int(n_cells, ip), 0_ip, comm%rank == 0)
      first = 1
    else
      nown = int(n_cells / comm%size + merge(1, 0, comm%rank < mod(n_cells, int(comm%size, gp))), ip)
      first = 1 + comm%rank * (n_cells / comm%size) + min(int(comm%rank, gp), mod(n_cells, int(comm%size, gp)))
    end if
    last = first + nown - 1

    ! ghosts: rows = east/north neighbours (faces I assemble), columns = all neighbours
    allocate(row_ghosts(2 * n), col_ghosts(4 * n))
    m = 0
    k = 0
    do c = first, last
      call neighbours(c, n, nb)
      do q = 1, 4
        if (nb(q) == 0 .or. (nb(q) >= first .and. nb(q) <= last)) cycle
        if (q >= 3 .and. .not. any(row_ghosts(1:m) == nb(q))) then
          m = m + 1
          row_ghosts(m) = nb(q)
        end if
        if (.not. any(col_ghosts(1:k) == nb(q))) then
          k = k + 1
          col_ghosts(k) = nb(q)
        end if
      end do
    end do
    call p%row_map%init(comm, nown, row_ghosts(1:m))
    call p%col_map%init(comm, nown, col_ghosts(1:k))

    ! pattern: the cell and its neighbours, local column ids ascending
    allocate(row_ptr(nown + 1), col(5 * nown))
    row_ptr(1) = 1
    do i = 1, nown
      c = first + i - 1
      call neighbours(c, n, nb)
      m = 0
      col(row_ptr(i)) = i
      do q = 1, 4
        if (nb(q) == 0) cycle
        m = m + 1
        col(row_ptr(i) + m) = p%col_map%local_id(nb(q))
      end do
      call sort_ascending(col(row_ptr(i):row_ptr(i) + m))
      row_ptr(i + 1) = row_ptr(i) + m + 1
    end do
    call p%a%init(p%row_map, p%col_map, row_ptr, col(1:row_ptr(nown + 1) - 1))

    ! face by face: each owned cell assembles its east and north faces and
    ! its boundary faces (Dirichlet 0 at half a cell: transmissibility 2 k)
    do c = first, last
      ic = int(mod(c - 1, int(n, gp))) + 1
      call neighbours(c, n, nb)
      kl = coefficient(ic, n, jump)
      do q = 1, 4
        if (nb(q) == 0) then
          t = 2.0_rp * kl
          if (q == 3) t = t + convection        ! outflow through the east boundary
          call p%a%add_value(local_row(p, c), local_col(p, c), t)
        else if (q >= 3) then
          kr = coefficient(merge(ic + 1, ic, q == 3), n, jump)
          t = 2.0_rp * kl * kr / (kl + kr)
          blk = reshape([t, -t, -t, t], [2, 2])
          if (q == 3) then
            ! upwind: the flux through the east face carries u of the west cell
            blk(1, 1) = blk(1, 1) + convection
            blk(2, 1) = blk(2, 1) - convection
          end if
          cl = c
          cr = nb(q)
          call p%a%add_block([local_row(p, cl), local_row(p, cr)], [local_col(p, cl), local_col(p, cr)], blk)
        end if
      end do
    end do
    call p%a%finalize_assembly()

    allocate(p%x_exact(nown), p%b(nown))
    do i = 1, nown
      c = first + i - 1
      p%x_exact(i) = sin(0.37_rp * real(c, rp)) + real(mod(c, 7_gp), rp) / 7.0_rp
    end do
    call p%a%apply(p%x_exact, p%b)
  end subroutine build_problem

  !> Neighbours of cell c in the n x n grid: west, south, east, north (0: none).
  subroutine neighbours(c, n, nb)
    integer(gp), intent(in) :: c
    integer, intent(in) :: n
    integer(gp), intent(out) :: nb(4)
    integer(gp) :: i, j
    i = mod(c - 1, int(n, gp)) + 1
    j = (c - 1) / n + 1
    nb = 0
    if (i > 1) nb(1) = c - 1
    if (j > 1) nb(2) = c - n
    if (i < n) nb(3) = c + 1
    if (j < n) nb(4) = c + n
  end subroutine neighbours

  integer(ip) function local_row(p, g)
    type(problem_t), intent(in) :: p
    integer(gp), intent(in) :: g
    local_row = p%row_map%local_id(g)
  end function local_row

  integer(ip) function local_col(p, g)
    type(problem_t), intent(in) :: p
    integer(gp), intent(in) :: g
    local_col = p%col_map%local_id(g)
  end function local_col

  subroutine sort_ascending(v)
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
  end subroutine sort_ascending

  subroutine free_problem(p)
    type(problem_t), intent(inout) :: p
    call p%a%free()
    call p%col_map%free()
    call p%row_map%free()
    deallocate(p%x_exact, p%b)
  end subroutine free_problem

  ! ---- checks of one solve -----------------------------------------------------

  !> The solve converged to rtol: the report says so, the TRUE residual
  !> (recomputed here) agrees, the history is consistent and the error
  !> against the exact solution is below err_tol (relative, max norm).
  subroutine check_converged(p, x, info, err_tol, label)
    type(problem_t), intent(inout) :: p
    real(rp), intent(in) :: x(:)
    type(solve_info_t), intent(in) :: info
    real(rp), intent(in) :: err_tol
    character(len=*), intent(in) :: label
    real(rp), allocatable :: r(:)
    real(rp) :: rel, err, scale, bnorm
    allocate(r(size(x)))
    call p%a%apply(x, r)
    r = p%b - r
    bnorm = pnorm2(comm, p%b)
    rel = pnorm2(comm, r) / bnorm
    err = 0.0_rp
    scale = 0.0_rp
    if (size(x) > 0) then
      err = maxval(abs(x - p%x_exact))
      scale = maxval(abs(p%x_exact))
    end if
    err = comm%max(err) / comm%max(scale)
    call suite%assert_true(info%converged .and. info%rel_res <= rtol .and. len_trim(info%msg) == 0, &
                           label//': converged, reported rel_res <= 1e-10, no msg')
    call suite%assert_true(rel <= rtol .and. abs(rel - info%rel_res) <= 1.0e-3_rp * rtol, &
                           label//': true residual <= 1e-10 and equal to the reported one')
    call suite%assert_true(allocated(info%history), label//': history allocated')
    if (allocated(info%history)) then
      call suite%assert_true(lbound(info%history, 1) == 0 .and. ubound(info%history, 1) == info%iterations &
                             .and. abs(info%history(0) - info%res0 / bnorm) <= 1.0e-12_rp &
                             .and. abs(info%history(info%iterations) - info%rel_res) <= 1.0e-12_rp, &
                             label//': history(0:iterations) from res0 to rel_res')
    end if
    call suite%assert_close(err, 0.0_rp, err_tol, label//': error against the exact solution')
  end subroutine check_converged

  ! ---- the test groups ---------------------------------------------------------

  !> Jump-coefficient diffusion (SPD): CG + Jacobi, FGMRES + Jacobi, FGMRES
  !> without preconditioner; iteration counts returned for the comparison
  !> of the two partitions.
  subroutine check_spd(all_on_root, its)
    logical, intent(in) :: all_on_root
    integer, intent(out) :: its(3)
    type(problem_t), target :: p
    type(jacobi_precon_t) :: jac
    type(identity_precon_t) :: none
    type(cg_t) :: cg_solver
    type(fgmres_t) :: gm
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: x(:)
    character(len=40) :: part
    real(rp), parameter :: err_tol = 1.0e-6_rp

    part = merge(' (all rows on rank 0)', ' (rows spread evenly)', all_on_root)
    call build_problem(p, n_side, all_on_root, 0.0_rp, .true.)
    call jac%setup(p%a, status)
    call suite%assert_true(status%ok(), 'jacobi setup on a good matrix'//trim(part))
    call suite%assert_true(jac%name() == 'jacobi', 'jacobi name')
    allocate(x(size(p%b)))

    call cg_solver%init(comm, rtol=rtol, atol=0.0_rp, max_iter=1000)
    x = 0.0_rp
    call cg_solver%solve(p%a, jac, p%b, x, info)
    call check_converged(p, x, info, err_tol, 'cg+jacobi'//trim(part))
    its(1) = info%iterations

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=1000, restart=400)
    call suite%assert_true(gm%name() == 'fgmres' .and. cg_solver%name() == 'cg', 'solver names')
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    call check_converged(p, x, info, err_tol, 'fgmres+jacobi'//trim(part))
    its(2) = info%iterations
    call suite%assert_true(info%iterations <= its(1), &
                           'fgmres+jacobi needs no more iterations than cg+jacobi (it minimizes)'//trim(part))
    call suite%assert_true(all(info%history(1:) <= info%history(0:info%iterations-1) * (1.0_rp + 1.0e-10_rp)), &
                           'fgmres residual history non-increasing'//trim(part))

    x = 0.0_rp
    call gm%solve(p%a, none, p%b, x, info)
    call check_converged(p, x, info, err_tol, 'fgmres+identity'//trim(part))
    its(3) = info%iterations
    call suite%assert_true(its(3) > its(2), 'jacobi helps fgmres on the jump coefficient'//trim(part))

    ! an exact initial guess: nothing to do
    x = p%x_exact
    call cg_solver%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 0, 'cg from the exact solution: 0 iterations')
    x = p%x_exact
    call gm%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 0, &
                           'fgmres from the exact solution: 0 iterations')
    call jac%free()
    call free_problem(p)
  end subroutine check_spd

  !> Diffusion plus strong upwind convection (unsymmetric): FGMRES + Jacobi.
  subroutine check_unsymmetric()
    type(problem_t), target :: p
    type(jacobi_precon_t) :: jac
    type(fgmres_t) :: gm
    type(cg_t) :: cg_solver
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: x(:)

    call build_problem(p, n_side, .false., 8.0_rp, .false.)
    call jac%setup(p%a, status)
    allocate(x(size(p%b)))
    ! independent check that the matrix is unsymmetric: x^T A y /= y^T A x
    call suite%assert_true(abs(asym(p)) > 1.0_rp, 'convection makes the matrix unsymmetric')
    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=1000, restart=200)
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    call check_converged(p, x, info, 1.0e-7_rp, 'fgmres+jacobi, convection')
    if (comm%rank == 0) write(*, '(a,i0)') '  iterations fgmres+jacobi with convection: ', info%iterations
    ! atol alone decides when rtol = 0
    call gm%init(comm, rtol=0.0_rp, atol=1.0e-6_rp * pnorm2(comm, p%b), max_iter=1000, restart=200)
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(info%converged .and. info%rel_res <= 1.0e-6_rp .and. info%rel_res > 1.0e-10_rp, &
                           'atol alone stops at its own level')
    ! CG on it: no promise of convergence, but a clean report either way
    call cg_solver%init(comm, rtol=rtol, max_iter=50)
    x = 0.0_rp
    call cg_solver%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(info%converged .or. len_trim(info%msg) > 0, 'cg on an unsymmetric matrix reports')
    call jac%free()
    call free_problem(p)
  end subroutine check_unsymmetric

  !> x^T A y - y^T A x for two fixed vectors (nonzero when A is unsymmetric).
  real(rp) function asym(p)
    type(problem_t), intent(inout) :: p
    real(rp), allocatable :: xv(:), yv(:), axv(:), ayv(:)
    integer :: i, n
    n = size(p%b)
    allocate(xv(n), yv(n), axv(n), ayv(n))
    do i = 1, n
      xv(i) = real(mod(p%row_map%first + i, 5_gp), rp)
      yv(i) = real(mod(3 * (p%row_map%first + i), 7_gp), rp)
    end do
    call p%a%apply(xv, axv)
    call p%a%apply(yv, ayv)
    asym = comm%sum(dot_product(xv, ayv) - dot_product(yv, axv))
  end function asym

  !> FGMRES restarted more often than it iterates; max_iter too small; b = 0.
  subroutine check_restart_and_limits()
    type(problem_t), target :: p
    type(jacobi_precon_t) :: jac
    type(fgmres_t) :: gm
    type(cg_t) :: cg_solver
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: x(:), zero_b(:)

    call build_problem(p, 12, .false., 0.0_rp, .false.)
    call jac%setup(p%a, status)
    allocate(x(size(p%b)), zero_b(size(p%b)))

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=3000, restart=10)
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    call check_converged(p, x, info, 1.0e-7_rp, 'fgmres(10)+jacobi')
    call suite%assert_true(info%iterations > 3 * 10, 'fgmres(10) went through several restarts')
    if (comm%rank == 0) write(*, '(a,i0)') '  iterations fgmres(10)+jacobi: ', info%iterations

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=5, restart=3)
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 5 .and. &
                           index(info%msg, 'max_iter = 5') > 0 .and. info%rel_res > rtol .and. &
                           info%rel_res < 1.0_rp, 'fgmres max_iter = 5: not converged, said why')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
    call cg_solver%init(comm, rtol=rtol, max_iter=5)
    x = 0.0_rp
    call cg_solver%solve(p%a, jac, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 5 .and. &
                           index(info%msg, 'max_iter = 5') > 0 .and. info%rel_res > rtol, &
                           'cg max_iter = 5: not converged, said why')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)

    zero_b = 0.0_rp
    x = 1.0_rp
    call gm%solve(p%a, jac, zero_b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 0 .and. all(x == 0.0_rp), &
                           'fgmres with b = 0: x = 0, 0 iterations')
    x = 1.0_rp
    call cg_solver%solve(p%a, jac, zero_b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 0 .and. all(x == 0.0_rp), &
                           'cg with b = 0: x = 0, 0 iterations')
    call jac%free()
    call free_problem(p)
  end subroutine check_restart_and_limits

  !> A preconditioner that changes from call to call (inner CG with a
  !> varying iteration count): FGMRES still converges.
  subroutine check_flexible()
    type(problem_t), target :: p
    type(jacobi_precon_t), target :: jac
    type(inner_cg_precon_t) :: var
    type(fgmres_t) :: gm
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: x(:), z1(:), z2(:)
    integer :: its_jacobi

    call build_problem(p, n_side, .false., 0.0_rp, .true.)
    call jac%setup(p%a, status)
    var%a => p%a
    var%jacobi => jac
    call var%inner%init(comm, rtol=1.0e-14_rp, atol=0.0_rp, max_iter=2)
    allocate(x(size(p%b)), z1(size(p%b)), z2(size(p%b)))

    ! the same r twice gives two different z
    call var%apply(p%b, z1)
    call var%apply(p%b, z2)
    call suite%assert_true(max_rel_diff(comm, z2, z1) > 1.0e-3_rp, &
                           'the variable preconditioner changes from call to call')

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=500, restart=30)
    x = 0.0_rp
    call gm%solve(p%a, jac, p%b, x, info)
    its_jacobi = info%iterations
    var%n_calls = 0
    x = 0.0_rp
    call gm%solve(p%a, var, p%b, x, info)
    call check_converged(p, x, info, 1.0e-6_rp, 'fgmres+variable inner cg')
    call suite%assert_true(info%iterations < its_jacobi, 'the inner cg preconditioner beats jacobi')
    if (comm%rank == 0) write(*, '(a,i0,a,i0)') '  iterations fgmres(30)+inner cg: ', info%iterations, &
      ', fgmres(30)+jacobi: ', its_jacobi
    call jac%free()
    call free_problem(p)
  end subroutine check_flexible

  !> inner_cg_precon with a fixed number of steps (contact's schur_solve =
  !> 'pcg'): k steps from zero are CG's first k iterations (cg_t with
  !> max_iter = k and no tolerance), for k = 1, 3, 8; more steps, a smaller
  !> error in the energy norm.
  subroutine check_fixed_steps()
    type(problem_t), target :: p
    type(steps_precon_t) :: sp
    class(precon_t), allocatable :: jac
    type(jacobi_precon_t) :: jac2
    type(cg_t) :: cg_solver
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: z(:), x(:), e(:), ae(:)
    real(rp) :: energy, last_energy
    integer :: i, k
    integer, parameter :: ks(3) = [1, 3, 8]

    call build_problem(p, n_side, .false., 0.0_rp, .true.)
    call jac2%setup(p%a, status)
    allocate(z(size(p%b)), x(size(p%b)), e(size(p%b)), ae(size(p%b)))
    last_energy = huge(1.0_rp)
    do i = 1, size(ks)
      k = ks(i)
      allocate(jacobi_precon_t :: jac)
      select type (jac)
      type is (jacobi_precon_t)
        call jac%setup(p%a, status)
      end select
      call sp%init_steps(jac, k, p%a)
      call sp%apply(p%b, z)
      call cg_solver%init(comm, rtol=0.0_rp, atol=0.0_rp, max_iter=k)
      x = 0.0_rp
      call cg_solver%solve(p%a, jac2, p%b, x, info)
      call suite%assert_true(max_rel_diff(comm, z, x) <= 1.0e-12_rp .and. info%iterations == k &
                             .and. sp%iterations == k, 'pcg steps: '//trim(itoa(k))//' steps = CG''s first '// &
                             trim(itoa(k))//' iterations')
      e = p%x_exact - z
      call p%a%apply(e, ae)
      energy = sqrt(comm%sum(dot_product(e, ae)))
      call suite%assert_true(energy < last_energy, 'pcg steps: the energy error falls with the steps ('// &
                             trim(itoa(k))//')')
      last_energy = energy
      if (k == 8) call suite%assert_true(sp%name() == 'PCG (8 steps) + jacobi', &
                                         'pcg steps: named by its steps and inner preconditioner')
      call sp%free()
    end do
  end subroutine check_fixed_steps

  !> Broken preconditioner (NaN), indefinite matrix for CG, bad diagonal for
  !> Jacobi: clean stops with a message, no endless loop.
  subroutine check_failures()
    type(problem_t), target :: p
    type(jacobi_precon_t) :: jac
    type(identity_precon_t) :: none
    type(nan_precon_t) :: broken
    type(fgmres_t) :: gm
    type(cg_t) :: cg_solver
    type(solve_info_t) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: x(:)
    integer(gp) :: g_bad
    integer(ip) :: i, k
    character(len=msg_len) :: expect

    call build_problem(p, 12, .false., 0.0_rp, .false.)
    allocate(x(size(p%b)))

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=100, restart=20)
    broken%good_calls = 2
    x = 0.0_rp
    call gm%solve(p%a, broken, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 3 .and. &
                           index(info%msg, 'NaN') > 0 .and. info%rel_res < 1.0_rp .and. &
                           all(abs(x) < huge(1.0_rp)), &
                           'fgmres: NaN from the preconditioner stops at once, x keeps the good columns')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
    broken%n_calls = 0
    broken%good_calls = 0
    x = 0.0_rp
    call gm%solve(p%a, broken, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 1 .and. index(info%msg, 'NaN') > 0 &
                           .and. all(x == 0.0_rp), 'fgmres: NaN at the first application')

    call cg_solver%init(comm, rtol=rtol, max_iter=100)
    broken%n_calls = 0
    broken%good_calls = 2
    x = 0.0_rp
    call cg_solver%solve(p%a, broken, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 2 .and. index(info%msg, 'NaN') > 0, &
                           'cg: NaN from the preconditioner stops at once')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)

    ! -A is negative definite: CG must say so at the first step
    p%a%val = -p%a%val
    p%b = -p%b
    x = 0.0_rp
    call cg_solver%solve(p%a, none, p%b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 1 .and. &
                           index(info%msg, 'p^T A p <= 0') > 0, 'cg on a negative definite matrix: breakdown')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
    ! FGMRES does not care about definiteness
    x = 0.0_rp
    call gm%solve(p%a, none, p%b, x, info)
    call suite%assert_true(info%converged, 'fgmres on the negative definite matrix converges')
    p%a%val = -p%a%val
    p%b = -p%b

    ! a zero diagonal entry in a row of the last rank: every rank gets the error
    g_bad = p%row_map%n_global - 3
    i = p%row_map%local_id(g_bad)
    if (i >= 1 .and. i <= p%row_map%n_owned) then
      k = p%a%find(i, i)
      p%a%val(k) = 0.0_rp
    end if
    call jac%setup(p%a, status)
    write(expect, '(a,i0,a)') 'global row ', g_bad, ' is zero'
    call suite%assert_true(.not. status%ok() .and. index(status%msg, trim(expect)) > 0, &
                           'jacobi setup names the global row of a zero diagonal, on every rank')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(status%msg)
    call free_problem(p)
  end subroutine check_failures
  !> Krylov spaces that end early, on matrix-free operators: exact solution
  !> in as many steps as distinct eigenvalues, GMRES(1) stagnation on a
  !> rotation, CG breakdown on it, a singular (zero) preconditioner.
  subroutine check_breakdowns()
    type(rotation_op_t) :: rot
    type(diagonal_op_t) :: dia
    type(identity_precon_t) :: none
    type(zero_precon_t) :: zero
    type(fgmres_t) :: gm
    type(cg_t) :: cg_solver
    type(solve_info_t) :: info
    real(rp), allocatable :: b(:), x(:), expect(:)
    real(rp), parameter :: values(0:2) = [1.0_rp, 2.0_rp, 5.0_rp]
    integer(gp) :: first
    integer(ip) :: i, n

    n = 10
    first = comm%exscan_g(int(n, gp)) + 1
    allocate(b(n), x(n), expect(n), dia%d(n))
    do i = 1, n
      b(i) = 1.0_rp + real(mod(first + i, 4_gp), rp)
      dia%d(i) = values(mod(first + i, 3_gp))
    end do
    expect = b / dia%d

    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=50, restart=20)
    x = 0.0_rp
    call gm%solve(dia, none, b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 3, &
                           'fgmres on a diagonal with 3 distinct values: 3 iterations')
    call suite%assert_close(comm%max(maxval(abs(x - expect))), 0.0_rp, 1.0e-10_rp, &
                            'fgmres on the diagonal: exact solution')
    call cg_solver%init(comm, rtol=rtol, atol=0.0_rp, max_iter=50)
    x = 0.0_rp
    call cg_solver%solve(dia, none, b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 3, &
                           'cg on a diagonal with 3 distinct values: 3 iterations')

    rot%n = n
    x = 0.0_rp
    call gm%solve(rot, none, b, x, info)
    call suite%assert_true(info%converged .and. info%iterations == 2, 'fgmres(20) on a rotation: 2 iterations')
    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=50, restart=1)
    x = 0.0_rp
    call gm%solve(rot, none, b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 1 .and. &
                           index(info%msg, 'stagnation') > 0, 'fgmres(1) on a rotation: stagnation reported at once')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
    x = 0.0_rp
    call cg_solver%solve(rot, none, b, x, info)
    call suite%assert_true(.not. info%converged .and. index(info%msg, 'p^T A p <= 0') > 0, &
                           'cg on a rotation (p^T A p = 0): breakdown reported')

    x = 0.0_rp
    call gm%init(comm, rtol=rtol, atol=0.0_rp, max_iter=50, restart=20)
    call gm%solve(dia, zero, b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 1 .and. &
                           index(info%msg, 'singular') > 0 .and. all(x == 0.0_rp), &
                           'fgmres with a zero preconditioner: singular breakdown at once')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
    x = 0.0_rp
    call cg_solver%solve(dia, zero, b, x, info)
    call suite%assert_true(.not. info%converged .and. info%iterations == 0 .and. &
                           index(info%msg, 'r^T M^-1 r <= 0') > 0, 'cg with a zero preconditioner: breakdown at once')
    if (comm%rank == 0) write(*, '(a,a)') '  msg: ', trim(info%msg)
  end subroutine check_breakdowns
end program test_krylov
