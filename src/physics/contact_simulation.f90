!> physics = 'contact': elasticity with frictional faults (contact.f90) in
!> quasi-static load steps. Each step is an active-set loop whose iterations
!> are Newton steps on the current statuses (stick, slip, open), each a
!> block solve for the update: FGMRES on the scaled system with a contact
!> block preconditioner (contact_precon.f90), or MUMPS. The driver halves a
!> step whose loop does not converge in max_newton iterations (max_cuts
!> times, from &contact).
module contact_simulation
  use kinds, only: rp, ip, gp, name_len, msg_len, path_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use linear_system, only: linear_system_t
  use dist_vector, only: pnorm2
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use contact_config, only: contact_config_t
  use fault_config, only: read_faults, load_fault_histories
  use flow_config, only: flow_config_t, well_config_t, read_wells, load_well_histories, pressure_bc_t, &
                         read_pressure_bcs
  use dist_mesh, only: dist_mesh_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t, scalar_name_len
  use fracture_output, only: fracture_output_t
  use contact, only: contact_t, state_open, state_slip, max_flips
  use mesh_pieces, only: mesh_pieces_t
  use contact_precon, only: contact_precon_t
  use mgr_precon, only: mgr_precon_t, mgr_contact, mgr_flow
  use param_group, only: param_group_t
  use simulation, only: simulation_t, foreign_len, common_parameter_groups, step_stats_t
  implicit none
  private

  public :: contact_simulation_t

  !> Fewer interface elements than this are solved by MUMPS whatever the
  !> deck's method: the block preconditioners' AMG on a Schur complement of a
  !> few rows fails (1 element: 3 rows, hypre refuses the set-up); with 4
  !> elements all three block preconditioners converge.
  integer, parameter :: min_block_interfaces = 4
  !> smoothing sweeps, at least, of S*'s BoomerAMG on a slab with flat cells
  integer, parameter :: slab_sweeps = 3

  type, extends(simulation_t) :: contact_simulation_t
    type(contact_t) :: phys
    type(contact_config_t) :: ccfg                  !< &contact
    type(contact_precon_t) :: cpc
    type(mgr_precon_t) :: mgr                      !< &solver precon = 'mgr': hypre's MGR (the peer)
    type(fracture_output_t) :: fout
    character(len=path_len) :: fractures_xdmf = ''  !< the XDMF file of the fault fields, once open
    real(rp), allocatable :: dx(:)                  !< Newton update of the block vector
    real(rp), allocatable :: dsc(:)                 !< scaling of the block system
    real(rp) :: lf = 0.0_rp                         !< load factor of the step
    logical :: geo_step = .false.                   !< step 0: the in-situ equilibrium (&geostatic), faults bonded
    real(rp), allocatable :: u_geo(:)               !< local displacements of step 0 [m]: outputs are measured from them
    real(rp), allocatable :: jump_geo(:,:)          !< (3, local elements) jumps of step 0 [m]
    type(mesh_pieces_t) :: pieces                   !< connected pieces of the mesh (faults cut them)
    integer(gp) :: open_checked = -1                !< open elements when the pieces were last checked
    integer(gp), allocatable :: fault_counts(:,:)   !< (3, faults) stick/slip/open per fault, last reported
    ! physics = 'fracture_flow': the fluid in the fractures
    logical :: flow = .false.
    type(flow_config_t) :: fcfg                     !< &fracture_flow
    type(well_config_t), allocatable :: wells(:)    !< &well groups
    type(pressure_bc_t), allocatable :: pbcs(:)     !< &fracture_pressure groups
    ! the Newton loop's convergence test (check_residual)
    integer(gp) :: changes = 0                      !< status changes of the last update
    integer :: settled_at = 0                       !< the update from which no status changed (0: not yet)
    integer :: field_at(3) = 0                      !< per field, the update from which it is within tolerance
    real(rp) :: ref_max(3) = 0.0_rp                 !< per field, the largest magnitude of the run
    real(rp) :: last_du = 0.0_rp, last_dp = 0.0_rp   !< relative size of the last update of u and p
  contains
    procedure :: name
    procedure :: read_deck
    procedure :: foreign_inputs
    procedure :: parameter_groups
    procedure :: setup
    procedure :: open_output
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
    procedure :: controls_group
    procedure :: finish
    procedure :: check_residual
    procedure :: free
  end type contact_simulation_t

contains

  function name(self) result(s)
    class(contact_simulation_t), intent(in) :: self
    character(len=name_len) :: s
    s = merge('fracture_flow', 'contact      ', self%flow)
  end function name

  !> The shared groups, &contact and the &fault groups (with their pressure
  !> histories); the linear solver must suit a saddle point.
  subroutine read_deck(self, d, mcfg, log, status)
    class(contact_simulation_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call self%read_common(d, log, status, 'block', flow_conditions=.false., with_faults=.true.)
    if (status%ok()) call self%ccfg%read(d, log, status)
    if (status%ok()) call read_faults(d, log, self%faults, status, mcfg%source)
    if (status%ok()) call load_fault_histories(self%comm, self%faults, status)
    if (status%ok() .and. self%flow) call read_flow_groups(self, d, log, status)
    if (.not. status%ok()) return
    if (self%flow .and. self%geo%on) then
      call status%set("deck '"//trim(d%path)//"': &geostatic is not available for physics = 'fracture_flow' yet "// &
        "(elasticity, contact and biot have it)")
      return
    end if
    ! the in-situ and pressure-change loads are nodal: the bubbles' share of
    ! them is not made yet
    if (self%ccfg%space == 'bubble' .and. (self%geo%on .or. size(self%pcs) > 0)) then
      call d%fail(status, 'contact', 1, 'space', "'bubble' does not take &geostatic or &pressure_change yet "// &
        "(use space = 'stabilized')")
      return
    end if
    self%max_newton = self%ccfg%max_newton
    self%max_cuts = self%ccfg%max_cuts
    self%residual_test = .true.
    if (self%solver%method == 'cg') then
      call status%set("deck '"//trim(d%path)//"', group &solver, variable method: "// &
        "the contact system is a saddle point: use 'fgmres' or 'mumps'")
    else if (self%solver%method == 'fgmres' .and. self%solver%precon /= 'block' .and. self%solver%precon /= 'mgr') then
      call status%set("deck '"//trim(d%path)//"', group &solver, variable precon: the contact system with fgmres "// &
        "needs precon = 'block' (ours, &contact block) or 'mgr' (hypre's)")
    else if (size(self%faults) == 0) then
      call status%set("deck '"//trim(d%path)//"': physics = 'contact' needs at least one &fault group")
    end if
  end subroutine read_deck

  !> &fracture_flow, &well and &fracture_pressure (with their histories) of
  !> a 'fracture_flow' run, which steps in time; the fluid pressure is an
  !> unknown there, so a fault's prescribed pressure is refused. An
  !> incompressible fluid in a fault that starts closed with no prescribed
  !> pressure is refused too: nothing stores the fluid there, and the
  !> pressure system is singular.
  subroutine read_flow_groups(self, d, log, status)
    type(contact_simulation_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: k
    self%transient = .true.
    call self%fcfg%read(d, log, status)
    if (status%ok()) call read_wells(d, log, self%wells, status)
    if (status%ok()) call load_well_histories(self%comm, self%wells, status)
    if (status%ok()) call read_pressure_bcs(self%comm, d, log, [(self%faults(k)%name, k = 1, size(self%faults))], &
                                            self%pbcs, status)
    if (.not. status%ok()) return
    do k = 1, size(self%faults)
      if (self%faults(k)%pressure /= 0.0_rp .or. len_trim(self%faults(k)%pressure_history) > 0) then
        call d%fail(status, 'fault', k, 'pressure', "the fluid pressure is an unknown with physics = "// &
          "'fracture_flow' (set its start with &fracture_flow initial_pressure)")
        return
      end if
    end do
    do k = 1, size(self%faults)
      if (self%fcfg%compressibility > 0.0_rp .or. self%faults(k)%initial_state == 'open') cycle
      if (any(self%pbcs%fault == self%faults(k)%name)) cycle
      call d%fail(status, 'fracture_flow', 1, 'compressibility', "is 0 while fault '"//trim(self%faults(k)%name)// &
        "' starts closed (initial_state = '"//trim(self%faults(k)%initial_state)//"') with no &fracture_pressure:"// &
        " an incompressible fluid in a closed fracture leaves its pressure undetermined (a singular system);"// &
        " give compressibility > 0 (water: 4.5e-10 1/Pa) or start the fault open")
      return
    end do
    if (self%ccfg%space /= 'stabilized') then
      call d%fail(status, 'contact', 1, 'space', "'"//trim(self%ccfg%space)//"' is for physics = 'contact': "// &
        "physics = 'fracture_flow' has the space 'stabilized' only (its mass rows and preconditioner rest on H_t)")
      return
    end if
    if (self%solver%method /= 'mumps' .and. self%ccfg%block /= 'reordered') call status%set("deck '"// &
      trim(d%path)//"', group &contact, variable block: physics = 'fracture_flow' has the 'reordered' block "// &
      "preconditioner (with the pressure's Schur complement as its second level), or method = 'mumps'")
  end subroutine read_flow_groups

  !> Split nodes, tractions, patterns and the stabilization; the rigid-body
  !> check. The tractions come first in the block system for the reordered
  !> and augmented preconditioners. Collective.
  subroutine setup(self, mesh, log, status)
    class(contact_simulation_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=32) :: pcount
    self%mesh => mesh
    call check_split(mesh, status)
    if (.not. status%ok()) return
    if (self%solver%method /= 'mumps' .and. mesh%iface_map%n_global < min_block_interfaces) then
      ! a Schur complement of a few rows is no system for AMG (BoomerAMG
      ! refuses a 3 x 3 one): the whole system is small, a direct solve is cheap
      self%solver%method = 'mumps'
      call log%info('contact: only '//itoa(int(mesh%iface_map%n_global))//' interface element(s), fewer than '// &
        itoa(min_block_interfaces)//' for the block preconditioners: the direct solver MUMPS is used instead of '// &
        'FGMRES')
    end if
    if (self%flow) then
      call self%phys%init(mesh, self%mats, self%bcs, self%faults, self%ccfg%stabilization == 'algebraic', &
                          self%solver%method /= 'mumps', status, self%fcfg, self%wells, self%pbcs, &
                          p_second=self%solver%method /= 'mumps' .and. self%fcfg%pressure_block == 'eliminated')
    else
      call self%phys%init(mesh, self%mats, self%bcs, self%faults, self%ccfg%stabilization == 'algebraic', &
                          self%solver%method /= 'mumps' .and. self%ccfg%block /= 'classical', status, &
                          bubble=self%ccfg%space == 'bubble')
    end if
    call agree(self%comm, status)
    if (status%ok()) call self%phys%mech%init_in_situ(mesh, self%geo, self%mats, status)
    if (status%ok()) call self%phys%mech%init_pressure_changes(mesh, self%pcs, self%mats, status)
    call agree(self%comm, status)
    if (.not. status%ok()) return
    allocate(self%u_geo(size(self%phys%u)), self%jump_geo(3, mesh%n_ifaces))
    self%u_geo = 0.0_rp
    self%jump_geo = 0.0_rp
    if (self%geo%on) call log%info('geostatic: largest nodal force of the in-situ state out of equilibrium '// &
      '(the faults carry it): '//trim(rtoa(self%phys%mech%in_situ_imbalance(mesh)))// &
      ' of the largest nodal weight; step 0 balances it with the faults bonded')
    call self%pieces%build(mesh)
    call check_pieces(self, status)
    if (.not. status%ok()) return
    call warn_tip_skew(self, log)
    if (self%phys%bubble) call log%info('contact: space bubble, u has '// &
      itoa(int(self%phys%bub%map%n_global))//' face bubbles (3 unknowns each) beside the nodes')
    ! (merge wants arguments of equal lengths: the checked build stops on it)
    pcount = ''
    if (self%phys%flow) pcount = ', p '//itoa(int(mesh%iface_map%n_global))
    call log%info('unknowns: u '//itoa(int(self%phys%mech%u%map%n_global))//', t '// &
      itoa(int(self%phys%t%map%n_global))//trim(pcount)//' ('//itoa(int(mesh%iface_map%n_global))//' interface elements, '// &
      itoa(int(self%comm%sum(self%phys%edges%n)))//' stabilization edge entries)')
    if (self%flow) call log_wells(self, log)
    if (self%solver%method == 'mumps') then
      call log%info('linear solver: MUMPS (direct) at every Newton iteration')
    else
      if (self%solver%precon == 'mgr') then
        call log%info("linear solver: FGMRES with hypre's MGR on the whole system (GEOS's contact strategy: "// &
                      't by l1-Jacobi'//trim(merge(', then p by Jacobi', '                  ', self%flow))// &
                      ', u by BoomerAMG)')
      else
        call log%info('linear solver: FGMRES with the '//trim(self%ccfg%block)//' block preconditioner')
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
    allocate(self%dx(size(self%phys%x)), self%dsc(size(self%phys%x)))
  end subroutine setup

  !> The 'fractures' grid beside the mesh, in <prefix>_fractures.xdmf. Collective.
  subroutine open_output(self, out, status)
    class(contact_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    call self%fout%init(out, self%mesh, status)
    if (status%ok()) self%fractures_xdmf = out%writer%xdmf_path(self%fout%grid)
  end subroutine open_output

  !> Load factor t: the step's start is remembered (the slip increments and
  !> the stick conditions are measured from it), the prescribed displacements
  !> imposed, K and the loads assembled.
  subroutine begin_step(self, t, dt, status)
    class(contact_simulation_t), intent(inout) :: self
    real(rp), intent(in) :: t, dt
    type(error_status_t), intent(inout) :: status
    self%changes = 0
    self%settled_at = 0
    self%field_at = 0
    if (self%flow) then
      ! time t: the loads at full value times their histories at t
      self%lf = 1.0_rp
      call self%phys%mech%set_time(t)
      call self%phys%begin_step(1.0_rp)
      call self%phys%assemble_stiffness(self%mesh, 1.0_rp, t)
      call self%phys%take_solution(self%mesh)
      call self%phys%begin_flow_step(self%wells, self%pbcs, t, dt)
      return
    end if
    self%lf = t
    self%geo_step = self%initial_step .and. dt == 0.0_rp
    call self%phys%begin_step(t)
    call self%phys%assemble_stiffness(self%mesh, t)
    call self%phys%take_solution(self%mesh)
  end subroutine begin_step

  !> The contact rows of the Jacobian and the residual at the iterate.
  subroutine assemble(self, status)
    class(contact_simulation_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    call self%phys%assemble_newton(self%mesh)
  end subroutine assemble

  !> J dx = -r for the update (from zero); the block preconditioner follows
  !> the statuses, so it is refreshed at every iteration.
  subroutine linear_system(self, direct, sys, log, status)
    class(contact_simulation_t), intent(inout), target :: self
    logical, intent(in) :: direct
    type(linear_system_t), intent(inout) :: sys
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    real(rp) :: t0
    integer(ip) :: u0, u1
    call check_pieces(self, status)
    if (.not. status%ok()) return
    call sys%reset()
    self%dx = 0.0_rp
    sys%a => self%phys%sys
    sys%b => self%phys%rhs
    sys%x => self%dx
    sys%fields = block_fields(self%phys)
    if (direct) then
      call scaling(self)
      sys%d => self%dsc
      return
    end if
    t0 = wall_time()
    if (self%solver%precon == 'mgr') then
      call mgr_setup(self, status)
    else
      self%cpc%subspace = self%flow .and. self%fcfg%subspace_correction
      call self%cpc%setup(self%phys, self%mesh, self%ccfg, self%amg_k, status, self%fcfg%pressure_precon)
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
    sys%d => self%dsc
    sys%setup_time = wall_time() - t0
    call self%phys%sys%block_range(self%phys%bu, u0, u1)
    sys%k_ref => self%phys%sys%a(self%phys%bu, self%phys%bu)
    sys%b_ref => self%phys%rhs(u0:u1)
  end subroutine linear_system

  !> hypre's MGR on the whole system as the preconditioner (labels: the
  !> displacement and traction components, the pressure). Collective.
  subroutine mgr_setup(self, status)
    type(contact_simulation_t), intent(inout), target :: self
    type(error_status_t), intent(inout) :: status
    integer :: ncomp(3), first(3)
    associate (phys => self%phys)
      ncomp(phys%bu) = 3
      first(phys%bu) = 0
      ncomp(phys%bt) = 3
      first(phys%bt) = 3
      if (self%flow) then
        ncomp(phys%bp) = 1
        first(phys%bp) = 6
        call self%mgr%setup_blocks(phys%sys, ncomp, first, mgr_flow(), self%amg, status)
      else
        call self%mgr%setup_blocks(phys%sys, ncomp(1:2), first(1:2), mgr_contact(), self%amg, status)
      end if
    end associate
  end subroutine mgr_setup

  !> Every piece of the mesh, with the pieces joined by interface elements
  !> that are not open, must be held by the displacement conditions (checked
  !> again whenever the number of open elements changes). Collective.
  subroutine check_pieces(self, status)
    type(contact_simulation_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer(gp), allocatable :: joins(:,:)
    integer(gp) :: n_open, pair(2)
    integer(ip) :: e, n, j
    associate (mesh => self%mesh, st => self%phys%state)
      n_open = self%comm%sum(int(count(st(1:mesh%iface_map%n_owned) == state_open), gp))
      if (n_open == self%open_checked) return
      ! the distinct pairs of pieces that holding owned elements join
      allocate(joins(2, 8))
      n = 0
      do e = 1, mesh%iface_map%n_owned
        if (st(e) == state_open) cycle
        pair = [self%pieces%label(mesh%iface_nodes(1, 1, e)), self%pieces%label(mesh%iface_nodes(1, 2, e))]
        if (pair(1) == pair(2)) cycle
        if (any([(joins(1, j) == pair(1) .and. joins(2, j) == pair(2), j = 1, n)])) cycle
        if (n == size(joins, 2)) joins = reshape([joins, joins], [2, 2 * n])
        n = n + 1
        joins(:, n) = pair
      end do
      call self%phys%mech%check_anchored(mesh, self%pieces, status, joins(:, 1:n))
      if (status%ok()) self%open_checked = n_open
    end associate
  end subroutine check_pieces

  !> A warning per fault whose tip elements sit on cells skewed by more than
  !> max_tip_skew degrees from its normal. Collective.
  subroutine warn_tip_skew(self, log)
    type(contact_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    real(rp), parameter :: max_tip_skew = 5.0_rp
    real(rp), allocatable :: skew(:)
    integer :: f
    allocate(skew(size(self%faults)))
    skew = self%phys%tip_skew(self%mesh)
    do f = 1, size(skew)
      if (skew(f) > max_tip_skew) call log%warn("fault '"//trim(self%faults(f)%name)// &
        "': the cells at its tips cross it at up to "//rtoa(real(nint(skew(f)), rp))//' degrees from its normal: '// &
        'where it slips, its tip elements'' tractions are then wrong by a share that grows under refinement; '// &
        'mesh the tip regions with cells perpendicular to the fault (doc/contact.md, tips on skewed cells)')
    end do
  end subroutine warn_tip_skew

  !> Symmetric scaling 1/sqrt of the diagonal of K (u rows) and of H~ (t rows),
  !> for the Krylov and the direct solver alike.
  !> The fields of the blocks in block order, comma separated ('t,u,p').
  function block_fields(phys) result(names)
    type(contact_t), intent(in) :: phys
    character(len=16) :: names
    character(len=1) :: f(3)
    integer :: nb
    nb = merge(3, 2, phys%flow)
    f(phys%bu) = 'u'
    f(phys%bt) = 't'
    if (phys%flow) f(phys%bp) = 'p'
    names = f(1)//','//f(2)
    if (nb == 3) names = trim(names)//','//f(3)
  end function block_fields

  subroutine scaling(self)
    type(contact_simulation_t), intent(inout) :: self
    integer(ip) :: u0, u1, t0, t1
    call self%phys%sys%block_range(self%phys%bu, u0, u1)
    call self%phys%sys%block_range(self%phys%bt, t0, t1)
    call self%phys%sys%a(self%phys%bu, self%phys%bu)%diagonal(self%dsc(u0:u1))
    call self%phys%ht_diagonal(self%mesh, 1.0_rp, .true., self%dsc(t0:t1))
    if (self%flow) then
      call self%phys%sys%block_range(self%phys%bp, u0, u1)
      call self%phys%sys%a(self%phys%bp, self%phys%bp)%diagonal(self%dsc(u0:u1))
    end if
    self%dsc = 1.0_rp / sqrt(abs(self%dsc))
  end subroutine scaling

  !> x += dx, the new jumps and tractions, the active-set update. Whether
  !> the step has converged is judged on the residual of the new iterate
  !> (check_residual, after the next assembly), so converged stays false.
  subroutine update(self, iteration, linear_its, log, converged, why, status)
    class(contact_simulation_t), intent(inout) :: self
    integer, intent(in) :: iteration, linear_its
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    type(error_status_t), intent(inout) :: status
    integer(gp) :: n(3)
    integer(ip) :: u0, u1, t0, t1
    real(rp) :: du, dt, dp
    character(len=msg_len) :: line
    associate (phys => self%phys, comm => self%comm)
      call phys%sys%block_range(phys%bu, u0, u1)
      call phys%sys%block_range(phys%bt, t0, t1)
      phys%x = phys%x + self%dx
      call phys%take_solution(self%mesh)
      ! step 0 (&geostatic) balances the in-situ state with the faults bonded
      self%changes = 0
      if (.not. self%geo_step) self%changes = phys%update_states(self%mesh, self%ccfg%status_tol)
      if (self%changes > 0) self%settled_at = 0
      if (self%changes == 0 .and. self%settled_at == 0) self%settled_at = iteration
      du = pnorm2(comm, self%dx(u0:u1)) / max(pnorm2(comm, phys%x(u0:u1)), tiny(1.0_rp))
      dt = pnorm2(comm, self%dx(t0:t1)) / max(pnorm2(comm, phys%x(t0:t1)), tiny(1.0_rp))
      n = phys%count_states(self%mesh)
      dp = 0.0_rp
      if (phys%flow) then
        call phys%sys%block_range(phys%bp, t0, t1)
        dp = pnorm2(comm, self%dx(t0:t1)) / max(pnorm2(comm, phys%x(t0:t1)), tiny(1.0_rp))
      end if
    end associate
    self%last_du = du
    self%last_dp = dp
    write(line, '(a,i3,a,i5,a,es9.2,a,es9.2,a,i0,a,3(i0,a))') '  newton ', iteration, '  linear its ', linear_its, &
      '  |du|/|u| ', du, &
      '  |dt|/|t| ', dt, '  status changes ', self%changes, '  stick/slip/open ', n(1), '/', n(2), '/', n(3), ''
    if (self%flow) write(line, '(a,a,es9.2)') trim(line), '  |dp|/|p| ', dp
    call log%detail(line)
    converged = .false.
    why = ''
  end subroutine update

  !> The residual of the iterate per field in physical units (contact_t
  !> field_residuals: force [N], traction [Pa], fluid volume of the step
  !> [m^3]), each against newton_tol times the magnitude it balances (at
  !> least ref_floor times the largest such magnitude of the run, so that a
  !> field at rest is not asked for digits below round-off of its earlier
  !> steps), and never below noise_ulps * eps times the magnitude of its
  !> terms' operands: what double precision can resolve. (A fracture whose
  !> cubic-law transmissibility dwarfs its storage, an aperture of 1 cm in
  !> 1 mm cells holding a fluid of c_f 1e-14, balances a step's volume of
  !> 6e-14 m^3 with flow terms of 0.25 m^3 each: its residual stalled at
  !> 1.2e-19 m^3, round-off, above newton_tol times 6e-14.) Converged
  !> when every field is within its tolerance and the last update changed
  !> no status. A detail line per iteration; at
  !> convergence, which field (or the active set) was the last to settle.
  subroutine check_residual(self, updates, log, converged, why)
    class(contact_simulation_t), intent(inout) :: self
    integer, intent(in) :: updates
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    real(rp), parameter :: ref_floor = 1.0e-4_rp, noise_ulps = 16.0_rp, hold_tol = 1.0e-3_rp
    character(len=8), parameter :: names(3) = [character(len=8) :: 'force', 'traction', 'volume']
    character(len=3), parameter :: units(3) = [character(len=3) :: 'N', 'Pa', 'm3']
    real(rp) :: res(3), ref(3), tol(3), noise(3)
    logical :: ok(3)
    integer :: k, nf, last
    character(len=msg_len) :: line, what
    call self%phys%field_residuals(self%mesh, res, ref, noise)
    nf = merge(3, 2, self%flow)
    line = '  residual after update '//itoa(updates)//':'
    why = ''
    do k = 1, nf
      tol(k) = max(self%ccfg%newton_tol * max(ref(k), ref_floor * self%ref_max(k)), &
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
    self%residual_ratio = maxval(res(1:nf) / max(tol(1:nf), tiny(1.0_rp)))
    converged = all(ok(1:nf)) .and. self%changes == 0
    if (self%changes > 0) why = trim(why)//', '//itoa(int(self%changes))//' status change(s) in the last update'
    ! an element held in its status after max_flips changes is accepted
    ! only where it sits on its limit: violated by at most hold_tol (a
    ! traction over the largest on the faults, an overlap over the largest
    ! jump). Beyond, the held status is wrong, not degenerate: the answer
    ! would break the contact conditions, so the step does not converge.
    if (self%phys%held_excess > hold_tol) then
      converged = .false.
      write(what, '(es9.2)') self%phys%held_excess
      why = trim(why)//', an element held in its status violates it by '//trim(adjustl(what))// &
            ' (relative; at most '//trim(rtoa(hold_tol))//')'
    end if
    ! with the fluid, after an inexact (Krylov) solve, the residual does not
    ! bound the error of the fractures' pressure where a small storage
    ! holds it, nor of the opening it drives: the last update of u and p,
    ! Newton's estimate of the previous iterate's error, must be below
    ! sqrt(newton_tol), so that this iterate's is near newton_tol. (The
    ! reduced nine fractures, FGMRES at rtol 1e-10 against MUMPS, differed
    ! by 1.5e-6 in pressure and 4.3e-6 in opening when the residual alone
    ! decided, and still so with the pressure's update alone. Not without
    ! the fluid: a fault block held only by its stick faults, the geostatic
    ! suite's dipping fault, has updates of u along a near null space that
    ! leave the residual at round-off.)
    if (converged .and. self%flow .and. self%solver%method /= 'mumps' .and. &
        max(self%last_du, self%last_dp) > sqrt(self%ccfg%newton_tol)) then
      converged = .false.
      write(what, '(a,es9.2,a,es9.2,a,es9.2)') '|du|/|u| ', self%last_du, ', |dp|/|p| ', self%last_dp, &
        ' > sqrt(newton_tol) = ', sqrt(self%ccfg%newton_tol)
      why = trim(why)//', the last update (Krylov) '//trim(what)
    end if
    if (len_trim(why) > 0) why = 'residual after the last update: '//why(3:)
    if (.not. converged) return
    ! (converged states only: a wild first iterate must not set the floor)
    self%ref_max(1:nf) = max(self%ref_max(1:nf), ref(1:nf))
    ! the last to settle: the field (or the active set) that met its
    ! tolerance at the latest update
    last = maxloc(self%field_at(1:nf), dim=1)
    if (all(self%field_at(1:nf) == updates) .and. self%settled_at <= updates .and. updates == 1) then
      call log%detail('  converged after 1 update: every field within its tolerance, no status change')
    else if (self%settled_at > self%field_at(last)) then
      call log%detail('  converged after '//itoa(updates)//' update(s); the last to settle: the active set (no '// &
                      'status change from update '//itoa(self%settled_at)//' on)')
    else
      call log%detail('  converged after '//itoa(updates)//' update(s); the last field to converge: '// &
                      trim(names(last))//' (within its tolerance from update '//itoa(self%field_at(last))//' on)')
    end if
    call warn_held(self, log)
  end subroutine check_residual

  !> After step 0 (&geostatic): per fault, the elements whose in-situ
  !> traction lies beyond the Coulomb limit (tension, or |t_T| > c - tan(phi)
  !> t_N beyond status_tol): bonded in step 0, they slip or open at step 1.
  !> Collective.
  function in_situ_notes(self) result(lines)
    type(contact_simulation_t), intent(in) :: self
    character(len=msg_len), allocatable :: lines(:)
    integer(gp), allocatable :: beyond(:)
    real(rp) :: tmax, tau
    integer(ip) :: e
    integer :: f
    allocate(beyond(size(self%mesh%fault_names)), lines(0))
    beyond = 0
    tmax = self%comm%max(max(0.0_rp, maxval(abs(self%phys%trac(:, 1:self%mesh%iface_map%n_owned)))))
    do e = 1, self%mesh%iface_map%n_owned
      associate (t => self%phys%trac(:, e))
        tau = self%phys%coh(e) - self%phys%fric(e) * t(1)
        if (t(1) > self%ccfg%status_tol * tmax .or. norm2(t(2:3)) > tau + self%ccfg%status_tol * tmax) &
          beyond(self%mesh%iface_fault(e)) = beyond(self%mesh%iface_fault(e)) + 1
      end associate
    end do
    call self%comm%sum_all(beyond)
    do f = 1, size(beyond)
      if (beyond(f) > 0) lines = [character(len=msg_len) :: lines, "geostatic: fault '"// &
        trim(self%mesh%fault_names(f))//"': "//itoa(int(beyond(f)))//' element(s) start beyond the Coulomb limit '// &
        '(bonded in step 0, they slip or open at step 1)']
    end do
    lines = [character(len=msg_len) :: lines, 'geostatic: in-situ state balanced with the faults bonded, max |u| '// &
      'of step 0 = '//trim(rtoa(self%comm%max(max(0.0_rp, maxval(abs(self%phys%u))))))// &
      ' m (displacements and jumps are measured from it)']
  end function in_situ_notes

  !> Per fault, the elements the active set held in their status in this
  !> step: max_flips status changes (contact.f90), the blocked one between
  !> stick and slip (held) or to or from open (held_open).
  subroutine warn_held(self, log)
    type(contact_simulation_t), intent(in) :: self
    type(logger_t), intent(inout) :: log
    integer :: f
    if (.not. allocated(self%phys%held)) return
    do f = 1, size(self%phys%held)
      if (self%phys%held(f) > 0) call log%warn("fault '"//trim(self%phys%faults(f)%name)//"': "// &
        itoa(int(self%phys%held(f)))//' element(s) changed status '//itoa(max_flips)//' times in this step and '// &
        'were held in it (stick <-> slip: they sit on the friction limit within &contact status_tol)')
      if (self%phys%held_open(f) > 0) call log%warn("fault '"//trim(self%phys%faults(f)%name)//"': "// &
        itoa(int(self%phys%held_open(f)))//' element(s) changed status '//itoa(max_flips)//' times in this step and '// &
        'were held in it (open <-> closed: they sit at the opening, t_N and g_N zero within &contact '// &
        'status_tol)')
    end do
    if (any(self%phys%held > 0) .or. any(self%phys%held_open > 0)) call log%detail('  held elements: largest '// &
      'violation of the held status '//trim(rtoa(self%phys%held_excess))//' (relative)')
  end subroutine warn_held

  !> The block vector (displacements and tractions) and the statuses; the
  !> rest follows from them.
  !> The unknowns by field ('x_u', 'x_t', 'x_p'), not as the block vector:
  !> the block order depends on the solver (MUMPS: u, t, p; the reordered
  !> preconditioners t first; pressure_block = 'eliminated' t, p, u), and a
  !> run may restart with another.
  subroutine save_state(self, st)
    class(contact_simulation_t), intent(inout) :: self
    type(state_record_t), intent(inout) :: st
    integer(ip) :: i0, i1
    call self%phys%sys%block_range(self%phys%bu, i0, i1)
    call st%put('x_u', self%phys%x(i0:i1))
    call self%phys%sys%block_range(self%phys%bt, i0, i1)
    call st%put('x_t', self%phys%x(i0:i1))
    if (self%flow) then
      call self%phys%sys%block_range(self%phys%bp, i0, i1)
      call st%put('x_p', self%phys%x(i0:i1))
    end if
    call st%put('status', self%phys%state)
    if (self%geo%on) then
      call st%put('displacement_in_situ', self%u_geo(1:self%phys%mech%u%n_owned()))
      call st%put('jump_in_situ', reshape(self%jump_geo(:, 1:self%mesh%iface_map%n_owned), &
                                          [3 * self%mesh%iface_map%n_owned]))
    end if
  end subroutine save_state

  !> Step 0 (&geostatic) is accepted: its displacements and jumps, the
  !> balance of the in-situ state on this mesh with the faults bonded,
  !> become the origin of the outputs'.
  subroutine accept_step(self)
    class(contact_simulation_t), intent(inout) :: self
    if (.not. self%geo_step) return
    self%u_geo = self%phys%u
    self%jump_geo = self%phys%jump
  end subroutine accept_step

  subroutine load_state(self, st, status)
    class(contact_simulation_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i0, i1
    call self%phys%sys%block_range(self%phys%bu, i0, i1)
    call st%get('x_u', self%phys%x(i0:i1), status)
    call self%phys%sys%block_range(self%phys%bt, i0, i1)
    call st%get('x_t', self%phys%x(i0:i1), status)
    if (self%flow) then
      call self%phys%sys%block_range(self%phys%bp, i0, i1)
      call st%get('x_p', self%phys%x(i0:i1), status)
    end if
    call st%get('status', self%phys%state, status)
    call self%phys%take_solution(self%mesh)
    if (self%geo%on) call load_in_situ(self, st, status)
    self%fault_counts = counts_per_fault(self)
  end subroutine load_state

  !> The step-0 state of a checkpoint (&geostatic): displacements and jumps.
  subroutine load_in_situ(self, st, status)
    type(contact_simulation_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: jg(:)
    integer(ip) :: no
    no = self%mesh%iface_map%n_owned
    allocate(jg(3 * no))
    call st%get('displacement_in_situ', self%u_geo(1:self%phys%mech%u%n_owned()), status)
    call st%get('jump_in_situ', jg, status)
    if (.not. status%ok()) return
    call self%phys%mech%u%map%import(self%u_geo)
    self%jump_geo(:, 1:no) = reshape(jg, [3, int(no)])
  end subroutine load_in_situ

  !> displacement, stress, region, rank (mesh grid) and the fault fields
  !> (fractures grid, fracture_output.f90; status there 0 stick, 1 slip, 2 open).
  subroutine write_output(self, out, status)
    class(contact_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: stress(:,:)
    allocate(stress(6, self%mesh%cell_map%n_owned))
    call self%phys%mech%cell_stress(self%mesh, self%phys%u, stress)
    call out%write_displacement(self%mesh, self%phys%u - self%u_geo, status)
    if (status%ok()) call out%writer%cell_field('stress', stress, status)
    call out%write_mesh_ids(self%mesh, status)
    if (status%ok() .and. size(self%phys%mech%pcs) > 0) &
      call out%writer%cell_field('pressure_change', self%phys%mech%pressure_change_field(self%mesh, self%lf), status)
    ! the output's status codes count from 0 (state_stick = 1, slip 2, open 3)
    if (status%ok()) call self%fout%write_step(out, self%mesh, self%phys%trac, self%phys%jump - self%jump_geo, &
                                                self%phys%state - 1, &
                                                self%phys%rot, self%phys%fric, self%phys%coh, status)
    if (.not. self%flow .and. status%ok()) then
      ! the fluid pressure on the faces: &fault pressure, the in-situ p0 and
      ! the mean &pressure_change of the two cells, at the step's load
      associate (n => self%mesh%iface_map%n_owned)
        call out%writer%cell_field('pressure', self%phys%pres(1:n), status, self%fout%grid)
      end associate
    end if
    if (self%flow .and. status%ok()) then
      associate (n => self%mesh%iface_map%n_owned)
        call out%writer%cell_field('pressure', self%phys%p(1:n), status, self%fout%grid)
        if (status%ok()) call out%writer%cell_field('aperture', self%phys%ff%aperture(1:n), status, self%fout%grid)
        if (status%ok()) call out%writer%cell_field('area', self%phys%area(1:n), status, self%fout%grid)
        if (status%ok()) call out%writer%cell_field('flux', &
          norm2(self%phys%ff%element_flux(self%mesh, self%phys%edges, self%phys%p), dim=1), status, self%fout%grid)
      end associate
    end if
  end subroutine write_output

  !> Displacement and stress for the probes.
  subroutine probe_names(self, names)
    class(contact_simulation_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    names = [character(len=8) :: 'ux', 'uy', 'uz', 'sxx', 'syy', 'szz', 'sxy', 'syz', 'sxz']
  end subroutine probe_names

  !> The probes' fields, and per fault (mesh order) its largest slip
  !> (tangential jump) and slipping area (elements with status slip).
  subroutine sample(self, pf, status)
    class(contact_simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: smax(:), area(:)
    integer(ip) :: e, nd
    integer :: f, nf
    pf%u = self%phys%nodal_u(self%mesh)
    if (self%geo%on) then
      do nd = 1, self%mesh%n_nodes
        pf%u(3*nd-2:3*nd) = pf%u(3*nd-2:3*nd) - self%u_geo(self%phys%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))
      end do
    end if
    allocate(pf%stress(6, self%mesh%cell_map%n_owned))
    call self%phys%mech%cell_stress(self%mesh, self%phys%u, pf%stress)
    nf = size(self%mesh%fault_names)
    allocate(smax(nf), area(nf), pf%names(2 * nf), pf%values(2 * nf))
    smax = 0.0_rp
    area = 0.0_rp
    do e = 1, self%mesh%iface_map%n_owned
      f = self%mesh%iface_fault(e)
      smax(f) = max(smax(f), norm2(self%phys%jump(2:3, e) - self%jump_geo(2:3, e)))
      if (self%phys%state(e) == state_slip) area(f) = area(f) + self%phys%area(e)
    end do
    call self%comm%sum_all(area)
    do f = 1, nf
      pf%names(2*f - 1) = trim(self%mesh%fault_names(f))//':max_slip [m]'
      pf%names(2*f) = trim(self%mesh%fault_names(f))//':slip_area [m2]'
      pf%values(2*f - 1) = self%comm%max(smax(f))
      pf%values(2*f) = area(f)
    end do
    if (self%flow) call sample_wells(self, pf)
  end subroutine sample

  !> One line per well: where it meets the fractures (the element centre of
  !> each connection, and for a segment well Peaceman's equivalent radius).
  subroutine log_wells(self, log)
    type(contact_simulation_t), intent(in) :: self
    type(logger_t), intent(inout) :: log
    character(len=:), allocatable :: line
    integer :: k, c
    associate (wl => self%phys%wl)
      do k = 1, size(self%wells)
        line = "well '"//trim(self%wells(k)%name)//"': "
        if (wl%along(k)) line = line//'along its segment, the rate split by pressure among '// &
                                itoa(wl%n_conn(k))//' fault(s):'
        do c = wl%first(k), wl%first(k + 1) - 1
          line = line//" '"//trim(self%mesh%fault_names(wl%fault(c)))//"' element at ("// &
                 rtoa(wl%centre(1, c))//', '//rtoa(wl%centre(2, c))//', '//rtoa(wl%centre(3, c))//')'
          if (wl%along(k)) line = line//' r_e '//rtoa(wl%r_e(c))//' m'
          if (c < wl%first(k + 1) - 1) line = line//';'
        end do
        call log%info(line)
      end do
    end associate
  end subroutine log_wells

  !> Per well, the step's rate and its bottom-hole pressure (of its element
  !> for a well at a point, of the wellbore for one along a segment), per
  !> connection of a segment well its rate and its element's pressure, and
  !> per fault the largest pressure and the fluid volume it holds (sum of
  !> A g_N over its open elements). Collective.
  subroutine sample_wells(self, pf)
    type(contact_simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    character(len=scalar_name_len), allocatable :: names(:)
    real(rp), allocatable :: values(:), pmax(:), vol(:), pw(:), qc(:), pc(:)
    integer :: k, nf, f, c
    integer(ip) :: e
    associate (wl => self%phys%wl)
      nf = size(self%mesh%fault_names)
      allocate(pw(size(self%wells)), qc(size(wl%gid)), pc(size(wl%gid)))
      pw = wl%bottom_hole(self%phys%p)
      qc = wl%rates(self%phys%p)
      pc = 0.0_rp
      where (wl%mine) pc = self%phys%p(max(wl%elem, 1))
      call self%comm%sum_all(qc)
      call self%comm%sum_all(pc)
      allocate(names(0), values(0))
      do k = 1, size(self%wells)
        names = [character(len=scalar_name_len) :: names, trim(self%wells(k)%name)//':rate [m3/s]', &
                 trim(self%wells(k)%name)//':pressure [Pa]']
        values = [values, wl%q(k), pw(k)]
        if (.not. wl%along(k)) cycle
        do c = wl%first(k), wl%first(k + 1) - 1
          associate (tag => trim(self%wells(k)%name)//'@'//trim(self%mesh%fault_names(wl%fault(c))))
            names = [character(len=scalar_name_len) :: names, tag//':rate [m3/s]', tag//':pressure [Pa]']
          end associate
          values = [values, qc(c), pc(c)]
        end do
      end do
    end associate
    allocate(pmax(nf), vol(nf))
    pmax = -huge(1.0_rp)
    vol = 0.0_rp
    do e = 1, self%mesh%iface_map%n_owned
      f = self%mesh%iface_fault(e)
      pmax(f) = max(pmax(f), self%phys%p(e))
      vol(f) = vol(f) + self%phys%area(e) * max(self%phys%jump(1, e), 0.0_rp)
    end do
    call self%comm%sum_all(vol)
    do f = 1, nf
      names = [character(len=scalar_name_len) :: names, trim(self%mesh%fault_names(f))//':max_pressure [Pa]', &
               trim(self%mesh%fault_names(f))//':fluid_volume [m3]']
      values = [values, self%comm%max(pmax(f)), vol(f)]
    end do
    pf%names = [pf%names, names]
    pf%values = [pf%values, values]
  end subroutine sample_wells

  subroutine report_step(self, stats, line)
    class(contact_simulation_t), intent(inout) :: self
    type(step_stats_t), intent(in) :: stats
    character(len=*), intent(out) :: line
    integer(gp) :: n(3)
    n = self%phys%count_states(self%mesh)
    if (self%flow) then
      write(line, '(a,i0,a,es10.3,a,i3,a,i5,a,3(i0,a),a,es10.3,a,es10.3,a,f8.3,a,f8.3,a)') 'time step ', stats%step, &
        '  t ', stats%t, ' s  newton ', stats%newton, '  linear its ', stats%linear_its, &
        '  stick/slip/open ', n(1), '/', n(2), '/', n(3), '', &
        '  max slip ', max_slip(self), ' m  max p ', self%comm%max(maxval(self%phys%p(1:self%mesh%iface_map%n_owned))), &
        ' Pa  setup ', stats%t_setup, ' s  solve ', stats%t_solve, ' s'
      return
    end if
    write(line, '(a,i0,a,i0,a,f6.3,a,i3,a,i5,a,3(i0,a),a,es10.3,a,f8.3,a,f8.3,a)') 'load step ', stats%step, '/', &
      stats%n_steps, '  load ', stats%t, '  newton ', stats%newton, '  linear its ', stats%linear_its, &
      '  stick/slip/open ', n(1), '/', n(2), '/', n(3), '', '  max slip ', max_slip(self), ' m  setup ', &
      stats%t_setup, ' s  solve ', stats%t_solve, ' s'
  end subroutine report_step

  !> max_newton and max_cuts are in &contact, with fluid or without.
  function controls_group(self) result(g)
    class(contact_simulation_t), intent(in) :: self
    character(len=name_len) :: g
    g = 'contact'
  end function controls_group

  !> One line per fault whose stick/slip/open counts changed since the last
  !> report (all faults at the first), e.g.
  !>   fault 'f3': stick/slip/open 49/0/0 -> 12/37/0 (slip starts)
  !> Collective.
  subroutine step_notes(self, lines)
    class(contact_simulation_t), intent(inout) :: self
    character(len=msg_len), allocatable, intent(out) :: lines(:)
    integer(gp), allocatable :: now(:,:)
    character(len=msg_len) :: starts
    integer :: f, n, k
    character(len=5), parameter :: what(3) = ['stick', 'slip ', 'open ']
    allocate(now(3, size(self%mesh%fault_names)))
    now = counts_per_fault(self)
    allocate(lines(size(now, 2)))
    n = 0
    do f = 1, size(now, 2)
      if (allocated(self%fault_counts)) then
        if (all(now(:, f) == self%fault_counts(:, f))) cycle
      end if
      n = n + 1
      lines(n) = "fault '"//trim(self%mesh%fault_names(f))//"': stick/slip/open "//counts_text(now(:, f))
      if (allocated(self%fault_counts)) then
        lines(n) = "fault '"//trim(self%mesh%fault_names(f))//"': stick/slip/open "// &
                   trim(counts_text(self%fault_counts(:, f)))//' -> '//counts_text(now(:, f))
        starts = ''
        do k = 1, 3
          if (now(k, f) > 0 .and. self%fault_counts(k, f) == 0) starts = trim(starts)//', '//trim(what(k))//' starts'
          if (now(k, f) == 0 .and. self%fault_counts(k, f) > 0) starts = trim(starts)//', no '//trim(what(k))//' left'
        end do
        if (len_trim(starts) > 0) lines(n) = trim(lines(n))//' ('//starts(3:len_trim(starts))//')'
      end if
    end do
    lines = lines(1:n)
    self%fault_counts = now
    if (self%geo_step) lines = [lines, in_situ_notes(self)]
  contains
    function counts_text(c) result(t)
      integer(gp), intent(in) :: c(3)
      character(len=msg_len) :: t
      t = itoa(int(c(1)))//'/'//itoa(int(c(2)))//'/'//itoa(int(c(3)))
    end function counts_text
  end subroutine step_notes

  !> Global stick/slip/open counts of every fault (3, faults). Collective.
  function counts_per_fault(self) result(c)
    type(contact_simulation_t), intent(in) :: self
    integer(gp), allocatable :: c(:,:)
    integer(gp), allocatable :: flat(:)
    integer(ip) :: e
    allocate(c(3, size(self%mesh%fault_names)))
    c = 0
    do e = 1, self%mesh%iface_map%n_owned
      c(self%phys%state(e), self%mesh%iface_fault(e)) = c(self%phys%state(e), self%mesh%iface_fault(e)) + 1
    end do
    flat = reshape(c, [size(c)])                  ! one reduction for every fault
    call self%comm%sum_all(flat)
    c = reshape(flat, shape(c))
  end function counts_per_fault

  !> Largest tangential jump over the faults [m]. Collective.
  real(rp) function max_slip(self)
    type(contact_simulation_t), intent(in) :: self
    integer(ip) :: e
    max_slip = 0.0_rp
    do e = 1, self%mesh%iface_map%n_owned
      max_slip = max(max_slip, norm2(self%phys%jump(2:3, e) - self%jump_geo(2:3, e)))
    end do
    max_slip = self%comm%max(max_slip)
  end function max_slip

  subroutine finish(self, log)
    class(contact_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    if (len_trim(self%fractures_xdmf) > 0) &
      call log%info('fault fields: '//trim(self%fractures_xdmf)//' (open it in ParaView)')
    if (self%cpc%reused > 0) call log%info('contact preconditioner: its Schur part kept at '//itoa(self%cpc%reused)// &
      ' Newton iteration(s) with every element sticking (&contact reuse)')
  end subroutine finish

  subroutine free(self)
    class(contact_simulation_t), intent(inout) :: self
    call self%cpc%free()
    call self%mgr%free()
    call self%phys%free()
    if (allocated(self%dx)) deallocate(self%dx, self%dsc)
    if (allocated(self%u_geo)) deallocate(self%u_geo, self%jump_geo)
  end subroutine free
  !> The resolved groups: the shared ones, then every &fault and &contact.
  subroutine parameter_groups(self, groups)
    class(contact_simulation_t), intent(in) :: self
    type(param_group_t), allocatable, intent(out) :: groups(:)
    type(param_group_t), allocatable :: common(:)
    integer :: k, n, nflow
    call common_parameter_groups(self, common)
    n = size(common)
    ! (not merge: it would take the sizes of the flow's arrays, which a
    ! contact run never allocates)
    nflow = 0
    if (self%flow) nflow = 1 + size(self%wells) + size(self%pbcs)
    allocate(groups(n + size(self%faults) + 1 + nflow))
    groups(1:n) = common
    do k = 1, size(self%faults)
      call self%faults(k)%describe(groups(n + k))
    end do
    call self%ccfg%describe(groups(n + size(self%faults) + 1))
    if (self%flow) then
      n = n + size(self%faults) + 1
      call self%fcfg%describe(groups(n + 1))
      do k = 1, size(self%wells)
        call self%wells(k)%describe(groups(n + 1 + k))
      end do
      do k = 1, size(self%pbcs)
        call self%pbcs(k)%describe(groups(n + 1 + size(self%wells) + k))
      end do
    end if
  end subroutine parameter_groups

  !> Groups and variables of other physics, refused in this one's deck.
  subroutine foreign_inputs(self, list)
    class(contact_simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'biot', 'source', 'block_fsai', &
            'material%biot_modulus', &
            'material%permeability', 'material%permeability_tensor', 'material%viscosity']
    if (.not. self%flow) list = [list, [character(len=foreign_len) :: 'fracture_flow', 'well', 'fracture_pressure']]
    if (self%flow) list = [list, [character(len=foreign_len) :: 'pressure_change']]
    ! the Biot coefficient weighs a &pressure_change
    if (size(self%pcs) == 0) list = [list, [character(len=foreign_len) :: 'material%biot']]
  end subroutine foreign_inputs
  !> Every interface element must have a split node: one whose four nodes
  !> all lie on the fault's edge (a fault patch less than two elements
  !> across) has a jump of zero by construction, so its tractions are
  !> undetermined and every solver fails on it. Refused with the fault, the
  !> element count and the first one's centre (the same on every rank).
  !> Collective.
  subroutine check_split(mesh, status)
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    integer(ip) :: e, n_bad, fidx
    integer(gp) :: first_bad
    real(rp) :: centre(3)
    n_bad = 0
    first_bad = huge(1_gp)
    do e = 1, mesh%iface_map%n_owned
      if (any(mesh%iface_nodes(:, 1, e) /= mesh%iface_nodes(:, 2, e))) cycle
      n_bad = n_bad + 1
      first_bad = min(first_bad, mesh%iface_orig(e))
    end do
    n_bad = mesh%comm%sum(n_bad)
    if (n_bad == 0) return
    first_bad = -mesh%comm%max(-first_bad)
    centre = 0.0_rp
    fidx = 0
    do e = 1, mesh%iface_map%n_owned
      if (mesh%iface_orig(e) /= first_bad) cycle
      centre = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
      fidx = mesh%iface_fault(e)
    end do
    call mesh%comm%sum_all(centre)
    fidx = mesh%comm%max(fidx)
    call status%set("fault '"//trim(mesh%fault_names(fidx))//"': "//itoa(n_bad)// &
      " interface element(s) with no split node (all four nodes on the fault's edge), the first centred at ("// &
      trim(rtoa(centre(1)))//', '//trim(rtoa(centre(2)))//', '//trim(rtoa(centre(3)))// &
      '): such an element can neither open nor slip and its tractions are undetermined; make the fault at '// &
      'least two elements across (&fault lower, upper) or refine the mesh')
  end subroutine check_split
end module contact_simulation
