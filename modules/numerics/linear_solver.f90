!> The one linear-solve path of every physics: a Krylov method ('fgmres',
!> 'cg') with the physics' preconditioner on the diagonally scaled system,
!> or the direct solver MUMPS ('mumps') on the assembled operator.
!>
!> Scaling: with a scaling D (linear_system_t%d), the Krylov method solves
!> (D A D) y = D b, x = D y, preconditioned by D^-1 M D^-1; its tolerances
!> then apply to the scaled residual, in which every block of a coupled
!> system counts (scaled_system.f90).
!>
!> Tolerance floor: within a step (between begin_step calls) the absolute
!> tolerance is at least floor_factor * rtol times the norm of the first
!> right-hand side of the step. Newton's last iterations have right-hand
!> sides near round-off, where rtol alone would ask for digits that do not
!> exist; a linear problem (one solve per step) never reaches the floor.
!>
!> A direct solve factorizes the scaled matrix D A D too when a scaling is
!> given: a saddle point whose blocks differ by twenty orders of magnitude
!> (stiffness against stabilization, contact) otherwise loses pivots to the
!> factorization's relative thresholds (MUMPS reported a stabilized stick
!> system of 58,614 unknowns numerically singular on one process).
!> A direct solve is judged by what a direct solve can achieve: its
!> componentwise backward error omega (backward_error: the smallest relative
!> change of each entry of A and b of which x is the exact solution), which
!> does not depend on the scaling, must be at most backward_tol = 1e-10.
!> The relative residual ||b - A x|| / ||b|| is no measure of a direct
!> solve: it is bounded only by omega times the condition number, which a
!> closed fracture's storage (c_f A a0 / dt, ~1e-16 m^3/Pa beside cubic-law
!> transmissibilities of ~1e-8 m^3/(Pa s)) or a nearly incompressible
!> fluid makes 1e8 or more, so that solves accurate to round-off showed
!> relative residuals of 1e-8 to 1e-5 and were refused. Before the
!> judgement, iterative refinement (ours, so that the host and the
!> distributed layouts get it alike) corrects x while omega is above
!> refine_target = 1e-14 and each correction at least halves it (at most
!> max_refine = 3); its steps are reported as the solve's iterations. A
!> matrix that is numerically singular leaves omega far above backward_tol
!> and the solve is refused, saying so.
module linear_solver
  use kinds, only: rp, ip, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use logger, only: logger_t
  use dist_vector, only: pnorm2
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use krylov, only: krylov_t, solve_info_t
  use fgmres, only: fgmres_t
  use cg, only: cg_t
  use mumps_solver, only: mumps_solver_t
  use scaled_system, only: scaled_operator_t, scaled_precon_t
  use linear_system, only: linear_system_t
  implicit none
  private

  public :: linear_solver_t, solver_methods, scale_matrix

  !> The methods init knows, for error messages.
  character(len=*), parameter :: solver_methods = "'fgmres', 'cg', 'mumps'"
  !> The floor of the absolute tolerance, relative to rtol times the first
  !> right-hand side of a step.
  real(rp), parameter :: floor_factor = 1.0e-4_rp
  !> A direct solve is accepted when its componentwise backward error is at
  !> most backward_tol; iterative refinement aims at refine_target, with at
  !> most max_refine corrections (module header).
  real(rp), parameter :: backward_tol = 1.0e-10_rp, refine_target = 1.0e-14_rp
  integer, parameter :: max_refine = 3

  type :: linear_solver_t
    character(len=name_len) :: method = ''
    type(parallel_comm_t) :: comm
    real(rp) :: rtol = 1.0e-8_rp, atol = 0.0_rp
    class(krylov_t), allocatable :: krylov
    type(mumps_solver_t) :: direct
    type(csr_matrix_t) :: mono                 !< the assembled copy of a block operator (direct)
    type(index_map_t) :: mono_map
    logical :: fact_is_mono = .true.           !< MUMPS factorized mono (else the unscaled operator, fact)
    type(csr_matrix_t), pointer :: fact => null()
    logical :: factored = .false.
    type(scaled_operator_t) :: sop
    type(scaled_precon_t) :: spc
    real(rp) :: first_norm = -1.0_rp           !< norm of the first right-hand side of the step (< 0: none yet)
    real(rp) :: t_factor = 0.0_rp              !< seconds of the factorization made by the last solve (0: none)
    integer :: n_factor = 0                    !< factorizations so far
  contains
    procedure :: init
    procedure :: is_direct
    procedure :: begin_step
    procedure :: drop_floor
    procedure :: set_rtol
    procedure :: solve
    procedure :: describe
    procedure :: report_factorization
    procedure :: free
    procedure, private :: solve_direct, solve_krylov, factorize
  end type linear_solver_t

contains

  !> Choose the method by name: 'fgmres' (restart: its cycle length), 'cg'
  !> or 'mumps'. rtol, atol: tolerances of the (scaled) residual norm,
  !> relative to ||b|| and absolute; max_iter: iteration cap. status names
  !> the valid methods when method is unknown. Nothing is built yet.
  subroutine init(self, comm, method, rtol, atol, max_iter, restart, status)
    class(linear_solver_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: method
    real(rp), intent(in) :: rtol, atol
    integer, intent(in) :: max_iter, restart
    type(error_status_t), intent(inout) :: status
    call self%free()
    self%comm = comm
    self%method = method
    self%rtol = rtol
    self%atol = atol
    select case (method)
    case ('fgmres')
      allocate(fgmres_t :: self%krylov)
      select type (k => self%krylov)
      type is (fgmres_t)
        call k%init(comm, rtol, atol, max_iter, restart, status)
      end select
    case ('cg')
      allocate(cg_t :: self%krylov)
      select type (k => self%krylov)
      type is (cg_t)
        call k%init(comm, rtol, atol, max_iter, status)
      end select
    case ('mumps')
    case default
      call status%set("linear solver: unknown method '"//trim(method)//"' (valid: "//solver_methods//")")
    end select
  end subroutine init

  logical function is_direct(self)
    class(linear_solver_t), intent(in) :: self
    is_direct = self%method == 'mumps'
  end function is_direct

  !> A new step (or sub-step) begins: the next right-hand side sets the
  !> tolerance floor.
  subroutine begin_step(self)
    class(linear_solver_t), intent(inout) :: self
    self%first_norm = -1.0_rp
  end subroutine begin_step

  !> No tolerance floor for the rest of the step: the Newton loop asks for
  !> it when a Krylov solve stopped at once below the floor while a field's
  !> physical residual is still above its tolerance (the scaled norm of the
  !> floor weighs the fields by their diagonals, and a field of small
  !> entries can sit below it unresolved).
  subroutine drop_floor(self)
    class(linear_solver_t), intent(inout) :: self
    self%first_norm = 0.0_rp
  end subroutine drop_floor

  !> The relative tolerance of the next Krylov solves (the tolerance floor
  !> stays that of init's rtol); no effect on a direct solve.
  subroutine set_rtol(self, rtol)
    class(linear_solver_t), intent(inout) :: self
    real(rp), intent(in) :: rtol
    if (allocated(self%krylov)) self%krylov%rtol = rtol
  end subroutine set_rtol

  !> Solve sys (sys%x: initial guess in, solution out). info reports the
  !> iterations, the (scaled, for Krylov) relative residual, the residual
  !> history and why it failed. Collective.
  subroutine solve(self, sys, info)
    class(linear_solver_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    type(solve_info_t), intent(out) :: info
    self%t_factor = 0.0_rp
    if (self%is_direct()) then
      call self%solve_direct(sys, info)
    else
      call self%solve_krylov(sys, info)
    end if
  end subroutine solve

  !> Krylov on the (scaled) system with the physics' preconditioner.
  subroutine solve_krylov(self, sys, info)
    class(linear_solver_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    type(solve_info_t), intent(out) :: info
    real(rp), allocatable :: y(:), bs(:)
    if (.not. associated(sys%m)) error stop 'linear_solver: a Krylov solve needs a preconditioner'
    if (associated(sys%d)) then
      bs = sys%d * sys%b
      call set_floor(self, pnorm2(self%comm, bs))
      y = sys%x / sys%d
      call self%sop%init(sys%a, sys%d)
      call self%spc%init(sys%m, sys%d)
      call self%krylov%solve(self%sop, self%spc, bs, y, info)
      sys%x = sys%d * y
    else
      call set_floor(self, pnorm2(self%comm, sys%b))
      call self%krylov%solve(sys%a, sys%m, sys%b, sys%x, info)
    end if
  end subroutine solve_krylov

  !> The absolute tolerance of the Krylov method for a right-hand side of
  !> norm bnorm: the deck's atol, raised to the step's floor.
  subroutine set_floor(self, bnorm)
    type(linear_solver_t), intent(inout) :: self
    real(rp), intent(in) :: bnorm
    if (self%first_norm < 0.0_rp) self%first_norm = bnorm
    self%krylov%atol = max(self%atol, floor_factor * self%rtol * self%first_norm)
  end subroutine set_floor

  !> MUMPS: factorize when the operator changed, solve, refine, judge the
  !> result by its componentwise backward error (module header).
  subroutine solve_direct(self, sys, info)
    class(linear_solver_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    type(solve_info_t), intent(out) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: r(:), bs(:), y(:)
    real(rp) :: t0, bnorm, rnorm
    info%iterations = 0
    if (sys%changed .or. .not. self%factored) call self%factorize(sys, status)
    t0 = wall_time()
    if (status%ok()) then
      ! the system MUMPS factorized: D A D y = D b, x = D y (or A x = b)
      bs = sys%b
      if (associated(sys%d)) bs = sys%d * sys%b
      allocate(y(size(bs)))
      call self%direct%solve(bs, y, status)
      if (status%ok()) call refine(self, bs, y, info%iterations, info%backward0, info%backward, status)
      sys%x = y
      if (associated(sys%d)) sys%x = sys%d * y
    end if
    if (.not. status%ok()) then
      info%msg = status%msg
      info%rel_res = huge(1.0_rp)
      info%solve_time = wall_time() - t0
      return
    end if
    ! the relative residual for the log and the history, in the scaled norm
    ! when a scaling is given (an unscaled norm adds forces to volumes)
    allocate(r(size(sys%b)))
    call sys%a%apply(sys%x, r)
    r = sys%b - r
    if (associated(sys%d)) r = sys%d * r
    bnorm = pnorm2(self%comm, bs)
    rnorm = pnorm2(self%comm, r)
    if (self%first_norm < 0.0_rp) self%first_norm = bnorm
    info%res0 = bnorm
    info%rel_res = rnorm / max(bnorm, tiny(1.0_rp))
    info%converged = bnorm == 0.0_rp .or. info%backward <= backward_tol
    if (.not. info%converged) write(info%msg, '(a,es10.3,a,es10.3,a,es8.1,a)') &
      'the direct solve left a componentwise backward error of ', info%backward, ' (relative residual ', &
      info%rel_res, '; accepted up to ', backward_tol, '): the matrix is numerically singular or nearly so'
    allocate(info%history(0:0))
    info%history(0) = info%rel_res
    info%solve_time = wall_time() - t0
  end subroutine solve_direct

  !> Iterative refinement of y, a solution of fact y = bs (the matrix MUMPS
  !> factorized): while the componentwise backward error is above
  !> refine_target, up to max_refine corrections y += fact^-1 (bs - fact y),
  !> stopping when one does not halve it (the best y is kept). steps: the
  !> corrections kept; omega0, omega: the backward errors of MUMPS's y and
  !> of the returned one.
  !> Collective.
  subroutine refine(self, bs, y, steps, omega0, omega, status)
    type(linear_solver_t), intent(inout) :: self
    real(rp), intent(in) :: bs(:)
    real(rp), intent(inout) :: y(:)
    integer, intent(out) :: steps
    real(rp), intent(out) :: omega0, omega
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: r(:), dy(:), yt(:)
    real(rp) :: om
    integer :: k
    allocate(r(size(bs)), dy(size(bs)))
    steps = 0
    omega = factorized_error(self, bs, y, r)
    omega0 = omega
    do k = 1, max_refine
      if (omega <= refine_target) exit
      call self%direct%solve(r, dy, status)
      if (.not. status%ok()) return
      yt = y + dy
      om = factorized_error(self, bs, yt, dy)
      if (.not. (om <= 0.5_rp * omega)) exit
      y = yt
      r = dy
      omega = om
      steps = k
    end do
  end subroutine refine

  !> backward_error on the matrix MUMPS factorized.
  real(rp) function factorized_error(self, b, y, r) result(omega)
    type(linear_solver_t), intent(inout) :: self
    real(rp), intent(in) :: b(:), y(:)
    real(rp), intent(out) :: r(:)
    if (self%fact_is_mono) then
      omega = backward_error(self%mono, b, y, r)
    else
      omega = backward_error(self%fact, b, y, r)
    end if
  end function factorized_error

  !> The componentwise backward error of y as a solution of a y = b (Arioli,
  !> Demmel and Duff, SIAM J. Matrix Anal. Appl. 10 (1989) 165-190, as MUMPS
  !> reports it in RINFOG(7) + RINFOG(8)): omega1 = max |r_i| / (|a| |y| +
  !> |b|)_i over the rows where that denominator is not negligible, omega2 =
  !> max |r_i| / ((|a| |y|)_i + max_j |a_ij| ||y||_inf) over the others
  !> (negligible: below 1000 n eps (max_j |a_ij| ||y||_inf + |b_i|)). Both
  !> are invariant under diagonal scalings of the rows and columns. r gets
  !> the residual b - a y. Collective.
  real(rp) function backward_error(a, b, y, r) result(omega)
    type(csr_matrix_t), intent(inout) :: a
    real(rp), intent(in) :: b(:), y(:)
    real(rp), intent(out) :: r(:)
    real(rp), allocatable :: ay(:), amax(:)
    real(rp) :: yinf, tau, om(2), den
    integer(ip) :: i
    allocate(ay(a%n_rows), amax(a%n_rows))
    call a%apply(y, r)
    r(1:a%n_rows) = b(1:a%n_rows) - r(1:a%n_rows)
    call a%abs_apply(y, ay, amax)
    yinf = 0.0_rp
    if (a%n_rows > 0) yinf = maxval(abs(y(1:a%n_rows)))
    yinf = a%row_map%comm%max(yinf)
    om = 0.0_rp
    do i = 1, a%n_rows
      den = ay(i) + abs(b(i))
      tau = 1000.0_rp * real(a%row_map%n_global, rp) * epsilon(1.0_rp) * (amax(i) * yinf + abs(b(i)))
      if (den > tau) then
        om(1) = max(om(1), abs(r(i)) / den)
      else if (ay(i) + amax(i) * yinf > 0.0_rp) then
        om(2) = max(om(2), abs(r(i)) / (ay(i) + amax(i) * yinf))
      else if (r(i) /= 0.0_rp) then
        om(2) = huge(1.0_rp)
      end if
    end do
    omega = a%row_map%comm%max(om(1)) + a%row_map%comm%max(om(2))
  end function backward_error

  !> Analysis and factorization of sys%a (a block operator is assembled
  !> into one matrix first). Collective.
  subroutine factorize(self, sys, status)
    class(linear_solver_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    type(error_status_t), intent(inout) :: status
    real(rp) :: t0
    t0 = wall_time()
    call self%direct%free()
    self%factored = .false.
    select type (a => sys%a)
    type is (csr_matrix_t)
      if (associated(sys%d)) then
        call self%mono%free()
        self%mono = a
        self%mono%owned_col_map => null()        ! a's own, freed with a
        call scale_matrix(self%mono, sys%d)
        call self%direct%setup(self%mono, status, sys%symmetric)
        self%fact_is_mono = .true.
      else
        call self%direct%setup(a, status, sys%symmetric)
        self%fact => a
        self%fact_is_mono = .false.
      end if
    type is (block_matrix_t)
      call self%mono%free()
      call a%monolithic(self%mono_map, self%mono)
      if (associated(sys%d)) call scale_matrix(self%mono, sys%d)
      call self%direct%setup(self%mono, status, sys%symmetric)
      self%fact_is_mono = .true.
    class default
      call status%set('linear solver: MUMPS needs an assembled matrix or block matrix')
    end select
    self%factored = status%ok()
    if (self%factored) self%n_factor = self%n_factor + 1
    self%t_factor = wall_time() - t0
  end subroutine factorize

  !> a = D a D for the owned scaling d (the ghost columns' from their owners).
  !> Collective.
  subroutine scale_matrix(a, d)
    type(csr_matrix_t), intent(inout) :: a
    real(rp), intent(in) :: d(:)
    real(rp), allocatable :: dc(:)
    integer(ip) :: i, k
    if (a%col_map%n_owned /= a%n_rows) error stop 'linear_solver: a scaled direct solve needs a square matrix'
    allocate(dc(a%col_map%n_local()))
    dc = 0.0_rp
    dc(1:a%n_rows) = d(1:a%n_rows)
    call a%col_map%import(dc)
    do i = 1, a%n_rows
      do k = a%row_ptr(i), a%row_ptr(i + 1) - 1
        a%val(k) = d(i) * a%val(k) * dc(a%col(k))
      end do
    end do
  end subroutine scale_matrix

  !> Log the factors and memory of the factorization made by the last solve,
  !> if it made one (the first on the screen, later ones as details).
  subroutine report_factorization(self, log)
    class(linear_solver_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    if (.not. (self%factored .and. self%t_factor > 0.0_rp)) return
    if (self%n_factor == 1) then
      call log%info(self%direct%summary())
    else
      call log%detail(self%direct%summary())
    end if
  end subroutine report_factorization

  !> One line naming the method, for the log.
  function describe(self) result(s)
    class(linear_solver_t), intent(in) :: self
    character(len=:), allocatable :: s
    if (self%is_direct()) then
      s = 'MUMPS direct solver'
    else
      s = trim(self%krylov%name())
    end if
  end function describe

  subroutine free(self)
    class(linear_solver_t), intent(inout) :: self
    if (allocated(self%krylov)) deallocate(self%krylov)
    call self%direct%free()
    call self%mono%free()
    self%factored = .false.
    self%n_factor = 0
    self%first_norm = -1.0_rp
  end subroutine free
end module linear_solver
