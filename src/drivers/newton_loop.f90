!> The one Newton / active-set loop of every physics, and the one linear-
!> solve path it uses: for one (sub-)step, up to sim%max_newton iterations
!> of assemble -> linear system -> solve -> update, until the physics says
!> the step has converged. A linear physics (max_newton = 1) is one pass.
!>
!> A failure the driver may answer with a smaller step (the linear solver
!> did not converge, a NaN, a preconditioner that could not be built, the
!> iterations ran out) comes back as converged = .false. with a reason; an
!> error that a smaller step cannot mend (assembly, an update that failed)
!> comes back in status.
module newton_loop
  use kinds, only: rp, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use timer_set, only: timer_set_t
  use strings, only: itoa, rtoa
  use krylov, only: solve_info_t
  use linear_system, only: linear_system_t
  use linear_solver, only: linear_solver_t
  use elastic_reference, only: solve_elastic_reference
  use residual_history, only: residual_history_t
  use system_export, only: export_system
  use simulation, only: simulation_t, step_stats_t
  implicit none
  private

  public :: newton_loop_t

  !> A Krylov solve that ends within stall_factor times rtol is accepted
  !> with a warning (solve_linear).
  real(rp), parameter :: stall_factor = 10.0_rp

  type :: newton_loop_t
    type(linear_solver_t) :: ls
    type(linear_system_t) :: sys
    type(residual_history_t) :: history
    logical :: reference_done = .false.          !< the elastic reference solve was made
    character(len=path_len) :: out_base = ''     !< <out>/<prefix>: the stem of the exported systems' files
    logical :: export_first = .false.            !< export the next system to <out_base>_K.mtx, _rhs.mtx
    logical :: step_exported = .false.           !< &solver export_step's system was written
  contains
    procedure :: init
    procedure :: solve_step
    procedure :: check_export
    procedure :: free
    procedure, private :: solve_linear
  end type newton_loop_t

contains

  !> The linear solver of sim's &solver; the residual history file at
  !> history_path; out_base: <out>/<prefix>, the stem of the exported
  !> systems' files; export_first: export the first system (as assembled);
  !> keep_through: a restarted run keeps the history rows up to that step.
  subroutine init(self, comm, sim, history_path, out_base, export_first, status, keep_through)
    class(newton_loop_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    class(simulation_t), intent(in) :: sim
    character(len=*), intent(in) :: history_path, out_base
    logical, intent(in) :: export_first
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: keep_through
    associate (s => sim%solver)
      call self%ls%init(comm, s%method, s%rtol, s%atol, s%max_iter, s%restart, status)
      self%ls%direct%on_host = s%mumps_layout == 'host'
    end associate
    call self%history%open(comm, history_path, keep_through)
    self%out_base = out_base
    self%export_first = export_first
  end subroutine init

  !> Iterate step `step` (sub-step from sim's accepted state to time t,
  !> begun by sim%begin_step, of size dt) to convergence. stats accumulates
  !> the step's figures (over sub-steps too); timers the run's. When it
  !> fails, cut_helps says whether a smaller step would meet another
  !> problem: not when the first linear system failed and it does not
  !> depend on the step's size (a load step's Jacobian at its start, or the
  !> step at t = 0 of size 0): a cut would repeat that very system.
  !> Collective; converged, cut_helps, why and status are the same on every
  !> rank.
  subroutine solve_step(self, sim, log, timers, step, t, dt, stats, converged, cut_helps, why, status)
    class(newton_loop_t), intent(inout) :: self
    class(simulation_t), intent(inout), target :: sim
    type(logger_t), intent(inout) :: log
    type(timer_set_t), intent(inout) :: timers
    integer, intent(in) :: step
    real(rp), intent(in) :: t, dt
    type(step_stats_t), intent(inout) :: stats
    logical, intent(out) :: converged, cut_helps
    character(len=*), intent(out) :: why
    type(error_status_t), intent(inout) :: status
    real(rp) :: secs, ratio_before, ratio_prev, rtol
    integer :: it, its
    logical :: stalled
    converged = .false.
    cut_helps = .true.
    why = ''
    stalled = .false.
    its = -1
    ratio_before = huge(1.0_rp)
    ratio_prev = huge(1.0_rp)
    call self%ls%begin_step()
    ! with a residual test, one assembly more than solves: the residual of
    ! the last update is judged before the loop gives up
    do it = 1, sim%max_newton + merge(1, 0, sim%residual_test)
      call timers%start('assembly')
      call sim%assemble(status)
      call timers%stop('assembly', secs)
      stats%t_assembly = stats%t_assembly + secs
      call agree(sim%comm, status)
      if (.not. status%ok()) return
      if (sim%residual_test .and. it > 1) then
        call sim%check_residual(it - 1, log, converged, why)
        if (converged) exit
        ! a solve accepted near rtol must still move the Newton residual down
        if (stalled .and. .not. (sim%residual_ratio < ratio_before)) then
          why = 'the linear solver stalled near rtol and the Newton residual did not fall ('//trim(why)//')'
          return
        end if
        ratio_prev = ratio_before
        ratio_before = sim%residual_ratio
        if (it > sim%max_newton) exit
        ! a Krylov solve that stopped at once under the step's tolerance
        ! floor left the iterate as it was: solve the next one for its own
        ! digits
        if (its == 0 .and. .not. self%ls%is_direct()) call self%ls%drop_floor()
      end if
      rtol = solve_rtol(sim, it, self%ls%is_direct(), ratio_prev)
      call self%ls%set_rtol(rtol)
      sim%last_solve_rtol = rtol
      sim%newton_it = it
      call self%solve_linear(sim, log, timers, step, t, it, rtol, stats, its, stalled, why)
      if (len_trim(why) > 0) then
        cut_helps = it > 1 .or. (sim%transient .and. dt > 0.0_rp)
        return
      end if
      call sim%update(it, its, log, converged, why, status)
      stats%newton = stats%newton + 1
      call agree(sim%comm, status)
      if (.not. status%ok() .or. converged) return
    end do
    if (converged) return
    if (sim%max_newton > 1) why = 'the Newton / active-set loop did not converge in '//itoa(sim%max_newton)// &
      ' iterations ('//trim(why)//')'
  end subroutine solve_step

  !> The relative tolerance of the Krylov solve of Newton iteration it
  !> (ratio_prev: the residual ratio of the check before this iteration's,
  !> huge if none). With the physics' moving_rtol > 0: an iteration that
  !> may still move an active set solves to moving_rtol (its statuses are a
  !> guess, and digits beyond that decide nothing); once the statuses
  !> settled, with the physics' settled_forcing (not with the matrix's
  !> fluid, whose pressure error the residual does not bound; with the
  !> fractures' fluid its update test bounds it), Eisenstat and Walker's
  !> second forcing term (SIAM J. Sci.
  !> Comput. 17 (1996) 16: 0.9 (r_k / r_k-1)^2, r the residual_ratio of
  !> check_residual: the worst field's residual over its tolerance), but at
  !> least need_factor / r_k, which would take the worst field to
  !> need_factor times its tolerance were the step linear (the margin
  !> covers that field's share of the scaled residual the Krylov method
  !> measures), never looser than moving_rtol nor tighter than rtol.
  !> need_factor 0.1: HI24L medium and contact n = 40 took the same Newton
  !> iterations as with 1e-3 and 316 against 341, 41 against 45 FGMRES
  !> iterations (2026-12-03). A step without status updates (step 0 with
  !> the faults bonded) is not moving: one solve to rtol.
  !> Otherwise (and for a direct solve, which ignores it) the deck's rtol.
  real(rp) function solve_rtol(sim, it, direct, ratio_prev) result(rtol)
    class(simulation_t), intent(in) :: sim
    integer, intent(in) :: it
    logical, intent(in) :: direct
    real(rp), intent(in) :: ratio_prev
    real(rp), parameter :: ew_gamma = 0.9_rp, need_factor = 0.1_rp
    real(rp) :: eta, r
    rtol = sim%solver%rtol
    if (.not. (sim%moving_rtol > 0.0_rp) .or. direct) return
    if (sim%active_set_moving(it)) then
      rtol = max(rtol, sim%moving_rtol)
    else if (sim%settled_forcing .and. sim%residual_test .and. it > 1) then
      r = max(sim%residual_ratio, 1.0_rp)
      eta = 0.0_rp
      if (ratio_prev < huge(1.0_rp)) eta = ew_gamma * (r / max(ratio_prev, 1.0_rp))**2
      eta = max(eta, need_factor / r)
      rtol = max(rtol, min(sim%moving_rtol, eta))
    end if
  end function solve_rtol

  !> The linear system of iteration it: set up by the physics, exported or
  !> measured against the elastic reference if asked, solved in its
  !> iterations. why is set when the solve failed (empty otherwise).
  !> Collective.
  subroutine solve_linear(self, sim, log, timers, step, t, it, rtol, stats, its, stalled, why)
    class(newton_loop_t), intent(inout) :: self
    class(simulation_t), intent(inout), target :: sim
    type(logger_t), intent(inout) :: log
    type(timer_set_t), intent(inout) :: timers
    integer, intent(in) :: step, it
    real(rp), intent(in) :: t
    real(rp), intent(in) :: rtol                  !< the Krylov solve's relative tolerance
    type(step_stats_t), intent(inout) :: stats
    integer, intent(out) :: its                   !< iterations of the solve
    logical, intent(out) :: stalled               !< a Krylov solve stalled near rtol was accepted
    character(len=*), intent(out) :: why
    type(error_status_t) :: status
    type(solve_info_t) :: info
    character(len=path_len) :: base
    logical :: has_nan, exported
    integer :: i
    why = ''
    its = 0
    stalled = .false.
    exported = .false.
    call timers%start('preconditioner set-up')
    call sim%linear_system(self%ls%is_direct(), self%sys, log, status)
    call timers%stop('preconditioner set-up')
    do i = 1, self%sys%n_parts
      call timers%add('  '//trim(self%sys%part_name(i)), self%sys%part_time(i), self%sys%part_rise(i))
    end do
    stats%t_setup = stats%t_setup + self%sys%setup_time
    if (.not. status%ok()) then
      why = status%msg
      return
    end if
    if (self%export_first) then
      call export_system(sim%comm, self%sys, trim(self%out_base), status)
      if (status%ok()) call log%info('matrix and right-hand side written to '//trim(self%out_base)//'_K.mtx and '// &
                                     trim(self%out_base)//'_rhs.mtx')
      if (.not. status%ok()) call log%fatal(sim%comm, status%msg)
      self%export_first = .false.
    end if
    if (step == sim%solver%export_step .and. it == sim%solver%export_newton .and. .not. self%step_exported) then
      base = trim(self%out_base)//'_step'//itoa(step)//'_newton'//itoa(it)
      call export_system(sim%comm, self%sys, trim(base), status, scaled=.true.)
      if (.not. status%ok()) call log%fatal(sim%comm, status%msg)
      call log%info('step '//itoa(step)//', Newton iteration '//itoa(it)//': the linear system as the solver '// &
                    'sees it written to '//trim(base)//'_K.mtx, _rhs.mtx, _fields.mtx'// &
                    trim(merge(', _scaling.mtx', '              ', associated(self%sys%d))))
      self%step_exported = .true.
      exported = .true.
    end if
    if (sim%solver%elastic_reference .and. .not. self%reference_done .and. associated(self%sys%k_ref)) then
      call solve_elastic_reference(sim%comm, log, self%sys%k_ref, self%sys%b_ref, sim%solver%rtol, &
                                   sim%solver%max_iter, sim%amg, self%sys%m_ref)
      self%reference_done = .true.
    end if
    call self%ls%solve(self%sys, info)
    ! the summary keeps a direct solver's factorization apart from its solve
    call timers%add('linear solve', info%solve_time)
    if (self%ls%t_factor > 0.0_rp) call timers%add('factorization (direct solver)', self%ls%t_factor)
    call self%ls%report_factorization(log)
    stats%t_setup = stats%t_setup + self%ls%t_factor
    stats%t_solve = stats%t_solve + info%solve_time
    its = info%iterations
    ! the exported system's own figures, for a peer solving the same files
    if (exported) call log%info('step '//itoa(step)//', Newton iteration '//itoa(it)//' (exported): iterations '// &
      itoa(info%iterations)//', set-up '//trim(secs_text(self%sys%setup_time + self%ls%t_factor))//' s, solve '// &
      trim(secs_text(info%solve_time))//' s')
    stats%linear_its = stats%linear_its + info%iterations
    if (info%backward >= 0.0_rp) call log%detail('  direct solve: componentwise backward error '// &
      trim(rtoa(info%backward))//' after '//itoa(info%iterations)//' refinement step(s) ('// &
      trim(rtoa(info%backward0))//' before), relative residual '//trim(rtoa(info%rel_res)))
    stats%rel_res = info%rel_res
    if (allocated(info%history)) call self%history%write(step, t, it, info%history)
    has_nan = sim%comm%any_true(any(self%sys%x /= self%sys%x))
    if (has_nan) then
      why = 'the linear solver returned NaN: '//trim(info%msg)
    else if (.not. info%converged .and. .not. self%ls%is_direct() .and. info%rel_res <= stall_factor * rtol) then
      ! a stall a hair above rtol is no reason to cut the step: accepted,
      ! said, counted; the Newton loop checks that its residual still falls
      stalled = .true.
      stats%near_rtol = stats%near_rtol + 1
      call log%warn('step '//itoa(step)//', Newton iteration '//itoa(it)//': the linear solver stalled at a '// &
        'relative residual of '//trim(rtoa(info%rel_res))//', within '//itoa(nint(stall_factor))//'x of rtol = '// &
        trim(rtoa(rtol))//': accepted')
    else if (.not. info%converged) then
      if (sim%solver%fail_on_no_convergence) then
        why = 'the linear solver did not converge: '//trim(info%msg)
      else
        call log%warn('step '//itoa(step)//': the linear solver did not converge: '//trim(info%msg))
      end if
    end if
  end subroutine solve_linear

  !> A warning when &solver export_step named a step the run did not reach
  !> or an iteration its Newton loop did not make. Collective.
  subroutine check_export(self, sim, log)
    class(newton_loop_t), intent(in) :: self
    class(simulation_t), intent(in) :: sim
    type(logger_t), intent(inout) :: log
    if (sim%solver%export_step < 0 .or. self%step_exported) return
    call log%warn('&solver export_step = '//itoa(sim%solver%export_step)//', export_newton = '// &
                  itoa(sim%solver%export_newton)//': the run made no such linear system; nothing was exported')
  end subroutine check_export

  subroutine free(self)
    class(newton_loop_t), intent(inout) :: self
    call self%ls%free()
    call self%history%close()
    call self%sys%reset()
  end subroutine free

  !> Seconds as text with 3 decimals.
  function secs_text(x) result(t)
    real(rp), intent(in) :: x
    character(len=24) :: t
    write(t, '(f0.3)') x
    if (t(1:1) == '.') t = '0'//t(1:23)
  end function secs_text
end module newton_loop
