!> The mechanics component (physics_component.f90): Q1 displacements u
!> (elasticity.f90, split at the faults the mesh carries; with the face
!> bubbles of the fault cells when the contact's space is 'bubble'), the
!> loads, the in-situ state (&geostatic) and the &pressure_change loads.
!> Its rows are the momentum balance
!>   K u + (the forces of the other unknowns, ctx%momentum_coupling) = f,
!> solved for increments: the prescribed displacements are imposed at the
!> start of every step, so the Jacobian's columns of prescribed dofs are
!> zero (the components that couple to u leave them out too).
module mechanics_component
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: rtoa
  use state_record, only: state_record_t
  use dist_mesh, only: dist_mesh_t
  use dist_vector, only: pnorm2
  use face_bubbles, only: face_bubbles_t
  use elasticity, only: elasticity_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  use physics_component, only: physics_component_t, coupling_t, field_len
  implicit none
  private

  public :: mechanics_component_t, mechanics_of

  type, extends(physics_component_t) :: mechanics_component_t
    type(elasticity_t) :: mech
    !> the fault cells' face bubbles enrich u (set before setup: the
    !> contact's space 'bubble')
    logical :: bubble = .false.
    type(face_bubbles_t) :: bub
    real(rp), allocatable :: u(:)                  !< local displacement (owned + ghosts) [m]
    real(rp), allocatable :: f_u(:)                !< load of the momentum rows (prescribed dofs lifted)
    real(rp), allocatable :: u_geo(:)              !< local displacements of step 0 [m]: outputs are measured from them
    ! the magnitudes the momentum rows balance at the last assembly
    ! (field_residuals): the largest force vector [N], and the round-off of
    ! evaluating them, |f| + |K| |u| + the coupling's operands
    real(rp) :: force_ref = 0.0_rp
    real(rp) :: force_noise = 0.0_rp
  contains
    procedure :: fields
    procedure :: field_size
    procedure :: components_of
    procedure :: setup
    procedure :: set_patterns
    procedure :: report_setup
    procedure :: begin_step
    procedure :: assemble
    procedure :: take_solution
    procedure :: residual_names
    procedure :: field_residuals
    procedure :: save_state
    procedure :: load_state
    procedure :: accept_step
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: nodal_u
    procedure :: free
  end type mechanics_component_t

contains

  subroutine fields(self, names)
    class(mechanics_component_t), intent(in) :: self
    character(len=field_len), allocatable, intent(out) :: names(:)
    names = [character(len=field_len) :: 'u']
  end subroutine fields

  integer(ip) function field_size(self, k)
    class(mechanics_component_t), intent(in) :: self
    integer, intent(in) :: k
    field_size = self%mech%u%n_owned()
  end function field_size

  integer function components_of(self, k) result(n)
    class(mechanics_component_t), intent(in) :: self
    integer, intent(in) :: k
    n = 3
  end function components_of

  !> Split nodes (and bubbles), conditions, the in-situ state and the
  !> pressure changes. Collective.
  subroutine setup(self, ctx, log, status)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    associate (mesh => ctx%mesh, sim => ctx%sim)
      if (self%bubble) then
        call self%bub%build(mesh)
        call self%mech%init(mesh, sim%mats, sim%bcs, status, self%bub)
      else
        call self%mech%init(mesh, sim%mats, sim%bcs, status)
      end if
      if (.not. status%ok()) return
      call self%mech%k%free()                       ! the block system holds K
      call self%mech%init_in_situ(mesh, sim%geo, sim%mats, status)
      if (status%ok()) call self%mech%init_pressure_changes(mesh, sim%pcs, sim%mats, status)
    end associate
    allocate(self%u(self%mech%u%n_local()), self%f_u(self%mech%u%n_owned()), self%u_geo(self%mech%u%n_local()))
    self%u = 0.0_rp
    self%u_geo = 0.0_rp
  end subroutine setup

  !> The pattern of K. Collective.
  subroutine set_patterns(self, ctx, status)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:)
    integer :: bu
    bu = ctx%block('u')
    call self%mech%stiffness_pattern(ctx%mesh, row_ptr, col)
    call ctx%sys%set_pattern(bu, bu, self%mech%u%map, self%mech%u%map, row_ptr, col)
  end subroutine set_patterns

  !> The in-situ state's imbalance on this mesh (&geostatic). Collective.
  subroutine report_setup(self, ctx, log, status)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    if (ctx%sim%geo%on) call log%info('geostatic: largest nodal force of the in-situ state out of equilibrium '// &
      '(the faults carry it): '//trim(rtoa(self%mech%in_situ_imbalance(ctx%mesh)))// &
      ' of the largest nodal weight; step 0 balances it with the faults bonded')
  end subroutine report_setup

  !> Impose the prescribed displacements at ctx%lf and assemble K and the
  !> loads at ctx%lf, all with the histories at ctx%time. (contact_t took
  !> the displacements' history factors of the step before in a run that
  !> steps in load: a &boundary history lagged one step behind its load.)
  !> Collective.
  subroutine begin_step(self, ctx)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: i, u0, u1
    call self%mech%set_time(ctx%time)
    do i = 1, self%mech%u%n_local()
      if (self%mech%fixed(i)) self%u(i) = ctx%lf * self%mech%prescribed_value(i)
    end do
    call ctx%range('u', u0, u1)
    ctx%x(u0:u1) = self%u(1:u1-u0+1)
    call self%mech%assemble_into(ctx%mesh, ctx%lf, ctx%sys%a(ctx%block('u'), ctx%block('u')), self%f_u)
  end subroutine begin_step

  !> Momentum rows: rhs = -(K u + ctx%momentum_coupling - f), prescribed
  !> rows zero; the magnitudes for field_residuals. Collective.
  subroutine assemble(self, ctx)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    real(rp), allocatable :: w(:)
    integer(ip) :: u0, u1, i
    integer :: bu
    bu = ctx%block('u')
    call ctx%range('u', u0, u1)
    w = ctx%momentum_coupling
    call ctx%sys%apply_block(bu, bu, ctx%x(u0:u1), ctx%rhs(u0:u1))
    do i = 1, u1 - u0 + 1
      if (.not. self%mech%fixed(i)) cycle
      ctx%rhs(u0 + i - 1) = 0.0_rp
      w(i) = 0.0_rp
    end do
    call force_scales(self, ctx, ctx%rhs(u0:u1), w)
    ctx%rhs(u0:u1) = self%f_u - ctx%rhs(u0:u1) - w
    do i = 1, u1 - u0 + 1
      if (self%mech%fixed(i)) ctx%rhs(u0 + i - 1) = 0.0_rp
    end do
  end subroutine assemble

  !> The momentum rows' magnitudes for field_residuals, from the internal
  !> forces ku = K u and the coupling forces w (free rows): force_ref, the
  !> largest of the loads, ku and w, and force_noise, |f| + |K| |u| + the
  !> coupling's operands. Collective.
  subroutine force_scales(self, ctx, ku, w)
    type(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    real(rp), intent(in) :: ku(:), w(:)
    real(rp), allocatable :: ka(:), rmax(:)
    integer(ip) :: u0, u1
    integer :: bu
    bu = ctx%block('u')
    call ctx%range('u', u0, u1)
    associate (comm => ctx%mesh%comm)
      self%force_ref = max(pnorm2(comm, pack(self%f_u, .not. self%mech%fixed(1:u1-u0+1))), &
                           pnorm2(comm, ku), pnorm2(comm, w))
      allocate(ka(u1 - u0 + 1), rmax(u1 - u0 + 1))
      call ctx%sys%a(bu, bu)%abs_apply(ctx%x(u0:u1), ka, rmax)
      ka = abs(self%f_u) + ka + ctx%momentum_coupling_mag
      where (self%mech%fixed(1:u1-u0+1)) ka = 0.0_rp
      self%force_noise = pnorm2(comm, ka)
    end associate
  end subroutine force_scales

  !> The local displacements from x. Collective.
  subroutine take_solution(self, ctx)
    class(mechanics_component_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    integer(ip) :: u0, u1
    call ctx%range('u', u0, u1)
    self%u(1:u1-u0+1) = ctx%x(u0:u1)
    call self%mech%u%map%import(self%u)
  end subroutine take_solution

  subroutine residual_names(self, names, units)
    class(mechanics_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    character(len=3), allocatable, intent(out) :: units(:)
    names = [character(len=8) :: 'force']
    units = [character(len=3) :: 'N']
  end subroutine residual_names

  !> force [N]: the momentum rows; against the largest of the loads, the
  !> internal forces K u and the coupling forces. Collective.
  subroutine field_residuals(self, ctx, res, ref, noise)
    class(mechanics_component_t), intent(in) :: self
    type(coupling_t), intent(in) :: ctx
    real(rp), intent(out) :: res(:), ref(:), noise(:)
    integer(ip) :: u0, u1
    call ctx%range('u', u0, u1)
    res(1) = pnorm2(ctx%mesh%comm, ctx%rhs(u0:u1))
    ref(1) = self%force_ref
    noise(1) = self%force_noise
  end subroutine field_residuals

  !> x_u and, with &geostatic, the displacements of step 0.
  subroutine save_state(self, ctx, st)
    class(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(state_record_t), intent(inout) :: st
    call ctx%put_field(st, 'u')
    if (ctx%sim%geo%on) call st%put('displacement_in_situ', self%u_geo(1:self%mech%u%n_owned()))
  end subroutine save_state

  subroutine load_state(self, ctx, st, status)
    class(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(inout) :: ctx
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    call ctx%get_field(st, 'u', status)
    if (.not. ctx%sim%geo%on) return
    call st%get('displacement_in_situ', self%u_geo(1:self%mech%u%n_owned()), status)
    if (status%ok()) call self%mech%u%map%import(self%u_geo)
  end subroutine load_state

  !> Step 0 (&geostatic) accepted: its displacements become the outputs' origin.
  subroutine accept_step(self, ctx)
    class(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    if (ctx%initial) self%u_geo = self%u
  end subroutine accept_step

  !> displacement (from step 0's), stress, region, rank and the pressure
  !> change of &pressure_change. Collective.
  subroutine write_output(self, ctx, out, status)
    class(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: stress(:,:)
    associate (mesh => ctx%mesh)
      allocate(stress(6, mesh%cell_map%n_owned))
      call self%mech%cell_stress(mesh, self%u, stress)
      call out%write_displacement(mesh, self%u - self%u_geo, status)
      if (status%ok()) call out%writer%cell_field('stress', stress, status)
      call out%write_mesh_ids(mesh, status)
      if (status%ok() .and. size(self%mech%pcs) > 0) &
        call out%writer%cell_field('pressure_change', self%mech%pressure_change_field(mesh, ctx%lf), status)
    end associate
  end subroutine write_output

  subroutine probe_names(self, names)
    class(mechanics_component_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    names = [character(len=8) :: 'ux', 'uy', 'uz', 'sxx', 'syy', 'szz', 'sxy', 'syz', 'sxz']
  end subroutine probe_names

  !> Displacement (from step 0's) and stress for the probes.
  subroutine sample(self, ctx, pf, status)
    class(mechanics_component_t), intent(inout) :: self
    type(coupling_t), intent(in) :: ctx
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    integer(ip) :: nd
    pf%u = self%nodal_u(ctx%mesh)
    if (ctx%sim%geo%on) then
      do nd = 1, ctx%mesh%n_nodes
        pf%u(3*nd-2:3*nd) = pf%u(3*nd-2:3*nd) - self%u_geo(self%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))
      end do
    end if
    allocate(pf%stress(6, ctx%mesh%cell_map%n_owned))
    call self%mech%cell_stress(ctx%mesh, self%u, pf%stress)
  end subroutine sample

  !> The local displacement at the nodes, 3 per local node in node order
  !> (the bubbles left out) [m].
  function nodal_u(self, mesh) result(un)
    class(mechanics_component_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), allocatable :: un(:)
    integer(ip) :: nd
    allocate(un(3 * mesh%n_nodes))
    do nd = 1, mesh%n_nodes
      un(3*nd-2:3*nd) = self%u(self%mech%u%dof(nd, [1_ip, 2_ip, 3_ip]))
    end do
  end function nodal_u

  subroutine free(self)
    class(mechanics_component_t), intent(inout) :: self
    call self%mech%free()
    call self%bub%free()
    if (allocated(self%u)) deallocate(self%u, self%f_u, self%u_geo)
  end subroutine free
  !> The mechanics component of the composition ctx, null if it has none.
  function mechanics_of(ctx) result(p)
    type(coupling_t), intent(in) :: ctx
    type(mechanics_component_t), pointer :: p
    class(physics_component_t), pointer :: c
    p => null()
    c => ctx%find('mechanics')
    if (.not. associated(c)) return
    select type (c)
    type is (mechanics_component_t)
      p => c
    end select
  end function mechanics_of
end module mechanics_component
