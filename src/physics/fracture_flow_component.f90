!> The fracture-flow component (physics_component.f90): the fluid in the
!> fractures, one pressure p per interface element (P0), with the cubic-law
!> transmissibilities of fracture_flow.f90 between neighbouring elements,
!> the fluid's storage, the wells (fracture_wells.f90) and the prescribed
!> pressures (&fracture_pressure). It couples to the interface contact
!> (interface_contact.f90) and the mechanics:
!>   - the faces carry t - p n: p is the pressure on the faces
!>     (ctx%face_pressure) that the momentum rows and the contact's residual
!>     read, and the Jacobian's momentum rows get Q1 = -(normal column of
!>     C1) in p's columns (assembled once, here);
!>   - its mass rows (assemble below) see the opening of the elements (the
!>     contact's jump operator and normal jumps) in their u columns, and
!>     the apertures follow the contact's statuses (open or closed).
module fracture_flow_component
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use dist_mesh, only: dist_mesh_t
  use dist_vector, only: pnorm2
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use param_group, only: param_group_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t, scalar_name_len
  use flow_config, only: flow_config_t, well_config_t, read_wells, load_well_histories, pressure_bc_t, &
                         read_pressure_bcs
  use fracture_flow, only: fracture_flow_t
  use fracture_wells, only: well_links_t
  use simulation, only: foreign_len
  use physics_component, only: physics_component_t, coupling_t, field_len
  use mechanics_component, only: mechanics_component_t, mechanics_of
  use interface_contact, only: interface_contact_t, interface_contact_of, state_open, nju
  implicit none
  private

  public :: fracture_flow_component_t, fracture_flow_of

  type, extends(physics_component_t) :: fracture_flow_component_t
    type(flow_config_t) :: fcfg                     !< &fracture_flow
    type(well_config_t), allocatable :: wells(:)    !< &well groups
    type(pressure_bc_t), allocatable :: pbcs(:)     !< &fracture_pressure groups
    type(dof_map_t) :: pd                           !< 1 pressure per interface element
    type(fracture_flow_t) :: ff                     !< cubic-law transmissibilities
    real(rp), allocatable :: p(:), p_step(:)        !< (pressure map's local) fluid pressure now and at the step's start [Pa]
    !> (pressure map's local) the hydrostatic pressure (&geostatic; else 0) and the faces' pressure p_hyd + p [Pa]
    real(rp), allocatable :: p_hyd(:), p_face(:)
    real(rp), allocatable :: gn_step(:)             !< (n) normal jump at the step's start [m]
    type(well_links_t) :: wl                        !< the wells' connections and rates
    integer, allocatable :: pfix(:)                 !< (n) the &fracture_pressure of an element, 0: none
    real(rp), allocatable :: p_fixed(:)             !< (n) its prescribed pressure in the step [Pa]
    real(rp) :: dt = 1.0_rp                         !< time step [s]
    real(rp) :: cf = 0.0_rp                         !< fluid compressibility [1/Pa]
    ! per mass row at the last assembly (field_residuals): the sum of its
    ! terms' absolute values [m^3] (0 on rows that hold a pressure), and
    ! the sum of the absolute values of their operands (round-off)
    real(rp), allocatable :: mass_mag(:), mass_noise(:)
    type(mechanics_component_t), pointer :: mc => null()
    type(interface_contact_t), pointer :: ic => null()
  contains
    procedure :: fields
    procedure :: field_size
    procedure :: read_deck
    procedure :: groups
    procedure :: parameter_groups
    procedure :: foreign_inputs
    procedure :: setup
    procedure :: set_patterns
    procedure :: describe_unknowns
    procedure :: start_step
    procedure :: assemble
    procedure :: take_solution
    procedure :: residual_names
    procedure :: field_residuals
    procedure :: save_state
    procedure :: load_state
    procedure :: write_output
    procedure :: sample
    procedure :: progress
    procedure :: held
    procedure :: free
  end type fracture_flow_component_t

contains

  subroutine fields(self, names)
    class(fracture_flow_component_t), intent(in) :: self
    character(len=field_len), allocatable, intent(out) :: names(:)
    names = [character(len=field_len) :: 'p']
  end subroutine fields

  integer(ip) function field_size(self, k)
    class(fracture_flow_component_t), intent(in) :: self
    integer, intent(in) :: k
    field_size = self%pd%n_owned()
  end function field_size

  !> &fracture_flow, &well and &fracture_pressure (with their histories):
  !> the run steps in time; the fluid pressure is an unknown, so a fault's
  !> prescribed pressure is refused. An incompressible fluid in a fault that
  !> starts closed with no prescribed pressure is refused too: nothing
  !> stores the fluid there, and the pressure system is singular. The
  !> contact's space must be 'stabilized' (the mass rows rest on H_t).
  subroutine read_deck(self, ctx, d, mcfg, log, status)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: k
    logical :: with_matrix
    associate (sim => ctx%sim)
      sim%transient = .true.
      call self%fcfg%read(d, log, status)
      if (status%ok()) call read_wells(d, log, self%wells, status)
      if (status%ok()) call load_well_histories(sim%comm, self%wells, status)
      if (status%ok()) call read_pressure_bcs(sim%comm, d, log, [(sim%faults(k)%name, k = 1, size(sim%faults))], &
                                              self%pbcs, status)
      if (.not. status%ok()) return
      do k = 1, size(sim%faults)
        if (sim%faults(k)%pressure /= 0.0_rp .or. len_trim(sim%faults(k)%pressure_history) > 0) then
          call d%fail(status, 'fault', k, 'pressure', "the fluid pressure is an unknown with physics = "// &
            "'fracture_flow' (set its start with &fracture_flow initial_pressure)")
          return
        end if
      end do
      do k = 1, size(sim%faults)
        if (self%fcfg%compressibility > 0.0_rp .or. sim%faults(k)%initial_state == 'open') cycle
        if (any(self%pbcs%fault == sim%faults(k)%name)) cycle
        call d%fail(status, 'fracture_flow', 1, 'compressibility', "is 0 while fault '"//trim(sim%faults(k)%name)// &
          "' starts closed (initial_state = '"//trim(sim%faults(k)%initial_state)//"') with no &fracture_pressure:"// &
          " an incompressible fluid in a closed fracture leaves its pressure undetermined (a singular system);"// &
          " give compressibility > 0 (water: 4.5e-10 1/Pa) or start the fault open")
        return
      end do
      call contact_of(self, ctx)
      if (self%ic%ccfg%space /= 'stabilized') then
        call d%fail(status, 'contact', 1, 'space', "'"//trim(self%ic%ccfg%space)//"' is for physics = 'contact': "// &
          "physics = 'fracture_flow' has the space 'stabilized' only (its mass rows and preconditioner rest on H_t)")
        return
      end if
      if (sim%solver%method /= 'mumps' .and. self%ic%ccfg%block /= 'reordered') call status%set("deck '"// &
        trim(d%path)//"', group &contact, variable block: physics = 'fracture_flow' has the 'reordered' block "// &
        "preconditioner (with the pressure's Schur complement as its second level), or method = 'mumps'")
      if (.not. status%ok()) return
      ! with the matrix's fluid (poromechanics_faults) the pressures are
      ! changes from the hydrostatic one, as biot's; alone, not yet
      with_matrix = associated(ctx%find('matrix_flow'))
      if (with_matrix .and. self%fcfg%block_choice_given) then
        call status%set("deck '"//trim(d%path)//"', group &fracture_flow, variables pressure_block and "// &
          "pressure_precon: physics = 'poromechanics_faults' puts the fracture pressure in one group with the "// &
          "matrix pressure (its S_P, &solver schur and schur_precon); remove them")
        return
      end if
      if (sim%geo%on .and. .not. with_matrix) call status%set("deck '"//trim(d%path)// &
        "': &geostatic is not available for physics = 'fracture_flow' yet (elasticity, contact, biot and "// &
        "poromechanics_faults have it)")
    end associate
  end subroutine read_deck

  !> The mechanics and interface contact components it couples to.
  subroutine contact_of(self, ctx)
    type(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    self%ic => interface_contact_of(ctx)
    self%mc => mechanics_of(ctx)
  end subroutine contact_of

  subroutine groups(self, list)
    class(fracture_flow_component_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'fracture_flow', 'well', 'fracture_pressure']
  end subroutine groups

  !> &fracture_flow, every &well and &fracture_pressure.
  subroutine parameter_groups(self, ctx, list)
    class(fracture_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(param_group_t), allocatable, intent(out) :: list(:)
    integer :: k
    allocate(list(1 + size(self%wells) + size(self%pbcs)))
    call self%fcfg%describe(list(1))
    do k = 1, size(self%wells)
      call self%wells(k)%describe(list(1 + k))
    end do
    do k = 1, size(self%pbcs)
      call self%pbcs(k)%describe(list(1 + size(self%wells) + k))
    end do
  end subroutine parameter_groups

  !> The pressure is an unknown: no &pressure_change.
  subroutine foreign_inputs(self, list)
    class(fracture_flow_component_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'pressure_change']
  end subroutine foreign_inputs

  !> The wells' connections and the pressure map: a well's connections
  !> couple their elements, so the map has the others as ghosts on a rank
  !> that owns one. Collective.
  subroutine setup(self, ctx, log, status)
    class(fracture_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    call contact_of(self, ctx)
    ! after an inexact solve, the residual alone does not bound the error of
    ! the pressure and of the opening it drives (coupled_simulation's
    ! update_check)
    self%update_test = [character(len=field_len) :: 'u', 'p']
    call self%wl%locate(ctx%mesh, self%wells, status)
    if (.not. status%ok()) return
    call self%pd%init('pressure', ctx%mesh%iface_map, 1_ip, self%wl%extra_ghosts(ctx%mesh))
    call self%wl%set_local(self%pd%map)
  end subroutine setup

  !> The patterns of the mass rows and of Q1, Q1 = -(normal column of C1)
  !> (assembled once), the transmissibility kernel, the prescribed
  !> pressures and the initial pressure; p becomes the faces' pressure.
  !> Collective.
  subroutine set_patterns(self, ctx, status)
    class(fracture_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:), connp(:,:), conn8(:,:), self_conn(:,:)
    integer(ip) :: n, e, k, ed, o, j, rows(nju), p0, p1
    real(rp) :: be(3, nju)
    integer :: bu, bp
    associate (mesh => ctx%mesh, ic => self%ic, umap => self%mc%mech%u%map, pmap => self%pd%map)
      n = mesh%n_ifaces
      bu = ctx%block('u')
      bp = ctx%block('p')
      call ic%element_entities(self%mc, mesh, conn8, self_conn)
      call element_pattern(mesh%node_map%n_owned, conn8(1:8, :), self_conn, 3_ip, 1_ip, row_ptr, col)
      call ctx%sys%set_pattern(bu, bp, umap, pmap, row_ptr, col)
      ! a mass row sees the nodes of its element and of its edge neighbours
      allocate(connp(40, n))
      connp = 0
      do e = 1, n
        connp(1:8, e) = conn8(1:8, e)
        do k = 1, 4
          ed = ic%edges%of_elem(k, e)
          if (ed == 0) cycle
          o = ic%edges%pair(1, ed) + ic%edges%pair(2, ed) - e
          connp(8*k+1:8*k+8, e) = conn8(1:8, o)
        end do
      end do
      call element_pattern(mesh%iface_map%n_owned, self_conn, connp, 1_ip, 3_ip, row_ptr, col)
      call ctx%sys%set_pattern(bp, bu, pmap, umap, row_ptr, col)
      call self%ff%pattern(mesh, ic%edges, row_ptr, col, self%wl%pairs())
      call ctx%sys%set_pattern(bp, bp, pmap, pmap, row_ptr, col)
      associate (q1 => ctx%sys%a(bu, bp))
        call q1%zero()
        do e = 1, mesh%iface_map%n_owned
          call ic%jump_operator(self%mc, mesh, e, be, rows)
          do j = 1, 24
            if (self%mc%mech%fixed(rows(j))) rows(j) = 0
          end do
          call q1%add_block(rows, [e], -transpose(be(1:1, :)))
        end do
        call q1%finalize_assembly()
      end associate
      call self%ff%init(mesh, ic%edges, self%fcfg%viscosity, self%fcfg%residual_aperture)
      self%cf = self%fcfg%compressibility
      allocate(self%p(self%pd%n_local()), self%p_step(self%pd%n_local()), self%gn_step(n))
      self%p = self%fcfg%initial_pressure
      self%p_step = self%p
      self%gn_step = 0.0_rp
      ! the faces' pressure: with &geostatic the unknown is the change from
      ! the hydrostatic pressure (as the matrix's), the faces feel both
      allocate(self%p_hyd(self%pd%n_local()), self%p_face(self%pd%n_local()))
      self%p_hyd = 0.0_rp
      if (self%mc%mech%geo%on) then
        do e = 1, mesh%n_ifaces
          self%p_hyd(e) = self%mc%mech%geo%pore_pressure(sum(mesh%coords(3, mesh%iface_nodes(:, 1, e))) / 4.0_rp)
        end do
      end if
      self%p_face = self%p + self%p_hyd
      ctx%face_pressure => self%p_face
      call prescribed_pressures(self, mesh)
      call ctx%range('p', p0, p1)
      ctx%x(p0:p1) = self%fcfg%initial_pressure
    end associate
  end subroutine set_patterns

  !> Prescribed pressures: the last &fracture_pressure whose box holds the
  !> element's centre wins.
  subroutine prescribed_pressures(self, mesh)
    type(fracture_flow_component_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp) :: c(3)
    integer(ip) :: e, n
    integer :: b
    n = mesh%n_ifaces
    allocate(self%pfix(n), self%p_fixed(n))
    self%pfix = 0
    self%p_fixed = 0.0_rp
    do e = 1, n
      c = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
      do b = 1, size(self%pbcs)
        if (self%pbcs(b)%fault /= mesh%fault_names(mesh%iface_fault(e))) cycle
        if (all(c >= self%pbcs(b)%lower .and. c <= self%pbcs(b)%upper)) self%pfix(e) = b
      end do
    end do
  end subroutine prescribed_pressures

  !> One line per well: where it meets the fractures (the element centre of
  !> each connection, and for a segment well Peaceman's equivalent radius).
  subroutine describe_unknowns(self, ctx, log)
    class(fracture_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(logger_t), intent(inout) :: log
    character(len=:), allocatable :: line
    integer :: k, c
    associate (wl => self%wl)
      do k = 1, size(self%wells)
        line = "well '"//trim(self%wells(k)%name)//"': "
        if (wl%along(k)) line = line//'along its segment, the rate split by pressure among '// &
                                itoa(wl%n_conn(k))//' fault(s):'
        do c = wl%first(k), wl%first(k + 1) - 1
          line = line//" '"//trim(ctx%mesh%fault_names(wl%fault(c)))//"' element at ("// &
                 rtoa(wl%centre(1, c))//', '//rtoa(wl%centre(2, c))//', '//rtoa(wl%centre(3, c))//')'
          if (wl%along(k)) line = line//' r_e '//rtoa(wl%r_e(c))//' m'
          if (c < wl%first(k + 1) - 1) line = line//';'
        end do
        call log%info(line)
      end do
    end associate
  end subroutine describe_unknowns

  !> Start a time step of the fluid once the start iterate is taken: the
  !> step's pressure and normal jumps, dt [s] and the wells' rates at the
  !> step's end time (implicit Euler). The equilibrium step 0 (dt = 0):
  !> nothing flows.
  subroutine start_step(self, ctx)
    class(fracture_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: e
    self%dt = ctx%dt
    self%p_step = self%p
    self%gn_step = self%ic%jump(1, :)
    do e = 1, size(self%pfix, kind=ip)
      if (self%pfix(e) > 0) self%p_fixed(e) = self%pbcs(self%pfix(e))%value_at(ctx%time)
    end do
    call self%wl%begin_step(self%wells, self%ff%aperture, self%ff%mu, ctx%time, ctx%dt)
  end subroutine start_step

  !> The mass rows of the fluid and their residual, per owned element e, in
  !> volumes over the step (the balance times dt, so that a step of size 0 is
  !> no division):
  !>   A (g_N - g_N^step) + A a c_f (p - p^step) + dt sum over edges T (p_e - p_o)
  !>     + (H_N (p - p^step))_e - dt q_e = 0,
  !> T from the cubic law at the current apertures (with its aperture
  !> derivatives in the u columns), c_f the fluid compressibility and H_N
  !> the normal-normal part of the traction stabilization's edge blocks: the
  !> pressure enters the momentum exactly as t_N does (Q1 = -C1 normal), so
  !> these rows give the stabilized saddle point of the contact block with
  !> -(dt T + storage + H_N) in place of -H_t. H_N acts on the pressure's
  !> increment: it vanishes at steady state and sums to zero over the
  !> fracture (mass is conserved exactly). A step of size 0 (&time undrained,
  !> the mechanical equilibrium at the start) keeps the pressure: p = p^step.
  !> Local.
  subroutine assemble(self, ctx)
    class(fracture_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp) :: be(3, nju), bo(3, nju), r, dp, m_self, m_off, dt, stor
    real(rp), allocatable :: wq(:)
    integer(ip) :: e, k, ed, o, dofs(nju), dofo(nju), p0, p1
    integer :: s
    dt = self%dt
    if (.not. allocated(self%mass_mag)) allocate(self%mass_mag(ctx%mesh%iface_map%n_owned), &
                                                 self%mass_noise(ctx%mesh%iface_map%n_owned))
    self%mass_mag = 0.0_rp
    self%mass_noise = 0.0_rp
    associate (jpu => ctx%sys%a(ctx%block('p'), ctx%block('u')), jpp => ctx%sys%a(ctx%block('p'), ctx%block('p')), &
               ic => self%ic, ff => self%ff, rhs => ctx%rhs)
      call jpu%zero()
      call jpp%zero()
      call ctx%range('p', p0, p1)
      do e = 1, ctx%mesh%iface_map%n_owned
        if (self%held(e)) then
          ! held (step 0) or prescribed: p = p^step or p = the prescribed value
          call jpp%add_value(e, e, 1.0_rp)
          rhs(p0 + e - 1) = -(self%p(e) - merge(self%p_fixed(e), self%p_step(e), dt > 0.0_rp))
          cycle
        end if
        call free_jump_operator(e, be, dofs)
        stor = ic%area(e) * ff%aperture(e) * self%cf
        r = ic%area(e) * (ic%jump(1, e) - self%gn_step(e)) + stor * (self%p(e) - self%p_step(e))
        self%mass_mag(e) = abs(ic%area(e) * (ic%jump(1, e) - self%gn_step(e))) + &
                           abs(stor * (self%p(e) - self%p_step(e)))
        ! the opening's round-off is that of the displacements it is the
        ! difference of (jump_mag), not of the opening: a closed, sealed
        ! fracture balances 1e-27 m^3 a step against 3e-21 m^3 of noise
        self%mass_noise(e) = ic%area(e) * (ic%jump_mag(e) + abs(self%gn_step(e))) + &
                             stor * (abs(self%p(e)) + abs(self%p_step(e)))
        call jpu%add_block([e], dofs, be(1:1, :) * (1.0_rp + self%cf * (self%p(e) - self%p_step(e)) &
                                                    * ff%da_dg(e)))
        call jpp%add_value(e, e, stor)
        do k = 1, 4
          ed = ic%edges%of_elem(k, e)
          if (ed == 0) cycle
          s = merge(1, 2, ic%edges%pair(1, ed) == e)
          o = ic%edges%pair(3 - s, ed)
          dp = self%p(e) - self%p(o)
          r = r + dt * ff%trans(ed) * dp
          self%mass_mag(e) = self%mass_mag(e) + abs(dt * ff%trans(ed) * dp)
          self%mass_noise(e) = self%mass_noise(e) + dt * ff%trans(ed) * (abs(self%p(e)) + abs(self%p(o)))
          call jpp%add_value(e, e, dt * ff%trans(ed))
          call jpp%add_value(e, o, -dt * ff%trans(ed))
          if (dp /= 0.0_rp .and. ff%da_dg(e) > 0.0_rp) &
            call jpu%add_block([e], dofs, dt * dp * ff%dtrans(s, ed) * ff%da_dg(e) * be(1:1, :) &
                                          / ic%area(e))
          if (dp /= 0.0_rp .and. ff%da_dg(o) > 0.0_rp) then
            call free_jump_operator(o, bo, dofo)
            call jpu%add_block([e], dofo, dt * dp * ff%dtrans(3 - s, ed) * ff%da_dg(o) * bo(1:1, :) &
                                          / ic%area(o))
          end if
          if (.not. ic%stabilized) cycle
          m_self = ic%eb(1, 1, merge(1, 3, s == 1), ed)
          m_off = ic%eb(1, 1, 2, ed)
          call jpp%add_value(e, e, m_self)
          call jpp%add_value(e, o, m_off)
          r = r + m_self * (self%p(e) - self%p_step(e)) + m_off * (self%p(o) - self%p_step(o))
          self%mass_mag(e) = self%mass_mag(e) + abs(m_self * (self%p(e) - self%p_step(e))) + &
                             abs(m_off * (self%p(o) - self%p_step(o)))
          self%mass_noise(e) = self%mass_noise(e) + abs(m_self) * (abs(self%p(e)) + abs(self%p_step(e))) + &
                               abs(m_off) * (abs(self%p(o)) + abs(self%p_step(o)))
        end do
        if (allocated(ctx%fracture_exchange)) then
          ! the matrix's fluid into the element (matrix_flow_component.f90)
          r = r - ctx%fracture_exchange(e)
          self%mass_mag(e) = self%mass_mag(e) + abs(ctx%fracture_exchange(e))
          self%mass_noise(e) = self%mass_noise(e) + ctx%fracture_exchange_mag(e)
        end if
        rhs(p0 + e - 1) = -r
      end do
      ! the wells' rates (-dt q in r); their volumes count in the magnitudes
      wq = rhs(p0:p1)
      call self%wl%add_mass_terms(self%p, dt, dt > 0.0_rp .and. self%pfix == 0, jpp, rhs(p0:p1))
      self%mass_mag = self%mass_mag + abs(rhs(p0:p1) - wq)
      self%mass_noise = self%mass_noise + abs(rhs(p0:p1) - wq)
      call jpu%finalize_assembly()
      call jpp%finalize_assembly()
    end associate
  contains
    !> The jump operator of element ee with the prescribed dofs' columns zero.
    subroutine free_jump_operator(ee, b, d)
      integer(ip), intent(in) :: ee
      real(rp), intent(out) :: b(3, nju)
      integer(ip), intent(out) :: d(nju)
      integer(ip) :: j
      call self%ic%jump_operator(self%mc, ctx%mesh, ee, b, d)
      do j = 1, 24
        if (self%mc%mech%fixed(d(j))) b(:, j) = 0.0_rp
      end do
    end subroutine free_jump_operator
  end subroutine assemble

  !> The pressures from x (with ghosts) and the apertures of the elements
  !> at their normal jumps and statuses (the contact's, taken before).
  !> Collective.
  subroutine take_solution(self, ctx)
    class(fracture_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: p0, p1
    call ctx%range('p', p0, p1)
    self%p = 0.0_rp
    self%p(1:p1-p0+1) = ctx%x(p0:p1)
    call self%pd%map%import(self%p)
    self%p_face = self%p + self%p_hyd
    ! the opening from the in-situ state (&geostatic: step 0's jumps, the
    ! in-situ state's imbalance taken up with the faults bonded, are the
    ! origin, as in the outputs; else 0)
    call self%ff%set_apertures(self%ic%edges, self%ic%jump(1, :) - self%ic%jump_geo(1, :), &
                               self%ic%state == state_open)
  end subroutine take_solution

  subroutine residual_names(self, names, units)
    class(fracture_flow_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    character(len=3), allocatable, intent(out) :: units(:)
    names = [character(len=8) :: 'volume']
    units = [character(len=3) :: 'm3']
  end subroutine residual_names

  !> volume [m^3]: the fluid volume of the step, the mass rows that
  !> balance a volume; against the sum of their terms' absolute values
  !> (opening, storage, flow to the neighbours, stabilization, wells). Rows
  !> that hold a value (a prescribed or step-0 pressure) are linear and
  !> left out. Collective.
  subroutine field_residuals(self, ctx, res, ref, noise)
    class(fracture_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(out) :: res(:), ref(:), noise(:)
    integer(ip) :: p0, p1, nown
    nown = ctx%mesh%iface_map%n_owned
    call ctx%range('p', p0, p1)
    res(1) = 0.0_rp
    if (self%dt > 0.0_rp) res(1) = pnorm2(ctx%mesh%comm, pack(ctx%rhs(p0:p1), self%pfix(1:nown) == 0))
    ref(1) = pnorm2(ctx%mesh%comm, self%mass_mag)
    noise(1) = pnorm2(ctx%mesh%comm, self%mass_noise)
  end subroutine field_residuals

  subroutine save_state(self, ctx, st)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(state_record_t), intent(inout) :: st
    call ctx%put_field(st, 'p')
  end subroutine save_state

  subroutine load_state(self, ctx, st, status)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    call ctx%get_field(st, 'p', status)
  end subroutine load_state

  !> aperture, area and flux on the fractures grid (the contact writes the
  !> pressure on the faces, which is p). Collective.
  subroutine write_output(self, ctx, out, status)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    if (.not. status%ok() .or. size(ctx%sim%faults) == 0) return
    associate (n => ctx%mesh%iface_map%n_owned, grid => self%ic%fout%grid)
      call out%writer%cell_field('aperture', self%ff%aperture(1:n), status, grid)
      if (status%ok()) call out%writer%cell_field('area', self%ic%area(1:n), status, grid)
      if (status%ok()) call out%writer%cell_field('flux', &
        norm2(self%ff%element_flux(ctx%mesh, self%ic%edges, self%p), dim=1), status, grid)
    end associate
  end subroutine write_output

  !> Per well, the step's rate and its bottom-hole pressure (of its element
  !> for a well at a point, of the wellbore for one along a segment), per
  !> connection of a segment well its rate and its element's pressure, and
  !> per fault the largest pressure and the fluid volume it holds (sum of
  !> A g_N over its open elements). Collective.
  subroutine sample(self, ctx, pf, status)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    character(len=scalar_name_len), allocatable :: names(:)
    real(rp), allocatable :: values(:), pmax(:), vol(:), pw(:), qc(:), pc(:)
    integer :: k, nf, f, c
    integer(ip) :: e
    associate (wl => self%wl, mesh => ctx%mesh, comm => ctx%sim%comm)
      nf = size(mesh%fault_names)
      allocate(pw(size(self%wells)), qc(size(wl%gid)), pc(size(wl%gid)))
      pw = wl%bottom_hole(self%p)
      qc = wl%rates(self%p)
      pc = 0.0_rp
      where (wl%mine) pc = self%p(max(wl%elem, 1))
      call comm%sum_all(qc)
      call comm%sum_all(pc)
      allocate(names(0), values(0))
      do k = 1, size(self%wells)
        names = [character(len=scalar_name_len) :: names, trim(self%wells(k)%name)//':rate [m3/s]', &
                 trim(self%wells(k)%name)//':pressure [Pa]']
        values = [values, wl%q(k), pw(k)]
        if (.not. wl%along(k)) cycle
        do c = wl%first(k), wl%first(k + 1) - 1
          associate (tag => trim(self%wells(k)%name)//'@'//trim(mesh%fault_names(wl%fault(c))))
            names = [character(len=scalar_name_len) :: names, tag//':rate [m3/s]', tag//':pressure [Pa]']
          end associate
          values = [values, qc(c), pc(c)]
        end do
      end do
      allocate(pmax(nf), vol(nf))
      pmax = -huge(1.0_rp)
      vol = 0.0_rp
      do e = 1, mesh%iface_map%n_owned
        f = mesh%iface_fault(e)
        pmax(f) = max(pmax(f), self%p(e))
        vol(f) = vol(f) + self%ic%area(e) * max(self%ic%jump(1, e), 0.0_rp)
      end do
      call comm%sum_all(vol)
      do f = 1, nf
        names = [character(len=scalar_name_len) :: names, trim(mesh%fault_names(f))//':max_pressure [Pa]', &
                 trim(mesh%fault_names(f))//':fluid_volume [m3]']
        values = [values, comm%max(pmax(f)), vol(f)]
      end do
    end associate
    pf%names = [pf%names, names]
    pf%values = [pf%values, values]
  end subroutine sample

  !> The largest pressure of the fractures.
  subroutine progress(self, ctx, line)
    class(fracture_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(inout) :: line
    character(len=32) :: piece
    if (size(ctx%sim%faults) == 0) return
    write(piece, '(a,es10.3,a)') '  max p ', ctx%sim%comm%max(maxval(self%p(1:ctx%mesh%iface_map%n_owned))), ' Pa'
    line = trim(line)//piece
  end subroutine progress

  !> Whether the mass row of local element e holds its pressure (the step
  !> of size 0, or a &fracture_pressure) rather than balancing its fluid.
  logical function held(self, e)
    class(fracture_flow_component_t), intent(in) :: self
    integer(ip), intent(in) :: e
    held = self%dt == 0.0_rp .or. self%pfix(e) > 0
  end function held

  subroutine free(self)
    class(fracture_flow_component_t), intent(inout) :: self
    call self%pd%free()
    call self%ff%free()
    if (allocated(self%p)) deallocate(self%p, self%p_step, self%gn_step)
    if (allocated(self%p_hyd)) deallocate(self%p_hyd, self%p_face)
    call self%wl%free()
    if (allocated(self%pfix)) deallocate(self%pfix, self%p_fixed)
    if (allocated(self%mass_mag)) deallocate(self%mass_mag, self%mass_noise)
    nullify(self%mc, self%ic)
  end subroutine free
  !> The fracture-flow component of the composition ctx, null if it has none.
  function fracture_flow_of(ctx) result(p)
    type(coupling_t), intent(in) :: ctx
    type(fracture_flow_component_t), pointer :: p
    class(physics_component_t), pointer :: c
    p => null()
    c => ctx%find('fracture_flow')
    if (.not. associated(c)) return
    select type (c)
    type is (fracture_flow_component_t)
      p => c
    end select
  end function fracture_flow_of
end module fracture_flow_component
