!> Components of a coupled physics (issue 33: compose, do not flag). A
!> component has one job (mechanics, interface contact, fracture flow,
!> matrix flow, ...): it owns its unknowns (fields, each one block of the
!> block system), the Jacobian rows of those unknowns (its diagonal blocks
!> and the off-diagonal blocks of its rows that couple to other components'
!> unknowns), its residuals in physical units, its part of the state record,
!> of the outputs and of the probes. The momentum rows are the exception:
!> the mechanics does not know what couples to it, so a component whose
!> unknowns act on the momentum assembles that block (C1 of the contact, Q1
!> of the fracture flow) and adds its forces in couple. A composition (coupled_simulation.f90)
!> holds an ordered list of components, lays out the blocks and runs the
!> Newton bookkeeping once for all of them.
!>
!> What the components share goes through one coupling context, coupling_t:
!> the mesh, the composition's common configuration (sim: &solver, &material,
!> &boundary, &fault, &geostatic, ...), the block system with its unknown x
!> and right-hand side rhs, the block of each field, the step (load factor,
!> time, dt, the initial step), and the couplings that are not Jacobian
!> blocks: the pressure on the interface's faces (face_pressure, which the
!> momentum rows and the contact's residual read) and the forces other
!> unknowns put on the momentum rows (momentum_coupling). Typed access to
!> another component's state (the interface's jump operator and normal
!> jumps, for the fracture mass rows) is by find(kind) and select type.
!>
!> Life of a component, as the composition calls it (every call in the
!> order of the list unless said):
!>   read_deck, check_deck        its deck groups; checks once all are read
!>   setup                        its data and dof maps (before the layout)
!>   fields, field_size           its unknowns: the composition lays out the blocks
!>   set_patterns                 its rows' patterns, constant blocks, initial x
!>   report_setup                 its set-up lines and checks (after all set-ups)
!>   unknowns_note, describe_unknowns   the unknowns' line, and lines after it
!>   per step: begin_step; take_solution (all); start_step
!>   per iteration: couple (all), assemble (all); field_residuals; check_system;
!>     (solve); take_solution (all); update_status; iteration_note
!>   save_state, load_state, accept_step, write_output, sample, progress,
!>   step_notes, finish.
module physics_component
  use kinds, only: rp, ip, gp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use state_record, only: state_record_t
  use block_matrix, only: block_matrix_t
  use dist_mesh, only: dist_mesh_t
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  use param_group, only: param_group_t
  use simulation, only: simulation_t, foreign_len
  implicit none
  private

  public :: physics_component_t, component_ptr_t, coupling_t, field_len, update_piece, hold_tol

  !> length of a field's name ('u', 't', 'p', ...)
  integer, parameter :: field_len = 8

  !> the largest violation of a status a component may hold an element in
  !> (relative: a traction over the largest traction, an overlap over the
  !> largest jump); beyond it the element is not held but changes status
  real(rp), parameter :: hold_tol = 1.0e-3_rp

  type :: component_ptr_t
    class(physics_component_t), pointer :: p => null()
  end type component_ptr_t

  !> The coupling context: what the components of a composition share.
  type :: coupling_t
    class(simulation_t), pointer :: sim => null()     !< the composition (common configuration)
    type(dist_mesh_t), pointer :: mesh => null()
    type(component_ptr_t), allocatable :: comps(:)     !< the components, in the composition's order
    character(len=field_len), allocatable :: order(:)  !< the fields in block order
    type(block_matrix_t) :: sys                        !< the Jacobian
    real(rp), allocatable :: x(:)                      !< current state, owned block vector
    real(rp), allocatable :: rhs(:)                    !< -residual, owned block vector
    real(rp), allocatable :: dx(:)                     !< the last Newton update
    !> per field (order of the components, then their fields): |dx|/|x| of the last update
    real(rp), allocatable :: rel_update(:)
    real(rp) :: lf = 0.0_rp                            !< load factor of the step (1 when stepping in time)
    real(rp) :: time = 0.0_rp                          !< the histories' time at the step's end
    real(rp) :: dt = 0.0_rp                            !< the step's size (0: an initial step)
    logical :: initial = .false.                       !< step 0: the in-situ equilibrium (&geostatic)
    real(rp) :: newton_tol = 1.0e-8_rp                 !< the Newton loop's relative tolerance (its controls group)
    !> the fluid pressure on the interface elements' faces (local elements) [Pa]:
    !> the contact's prescribed one, or the fracture flow's unknown
    real(rp), pointer :: face_pressure(:) => null()
    !> (owned u dofs) the forces other unknowns put on the momentum rows
    !> (C1 (t - p n)), and the magnitudes of their operands (|C1| |t - p n|)
    real(rp), allocatable :: momentum_coupling(:), momentum_coupling_mag(:)
    !> (owned interface elements; allocated by a component that puts fluid
    !> into the fractures: the matrix flow) the fluid volume it puts into
    !> each element over the step [m^3], and the magnitude of its terms'
    !> operands; the fracture flow's mass rows take it in
    real(rp), allocatable :: fracture_exchange(:), fracture_exchange_mag(:)
  contains
    procedure :: block => field_block
    procedure :: range => field_range
    procedure :: find
    procedure :: put_field
    procedure :: get_field
  end type coupling_t

  type, abstract :: physics_component_t
    character(len=name_len) :: kind = ''                !< 'mechanics', 'contact', 'fracture_flow', ...
    !> the largest violation of a held status at the last status update
    !> (relative; 0 for a component without statuses)
    real(rp) :: held_excess = 0.0_rp
    !> fields whose last update must be small after an inexact (Krylov)
    !> solve when this component is in the composition (check_residual)
    character(len=field_len), allocatable :: update_test(:)
  contains
    procedure(fields_iface), deferred :: fields
    procedure(field_size_iface), deferred :: field_size
    procedure(setup_iface), deferred :: setup
    procedure(patterns_iface), deferred :: set_patterns
    procedure(ctx_iface), deferred :: assemble
    procedure(ctx_iface), deferred :: take_solution
    procedure(residual_names_iface), deferred :: residual_names
    procedure(field_residuals_iface), deferred :: field_residuals
    procedure :: scaling
    procedure(save_state_iface), deferred :: save_state
    procedure(load_state_iface), deferred :: load_state
    procedure(free_iface), deferred :: free
    procedure :: components_of
    procedure :: read_deck
    procedure :: check_deck
    procedure :: groups
    procedure :: parameter_groups
    procedure :: foreign_inputs
    procedure :: report_setup
    procedure :: unknowns_note
    procedure :: describe_unknowns
    procedure :: begin_step
    procedure :: start_step
    procedure :: couple
    procedure :: check_system
    procedure :: update_status
    procedure :: iteration_note
    procedure :: status_notes
    procedure :: accept_step
    procedure :: open_output
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: progress
    procedure :: step_notes
    procedure :: finish
  end type physics_component_t

  abstract interface
    !> The names of its unknowns, one block each ('u'; 't'; 'p').
    subroutine fields_iface(self, names)
      import :: physics_component_t, field_len
      class(physics_component_t), intent(in) :: self
      character(len=field_len), allocatable, intent(out) :: names(:)
    end subroutine fields_iface

    !> Owned rows of its field k (after setup).
    integer(ip) function field_size_iface(self, k)
      import :: physics_component_t, ip
      class(physics_component_t), intent(in) :: self
      integer, intent(in) :: k
    end function field_size_iface

    !> Its data, dof maps and checks on ctx%mesh. Collective.
    subroutine setup_iface(self, ctx, log, status)
      import :: physics_component_t, coupling_t, logger_t, error_status_t
      class(physics_component_t), intent(inout), target :: self
      type(coupling_t), intent(inout), target :: ctx
      type(logger_t), intent(inout) :: log
      type(error_status_t), intent(inout) :: status
    end subroutine setup_iface

    !> Once the blocks are laid out (ctx%sys, ctx%x = 0): the patterns of
    !> its rows, its constant blocks, its part of the initial state. Collective.
    subroutine patterns_iface(self, ctx, status)
      import :: physics_component_t, coupling_t, error_status_t
      class(physics_component_t), intent(inout), target :: self
      type(coupling_t), intent(inout), target :: ctx
      type(error_status_t), intent(inout) :: status
    end subroutine patterns_iface

    subroutine ctx_iface(self, ctx)
      import :: physics_component_t, coupling_t
      class(physics_component_t), intent(inout), target :: self
      type(coupling_t), intent(inout), target :: ctx
    end subroutine ctx_iface

    !> Names and units of its residuals (field_residuals), e.g. 'force', 'N'.
    subroutine residual_names_iface(self, names, units)
      import :: physics_component_t
      class(physics_component_t), intent(in) :: self
      character(len=8), allocatable, intent(out) :: names(:)
      character(len=3), allocatable, intent(out) :: units(:)
    end subroutine residual_names_iface

    !> The residual of the last assembly per residual_names entry, in
    !> physical units, the magnitude it balances and the magnitude of its
    !> terms' operands (whose eps multiple is its round-off). Collective.
    subroutine field_residuals_iface(self, ctx, res, ref, noise)
      import :: physics_component_t, coupling_t, rp
      class(physics_component_t), intent(in) :: self
      type(coupling_t), intent(in) :: ctx
      real(rp), intent(out) :: res(:), ref(:), noise(:)
    end subroutine field_residuals_iface


    subroutine save_state_iface(self, ctx, st)
      import :: physics_component_t, coupling_t, state_record_t
      class(physics_component_t), intent(inout) :: self
      type(coupling_t), intent(in) :: ctx
      type(state_record_t), intent(inout) :: st
    end subroutine save_state_iface

    !> Its part of the state from st (the composition takes the solution
    !> of every component afterwards). Collective.
    subroutine load_state_iface(self, ctx, st, status)
      import :: physics_component_t, coupling_t, state_record_t, error_status_t
      class(physics_component_t), intent(inout) :: self
      type(coupling_t), intent(inout) :: ctx
      type(state_record_t), intent(in) :: st
      type(error_status_t), intent(inout) :: status
    end subroutine load_state_iface

    subroutine free_iface(self)
      import :: physics_component_t
      class(physics_component_t), intent(inout) :: self
    end subroutine free_iface
  end interface

contains

  !> The block of field name (0: no component has it).
  integer function field_block(self, name) result(b)
    class(coupling_t), intent(in) :: self
    character(len=*), intent(in) :: name
    do b = 1, size(self%order)
      if (self%order(b) == name) return
    end do
    b = 0
  end function field_block

  !> The range of field name's block in the block vector.
  subroutine field_range(self, name, i0, i1)
    class(coupling_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(ip), intent(out) :: i0, i1
    call self%sys%block_range(self%block(name), i0, i1)
  end subroutine field_range

  !> The component of kind, null when the composition has none.
  function find(self, kind) result(c)
    class(coupling_t), intent(in) :: self
    character(len=*), intent(in) :: kind
    class(physics_component_t), pointer :: c
    integer :: k
    c => null()
    if (.not. allocated(self%comps)) return
    do k = 1, size(self%comps)
      if (self%comps(k)%p%kind == kind) c => self%comps(k)%p
    end do
  end function find

  !> Put field name of x into st as 'x_<name>' (by field, not as the block
  !> vector: the block order depends on the solver, and a run may restart
  !> with another).
  subroutine put_field(self, st, name)
    class(coupling_t), intent(in) :: self
    type(state_record_t), intent(inout) :: st
    character(len=*), intent(in) :: name
    integer(ip) :: i0, i1
    call self%range(name, i0, i1)
    call st%put('x_'//trim(name), self%x(i0:i1))
  end subroutine put_field

  !> Field name of x from st ('x_<name>').
  subroutine get_field(self, st, name, status)
    class(coupling_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    character(len=*), intent(in) :: name
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i0, i1
    call self%range(name, i0, i1)
    call st%get('x_'//trim(name), self%x(i0:i1), status)
  end subroutine get_field

  !> '  |df|/|f| ' and rel: a field's relative update in the iteration's line.
  function update_piece(f, rel) result(piece)
    character(len=*), intent(in) :: f
    real(rp), intent(in) :: rel
    character(len=32) :: piece
    write(piece, '(a,es9.2)') '  |d'//trim(f)//'|/|'//trim(f)//'| ', rel
  end function update_piece

  !> The diagonal d of its rows for the symmetric scaling 1/sqrt(|d|) (d:
  !> the whole block vector; fill its blocks' ranges). Default: the
  !> diagonals of its fields' diagonal blocks.
  subroutine scaling(self, ctx, d)
    class(physics_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(inout) :: d(:)
    character(len=field_len), allocatable :: names(:)
    integer(ip) :: i0, i1
    integer :: k
    call self%fields(names)
    do k = 1, size(names)
      call ctx%range(names(k), i0, i1)
      call ctx%sys%a(ctx%block(names(k)), ctx%block(names(k)))%diagonal(d(i0:i1))
    end do
  end subroutine scaling

  !> The components of field k (for hypre's MGR labels: 3 for a vector, 1
  !> for a scalar). Default: 1.
  integer function components_of(self, k) result(n)
    class(physics_component_t), intent(in) :: self
    integer, intent(in) :: k
    n = 1
  end function components_of

  !> Read, check and echo its deck groups (default: none). Collective.
  subroutine read_deck(self, ctx, d, mcfg, log, status)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
  end subroutine read_deck

  !> Checks once every component has read its groups (default: none).
  subroutine check_deck(self, ctx, d, status)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
  end subroutine check_deck

  !> The deck groups it reads: a composition without it refuses them.
  subroutine groups(self, list)
    class(physics_component_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    allocate(list(0))
  end subroutine groups

  !> Its resolved deck groups (default: none).
  subroutine parameter_groups(self, ctx, list)
    class(physics_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(param_group_t), allocatable, intent(out) :: list(:)
    allocate(list(0))
  end subroutine parameter_groups

  !> Groups and variables that a composition with it refuses (default: none).
  subroutine foreign_inputs(self, list)
    class(physics_component_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    allocate(list(0))
  end subroutine foreign_inputs

  !> Its set-up lines and checks, once every component is set up
  !> (default: none). Collective.
  subroutine report_setup(self, ctx, log, status)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
  end subroutine report_setup

  !> Its note in the unknowns' log line (in parentheses; default: none).
  !> Collective.
  subroutine unknowns_note(self, ctx, note)
    class(physics_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(out) :: note
    note = ''
  end subroutine unknowns_note

  !> Lines on its unknowns after the unknowns' log line (default: none).
  subroutine describe_unknowns(self, ctx, log)
    class(physics_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
  end subroutine describe_unknowns

  !> Start a step (ctx%lf, ctx%time, ctx%dt): loads and prescribed values,
  !> what the step measures from, before the start iterate is taken
  !> (default: nothing). Collective.
  subroutine begin_step(self, ctx)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
  end subroutine begin_step

  !> After the start iterate is taken: what the step measures from it
  !> (default: nothing). Collective.
  subroutine start_step(self, ctx)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
  end subroutine start_step

  !> Before any component assembles: its terms in other components' rows
  !> that are not Jacobian products of the iterate's update (the forces of
  !> its unknowns on the momentum rows; default: none). Collective.
  subroutine couple(self, ctx)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
  end subroutine couple

  !> Before every linear solve: can the system be solved (default: yes).
  !> Collective.
  subroutine check_system(self, ctx, status)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
  end subroutine check_system

  !> After the solution is taken: update its statuses (an active set),
  !> the global number of changes; held_excess (default: none). Collective.
  subroutine update_status(self, ctx, changes)
    class(physics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(gp), intent(out) :: changes
    changes = 0
  end subroutine update_status

  !> Its part of the Newton iteration's detail line, appended to line.
  !> rel: |dx|/|x| of its fields (default: those). Collective.
  subroutine iteration_note(self, ctx, rel, line)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(in) :: rel(:)
    character(len=*), intent(inout) :: line
    character(len=field_len), allocatable :: names(:)
    integer :: k
    call self%fields(names)
    do k = 1, size(names)
      line = trim(line)//update_piece(names(k), rel(k))
    end do
  end subroutine iteration_note

  !> Lines on its statuses once the step has converged (default: none).
  !> Collective.
  subroutine status_notes(self, ctx, log)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
  end subroutine status_notes

  !> The step is accepted (default: nothing).
  subroutine accept_step(self, ctx)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
  end subroutine accept_step

  !> Its own grids in the output (default: none). Collective.
  subroutine open_output(self, ctx, out, status)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
  end subroutine open_output

  !> Its fields of the step (default: none). Collective.
  subroutine write_output(self, ctx, out, status)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
  end subroutine write_output

  !> The &probe fields it provides (default: none).
  subroutine probe_names(self, names)
    class(physics_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    allocate(names(0))
  end subroutine probe_names

  !> Its probe fields and scalars (default: none). Collective.
  subroutine sample(self, ctx, pf, status)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
  end subroutine sample

  !> Its part of the step's progress line, appended to line. Collective.
  subroutine progress(self, ctx, line)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(inout) :: line
  end subroutine progress

  !> Lines on what changed in the step (default: none). Collective.
  subroutine step_notes(self, ctx, lines)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=msg_len), allocatable, intent(inout) :: lines(:)
  end subroutine step_notes

  !> Closing lines of the run (default: none).
  subroutine finish(self, ctx, log)
    class(physics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
  end subroutine finish
end module physics_component
