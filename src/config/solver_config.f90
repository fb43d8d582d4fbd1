!> Deck group &solver: the linear solver of each step.
!>
!>   method    'fgmres' (flexible GMRES, right preconditioned), 'cg' (for SPD
!>             systems with an SPD preconditioner) or 'mumps' (direct)     ['fgmres']
!>   precon    'boomeramg' (settings in &amg), 'jacobi', 'afsai' (our adaptive
!>             FSAI, settings in &afsai), 'hypre_fsai' (hypre's FSAI with the
!>             max_steps, step_size and tol of &afsai) or 'none'; for
!>             physics = 'biot': 'block' (the block preconditioner); biot,
!>             contact, fracture_flow and poromechanics_faults: 'block'
!>             (ours) or 'mgr' (hypre's MGR on the whole system, GEOS's
!>             strategies: the peer of the benchmarks, mgr_precon.f90)
!>                            ['boomeramg'; biot, contact and fracture_flow: 'block']
!>   decoupling biot: approximation of the decoupling factors F and G of the
!>             block framework: 'implicit' (products with the coupling blocks
!>             and the inner preconditioners) or 'explicit' (block aFSAI
!>             F ~ K^-1 Q and A^-1 B, settings in &block_fsai)           ['implicit']
!>   block_mode  biot: 'ldu' (F S^-1 G), 'ldu_cheap' (implicit only: Jacobi
!>             in G, one AMG cycle of K per iteration), 'lower' (S^-1 G),
!>             'upper' (F S^-1) or 'diagonal' (S^-1)      ['ldu_cheap'; explicit: 'ldu']
!>   k_precon  biot: preconditioner of K: 'boomeramg' or 'afsai' (&afsai) ['boomeramg']
!>   elastic_reference  biot, contact (iterative): also solve K u = f once
!>             with CG and BoomerAMG (the reference cost of the benchmarks;
!>             contact: at the first Newton iteration)                   [.false.]
!>   schur     biot: the pressure Schur complement: 'fixed_stress' (b^2 |c| /
!>             K_dr per cell for Q^T K^-1 Q) or 'algebraic' (Q^T diag(K)^-1 Q),
!>             both with the scaled Laplacian for B^T A^-1 B; or 'explicit'
!>             (P + F1^T K F1 + gamma F2^T A F2 from the explicit factors)
!>                                           ['fixed_stress'; explicit: 'explicit']
!>   schur_precon biot: preconditioner of the Schur complement: 'boomeramg'
!>             or 'afsai'                                                ['boomeramg']
!>   flux_precon biot: preconditioner of the Darcy mass block A:
!>             'jacobi' (its diagonal), 'boomeramg' or 'afsai'           ['jacobi']
!>   rtol      relative residual tolerance, 0 < rtol < 1                 [1e-8]
!>   atol      absolute residual tolerance, >= 0                         [0]
!>   max_iter  iteration cap, >= 1                                        [1000]
!>   restart   FGMRES restart length, >= 1                                [100]
!>   fail_on_no_convergence  a Krylov solve that does not converge fails the
!>             step (cut in half where the physics allows, else the run
!>             stops; a stall within 10x rtol is accepted with a warning);
!>             .false.: a warning, and the run goes on                [.true.]
!>   mumps_layout  where MUMPS factorizes (method = 'mumps'): 'host' (the
!>             matrix gathered on rank 0 and
!>             factorized there: repeats are bit-identical) or 'distributed'
!>             (over all ranks: memory spread, but the last digits change
!>             from run to run)                                         ['host']
!>   export_step  write the linear system of this step (0: the equilibrium
!>             step of a transient run) as the Krylov solver sees it
!>             (D A D and D b after the symmetric scaling D): MatrixMarket
!>             <out>/<prefix>_step<N>_newton<M>_K.mtx, _rhs.mtx, _scaling.mtx
!>             (D) and _fields.mtx (the block of every row); -1: none     [-1]
!>   export_newton  the Newton iteration of export_step to write, >= 1    [1]
module solver_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use strings, only: itoa, rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: solver_config_t

  type :: solver_config_t
    character(len=name_len) :: method = 'fgmres'
    character(len=name_len) :: precon = 'boomeramg'
    real(rp) :: rtol = 1.0e-8_rp
    real(rp) :: atol = 0.0_rp
    integer :: max_iter = 1000
    integer :: restart = 100
    logical :: fail_on_no_convergence = .true.
    character(len=name_len) :: decoupling = 'implicit'
    character(len=name_len) :: block_mode = 'ldu_cheap'
    character(len=name_len) :: k_precon = 'boomeramg'
    character(len=name_len) :: flux_precon = 'jacobi'
    logical :: elastic_reference = .false.
    character(len=name_len) :: schur = 'fixed_stress'
    character(len=name_len) :: schur_precon = 'boomeramg'
    character(len=name_len) :: mumps_layout = 'host'
    integer :: export_step = -1
    integer :: export_newton = 1
  contains
    procedure :: read => read_solver_config
    procedure :: describe => describe_solver_config
  end type solver_config_t

contains

  !> Read and check &solver (optional group).
  subroutine read_solver_config(self, d, log, status)
    class(solver_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: method, precon, block_mode, flux_precon, schur, decoupling, k_precon, schur_precon
    character(len=name_len) :: mumps_layout
    real(rp) :: rtol, atol
    integer :: max_iter, restart, ios, export_step, export_newton
    logical :: fail_on_no_convergence, elastic_reference
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /solver/ method, precon, rtol, atol, max_iter, restart, fail_on_no_convergence, block_mode, flux_precon, &
                     elastic_reference, schur, decoupling, k_precon, schur_precon, mumps_layout, export_step, &
                     export_newton

    method = self%method; precon = self%precon; rtol = self%rtol; atol = self%atol
    max_iter = self%max_iter; restart = self%restart; fail_on_no_convergence = self%fail_on_no_convergence
    block_mode = ''; flux_precon = self%flux_precon; elastic_reference = self%elastic_reference
    schur = ''; decoupling = self%decoupling; k_precon = self%k_precon; schur_precon = self%schur_precon
    mumps_layout = self%mumps_layout
    export_step = self%export_step; export_newton = self%export_newton
    if (d%count('solver') > 0) then
      call d%block('solver', 1, b)
      read(b, nml=solver, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('solver', 1, ios, msg, status)
        return
      end if
    end if
    if (method /= 'fgmres' .and. method /= 'cg' .and. method /= 'mumps') &
      call d%fail(status, 'solver', 1, 'method', "must be one of 'fgmres', 'cg', 'mumps' (got '"//trim(method)//"')")
    if (precon /= 'boomeramg' .and. precon /= 'jacobi' .and. precon /= 'afsai' .and. precon /= 'hypre_fsai' .and. &
        precon /= 'none' .and. precon /= 'block' .and. precon /= 'mgr') &
      call d%fail(status, 'solver', 1, 'precon', "must be one of 'boomeramg', 'jacobi', 'afsai', 'hypre_fsai', "// &
                  "'none', 'block', 'mgr' (got '"//trim(precon)//"')")
    if (decoupling /= 'implicit' .and. decoupling /= 'explicit') &
      call d%fail(status, 'solver', 1, 'decoupling', "must be 'implicit' or 'explicit' (got '"//trim(decoupling)//"')")
    if (block_mode == '') block_mode = merge('ldu_cheap', 'ldu      ', decoupling /= 'explicit')
    if (schur == '') schur = merge('fixed_stress', 'explicit    ', decoupling /= 'explicit')
    if (block_mode /= 'ldu' .and. block_mode /= 'lower' .and. block_mode /= 'upper' .and. block_mode /= 'diagonal' &
        .and. block_mode /= 'ldu_cheap') then
      call d%fail(status, 'solver', 1, 'block_mode', "must be one of 'ldu', 'ldu_cheap', 'lower', 'upper', "// &
                  "'diagonal' (got '"//trim(block_mode)//"')")
    else if (block_mode == 'ldu_cheap' .and. decoupling == 'explicit') then
      call d%fail(status, 'solver', 1, 'block_mode', "'ldu_cheap' is a variant of the implicit factors: "// &
                  "use decoupling = 'implicit' or another block_mode")
    end if
    if (schur /= 'fixed_stress' .and. schur /= 'algebraic' .and. schur /= 'explicit') then
      call d%fail(status, 'solver', 1, 'schur', "must be 'fixed_stress', 'algebraic' or 'explicit' (got '"// &
                  trim(schur)//"')")
    else if (schur == 'explicit' .and. decoupling /= 'explicit') then
      call d%fail(status, 'solver', 1, 'schur', "'explicit' is computed from the explicit factors: "// &
                  "it needs decoupling = 'explicit'")
    end if
    if (flux_precon /= 'jacobi' .and. flux_precon /= 'boomeramg' .and. flux_precon /= 'afsai') &
      call d%fail(status, 'solver', 1, 'flux_precon', "must be 'jacobi', 'boomeramg' or 'afsai' (got '"// &
                  trim(flux_precon)//"')")
    if (k_precon /= 'boomeramg' .and. k_precon /= 'afsai') &
      call d%fail(status, 'solver', 1, 'k_precon', "must be 'boomeramg' or 'afsai' (got '"//trim(k_precon)//"')")
    if (schur_precon /= 'boomeramg' .and. schur_precon /= 'afsai') &
      call d%fail(status, 'solver', 1, 'schur_precon', "must be 'boomeramg' or 'afsai' (got '"// &
                  trim(schur_precon)//"')")
    if (mumps_layout /= 'host' .and. mumps_layout /= 'distributed') &
      call d%fail(status, 'solver', 1, 'mumps_layout', "must be 'host' or 'distributed' (got '"// &
                  trim(mumps_layout)//"')")
    if (.not. (rtol > 0.0_rp .and. rtol < 1.0_rp)) &
      call d%fail(status, 'solver', 1, 'rtol', 'must lie in (0, 1) (got '//rtoa(rtol)//')')
    if (.not. (atol >= 0.0_rp)) call d%fail(status, 'solver', 1, 'atol', 'must be >= 0 (got '//rtoa(atol)//')')
    if (max_iter < 1) call d%fail(status, 'solver', 1, 'max_iter', 'must be at least 1 (got '//itoa(max_iter)//')')
    if (restart < 1) call d%fail(status, 'solver', 1, 'restart', 'must be at least 1 (got '//itoa(restart)//')')
    if (export_step < -1) call d%fail(status, 'solver', 1, 'export_step', &
      'must be a step number >= 0, or -1 for none (got '//itoa(export_step)//')')
    if (export_newton < 1) call d%fail(status, 'solver', 1, 'export_newton', &
      'must be at least 1 (got '//itoa(export_newton)//')')
    if (.not. status%ok()) return
    self%export_step = export_step
    self%export_newton = export_newton
    self%method = method
    self%precon = precon
    self%rtol = rtol
    self%atol = atol
    self%max_iter = max_iter
    self%restart = restart
    self%fail_on_no_convergence = fail_on_no_convergence
    self%block_mode = block_mode
    self%flux_precon = flux_precon
    self%elastic_reference = elastic_reference
    self%schur = schur
    self%decoupling = decoupling
    self%k_precon = k_precon
    self%schur_precon = schur_precon
    self%mumps_layout = mumps_layout
  end subroutine read_solver_config

  !> The resolved &solver group (defaults resolved for the physics).
  subroutine describe_solver_config(self, g)
    class(solver_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('solver', "the linear solver of each Newton iteration and the block preconditioner's parts")
    call g%add('method', self%method, '-', "Krylov method, or the direct solver ('cg': elasticity only)", &
               "'fgmres', 'cg' or 'mumps'")
    call g%add('precon', self%precon, '-', "preconditioner: 'block' (ours) for biot, contact, fracture_flow "// &
               "and poromechanics_faults, 'mgr' (hypre's MGR) for the same four, the others for elasticity", &
               "'boomeramg', 'jacobi', 'afsai', 'hypre_fsai', 'none', 'block' or 'mgr'")
    call g%add('rtol', self%rtol, '-', 'relative residual tolerance (of the scaled system where the physics '// &
               'scales it)', '(0, 1)')
    call g%add('atol', self%atol, '-', 'absolute residual tolerance', '>= 0')
    call g%add('max_iter', self%max_iter, '-', 'iteration cap', '>= 1')
    call g%add('restart', self%restart, '-', 'FGMRES restart length', '>= 1')
    call g%add('fail_on_no_convergence', self%fail_on_no_convergence, '-', 'a solve that does not converge '// &
               'fails the step (which is then cut, or stops the run)')
    call g%add('decoupling', self%decoupling, '-', 'biot: decoupling factors F, G of the block preconditioner: '// &
               'implicit (products with the coupling blocks) or explicit (block aFSAI, &block_fsai)', &
               "'implicit' or 'explicit'")
    call g%add('block_mode', self%block_mode, '-', "biot: which factors are applied ('ldu_cheap': Jacobi in G, "// &
               "one AMG cycle of K per iteration; explicit: default 'ldu')", &
               "'ldu', 'ldu_cheap' (implicit only), 'lower', 'upper' or 'diagonal'")
    call g%add('k_precon', self%k_precon, '-', 'biot: preconditioner of K', "'boomeramg' or 'afsai'")
    call g%add('flux_precon', self%flux_precon, '-', 'biot: preconditioner of the Darcy mass block A', &
               "'jacobi', 'boomeramg' or 'afsai'")
    call g%add('elastic_reference', self%elastic_reference, '-', 'biot, contact: also solve K u = f once with '// &
               'CG + BoomerAMG and log its cost (the benchmarks'' reference)')
    call g%add('schur', self%schur, '-', "biot: the pressure Schur complement: fixed stress or Q^T diag(K)^-1 Q, "// &
               "each + the scaled Laplacian, or explicit from the factors (explicit: default 'explicit')", &
               "'fixed_stress', 'algebraic' or 'explicit' (explicit decoupling only)")
    call g%add('schur_precon', self%schur_precon, '-', 'biot: preconditioner of the Schur complement', &
               "'boomeramg' or 'afsai'")
    call g%add('mumps_layout', self%mumps_layout, '-', "method = 'mumps': 'host' (rank 0 factorizes: "// &
               "bit-identical repeats) or 'distributed' (over all ranks: memory spread, last digits vary)", &
               "'host' or 'distributed'")
    call g%add('export_step', self%export_step, '-', 'write the linear system of this step (0: the equilibrium '// &
               'step) as the Krylov solver sees it, MatrixMarket (-1: none)', '>= -1')
    call g%add('export_newton', self%export_newton, '-', 'the Newton iteration of export_step to write', '>= 1')
  end subroutine describe_solver_config
end module solver_config
