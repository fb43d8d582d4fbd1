!> physics = 'elasticity': quasi-static linear elasticity in load steps
!> (loads and prescribed displacements grow linearly to their full value at
!> the last step), one linear solve per step: CG or FGMRES with a
!> preconditioner of K from the factory (BoomerAMG by default), or MUMPS.
!> K does not depend on the load, so its preconditioner (or factorization)
!> is set up once.
module elastic_simulation
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: wall_time
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use precon, only: precon_t
  use precon_factory, only: precon_params_t, make_precon, setup_precon, report_precon
  use linear_system, only: linear_system_t
  use dist_vector, only: pmax_abs
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use dist_mesh, only: dist_mesh_t
  use mesh_pieces, only: mesh_pieces_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  use elasticity, only: elasticity_t
  use simulation, only: simulation_t, foreign_len, step_stats_t
  implicit none
  private

  public :: elastic_simulation_t

  type, extends(simulation_t) :: elastic_simulation_t
    type(elasticity_t) :: mech
    real(rp), allocatable :: x(:)              !< owned displacements [m]
    real(rp), allocatable :: u_loc(:)          !< local displacements, ghosts imported [m]
    class(precon_t), allocatable :: pc         !< preconditioner of K (Krylov methods)
    logical :: pc_ready = .false.
    logical :: solved = .false.                !< K has been handed to a solver (it does not change)
    real(rp) :: t = 0.0_rp                     !< load factor of the step
    logical :: geo_step = .false.              !< this is step 0, the in-situ equilibrium (&geostatic)
    real(rp), allocatable :: u_geo(:)          !< local displacements of step 0 [m]: outputs are measured from them
  contains
    procedure :: name
    procedure :: read_deck
    procedure :: foreign_inputs
    procedure :: setup
    procedure :: begin_step
    procedure :: assemble
    procedure :: linear_system
    procedure :: update
    procedure :: save_state
    procedure :: load_state
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: report_step
    procedure :: accept_step
    procedure :: step_notes
    procedure :: finish
    procedure :: free
  end type elastic_simulation_t

contains

  function name(self) result(s)
    class(elastic_simulation_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'elasticity'
  end function name

  !> &material, &boundary, &solver, &amg, &afsai (the shared groups).
  subroutine read_deck(self, d, mcfg, log, status)
    class(elastic_simulation_t), intent(inout), target :: self
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call self%read_common(d, log, status, 'boomeramg', flow_conditions=.false., with_faults=.false.)
    if (.not. status%ok()) return
    if (self%solver%precon == 'block' .or. self%solver%precon == 'mgr') &
      call status%set("deck '"//trim(d%path)//"', group &solver, variable precon: '"//trim(self%solver%precon)// &
        "' is for the block systems (physics 'biot', 'contact', 'fracture_flow'); elasticity takes 'boomeramg', "// &
        "'jacobi', 'afsai', 'hypre_fsai' or 'none'")
  end subroutine read_deck

  !> The displacement dofs, K's pattern, the rigid-body check and the
  !> preconditioner's type. Collective.
  subroutine setup(self, mesh, log, status)
    class(elastic_simulation_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    type(mesh_pieces_t) :: pieces
    self%mesh => mesh
    call self%mech%init(mesh, self%mats, self%bcs, status)
    call agree(self%comm, status)
    if (status%ok()) call self%mech%init_in_situ(mesh, self%geo, self%mats, status)
    if (status%ok()) call self%mech%init_pressure_changes(mesh, self%pcs, self%mats, status)
    call agree(self%comm, status)
    if (.not. status%ok()) return
    if (self%geo%on) call log%info('geostatic: largest nodal force of the in-situ state out of equilibrium: '// &
      trim(rtoa(self%mech%in_situ_imbalance(mesh)))//' of the largest nodal weight; step 0 balances it')
    call pieces%build(mesh)
    call self%mech%check_anchored(mesh, pieces, status)
    call pieces%free()
    if (.not. status%ok()) return
    call log%info('displacement dofs: '//itoa(int(self%mech%u%map%n_global))//', matrix non-zeros: '// &
                  itoa(int(self%mech%k%global_nnz())))
    if (self%solver%method /= 'mumps' .and. self%solver%precon == 'boomeramg') call self%adapt_amg(mesh, log)
    allocate(self%x(self%mech%u%n_owned()), self%u_loc(self%mech%u%n_local()), self%u_geo(self%mech%u%n_local()))
    self%x = 0.0_rp
    self%u_loc = 0.0_rp
    self%u_geo = 0.0_rp
    if (self%solver%method == 'mumps') then
      call log%info('linear solver: MUMPS direct solver')
    else
      call make_precon(self%solver%precon, self%pc, status)
      if (status%ok()) call log%info('linear solver: '//trim(self%solver%method)//' + '//trim(self%pc%name()))
    end if
  end subroutine setup

  !> Load factor t: the boundary conditions' histories at t.
  subroutine begin_step(self, t, dt, status)
    class(elastic_simulation_t), intent(inout) :: self
    real(rp), intent(in) :: t, dt
    type(error_status_t), intent(inout) :: status
    self%t = t
    self%geo_step = self%initial_step .and. dt == 0.0_rp
    call self%mech%set_time(t)
  end subroutine begin_step

  !> K and the right-hand side at the step's load factor.
  subroutine assemble(self, status)
    class(elastic_simulation_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    call self%mech%assemble(self%mesh, self%t)
  end subroutine assemble

  !> K u = f for the displacements, from the last step's as initial guess;
  !> the preconditioner of K is set up at the first step only.
  subroutine linear_system(self, direct, sys, log, status)
    class(elastic_simulation_t), intent(inout), target :: self
    logical, intent(in) :: direct
    type(linear_system_t), intent(inout) :: sys
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    type(precon_params_t) :: params
    integer(gp), allocatable :: keys(:)
    real(rp) :: t0
    call sys%reset()
    sys%a => self%mech%k
    sys%b => self%mech%rhs
    sys%x => self%x
    sys%fields = 'u'
    sys%symmetric = .true.
    sys%changed = .not. self%solved
    self%solved = .true.
    if (direct) return
    if (.not. self%pc_ready) then
      t0 = wall_time()
      params%amg = self%amg_k
      params%fsai = self%fsai%precon
      if (self%amg%interp_vec_variant > 0) params%modes = self%mech%rigid_body_modes(self%mesh)
      call self%mesh%node_keys(3, keys)
      call setup_precon(self%pc, self%mech%k, params, status, symmetric=.true., keys=keys)
      sys%setup_time = wall_time() - t0
      call sys%add_part('K: '//trim(self%pc%name()), sys%setup_time)
      call agree(self%comm, status)
      if (status%ok()) call report_precon(self%pc, self%mech%k, log, status)
      if (.not. status%ok()) return
      self%pc_ready = .true.
    end if
    sys%m => self%pc
  end subroutine linear_system

  !> The solved displacements with their ghosts; a linear step is done.
  subroutine update(self, iteration, linear_its, log, converged, why, status)
    class(elastic_simulation_t), intent(inout) :: self
    integer, intent(in) :: iteration, linear_its
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    type(error_status_t), intent(inout) :: status
    self%u_loc(1:size(self%x)) = self%x
    call self%mech%u%map%import(self%u_loc)
    converged = .true.
    why = ''
  end subroutine update

  !> Step 0 (&geostatic) is accepted: its displacements, the balance of the
  !> in-situ state on this mesh, become the origin of the outputs'.
  subroutine accept_step(self)
    class(elastic_simulation_t), intent(inout) :: self
    if (self%geo_step) self%u_geo = self%u_loc
  end subroutine accept_step

  !> After step 0 (&geostatic): the size of the balancing displacements.
  subroutine step_notes(self, lines)
    class(elastic_simulation_t), intent(inout) :: self
    character(len=msg_len), allocatable, intent(out) :: lines(:)
    allocate(lines(0))
    if (.not. self%geo_step) return
    lines = [character(len=msg_len) :: 'geostatic: in-situ state balanced, max |u| of step 0 = '// &
      trim(rtoa(pmax_abs(self%comm, self%x)))//' m (displacements are measured from it)']
  end subroutine step_notes

  subroutine save_state(self, st)
    class(elastic_simulation_t), intent(inout) :: self
    type(state_record_t), intent(inout) :: st
    call st%put('displacement', self%x)
    if (self%geo%on) call st%put('displacement_in_situ', self%u_geo(1:size(self%x)))
  end subroutine save_state

  subroutine load_state(self, st, status)
    class(elastic_simulation_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    call st%get('displacement', self%x, status)
    self%u_loc(1:size(self%x)) = self%x
    call self%mech%u%map%import(self%u_loc)
    if (self%geo%on) then
      call st%get('displacement_in_situ', self%u_geo(1:size(self%x)), status)
      call self%mech%u%map%import(self%u_geo)
    end if
  end subroutine load_state

  !> displacement [m] per node; stress [Pa] (Tensor6 xx yy zz xy yz xz,
  !> tension positive), region and rank per cell.
  subroutine write_output(self, out, status)
    class(elastic_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: stress(:,:)
    allocate(stress(6, self%mesh%cell_map%n_owned))
    call self%mech%cell_stress(self%mesh, self%u_loc, stress)
    call out%write_displacement(self%mesh, self%u_loc - self%u_geo, status)
    if (status%ok()) call out%writer%cell_field('stress', stress, status)
    call out%write_mesh_ids(self%mesh, status)
    if (status%ok() .and. size(self%mech%pcs) > 0) &
      call out%writer%cell_field('pressure_change', self%mech%pressure_change_field(self%mesh, self%t), status)
  end subroutine write_output

  !> Displacement and stress for the probes.
  subroutine probe_names(self, names)
    class(elastic_simulation_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    names = [character(len=8) :: 'ux', 'uy', 'uz', 'sxx', 'syy', 'szz', 'sxy', 'syz', 'sxz']
  end subroutine probe_names

  subroutine sample(self, pf, status)
    class(elastic_simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    pf%u = self%u_loc - self%u_geo
    allocate(pf%stress(6, self%mesh%cell_map%n_owned))
    call self%mech%cell_stress(self%mesh, self%u_loc, pf%stress)
  end subroutine sample

  subroutine report_step(self, stats, line)
    class(elastic_simulation_t), intent(inout) :: self
    type(step_stats_t), intent(in) :: stats
    character(len=*), intent(out) :: line
    write(line, '(a,i0,a,i0,a,f6.3,a,i5,a,es9.2,a,f8.3,a,f8.3,a,f8.3,a)') 'step ', stats%step, '/', stats%n_steps, &
      '  load ', stats%t, '  iterations ', stats%linear_its, '  rel. residual ', stats%rel_res, &
      '  assembly ', stats%t_assembly, ' s  setup ', stats%t_setup, ' s  solve ', stats%t_solve, ' s'
  end subroutine report_step

  subroutine finish(self, log)
    class(elastic_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    call log%info('max |u| = '//rtoa(pmax_abs(self%comm, self%x - self%u_geo(1:size(self%x))))//' m')
  end subroutine finish

  subroutine free(self)
    class(elastic_simulation_t), intent(inout) :: self
    if (allocated(self%pc)) then
      call self%pc%free()
      deallocate(self%pc)
    end if
    call self%mech%free()
    if (allocated(self%x)) deallocate(self%x, self%u_loc, self%u_geo)
    self%pc_ready = .false.
    self%solved = .false.
  end subroutine free
  !> Groups and variables of other physics, refused in this one's deck.
  subroutine foreign_inputs(self, list)
    class(elastic_simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'biot', 'source', 'fault', 'contact', 'fracture_flow', 'well', &
            'fracture_pressure', 'block_fsai', &
            'material%biot_modulus', &
            'material%permeability', 'material%permeability_tensor', 'material%viscosity']
    ! the Biot coefficient weighs a &pressure_change
    if (size(self%pcs) == 0) list = [list, [character(len=foreign_len) :: 'material%biot']]
  end subroutine foreign_inputs
end module elastic_simulation
