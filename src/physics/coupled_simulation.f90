!> A physics as a composition of components (physics_component.f90): an
!> ordered list of components, each with its unknowns, rows, residuals and
!> state, coupled through their off-diagonal blocks and the coupling
!> context. The composition lays out the block system, runs the Newton /
!> active-set bookkeeping once for all components (the residual test per
!> field, status changes, the held-element check, the settled / last-field
!> lines) and composes the state record, the outputs, the probes and the
!> progress lines. simulation_factory.f90 builds the compositions:
!>   'contact'       = [mechanics, interface contact]                 load steps
!>   'fracture_flow' = [mechanics, interface contact, fracture flow]  time steps
!> Each step is an active-set loop whose iterations are Newton steps on the
!> current statuses (stick, slip, open), each a block solve for the
!> update: FGMRES on the scaled system with the contact block
!> preconditioner (contact_precon.f90) or hypre's MGR, or MUMPS. The driver
!> halves a step whose loop does not converge in max_newton iterations
!> (max_cuts times, from &contact).
module coupled_simulation
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: wall_time
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use linear_system, only: linear_system_t
  use dist_vector, only: pnorm2
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use dist_mesh, only: dist_mesh_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  use param_group, only: param_group_t
  use flow_config, only: flow_config_t
  use contact_precon, only: contact_precon_t
  use poro_faults_precon, only: poro_faults_precon_t
  use precon_factory, only: precon_params_t
  use mgr_precon, only: mgr_precon_t, mgr_contact, mgr_flow, mgr_poro_faults
  use simulation, only: simulation_t, foreign_len, common_parameter_groups, step_stats_t
  use physics_component, only: physics_component_t, coupling_t, field_len
  use interface_contact, only: interface_contact_t, interface_contact_of
  use fracture_flow_component, only: fracture_flow_component_t, fracture_flow_of
  implicit none
  private

  public :: coupled_simulation_t

  !> smoothing sweeps, at least, of S*'s BoomerAMG on a slab with flat cells
  integer, parameter :: slab_sweeps = 3

  type :: component_slot_t
    class(physics_component_t), allocatable :: c
  end type component_slot_t

  type, extends(simulation_t) :: coupled_simulation_t
    character(len=name_len) :: physics = ''         !< the deck's name of the composition
    character(len=name_len) :: controls = ''        !< the deck group of max_newton and max_cuts
    type(component_slot_t), allocatable :: slots(:) !< the components, in order
    !> groups of the components it does not have (refused in its deck)
    character(len=foreign_len), allocatable :: refused(:)
    type(coupling_t) :: ctx
    type(contact_precon_t) :: cpc
    type(poro_faults_precon_t) :: pfp               !< with the matrix's fluid: its blocks in cpc's framework
    type(mgr_precon_t) :: mgr                       !< &solver precon = 'mgr': hypre's MGR (the peer)
    real(rp), allocatable :: dsc(:)                 !< scaling of the block system
    ! the Newton loop's convergence test (check_residual)
    integer(gp) :: changes = 0                      !< status changes of the last update
    integer :: settled_at = 0                       !< the update from which no status changed (0: not yet)
    !> an update of this step changed a status (before the run's first
    !> step: assumed, so that step's first iteration counts as moving)
    logical :: step_moved = .true.
    logical :: last_moved = .true.                  !< one of the last step did
    integer, allocatable :: field_at(:)             !< per residual, the update from which it is within tolerance
    real(rp), allocatable :: ref_max(:)             !< per residual, the largest magnitude of the run
  contains
    procedure :: add
    procedure :: name
    procedure :: read_deck
    procedure :: foreign_inputs
    procedure :: parameter_groups
    procedure :: controls_group
    procedure :: setup
    procedure :: open_output
    procedure :: begin_step
    procedure :: assemble
    procedure :: linear_system
    procedure :: update
    procedure :: check_residual
    procedure :: active_set_moving
    procedure :: save_state
    procedure :: load_state
    procedure :: accept_step
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: report_step
    procedure :: step_notes
    procedure :: finish
    procedure :: free
  end type coupled_simulation_t

contains

  !> Append component c (moved in) to the composition.
  subroutine add(self, c)
    class(coupled_simulation_t), intent(inout) :: self
    class(physics_component_t), allocatable, intent(inout) :: c
    type(component_slot_t), allocatable :: s(:)
    integer :: k, n
    n = 0
    if (allocated(self%slots)) n = size(self%slots)
    allocate(s(n + 1))
    do k = 1, n
      call move_alloc(self%slots(k)%c, s(k)%c)
    end do
    call move_alloc(c, s(n + 1)%c)
    call move_alloc(s, self%slots)
  end subroutine add

  function name(self) result(s)
    class(coupled_simulation_t), intent(in) :: self
    character(len=name_len) :: s
    s = self%physics
  end function name

  !> The context's view of the composition and its components.
  subroutine link(self)
    type(coupled_simulation_t), intent(inout), target :: self
    integer :: k
    self%ctx%sim => self
    if (allocated(self%ctx%comps)) deallocate(self%ctx%comps)
    allocate(self%ctx%comps(size(self%slots)))
    do k = 1, size(self%slots)
      self%ctx%comps(k)%p => self%slots(k)%c
    end do
  end subroutine link

  !> The shared groups, then the components' groups in order, then their
  !> checks once every group is read.
  subroutine read_deck(self, d, mcfg, log, status)
    class(coupled_simulation_t), intent(inout), target :: self
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: k
    call link(self)
    ! the matrix's fluid takes pressure and flux conditions (and no &pressure_change)
    call self%read_common(d, log, status, 'block', flow_conditions=has_kind(self, 'matrix_flow'), &
                          with_faults=.true.)
    do k = 1, size(self%slots)
      if (status%ok()) call self%slots(k)%c%read_deck(self%ctx, d, mcfg, log, status)
    end do
    do k = 1, size(self%slots)
      if (status%ok()) call self%slots(k)%c%check_deck(self%ctx, d, status)
    end do
  end subroutine read_deck

  !> Groups and variables of other physics, those of the components it
  !> does not have, and what its components refuse.
  subroutine foreign_inputs(self, list)
    class(coupled_simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    character(len=foreign_len), allocatable :: more(:)
    integer :: k
    list = [character(len=foreign_len) :: 'biot', 'source', 'block_fsai', &
            'material%biot_modulus', &
            'material%permeability', 'material%permeability_tensor', 'material%viscosity']
    ! the matrix's fluid uses them (and refuses &block_fsai, which is biot's)
    if (has_kind(self, 'matrix_flow')) list = [character(len=foreign_len) :: 'block_fsai']
    list = [list, self%refused]
    do k = 1, size(self%slots)
      call self%slots(k)%c%foreign_inputs(more)
      list = [list, more]
    end do
    ! the Biot coefficient weighs a &pressure_change
    if (size(self%pcs) == 0 .and. .not. has_kind(self, 'matrix_flow')) &
      list = [list, [character(len=foreign_len) :: 'material%biot']]
  end subroutine foreign_inputs

  !> Whether the composition has a component of kind.
  logical function has_kind(self, kind)
    type(coupled_simulation_t), intent(in) :: self
    character(len=*), intent(in) :: kind
    integer :: k
    has_kind = .false.
    if (.not. allocated(self%slots)) return
    do k = 1, size(self%slots)
      has_kind = has_kind .or. self%slots(k)%c%kind == kind
    end do
  end function has_kind

  !> The resolved groups: the shared ones, then the components' in order.
  subroutine parameter_groups(self, groups)
    class(coupled_simulation_t), intent(in) :: self
    type(param_group_t), allocatable, intent(out) :: groups(:)
    type(param_group_t), allocatable :: more(:)
    integer :: k
    call common_parameter_groups(self, groups)
    do k = 1, size(self%slots)
      call self%slots(k)%c%parameter_groups(self%ctx, more)
      groups = [groups, more]
    end do
  end subroutine parameter_groups

  function controls_group(self) result(g)
    class(coupled_simulation_t), intent(in) :: self
    character(len=name_len) :: g
    g = self%controls
  end function controls_group

  !> The components' set-ups, the block layout (the order the block
  !> preconditioners want), the patterns, the components' checks and the
  !> solver's set-up lines. Collective.
  subroutine setup(self, mesh, log, status)
    class(coupled_simulation_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: k
    self%mesh => mesh
    call link(self)
    self%ctx%mesh => mesh
    do k = 1, size(self%slots)
      call self%slots(k)%c%setup(self%ctx, log, status)
      if (.not. status%ok()) exit
    end do
    call agree(self%comm, status)
    if (.not. status%ok()) return
    call layout(self)
    call residual_count(self)
    do k = 1, size(self%slots)
      if (status%ok()) call self%slots(k)%c%set_patterns(self%ctx, status)
    end do
    call agree(self%comm, status)
    if (.not. status%ok()) return
    do k = 1, size(self%slots)
      call self%slots(k)%c%report_setup(self%ctx, log, status)
      if (.not. status%ok()) return
    end do
    call log_unknowns(self, log)
    call solver_setup(self, mesh, log)
  end subroutine setup

  !> The blocks: the fields of the components in order, the tractions
  !> first for the reordered and augmented preconditioners, and with the
  !> fluid's pressure_block = 'eliminated' the pressure second (the
  !> displacement last: the pressure eliminated with the tractions). The
  !> block system, x (0) and rhs.
  subroutine layout(self)
    type(coupled_simulation_t), intent(inout), target :: self
    character(len=field_len), allocatable :: order(:), names(:)
    integer(ip), allocatable :: no(:)
    integer, allocatable :: owner(:), index_in(:)
    integer :: k, j, b
    type(interface_contact_t), pointer :: ic
    type(fracture_flow_component_t), pointer :: fc
    allocate(order(0), owner(0), index_in(0))
    do k = 1, size(self%slots)
      call self%slots(k)%c%fields(names)
      do j = 1, size(names)
        order = [order, names(j)]
        owner = [owner, k]
        index_in = [index_in, j]
      end do
    end do
    ic => contact_component(self)
    fc => flow_component(self)
    if (self%solver%method /= 'mumps' .and. associated(ic)) then
      if (ic%ccfg%block /= 'classical' .or. associated(fc)) call to_position(findloc(order, 't', dim=1), 1)
      ! with the matrix's fluid: t, u, q, pm, p (the two pressures last, one group)
      if (associated(fc) .and. .not. has_kind(self, 'matrix_flow')) then
        if (fc%fcfg%pressure_block == 'eliminated') call to_position(findloc(order, 'p', dim=1), 2)
      end if
    end if
    self%ctx%order = order
    allocate(no(size(order)))
    do b = 1, size(order)
      no(b) = self%slots(owner(b))%c%field_size(index_in(b))
    end do
    call self%ctx%sys%init(no)
    associate (n => self%ctx%sys%offset(self%ctx%sys%nb + 1))
      allocate(self%ctx%x(n), self%ctx%rhs(n), self%ctx%dx(n), self%dsc(n))
    end associate
    self%ctx%x = 0.0_rp
    allocate(self%ctx%rel_update(size(order)))
    self%ctx%rel_update = 0.0_rp
  contains
    subroutine to_position(from, to)
      integer, intent(in) :: from, to
      character(len=field_len) :: f
      integer :: o, i
      f = order(from)
      o = owner(from)
      i = index_in(from)
      order(to+1:from) = order(to:from-1)
      owner(to+1:from) = owner(to:from-1)
      index_in(to+1:from) = index_in(to:from-1)
      order(to) = f
      owner(to) = o
      index_in(to) = i
    end subroutine to_position
  end subroutine layout

  !> The Newton bookkeeping's arrays, one entry per residual of the components.
  subroutine residual_count(self)
    type(coupled_simulation_t), intent(inout) :: self
    character(len=8), allocatable :: nk(:)
    character(len=3), allocatable :: uk(:)
    integer :: k, nf
    nf = 0
    do k = 1, size(self%slots)
      call self%slots(k)%c%residual_names(nk, uk)
      nf = nf + size(nk)
    end do
    allocate(self%field_at(nf), self%ref_max(nf))
    self%field_at = 0
    self%ref_max = 0.0_rp
  end subroutine residual_count

  !> The interface contact component, null if none.
  function contact_component(self) result(ic)
    type(coupled_simulation_t), intent(in), target :: self
    type(interface_contact_t), pointer :: ic
    ic => interface_contact_of(self%ctx)
  end function contact_component

  !> The fracture-flow component, null if none: the preconditioner's
  !> choices depend on it.
  function flow_component(self) result(fc)
    type(coupled_simulation_t), intent(in), target :: self
    type(fracture_flow_component_t), pointer :: fc
    fc => fracture_flow_of(self%ctx)
  end function flow_component

  !> 'unknowns: u N, t M, p K (the components' notes)', then the
  !> components' lines on their unknowns.
  subroutine log_unknowns(self, log)
    type(coupled_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    character(len=:), allocatable :: line, notes
    character(len=field_len), allocatable :: names(:)
    character(len=msg_len) :: note
    integer :: k, j
    line = 'unknowns:'
    notes = ''
    do k = 1, size(self%slots)
      call self%slots(k)%c%fields(names)
      do j = 1, size(names)
        if (line /= 'unknowns:') line = line//','
        line = line//' '//trim(names(j))//' '//itoa(int(self%comm%sum(int(self%slots(k)%c%field_size(j), gp))))
      end do
      call self%slots(k)%c%unknowns_note(self%ctx, note)
      if (len_trim(note) == 0) cycle
      if (len(notes) > 0) notes = notes//', '
      notes = notes//trim(note)
    end do
    if (len(notes) > 0) line = line//' ('//notes//')'
    call log%info(line)
    do k = 1, size(self%slots)
      call self%slots(k)%c%describe_unknowns(self%ctx, log)
    end do
  end subroutine log_unknowns

  !> The solver's lines and the displacement block's AMG settings.
  !> Collective.
  subroutine solver_setup(self, mesh, log)
    type(coupled_simulation_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(logger_t), intent(inout) :: log
    type(interface_contact_t), pointer :: ic
    ic => contact_component(self)
    if (self%solver%method == 'mumps') then
      call log%info('linear solver: MUMPS (direct) at every Newton iteration')
    else
      if (self%solver%precon == 'mgr' .and. has_kind(self, 'matrix_flow')) then
        call log%info("linear solver: FGMRES with hypre's MGR on the whole system (GEOS's poromechanics and "// &
                      'contact strategies: u by BoomerAMG, then t by l1-Jacobi, then q by Jacobi, (pm, p) '// &
                      'by BoomerAMG)')
      else if (self%solver%precon == 'mgr') then
        call log%info("linear solver: FGMRES with hypre's MGR on the whole system (GEOS's contact strategy: "// &
                      't by l1-Jacobi'//trim(merge(', then p by Jacobi', '                  ', &
                      associated(flow_component(self))))//', u by BoomerAMG)')
      else
        call log%info('linear solver: FGMRES with the '//trim(ic%ccfg%block)//' block preconditioner')
        if (has_kind(self, 'matrix_flow')) call log%info('  with the matrix fluid: blocks t, u, q, (pm, p); S_q '// &
          trim(self%solver%flux_precon)//', S_P of (pm, p) '//trim(self%solver%schur)//' + scaled Laplacian, '// &
          trim(self%solver%schur_precon))
      end if
    end if
    self%amg_k = self%amg
    if (self%solver%method /= 'mumps' .and. self%solver%precon /= 'mgr') call self%adapt_amg(mesh, log)
    if (self%on_slab .and. self%amg_k%num_sweeps < slab_sweeps) then
      ! S* on a slab: the fault's penalty ties the faces' through-thickness
      ! pairs across it, and one l1-Gauss-Seidel sweep leaves S*'s AMG at
      ! 2.1x the elastic count. tests/verification/slab_amg.sh's slab (2
      ! ranks, reordered, FGMRES per Newton iteration; elastic CG 22):
      ! contact 48 46 with 1 sweep, 31 30 with 2, 24 24 with W(3,3) cycles,
      ! 8 7 with S* solved exactly (inner_cg); the fluid in the fault, the
      ! largest count of 12 Newton iterations, 36 with 2 sweeps and 32 with
      ! 3 (1.45x the elastic count)
      self%amg_k%num_sweeps = slab_sweeps
      call log%info('slab: BoomerAMG of S* with '//itoa(slab_sweeps)//' smoothing sweeps (&amg num_sweeps raises it)')
    end if
    ! nor do two CG steps on S* suit a slab, where its AMG is the weaker:
    ! on that slab 46 68 FGMRES iterations (30 34 with 1 step, 27 24 with
    ! 4) against the V-cycle's 27 27; the deck's own choice stays
    if (self%on_slab .and. associated(ic)) then
      if (ic%ccfg%schur_solve == 'pcg' .and. .not. ic%ccfg%schur_given) then
        ic%ccfg%schur_solve = 'vcycle'
        call log%info("slab: S* by one V-cycle (&contact schur_solve = 'pcg' sets the CG steps)")
      end if
    end if
  end subroutine solver_setup

  !> The components' grids. Collective.
  subroutine open_output(self, out, status)
    class(coupled_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    integer :: k
    do k = 1, size(self%slots)
      if (status%ok()) call self%slots(k)%c%open_output(self%ctx, out, status)
    end do
  end subroutine open_output

  !> Time or load factor t: load steps (t the load factor) or time steps
  !> (the loads at full value times their histories at t); the
  !> components' step starts, the start iterate, what the step measures
  !> from it. Collective.
  subroutine begin_step(self, t, dt, status)
    class(coupled_simulation_t), intent(inout) :: self
    real(rp), intent(in) :: t, dt
    type(error_status_t), intent(inout) :: status
    integer :: k
    self%last_moved = self%step_moved
    self%step_moved = .false.
    self%changes = 0
    self%settled_at = 0
    self%field_at = 0
    self%ctx%lf = merge(1.0_rp, t, self%transient)
    self%ctx%time = t
    self%ctx%dt = dt
    self%ctx%initial = self%initial_step .and. dt == 0.0_rp
    ! a step without status updates (step 0 with the faults bonded) decides
    ! no status: the next step's first iteration may move them
    if (self%ctx%initial) self%step_moved = .true.
    do k = 1, size(self%slots)
      call self%slots(k)%c%begin_step(self%ctx)
    end do
    call take_solution(self)
    do k = 1, size(self%slots)
      call self%slots(k)%c%start_step(self%ctx)
    end do
  end subroutine begin_step

  !> Every component takes its part of x, in order. Collective.
  subroutine take_solution(self)
    type(coupled_simulation_t), intent(inout) :: self
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%take_solution(self%ctx)
    end do
  end subroutine take_solution

  !> The couplings' terms, then every component's rows. Collective.
  subroutine assemble(self, status)
    class(coupled_simulation_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer :: k
    integer(ip) :: u0, u1
    call self%ctx%range('u', u0, u1)
    if (.not. allocated(self%ctx%momentum_coupling)) allocate(self%ctx%momentum_coupling(u1 - u0 + 1), &
                                                              self%ctx%momentum_coupling_mag(u1 - u0 + 1))
    self%ctx%momentum_coupling = 0.0_rp
    self%ctx%momentum_coupling_mag = 0.0_rp
    do k = 1, size(self%slots)
      call self%slots(k)%c%couple(self%ctx)
    end do
    do k = 1, size(self%slots)
      call self%slots(k)%c%assemble(self%ctx)
    end do
  end subroutine assemble

  !> J dx = -r for the update (from zero); the block preconditioner follows
  !> the statuses, so it is refreshed at every iteration.
  subroutine linear_system(self, direct, sys, log, status)
    class(coupled_simulation_t), intent(inout), target :: self
    logical, intent(in) :: direct
    type(linear_system_t), intent(inout) :: sys
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    real(rp) :: t0
    integer(ip) :: u0, u1
    integer :: k
    type(interface_contact_t), pointer :: ic
    type(fracture_flow_component_t), pointer :: fc
    type(flow_config_t) :: no_flow
    do k = 1, size(self%slots)
      call self%slots(k)%c%check_system(self%ctx, status)
      if (.not. status%ok()) return
    end do
    call sys%reset()
    self%ctx%dx = 0.0_rp
    sys%a => self%ctx%sys
    sys%b => self%ctx%rhs
    sys%x => self%ctx%dx
    sys%fields = block_fields(self)
    if (direct) then
      call scaling(self)
      sys%d => self%dsc
      return
    end if
    ic => contact_component(self)
    fc => flow_component(self)
    t0 = wall_time()
    self%cpc%step_start = self%newton_it <= 1
    if (self%solver%precon == 'mgr') then
      call mgr_setup(self, status)
    else if (associated(fc)) then
      self%cpc%subspace = fc%fcfg%subspace_correction
      self%cpc%joint_pressure = has_kind(self, 'matrix_flow')
      call self%cpc%setup(self%ctx, self%mesh, ic%ccfg, self%amg_k, status, fc%fcfg%pressure_precon)
      if (self%cpc%joint_pressure) call matrix_fluid_setup(self, status)
    else
      self%cpc%subspace = .false.
      call self%cpc%setup(self%ctx, self%mesh, ic%ccfg, self%amg_k, status, no_flow%pressure_precon)
    end if
    call agree(self%comm, status)
    if (.not. status%ok()) then
      status%msg = 'preconditioner set-up: '//trim(status%msg)
      return
    end if
    call scaling(self)
    if (self%solver%precon == 'mgr') then
      call sys%add_part('hypre MGR', self%mgr%setup_time)
      sys%m => self%mgr
    else if (self%cpc%subspace) then
      sys%m => self%cpc%sub
    else
      sys%m => self%cpc%bp
    end if
    if (self%solver%precon /= 'mgr') call self%cpc%add_parts(sys)
    if (self%cpc%joint_pressure) call self%pfp%add_parts(sys)
    sys%d => self%dsc
    sys%setup_time = wall_time() - t0
    call self%ctx%range('u', u0, u1)
    sys%k_ref => self%ctx%sys%a(self%ctx%block('u'), self%ctx%block('u'))
    sys%b_ref => self%ctx%rhs(u0:u1)
  end subroutine linear_system

  !> The matrix fluid's blocks of the contact's preconditioner
  !> (poro_faults_precon.f90), after its set-up. Collective.
  subroutine matrix_fluid_setup(self, status)
    type(coupled_simulation_t), intent(inout), target :: self
    type(error_status_t), intent(inout) :: status
    type(precon_params_t) :: params
    if (.not. status%ok()) return
    params%amg = self%amg%scalar()
    params%fsai = self%fsai%precon
    call self%pfp%setup(self%cpc, self%ctx, self%solver%schur, self%solver%schur_precon, self%solver%flux_precon, &
                        params, status)
  end subroutine matrix_fluid_setup

  !> hypre's MGR on the whole system (labels: the components of each field
  !> in the order of the components: u 0-2, t 3-5, p 6; with the matrix
  !> flow u 0-2, q 3, pm 4, t 5-7, p 8). Collective.
  subroutine mgr_setup(self, status)
    type(coupled_simulation_t), intent(inout), target :: self
    type(error_status_t), intent(inout) :: status
    integer, allocatable :: ncomp(:), first(:)
    character(len=field_len), allocatable :: names(:)
    integer :: k, j, b, next
    allocate(ncomp(size(self%ctx%order)), first(size(self%ctx%order)))
    next = 0
    do k = 1, size(self%slots)
      call self%slots(k)%c%fields(names)
      do j = 1, size(names)
        b = self%ctx%block(names(j))
        ncomp(b) = self%slots(k)%c%components_of(j)
        first(b) = next
        next = next + ncomp(b)
      end do
    end do
    if (has_kind(self, 'matrix_flow')) then
      call self%mgr%setup_blocks(self%ctx%sys, ncomp, first, mgr_poro_faults(), self%amg, status)
    else if (associated(flow_component(self))) then
      call self%mgr%setup_blocks(self%ctx%sys, ncomp, first, mgr_flow(), self%amg, status)
    else
      call self%mgr%setup_blocks(self%ctx%sys, ncomp, first, mgr_contact(), self%amg, status)
    end if
  end subroutine mgr_setup

  !> The fields of the blocks in block order, comma separated ('t,u,p').
  function block_fields(self) result(names)
    type(coupled_simulation_t), intent(in) :: self
    character(len=16) :: names
    integer :: b
    names = self%ctx%order(1)
    do b = 2, size(self%ctx%order)
      names = trim(names)//','//trim(self%ctx%order(b))
    end do
  end function block_fields

  !> Symmetric scaling 1/sqrt of the components' diagonals (K, H~, the
  !> pressure block), for the Krylov and the direct solver alike.
  subroutine scaling(self)
    type(coupled_simulation_t), intent(inout) :: self
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%scaling(self%ctx, self%dsc)
    end do
    self%dsc = 1.0_rp / sqrt(abs(self%dsc))
  end subroutine scaling

  !> x += dx, the components' new state, their status updates (the active
  !> set), the iteration's detail line. Whether the step has converged is
  !> judged on the residual of the new iterate (check_residual, after the
  !> next assembly), so converged stays false.
  subroutine update(self, iteration, linear_its, log, converged, why, status)
    class(coupled_simulation_t), intent(inout) :: self
    integer, intent(in) :: iteration, linear_its
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    type(error_status_t), intent(inout) :: status
    integer(gp) :: n
    integer(ip) :: i0, i1
    integer :: k, b, f0
    character(len=msg_len) :: line
    character(len=field_len), allocatable :: names(:)
    associate (ctx => self%ctx, comm => self%comm)
      ctx%x = ctx%x + ctx%dx
      call take_solution(self)
      self%changes = 0
      do k = 1, size(self%slots)
        call self%slots(k)%c%update_status(ctx, n)
        self%changes = self%changes + n
      end do
      if (self%changes > 0) then
        self%settled_at = 0
        self%step_moved = .true.
      end if
      if (self%changes == 0 .and. self%settled_at == 0) self%settled_at = iteration
      write(line, '(a,i3,a,i5)') '  newton ', iteration, '  linear its ', linear_its
      f0 = 0
      do k = 1, size(self%slots)
        call self%slots(k)%c%fields(names)
        do b = 1, size(names)
          call ctx%range(names(b), i0, i1)
          ctx%rel_update(f0 + b) = pnorm2(comm, ctx%dx(i0:i1)) / max(pnorm2(comm, ctx%x(i0:i1)), tiny(1.0_rp))
        end do
        call self%slots(k)%c%iteration_note(ctx, ctx%rel_update(f0 + 1 : f0 + size(names)), line)
        f0 = f0 + size(names)
      end do
    end associate
    call log%detail(line)
    converged = .false.
    why = ''
  end subroutine update

  !> Every Newton iteration after an update that changed a status may still
  !> move the active set, and so may the first of a step when the last step
  !> changed statuses (the loads are still moving them; the first step of
  !> the run is assumed to). The first iteration of a step that follows a
  !> step with no status change is solved to rtol: a proportional or steady
  !> step then converges in one update, as the exact loop does. A step
  !> without updates (step 0 with the faults bonded) moves none, and counts
  !> as a step that did for the next (it judged no status).
  logical function active_set_moving(self, iteration)
    class(coupled_simulation_t), intent(in) :: self
    integer, intent(in) :: iteration
    if (self%ctx%initial) then
      active_set_moving = .false.
    else if (iteration == 1) then
      active_set_moving = self%last_moved
    else
      active_set_moving = self%changes > 0
    end if
  end function active_set_moving

  !> The residual of the iterate per residual of the components, in
  !> physical units (force [N], traction [Pa], fluid volume of the step
  !> [m^3], ...), each against newton_tol times the magnitude it balances
  !> (at least ref_floor times the largest such magnitude of the run, so
  !> that a field at rest is not asked for digits below round-off of its
  !> earlier steps), and never below noise_ulps * eps times the magnitude of
  !> its terms' operands: what double precision can resolve. (A fracture
  !> whose cubic-law transmissibility dwarfs its storage, an aperture of 1
  !> cm in 1 mm cells holding a fluid of c_f 1e-14, balances a step's volume
  !> of 6e-14 m^3 with flow terms of 0.25 m^3 each: its residual stalled at
  !> 1.2e-19 m^3, round-off, above newton_tol times 6e-14.) Converged when
  !> every residual is within its tolerance and the last update changed no
  !> status. A detail line per iteration; at convergence, which field (or
  !> the active set) was the last to settle.
  subroutine check_residual(self, updates, log, converged, why)
    class(coupled_simulation_t), intent(inout) :: self
    integer, intent(in) :: updates
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    real(rp), parameter :: ref_floor = 1.0e-4_rp, noise_ulps = 16.0_rp
    character(len=8), allocatable :: names(:), nk(:)
    character(len=3), allocatable :: units(:), uk(:)
    real(rp), allocatable :: res(:), ref(:), tol(:), noise(:)
    logical, allocatable :: ok(:)
    integer :: k, nf, last, r0
    character(len=msg_len) :: line, what
    allocate(names(0), units(0))
    do k = 1, size(self%slots)
      call self%slots(k)%c%residual_names(nk, uk)
      names = [names, nk]
      units = [units, uk]
    end do
    nf = size(names)
    allocate(res(nf), ref(nf), tol(nf), noise(nf), ok(nf))
    r0 = 0
    do k = 1, size(self%slots)
      call self%slots(k)%c%residual_names(nk, uk)
      call self%slots(k)%c%field_residuals(self%ctx, res(r0+1:r0+size(nk)), ref(r0+1:r0+size(nk)), &
                                           noise(r0+1:r0+size(nk)))
      r0 = r0 + size(nk)
    end do
    line = '  residual after update '//itoa(updates)//':'
    why = ''
    do k = 1, nf
      tol(k) = max(self%ctx%newton_tol * max(ref(k), ref_floor * self%ref_max(k)), &
                   noise_ulps * epsilon(1.0_rp) * noise(k))
      ok(k) = res(k) <= tol(k)
      if (.not. ok(k)) self%field_at(k) = 0
      if (ok(k) .and. self%field_at(k) == 0) self%field_at(k) = updates
      write(what, '(a,1x,es9.2,a,es9.2,1x,a)') trim(names(k)), res(k), merge(' <=', ' > ', ok(k)), tol(k), &
        trim(units(k))
      line = trim(line)//'  '//trim(what)
      if (.not. ok(k)) why = trim(why)//', '//trim(what)
    end do
    call log%detail(trim(line)//'  status changes '//itoa(int(self%changes)))
    self%residual_ratio = maxval(res / max(tol, tiny(1.0_rp)))
    converged = all(ok) .and. self%changes == 0
    if (self%changes > 0) why = trim(why)//', '//itoa(int(self%changes))//' status change(s) in the last update'
    call update_check(self, converged, why)
    if (len_trim(why) > 0) why = 'residual after the last update: '//why(3:)
    if (.not. converged) return
    ! (converged states only: a wild first iterate must not set the floor)
    self%ref_max = max(self%ref_max, ref)
    ! the last to settle: the field (or the active set) that met its
    ! tolerance at the latest update
    last = maxloc(self%field_at, dim=1)
    if (all(self%field_at == updates) .and. self%settled_at <= updates .and. updates == 1) then
      call log%detail('  converged after 1 update: every field within its tolerance, no status change')
    else if (self%settled_at > self%field_at(last)) then
      call log%detail('  converged after '//itoa(updates)//' update(s); the last to settle: the active set (no '// &
                      'status change from update '//itoa(self%settled_at)//' on)')
    else
      call log%detail('  converged after '//itoa(updates)//' update(s); the last field to converge: '// &
                      trim(names(last))//' (within its tolerance from update '//itoa(self%field_at(last))//' on)')
    end if
    do k = 1, size(self%slots)
      call self%slots(k)%c%status_notes(self%ctx, log)
    end do
  end subroutine check_residual

  !> A component's update_test fields (the fracture flow's: u and p), after
  !> an inexact (Krylov) solve: the residual does not bound the error of the
  !> fractures' pressure where a small storage holds it, nor of the opening
  !> it drives, so the last update of those fields, Newton's estimate of the
  !> previous iterate's error, must be below sqrt(newton_tol), so that this
  !> iterate's is near newton_tol. (The reduced nine fractures, FGMRES at
  !> rtol 1e-10 against MUMPS, differed by 1.5e-6 in pressure and 4.3e-6 in
  !> opening when the residual alone decided, and still so with the
  !> pressure's update alone. Not without the fluid: a fault block held
  !> only by its stick faults, the geostatic suite's dipping fault, has
  !> updates of u along a near null space that leave the residual at
  !> round-off.) When the last solve stopped above the deck's rtol (the
  !> forcing term of settled iterations), Newton converges linearly, not
  !> quadratically: the update must then be below newton_tol itself, which
  !> bounds this iterate's error where the iteration contracts by at least
  !> half. (With the quadratic bound the same case under the forcing term
  !> differed from MUMPS by 3.7e-6 in pressure and 9.4e-6 in opening; with
  !> this one by 1.5e-9 and 5.8e-9.)
  subroutine update_check(self, converged, why)
    type(coupled_simulation_t), intent(in) :: self
    logical, intent(inout) :: converged
    character(len=*), intent(inout) :: why
    character(len=msg_len) :: what, piece
    character(len=16) :: bound
    real(rp) :: largest, limit
    integer :: k, j
    if (.not. converged .or. self%solver%method == 'mumps') return
    limit = sqrt(self%ctx%newton_tol)
    bound = 'sqrt(newton_tol)'
    if (self%last_solve_rtol > self%solver%rtol) then
      limit = self%ctx%newton_tol
      bound = 'newton_tol'
    end if
    do k = 1, size(self%slots)
      if (.not. allocated(self%slots(k)%c%update_test)) cycle
      largest = 0.0_rp
      what = ''
      do j = 1, size(self%slots(k)%c%update_test)
        associate (f => self%slots(k)%c%update_test(j))
          largest = max(largest, rel_update_of(self, f))
          write(piece, '(a,es9.2)') '|d'//trim(f)//'|/|'//trim(f)//'| ', rel_update_of(self, f)
          if (j > 1) what = trim(what)//','
          what = trim(what)//' '//trim(piece)
        end associate
      end do
      if (.not. (largest > limit)) cycle
      converged = .false.
      write(piece, '(a,es9.2)') ' > '//trim(bound)//' = ', limit
      why = trim(why)//', the last update (Krylov) '//trim(adjustl(what))//trim(piece)
    end do
  end subroutine update_check

  !> |dx|/|x| of the last update of field f.
  real(rp) function rel_update_of(self, f) result(r)
    type(coupled_simulation_t), intent(in) :: self
    character(len=*), intent(in) :: f
    character(len=field_len), allocatable :: names(:)
    integer :: k, j, i
    r = 0.0_rp
    i = 0
    do k = 1, size(self%slots)
      call self%slots(k)%c%fields(names)
      do j = 1, size(names)
        i = i + 1
        if (names(j) == f) r = self%ctx%rel_update(i)
      end do
    end do
  end function rel_update_of

  !> Every component's part of the state (by field, not as the block
  !> vector: the block order depends on the solver, and a run may restart
  !> with another).
  subroutine save_state(self, st)
    class(coupled_simulation_t), intent(inout) :: self
    type(state_record_t), intent(inout) :: st
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%save_state(self%ctx, st)
    end do
    ! whether the step changed statuses: the next step's first solve
    ! (active_set_moving) is then the same in a resumed run
    call st%put('newton_step_moved', [merge(1, 0, self%step_moved)])
  end subroutine save_state

  subroutine load_state(self, st, status)
    class(coupled_simulation_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    integer :: k
    integer :: moved(1)
    do k = 1, size(self%slots)
      call self%slots(k)%c%load_state(self%ctx, st, status)
    end do
    call take_solution(self)
    ! (a checkpoint written before this entry existed: the next step is
    ! taken as a run's first)
    if (st%find('newton_step_moved') > 0) then
      call st%get('newton_step_moved', moved, status)
      self%step_moved = moved(1) == 1
    end if
  end subroutine load_state

  subroutine accept_step(self)
    class(coupled_simulation_t), intent(inout) :: self
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%accept_step(self%ctx)
    end do
  end subroutine accept_step

  subroutine write_output(self, out, status)
    class(coupled_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%write_output(self%ctx, out, status)
    end do
  end subroutine write_output

  subroutine probe_names(self, names)
    class(coupled_simulation_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    character(len=8), allocatable :: more(:)
    integer :: k
    allocate(names(0))
    do k = 1, size(self%slots)
      call self%slots(k)%c%probe_names(more)
      names = [names, more]
    end do
  end subroutine probe_names

  subroutine sample(self, pf, status)
    class(coupled_simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%sample(self%ctx, pf, status)
    end do
  end subroutine sample

  !> 'load step i/n  load x' or 'time step i  t x s', the iterations, the
  !> components' parts, the times.
  subroutine report_step(self, stats, line)
    class(coupled_simulation_t), intent(inout) :: self
    type(step_stats_t), intent(in) :: stats
    character(len=*), intent(out) :: line
    character(len=msg_len) :: piece
    integer :: k
    if (self%transient) then
      write(line, '(a,i0,a,es10.3,a,i3,a,i5)') 'time step ', stats%step, '  t ', stats%t, ' s  newton ', &
        stats%newton, '  linear its ', stats%linear_its
    else
      write(line, '(a,i0,a,i0,a,f6.3,a,i3,a,i5)') 'load step ', stats%step, '/', stats%n_steps, '  load ', stats%t, &
        '  newton ', stats%newton, '  linear its ', stats%linear_its
    end if
    do k = 1, size(self%slots)
      call self%slots(k)%c%progress(self%ctx, line)
    end do
    write(piece, '(a,f8.3,a,f8.3,a)') '  setup ', stats%t_setup, ' s  solve ', stats%t_solve, ' s'
    line = trim(line)//piece
  end subroutine report_step

  subroutine step_notes(self, lines)
    class(coupled_simulation_t), intent(inout) :: self
    character(len=msg_len), allocatable, intent(out) :: lines(:)
    integer :: k
    allocate(lines(0))
    do k = 1, size(self%slots)
      call self%slots(k)%c%step_notes(self%ctx, lines)
    end do
  end subroutine step_notes

  subroutine finish(self, log)
    class(coupled_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    integer :: k
    do k = 1, size(self%slots)
      call self%slots(k)%c%finish(self%ctx, log)
    end do
    if (self%cpc%reused > 0) call log%info('contact preconditioner: its Schur part kept at '//itoa(self%cpc%reused)// &
      ' Newton iteration(s) with every element sticking (&contact reuse)')
  end subroutine finish

  subroutine free(self)
    class(coupled_simulation_t), intent(inout) :: self
    integer :: k
    call self%cpc%free()
    call self%pfp%free()
    call self%mgr%free()
    if (allocated(self%slots)) then
      do k = 1, size(self%slots)
        call self%slots(k)%c%free()
      end do
    end if
    call self%ctx%sys%free()
    if (allocated(self%ctx%x)) deallocate(self%ctx%x, self%ctx%rhs, self%ctx%dx)
    if (allocated(self%dsc)) deallocate(self%dsc)
  end subroutine free
end module coupled_simulation
