!> Driver of a frictional contact run (physics = 'contact'): quasi-static load
!> stepping; in every load step an active-set loop whose iterations are
!> Newton steps on the current statuses (stick, slip, open), each a block
!> solve; a step whose loop does not converge within max_newton iterations
!> is halved (max_cuts times) before the run stops with a report.
module contact_driver
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use timer_set, only: timer_set_t
  use strings, only: itoa, rtoa
  use deck, only: deck_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use material_config, only: material_config_t, read_materials
  use boundary_config, only: boundary_config_t, read_boundaries, load_histories
  use fault_config, only: fault_config_t, read_faults, load_fault_histories
  use solver_config, only: solver_config_t
  use contact_config, only: contact_config_t
  use amg_config, only: read_amg_config
  use amg_params, only: amg_params_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use contact, only: contact_t
  use contact_precon, only: contact_precon_t
  use scaled_system, only: scaled_operator_t, scaled_precon_t
  use fgmres, only: fgmres_t
  use krylov, only: solve_info_t
  use mumps_solver, only: mumps_solver_t
  use field_output, only: field_output_t
  use fracture_output, only: fracture_output_t
  use dist_vector, only: pnorm2
  use elastic_reference, only: solve_elastic_reference
  implicit none
  private

  public :: run_contact

  !> What the linear solves of one load step need.
  type :: contact_solver_t
    type(solver_config_t) :: scfg
    type(contact_config_t) :: ccfg
    type(amg_params_t) :: amg
    type(contact_precon_t) :: cpc
    type(scaled_operator_t) :: sop
    type(scaled_precon_t) :: spc
    type(fgmres_t) :: krylov
    type(mumps_solver_t) :: direct
    type(csr_matrix_t) :: mono
    type(index_map_t) :: mono_map
    integer :: linear_its = 0
    logical :: reference_done = .false.    !< the elastic reference solve was made
    real(rp) :: t_setup = 0.0_rp, t_solve = 0.0_rp
  end type contact_solver_t

contains

  !> Run the contact problem of deck d. Stops collectively on any error.
  subroutine run_contact(comm, log, d, run)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    type(mesh_config_t) :: mcfg
    type(material_config_t), allocatable :: mats(:)
    type(boundary_config_t), allocatable :: bcs(:)
    type(fault_config_t), allocatable :: faults(:)
    type(error_status_t) :: status
    type(dist_mesh_t), target :: mesh
    type(contact_t), target :: phys
    type(contact_solver_t), target :: ls
    type(field_output_t) :: out
    type(fracture_output_t) :: fout
    type(timer_set_t) :: timers
    real(rp), allocatable :: stress(:,:)
    real(rp) :: lf, lf_done, lf_target, dl
    integer :: step, cuts, newton_its, total_its, total_lin, c
    integer(gp) :: n(3)
    logical :: converged
    character(len=msg_len) :: line, why

    call timers%start('total')
    call mcfg%read(d, log, status)
    if (status%ok()) call read_materials(d, log, mats, status)
    if (status%ok()) call read_boundaries(d, log, bcs, status)
    if (status%ok()) then
      ls%scfg%precon = 'block'
      call ls%scfg%read(d, log, status)
    end if
    if (status%ok()) call read_amg_config(d, log, ls%amg, status)
    if (status%ok()) call ls%ccfg%read(d, log, status)
    if (status%ok()) call read_faults(d, log, faults, status, mcfg%source)
    if (status%ok()) call load_histories(comm, bcs, status)
    if (status%ok()) call load_fault_histories(comm, faults, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    if (ls%scfg%method == 'cg') call log%fatal(comm, "deck '"//trim(d%path)//"', group &solver, variable method: "// &
      "the contact system is a saddle point: use 'fgmres' or 'mumps'")
    if (size(faults) == 0) call log%fatal(comm, "deck '"//trim(d%path)//"': physics = 'contact' needs at least "// &
      "one &fault group")
    do c = 1, size(bcs)
      if (bcs(c)%type == 'pressure' .or. bcs(c)%type == 'flux') call log%fatal(comm, "&boundary on set '"// &
        trim(bcs(c)%set)//"': type = '"//trim(bcs(c)%type)//"' needs physics = 'biot' in &run")
    end do

    call timers%start('mesh')
    call build_mesh(comm, mcfg, log, mesh, status, faults)
    call timers%stop('mesh')
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call phys%init(mesh, mats, bcs, faults, ls%ccfg%stabilization == 'algebraic', &
                   ls%scfg%method /= 'mumps' .and. ls%ccfg%block /= 'classical', status)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call phys%mech%check_anchored(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call log%info('unknowns: u '//itoa(int(phys%mech%u%map%n_global))//', t '//itoa(int(phys%t%map%n_global))// &
      ' ('//itoa(int(mesh%iface_map%n_global))//' interface elements, '//itoa(int(comm%sum(phys%n_edges)))// &
      ' stabilization edge entries)')
    if (ls%scfg%method == 'mumps') then
      call log%info('linear solver: MUMPS (direct) at every Newton iteration')
    else
      call log%info('linear solver: FGMRES with the '//trim(ls%ccfg%block)//' block preconditioner')
      call ls%krylov%init(comm, ls%scfg%rtol, ls%scfg%atol, ls%scfg%max_iter, ls%scfg%restart, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if
    if (run%fields) then
      call out%init(mesh, run%out_dir, run%prefix, status)
      if (status%ok()) call fout%init(out, mesh, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if
    allocate(stress(6, mesh%cell_map%n_owned))

    lf_done = 0.0_rp
    do step = 1, run%n_steps
      lf_target = real(step, rp) / real(run%n_steps, rp)
      dl = lf_target - lf_done
      cuts = 0
      total_its = 0
      total_lin = 0
      ls%t_setup = 0.0_rp
      ls%t_solve = 0.0_rp
      do while (lf_done < lf_target * (1.0_rp - 1.0e-12_rp))
        lf = min(lf_done + dl, lf_target)
        call load_step(phys, mesh, ls, log, lf, converged, newton_its, why)
        total_its = total_its + newton_its
        total_lin = total_lin + ls%linear_its
        if (converged) then
          lf_done = lf
          cycle
        end if
        call phys%restore_step()
        call phys%take_solution(mesh)
        cuts = cuts + 1
        if (cuts > ls%ccfg%max_cuts) call log%fatal(comm, 'load step '//itoa(step)//' (load factor '// &
          trim(rtoa(lf))//'): the active-set / Newton loop did not converge in '//itoa(ls%ccfg%max_newton)// &
          ' iterations after '//itoa(ls%ccfg%max_cuts)//' step cuts: '//trim(why)// &
          ' (raise max_newton or max_cuts in &contact, or use more load steps in &time)')
        call log%warn('load step '//itoa(step)//': no convergence at load factor '//trim(rtoa(lf))//' ('// &
          trim(why)//'); the step is cut in half')
        dl = 0.5_rp * dl
      end do
      n = phys%count_states(mesh)
      write(line, '(a,i0,a,i0,a,f6.3,a,i3,a,i5,a,3(i0,a),a,es10.3,a,f8.3,a,f8.3,a)') 'load step ', step, '/', &
        run%n_steps, '  load ', lf_done, '  newton ', total_its, '  linear its ', total_lin, &
        '  stick/slip/open ', n(1), '/', n(2), '/', n(3), '', '  max slip ', max_slip(phys, mesh), ' m  setup ', &
        ls%t_setup, ' s  solve ', ls%t_solve, ' s'
      call log%info(line)
      if (run%fields .and. (mod(step, run%every) == 0 .or. step == 1 .or. step == run%n_steps)) then
        call timers%start('output')
        call phys%mech%cell_stress(mesh, phys%u, stress)
        call out%write_step(mesh, lf_done, phys%u, stress, status, keep_open=.true.)
        if (status%ok()) call fout%write_step(out, mesh, phys%trac, phys%jump, phys%state, phys%rot, status)
        if (status%ok()) call out%writer%end_step(status)
        call timers%stop('output')
        if (.not. status%ok()) call log%fatal(comm, status%msg)
      end if
    end do
    if (run%fields) call log%info('output: '//trim(out%path())//' (open it in ParaView; the faults are the '// &
      "grid 'fractures')")
    call timers%stop('total')
    call timers%report(comm, log)
    call ls%cpc%free()
    call ls%direct%free()
    call out%free()
    call phys%free()
    call mesh%free()
  end subroutine run_contact

  !> One load step to load factor lf: the active-set / Newton loop.
  !> converged is the same on every rank; why says what failed.
  subroutine load_step(phys, mesh, ls, log, lf, converged, its, why)
    type(contact_t), intent(inout), target :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(contact_solver_t), intent(inout), target :: ls
    type(logger_t), intent(inout) :: log
    real(rp), intent(in) :: lf
    logical, intent(out) :: converged
    integer, intent(out) :: its
    character(len=*), intent(out) :: why
    type(parallel_comm_t) :: comm
    type(error_status_t) :: status
    type(solve_info_t) :: info
    real(rp), allocatable :: dx(:), dsc(:), bs(:)
    real(rp) :: du, dt, tp0, b_first
    !> floor of the linear tolerance, relative to rtol times the first residual
    real(rp), parameter :: floor_factor = 1.0e-4_rp
    integer(gp) :: changed, n(3)
    integer(ip) :: u0, u1, t0, t1
    logical :: has_nan
    character(len=msg_len) :: line

    comm = mesh%comm
    converged = .false.
    why = ''
    b_first = 0.0_rp
    ls%linear_its = 0
    call phys%begin_step(lf)
    call phys%assemble_stiffness(mesh, lf)
    call phys%take_solution(mesh)
    call phys%sys%block_range(phys%bu, u0, u1)
    call phys%sys%block_range(phys%bt, t0, t1)
    allocate(dx(size(phys%x)), bs(size(phys%x)))
    do its = 1, ls%ccfg%max_newton
      call phys%assemble_newton(mesh)
      dx = 0.0_rp
      tp0 = wall_time()
      if (ls%scfg%method == 'mumps') then
        call ls%direct%free()
        call ls%mono%free()
        call phys%sys%monolithic(ls%mono_map, ls%mono)
        call ls%direct%setup(ls%mono, status)
        ls%t_setup = ls%t_setup + (wall_time() - tp0)
        tp0 = wall_time()
        if (status%ok()) call ls%direct%solve(phys%rhs, dx, status)
        info%iterations = 0
        info%converged = status%ok()
        info%msg = status%msg
        ls%t_solve = ls%t_solve + (wall_time() - tp0)
      else
        call ls%cpc%setup(phys, mesh, ls%ccfg, ls%amg, status)
        call agree(comm, status)
        if (.not. status%ok()) then
          why = 'preconditioner set-up: '//trim(status%msg)
          return
        end if
        call scaling(phys, mesh, dsc)
        call ls%sop%init(phys%sys, dsc)
        call ls%spc%init(ls%cpc%bp, dsc)
        ls%t_setup = ls%t_setup + (wall_time() - tp0)
        if (ls%scfg%elastic_reference .and. .not. ls%reference_done) then
          call solve_elastic_reference(comm, log, phys%sys%a(phys%bu, phys%bu), phys%rhs(u0:u1), ls%scfg, ls%amg)
          ls%reference_done = .true.
        end if
        ! The tolerance is relative to this iteration's residual, with a floor
        ! relative to the first one of the load step: the last Newton
        ! iterations have residuals near round-off, where rtol alone would ask
        ! FGMRES for digits that do not exist (it would stagnate).
        bs = dsc * phys%rhs
        if (its == 1) b_first = pnorm2(comm, bs)
        ls%krylov%atol = max(ls%scfg%atol, floor_factor * ls%scfg%rtol * b_first)
        call ls%krylov%solve(ls%sop, ls%spc, bs, dx, info)
        dx = dsc * dx
        ls%t_solve = ls%t_solve + info%solve_time
        ls%linear_its = ls%linear_its + info%iterations
      end if
      call agree(comm, status)
      has_nan = comm%any_true(any(dx /= dx))
      if (.not. info%converged .or. has_nan) then
        why = 'the linear solver did not converge: '//trim(info%msg)
        return
      end if
      phys%x = phys%x + dx
      call phys%take_solution(mesh)
      changed = phys%update_states(mesh, ls%ccfg%status_tol)
      du = pnorm2(comm, dx(u0:u1)) / max(pnorm2(comm, phys%x(u0:u1)), tiny(1.0_rp))
      dt = pnorm2(comm, dx(t0:t1)) / max(pnorm2(comm, phys%x(t0:t1)), tiny(1.0_rp))
      n = phys%count_states(mesh)
      write(line, '(a,i3,a,i5,a,es9.2,a,es9.2,a,i0,a,3(i0,a))') '  newton ', its, '  linear its ', info%iterations, &
        '  |du|/|u| ', du, '  |dt|/|t| ', dt, '  status changes ', changed, '  stick/slip/open ', &
        n(1), '/', n(2), '/', n(3), ''
      call log%detail(line)
      if (changed == 0 .and. (n(2) == 0 .or. (du <= ls%ccfg%newton_tol .and. dt <= ls%ccfg%newton_tol))) then
        converged = .true.
        return
      end if
      write(why, '(a,i0,a,es9.2,a,es9.2)') 'last iteration: ', changed, ' status changes, |du|/|u| ', du, &
        ', |dt|/|t| ', dt
    end do
    its = ls%ccfg%max_newton
  end subroutine load_step

  !> Symmetric scaling 1/sqrt of the diagonal of K (u rows) and of H~ (t rows).
  subroutine scaling(phys, mesh, d)
    type(contact_t), intent(inout) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable, intent(inout) :: d(:)
    integer(ip) :: u0, u1, t0, t1
    if (.not. allocated(d)) allocate(d(size(phys%x)))
    call phys%sys%block_range(phys%bu, u0, u1)
    call phys%sys%block_range(phys%bt, t0, t1)
    call phys%sys%a(phys%bu, phys%bu)%diagonal(d(u0:u1))
    call phys%ht_diagonal(mesh, 1.0_rp, .true., d(t0:t1))
    d = 1.0_rp / sqrt(abs(d))
  end subroutine scaling

  !> Largest tangential jump over the faults [m]. Collective.
  real(rp) function max_slip(phys, mesh)
    type(contact_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(parallel_comm_t) :: comm
    integer(ip) :: e
    comm = mesh%comm
    max_slip = 0.0_rp
    do e = 1, mesh%iface_map%n_owned
      max_slip = max(max_slip, norm2(phys%jump(2:3, e)))
    end do
    max_slip = comm%max(max_slip)
  end function max_slip
end module contact_driver
