!> Driver of a three-field Biot run: an undrained step at t = 0 (optional),
!> then implicit Euler steps to t_end, each an assembly of the block system,
!> a solve (FGMRES + the block preconditioner, or MUMPS) and an output.
!>
!> Set-up cost is split as in the seed: the dt-independent part (AMG of K and
!> the Darcy mass block, once) and the dt-dependent part (the Schur
!> approximation and its AMG, redone when dt changes).
module biot_driver
  use kinds, only: rp, ip, gp, msg_len, path_len
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
  use solver_config, only: solver_config_t
  use amg_config, only: read_amg_config
  use biot_config, only: biot_config_t
  use source_config, only: source_config_t, read_sources
  use amg_params, only: amg_params_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use poromechanics, only: poromechanics_t, iu, iq, ipr
  use krylov, only: solve_info_t
  use fgmres, only: fgmres_t
  use precon, only: precon_t
  use jacobi_precon, only: jacobi_precon_t
  use mumps_solver, only: mumps_solver_t
  use block_precon, only: block_precon_t
  use biot_precon, only: biot_precon_t
  use fsai_config, only: fsai_config_t
  use scaled_system, only: scaled_operator_t, scaled_precon_t
  use dist_vector, only: pnorm2, pmax_abs
  use xdmf_writer, only: xdmf_writer_t
  use elastic_reference, only: solve_elastic_reference
  implicit none
  private

  public :: run_biot

contains

  !> Run the poromechanics problem of deck d. Stops collectively on any error.
  subroutine run_biot(comm, log, d, run)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    type(mesh_config_t) :: mcfg
    type(material_config_t), allocatable :: mats(:)
    type(boundary_config_t), allocatable :: bcs(:)
    type(source_config_t), allocatable :: srcs(:)
    type(solver_config_t) :: scfg
    type(biot_config_t) :: bcfg
    type(amg_params_t) :: amg, amg_s
    type(error_status_t) :: status
    type(dist_mesh_t), target :: mesh
    type(poromechanics_t), target :: phys
    type(fsai_config_t) :: fcfg
    type(biot_precon_t), target :: bpc
    type(scaled_operator_t) :: sop
    type(scaled_precon_t) :: spc
    real(rp), allocatable :: dscale(:), y(:), b_scaled(:)
    type(fgmres_t) :: krylov
    type(mumps_solver_t) :: direct
    type(csr_matrix_t) :: mono
    type(index_map_t), target :: mono_map
    type(timer_set_t) :: timers
    type(solve_info_t) :: info
    type(xdmf_writer_t) :: out
    real(rp) :: t, dt, dt_used, t_p1, t_p2, t0
    integer :: step
    logical :: setup_done, has_nan
    character(len=msg_len) :: line
    integer :: hist_unit, k, ios
    integer(ip) :: u0, u1

    call timers%start('total')
    call mcfg%read(d, log, status)
    if (status%ok()) call read_materials(d, log, mats, status)
    if (status%ok()) call read_boundaries(d, log, bcs, status)
    if (status%ok()) then
      scfg%precon = 'block'
      call scfg%read(d, log, status)
    end if
    if (status%ok()) call read_amg_config(d, log, amg, status)
    if (status%ok()) call fcfg%read(d, log, status)
    if (status%ok()) call bcfg%read(d, log, status)
    if (status%ok()) call load_histories(comm, bcs, status)
    if (status%ok()) call read_sources(d, log, srcs, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    if (d%count('fault') > 0) call log%fatal(comm, "deck '"//trim(d%path)//"': &fault groups need "// &
      "physics = 'contact' in &run")
    if (scfg%method == 'cg') call log%fatal(comm, "deck '"//trim(d%path)//"', group &solver, variable method: "// &
      "the Biot system is not symmetric positive definite: use 'fgmres' or 'mumps'")
    if (scfg%method == 'fgmres' .and. scfg%precon /= 'block') call log%fatal(comm, "deck '"//trim(d%path)// &
      "', group &solver, variable precon: physics = 'biot' with fgmres needs precon = 'block'")

    call timers%start('mesh')
    call build_mesh(comm, mcfg, log, mesh, status)
    call timers%stop('mesh')
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call phys%init(mesh, mats, bcs, srcs, bcfg%beta(), status)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call log%info('unknowns: u '//itoa(int(phys%mech%u%map%n_global))//', q '//itoa(int(phys%qd%map%n_global))// &
                  ', p '//itoa(int(phys%pd%map%n_global))//', total '// &
                  itoa(int(phys%mech%u%map%n_global + phys%qd%map%n_global + phys%pd%map%n_global)))

    if (run%fields) then
      call open_output(out, mesh, run, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if

    ! residual histories of every solve, for postproc/plot_convergence.py
    hist_unit = 0
    if (comm%is_root()) then
      open(newunit=hist_unit, file=trim(run%out_dir)//'/'//trim(run%prefix)//'_residuals.csv', &
           status='replace', action='write', iostat=ios)
      if (ios == 0) write(hist_unit, '(a)') 'step,time,iteration,relative_residual'
    end if
    amg_s = amg
    amg_s%num_functions = 1
    amg_s%strong_threshold = 0.25_rp
    call krylov%init(comm, scfg%rtol, scfg%atol, scfg%max_iter, scfg%restart, status)
    t = 0.0_rp
    dt = run%dt
    dt_used = -1.0_rp
    setup_done = .false.
    step = 0
    if (.not. run%undrained) step = 1
    do
      if (step == 0) then
        dt = 0.0_rp
      else
        if (t >= run%t_end * (1.0_rp - 1.0e-12_rp)) exit
        if (allocated(run%times)) then
          dt = run%times(step) - t
        else
          dt = min(run%dt * run%dt_growth**(step - 1), run%dt_max, run%t_end - t)
        end if
      end if
      call timers%start('assembly')
      call phys%assemble(mesh, t + dt, dt, status)
      call timers%stop('assembly')
      call agree(comm, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)

      ! preconditioner / factorization
      t_p1 = 0.0_rp
      t_p2 = 0.0_rp
      if (scfg%method == 'mumps') then
        t0 = wall_time()
        call direct%free()
        call mono%free()
        call phys%sys%monolithic(mono_map, mono)
        call direct%setup(mono, status)
        t_p1 = wall_time() - t0
      else
        if (.not. setup_done) then
          call bpc%setup_fixed(phys, mesh, scfg, fcfg, amg, amg_s, status)
          call agree(comm, status)
          if (.not. status%ok()) call log%fatal(comm, 'preconditioner set-up: '//trim(status%msg))
          setup_done = .true.
          t_p1 = bpc%t_p1
          if (bpc%explicit) call log%info('explicit decoupling factors: ||K F1 - Q||/||Q|| '// &
            trim(rtoa(bpc%resid_f(1)))//', ||A F2 - B||/||B|| '//trim(rtoa(bpc%resid_f(2))))
        end if
        if (dt /= dt_used) then
          call bpc%setup_dt(phys, mesh, dt, status)
          call agree(comm, status)
          if (.not. status%ok()) call log%fatal(comm, 'preconditioner set-up: '//trim(status%msg))
          t_p2 = bpc%t_p2
          if (bpc%nnz_fixed + bpc%nnz_dt > 0) then
            line = 'block preconditioner '//trim(bpc%bp%name())//': density mu '//trim(rtoa(bpc%density()))// &
              ' (stored non-zeros '//itoa(int(bpc%nnz_fixed + bpc%nnz_dt))//' / '//itoa(int(bpc%nnz_matrix))//')'
            if (dt_used < 0.0_rp) then
              call log%info(line)
            else
              call log%detail(line)
            end if
          end if
          dt_used = dt
          call scaling(phys, bpc%s, dscale)
          call sop%init(phys%sys, dscale)
          call spc%init(bpc%bp, dscale)
        end if
      end if
      call agree(comm, status)
      if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(step)//': '//trim(status%msg))

      if (scfg%elastic_reference .and. t_p1 > 0.0_rp .and. scfg%method /= 'mumps') then
        call phys%sys%block_range(iu, u0, u1)
        call solve_elastic_reference(comm, log, phys%sys%a(iu, iu), phys%rhs(u0:u1), scfg, amg, bpc%bp%s(iu)%p)
      end if

      ! solve from the previous state
      phys%x = phys%x_old
      call timers%start('solve')
      if (scfg%method == 'mumps') then
        t0 = wall_time()
        call direct%solve(phys%rhs, phys%x, status)
        info%iterations = 0
        info%solve_time = wall_time() - t0
        info%converged = status%ok()
        info%rel_res = residual_norm(phys)
        info%msg = status%msg
      else
        ! solve the scaled system (D A D) y = D b, x = D y
        y = phys%x / dscale
        b_scaled = dscale * phys%rhs
        call krylov%solve(sop, spc, b_scaled, y, info)
        phys%x = dscale * y
      end if
      call timers%stop('solve')
      t = t + dt
      write(line, '(a,i4,a,es10.3,a,es10.3,a,i4,a,es9.2,a,es9.2,a,f8.3,a,f8.3,a,f8.3,a)') 'step ', step, '  t ', t, &
        '  dt ', dt, '  iterations ', info%iterations, '  rel. residual ', info%rel_res, &
        '  mass balance ', mass_balance(phys), &
        '  setup(dt-indep.) ', t_p1, ' s  setup(dt) ', t_p2, ' s  solve ', info%solve_time, ' s'
      call log%info(line)
      if (comm%is_root() .and. allocated(info%history)) then
        do k = 0, info%iterations
          write(hist_unit, '(i0,a,es16.8,a,i0,a,es16.8)', iostat=ios) step, ',', t, ',', k, ',', info%history(k)
        end do
        flush(hist_unit)
      end if
      has_nan = comm%any_true(any(phys%x /= phys%x))
      if (.not. info%converged .or. has_nan) then
        if (scfg%fail_on_no_convergence .or. has_nan) &
          call log%fatal(comm, 'step '//itoa(step)//': the linear solver did not converge: '//trim(info%msg))
        call log%warn('step '//itoa(step)//': the linear solver did not converge: '//trim(info%msg))
      end if
      if (run%fields .and. (mod(step, run%every) == 0 .or. step <= 1 .or. &
          t >= run%t_end * (1.0_rp - 1.0e-12_rp))) then
        call timers%start('output')
        call write_fields(out, mesh, phys, t, status)
        call timers%stop('output')
        if (.not. status%ok()) call log%fatal(comm, status%msg)
      end if
      phys%x_old = phys%x
      step = step + 1
    end do
    if (comm%is_root()) close(hist_unit)
    if (run%fields) call log%info('output: '//trim(out%xdmf_path())//' (open it in ParaView)')
    call log%info('residual histories: '//trim(run%out_dir)//'/'//trim(run%prefix)//'_residuals.csv')
    call timers%stop('total')
    call timers%report(comm, log)
    call bpc%free()
    call direct%free()
    call out%free()
    call phys%free()
    call mesh%free()
  end subroutine run_biot

  !> Scaling of the rows and columns of the block system: 1/sqrt of the
  !> diagonal of K and A, and of the Schur approximation s for the pressure
  !> (whose own diagonal vanishes for incompressible constituents).
  subroutine scaling(phys, s, d)
    type(poromechanics_t), intent(inout) :: phys
    type(csr_matrix_t), intent(in) :: s
    real(rp), allocatable, intent(inout) :: d(:)
    integer(ip) :: u0, u1, q0, q1, p0, p1
    if (.not. allocated(d)) allocate(d(size(phys%rhs)))
    call phys%sys%block_range(iu, u0, u1)
    call phys%sys%block_range(iq, q0, q1)
    call phys%sys%block_range(ipr, p0, p1)
    call phys%sys%a(iu, iu)%diagonal(d(u0:u1))
    call phys%sys%a(iq, iq)%diagonal(d(q0:q1))
    call s%diagonal(d(p0:p1))
    d = 1.0_rp / sqrt(abs(d))
  end subroutine scaling

  !> Local mass conservation of the step: the largest cell residual of the
  !> mass balance rows, relative to the largest sum of the magnitudes of a
  !> cell's terms (volume change, storage, net outflow). Collective.
  real(rp) function mass_balance(phys)
    type(poromechanics_t), intent(inout) :: phys
    real(rp), allocatable :: r(:), t1(:), t2(:), t3(:)
    integer(ip) :: u0, u1, q0, q1, p0, p1
    type(parallel_comm_t) :: comm
    real(rp) :: scale
    comm = phys%mech%u%map%comm
    call phys%sys%block_range(iu, u0, u1)
    call phys%sys%block_range(iq, q0, q1)
    call phys%sys%block_range(ipr, p0, p1)
    allocate(r(size(phys%rhs)), t1(p1 - p0 + 1), t2(p1 - p0 + 1), t3(p1 - p0 + 1))
    call phys%sys%apply(phys%x, r)
    r = phys%rhs - r
    call phys%sys%apply_block(ipr, iu, phys%x(u0:u1) - phys%x_old(u0:u1), t1)
    call phys%sys%apply_block(ipr, iq, phys%x(q0:q1), t2)
    call phys%sys%apply_block(ipr, ipr, phys%x(p0:p1) - phys%x_old(p0:p1), t3)
    scale = 0.0_rp
    if (p1 >= p0) scale = maxval(abs(t1) + abs(t2) + abs(t3))
    scale = comm%max(scale)
    mass_balance = 0.0_rp
    if (p1 >= p0) mass_balance = maxval(abs(r(p0:p1)))
    mass_balance = comm%max(mass_balance) / max(scale, tiny(1.0_rp))
  end function mass_balance

  !> ||b - A x|| / ||b|| of the current state.
  real(rp) function residual_norm(phys)
    type(poromechanics_t), intent(inout) :: phys
    real(rp), allocatable :: r(:)
    real(rp) :: bn
    type(parallel_comm_t) :: comm
    allocate(r(size(phys%rhs)))
    call phys%sys%apply(phys%x, r)
    r = phys%rhs - r
    comm = phys%mech%u%map%comm
    bn = pnorm2(comm, phys%rhs)
    residual_norm = pnorm2(comm, r) / max(bn, tiny(1.0_rp))
  end function residual_norm

  subroutine open_output(out, mesh, run, status)
    type(xdmf_writer_t), intent(inout) :: out
    type(dist_mesh_t), intent(in) :: mesh
    type(run_config_t), intent(in) :: run
    type(error_status_t), intent(inout) :: status
    integer(gp), allocatable :: conn(:,:)
    integer(ip) :: c, a
    allocate(conn(8, mesh%cell_map%n_owned))
    do c = 1, mesh%cell_map%n_owned
      do a = 1, 8
        conn(a, c) = mesh%node_map%global_id(mesh%cell_nodes(a, c))
      end do
    end do
    call out%init(mesh%comm, run%out_dir, run%prefix, mesh%n_nodes_global, mesh%node_map%first, &
                  mesh%coords(:, 1:mesh%node_map%n_owned), mesh%n_cells_global, mesh%cell_map%first, conn, status)
  end subroutine open_output

  !> Fields at time t: displacement [m], pressure [Pa], Darcy velocity [m/s]
  !> and total stress [Pa] (Tensor6 xx xy xz yy yz zz, tension positive) per cell.
  subroutine write_fields(out, mesh, phys, t, status)
    type(xdmf_writer_t), intent(inout) :: out
    type(dist_mesh_t), intent(in) :: mesh
    type(poromechanics_t), intent(inout) :: phys
    real(rp), intent(in) :: t
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: u_loc(:), q_loc(:), stress(:,:), vel(:,:), pres(:)
    integer(ip) :: u0, u1, q0, q1, p0, p1, c, nc
    call phys%sys%block_range(iu, u0, u1)
    call phys%sys%block_range(iq, q0, q1)
    call phys%sys%block_range(ipr, p0, p1)
    nc = mesh%cell_map%n_owned
    allocate(u_loc(phys%mech%u%n_local()), q_loc(phys%qd%n_local()), stress(6, nc), vel(3, nc))
    u_loc = 0.0_rp
    u_loc(1:u1 - u0 + 1) = phys%x(u0:u1)
    call phys%mech%u%map%import(u_loc)
    q_loc = 0.0_rp
    q_loc(1:q1 - q0 + 1) = phys%x(q0:q1)
    call phys%qd%map%import(q_loc)
    pres = phys%x(p0:p1)
    call phys%mech%cell_stress(mesh, u_loc, stress)
    do c = 1, nc
      ! total stress = effective - b p I (xx, yy, zz are components 1, 4, 6)
      stress([1, 4, 6], c) = stress([1, 4, 6], c) - phys%biot(mesh%cell_region(c)) * pres(c)
    end do
    call phys%cell_velocity(mesh, q_loc, vel)
    call out%begin_step(t, status)
    if (status%ok()) call out%node_field('displacement', reshape(u_loc(1:u1 - u0 + 1), [3, (u1 - u0 + 1) / 3]), status)
    if (status%ok()) call out%cell_field('pressure', pres, status)
    if (status%ok()) call out%cell_field('darcy_velocity', vel, status)
    if (status%ok()) call out%cell_field('stress', stress, status)
    if (status%ok()) call out%cell_field('region', mesh%cell_region(1:nc), status)
    if (status%ok()) call out%cell_field('rank', mesh%cell_owner(1:nc), status)
    if (status%ok()) call out%end_step(status)
  end subroutine write_fields
end module biot_driver
