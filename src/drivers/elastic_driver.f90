!> Driver of an elasticity run: load steps, each an assembly, a linear solve
!> and an output, with a progress line per step and a timing summary.
module elastic_driver
  use kinds, only: rp, ip, gp, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
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
  use amg_params, only: amg_params_t
  use fsai_config, only: fsai_config_t
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use elasticity, only: elasticity_t
  use linear_solver, only: linear_solver_t
  use krylov, only: solve_info_t
  use field_output, only: field_output_t
  use dist_vector, only: write_vector_market, pmax_abs
  implicit none
  private

  public :: run_elasticity

contains

  !> Run the elasticity problem of deck d. Stops collectively on any error.
  subroutine run_elasticity(comm, log, d, run)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(deck_t), intent(in) :: d
    type(run_config_t), intent(in) :: run
    type(mesh_config_t) :: mcfg
    type(material_config_t), allocatable :: mats(:)
    type(boundary_config_t), allocatable :: bcs(:)
    type(solver_config_t) :: scfg
    type(fsai_config_t) :: fcfg
    integer(gp), allocatable :: keys(:)
    type(amg_params_t) :: amg
    type(error_status_t) :: status
    type(dist_mesh_t) :: mesh
    type(elasticity_t) :: phys
    type(linear_solver_t) :: solver
    type(field_output_t) :: out
    type(timer_set_t) :: timers
    type(solve_info_t) :: info
    real(rp), allocatable :: x(:), u_loc(:), stress(:,:)
    real(rp) :: lf, t_setup, t_asm
    integer :: step, c
    logical :: has_nan
    character(len=msg_len) :: line
    character(len=path_len) :: mm

    call timers%start('total')
    call mcfg%read(d, log, status)
    if (status%ok()) call read_materials(d, log, mats, status)
    if (status%ok()) call read_boundaries(d, log, bcs, status)
    if (status%ok()) call scfg%read(d, log, status)
    if (status%ok()) call read_amg_config(d, log, amg, status)
    if (status%ok()) call fcfg%read(d, log, status)
    if (status%ok()) call load_histories(comm, bcs, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    if (d%count('fault') > 0) call log%fatal(comm, "deck '"//trim(d%path)//"': &fault groups need "// &
      "physics = 'contact' in &run")

    do c = 1, size(bcs)
      if (bcs(c)%type == 'pressure' .or. bcs(c)%type == 'flux') call log%fatal(comm, "&boundary on set '"// &
        trim(bcs(c)%set)//"': type = '"//trim(bcs(c)%type)//"' needs physics = 'biot' in &run")
    end do
    call timers%start('mesh')
    call build_mesh(comm, mcfg, log, mesh, status)
    call timers%stop('mesh')
    if (.not. status%ok()) call log%fatal(comm, status%msg)

    call phys%init(mesh, mats, bcs, status)
    call agree(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call phys%check_anchored(comm, status)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call log%info('displacement dofs: '//itoa(int(phys%u%map%n_global))//', matrix non-zeros: '// &
                  itoa(int(phys%k%global_nnz())))

    call solver%init(comm, scfg, amg, status, fcfg%precon)
    if (.not. status%ok()) call log%fatal(comm, status%msg)
    call log%info('linear solver: '//solver%describe())
    if (run%fields) then
      call out%init(mesh, run%out_dir, run%prefix, status)
      if (.not. status%ok()) call log%fatal(comm, status%msg)
    end if

    allocate(x(phys%u%n_owned()), u_loc(phys%u%n_local()), stress(6, mesh%cell_map%n_owned))
    x = 0.0_rp
    do step = 1, run%n_steps
      lf = real(step, rp) / real(run%n_steps, rp)
      call timers%start('assembly')
      call phys%set_time(lf)
      call phys%assemble(mesh, lf)
      call timers%stop('assembly', t_asm)
      if (step == 1 .and. run%export_matrix) then
        mm = trim(run%out_dir)//'/'//trim(run%prefix)
        call write_exports(comm, log, phys, trim(mm))
      end if
      ! the stiffness does not depend on the load: set up once
      t_setup = 0.0_rp
      if (step == 1) then
        call timers%start('preconditioner setup')
        call mesh%node_keys(3, keys)
        call solver%setup(phys%k, status, symmetric=.true., keys=keys)
        call timers%stop('preconditioner setup', t_setup)
        call agree(comm, status)
        if (status%ok()) call solver%setup_report(phys%k, log, status)
        if (.not. status%ok()) call log%fatal(comm, 'step '//itoa(step)//': '//trim(status%msg))
      end if
      call timers%start('solve')
      call solver%solve(phys%k, phys%rhs, x, info)
      call timers%stop('solve')
      write(line, '(a,i0,a,i0,a,f6.3,a,i5,a,es9.2,a,f8.3,a,f8.3,a,f8.3,a)') 'step ', step, '/', run%n_steps, &
        '  load ', lf, '  iterations ', info%iterations, '  rel. residual ', info%rel_res, &
        '  assembly ', t_asm, ' s  setup ', t_setup, ' s  solve ', info%solve_time, ' s'
      call log%info(line)
      has_nan = comm%any_true(any(x /= x))
      if (.not. info%converged .or. has_nan) then
        if (scfg%fail_on_no_convergence .or. has_nan) &
          call log%fatal(comm, 'step '//itoa(step)//': the linear solver did not converge: '//trim(info%msg))
        call log%warn('step '//itoa(step)//': the linear solver did not converge: '//trim(info%msg))
      end if
      u_loc(1:size(x)) = x
      call phys%u%map%import(u_loc)
      call phys%cell_stress(mesh, u_loc, stress)
      if (run%fields .and. (mod(step, run%every) == 0 .or. step == 1 .or. step == run%n_steps)) then
        call timers%start('output')
        call out%write_step(mesh, lf, u_loc, stress, status)
        call timers%stop('output')
        if (.not. status%ok()) call log%fatal(comm, status%msg)
      end if
    end do
    call log%info('max |u| = '//rtoa(pmax_abs(comm, x))//' m')
    if (run%fields) call log%info('output: '//trim(out%path())//' (open it in ParaView)')
    call timers%stop('total')
    call timers%report(comm, log)
    call out%free()
    call solver%free()
    call phys%free()
    call mesh%free()
  end subroutine run_elasticity


  !> Matrix and right-hand side of the first step, MatrixMarket format.
  subroutine write_exports(comm, log, phys, base)
    type(parallel_comm_t), intent(inout) :: comm
    type(logger_t), intent(inout) :: log
    type(elasticity_t), intent(in) :: phys
    character(len=*), intent(in) :: base
    integer :: ios
    call phys%k%write_matrix_market(base//'_K.mtx', ios)
    if (ios == 0) call write_vector_market(comm, base//'_rhs.mtx', phys%rhs, phys%u%map%n_global, ios)
    if (ios /= 0) call log%fatal(comm, 'cannot write the matrix export '//base//'_K.mtx / _rhs.mtx')
    call log%info('matrix and right-hand side written to '//base//'_K.mtx and '//base//'_rhs.mtx')
  end subroutine write_exports
end module elastic_driver
