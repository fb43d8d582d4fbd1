!> The matrix flow component (physics_component.f90): the fluid of the
!> porous matrix in three-field Biot form, the Darcy flux q (RT0, one per
!> face of the mesh split at the faults, each side its own faces; field
!> 'q') and the pressure p (P0, one per cell; field 'pm'), implicit Euler,
!> with the kernels of 'biot' (poro_media.f90). Its rows, per step of size
!> dt from the step's start (u^s, p^s):
!>   Darcy (face f)   A q - B p + (p_bar on pressure faces) + (fault term) = 0
!>   mass (cell c)    Q^T (u - u^s) + dt B^T q + (P + J)(p - p^s) - dt s |c| = 0
!> (s the &source rate, or I (p_w - p) for a pressure-controlled source of
!> index I: dt I |c| joins P) and its coupling in the momentum rows, -Q p
!> (Biot's effective stress: the mechanics' K u is the effective stress's,
!> the total is sigma' - b p I); A, B, Q, P = |c|/M and the pressure-jump stabilization
!> J are those of poromechanics.f90.
!> On a fault face f of cell c (sign s_f of the face's global normal to
!> c's outward one), with p_f the fracture's pressure of the interface
!> element on f (fracture_flow_component.f90), per the &fault's exchange:
!>   'open'     the natural boundary term  s_f p_f  (the face's pressure
!>              is p_f): block (q, p_f) = s_f;
!>   'barrier'  s_f p_f + q_f / (lambda |f|): the outflow s_f q_f =
!>              lambda |f| (p_face - p_f), lambda the exchange_transmissibility;
!>   'sealing'  q_f = 0 (a prescribed flux: no exchange).
!> The fracture's mass rows take the fluid the faces put in over the step,
!> dt sum_f s_f q_f over its two faces (ctx%fracture_exchange, block
!> (p_f, q) = -dt s_f, where the fracture's row balances its fluid), so the
!> matrix, the fractures and the wells conserve the fluid together.
module matrix_flow_component
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa
  use state_record, only: state_record_t
  use dist_mesh, only: dist_mesh_t
  use dist_vector, only: pnorm2
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use param_group, only: param_group_t
  use biot_config, only: biot_config_t
  use fault_config, only: fault_config_t
  use source_config, only: source_config_t, read_sources
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t, scalar_name_len
  use poro_media, only: poro_media_t, cell_coupling, cell_darcy, flow_patterns, face_area
  use simulation, only: foreign_len
  use physics_component, only: physics_component_t, coupling_t, field_len
  use mechanics_component, only: mechanics_component_t, mechanics_of
  use interface_contact, only: interface_contact_t, interface_contact_of
  use fracture_flow_component, only: fracture_flow_component_t, fracture_flow_of
  implicit none
  private

  public :: matrix_flow_component_t, matrix_flow_of

  !> a fault face's exchange
  integer, parameter :: ex_none = 0, ex_open = 1, ex_barrier = 2, ex_sealing = 3

  type, extends(physics_component_t) :: matrix_flow_component_t
    type(biot_config_t) :: bcfg                     !< &biot
    type(source_config_t), allocatable :: srcs(:)   !< &source groups
    type(poro_media_t) :: med                       !< materials, flux conditions, stabilization
    type(dof_map_t) :: qd, pd                       !< flux (faces) and pressure (cells) dofs
    real(rp), allocatable :: qe(:,:)                !< (24, owned cells) Q_e
    real(rp), allocatable :: ae(:,:,:), be(:,:)     !< (6, 6 | 6, owned cells) A_e, B_e (global orientation)
    integer(ip), allocatable :: dofs(:,:)           !< (24, owned cells) the cells' u dofs
    ! fault faces (local faces): the interface element, the sign of the
    ! face's global normal to its cell's outward one, the exchange and
    ! (barrier) 1 / (lambda |f|)
    integer(ip), allocatable :: face_elem(:), face_sign(:)
    integer, allocatable :: face_ex(:)
    real(rp), allocatable :: face_res(:)            !< [Pa s/m^3]
    integer(ip), allocatable :: elem_faces(:,:)     !< (2, local elements) its faces (0: sealing or none)
    real(rp), allocatable :: q(:), p(:)             !< local (ghosts imported) flux [m^3/s] and pressure [Pa]
    real(rp), allocatable :: u_step(:), p_step(:)   !< local u and p at the step's start
    ! per owned row at the last assembly: the magnitudes of the terms and
    ! of their operands (field_residuals, the mass balance)
    real(rp), allocatable :: mass_mag(:), mass_noise(:)
    real(rp) :: darcy_ref = 0.0_rp, darcy_noise = 0.0_rp
    type(mechanics_component_t), pointer :: mc => null()
    type(fracture_flow_component_t), pointer :: fc => null()
  contains
    procedure :: fields
    procedure :: field_size
    procedure :: read_deck
    procedure :: groups
    procedure :: parameter_groups
    procedure :: setup
    procedure :: set_patterns
    procedure :: begin_step
    procedure :: start_step
    procedure :: accept_step
    procedure :: couple
    procedure :: assemble
    procedure :: take_solution
    procedure :: residual_names
    procedure :: field_residuals
    procedure :: scaling
    procedure :: save_state
    procedure :: load_state
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: progress
    procedure :: free
  end type matrix_flow_component_t

contains

  subroutine fields(self, names)
    class(matrix_flow_component_t), intent(in) :: self
    character(len=field_len), allocatable, intent(out) :: names(:)
    names = [character(len=field_len) :: 'q', 'pm']
  end subroutine fields

  integer(ip) function field_size(self, k)
    class(matrix_flow_component_t), intent(in) :: self
    integer, intent(in) :: k
    if (k == 1) then
      field_size = self%qd%n_owned()
    else
      field_size = self%pd%n_owned()
    end if
  end function field_size

  !> &biot and &source; the &solver choices the block preconditioner
  !> (poro_faults_precon.f90) takes.
  subroutine read_deck(self, ctx, d, mcfg, log, status)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    ctx%sim%transient = .true.
    call self%bcfg%read(d, log, status)
    if (status%ok()) call read_sources(d, log, self%srcs, status)
    if (.not. status%ok()) return
    associate (sv => ctx%sim%solver)
      if (sv%method /= 'mumps' .and. sv%decoupling == 'explicit' .and. status%ok()) call status%set("deck '"//trim(d%path)// &
        "', group &solver, variable decoupling: physics = 'poromechanics_faults' has implicit factors only (its "// &
        "displacement block S* follows the contact's statuses: an explicit K^-1 Q would be rebuilt every iteration)")
      if (sv%method /= 'mumps' .and. sv%schur_precon == 'afsai' .and. status%ok()) call status%set("deck '"// &
        trim(d%path)//"', group &solver, variable schur_precon: physics = 'poromechanics_faults' takes 'boomeramg' "// &
        "(its pressure Schur complement is not symmetric where the fractures' pressure is: aFSAI needs an SPD matrix)")
      if (sv%method /= 'mumps' .and. sv%schur == 'explicit' .and. status%ok()) call status%set("deck '"//trim(d%path)// &
        "', group &solver, variable schur: physics = 'poromechanics_faults' takes 'fixed_stress' or 'algebraic'")
    end associate
  end subroutine read_deck

  !> Its groups and the &fault variables of the exchange: refused where
  !> the composition has no matrix flow.
  subroutine groups(self, list)
    class(matrix_flow_component_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'biot', 'source', 'fault%exchange', 'fault%exchange_transmissibility']
  end subroutine groups

  !> &biot and every &source.
  subroutine parameter_groups(self, ctx, list)
    class(matrix_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    type(param_group_t), allocatable, intent(out) :: list(:)
    integer :: k
    allocate(list(1 + size(self%srcs)))
    call self%bcfg%describe(list(1))
    do k = 1, size(self%srcs)
      call self%srcs(k)%describe(list(1 + k))
    end do
  end subroutine parameter_groups

  !> The medium, the dof maps and the fault faces. Collective.
  subroutine setup(self, ctx, log, status)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    self%mc => mechanics_of(ctx)
    self%fc => fracture_flow_of(ctx)
    call self%med%init_media(ctx%mesh, ctx%sim%mats, ctx%sim%bcs, self%srcs, self%bcfg%beta(), &
                             self%bcfg%stab_mode == 'adaptive', self%mc%mech%box_tol, 'poromechanics_faults', status)
    if (.not. status%ok()) return
    call self%qd%init('flux', ctx%mesh%face_map, 1_ip)
    call self%pd%init('pressure', ctx%mesh%cell_map, 1_ip)
    call fault_faces(self, ctx, status)
    allocate(self%q(self%qd%n_local()), self%p(self%pd%n_local()), self%p_step(self%pd%n_local()), &
             self%u_step(self%mc%mech%u%n_local()))
    self%q = 0.0_rp
    self%p = 0.0_rp
    self%p_step = 0.0_rp
    self%u_step = 0.0_rp
  end subroutine setup

  !> Each local interface element's faces (one per side, the face of its
  !> cell with the element's nodes) and their exchange; an 'open' or
  !> 'barrier' face lets fluid through (it is not impermeable).
  subroutine fault_faces(self, ctx, status)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip) :: e, k, c, j, f
    associate (mesh => ctx%mesh)
      allocate(self%face_elem(mesh%n_faces), self%face_sign(mesh%n_faces), self%face_ex(mesh%n_faces), &
               self%face_res(mesh%n_faces), self%elem_faces(2, mesh%n_ifaces))
      self%face_elem = 0
      self%face_sign = 0
      self%face_ex = ex_none
      self%face_res = 0.0_rp
      self%elem_faces = 0
      do e = 1, mesh%n_ifaces
        do k = 1, 2
          c = mesh%iface_cells(k, e)
          f = 0
          do j = 1, 6
            if (same_nodes(mesh%face_nodes(:, mesh%cell_faces(j, c)), mesh%iface_nodes(:, k, e))) then
              f = mesh%cell_faces(j, c)
              self%face_sign(f) = mesh%cell_face_sign(j, c)
            end if
          end do
          if (f == 0) then
            call status%set('matrix flow: an interface element has no face of its cell (mesh split)')
            return
          end if
          call face_exchange(self, ctx, f, ctx%sim%faults(mesh%iface_fault(e)))
          self%face_elem(f) = e
          if (self%face_ex(f) /= ex_sealing) self%elem_faces(k, e) = f
        end do
      end do
    end associate
  end subroutine fault_faces

  !> The exchange of fault face f from its &fault.
  subroutine face_exchange(self, ctx, f, fault)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    integer(ip), intent(in) :: f
    type(fault_config_t), intent(in) :: fault
    select case (fault%exchange)
    case ('sealing')
      self%face_ex(f) = ex_sealing
      self%med%q_fixed(f) = .true.
      self%med%q_value(f) = 0.0_rp
    case ('barrier')
      self%face_ex(f) = ex_barrier
      self%med%q_fixed(f) = .false.
      self%face_res(f) = 1.0_rp / (fault%exchange_transmissibility * face_area(ctx%mesh, f))
    case default
      self%face_ex(f) = ex_open
      self%med%q_fixed(f) = .false.
    end select
  end subroutine face_exchange

  !> Whether the two quads have the same nodes.
  logical function same_nodes(a, b)
    integer(ip), intent(in) :: a(4), b(4)
    integer :: i
    same_nodes = .true.
    do i = 1, 4
      same_nodes = same_nodes .and. any(b == a(i))
    end do
  end function same_nodes

  !> The patterns of its rows ((q, q), (q, pm), (pm, u), (pm, q), (pm, pm)),
  !> of its coupling (u, pm) in the momentum rows and of the exchange
  !> ((q, p), (p, q)); the cell kernels; the constant blocks. Collective.
  subroutine set_patterns(self, ctx, status)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:), elems(:,:)
    integer(ip) :: e
    associate (mesh => ctx%mesh)
      call flow_patterns(mesh, ctx%sys, [ctx%block('u'), ctx%block('q'), ctx%block('pm')], self%mc%mech%u%map, &
                         self%qd%map, self%pd%map)
      allocate(elems(1, mesh%n_ifaces))
      elems(1, :) = [(e, e = 1, mesh%n_ifaces)]
      call element_pattern(mesh%face_map%n_owned, self%elem_faces, elems, 1_ip, 1_ip, row_ptr, col)
      call ctx%sys%set_pattern(ctx%block('q'), ctx%block('p'), self%qd%map, self%fc%pd%map, row_ptr, col)
      call element_pattern(mesh%iface_map%n_owned, elems, self%elem_faces, 1_ip, 1_ip, row_ptr, col)
      call ctx%sys%set_pattern(ctx%block('p'), ctx%block('q'), self%fc%pd%map, self%qd%map, row_ptr, col)
    end associate
    call cell_kernels(self, ctx, status)
    if (status%ok()) call constant_blocks(self, ctx)
  end subroutine set_patterns

  !> Q_e, A_e, B_e and the u dofs of every owned cell.
  subroutine cell_kernels(self, ctx, status)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip) :: c, a, nc, r
    real(rp) :: xe(3, 8)
    associate (mesh => ctx%mesh)
      nc = mesh%cell_map%n_owned
      allocate(self%qe(24, nc), self%ae(6, 6, nc), self%be(6, nc), self%dofs(24, nc))
      do c = 1, nc
        xe = mesh%coords(:, mesh%cell_nodes(:, c))
        r = mesh%cell_region(c)
        call cell_coupling(xe, self%med%biot(r), self%qe(:, c))
        call cell_darcy(xe, self%med%kinv(:, :, r), mesh%cell_face_sign(:, c), self%ae(:, :, c), self%be(:, c), &
                        status)
        if (.not. status%ok()) return
        do a = 1, 8
          self%dofs(3*a-2:3*a, c) = self%mc%mech%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
        end do
      end do
    end associate
  end subroutine cell_kernels

  !> The blocks that do not change: -Q (momentum rows, prescribed rows
  !> left out), Q^T (prescribed columns left out), A with the barriers'
  !> resistances, -B and the fault faces' (q, p) = s_f; the rows of
  !> prescribed fluxes are a scaled identity (the mean diagonal of the free
  !> rows of A). Collective.
  subroutine constant_blocks(self, ctx)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    integer(ip) :: c, i, j, f
    integer :: bu, bq, bm
    bu = ctx%block('u')
    bq = ctx%block('q')
    bm = ctx%block('pm')
    associate (mesh => ctx%mesh, fixed => self%mc%mech%fixed, qf => self%med%q_fixed, sys => ctx%sys)
      call sys%a(bu, bm)%zero()
      call sys%a(bm, bu)%zero()
      call sys%a(bq, bq)%zero()
      call sys%a(bq, bm)%zero()
      call sys%a(bq, ctx%block('p'))%zero()
      do c = 1, mesh%cell_map%n_owned
        do j = 1, 24
          if (fixed(self%dofs(j, c))) cycle
          call sys%a(bu, bm)%add_value(self%dofs(j, c), c, -self%qe(j, c))
          call sys%a(bm, bu)%add_value(c, self%dofs(j, c), self%qe(j, c))
        end do
        do j = 1, 6
          f = mesh%cell_faces(j, c)
          if (qf(f)) cycle
          do i = 1, 6
            call sys%a(bq, bq)%add_value(f, mesh%cell_faces(i, c), self%ae(j, i, c))
          end do
          call sys%a(bq, bm)%add_value(f, c, -self%be(j, c))
        end do
      end do
      do f = 1, mesh%face_map%n_owned
        if (self%face_ex(f) == ex_open .or. self%face_ex(f) == ex_barrier) then
          call sys%a(bq, ctx%block('p'))%add_value(f, self%face_elem(f), real(self%face_sign(f), rp))
          if (self%face_ex(f) == ex_barrier) call sys%a(bq, bq)%add_value(f, f, self%face_res(f))
        end if
      end do
      call sys%a(bu, bm)%finalize_assembly()
      call sys%a(bm, bu)%finalize_assembly()
      call sys%a(bq, bq)%finalize_assembly()
      call sys%a(bq, bm)%finalize_assembly()
      call sys%a(bq, ctx%block('p'))%finalize_assembly()
    end associate
    call fixed_flux_rows(self, ctx)
  end subroutine constant_blocks

  !> Rows of prescribed fluxes: a scaled identity, the mean diagonal of the
  !> free rows of A. Collective.
  subroutine fixed_flux_rows(self, ctx)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    real(rp) :: dsum, dcount
    integer(ip) :: f
    integer :: bq
    bq = ctx%block('q')
    associate (aq => ctx%sys%a(bq, bq))
      dsum = 0.0_rp
      dcount = 0.0_rp
      do f = 1, self%qd%n_owned()
        if (self%med%q_fixed(f)) cycle
        dsum = dsum + aq%val(aq%find(f, f))
        dcount = dcount + 1.0_rp
      end do
      dsum = ctx%mesh%comm%sum(dsum)
      dcount = ctx%mesh%comm%sum(dcount)
      self%med%a_scale = 1.0_rp
      if (dcount > 0.0_rp) self%med%a_scale = dsum / dcount
      do f = 1, self%qd%n_owned()
        if (self%med%q_fixed(f)) aq%val(aq%find(f, f)) = self%med%a_scale
      end do
    end associate
  end subroutine fixed_flux_rows

  !> The prescribed fluxes at the step's end go into x (their rows then
  !> hold them). Collective.
  subroutine begin_step(self, ctx)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: q0, q1, f
    call ctx%range('q', q0, q1)
    do f = 1, q1 - q0 + 1
      if (self%med%q_fixed(f)) ctx%x(q0 + f - 1) = self%med%prescribed_flux(f, ctx%time)
    end do
  end subroutine begin_step

  !> What the step measures from: p at its start (u^s is the accepted
  !> state's, kept by accept_step and load_state: the mechanics has
  !> imposed the prescribed displacements of the step's end by now).
  subroutine start_step(self, ctx)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    self%p_step = self%p
  end subroutine start_step

  !> The accepted displacements: the next step's u^s.
  subroutine accept_step(self, ctx)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    self%u_step = self%mc%u
  end subroutine accept_step

  !> Its terms in other rows: -Q p in the momentum rows, and the fluid its
  !> fault faces put into the fractures over the step, dt sum s_f q_f.
  !> Collective.
  subroutine couple(self, ctx)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp), allocatable :: w(:), ca(:), rmax(:)
    integer(ip) :: p0, p1, e, k, f, n
    integer :: bu, bm
    bu = ctx%block('u')
    bm = ctx%block('pm')
    call ctx%range('pm', p0, p1)
    n = size(ctx%momentum_coupling, kind=ip)
    allocate(w(n), ca(n), rmax(n))
    call ctx%sys%apply_block(bu, bm, ctx%x(p0:p1), w)
    call ctx%sys%a(bu, bm)%abs_apply(ctx%x(p0:p1), ca, rmax)
    ctx%momentum_coupling = ctx%momentum_coupling + w
    ctx%momentum_coupling_mag = ctx%momentum_coupling_mag + ca
    n = ctx%mesh%iface_map%n_owned
    if (.not. allocated(ctx%fracture_exchange)) allocate(ctx%fracture_exchange(n), ctx%fracture_exchange_mag(n))
    ctx%fracture_exchange = 0.0_rp
    ctx%fracture_exchange_mag = 0.0_rp
    do e = 1, n
      do k = 1, 2
        f = self%elem_faces(k, e)
        if (f == 0) cycle
        ctx%fracture_exchange(e) = ctx%fracture_exchange(e) + ctx%dt * self%face_sign(f) * self%q(f)
        ctx%fracture_exchange_mag(e) = ctx%fracture_exchange_mag(e) + ctx%dt * abs(self%q(f))
      end do
    end do
  end subroutine couple

  !> The blocks that follow dt ((pm, q) = dt B^T, (pm, pm) = P + J, and the
  !> fractures' (p, q) = -dt s_f where their rows balance fluid), then the
  !> residuals of its rows into rhs. Collective.
  subroutine assemble(self, ctx)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    logical :: changed
    changed = self%med%jump_factor(ctx%dt)
    call step_blocks(self, ctx)
    call darcy_residual(self, ctx)
    call mass_residual(self, ctx)
  end subroutine assemble

  !> (pm, q) = dt B^T, (pm, pm) = P + J, (p, q) = -dt s_f. Collective.
  subroutine step_blocks(self, ctx)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    integer(ip) :: c, j, e, k, f
    integer :: bq, bm, bp
    bq = ctx%block('q')
    bm = ctx%block('pm')
    bp = ctx%block('p')
    associate (mesh => ctx%mesh, sys => ctx%sys)
      call sys%a(bm, bq)%zero()
      call sys%a(bm, bm)%zero()
      call sys%a(bp, bq)%zero()
      do c = 1, mesh%cell_map%n_owned
        do j = 1, 6
          call sys%a(bm, bq)%add_value(c, mesh%cell_faces(j, c), ctx%dt * self%be(j, c))
        end do
        call self%med%storage_row(mesh, c, ctx%dt, sys%a(bm, bm))
      end do
      do e = 1, mesh%iface_map%n_owned
        if (self%fc%held(e)) cycle
        do k = 1, 2
          f = self%elem_faces(k, e)
          if (f > 0) call sys%a(bp, bq)%add_value(e, f, -ctx%dt * self%face_sign(f))
        end do
      end do
      call sys%a(bm, bq)%finalize_assembly()
      call sys%a(bm, bm)%finalize_assembly()
      call sys%a(bp, bq)%finalize_assembly()
    end associate
  end subroutine step_blocks

  !> The Darcy rows' residual A q - B p + p_bar + (fault terms) (prescribed
  !> rows: a_scale (q - q_prescribed)) into rhs, and its magnitudes.
  !> Collective.
  subroutine darcy_residual(self, ctx)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    real(rp), allocatable :: t1(:), t2(:), t3(:), pb(:), m1(:), m2(:), m3(:), rmax(:)
    integer(ip) :: q0, q1, p0, p1, f0, f1, f, n
    integer :: bq
    bq = ctx%block('q')
    call ctx%range('q', q0, q1)
    call ctx%range('pm', p0, p1)
    call ctx%range('p', f0, f1)
    n = q1 - q0 + 1
    allocate(t1(n), t2(n), t3(n), pb(n), m1(n), m2(n), m3(n), rmax(n))
    call ctx%sys%apply_block(bq, bq, ctx%x(q0:q1), t1)
    call ctx%sys%apply_block(bq, ctx%block('pm'), ctx%x(p0:p1), t2)
    call ctx%sys%apply_block(bq, ctx%block('p'), ctx%x(f0:f1), t3)
    call ctx%sys%a(bq, bq)%abs_apply(ctx%x(q0:q1), m1, rmax)
    call ctx%sys%a(bq, ctx%block('pm'))%abs_apply(ctx%x(p0:p1), m2, rmax)
    call ctx%sys%a(bq, ctx%block('p'))%abs_apply(ctx%x(f0:f1), m3, rmax)
    pb = 0.0_rp
    do f = 1, n
      if (self%med%q_fixed(f)) then
        pb(f) = -self%med%a_scale * self%med%prescribed_flux(f, ctx%time)
      else if (self%med%p_face(f)) then
        pb(f) = self%med%p_bc(f) * self%med%bcs(self%med%face_bc(f))%factor(ctx%time)
      end if
    end do
    ctx%rhs(q0:q1) = -(t1 + t2 + t3 + pb)
    associate (comm => ctx%mesh%comm)
      self%darcy_ref = max(pnorm2(comm, t1), pnorm2(comm, t2), pnorm2(comm, t3), pnorm2(comm, pb))
      self%darcy_noise = pnorm2(comm, m1 + m2 + m3 + abs(pb))
    end associate
  end subroutine darcy_residual

  !> The mass rows' residual (in volumes over the step) into rhs, and
  !> their magnitudes; Q^T (u - u^s) with every column (the prescribed
  !> displacements' change counts). Collective.
  subroutine mass_residual(self, ctx)
    type(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    real(rp), allocatable :: t2(:), t3(:), dp(:), m2(:), m3(:), rmax(:)
    real(rp) :: t1, m1, src
    integer(ip) :: q0, q1, p0, p1, c, n
    integer :: bm
    bm = ctx%block('pm')
    call ctx%range('q', q0, q1)
    call ctx%range('pm', p0, p1)
    n = p1 - p0 + 1
    allocate(t2(n), t3(n), m2(n), m3(n), rmax(n))
    dp = ctx%x(p0:p1) - self%p_step(1:n)
    call ctx%sys%apply_block(bm, ctx%block('q'), ctx%x(q0:q1), t2)
    call ctx%sys%apply_block(bm, bm, dp, t3)
    call ctx%sys%a(bm, ctx%block('q'))%abs_apply(ctx%x(q0:q1), m2, rmax)
    call ctx%sys%a(bm, bm)%abs_apply(abs(ctx%x(p0:p1)) + abs(self%p_step(1:n)), m3, rmax)
    if (.not. allocated(self%mass_mag)) allocate(self%mass_mag(n), self%mass_noise(n))
    associate (u => self%mc%u, us => self%u_step, mesh => ctx%mesh)
      do c = 1, n
        t1 = dot_product(self%qe(:, c), u(self%dofs(:, c)) - us(self%dofs(:, c)))
        m1 = dot_product(abs(self%qe(:, c)), abs(u(self%dofs(:, c))) + abs(us(self%dofs(:, c))))
        ! the sources' fluid: the rate ones', and the pressure-controlled
        ! ones' dt |c| I (p_w - p) less its part in t3, dt I |c| (p - p^s)
        src = ctx%dt * self%med%vol(c) * (self%med%src_rate(c) + self%med%src_jp(c) - &
                                          self%med%src_index(c) * self%p_step(c))
        ctx%rhs(p0 + c - 1) = -(t1 + t2(c) + t3(c) - src)
        self%mass_mag(c) = abs(t1) + abs(t2(c)) + abs(t3(c)) + abs(src)
        self%mass_noise(c) = m1 + m2(c) + m3(c) + abs(src)
      end do
    end associate
  end subroutine mass_residual

  !> The fluxes and pressures from x (with ghosts). Collective.
  subroutine take_solution(self, ctx)
    class(matrix_flow_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: i0, i1
    call ctx%range('q', i0, i1)
    self%q = 0.0_rp
    self%q(1:i1-i0+1) = ctx%x(i0:i1)
    call self%qd%map%import(self%q)
    call ctx%range('pm', i0, i1)
    self%p = 0.0_rp
    self%p(1:i1-i0+1) = ctx%x(i0:i1)
    call self%pd%map%import(self%p)
  end subroutine take_solution

  subroutine residual_names(self, names, units)
    class(matrix_flow_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    character(len=3), allocatable, intent(out) :: units(:)
    names = [character(len=8) :: 'darcy', 'mass']
    units = [character(len=3) :: 'Pa', 'm3']
  end subroutine residual_names

  !> darcy [Pa]: the Darcy rows (pressure times the face's unit flux);
  !> mass [m^3]: the matrix's fluid volume of the step. Collective.
  subroutine field_residuals(self, ctx, res, ref, noise)
    class(matrix_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(out) :: res(:), ref(:), noise(:)
    integer(ip) :: i0, i1
    call ctx%range('q', i0, i1)
    res(1) = pnorm2(ctx%mesh%comm, ctx%rhs(i0:i1))
    ref(1) = self%darcy_ref
    noise(1) = self%darcy_noise
    call ctx%range('pm', i0, i1)
    res(2) = pnorm2(ctx%mesh%comm, ctx%rhs(i0:i1))
    ref(2) = pnorm2(ctx%mesh%comm, self%mass_mag)
    noise(2) = pnorm2(ctx%mesh%comm, self%mass_noise)
  end subroutine field_residuals

  !> The diagonal of A (q rows), and for the pressure that of the
  !> fixed-stress Schur approximation, |c| (1/M + b^2/K_dr) + J (the
  !> pressure block's own diagonal vanishes for incompressible
  !> constituents).
  subroutine scaling(self, ctx, d)
    class(matrix_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(inout) :: d(:)
    integer(ip) :: i0, i1, c, r
    call ctx%range('q', i0, i1)
    call ctx%sys%a(ctx%block('q'), ctx%block('q'))%diagonal(d(i0:i1))
    call ctx%range('pm', i0, i1)
    call ctx%sys%a(ctx%block('pm'), ctx%block('pm'))%diagonal(d(i0:i1))
    do c = 1, i1 - i0 + 1
      r = ctx%mesh%cell_region(c)
      d(i0 + c - 1) = d(i0 + c - 1) + self%med%vol(c) * self%med%biot(r)**2 / self%med%kdr(r)
      if (d(i0 + c - 1) == 0.0_rp) d(i0 + c - 1) = 1.0_rp
    end do
  end subroutine scaling

  subroutine save_state(self, ctx, st)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(state_record_t), intent(inout) :: st
    call ctx%put_field(st, 'q')
    call ctx%put_field(st, 'pm')
  end subroutine save_state

  subroutine load_state(self, ctx, st, status)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    integer(ip) :: u0, u1
    call ctx%get_field(st, 'q', status)
    if (status%ok()) call ctx%get_field(st, 'pm', status)
    ! the mechanics (before it in the list) has its x_u back: u^s
    call ctx%range('u', u0, u1)
    self%u_step = 0.0_rp
    self%u_step(1:u1-u0+1) = ctx%x(u0:u1)
    call self%mc%mech%u%map%import(self%u_step)
  end subroutine load_state

  !> pressure [Pa], Darcy velocity [m/s] and total stress [Pa] (sigma' -
  !> b p I; the mechanics' stress is the effective one) per cell; on the
  !> fractures grid the leak-off into each element [m^3/s]. Collective.
  subroutine write_output(self, ctx, out, status)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: vel(:,:), stress(:,:), l(:)
    type(interface_contact_t), pointer :: ic
    integer(ip) :: nc
    if (.not. status%ok()) return
    nc = ctx%mesh%cell_map%n_owned
    allocate(vel(3, nc))
    call self%med%cell_velocity(ctx%mesh, self%q, vel)
    call total_stress(self, ctx, stress)
    call out%writer%cell_field('pressure', self%p(1:nc), status)
    if (status%ok()) call out%writer%cell_field('darcy_velocity', vel, status)
    if (status%ok()) call out%writer%cell_field('total_stress', stress, status)
    if (size(ctx%sim%faults) == 0) return
    ic => interface_contact_of(ctx)
    call leakoff(self, ctx, l)
    if (status%ok()) call out%writer%cell_field('leakoff', l, status, ic%fout%grid)
  end subroutine write_output

  !> The total stress of the owned cells (xx yy zz xy yz xz, tension
  !> positive) [Pa].
  subroutine total_stress(self, ctx, stress)
    type(matrix_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), allocatable, intent(out) :: stress(:,:)
    integer(ip) :: c
    allocate(stress(6, ctx%mesh%cell_map%n_owned))
    call self%mc%mech%cell_stress(ctx%mesh, self%mc%u, stress)
    do c = 1, ctx%mesh%cell_map%n_owned
      stress(1:3, c) = stress(1:3, c) - self%med%biot(ctx%mesh%cell_region(c)) * self%p(c)
    end do
  end subroutine total_stress

  !> The matrix's flux into each owned interface element [m^3/s]: sum over
  !> its faces of s_f q_f.
  subroutine leakoff(self, ctx, l)
    type(matrix_flow_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), allocatable, intent(out) :: l(:)
    integer(ip) :: e, k, f
    allocate(l(ctx%mesh%iface_map%n_owned))
    l = 0.0_rp
    do e = 1, size(l, kind=ip)
      do k = 1, 2
        f = self%elem_faces(k, e)
        if (f > 0) l(e) = l(e) + self%face_sign(f) * self%q(f)
      end do
    end do
  end subroutine leakoff

  subroutine probe_names(self, names)
    class(matrix_flow_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    names = [character(len=8) :: 'p']
  end subroutine probe_names

  !> The cell pressure for the probes, per fault the leak-off from the
  !> matrix [m^3/s], and the rate of each pressure-controlled source.
  !> Collective.
  subroutine sample(self, ctx, pf, status)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: l(:), per_fault(:)
    integer(ip) :: e
    integer :: k
    pf%p = self%p(1:ctx%mesh%cell_map%n_owned)
    call leakoff(self, ctx, l)
    allocate(per_fault(size(ctx%mesh%fault_names)))
    per_fault = 0.0_rp
    do e = 1, size(l, kind=ip)
      per_fault(ctx%mesh%iface_fault(e)) = per_fault(ctx%mesh%iface_fault(e)) + l(e)
    end do
    call ctx%sim%comm%sum_all(per_fault)
    if (.not. allocated(pf%names)) allocate(pf%names(0))
    if (.not. allocated(pf%values)) allocate(pf%values(0))
    do k = 1, size(per_fault)
      pf%names = [pf%names, [character(len=scalar_name_len) :: trim(ctx%mesh%fault_names(k))//':leakoff [m3/s]']]
      pf%values = [pf%values, per_fault(k)]
    end do
    call self%med%source_rates(ctx%mesh, self%p, pf%names, pf%values)
  end subroutine sample

  !> The step's mass balance: the largest residual of the mass rows of the
  !> matrix and of the fractures (those that balance fluid), relative to
  !> the largest sum of the magnitudes of a row's terms. Collective.
  subroutine progress(self, ctx, line)
    class(matrix_flow_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    character(len=*), intent(inout) :: line
    character(len=32) :: piece
    real(rp) :: r, scale
    integer(ip) :: p0, p1, e
    call ctx%range('pm', p0, p1)
    r = 0.0_rp
    scale = 0.0_rp
    if (p1 >= p0) r = maxval(abs(ctx%rhs(p0:p1)))
    if (p1 >= p0) scale = maxval(self%mass_mag)
    call ctx%range('p', p0, p1)
    do e = 1, p1 - p0 + 1
      if (self%fc%held(e)) cycle
      r = max(r, abs(ctx%rhs(p0 + e - 1)))
      scale = max(scale, self%fc%mass_mag(e))
    end do
    r = ctx%sim%comm%max(r) / max(ctx%sim%comm%max(scale), tiny(1.0_rp))
    write(piece, '(a,es9.2)') '  mass balance ', r
    line = trim(line)//piece
  end subroutine progress

  subroutine free(self)
    class(matrix_flow_component_t), intent(inout) :: self
    call self%med%free_media()
    call self%qd%free()
    call self%pd%free()
    if (allocated(self%qe)) deallocate(self%qe, self%ae, self%be, self%dofs)
    if (allocated(self%face_elem)) deallocate(self%face_elem, self%face_sign, self%face_ex, self%face_res, &
                                              self%elem_faces)
    if (allocated(self%q)) deallocate(self%q, self%p, self%p_step, self%u_step)
    if (allocated(self%mass_mag)) deallocate(self%mass_mag, self%mass_noise)
    nullify(self%mc, self%fc)
  end subroutine free

  !> The matrix flow component of ctx's composition, null if none.
  function matrix_flow_of(ctx) result(p)
    type(coupling_t), intent(in) :: ctx
    type(matrix_flow_component_t), pointer :: p
    class(physics_component_t), pointer :: c
    p => null()
    c => ctx%find('matrix_flow')
    if (.not. associated(c)) return
    select type (c)
    type is (matrix_flow_component_t)
      p => c
    end select
  end function matrix_flow_of
end module matrix_flow_component
