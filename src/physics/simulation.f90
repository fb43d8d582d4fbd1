!> The simulation contract: what every physics provides so that one driver
!> (src/drivers: one time loop with step cuts, one Newton / active-set loop,
!> one linear-solve path) runs it. A driver knows this type, never a
!> concrete physics; simulation_factory maps the deck's name to a type.
!>
!> Life of a simulation, as the driver calls it:
!>
!>   read_deck(d, mcfg)               its deck groups (read_common reads the ones
!>                                every physics shares), validated and echoed;
!>                                sets faults (surfaces the mesh must split),
!>                                transient, max_newton, max_cuts
!>   setup(mesh)                  unknowns, blocks, patterns, checks
!>   open_output(out)             grids of its own beside the mesh grid
!>   per step (t_old -> t, dt):
!>     save_state(st)             what a step cut restores (and a checkpoint keeps)
!>     begin_step(t, dt)          loads and prescribed values at t
!>     Newton / active-set loop, it = 1 .. max_newton:
!>       assemble()               Jacobian and right-hand side at the iterate
!>       check_residual(it - 1)   (a physics with residual_test, from it = 2 on)
!>                                the residual of the iterate per field in
!>                                physical units: the step has converged when
!>                                every field is within its tolerance and
!>                                the last update changed no status
!>       linear_system(sys)       the system to solve: views of its operator,
!>                                rhs, unknown, preconditioner (set up or
!>                                refreshed here), scaling
!>       (the driver solves it)
!>       update(it, converged)    take the solution, update the active set,
!>                                say whether the step has converged
!>     accept_step()  or  load_state(st) and a smaller step
!>     report_step(stats)         its progress line
!>     step_notes(lines)          lines on what changed in the step, if any
!>                                (contact: a fault's statuses)
!>     write_output(out)          its fields of the step
!>     sample(pf)                 the fields &probe may name (probe_names) and
!>                                scalars of its own, for the probe file
!>   finish(log)                  closing lines of the run
!>
!> A linear physics (max_newton = 1) solves for its state in one iteration;
!> a nonlinear one solves for updates. Each physics states its own progress
!> line (report_step) from the figures the driver measured (step_stats_t).
module simulation
  use kinds, only: rp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use state_record, only: state_record_t
  use linear_system, only: linear_system_t
  use amg_params, only: amg_params_t
  use deck, only: deck_t, unset_real
  use mesh_config, only: mesh_config_t
  use solver_config, only: solver_config_t
  use amg_config, only: read_amg_config, describe_amg_config
  use param_group, only: param_group_t
  use fsai_config, only: fsai_config_t
  use material_config, only: material_config_t, read_materials
  use geostatic_config, only: geostatic_config_t
  use pressure_change_config, only: pressure_change_config_t, read_pressure_changes, load_pressure_change_histories
  use boundary_config, only: boundary_config_t, read_boundaries, load_histories
  use fault_config, only: fault_config_t
  use dist_mesh, only: dist_mesh_t
  use slab_geometry, only: slab_t, find_slab
  use strings, only: itoa, rtoa
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  implicit none
  private

  public :: simulation_t, step_stats_t, foreign_len, common_parameter_groups

  !> length of a foreign_inputs entry ('group%variable')
  integer, parameter :: foreign_len = 40

  !> What the driver measured over one step (all its Newton iterations and,
  !> when it was cut, all its sub-steps), for the physics' progress line.
  type :: step_stats_t
    integer :: step = 0                  !< step number (0: the initial, e.g. undrained, step)
    integer :: n_steps = 0               !< steps of the run when known in advance (load steps), else 0
    real(rp) :: t = 0.0_rp               !< time (load factor for load steps) at the end of the step
    real(rp) :: dt = 0.0_rp              !< the step's size (of its last sub-step when cut)
    integer :: newton = 0                !< Newton / active-set iterations
    integer :: linear_its = 0            !< linear iterations, summed
    integer :: cuts = 0                  !< halvings of the step
    integer :: near_rtol = 0             !< Krylov solves accepted after stalling within 10x of rtol
    real(rp) :: rel_res = 0.0_rp         !< relative residual of the last linear solve
    real(rp) :: t_assembly = 0.0_rp      !< seconds: assembly
    real(rp) :: t_setup = 0.0_rp         !< seconds: preconditioner set-up and factorizations
    real(rp) :: t_solve = 0.0_rp         !< seconds: linear solves
  end type step_stats_t

  type, abstract :: simulation_t
    type(parallel_comm_t) :: comm                          !< set by the driver before read_deck
    type(dist_mesh_t), pointer :: mesh => null()          !< set by setup; owned by the driver
    type(solver_config_t) :: solver                        !< &solver
    type(amg_params_t) :: amg                              !< &amg
    !> &amg for the displacement block's AMG (K, S*), adapted to the mesh (adapt_amg)
    type(amg_params_t) :: amg_k
    logical :: on_slab = .false.                           !< adapt_amg found a slab with flat cells
    type(fsai_config_t) :: fsai                            !< &afsai, &block_fsai
    type(material_config_t), allocatable :: mats(:)        !< &material groups
    type(boundary_config_t), allocatable :: bcs(:)         !< &boundary groups (histories loaded)
    type(fault_config_t), allocatable :: faults(:)         !< surfaces the mesh must split (&fault)
    logical :: transient = .false.                         !< time steps (dt, t_end) rather than load steps
    integer :: max_newton = 1                              !< iterations per step (1: linear)
    !> the step's convergence is judged by check_residual on the residual
    !> of the iterate (a nonlinear physics), not by update
    logical :: residual_test = .false.
    !> check_residual's largest residual over tolerance of the fields
    !> (below 1: converged), for the Newton loop's progress check
    real(rp) :: residual_ratio = 0.0_rp
    !> relative tolerance of a Krylov solve whose Newton iteration still
    !> moves an active set (active_set_moving); 0: the deck's rtol always
    real(rp) :: moving_rtol = 0.0_rp
    !> with moving_rtol: the settled iterations' solves by Eisenstat and
    !> Walker's forcing term (else to rtol)
    logical :: settled_forcing = .false.
    !> the relative tolerance the Newton loop gave the last linear solve
    !> (0 before the first): above the deck's rtol that solve was inexact
    real(rp) :: last_solve_rtol = 0.0_rp
    !> the Newton iteration of the step (or sub-step) being solved (1: its first)
    integer :: newton_it = 0
    integer :: max_cuts = 0                                !< halvings of a step that does not converge
    type(geostatic_config_t) :: geo                        !< &geostatic (geo%on: the run starts in situ)
    logical :: initial_step = .false.                      !< a step 0 at t = 0 before any load (geostatic)
    type(pressure_change_config_t), allocatable :: pcs(:)  !< &pressure_change groups (histories loaded)
  contains
    procedure(name_iface), deferred :: name
    procedure(read_deck_iface), deferred :: read_deck
    procedure(setup_iface), deferred :: setup
    procedure(begin_step_iface), deferred :: begin_step
    procedure(assemble_iface), deferred :: assemble
    procedure(linear_system_iface), deferred :: linear_system
    procedure(update_iface), deferred :: update
    procedure(save_state_iface), deferred :: save_state
    procedure(load_state_iface), deferred :: load_state
    procedure(write_output_iface), deferred :: write_output
    procedure(report_step_iface), deferred :: report_step
    procedure(free_iface), deferred :: free
    procedure :: read_common
    procedure :: adapt_amg
    procedure :: foreign_inputs
    procedure :: check_foreign
    procedure :: unused_inputs
    procedure :: parameter_groups
    procedure :: open_output
    procedure :: probe_names
    procedure :: sample
    procedure :: accept_step
    procedure :: step_notes
    procedure :: controls_group
    procedure :: finish
    procedure :: check_residual
    procedure :: active_set_moving
  end type simulation_t

  abstract interface
    !> The physics' name, as &run physics gives it.
    function name_iface(self) result(s)
      import :: simulation_t, name_len
      class(simulation_t), intent(in) :: self
      character(len=name_len) :: s
    end function name_iface

    !> Read, check and echo the deck groups of the physics (all but &run,
    !> &time, &output and &mesh, which the driver reads; mcfg is &mesh, for
    !> checks that depend on the kind of mesh). Collective: status is the
    !> same on every rank.
    subroutine read_deck_iface(self, d, mcfg, log, status)
      import :: simulation_t, deck_t, mesh_config_t, logger_t, error_status_t
      class(simulation_t), intent(inout), target :: self
      type(deck_t), intent(in) :: d
      type(mesh_config_t), intent(in) :: mcfg
      type(logger_t), intent(inout) :: log
      type(error_status_t), intent(inout) :: status
    end subroutine read_deck_iface

    !> Unknowns, blocks, patterns and checks on mesh (kept by pointer); log
    !> the sizes. Collective; status may differ between ranks (the driver
    !> makes it agree).
    subroutine setup_iface(self, mesh, log, status)
      import :: simulation_t, dist_mesh_t, logger_t, error_status_t
      class(simulation_t), intent(inout), target :: self
      type(dist_mesh_t), intent(in), target :: mesh
      type(logger_t), intent(inout) :: log
      type(error_status_t), intent(inout) :: status
    end subroutine setup_iface

    !> Start a step from the accepted state to time (or load factor) t with
    !> step size dt (0 for an initial instantaneous step): loads, prescribed
    !> values and histories at t. Collective.
    subroutine begin_step_iface(self, t, dt, status)
      import :: simulation_t, rp, error_status_t
      class(simulation_t), intent(inout) :: self
      real(rp), intent(in) :: t, dt
      type(error_status_t), intent(inout) :: status
    end subroutine begin_step_iface

    !> Jacobian and right-hand side at the current iterate. Collective.
    subroutine assemble_iface(self, status)
      import :: simulation_t, error_status_t
      class(simulation_t), intent(inout) :: self
      type(error_status_t), intent(inout) :: status
    end subroutine assemble_iface

    !> Fill sys with views of the system to solve now. Unless direct (a
    !> direct solver factorizes the operator itself), set up or refresh the
    !> preconditioner and scaling; sys%setup_time gets the seconds spent.
    !> Collective; status is the same on every rank.
    subroutine linear_system_iface(self, direct, sys, log, status)
      import :: simulation_t, linear_system_t, logger_t, error_status_t
      class(simulation_t), intent(inout), target :: self
      logical, intent(in) :: direct
      type(linear_system_t), intent(inout) :: sys
      type(logger_t), intent(inout) :: log
      type(error_status_t), intent(inout) :: status
    end subroutine linear_system_iface

    !> Take the solution of the linear system of iteration `iteration` of
    !> the step (solved in linear_its iterations, for the log), update what depends on it (the active set), and say whether
    !> the step has converged; why: what was still moving (for the message
    !> of a step that fails). Collective; converged is the same everywhere.
    subroutine update_iface(self, iteration, linear_its, log, converged, why, status)
      import :: simulation_t, logger_t, error_status_t
      class(simulation_t), intent(inout) :: self
      integer, intent(in) :: iteration, linear_its
      type(logger_t), intent(inout) :: log
      logical, intent(out) :: converged
      character(len=*), intent(out) :: why
      type(error_status_t), intent(inout) :: status
    end subroutine update_iface

    !> Put into st every array the physics needs to resume from the last
    !> accepted step.
    subroutine save_state_iface(self, st)
      import :: simulation_t, state_record_t
      class(simulation_t), intent(inout) :: self
      type(state_record_t), intent(inout) :: st
    end subroutine save_state_iface

    !> Go back to the state in st (made by save_state on this partition).
    !> Collective.
    subroutine load_state_iface(self, st, status)
      import :: simulation_t, state_record_t, error_status_t
      class(simulation_t), intent(inout) :: self
      type(state_record_t), intent(in) :: st
      type(error_status_t), intent(inout) :: status
    end subroutine load_state_iface

    !> Write the fields of the step into the open step of out. Collective.
    subroutine write_output_iface(self, out, status)
      import :: simulation_t, field_output_t, error_status_t
      class(simulation_t), intent(inout) :: self
      type(field_output_t), intent(inout) :: out
      type(error_status_t), intent(inout) :: status
    end subroutine write_output_iface

    !> The progress line of a finished step. Collective (it may reduce).
    subroutine report_step_iface(self, stats, line)
      import :: simulation_t, step_stats_t
      class(simulation_t), intent(inout) :: self
      type(step_stats_t), intent(in) :: stats
      character(len=*), intent(out) :: line
    end subroutine report_step_iface

    subroutine free_iface(self)
      import :: simulation_t
      class(simulation_t), intent(inout) :: self
    end subroutine free_iface
  end interface

contains

  !> Read the groups every physics shares: &material, &boundary (and their
  !> history files), &solver (default_precon: the precon a physics defaults
  !> to), &amg, &afsai and &block_fsai. flow_conditions: the physics has
  !> pressure and flux boundary conditions; with_faults: it uses &fault
  !> groups (others refuse them). Collective.
  subroutine read_common(self, d, log, status, default_precon, flow_conditions, with_faults)
    class(simulation_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in) :: default_precon
    logical, intent(in) :: flow_conditions, with_faults
    integer :: c
    call read_materials(d, log, self%mats, status)
    if (status%ok()) call read_boundaries(d, log, self%bcs, status)
    if (status%ok()) then
      self%solver%precon = default_precon
      call self%solver%read(d, log, status)
    end if
    if (status%ok()) call read_amg_config(d, log, self%amg, status)
    if (status%ok()) call self%fsai%read(d, log, status)
    if (status%ok()) call load_histories(self%comm, self%bcs, status)
    if (status%ok()) call self%geo%read(d, log, status)
    if (status%ok()) call check_in_situ(self, d, status)
    if (.not. status%ok()) return
    ! the equilibrium step of the in-situ state (Biot: its layers are in
    ! equilibrium by construction, and its step 0 is the undrained one;
    ! with faults, step 0 balances it with the faults bonded)
    self%initial_step = self%geo%on .and. (with_faults .or. .not. flow_conditions)
    if (flow_conditions) then
      allocate(self%pcs(0))
      if (d%count('pressure_change') > 0) then
        call status%set("deck '"//trim(d%path)//"': &pressure_change is for physics 'elasticity' and 'contact' "// &
          "(in 'biot' the pressure is an unknown: use &source or a &boundary pressure)")
        return
      end if
    else
      call read_pressure_changes(d, log, self%pcs, status)
      if (status%ok()) call load_pressure_change_histories(self%comm, self%pcs, status)
      if (.not. status%ok()) return
    end if
    if (.not. with_faults .and. d%count('fault') > 0) then
      call status%set("deck '"//trim(d%path)//"': &fault groups need physics = 'contact' in &run")
      return
    end if
    if (flow_conditions) return
    do c = 1, size(self%bcs)
      if (self%bcs(c)%type == 'pressure' .or. self%bcs(c)%type == 'flux') then
        call status%set("&boundary on set '"//trim(self%bcs(c)%set)//"': type = '"//trim(self%bcs(c)%type)// &
                        "' needs physics = 'biot' in &run")
        return
      end if
    end do
  end subroutine read_common

  !> amg_k, the settings of the displacement block's BoomerAMG (K, and S*
  !> of contact): &amg, with strong_threshold raised to slab_threshold on a
  !> slab with flat cells (slab_geometry.f90; amg_params.f90 says why), and
  !> a log line saying so. Call in setup, once the mesh is known. Collective.
  subroutine adapt_amg(self, mesh, log)
    class(simulation_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(logger_t), intent(inout) :: log
    type(slab_t) :: slab
    character(len=msg_len) :: line
    self%amg_k = self%amg
    slab = find_slab(mesh)
    if (slab%axis == 0) return
    self%on_slab = .true.
    self%amg_k = self%amg%for_slab()
    line = 'slab along '//achar(iachar('w') + slab%axis)//' ('//rtoa(slab%thickness)//' m thick, '// &
      rtoa(slab%width)//' m wide, cells flat up to 1:'//itoa(nint(slab%flatness))// &
      '): BoomerAMG of the displacement block with strong_threshold '//rtoa(self%amg_k%strong_threshold)// &
      ' (&amg slab_threshold)'
    call log%info(line)
  end subroutine adapt_amg

  !> &material density, k0 and k0_max belong to &geostatic: required (density) with
  !> it, refused without it; gravity comes from &geostatic, so a material's
  !> body_force would count it twice.
  subroutine check_in_situ(self, d, status)
    class(simulation_t), intent(in) :: self
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
    integer :: k
    do k = 1, size(self%mats)
      associate (m => self%mats(k))
        if (self%geo%on) then
          if (m%density == unset_real) call d%fail(status, 'material', k, 'density', &
            'required with &geostatic (the in-situ stress is the weight of the layers above)')
          if (any(m%body_force /= 0.0_rp)) call d%fail(status, 'material', k, 'body_force', &
            'not with &geostatic, whose gravity acts on the density (the weight would count twice)')
        else
          if (m%density /= unset_real) call d%fail(status, 'material', k, 'density', &
            'is used only with a &geostatic group (for a load, use body_force)')
          if (m%k0 /= unset_real) call d%fail(status, 'material', k, 'k0', &
            'is used only with a &geostatic group')
          if (m%k0_max /= unset_real) call d%fail(status, 'material', k, 'k0_max', &
            'is used only with a &geostatic group')
        end if
      end associate
      if (.not. status%ok()) return
    end do
  end subroutine check_in_situ

  !> Add the physics' own grids to the output (default: none). Collective.
  subroutine open_output(self, out, status)
    class(simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
  end subroutine open_output

  !> The quantities of probe_config's list that sample provides (default:
  !> none, so a deck with &probe fields is refused).
  subroutine probe_names(self, names)
    class(simulation_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    allocate(names(0))
  end subroutine probe_names

  !> The fields of the accepted state that the probes read, and scalars of
  !> the physics' own (probe_fields_t; default: nothing). Collective.
  subroutine sample(self, pf, status)
    class(simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
  end subroutine sample

  !> The step is accepted: the current state becomes the old state of the
  !> next step (default: nothing to do).
  subroutine accept_step(self)
    class(simulation_t), intent(inout) :: self
  end subroutine accept_step

  !> The deck group that holds max_newton and max_cuts (default: the
  !> physics' own group, named as the physics).
  function controls_group(self) result(g)
    class(simulation_t), intent(in) :: self
    character(len=name_len) :: g
    g = self%name()
  end function controls_group

  !> Lines for the log after the step's progress line, on what changed in
  !> the step (default: none). Collective.
  subroutine step_notes(self, lines)
    class(simulation_t), intent(inout) :: self
    character(len=msg_len), allocatable, intent(out) :: lines(:)
    allocate(lines(0))
  end subroutine step_notes

  !> With residual_test: judge the residual of the iterate just assembled,
  !> after `updates` Newton updates of the step (>= 1): converged when every
  !> field is within its tolerance and the statuses have settled; why: what
  !> is still out, in physical units. Default (no residual test): never
  !> converged here. Collective; converged is the same on every rank.
  subroutine check_residual(self, updates, log, converged, why)
    class(simulation_t), intent(inout) :: self
    integer, intent(in) :: updates
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    converged = .false.
    why = ''
  end subroutine check_residual

  !> Whether Newton iteration `iteration` of the step may still change an
  !> active set, so that its linear solve need not be tight (moving_rtol).
  !> Default (no active set): never. The same on every rank.
  logical function active_set_moving(self, iteration)
    class(simulation_t), intent(in) :: self
    integer, intent(in) :: iteration
    active_set_moving = .false.
  end function active_set_moving

  !> Closing lines of the run (default: none). Collective.
  subroutine finish(self, log)
    class(simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
  end subroutine finish
  !> Deck groups ('group') and variables ('group%variable') this physics
  !> does not use; a deck that sets one is refused (check_foreign). Default:
  !> none. The &time variables of the other kind of stepping are added by
  !> check_foreign itself.
  subroutine foreign_inputs(self, list)
    class(simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    allocate(list(0))
  end subroutine foreign_inputs

  !> Everything this physics does not use: its foreign_inputs and the
  !> &time variables of the other kind of stepping (load steps n_steps, or
  !> time steps dt, t_end, dt_growth, dt_max, times, undrained).
  subroutine unused_inputs(self, list)
    class(simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    character(len=foreign_len), parameter :: time_vars(6) = [character(len=foreign_len) :: 'time%dt', &
      'time%t_end', 'time%dt_growth', 'time%dt_max', 'time%times', 'time%undrained']
    character(len=foreign_len), allocatable :: own(:)
    call self%foreign_inputs(own)
    if (.not. self%geo%on) own = [own, [character(len=foreign_len) :: 'material%density', 'material%k0', &
                                                                   'material%k0_max']]
    if (self%transient) then
      list = [own, [character(len=foreign_len) :: 'time%n_steps']]
    else
      list = [own, time_vars]
    end if
  end subroutine unused_inputs

  !> Refuse a deck that sets what this physics would silently ignore
  !> (unused_inputs). The message names the group, the variable and the
  !> physics.
  subroutine check_foreign(self, d, status)
    class(simulation_t), intent(in) :: self
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
    character(len=foreign_len), allocatable :: list(:)
    character(len=:), allocatable :: why
    integer :: j, k, p
    call self%unused_inputs(list)
    why = merge(' (it steps in time: dt, t_end)', ' (it steps in load: n_steps)  ', self%transient)
    why = trim(why)
    do j = 1, size(list)
      p = index(list(j), '%')
      if (p == 0) then
        if (d%count(trim(list(j))) > 0) call status%set("deck '"//trim(d%path)//"': group &"//trim(list(j))// &
          " is not used by physics = '"//trim(self%name())//"'; remove it")
      else
        do k = 1, d%count(list(j)(1:p-1))
          if (.not. d%assigned(list(j)(1:p-1), k, trim(list(j)(p+1:)))) cycle
          if (list(j)(1:p-1) == 'time') then
            call d%fail(status, list(j)(1:p-1), k, trim(list(j)(p+1:)), "is not used by physics = '"// &
                        trim(self%name())//"'"//why//'; remove it')
          else
            call d%fail(status, list(j)(1:p-1), k, trim(list(j)(p+1:)), "is not used by physics = '"// &
                        trim(self%name())//"'; remove it")
          end if
        end do
      end if
      if (.not. status%ok()) return
    end do
  end subroutine check_foreign

  !> The resolved deck groups of the physics, all but &run, &time, &output
  !> and &mesh (default: the shared ones, common_parameter_groups). The
  !> driver drops what unused_inputs lists.
  subroutine parameter_groups(self, groups)
    class(simulation_t), intent(in) :: self
    type(param_group_t), allocatable, intent(out) :: groups(:)
    call common_parameter_groups(self, groups)
  end subroutine parameter_groups

  !> The groups read_common reads: every &material and &boundary, &solver,
  !> &amg, &afsai and &block_fsai.
  subroutine common_parameter_groups(sim, groups)
    class(simulation_t), intent(in) :: sim
    type(param_group_t), allocatable, intent(out) :: groups(:)
    integer :: k, n
    allocate(groups(size(sim%mats) + size(sim%bcs) + merge(5, 4, sim%geo%on) + size(sim%pcs)))
    n = 0
    do k = 1, size(sim%mats)
      n = n + 1
      call sim%mats(k)%describe(groups(n))
    end do
    do k = 1, size(sim%bcs)
      n = n + 1
      call sim%bcs(k)%describe(groups(n))
    end do
    call sim%solver%describe(groups(n + 1))
    call describe_amg_config(sim%amg, groups(n + 2))
    call sim%fsai%describe(groups(n + 3), groups(n + 4))
    n = n + 4
    if (sim%geo%on) then
      n = n + 1
      call sim%geo%describe(groups(n))
    end if
    do k = 1, size(sim%pcs)
      call sim%pcs(k)%describe(groups(n + k))
    end do
  end subroutine common_parameter_groups
end module simulation
