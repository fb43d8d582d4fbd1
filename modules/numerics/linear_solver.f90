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
!> A direct solve is checked: its true relative residual ||b - A x|| / ||b||
!> (in the scaled norm ||D (b - A x)|| / ||D b|| when a scaling is given)
!> must be at most max(rtol, 1e-10) (or below the floor), else the solve is
!> reported as not converged.
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

  type :: linear_solver_t
    character(len=name_len) :: method = ''
    type(parallel_comm_t) :: comm
    real(rp) :: rtol = 1.0e-8_rp, atol = 0.0_rp
    class(krylov_t), allocatable :: krylov
    type(mumps_solver_t) :: direct
    type(csr_matrix_t) :: mono                 !< the assembled copy of a block operator (direct)
    type(index_map_t) :: mono_map
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

  !> MUMPS: factorize when the operator changed, solve, check the residual.
  subroutine solve_direct(self, sys, info)
    class(linear_solver_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    type(solve_info_t), intent(out) :: info
    type(error_status_t) :: status
    real(rp), allocatable :: r(:)
    real(rp) :: t0, bnorm, rnorm
    info%iterations = 0
    if (sys%changed .or. .not. self%factored) call self%factorize(sys, status)
    t0 = wall_time()
    if (status%ok()) then
      if (associated(sys%d)) then
        allocate(r(size(sys%b)))
        r = sys%d * sys%b
        call self%direct%solve(r, sys%x, status)
        sys%x = sys%d * sys%x
        deallocate(r)
      else
        call self%direct%solve(sys%b, sys%x, status)
      end if
    end if
    if (.not. status%ok()) then
      info%msg = status%msg
      info%rel_res = huge(1.0_rp)
      info%solve_time = wall_time() - t0
      return
    end if
    allocate(r(size(sys%b)))
    call sys%a%apply(sys%x, r)
    r = sys%b - r
    if (associated(sys%d)) then
      ! the scaled residual, as for the Krylov methods: every block counts
      ! (an unscaled norm adds forces to volumes)
      r = sys%d * r
      bnorm = pnorm2(self%comm, sys%d * sys%b)
    else
      bnorm = pnorm2(self%comm, sys%b)
    end if
    rnorm = pnorm2(self%comm, r)
    if (self%first_norm < 0.0_rp) self%first_norm = bnorm
    info%res0 = bnorm
    info%rel_res = rnorm / max(bnorm, tiny(1.0_rp))
    info%converged = bnorm == 0.0_rp .or. info%rel_res <= max(self%rtol, 1.0e-10_rp) .or. &
                     rnorm <= max(self%atol, floor_factor * self%rtol * self%first_norm)
    if (.not. info%converged) write(info%msg, '(a,es10.3)') 'the direct solve left a relative residual of ', &
      info%rel_res
    allocate(info%history(0:0))
    info%history(0) = info%rel_res
    info%solve_time = wall_time() - t0
  end subroutine solve_direct

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
      else
        call self%direct%setup(a, status, sys%symmetric)
      end if
    type is (block_matrix_t)
      call self%mono%free()
      call a%monolithic(self%mono_map, self%mono)
      if (associated(sys%d)) call scale_matrix(self%mono, sys%d)
      call self%direct%setup(self%mono, status, sys%symmetric)
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
