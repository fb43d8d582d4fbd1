!> The interface contact component (physics_component.f90): frictional
!> contact on faults and fractures, one traction vector per interface
!> element (P0, in the element's local frame: normal, two tangential
!> components) as Lagrange multiplier, Coulomb friction with cohesion, the
!> active set (stick, slip, open), and the algebraic stabilization H_t of
!> Franceschini, Castelletto, White and Tchelepi (CMAME 368 (2020) 113161)
!> that the Q1-P0 pair needs. The displacements are the mechanics
!> component's (mechanics_component.f90).
!>
!> Its unknown t, its rows and its coupling blocks:
!>   C1 (t - t_p) in the momentum rows          (C1 in the (u, t) block; the
!>                                               forces go to ctx%momentum_coupling)
!>   r_t(u, t) = 0, per element and by status:   contact (C2 and the (t, t) block)
!>     stick: A g_N = 0 and A (g_T - g_T^n) = 0, each stabilized: - H v
!>     slip : A g_N - H v = 0 (normal only) and -s (t_T - tau(t_N) d) = 0,
!>            tau = c - tan(phi) t_N, d the unit direction of the slip
!>            increment g_T - g_T^n (of t_T while that is zero)
!>     open : -s t = 0
!> with g = R [[u]] the mean jump across the element in its frame ([[u]] =
!> u_plus - u_minus, so g_N > 0 opens), A the area, t the traction on the
!> minus side (t_N < 0 in compression), t_p = (p, 0, 0) the fluid pressure
!> p on the faces (ctx%face_pressure: the &fault pressure, in-situ pore
!> pressure and &pressure_change here, pres; the fracture flow's unknown
!> when the composition has one), v = (t_N, t_T - t_T^n) and s a
!> per-element scale (the diagonal of C2 diag(K)^-1 C1) that keeps the open
!> and slip rows in proportion with the others. C1 = integral of [[N]]^T
!> R^T; for stick rows the Jacobian block C2 is C1^T, so the stick problem
!> is the symmetric saddle point [K C1; C1^T -H_t].
!>
!> H_t: for every edge shared by two interface elements e1, e2 of a fault,
!>   M = sum over the edge's split nodes of w1 w2 diag(1/K_minus + 1/K_plus),
!> where w are the nodal areas of the node in the two elements and K_side the
!> diagonal stiffness of the node from the two cells of that side (the
!> macro-element of the two elements), and H gets R1 M R1^T, R2 M R2^T on the
!> diagonal and -sigma R1 M R2^T off it (sigma = -1 when the two elements see
!> the fault from opposite sides). Only the constrained components take part:
!> three for stick, the normal one for slip, none for open. This follows the
!> paper's macro-element argument (the jump of the multipliers between
!> neighbours is penalized by the local Schur complement) with the exact
!> element-stiffness diagonals in place of its closed-form estimate.
!>
!> Space 'bubble' (&contact space; the mechanics carries the bubbles): the
!> displacement field also has a face bubble in the cell on each side of
!> every element (face_bubbles.f90, elasticity's enriched cells), which makes
!> the P0 tractions inf-sup stable. The jump operator gets the bubbles'
!> columns (+-wb R, wb the integral of the bubble over the face), so C1, C2,
!> the mean jumps and the row scales s include them, and H_t is left out:
!> the stick problem is the pure saddle point [K C1; C1^T 0].
module interface_contact
  use kinds, only: rp, ip, gp, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use dist_mesh, only: dist_mesh_t
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use param_group, only: param_group_t
  use contact_config, only: contact_config_t
  use fault_config, only: fault_config_t, read_faults, load_fault_histories
  use interface_element, only: interface_geometry, face_bubble_integral
  use fault_edges, only: fault_edges_t
  use mesh_pieces, only: mesh_pieces_t
  use field_output, only: field_output_t
  use fracture_output, only: fracture_output_t
  use probe_fields, only: probe_fields_t, scalar_name_len
  use dist_vector, only: pnorm2
  use physics_component, only: physics_component_t, coupling_t, field_len, update_piece, hold_tol
  use mechanics_component, only: mechanics_component_t, mechanics_of
  implicit none
  private

  public :: interface_contact_of, interface_contact_t, state_stick, state_slip, state_open, state_names, max_flips, nju, &
            check_split, violation_names, viol_beyond

  integer, parameter :: state_stick = 1, state_slip = 2, state_open = 3
  !> the checks an update may find broken (update_states), as the log names them
  integer, parameter :: viol_tension = 1, viol_beyond = 2, viol_under = 3, viol_back = 4, viol_overlap = 5
  character(len=40), parameter :: violation_names(5) = [character(len=40) :: &
    'tension on a closed element', 'stuck beyond its friction limit', 'slipping under its friction limit', &
    'slip turned against its friction', 'overlap of an open element']
  character(len=5), parameter :: state_names(3) = ['stick', 'slip ', 'open ']
  !> status changes of one element in a step before it is held (update_states)
  integer, parameter :: max_flips = 4
  real(rp), parameter :: deg = acos(-1.0_rp) / 180.0_rp
  !> columns of an element's jump operator: 4 + 4 nodes and (space 'bubble')
  !> the bubbles of its two sides, 3 components each (unused ones: dof 0)
  integer(ip), parameter :: nju = 30
  !> Fewer interface elements than this are solved by MUMPS whatever the
  !> deck's method: the block preconditioners' AMG on a Schur complement of a
  !> few rows fails (1 element: 3 rows, hypre refuses the set-up); with 4
  !> elements all three block preconditioners converge.
  integer, parameter :: min_block_interfaces = 4

  type, extends(physics_component_t) :: interface_contact_t
    type(contact_config_t) :: ccfg                 !< &contact
    type(dof_map_t) :: t                           !< 3 traction components per interface element
    logical :: stabilized = .true.
    type(mechanics_component_t), pointer :: mc => null()   !< the displacements' component
    ! per local interface element
    real(rp), allocatable :: wb(:)                 !< (n) integral of a bubble over the element [m^2]
    real(rp), allocatable :: area(:), wn(:,:), rot(:,:,:)  !< [m^2], (4,n) nodal areas, (3,3,n) frame rows
    real(rp), allocatable :: s(:)                  !< scale of the open and slip rows [m^3/Pa]
    !> tan(phi), cohesion [Pa], the prescribed fluid pressure on the faces [Pa]
    real(rp), allocatable :: fric(:), coh(:)
    real(rp), allocatable :: pres(:)
    integer, allocatable :: fault(:)               !< index of the element's fault in faults(:)
    integer, allocatable :: state(:)
    integer, allocatable :: flips(:)               !< status changes of the element in this step (any)
    logical, allocatable :: fresh(:)               !< slipping since the last status update (was stick)
    logical, allocatable :: slipped(:)             !< slip at the step's start or at an update of the step
    real(rp), allocatable :: allow(:)              !< min(c |dg|, tau) at the element's last stuck iterate of the step [Pa]
    real(rp), allocatable :: gap_prev(:)           !< an open element's normal jump at the previous update of the step [m] (-1: none)
    logical, allocatable :: early(:)               !< closed by its gap's trend in this step (close_ratio)
    integer(gp), allocatable :: held(:)            !< per fault (of faults(:)): elements held in their status at the last update
    integer(gp), allocatable :: held_open(:)       !< the same, held between open and closed
    !> the largest held violation of the last update (held_excess): which
    !> check it broke (one of violation_names, 0: none held) and the
    !> element's stabilization allowance then, relative as held_excess
    integer :: held_kind = 0
    real(rp) :: held_allow = 0.0_rp
    integer(gp) :: changes = 0                     !< status changes of the last update
    integer(gp) :: moves(3, 3) = 0                 !< (from, to) status changes of the last update
    real(rp), allocatable :: trac(:,:), trac_step(:,:)     !< (3,n) local-frame traction [Pa]
    real(rp), allocatable :: jump(:,:), jump_step(:,:)     !< (3,n) local-frame mean jump [m]
    !> (n) |B| |u| / A of the normal jump: the size of the displacements it
    !> is the difference of, so its round-off is eps times it [m]
    real(rp), allocatable :: jump_mag(:)
    real(rp), allocatable :: jump_geo(:,:)         !< (3,n) jumps of step 0 [m]: outputs are measured from them
    ! stabilization edges
    type(fault_edges_t) :: edges                   !< neighbouring elements (fault_edges)
    real(rp), allocatable :: eb(:,:,:,:)           !< (3,3,3,edges%n): blocks 11, 12, 22
    real(rp) :: length = 1.0_rp                    !< mesh size scale [m] (sqrt of the mean element area)
    type(fault_config_t), allocatable :: faults(:)
    type(mesh_pieces_t) :: pieces                  !< connected pieces of the mesh (faults cut them)
    integer(gp) :: open_checked = -1               !< open elements when the pieces were last checked
    integer(gp), allocatable :: fault_counts(:,:)  !< (3, faults) stick/slip/open per fault, last reported
    type(fracture_output_t) :: fout                !< the 'fractures' grid
    character(len=path_len) :: fractures_xdmf = '' !< its XDMF file, once open
  contains
    procedure :: fields
    procedure :: field_size
    procedure :: components_of
    procedure :: read_deck
    procedure :: check_deck
    procedure :: parameter_groups
    procedure :: setup
    procedure :: set_patterns
    procedure :: report_setup
    procedure :: unknowns_note
    procedure :: begin_step
    procedure :: couple
    procedure :: assemble
    procedure :: take_solution
    procedure :: residual_names
    procedure :: field_residuals
    procedure :: scaling
    procedure :: check_system
    procedure :: update_status
    procedure :: iteration_note
    procedure :: status_notes
    procedure :: save_state
    procedure :: load_state
    procedure :: accept_step
    procedure :: open_output
    procedure :: write_output
    procedure :: sample
    procedure :: progress
    procedure :: step_notes
    procedure :: finish
    procedure :: element_entities
    procedure :: jump_operator
    procedure :: update_states
    procedure :: count_states
    procedure :: ht_diagonal
    procedure :: tip_skew
    procedure :: row_scales
    procedure :: free
  end type interface_contact_t

contains

  subroutine fields(self, names)
    class(interface_contact_t), intent(in) :: self
    character(len=field_len), allocatable, intent(out) :: names(:)
    names = [character(len=field_len) :: 't']
  end subroutine fields

  integer(ip) function field_size(self, k)
    class(interface_contact_t), intent(in) :: self
    integer, intent(in) :: k
    field_size = self%t%n_owned()
  end function field_size

  integer function components_of(self, k) result(n)
    class(interface_contact_t), intent(in) :: self
    integer, intent(in) :: k
    n = 3
  end function components_of

  !> &contact and the &fault groups (into the composition's faults, with
  !> their pressure histories). Collective.
  subroutine read_deck(self, ctx, d, mcfg, log, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call self%ccfg%read(d, log, status)
    if (status%ok()) call read_faults(d, log, ctx%sim%faults, status, mcfg%source)
    if (status%ok()) call load_fault_histories(ctx%sim%comm, ctx%sim%faults, status)
  end subroutine read_deck

  !> The space's limits, the loop's controls (&contact max_newton,
  !> max_cuts: the step's convergence is judged on the residual) and the
  !> linear solver, which must suit a saddle point. The space 'bubble' sets
  !> the mechanics' bubbles.
  subroutine check_deck(self, ctx, d, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
    type(mechanics_component_t), pointer :: mc
    logical :: matrix, fluid
    ! with the matrix's fluid, a mesh without faults is Biot's problem
    matrix = associated(ctx%find('matrix_flow'))
    fluid = matrix .or. associated(ctx%find('fracture_flow'))
    associate (sim => ctx%sim)
      ! the in-situ and pressure-change loads are nodal: the bubbles' share of
      ! them is not made yet
      if (self%ccfg%space == 'bubble' .and. (sim%geo%on .or. size(sim%pcs) > 0)) then
        call d%fail(status, 'contact', 1, 'space', "'bubble' does not take &geostatic or &pressure_change yet "// &
          "(use space = 'stabilized')")
        return
      end if
      mc => mechanics_of(ctx)
      mc%bubble = self%ccfg%space == 'bubble'
      call self%ccfg%resolve_schur_solve(fluid)
      sim%max_newton = self%ccfg%max_newton
      sim%max_cuts = self%ccfg%max_cuts
      sim%residual_test = .true.
      sim%moving_rtol = self%ccfg%moving_rtol
      ! with the matrix's fluid the residual alone does not bound the
      ! pressure's error (coupled_simulation's check_residual): its settled
      ! iterations solve to rtol. The fractures' fluid has an update test
      ! that holds after inexact solves too (update_check), so its settled
      ! iterations take the forcing term: the seed's nine fractures at 4 m,
      ! 419 FGMRES iterations against 589, 27 Newton iterations against 24,
      ! the fields within 1e-6 of MUMPS's
      sim%settled_forcing = .not. matrix
      ctx%newton_tol = self%ccfg%newton_tol
      if (sim%solver%method == 'cg') then
        call status%set("deck '"//trim(d%path)//"', group &solver, variable method: "// &
          "the contact system is a saddle point: use 'fgmres' or 'mumps'")
      else if (sim%solver%method == 'fgmres' .and. sim%solver%precon /= 'block' .and. sim%solver%precon /= 'mgr') then
        call status%set("deck '"//trim(d%path)//"', group &solver, variable precon: the contact system with fgmres "// &
          "needs precon = 'block' (ours, &contact block) or 'mgr' (hypre's)")
      else if (size(sim%faults) == 0 .and. .not. matrix) then
        call status%set("deck '"//trim(d%path)//"': physics = 'contact' needs at least one &fault group")
      end if
    end associate
  end subroutine check_deck

  !> Every &fault, then &contact.
  subroutine parameter_groups(self, ctx, list)
    class(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(param_group_t), allocatable, intent(out) :: list(:)
    integer :: k
    allocate(list(size(ctx%sim%faults) + 1))
    do k = 1, size(ctx%sim%faults)
      call ctx%sim%faults(k)%describe(list(k))
    end do
    call self%ccfg%describe(list(size(ctx%sim%faults) + 1))
  end subroutine parameter_groups

  !> Every element split (check_split); tractions, geometry, stabilization
  !> and the faults' properties and initial statuses; the faces' pressure
  !> is pres until a component provides another. A few interface elements
  !> are solved by MUMPS. Collective.
  subroutine setup(self, ctx, log, status)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer(ip) :: e, n, f
    call check_split(ctx%mesh, status)
    if (.not. status%ok()) return
    if (ctx%sim%solver%method /= 'mumps' .and. ctx%mesh%iface_map%n_global < min_block_interfaces) then
      ! a Schur complement of a few rows is no system for AMG (BoomerAMG
      ! refuses a 3 x 3 one): the whole system is small, a direct solve is cheap
      ctx%sim%solver%method = 'mumps'
      call log%info('contact: only '//itoa(int(ctx%mesh%iface_map%n_global))//' interface element(s), fewer than '// &
        itoa(min_block_interfaces)//' for the block preconditioners: the direct solver MUMPS is used instead of '// &
        'FGMRES')
    end if
    self%mc => mechanics_of(ctx)
    associate (mesh => ctx%mesh)
      self%stabilized = self%ccfg%stabilization == 'algebraic'
      self%faults = ctx%sim%faults
      n = mesh%n_ifaces
      call self%t%init('traction', mesh%iface_map, 3_ip)
      call geometry(self, mesh)
      call self%edges%build(mesh)
      call edge_blocks(self, mesh)
      ! fault properties and initial state
      allocate(self%fric(n), self%coh(n), self%pres(n), self%state(n), self%fault(n), self%flips(n), self%fresh(n), &
               self%slipped(n), self%allow(n), self%gap_prev(n), self%early(n))
      self%flips = 0
      self%allow = 0.0_rp
      self%gap_prev = -1.0_rp
      self%early = .false.
      self%fresh = .false.
      self%slipped = .false.
      do e = 1, n
        f = fault_index(self, mesh, mesh%iface_fault(e))
        self%fault(e) = f
        if (f == 0) then
          call status%set("fault '"//trim(mesh%fault_names(mesh%iface_fault(e)))//"' of the mesh has no &fault group")
          return
        end if
        self%fric(e) = tan(self%faults(f)%friction_angle * deg)
        self%coh(e) = self%faults(f)%cohesion
        self%pres(e) = 0.0_rp
        self%state(e) = state_stick
        if (self%faults(f)%initial_state == 'open') self%state(e) = state_open
      end do
      allocate(self%trac(3, n), self%trac_step(3, n), self%jump(3, n), self%jump_step(3, n), self%jump_geo(3, n), &
               self%jump_mag(n))
      self%trac = 0.0_rp
      self%trac_step = 0.0_rp
      self%jump = 0.0_rp
      self%jump_step = 0.0_rp
      self%jump_geo = 0.0_rp
    end associate
    ctx%face_pressure => self%pres
  end subroutine setup

  !> The displacement entities of each local element (dof_map's entity
  !> numbers): 4 + 4 nodes, then its bubbles (0: none); and the element
  !> itself (self_conn), for element_pattern.
  subroutine element_entities(self, mc, mesh, conn8, self_conn)
    class(interface_contact_t), intent(in) :: self
    type(mechanics_component_t), intent(in) :: mc
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), allocatable, intent(out) :: conn8(:,:), self_conn(:,:)
    integer(ip) :: e, n, s
    n = mesh%n_ifaces
    allocate(conn8(10, n), self_conn(1, n))
    conn8 = 0
    do e = 1, n
      conn8(1:4, e) = mc%mech%u%entity(mesh%iface_nodes(:, 1, e))
      conn8(5:8, e) = mc%mech%u%entity(mesh%iface_nodes(:, 2, e))
      if (mc%bubble) then
        do s = 1, 2
          conn8(8 + s, e) = mc%mech%u%extra_entity(mc%bub%of_iface(s, e))
        end do
      end if
      self_conn(1, e) = e
    end do
  end subroutine element_entities

  !> The patterns of C1 (u, t), C2 (t, u) and the (t, t) block; C1. Collective.
  subroutine set_patterns(self, ctx, status)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:), conn8(:,:), self_conn(:,:), pairs(:,:)
    integer(ip) :: n, nown
    integer :: bu, bt
    n = ctx%mesh%n_ifaces
    nown = ctx%mesh%iface_map%n_owned
    bu = ctx%block('u')
    bt = ctx%block('t')
    call self%element_entities(self%mc, ctx%mesh, conn8, self_conn)
    associate (umap => self%mc%mech%u%map, tmap => self%t%map)
      call element_pattern(umap%n_owned / 3, conn8, self_conn, 3_ip, 3_ip, row_ptr, col)
      call ctx%sys%set_pattern(bu, bt, umap, tmap, row_ptr, col)
      call element_pattern(nown, self_conn, conn8, 3_ip, 3_ip, row_ptr, col)
      call ctx%sys%set_pattern(bt, bu, tmap, umap, row_ptr, col)
      allocate(pairs(2, n + self%edges%n))
      pairs(:, 1:n) = spread(self_conn(1, :), 1, 2)
      pairs(:, n+1:) = self%edges%pair
      call element_pattern(nown, pairs, pairs, 3_ip, 3_ip, row_ptr, col)
      call ctx%sys%set_pattern(bt, bt, tmap, tmap, row_ptr, col)
    end associate
    call assemble_c1(self, ctx)
  end subroutine set_patterns

  !> The mesh's pieces held (rigid-body check), the tips' skew, the
  !> bubbles. Collective.
  subroutine report_setup(self, ctx, log, status)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call self%pieces%build(ctx%mesh)
    call check_pieces(self, ctx, status)
    if (.not. status%ok()) return
    if (.not. self%stabilized) call check_free_jump(self, ctx%mesh, status)
    if (.not. status%ok()) return
    call warn_tip_skew(self, ctx, log)
    if (.not. (self%stabilized .or. self%mc%bubble)) call log%warn("contact: stabilization = 'none' on space = "// &
      "'stabilized': Q1 displacements with piecewise-constant tractions are not inf-sup stable without H_t, "// &
      'so the tractions may oscillate from element to element and the iterative solve''s counts grow with '// &
      "refinement until it fails; use stabilization = 'algebraic' (the default) or space = 'bubble' "// &
      '(doc/contact.md, stable space)')
    if (self%mc%bubble) call log%info('contact: space bubble, u has '// &
      itoa(int(self%mc%bub%map%n_global))//' face bubbles (3 unknowns each) beside the nodes')
  end subroutine report_setup

  !> The interface elements and the stabilization's edge entries. Collective.
  subroutine unknowns_note(self, ctx, note)
    class(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(out) :: note
    note = itoa(int(ctx%mesh%iface_map%n_global))//' interface elements, '// &
      itoa(int(ctx%sim%comm%sum(self%edges%n)))//' stabilization edge entries'
  end subroutine unknowns_note

  !> Remember the tractions and jumps of the step's start (the stick and
  !> slip conditions are measured from them); the faces' prescribed
  !> pressure at ctx%lf; on the first call the row scales s (K is
  !> assembled: the mechanics come first). (A step cut goes back to the
  !> accepted state through the simulation's state record.) Collective.
  subroutine begin_step(self, ctx)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: e
    real(rp) :: lf
    self%trac_step = self%trac
    self%jump_step = self%jump
    self%flips = 0
    self%fresh = .false.
    self%slipped = self%state == state_slip
    self%allow = 0.0_rp
    self%gap_prev = -1.0_rp
    self%early = .false.
    lf = ctx%lf
    associate (mesh => ctx%mesh, mech => self%mc%mech)
      do e = 1, mesh%n_ifaces
        associate (f => self%faults(self%fault(e)))
          self%pres(e) = lf * f%pressure * f%factor(lf)
        end associate
        ! the in-situ pore pressure (&geostatic water table) acts on the faces
        ! too, and so does a &pressure_change of the cells on either side
        if (mech%geo%on) self%pres(e) = self%pres(e) + &
          mech%geo%pore_pressure(sum(mesh%coords(3, mesh%iface_nodes(:, 1, e))) / 4.0_rp)
        self%pres(e) = self%pres(e) + 0.5_rp * lf * (mech%pressure_change_at(mesh, mesh%iface_cells(1, e)) + &
                                                     mech%pressure_change_at(mesh, mesh%iface_cells(2, e)))
      end do
    end associate
    if (.not. allocated(self%s)) call self%row_scales(ctx)
  end subroutine begin_step

  !> The row scales s: the diagonal of C2 diag(K)^-1 C1, per element.
  !> Collective.
  subroutine row_scales(self, ctx)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    real(rp), allocatable :: d(:)
    real(rp) :: kn(2)
    integer(ip) :: e, a, s, nd
    associate (mesh => ctx%mesh, mc => self%mc)
      allocate(d(mc%mech%u%n_local()), self%s(mesh%n_ifaces))
      d = 0.0_rp
      call ctx%sys%a(ctx%block('u'), ctx%block('u'))%diagonal(d(1:mc%mech%u%n_owned()))
      call mc%mech%u%map%import(d)
      do e = 1, mesh%n_ifaces
        self%s(e) = 0.0_rp
        do a = 1, 4
          do s = 1, 2
            nd = mesh%iface_nodes(a, s, e)
            kn(s) = sum(d(mc%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))) / 3.0_rp
          end do
          self%s(e) = self%s(e) + self%wn(a, e)**2 * (1.0_rp / kn(1) + 1.0_rp / kn(2))
        end do
        ! with bubbles, theirs too: s is the diagonal of C2 diag(K)^-1 C1
        if (.not. mc%bubble) cycle
        do s = 1, 2
          kn(s) = sum(d(mc%mech%u%extra_dof(mc%bub%of_iface(s, e), [1_ip, 2_ip, 3_ip]))) / 3.0_rp
        end do
        self%s(e) = self%s(e) + self%wb(e)**2 * (1.0_rp / kn(1) + 1.0_rp / kn(2))
      end do
    end associate
  end subroutine row_scales

  !> The faces' forces on the momentum rows, C1 (t - t_p), and their
  !> operands' magnitudes |C1| |t - t_p| (free rows and prescribed alike:
  !> the mechanics leaves the prescribed ones out). Collective.
  subroutine couple(self, ctx)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp), allocatable :: tp(:), w(:), ca(:), rmax(:)
    integer(ip) :: e, u0, u1, t0, t1
    integer :: bu, bt
    bu = ctx%block('u')
    bt = ctx%block('t')
    call ctx%range('u', u0, u1)
    call ctx%range('t', t0, t1)
    allocate(tp(self%t%n_owned()), w(u1 - u0 + 1), ca(u1 - u0 + 1), rmax(u1 - u0 + 1))
    tp = ctx%x(t0:t1)
    do e = 1, ctx%mesh%iface_map%n_owned
      tp(3*e-2) = tp(3*e-2) - ctx%face_pressure(e)
    end do
    call ctx%sys%apply_block(bu, bt, tp, w)
    call ctx%sys%a(bu, bt)%abs_apply(tp, ca, rmax)
    ctx%momentum_coupling = ctx%momentum_coupling + w
    ctx%momentum_coupling_mag = ctx%momentum_coupling_mag + ca
  end subroutine couple

  subroutine residual_names(self, names, units)
    class(interface_contact_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    character(len=3), allocatable, intent(out) :: units(:)
    names = [character(len=8) :: 'traction']
    units = [character(len=3) :: 'Pa']
  end subroutine residual_names

  !> The diagonal H~ of its rows (ht_diagonal).
  subroutine scaling(self, ctx, d)
    class(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(inout) :: d(:)
    integer(ip) :: t0, t1
    call ctx%range('t', t0, t1)
    call self%ht_diagonal(ctx, 1.0_rp, .true., d(t0:t1))
  end subroutine scaling

  !> Every piece of the mesh must be held (check_pieces). Collective.
  subroutine check_system(self, ctx, status)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
    call check_pieces(self, ctx, status)
  end subroutine check_system

  !> The active-set update (update_states); step 0 (&geostatic) balances
  !> the in-situ state with the faults bonded: no update there. Collective.
  subroutine update_status(self, ctx, changes)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(gp), intent(out) :: changes
    changes = 0
    if (.not. ctx%initial) changes = self%update_states(ctx%mesh, self%ccfg%status_tol)
    self%changes = changes
  end subroutine update_status

  subroutine iteration_note(self, ctx, rel, line)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(in) :: rel(:)
    character(len=*), intent(inout) :: line
    character(len=msg_len) :: piece
    integer(gp) :: n(3)
    n = self%count_states(ctx%mesh)
    write(piece, '(a,i0,a,3(i0,a))') '  status changes ', self%changes, &
      '  stick/slip/open ', n(1), '/', n(2), '/', n(3), ''
    line = trim(line)//trim(update_piece('t', rel(1)))//trim(piece)//moves_text(self%moves)
  end subroutine iteration_note
  !> The nonzero (from, to) counts of an update, e.g. ' (slip>stick 226, slip>open 123)';
  !> empty without changes.
  function moves_text(m) result(t)
    integer(gp), intent(in) :: m(3, 3)
    character(len=:), allocatable :: t
    integer :: a, b
    t = ''
    do a = 1, 3
      do b = 1, 3
        if (m(a, b) == 0) cycle
        t = t//', '//trim(state_names(a))//'>'//trim(state_names(b))//' '//itoa(int(m(a, b)))
      end do
    end do
    if (len(t) > 0) t = ' ('//t(3:)//')'
  end function moves_text

  !> x_t (by field) and the statuses; with &geostatic, the jumps of step 0.
  subroutine save_state(self, ctx, st)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(state_record_t), intent(inout) :: st
    call ctx%put_field(st, 't')
    call st%put('status', self%state)
    if (ctx%sim%geo%on) call st%put('jump_in_situ', reshape(self%jump_geo(:, 1:ctx%mesh%iface_map%n_owned), &
                                                            [3 * ctx%mesh%iface_map%n_owned]))
  end subroutine save_state

  subroutine load_state(self, ctx, st, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: jg(:)
    integer(ip) :: no
    call ctx%get_field(st, 't', status)
    call st%get('status', self%state, status)
    self%fault_counts = counts_per_fault(self, ctx)
    if (.not. ctx%sim%geo%on) return
    no = ctx%mesh%iface_map%n_owned
    allocate(jg(3 * no))
    call st%get('jump_in_situ', jg, status)
    if (status%ok()) self%jump_geo(:, 1:no) = reshape(jg, [3, int(no)])
  end subroutine load_state

  !> Step 0 (&geostatic) accepted: its jumps become the outputs' origin.
  subroutine accept_step(self, ctx)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    if (ctx%initial) self%jump_geo = self%jump
  end subroutine accept_step

  !> The 'fractures' grid beside the mesh, in <prefix>_fractures.xdmf
  !> (none without faults: 'poromechanics_faults' allows that). Collective.
  subroutine open_output(self, ctx, out, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    if (size(ctx%sim%faults) == 0) return
    call self%fout%init(out, ctx%mesh, status)
    if (status%ok()) self%fractures_xdmf = out%writer%xdmf_path(self%fout%grid)
  end subroutine open_output

  !> The fault fields (fractures grid, fracture_output.f90; status there 0
  !> stick, 1 slip, 2 open), the fluid pressure on the faces and the total
  !> normal traction t_N - p on them (normal_traction, t_N, is the effective
  !> one that the friction law sees). Collective.
  subroutine write_output(self, ctx, out, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    if (size(ctx%sim%faults) == 0) return
    ! the output's status codes count from 0 (state_stick = 1, slip 2, open 3)
    if (status%ok()) call self%fout%write_step(out, ctx%mesh, self%trac, self%jump - self%jump_geo, &
                                                self%state - 1, self%rot, self%fric, self%coh, status)
    if (.not. status%ok()) return
    ! the fluid pressure on the faces: &fault pressure, the in-situ p0 and
    ! the mean &pressure_change of the two cells at the step's load, or the
    ! fracture flow's pressure
    associate (n => ctx%mesh%iface_map%n_owned)
      call out%writer%cell_field('pressure', ctx%face_pressure(1:n), status, self%fout%grid)
      if (status%ok()) call out%writer%cell_field('total_normal_traction', self%trac(1, 1:n) - ctx%face_pressure(1:n), &
                                                  status, self%fout%grid)
    end associate
  end subroutine write_output

  !> Per fault (mesh order) its largest slip (tangential jump), its mean
  !> slip (weighted by the elements' areas) and slipping area (elements
  !> with status slip).
  subroutine sample(self, ctx, pf, status)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: smax(:), sums(:), values(:)
    character(len=scalar_name_len), allocatable :: names(:)
    real(rp) :: s
    integer(ip) :: e
    integer :: f, nf
    associate (mesh => ctx%mesh, comm => ctx%sim%comm)
      nf = size(mesh%fault_names)
      ! sums: per fault its slipping area, its area and its area-weighted slip
      allocate(smax(nf), sums(3 * nf), names(3 * nf), values(3 * nf))
      smax = 0.0_rp
      sums = 0.0_rp
      do e = 1, mesh%iface_map%n_owned
        f = mesh%iface_fault(e)
        s = norm2(self%jump(2:3, e) - self%jump_geo(2:3, e))
        smax(f) = max(smax(f), s)
        if (self%state(e) == state_slip) sums(f) = sums(f) + self%area(e)
        sums(nf + f) = sums(nf + f) + self%area(e)
        sums(2 * nf + f) = sums(2 * nf + f) + self%area(e) * s
      end do
      call comm%sum_all(sums)
      do f = 1, nf
        names(3*f - 2) = trim(mesh%fault_names(f))//':max_slip [m]'
        names(3*f - 1) = trim(mesh%fault_names(f))//':mean_slip [m]'
        names(3*f) = trim(mesh%fault_names(f))//':slip_area [m2]'
        values(3*f - 2) = comm%max(smax(f))
        values(3*f - 1) = sums(2 * nf + f) / max(sums(nf + f), tiny(1.0_rp))
        values(3*f) = sums(f)
      end do
    end associate
    ! after the scalars of the components before it (the matrix flow's)
    if (allocated(pf%names)) then
      pf%names = [pf%names, names]
      pf%values = [pf%values, values]
    else
      call move_alloc(names, pf%names)
      call move_alloc(values, pf%values)
    end if
  end subroutine sample

  !> The statuses and the largest slip.
  subroutine progress(self, ctx, line)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(inout) :: line
    character(len=msg_len) :: piece
    integer(gp) :: n(3)
    n = self%count_states(ctx%mesh)
    write(piece, '(a,3(i0,a),a,es10.3,a)') '  stick/slip/open ', n(1), '/', n(2), '/', n(3), '', &
      '  max slip ', max_slip(self, ctx), ' m'
    line = trim(line)//piece
  end subroutine progress

  subroutine finish(self, ctx, log)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
    if (len_trim(self%fractures_xdmf) > 0) &
      call log%info('fault fields: '//trim(self%fractures_xdmf)//' (open it in ParaView)')
  end subroutine finish

  subroutine free(self)
    class(interface_contact_t), intent(inout) :: self
    call self%t%free()
    if (allocated(self%area)) deallocate(self%area, self%wn, self%rot, self%wb)
    if (allocated(self%s)) deallocate(self%s)
    if (allocated(self%fric)) deallocate(self%fric, self%coh, self%pres, self%state, &
                                                 self%fault, self%flips, self%fresh, self%slipped, self%allow, &
                                                 self%gap_prev, self%early)
    if (allocated(self%held)) deallocate(self%held, self%held_open)
    if (allocated(self%trac)) deallocate(self%trac, self%trac_step, self%jump, self%jump_step, self%jump_geo, &
                                         self%jump_mag)
    call self%edges%free()
    if (allocated(self%eb)) deallocate(self%eb)
    if (allocated(self%faults)) deallocate(self%faults)
    nullify(self%mc)
  end subroutine free
  integer function fault_index(self, mesh, mf)
    type(interface_contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: mf
    integer :: f
    fault_index = 0
    do f = 1, size(self%faults)
      if (self%faults(f)%name == mesh%fault_names(mf)) fault_index = f
    end do
  end function fault_index

  !> Area, nodal areas and frame of every local element; the mesh size scale.
  subroutine geometry(self, mesh)
    type(interface_contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip) :: e, n, nown
    real(rp) :: a_sum, n_sum
    type(parallel_comm_t) :: comm
    n = mesh%n_ifaces
    allocate(self%area(n), self%wn(4, n), self%rot(3, 3, n), self%wb(n))
    do e = 1, n
      call interface_geometry(mesh%coords(:, mesh%iface_nodes(:, 1, e)), self%area(e), self%wn(:, e), self%rot(:, :, e))
      self%wb(e) = face_bubble_integral(mesh%coords(:, mesh%iface_nodes(:, 1, e)))
    end do
    comm = mesh%comm
    nown = mesh%iface_map%n_owned
    a_sum = comm%sum(sum(self%area(1:nown)))
    n_sum = comm%sum(real(nown, rp))
    if (n_sum > 0.0_rp) self%length = sqrt(a_sum / n_sum)
  end subroutine geometry

  !> The 3x3 blocks of H_t of every edge (see the module header).
  subroutine edge_blocks(self, mesh)
    type(interface_contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: kd(:,:)
    logical, allocatable :: done(:)
    real(rp) :: mm(3, 3), inv(3), kdm(3), kdp(3), sigma
    integer(ip) :: ed, e1, e2, q, k1, k2, nm, np, cm(2), cp(2), ks(2)
    logical :: found
    allocate(self%eb(3, 3, 3, self%edges%n))
    allocate(kd(24, mesh%n_cells), done(mesh%n_cells))
    done = .false.
    do ed = 1, self%edges%n
      e1 = self%edges%pair(1, ed)
      e2 = self%edges%pair(2, ed)
      mm = 0.0_rp
      sigma = 0.0_rp
      ks = pack([1_ip, 2_ip, 3_ip, 4_ip], self%edges%of_elem(:, e1) == ed, [0_ip, 0_ip])
      do q = 0, 1
        k1 = mod(ks(1) - 1 + q, 4) + 1
        nm = mesh%iface_nodes(k1, 1, e1)
        np = mesh%iface_nodes(k1, 2, e1)
        if (nm == np) cycle                            ! a tip: no jump there
        found = .false.
        do k2 = 1, 4
          if (mesh%iface_nodes(k2, 1, e2) == nm) then
            found = .true.
            if (sigma == 0.0_rp) sigma = 1.0_rp
            cm = [mesh%iface_cells(1, e1), mesh%iface_cells(1, e2)]
            cp = [mesh%iface_cells(2, e1), mesh%iface_cells(2, e2)]
            exit
          else if (mesh%iface_nodes(k2, 2, e2) == nm) then
            found = .true.
            if (sigma == 0.0_rp) sigma = -1.0_rp
            cm = [mesh%iface_cells(1, e1), mesh%iface_cells(2, e2)]
            cp = [mesh%iface_cells(2, e1), mesh%iface_cells(1, e2)]
            exit
          end if
        end do
        if (.not. found) cycle                         ! a junction of faults
        kdm = node_diag(cm(1), nm) + node_diag(cm(2), nm)
        kdp = node_diag(cp(1), np) + node_diag(cp(2), np)
        inv = 1.0_rp / kdm + 1.0_rp / kdp
        mm(1, 1) = mm(1, 1) + self%wn(k1, e1) * self%wn(k2, e2) * inv(1)
        mm(2, 2) = mm(2, 2) + self%wn(k1, e1) * self%wn(k2, e2) * inv(2)
        mm(3, 3) = mm(3, 3) + self%wn(k1, e1) * self%wn(k2, e2) * inv(3)
      end do
      associate (r1 => self%rot(:, :, e1), r2 => self%rot(:, :, e2))
        self%eb(:, :, 1, ed) = matmul(r1, matmul(mm, transpose(r1)))
        self%eb(:, :, 2, ed) = -sigma * matmul(r1, matmul(mm, transpose(r2)))
        self%eb(:, :, 3, ed) = matmul(r2, matmul(mm, transpose(r2)))
      end associate
      ! only the local frames' own components: the stick rows measure the
      ! normal traction whole and the tangential one from the step's start,
      ! so a normal-tangential coupling (mm is not isotropic, and a fault
      ! that is not along an axis rotates it into one) made the normal row
      ! of a step's start differ from the end of the step before by H_NT
      ! times the tangential change of that step: a dipping fault under an
      ! in-situ shear drifted by 1.6 % of its displacement per unloaded step
      do q = 1, 3
        self%eb(:, :, q, ed) = diag3(self%eb(:, :, q, ed))
      end do
    end do
  contains
    !> The diagonal of a 3 x 3 block, as a block.
    pure function diag3(a) result(b)
      real(rp), intent(in) :: a(3, 3)
      real(rp) :: b(3, 3)
      b = 0.0_rp
      b(1, 1) = a(1, 1)
      b(2, 2) = a(2, 2)
      b(3, 3) = a(3, 3)
    end function diag3
    !> Diagonal stiffness (x, y, z) of node nd from cell c alone.
    function node_diag(c, nd) result(v)
      integer(ip), intent(in) :: c, nd
      real(rp) :: v(3), ke(24, 24)
      integer(ip) :: a, i
      if (.not. done(c)) then
        call self%mc%mech%element_stiffness(mesh, c, ke)
        kd(:, c) = [(ke(i, i), i = 1, 24)]
        done(c) = .true.
      end if
      v = 0.0_rp
      do a = 1, 8
        if (mesh%cell_nodes(a, c) == nd) v = kd(3*a-2:3*a, c)
      end do
    end function node_diag
  end subroutine edge_blocks
  !> C1 = integral of [[N]]^T R^T over the owned elements (rows of the
  !> prescribed dofs left out). Constant: assembled once.
  subroutine assemble_c1(self, ctx)
    type(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp) :: be(3, nju)
    integer(ip) :: e, j, rows(nju), cols(3)
    associate (c1 => ctx%sys%a(ctx%block('u'), ctx%block('t')), mesh => ctx%mesh)
      call c1%zero()
      do e = 1, mesh%iface_map%n_owned
        call self%jump_operator(self%mc, mesh, e, be, rows)
        do j = 1, 24
          if (self%mc%mech%fixed(rows(j))) rows(j) = 0
        end do
        cols = self%t%dof(e, [1_ip, 2_ip, 3_ip])
        call c1%add_block(rows, cols, transpose(be))
      end do
      call c1%finalize_assembly()
    end associate
  end subroutine assemble_c1

  !> be(3, nju) = C1^T block of element e (local frame rows; columns the x, y,
  !> z dofs of its 4 minus-side then 4 plus-side nodes, then with bubbles
  !> those of its minus-side and plus-side bubbles, else dof 0 and zero
  !> columns) and those dofs. A bubble's column is the integral of the
  !> bubble over the face, wb, where a node has its nodal area.
  subroutine jump_operator(self, mc, mesh, e, be, dofs)
    class(interface_contact_t), intent(in) :: self
    type(mechanics_component_t), intent(in) :: mc
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: e
    real(rp), intent(out) :: be(3, nju)
    integer(ip), intent(out) :: dofs(nju)
    integer(ip) :: a, s
    real(rp) :: sg
    do s = 1, 2
      sg = merge(-1.0_rp, 1.0_rp, s == 1)
      do a = 1, 4
        be(:, 12*(s-1) + 3*a-2 : 12*(s-1) + 3*a) = sg * self%wn(a, e) * self%rot(:, :, e)
        dofs(12*(s-1) + 3*a-2 : 12*(s-1) + 3*a) = mc%mech%u%dof(mesh%iface_nodes(a, s, e), [1_ip, 2_ip, 3_ip])
      end do
      if (mc%bubble) then
        be(:, 24 + 3*s-2 : 24 + 3*s) = sg * self%wb(e) * self%rot(:, :, e)
        dofs(24 + 3*s-2 : 24 + 3*s) = mc%mech%u%extra_dof(mc%bub%of_iface(s, e), [1_ip, 2_ip, 3_ip])
      else
        be(:, 24 + 3*s-2 : 24 + 3*s) = 0.0_rp
        dofs(24 + 3*s-2 : 24 + 3*s) = 0
      end if
    end do
  end subroutine jump_operator

  !> Zero the columns of be (from jump_operator) whose node dofs the
  !> displacement conditions fix. Local.
  subroutine drop_fixed(self, be, dofs)
    type(interface_contact_t), intent(in) :: self
    real(rp), intent(inout) :: be(3, nju)
    integer(ip), intent(in) :: dofs(nju)
    integer :: j
    do j = 1, 24
      if (self%mc%mech%fixed(dofs(j))) be(:, j) = 0.0_rp
    end do
  end subroutine drop_fixed
  !> The Jacobian blocks of the contact rows (C2 and the (t, t) block) and
  !> their rhs = -residual at the current state (x, u, trac, jump, state).
  !> Collective.
  subroutine assemble(self, ctx)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp) :: be(3, nju), jt(3, nju), r(3), v(3), hb(3, 3), dd(2), dg(2), tau, nrm, p2(2, 2), z(2), cz
    integer(ip) :: e, k, ed, o, dofs(nju), cols(3), ne, t0, t1
    associate (jtu => ctx%sys%a(ctx%block('t'), ctx%block('u')), jtt => ctx%sys%a(ctx%block('t'), ctx%block('t')), &
               mesh => ctx%mesh)
      call jtu%zero()
      call jtt%zero()
      call ctx%range('t', t0, t1)
      do e = 1, mesh%iface_map%n_owned
        call self%jump_operator(self%mc, mesh, e, be, dofs)
        call drop_fixed(self, be, dofs)
        cols = self%t%dof(e, [1_ip, 2_ip, 3_ip])
        ne = ncon(self%state(e))
        r = 0.0_rp
        jt = 0.0_rp
        select case (self%state(e))
        case (state_stick)
          jt = be
          r(1) = self%area(e) * self%jump(1, e)
          r(2:3) = self%area(e) * (self%jump(2:3, e) - self%jump_step(2:3, e))
        case (state_slip)
          jt(1, :) = be(1, :)
          r(1) = self%area(e) * self%jump(1, e)
          ! the friction limit, zero where t_N > 0 (within status_tol) would
          ! make it negative
          tau = max(self%coh(e) - self%fric(e) * self%trac(1, e), 0.0_rp)
          dg = self%jump(2:3, e) - self%jump_step(2:3, e)
          hb = 0.0_rp
          ! semi-smooth Newton on t_T = tau z / |z|, z = t_T + c dg with
          ! c = A / s (a stiffness): the direction blends the traction and
          ! the slip increment of the step, so that a new slip element needs
          ! no special case and a small increment does not steer it (with
          ! dg, the old Newton direction, an element whose increment was
          ! still tiny reversed it and went back to stick, and the active
          ! set cycled). Before any increment of the step (dg = 0) the
          ! direction is held (jt = 0, t_T = tau t_T/|t_T|): the exact
          ! derivative there, rank one in t_T, cost the reordered
          ! preconditioner 3x its iterations. So is it in the first iteration
          ! of an element's first slip in the step (fresh): its dg is the stick
          ! solution's stabilization allowance, |z| is about tau when the
          ! load crossed the limit gently, and the exact derivative then
          ! constrains the slip across the direction, t_T's component there a
          ! multiplier with no stabilization (Q1-P0 unstable, the count grows
          ! with refinement). Seed's nine fractures, first iteration after
          ! slip starts (step 3, Newton 2), FGMRES its at 4, 2, 1 m cells:
          ! 58, 116, 185 with the exact derivative; 26, 29, 32 held. The
          ! step may need one Newton iteration more (1 m: 8 against 7), but
          ! fewer iterations in all (2 m, step 3: 242 FGMRES its against 325).
          cz = self%area(e) / self%s(e)
          z = self%trac(2:3, e) + cz * dg
          nrm = norm2(z)
          dd = 0.0_rp
          if (nrm > 0.0_rp) dd = z / nrm
          p2 = -spread(dd, 2, 2) * spread(dd, 1, 2)
          p2(1, 1) = p2(1, 1) + 1.0_rp
          p2(2, 2) = p2(2, 2) + 1.0_rp
          r(2:3) = -self%s(e) * (self%trac(2:3, e) - tau * dd)
          hb(2, 2) = -self%s(e)
          hb(3, 3) = -self%s(e)
          if (nrm > 0.0_rp .and. any(dg /= 0.0_rp) .and. .not. self%fresh(e)) then
            hb(2:3, 2:3) = hb(2:3, 2:3) + self%s(e) * tau / nrm * p2
            jt(2:3, :) = self%s(e) * tau * cz / (nrm * self%area(e)) * matmul(p2, be(2:3, :))
          end if
          if (tau > 0.0_rp) hb(2:3, 1) = -self%s(e) * self%fric(e) * dd
          call jtt%add_block(cols, cols, hb)
        case (state_open)
          r = -self%s(e) * self%trac(:, e)
          hb = 0.0_rp
          hb(1, 1) = -self%s(e)
          hb(2, 2) = -self%s(e)
          hb(3, 3) = -self%s(e)
          call jtt%add_block(cols, cols, hb)
        end select
        call jtu%add_block(cols, dofs, jt)
        ! stabilization: -H restricted to the constrained components
        if (self%stabilized .and. ne > 0) then
          do k = 1, 4
            ed = self%edges%of_elem(k, e)
            if (ed == 0) cycle
            if (self%edges%pair(1, ed) == e) then
              o = self%edges%pair(2, ed)
              hb = self%eb(:, :, 1, ed)
              call add_h(hb, e)
              hb = self%eb(:, :, 2, ed)
              call add_h(hb, o)
            else
              o = self%edges%pair(1, ed)
              hb = self%eb(:, :, 3, ed)
              call add_h(hb, e)
              hb = transpose(self%eb(:, :, 2, ed))
              call add_h(hb, o)
            end if
          end do
        end if
        ctx%rhs(t0 + 3*(e-1) : t0 + 3*e - 1) = -r
      end do
      call jtu%finalize_assembly()
      call jtt%finalize_assembly()
    end associate
  contains
    !> Row e gets -hb(1:ne, 1:n_o) on the columns of o and the residual -hb v(o).
    subroutine add_h(hbl, oe)
      real(rp), intent(in) :: hbl(3, 3)
      integer(ip), intent(in) :: oe
      integer(ip) :: no2, cols_o(3)
      real(rp) :: blk(3, 3)
      no2 = ncon(self%state(oe))
      if (no2 == 0) return
      cols_o = self%t%dof(oe, [1_ip, 2_ip, 3_ip])
      blk = 0.0_rp
      blk(1:ne, 1:no2) = -hbl(1:ne, 1:no2)
      call ctx%sys%a(ctx%block('t'), ctx%block('t'))%add_block(cols(1:ne), cols_o(1:no2), blk(1:ne, 1:no2))
      v(1) = self%trac(1, oe)
      v(2:3) = self%trac(2:3, oe) - self%trac_step(2:3, oe)
      r(1:ne) = r(1:ne) - matmul(hbl(1:ne, 1:no2), v(1:no2))
    end subroutine add_h
  end subroutine assemble
  !> Constrained traction components of a status.
  pure integer(ip) function ncon(st)
    integer, intent(in) :: st
    select case (st)
    case (state_stick)
      ncon = 3
    case (state_slip)
      ncon = 1
    case default
      ncon = 0
    end select
  end function ncon
  !> The tractions of x (with ghosts) and the mean jumps of the local
  !> elements at the mechanics' displacements (taken before). Collective.
  subroutine take_solution(self, ctx)
    class(interface_contact_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp), allocatable :: tl(:)
    real(rp) :: be(3, nju)
    integer(ip) :: t0, t1, e, dofs(nju)
    call ctx%range('t', t0, t1)
    allocate(tl(self%t%n_local()))
    tl = 0.0_rp
    tl(1:t1-t0+1) = ctx%x(t0:t1)
    call self%t%map%import(tl)
    self%trac = reshape(tl, [3, ctx%mesh%n_ifaces])
    do e = 1, ctx%mesh%n_ifaces
      call self%jump_operator(self%mc, ctx%mesh, e, be, dofs)
      self%jump(:, e) = matmul(be, self%mc%u(max(dofs, 1_ip))) / self%area(e)   ! unused columns are zero
      self%jump_mag(e) = dot_product(abs(be(1, :)), abs(self%mc%u(max(dofs, 1_ip)))) / self%area(e)
    end do
  end subroutine take_solution

  !> traction [Pa]: each contact row divided by its element's scale s (a
  !> stick row's gap A g and a slip row's friction mismatch alike become
  !> the traction that would close them at the element's stiffness) over
  !> the owned rows; against the tractions and the faces' fluid pressures.
  !> noise: the magnitude of its terms' operands. Collective.
  subroutine field_residuals(self, ctx, res, ref, noise)
    class(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(out) :: res(:), ref(:), noise(:)
    real(rp), allocatable :: rt(:), tp(:), nt(:)
    integer(ip) :: t0, t1, e, nown
    type(parallel_comm_t) :: comm
    comm = ctx%mesh%comm
    nown = ctx%mesh%iface_map%n_owned
    call ctx%range('t', t0, t1)
    allocate(rt(3 * nown), tp(nown), nt(3 * nown))
    do e = 1, nown
      rt(3*e-2:3*e) = ctx%rhs(t0 + 3*(e-1) : t0 + 3*e - 1) / self%s(e)
      tp(e) = ctx%face_pressure(e)
      nt(3*e-2:3*e) = self%area(e) * (abs(self%jump(:, e)) + abs(self%jump_step(:, e))) / self%s(e) + &
                      abs(self%trac(:, e)) + abs(self%trac_step(:, e)) + abs(tp(e))
    end do
    res(1) = pnorm2(comm, rt)
    ref(1) = pnorm2(comm, [reshape(self%trac(:, 1:nown), [3 * nown]), tp])
    noise(1) = pnorm2(comm, nt)
  end subroutine field_residuals
  !> Active-set update of the owned elements from the current state, ghosts
  !> synchronized. Returns the global number of changes. Collective.
  integer(gp) function update_states(self, mesh, tol) result(changed)
    class(interface_contact_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: tol                    !< relative tolerance of the checks
    integer :: f
    type(parallel_comm_t) :: comm
    real(rp) :: t_ref, g_ref, excess, t_open, big
    real(rp), allocatable :: st(:)
    integer, allocatable :: before(:)
    integer(ip) :: e, nown
    integer :: new, kind
    comm = mesh%comm
    nown = mesh%iface_map%n_owned
    t_ref = 0.0_rp
    g_ref = 0.0_rp
    if (nown > 0) then
      t_ref = maxval(abs(self%trac(:, 1:nown)))
      t_ref = max(t_ref, maxval(abs(self%pres(1:nown))), maxval(self%coh(1:nown)))
      g_ref = maxval(abs(self%jump(:, 1:nown)))
    end if
    t_ref = comm%max(t_ref)
    g_ref = max(comm%max(g_ref), 1.0e-9_rp * self%length)
    ! damped opening (&contact open_fraction): a closed element opens when
    ! its tension is at least that fraction of the largest one among the
    ! closed elements that may still change; the others wait, keeping their
    ! status. (The seed's nine fractures at 2 m cells, opening step: the
    ! closed fractures' small storage over-pressurizes them at the first
    ! iterate and the undamped update opened 974 elements where 267 stay
    ! open, closed back a few per update: 15 Newton iterations; with 0.5,
    ! 9. Letting the waiting elements change stick <-> slip: 10.)
    t_open = 0.0_rp
    do e = 1, nown
      if (self%state(e) /= state_open .and. self%flips(e) < max_flips) t_open = max(t_open, self%trac(1, e))
    end do
    t_open = self%ccfg%open_fraction * comm%max(t_open)
    changed = 0
    self%moves = 0
    if (.not. allocated(self%held)) allocate(self%held(size(self%faults)), self%held_open(size(self%faults)))
    self%held = 0
    self%held_open = 0
    self%held_excess = 0.0_rp
    self%held_kind = 0
    self%held_allow = 0.0_rp
    before = self%state
    do e = 1, nown
      call judge_element(self, e, tol, t_ref, g_ref, t_open, before, new, excess, kind)
      ! an element that changed max_flips times in this step sits on the
      ! friction limit (stick <-> slip) or at the opening (open <-> closed:
      ! t_N and g_N both zero) within the tolerances: it keeps its status.
      ! (Without the cap on the opening, one element of the seed's nine
      ! fractures at 1 m cells went open, stick, open, ... through 20 Newton
      ! iterations and the step was cut twice.) Only within hold_tol of its
      ! limit: beyond, the held status is wrong, and it changes. (Reduced
      ! nine fractures at 2 m cells, steps of 0.25 s from t = 15 s: at
      ! t = 16 s elements held in stick beyond the friction limit by 5e-3
      ! stopped the loop, unchanged, until max_newton, and the step was cut.)
      ! Between stick and slip also within the element's own stabilization
      ! allowance c |dg| at its last stuck iterate, at most tau: the stick rows let its
      ! jump move that much, so the friction law is not resolved more finely
      ! there. (Seed's nine fractures at 1 m cells, step 7: elements of t_N
      ! -0.05 to -0.3 MPa beside open ones, c |dg| 10-60 % of tau, stuck 3-15 %
      ! beyond tau and slipping 5-15 % under it, cycled stick <-> slip past
      ! 1e-3 of the largest traction to max_newton, and the step was cut.)
      if (new /= self%state(e)) then
        if (self%flips(e) >= max_flips .and. (excess <= hold_tol .or. &
            (new /= state_open .and. self%state(e) /= state_open .and. excess * t_ref <= self%allow(e)))) then
          if (new == state_open .or. self%state(e) == state_open) then
            self%held_open(self%fault(e)) = self%held_open(self%fault(e)) + 1
          else
            self%held(self%fault(e)) = self%held(self%fault(e)) + 1
          end if
          if (excess > self%held_excess .or. self%held_kind == 0) then
            self%held_excess = excess
            self%held_kind = kind
            self%held_allow = self%allow(e) / max(t_ref, tiny(1.0_rp))
          end if
          new = self%state(e)
        else
          self%flips(e) = self%flips(e) + 1
        end if
      end if
      if (new /= self%state(e)) then
        changed = changed + 1
        self%moves(self%state(e), new) = self%moves(self%state(e), new) + 1
      end if
      ! the direction is held in an element's first slip of the step only:
      ! one that slips again (it turned back through stick) takes the exact
      ! derivative at once
      self%fresh(e) = new == state_slip .and. self%state(e) == state_stick .and. .not. self%slipped(e)
      ! the gap an element that stays open had at this update (close_ratio)
      self%gap_prev(e) = merge(self%jump(1, e), -1.0_rp, new == state_open .and. self%state(e) == state_open)
      if (new == state_slip) self%slipped(e) = .true.
      self%state(e) = new
    end do
    changed = comm%sum(changed)
    block
      integer(gp) :: flat(9)
      flat = reshape(self%moves, [9])
      call comm%sum_all(flat)
      self%moves = reshape(flat, [3, 3])
    end block
    ! the largest held violation over the ranks, with its kind and allowance
    ! (from the rank that holds it: the largest kind among equal maxima)
    big = comm%max(self%held_excess)
    if (self%held_kind == 0 .or. self%held_excess < big) then
      self%held_kind = 0
      self%held_allow = 0.0_rp
    end if
    self%held_excess = big
    self%held_kind = comm%max(self%held_kind)
    self%held_allow = comm%max(self%held_allow)
    do f = 1, size(self%held)
      self%held(f) = comm%sum(self%held(f))
      self%held_open(f) = comm%sum(self%held_open(f))
    end do
    allocate(st(mesh%n_ifaces))
    st = real(self%state, rp)
    call mesh%iface_map%import(st)
    self%state = nint(st)
  end function update_states

  !> Whether open element e closes ahead of its overlap (&contact
  !> close_ratio): once a step, an open element beside a closed one (before:
  !> the statuses before this update) whose gap fell below close_ratio times
  !> its gap at the previous update. With 0.5 that is the linear
  !> extrapolation of its last two gaps reaching zero by the next update.
  !> (Seed's nine fractures at 1 m cells, opening step: the first update
  !> opens 349 elements where 74-95 stay open, and the overlap alone closed
  !> the excess a ring per update as each edge element's gap shrank, e.g.
  !> 3.12, 1.65, 0.73, 0.23 micrometres: 12 Newton iterations; with 0.5, 9,
  !> in another state of the band consistent open and closed; 0.6: 10, with
  !> reopenings.) Local.
  logical function closes_early(self, e, before) result(yes)
    class(interface_contact_t), intent(in) :: self
    integer(ip), intent(in) :: e
    integer, intent(in) :: before(:)
    integer :: k
    integer(ip) :: ed, o
    yes = .false.
    if (.not. self%ccfg%close_ratio > 0.0_rp .or. self%early(e) .or. .not. (self%gap_prev(e) > 0.0_rp)) return
    if (.not. (self%jump(1, e) < self%ccfg%close_ratio * self%gap_prev(e))) return
    do k = 1, 4
      ed = self%edges%of_elem(k, e)
      if (ed <= 0) cycle
      o = self%edges%pair(1, ed)
      if (o == e) o = self%edges%pair(2, ed)
      if (before(o) /= state_open) then
        yes = .true.
        return
      end if
    end do
  end function closes_early

  !> The status element e's iterate asks for (new: its own when no check
  !> fails), the violation that asks for it relative to t_ref (g_ref for an
  !> overlap) and which check it broke (viol_*, 0: none); records a stuck
  !> element's stabilization allowance. Local.
  subroutine judge_element(self, e, tol, t_ref, g_ref, t_open, before, new, excess, kind)
    class(interface_contact_t), intent(inout) :: self
    integer(ip), intent(in) :: e
    real(rp), intent(in) :: tol, t_ref, g_ref   !< the checks' tolerance, the largest traction and jump
    real(rp), intent(in) :: t_open              !< the tension at which a closed element opens
    integer, intent(in) :: before(:)            !< the statuses before this update (closes_early)
    integer, intent(out) :: new, kind
    real(rp), intent(out) :: excess
    real(rp) :: tau, dg(2), cdg(2), under, back
    new = self%state(e)
    tau = max(self%coh(e) - self%fric(e) * self%trac(1, e), 0.0_rp)
    dg = self%jump(2:3, e) - self%jump_step(2:3, e)
    cdg = self%area(e) / self%s(e) * dg          ! the step's slip as a traction, c = A / s
    excess = 0.0_rp
    kind = 0
    ! a stuck element's stabilization allowance (update_states' hold rule), at
    ! most its friction limit. (Seed's nine fractures at 1 m cells, step 7:
    ! an element whose jump moved by 0.55 of the largest traction was held
    ! stuck 0.159 of it beyond its limit; capped, 15 Newton iterations as
    ! before, the largest held violation 3.4e-3.)
    if (self%state(e) == state_stick) self%allow(e) = min(self%area(e) / self%s(e) * norm2(dg), tau)
    select case (self%state(e))
    case (state_stick)
      if (self%trac(1, e) > tol * t_ref) then
        ! in tension: it opens, or waits in its status for a later update
        if (self%trac(1, e) >= t_open) new = state_open
        excess = self%trac(1, e) / max(t_ref, tiny(1.0_rp))
        kind = viol_tension
      else if (norm2(self%trac(2:3, e)) > tau + tol * t_ref) then
        new = state_slip
        excess = (norm2(self%trac(2:3, e)) - tau) / max(t_ref, tiny(1.0_rp))
        kind = viol_beyond
      end if
    case (state_slip)
      if (self%trac(1, e) > tol * t_ref) then
        if (self%trac(1, e) >= t_open) new = state_open
        excess = self%trac(1, e) / max(t_ref, tiny(1.0_rp))
        kind = viol_tension
      else if (norm2(self%trac(2:3, e) + cdg) < tau - tol * t_ref .or. &
               dot_product(self%trac(2:3, e), cdg) < &
               -tol * t_ref * norm2(self%trac(2:3, e))) then
        ! |z| below the limit, or the slip increment against the friction
        ! traction (which the slip rows set along the last direction) by
        ! more than the tolerance, as a traction c dg: the slip turned
        ! back, and an element that reverses passes through stick. (Without
        ! it, the elements of a fault whose slip front outran the pressure
        ! swapped t_T = +tau and -tau at every Newton iteration, each
        ! increment c |dg| far above 2 tau, with no status change, for 30
        ! iterations.)
        new = state_stick
        under = tau - norm2(self%trac(2:3, e) + cdg)
        back = -dot_product(self%trac(2:3, e), cdg) / &
               max(norm2(self%trac(2:3, e)), tiny(1.0_rp))
        excess = max(under, back) / max(t_ref, tiny(1.0_rp))
        kind = merge(viol_under, viol_back, under >= back)
      end if
    case (state_open)
      ! a closing element that slipped in this step closes slipping: its
      ! tangential jump moved while it was open, and stick would pull it
      ! back to the step's start (a tangential traction far beyond the
      ! friction limit, stick -> slip at the next update). The slip rows
      ! send it to stick once its friction holds. (Seed's nine fractures at
      ! 1 m cells, opening step: 137 of 349 elements closed into stick,
      ! and stick <-> slip changed 100-300 statuses an update for 14.)
      ! (or ahead of its overlap: closes_early)
      if (self%jump(1, e) < -tol * g_ref) then
        new = merge(state_slip, state_stick, self%slipped(e))
      else if (closes_early(self, e, before)) then
        new = merge(state_slip, state_stick, self%slipped(e))
        self%early(e) = .true.
      end if
      excess = -self%jump(1, e) / g_ref
      kind = viol_overlap
    end select
  end subroutine judge_element

  !> Global number of owned elements in each status. Collective.
  function count_states(self, mesh) result(n)
    class(interface_contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(gp) :: n(3)
    integer :: k
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    do k = 1, 3
      n(k) = comm%sum(int(count(self%state(1:mesh%iface_map%n_owned) == k), gp))
    end do
  end function count_states

  !> The regular diagonal H~ of the contact rows (owned t dofs): where the
  !> diagonal of -J_tt is positive, the sum of the absolute values of that
  !> row of J_tt (a dominant diagonal: H~ >= H_t, so that the eigenvalues of
  !> the traction block of the preconditioned reordered system lie in (0, 1]);
  !> elsewhere the row scale s; times scale. With use_h = .false. it is
  !> scale * s everywhere (the augmentation D).
  !> Measured on tests/decks/contact_block.nml, all stick, cubes n = 8..32,
  !> with S* solved exactly: 9, 11, 11, 11 FGMRES iterations against 11, 12,
  !> 13, 13 with the plain diagonal of -J_tt (whose spectrum reaches 2).
  !> On a slipping element's tangential rows H~ is at least slip_floor * s.
  !> There -J_tt = s (I - theta (I - d d^T)), theta = tau / |z| (assemble_
  !> newton): for an element that barely slips theta is near 1 and the row
  !> across the direction d is nearly a multiplier with no stabilization, so
  !> the row sum s (1 - theta) made C1 H~^-1 C2 a penalty on that slip,
  !> stiffer than any stick element's, and BoomerAMG on S* lost its grip.
  !> Seed's nine fractures, step 3 (slip starts), the largest FGMRES count
  !> of its Newton iterations from the second on, 4 m / 2 m cells: 34 / 54
  !> without the floor; with it 0.1: - / 41, 0.2: - / 33, 0.3: 27 / 31,
  !> 0.5: 31 / 36, 1.0: 42 / 50 (the slipping step 4: 34 / 38 either way).
  subroutine ht_diagonal(self, ctx, scale, use_h, h)
    class(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(in) :: scale
    logical, intent(in) :: use_h
    real(rp), intent(out) :: h(:)
    !> floor of H~ on a slipping element's tangential rows, times s
    real(rp), parameter :: slip_floor = 0.3_rp
    integer(ip) :: e, c, i
    if (use_h) then
      associate (a => ctx%sys%a(ctx%block('t'), ctx%block('t')))
        call a%diagonal(h)
        do i = 1, a%n_rows
          if (-h(i) > 0.0_rp) then
            h(i) = sum(abs(a%val(a%row_ptr(i):a%row_ptr(i + 1) - 1)))
          else
            h(i) = 0.0_rp
          end if
        end do
      end associate
    else
      h = 0.0_rp
    end if
    do e = 1, ctx%mesh%iface_map%n_owned
      do c = 1, 3
        i = 3 * (e - 1) + c
        if (.not. (h(i) > 0.0_rp)) then
          h(i) = self%s(e)
        else if (c > 1 .and. self%state(e) == state_slip) then
          h(i) = max(h(i), slip_floor * self%s(e))
        end if
      end do
    end do
    h = scale * h
  end subroutine ht_diagonal

  !> Per fault (of faults(:)), the largest angle [degrees] between its
  !> normal and the cell edges that leave its tip elements (elements with an
  !> unsplit node), 0 for a fault without tips. Where the cells on the two
  !> sides are not mirror images near a tip, Q1 couples slip to a normal
  !> force that grows under refinement (doc/contact.md, tips on skewed cells).
  !> Collective.
  function tip_skew(self, mesh) result(worst)
    class(interface_contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: worst(size(self%faults))
    integer, parameter :: hex_edges(2, 12) = reshape([1, 2, 2, 3, 3, 4, 4, 1, 5, 6, 6, 7, 7, 8, 8, 5, &
                                                      1, 5, 2, 6, 3, 7, 4, 8], [2, 12])
    integer(ip) :: e, side, c, k, na, nb
    real(rp) :: v(3), cosine
    type(parallel_comm_t) :: comm
    worst = 0.0_rp
    do e = 1, mesh%iface_map%n_owned
      if (all(mesh%iface_nodes(:, 1, e) /= mesh%iface_nodes(:, 2, e))) cycle
      do side = 1, 2
        c = mesh%iface_cells(side, e)
        do k = 1, 12
          na = mesh%cell_nodes(hex_edges(1, k), c)
          nb = mesh%cell_nodes(hex_edges(2, k), c)
          if (any(mesh%iface_nodes(:, side, e) == na) .eqv. any(mesh%iface_nodes(:, side, e) == nb)) cycle
          v = mesh%coords(:, nb) - mesh%coords(:, na)
          cosine = min(1.0_rp, abs(dot_product(v, self%rot(1, :, e))) / norm2(v))
          worst(self%fault(e)) = max(worst(self%fault(e)), acos(cosine) / deg)
        end do
      end do
    end do
    comm = mesh%comm
    do k = 1, size(worst)
      worst(k) = comm%max(worst(k))
    end do
  end function tip_skew
  !> Every piece of the mesh, with the pieces joined by interface elements
  !> that are not open, must be held by the displacement conditions (checked
  !> again whenever the number of open elements changes). Collective.
  subroutine check_pieces(self, ctx, status)
    type(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(error_status_t), intent(inout) :: status
    integer(gp), allocatable :: joins(:,:)
    integer(gp) :: n_open, pair(2)
    integer(ip) :: e, n, j
    associate (mesh => ctx%mesh, st => self%state, comm => ctx%sim%comm)
      n_open = comm%sum(int(count(st(1:mesh%iface_map%n_owned) == state_open), gp))
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
      call self%mc%mech%check_anchored(mesh, self%pieces, status, joins(:, 1:n))
      if (status%ok()) self%open_checked = n_open
    end associate
  end subroutine check_pieces

  !> A warning per fault whose tip elements sit on cells skewed by more than
  !> max_tip_skew degrees from its normal. Collective.
  subroutine warn_tip_skew(self, ctx, log)
    type(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
    real(rp), parameter :: max_tip_skew = 5.0_rp
    real(rp), allocatable :: skew(:)
    integer :: f
    allocate(skew(size(self%faults)))
    skew = self%tip_skew(ctx%mesh)
    do f = 1, size(skew)
      if (skew(f) > max_tip_skew) call log%warn("fault '"//trim(self%faults(f)%name)// &
        "': the cells at its tips cross it at up to "//rtoa(real(nint(skew(f)), rp))//' degrees from its normal: '// &
        'where it slips, its tip elements'' tractions are then wrong by a share that grows under refinement; '// &
        'mesh the tip regions with cells perpendicular to the fault (doc/contact.md, tips on skewed cells)')
    end do
  end subroutine warn_tip_skew
  !> After step 0 (&geostatic): per fault, the elements whose in-situ
  !> traction lies beyond the Coulomb limit (tension, or |t_T| > c - tan(phi)
  !> t_N beyond status_tol): bonded in step 0, they slip or open at step 1.
  !> Collective.
  function in_situ_notes(self, ctx) result(lines)
    type(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=msg_len), allocatable :: lines(:)
    integer(gp), allocatable :: beyond(:)
    real(rp) :: tmax, tau
    integer(ip) :: e
    integer :: f
    allocate(beyond(size(ctx%mesh%fault_names)), lines(0))
    beyond = 0
    tmax = ctx%sim%comm%max(max(0.0_rp, maxval(abs(self%trac(:, 1:ctx%mesh%iface_map%n_owned)))))
    do e = 1, ctx%mesh%iface_map%n_owned
      associate (t => self%trac(:, e))
        tau = self%coh(e) - self%fric(e) * t(1)
        if (t(1) > self%ccfg%status_tol * tmax .or. norm2(t(2:3)) > tau + self%ccfg%status_tol * tmax) &
          beyond(ctx%mesh%iface_fault(e)) = beyond(ctx%mesh%iface_fault(e)) + 1
      end associate
    end do
    call ctx%sim%comm%sum_all(beyond)
    do f = 1, size(beyond)
      if (beyond(f) > 0) lines = [character(len=msg_len) :: lines, "geostatic: fault '"// &
        trim(ctx%mesh%fault_names(f))//"': "//itoa(int(beyond(f)))//' element(s) start beyond the Coulomb limit '// &
        '(bonded in step 0, they slip or open at step 1)']
    end do
    lines = [character(len=msg_len) :: lines, 'geostatic: in-situ state balanced with the faults bonded, max |u| '// &
      'of step 0 = '//trim(rtoa(ctx%sim%comm%max(max(0.0_rp, maxval(abs(self%mc%u))))))// &
      ' m (displacements and jumps are measured from it)']
  end function in_situ_notes

  !> Per fault, the elements the active set held in their status in this
  !> step: max_flips status changes (contact.f90), the blocked one between
  !> stick and slip (held) or to or from open (held_open).
  subroutine status_notes(self, ctx, log)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
    integer :: f
    if (.not. allocated(self%held)) return
    do f = 1, size(self%held)
      if (self%held(f) > 0) call log%warn("fault '"//trim(self%faults(f)%name)//"': "// &
        itoa(int(self%held(f)))//' element(s) changed status '//itoa(max_flips)//' times in this step and '// &
        'were held in it (stick <-> slip: they sit on the friction limit within &contact status_tol)')
      if (self%held_open(f) > 0) call log%warn("fault '"//trim(self%faults(f)%name)//"': "// &
        itoa(int(self%held_open(f)))//' element(s) changed status '//itoa(max_flips)//' times in this step and '// &
        'were held in it (open <-> closed: they sit at the opening, t_N and g_N zero within &contact '// &
        'status_tol)')
    end do
    if ((any(self%held > 0) .or. any(self%held_open > 0)) .and. self%held_kind > 0) then
      if (self%held_excess <= hold_tol) then
        call log%detail('  held elements: largest violation of the held status '//trim(rtoa(self%held_excess))// &
          ' (relative), '//trim(violation_names(self%held_kind))//', within the hold bound '//trim(rtoa(hold_tol)))
      else
        call log%detail('  held elements: largest violation of the held status '//trim(rtoa(self%held_excess))// &
          ' (relative), '//trim(violation_names(self%held_kind))//', within its stabilization allowance '// &
          trim(rtoa(self%held_allow)))
      end if
    end if
  end subroutine status_notes
  !> One line per fault whose stick/slip/open counts changed since the last
  !> report (all faults at the first), e.g.
  !>   fault 'f3': stick/slip/open 49/0/0 -> 12/37/0 (slip starts)
  !> Collective.
  subroutine step_notes(self, ctx, lines)
    class(interface_contact_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=msg_len), allocatable, intent(inout) :: lines(:)
    character(len=msg_len), allocatable :: mine(:)
    integer(gp), allocatable :: now(:,:)
    character(len=msg_len) :: starts
    integer :: f, n, k
    character(len=5), parameter :: what(3) = ['stick', 'slip ', 'open ']
    allocate(now(3, size(ctx%mesh%fault_names)))
    now = counts_per_fault(self, ctx)
    allocate(mine(size(now, 2)))
    n = 0
    do f = 1, size(now, 2)
      if (allocated(self%fault_counts)) then
        if (all(now(:, f) == self%fault_counts(:, f))) cycle
      end if
      n = n + 1
      mine(n) = "fault '"//trim(ctx%mesh%fault_names(f))//"': stick/slip/open "//counts_text(now(:, f))
      if (allocated(self%fault_counts)) then
        mine(n) = "fault '"//trim(ctx%mesh%fault_names(f))//"': stick/slip/open "// &
                   trim(counts_text(self%fault_counts(:, f)))//' -> '//counts_text(now(:, f))
        starts = ''
        do k = 1, 3
          if (now(k, f) > 0 .and. self%fault_counts(k, f) == 0) starts = trim(starts)//', '//trim(what(k))//' starts'
          if (now(k, f) == 0 .and. self%fault_counts(k, f) > 0) starts = trim(starts)//', no '//trim(what(k))//' left'
        end do
        if (len_trim(starts) > 0) mine(n) = trim(mine(n))//' ('//starts(3:len_trim(starts))//')'
      end if
    end do
    mine = mine(1:n)
    self%fault_counts = now
    if (ctx%initial) mine = [mine, in_situ_notes(self, ctx)]
    lines = [lines, mine]
  contains
    function counts_text(c) result(t)
      integer(gp), intent(in) :: c(3)
      character(len=msg_len) :: t
      t = itoa(int(c(1)))//'/'//itoa(int(c(2)))//'/'//itoa(int(c(3)))
    end function counts_text
  end subroutine step_notes

  !> Global stick/slip/open counts of every fault (3, faults). Collective.
  function counts_per_fault(self, ctx) result(c)
    type(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    integer(gp), allocatable :: c(:,:)
    integer(gp), allocatable :: flat(:)
    integer(ip) :: e
    allocate(c(3, size(ctx%mesh%fault_names)))
    c = 0
    do e = 1, ctx%mesh%iface_map%n_owned
      c(self%state(e), ctx%mesh%iface_fault(e)) = c(self%state(e), ctx%mesh%iface_fault(e)) + 1
    end do
    flat = reshape(c, [size(c)])                  ! one reduction for every fault
    call ctx%sim%comm%sum_all(flat)
    c = reshape(flat, shape(c))
  end function counts_per_fault

  !> Largest tangential jump over the faults [m]. Collective.
  real(rp) function max_slip(self, ctx)
    type(interface_contact_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    integer(ip) :: e
    max_slip = 0.0_rp
    do e = 1, ctx%mesh%iface_map%n_owned
      max_slip = max(max_slip, norm2(self%jump(2:3, e) - self%jump_geo(2:3, e)))
    end do
    max_slip = ctx%sim%comm%max(max_slip)
  end function max_slip
  !> Every interface element must have a split node: one whose four nodes
  !> all lie on the fault's edge (a fault patch less than two elements
  !> across) has a jump of zero by construction, so its tractions are
  !> undetermined and every solver fails on it. Refused with the fault, the
  !> element count and the first one's centre (the same on every rank).
  !> Collective.
  subroutine check_split(mesh, status)
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    integer(ip) :: e, n_bad
    integer(gp) :: first_bad
    real(rp) :: info(7)
    n_bad = 0
    first_bad = huge(1_gp)
    info = 0.0_rp
    do e = 1, mesh%iface_map%n_owned
      if (any(mesh%iface_nodes(:, 1, e) /= mesh%iface_nodes(:, 2, e))) cycle
      n_bad = n_bad + 1
      if (mesh%iface_orig(e) < first_bad) call note_first(mesh, e, [0.0_rp, 0.0_rp, 0.0_rp], first_bad, info)
    end do
    n_bad = mesh%comm%sum(n_bad)
    if (n_bad == 0) return
    call agree_first(mesh, first_bad, info)
    call status%set("fault '"//trim(mesh%fault_names(nint(info(7))))//"': "//itoa(n_bad)// &
      " interface element(s) with no split node (all four nodes on the fault's edge), the first centred at ("// &
      trim(rtoa(info(1)))//', '//trim(rtoa(info(2)))//', '//trim(rtoa(info(3)))// &
      '): such an element can neither open nor slip and its tractions are undetermined; make the fault at '// &
      'least two elements across (&fault lower, upper) or refine the mesh')
  end subroutine check_split
  !> Without the stabilization H_t a traction is determined only by the
  !> jump it acts on. Where the displacement conditions fix that jump on
  !> both sides (every column of the element's row of C1 is a fixed dof: a
  !> one-cell-thick slab with uz = 0 on both faces and its out-of-plane
  !> traction) the traction has no equation and the system is singular.
  !> Refused with the fault, the count, the first such element's centre and
  !> the direction (the same on every rank). Collective.
  subroutine check_free_jump(self, mesh, status)
    type(interface_contact_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(error_status_t), intent(inout) :: status
    real(rp) :: be(3, nju), info(7)
    integer(ip) :: e, c, n_bad, dofs(nju)
    integer(gp) :: first_bad
    logical :: free_row(3)
    n_bad = 0
    first_bad = huge(1_gp)
    info = 0.0_rp
    do e = 1, mesh%iface_map%n_owned
      call self%jump_operator(self%mc, mesh, e, be, dofs)
      call drop_fixed(self, be, dofs)
      free_row = [(all(be(c, :) == 0.0_rp), c = 1, 3)]
      if (.not. any(free_row)) cycle
      n_bad = n_bad + count(free_row)
      if (mesh%iface_orig(e) < first_bad) &
        call note_first(mesh, e, self%rot(findloc(free_row, .true., dim=1), :, e), first_bad, info)
    end do
    n_bad = mesh%comm%sum(n_bad)
    if (n_bad == 0) return
    call agree_first(mesh, first_bad, info)
    call status%set("fault '"//trim(mesh%fault_names(nint(info(7))))//"': "//itoa(n_bad)// &
      ' traction component(s) act on a jump that the displacement conditions fix on both sides, the first '// &
      'at ('//trim(rtoa(info(1)))//', '//trim(rtoa(info(2)))//', '//trim(rtoa(info(3)))//') along ('// &
      trim(rtoa(info(4)))//', '//trim(rtoa(info(5)))//', '//trim(rtoa(info(6)))//"): with &contact "// &
      "stabilization = 'none' nothing determines them and the system is singular; use stabilization = "// &
      "'algebraic' (the default) or free that displacement")
  end subroutine check_free_jump

  !> Element e is the first offender so far (by its original id): keep its
  !> id and, in info, its centre (1:3), a direction (4:6) and its fault
  !> (7), for agree_first. Local.
  subroutine note_first(mesh, e, direction, first_bad, info)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: e
    real(rp), intent(in) :: direction(3)
    integer(gp), intent(inout) :: first_bad
    real(rp), intent(inout) :: info(7)
    first_bad = mesh%iface_orig(e)
    info(1:3) = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
    info(4:6) = direction
    info(7) = real(mesh%iface_fault(e), rp)
  end subroutine note_first

  !> The info of note_first of the first offender over all ranks (the
  !> smallest original id), on every rank. Collective.
  subroutine agree_first(mesh, first_bad, info)
    type(dist_mesh_t), intent(in) :: mesh
    integer(gp), intent(in) :: first_bad
    real(rp), intent(inout) :: info(7)
    if (-mesh%comm%max(-first_bad) /= first_bad) info = 0.0_rp
    call mesh%comm%sum_all(info)
  end subroutine agree_first

  !> The interface contact component of the composition ctx, null if it has none.
  function interface_contact_of(ctx) result(p)
    type(coupling_t), intent(in) :: ctx
    type(interface_contact_t), pointer :: p
    class(physics_component_t), pointer :: c
    p => null()
    c => ctx%find('contact')
    if (.not. associated(c)) return
    select type (c)
    type is (interface_contact_t)
      p => c
    end select
  end function interface_contact_of
end module interface_contact
