!> physics = 'biot': three-field poromechanics (poromechanics.f90) in time
!> steps of implicit Euler, optionally from an undrained step at t = 0; one
!> linear solve of the block system per step: FGMRES on the diagonally
!> scaled system with the block preconditioner of biot_precon.f90, or MUMPS.
!>
!> Set-up cost is split as in the seed: the dt-independent part T_p1 (the
!> preconditioners of K and of the Darcy block, the explicit factors; once)
!> and the dt-dependent part T_p2 (the Schur approximation and its
!> preconditioner, and the scaling; redone when dt changes).
module biot_simulation
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use strings, only: itoa, rtoa
  use state_record, only: state_record_t
  use linear_system, only: linear_system_t
  use csr_matrix, only: csr_matrix_t
  use amg_params, only: amg_params_t
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use biot_config, only: biot_config_t
  use source_config, only: source_config_t, read_sources
  use dist_mesh, only: dist_mesh_t
  use mesh_pieces, only: mesh_pieces_t
  use field_output, only: field_output_t
  use probe_fields, only: probe_fields_t
  use poromechanics, only: poromechanics_t, iu, iq, ipr
  use biot_precon, only: biot_precon_t
  use mgr_precon, only: mgr_precon_t, mgr_biot
  use param_group, only: param_group_t
  use simulation, only: simulation_t, foreign_len, common_parameter_groups, step_stats_t
  implicit none
  private

  public :: biot_simulation_t

  type, extends(simulation_t) :: biot_simulation_t
    type(poromechanics_t) :: phys
    type(biot_config_t) :: bcfg                     !< &biot
    type(source_config_t), allocatable :: srcs(:)   !< &source groups
    type(biot_precon_t) :: bpc
    type(mgr_precon_t) :: mgr                      !< &solver precon = 'mgr': hypre's MGR (the peer)
    real(rp) :: mgr_dt = -1.0_rp                   !< dt of the MGR set-up
    real(rp) :: direct_dt = -1.0_rp                !< dt of the matrix a direct solver last saw (< 0: none)
    type(amg_params_t) :: amg_s                     !< BoomerAMG settings of the scalar blocks
    real(rp), allocatable :: dscale(:)              !< scaling of the block system
    real(rp) :: t = 0.0_rp, dt = 0.0_rp             !< the step's end time and size [s]
    real(rp) :: dt_used = -1.0_rp                   !< dt of the last dt-dependent set-up (< 0: none)
    real(rp) :: t_p1 = 0.0_rp, t_p2 = 0.0_rp        !< set-up seconds of this step, each part
    real(rp) :: mass_bal = 0.0_rp                   !< local mass balance of the last solve (see mass_balance)
    logical :: setup_done = .false.                 !< the dt-independent part is built
  contains
    procedure :: name
    procedure :: read_deck
    procedure :: foreign_inputs
    procedure :: parameter_groups
    procedure :: setup
    procedure :: begin_step
    procedure :: assemble
    procedure :: linear_system
    procedure :: update
    procedure :: accept_step
    procedure :: save_state
    procedure :: load_state
    procedure :: write_output
    procedure :: probe_names
    procedure :: sample
    procedure :: report_step
    procedure :: free
    procedure, private :: setup_precon
  end type biot_simulation_t

contains

  function name(self) result(s)
    class(biot_simulation_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'biot'
  end function name

  !> The shared groups (with pressure and flux conditions), &biot and
  !> &source; the linear solver must suit a non-symmetric block system.
  subroutine read_deck(self, d, mcfg, log, status)
    class(biot_simulation_t), intent(inout), target :: self
    type(deck_t), intent(in) :: d
    type(mesh_config_t), intent(in) :: mcfg
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    self%transient = .true.
    call self%read_common(d, log, status, 'block', flow_conditions=.true., with_faults=.false.)
    if (status%ok()) call self%bcfg%read(d, log, status)
    if (status%ok()) call read_sources(d, log, self%srcs, status)
    if (.not. status%ok()) return
    if (self%solver%method == 'cg') then
      call status%set("deck '"//trim(d%path)//"', group &solver, variable method: "// &
        "the Biot system is not symmetric positive definite: use 'fgmres' or 'mumps'")
    else if (self%solver%method == 'fgmres' .and. self%solver%precon /= 'block' .and. self%solver%precon /= 'mgr') then
      call status%set("deck '"//trim(d%path)//"', group &solver, variable precon: physics = 'biot' with fgmres "// &
        "needs precon = 'block' (or hypre's 'mgr')")
    end if
  end subroutine read_deck

  !> Unknowns, block patterns, materials and boundary data. Collective.
  subroutine setup(self, mesh, log, status)
    class(biot_simulation_t), intent(inout), target :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    type(mesh_pieces_t) :: pieces
    self%mesh => mesh
    call self%phys%init(mesh, self%mats, self%bcs, self%srcs, self%bcfg%beta(), self%bcfg%stab_mode == 'adaptive', &
                        status)
    call agree(self%comm, status)
    if (status%ok()) call self%phys%mech%init_in_situ(mesh, self%geo, self%mats, status)
    call agree(self%comm, status)
    if (.not. status%ok()) return
    if (self%geo%on) call report_in_situ(self, log)
    call pieces%build(mesh)
    call self%phys%mech%check_anchored(mesh, pieces, status)
    call pieces%free()
    if (.not. status%ok()) return
    associate (nu => self%phys%mech%u%map%n_global, nq => self%phys%qd%map%n_global, np => self%phys%pd%map%n_global)
      call log%info('unknowns: u '//itoa(int(nu))//', q '//itoa(int(nq))//', p '//itoa(int(np))//', total '// &
                    itoa(int(nu + nq + np)))
    end associate
    if (self%solver%method == 'mumps') then
      call log%info('linear solver: MUMPS direct solver on the assembled block system')
    else if (self%solver%precon == 'mgr') then
      call log%info("linear solver: fgmres + hypre's MGR on the whole system (GEOS's poromechanics strategy: "// &
                    'u by BoomerAMG, then q by Jacobi, p by BoomerAMG)')
    else
      call log%info('linear solver: fgmres + block preconditioner ('//trim(self%solver%decoupling)//' factors, '// &
                    trim(self%solver%block_mode)//', Schur '//trim(self%solver%schur)//')')
    end if
    self%amg_s = self%amg%scalar()
    self%amg_k = self%amg
    if (self%solver%method /= 'mumps' .and. self%solver%precon == 'block' .and. self%solver%k_precon == 'boomeramg') &
      call self%adapt_amg(mesh, log)
    allocate(self%dscale(size(self%phys%rhs)))
    self%dscale = 1.0_rp
  end subroutine setup

  !> A step to time t with gamma = dt (0: the undrained step).
  subroutine begin_step(self, t, dt, status)
    class(biot_simulation_t), intent(inout) :: self
    real(rp), intent(in) :: t, dt
    type(error_status_t), intent(inout) :: status
    self%t = t
    self%dt = dt
    self%t_p1 = 0.0_rp
    self%t_p2 = 0.0_rp
  end subroutine begin_step

  !> The block system of the step, from the state of the last step.
  subroutine assemble(self, status)
    class(biot_simulation_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    call self%phys%assemble(self%mesh, self%t, self%dt, status)
  end subroutine assemble

  !> The block system for the new state, from the old state as initial
  !> guess; the preconditioner's parts are (re)built as they fall due.
  !> The matrix depends on dt alone (assemble), so a direct solver keeps its
  !> factors while dt stays the same.
  subroutine linear_system(self, direct, sys, log, status)
    class(biot_simulation_t), intent(inout), target :: self
    logical, intent(in) :: direct
    type(linear_system_t), intent(inout) :: sys
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer(ip) :: u0, u1
    call sys%reset()
    self%phys%x = self%phys%x_old
    sys%a => self%phys%sys
    sys%b => self%phys%rhs
    sys%x => self%phys%x
    sys%fields = 'u,q,p'
    if (direct) then
      sys%changed = self%dt /= self%direct_dt
      self%direct_dt = self%dt
      return
    end if
    call self%setup_precon(log, status)
    if (.not. status%ok()) return
    sys%m => self%bpc%bp
    sys%d => self%dscale
    sys%setup_time = self%t_p1 + self%t_p2
    call self%bpc%add_parts(sys)
    if (self%solver%precon == 'mgr') then
      ! hypre's MGR on the whole system (the block preconditioner above
      ! still gives the scaling and the elastic reference's AMG)
      sys%setup_time = 0.0_rp
      if (self%dt /= self%mgr_dt) then
        call self%mgr%setup_blocks(self%phys%sys, [3, 1, 1], [0, 3, 4], mgr_biot(), self%amg, status)
        call agree(self%comm, status)
        if (.not. status%ok()) return
        self%mgr_dt = self%dt
        sys%setup_time = self%mgr%setup_time
        call sys%add_part('hypre MGR', self%mgr%setup_time)
      end if
      sys%m => self%mgr
    end if
    call self%phys%sys%block_range(iu, u0, u1)
    sys%k_ref => self%phys%sys%a(iu, iu)
    sys%b_ref => self%phys%rhs(u0:u1)
    sys%m_ref => self%bpc%bp%s(iu)%p
  end subroutine linear_system

  !> T_p1 on the first call, T_p2 and the scaling whenever dt changed.
  !> Collective; status agrees.
  subroutine setup_precon(self, log, status)
    class(biot_simulation_t), intent(inout), target :: self
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=msg_len) :: line
    if (.not. self%setup_done) then
      call self%bpc%setup_fixed(self%phys, self%mesh, self%solver, self%fsai, self%amg_k, self%amg_s, status)
      call agree(self%comm, status)
      if (.not. status%ok()) then
        status%msg = 'preconditioner set-up: '//trim(status%msg)
        return
      end if
      self%setup_done = .true.
      self%t_p1 = self%bpc%t_p1
      if (self%bpc%explicit) call log%info('explicit decoupling factors: ||K F1 - Q||/||Q|| '// &
        trim(rtoa(self%bpc%resid_f(1)))//', ||A F2 - B||/||B|| '//trim(rtoa(self%bpc%resid_f(2))))
    end if
    if (self%dt == self%dt_used) return
    call self%bpc%setup_dt(self%phys, self%mesh, self%dt, status)
    call agree(self%comm, status)
    if (.not. status%ok()) then
      status%msg = 'preconditioner set-up: '//trim(status%msg)
      return
    end if
    self%t_p2 = self%bpc%t_p2
    if (self%bpc%nnz_fixed + self%bpc%nnz_dt > 0) then
      line = 'block preconditioner '//trim(self%bpc%bp%name())//': density mu '//trim(rtoa(self%bpc%density()))// &
        ' (stored non-zeros '//itoa(int(self%bpc%nnz_fixed + self%bpc%nnz_dt))//' / '// &
        itoa(int(self%bpc%nnz_matrix))//')'
      if (self%dt_used < 0.0_rp) then
        call log%info(line)
      else
        call log%detail(line)
      end if
    end if
    self%dt_used = self%dt
    call scaling(self)
  end subroutine setup_precon

  !> Scaling of the rows and columns of the block system: 1/sqrt of the
  !> diagonal of K and A, and of the Schur approximation for the pressure
  !> (whose own diagonal vanishes for incompressible constituents).
  subroutine scaling(self)
    type(biot_simulation_t), intent(inout) :: self
    integer(ip) :: u0, u1, q0, q1, p0, p1
    call self%phys%sys%block_range(iu, u0, u1)
    call self%phys%sys%block_range(iq, q0, q1)
    call self%phys%sys%block_range(ipr, p0, p1)
    call self%phys%sys%a(iu, iu)%diagonal(self%dscale(u0:u1))
    call self%phys%sys%a(iq, iq)%diagonal(self%dscale(q0:q1))
    call self%bpc%s%diagonal(self%dscale(p0:p1))
    self%dscale = 1.0_rp / sqrt(abs(self%dscale))
  end subroutine scaling

  !> A linear step is done once solved; its mass balance is measured.
  subroutine update(self, iteration, linear_its, log, converged, why, status)
    class(biot_simulation_t), intent(inout) :: self
    integer, intent(in) :: iteration, linear_its
    type(logger_t), intent(inout) :: log
    logical, intent(out) :: converged
    character(len=*), intent(out) :: why
    type(error_status_t), intent(inout) :: status
    self%mass_bal = mass_balance(self%phys)
    converged = .true.
    why = ''
  end subroutine update

  !> The new state becomes the old one.
  subroutine accept_step(self)
    class(biot_simulation_t), intent(inout) :: self
    self%phys%x_old = self%phys%x
  end subroutine accept_step

  subroutine save_state(self, st)
    class(biot_simulation_t), intent(inout) :: self
    type(state_record_t), intent(inout) :: st
    call st%put('state', self%phys%x_old)
  end subroutine save_state

  subroutine load_state(self, st, status)
    class(biot_simulation_t), intent(inout) :: self
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    call st%get('state', self%phys%x_old, status)
    self%phys%x = self%phys%x_old
  end subroutine load_state

  !> displacement [m] per node; pressure [Pa], Darcy velocity [m/s], total
  !> stress [Pa] (Tensor6 xx yy zz xy yz xz, tension positive), region and
  !> rank per cell.
  subroutine write_output(self, out, status)
    class(biot_simulation_t), intent(inout) :: self
    type(field_output_t), intent(inout) :: out
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: u_loc(:), q_loc(:), stress(:,:), vel(:,:), pres(:)
    integer(ip) :: q0, q1, nc, p0, p1
    associate (phys => self%phys, mesh => self%mesh)
      call solid_fields(self, u_loc, pres, stress)
      call phys%sys%block_range(iq, q0, q1)
      call phys%sys%block_range(ipr, p0, p1)
      nc = mesh%cell_map%n_owned
      allocate(q_loc(phys%qd%n_local()), vel(3, nc))
      q_loc = 0.0_rp
      q_loc(1:q1 - q0 + 1) = phys%x(q0:q1)
      call phys%qd%map%import(q_loc)
      call phys%cell_velocity(mesh, q_loc, vel)
      call out%write_displacement(mesh, u_loc, status)
      if (status%ok()) call out%writer%cell_field('pressure', pres, status)
      if (status%ok() .and. phys%mech%geo%on) call out%writer%cell_field('pressure_change', &
        phys%x(p0:p0 + nc - 1), status)
      if (status%ok()) call out%writer%cell_field('darcy_velocity', vel, status)
      if (status%ok()) call out%writer%cell_field('stress', stress, status)
      call out%write_mesh_ids(mesh, status)
    end associate
  end subroutine write_output

  !> &geostatic: how far the in-situ state is from equilibrium on this mesh.
  !> Biot has no balancing step (its step 0 is the undrained response to the
  !> loads): a state out of equilibrium beyond round-off moves the solid,
  !> and the log says so. Collective.
  subroutine report_in_situ(self, log)
    type(biot_simulation_t), intent(inout) :: self
    type(logger_t), intent(inout) :: log
    real(rp) :: r
    r = self%phys%mech%in_situ_imbalance(self%mesh)
    call log%info('geostatic: largest nodal force of the in-situ state out of equilibrium: '//trim(rtoa(r))// &
      ' of the largest nodal weight; the pressure unknown, its boundary values and sources are changes from '// &
      'the hydrostatic pressure, the output pressure the total')
    if (r > 1.0e-8_rp) call log%warn('geostatic: the in-situ state is not in equilibrium on this mesh (layers '// &
      'not bounded by horizontal planes?): the displacements include its response')
  end subroutine report_in_situ

  !> The displacement (local, ghosts imported), the pressure and the total
  !> stress (xx yy zz xy yz xz, tension positive) of the current state.
  subroutine solid_fields(self, u_loc, pres, stress)
    type(biot_simulation_t), intent(inout) :: self
    real(rp), allocatable, intent(out) :: u_loc(:), pres(:), stress(:,:)
    integer(ip) :: u0, u1, p0, p1, c, nc
    associate (phys => self%phys, mesh => self%mesh)
      call phys%sys%block_range(iu, u0, u1)
      call phys%sys%block_range(ipr, p0, p1)
      nc = mesh%cell_map%n_owned
      allocate(u_loc(phys%mech%u%n_local()), stress(6, nc))
      u_loc = 0.0_rp
      u_loc(1:u1 - u0 + 1) = phys%x(u0:u1)
      call phys%mech%u%map%import(u_loc)
      pres = phys%x(p0:p1)
      ! &geostatic: the unknown is the change from the hydrostatic pressure
      if (phys%mech%geo%on) then
        do c = 1, nc
          pres(c) = pres(c) + phys%mech%geo%pore_pressure(sum(mesh%coords(3, mesh%cell_nodes(:, c))) / 8.0_rp)
        end do
      end if
      call phys%mech%cell_stress(mesh, u_loc, stress)
      do c = 1, nc
        ! total stress = effective - b p I (xx, yy, zz are components 1, 2, 3)
        stress(1:3, c) = stress(1:3, c) - phys%biot(mesh%cell_region(c)) * pres(c)
      end do
    end associate
  end subroutine solid_fields

  !> Displacement, pressure and total stress for the probes.
  subroutine probe_names(self, names)
    class(biot_simulation_t), intent(in) :: self
    character(len=8), allocatable, intent(out) :: names(:)
    names = [character(len=8) :: 'ux', 'uy', 'uz', 'p', 'sxx', 'syy', 'szz', 'sxy', 'syz', 'sxz']
  end subroutine probe_names

  !> The probes' fields, and the rate of each pressure-controlled source
  !> (its column). Collective.
  subroutine sample(self, pf, status)
    class(biot_simulation_t), intent(inout) :: self
    type(probe_fields_t), intent(inout) :: pf
    type(error_status_t), intent(inout) :: status
    integer(ip) :: p0, p1
    call solid_fields(self, pf%u, pf%p, pf%stress)
    call self%phys%sys%block_range(ipr, p0, p1)
    call self%phys%source_rates(self%mesh, self%phys%x(p0:p1), pf%names, pf%values)
  end subroutine sample

  !> The step line: iterations, residual, local mass balance, the two set-up
  !> parts (MUMPS: analysis + factorization as the first) and the solve.
  subroutine report_step(self, stats, line)
    class(biot_simulation_t), intent(inout) :: self
    type(step_stats_t), intent(in) :: stats
    character(len=*), intent(out) :: line
    real(rp) :: p1, p2
    p1 = self%t_p1
    p2 = self%t_p2
    if (self%solver%method == 'mumps') then
      p1 = stats%t_setup
      p2 = 0.0_rp
    end if
    write(line, '(a,i4,a,es10.3,a,es10.3,a,i4,a,es9.2,a,es9.2,a,f8.3,a,f8.3,a,f8.3,a)') 'step ', stats%step, &
      '  t ', stats%t, '  dt ', stats%dt, '  iterations ', stats%linear_its, '  rel. residual ', stats%rel_res, &
      '  mass balance ', self%mass_bal, '  setup(dt-indep.) ', p1, ' s  setup(dt) ', p2, &
      ' s  solve ', stats%t_solve, ' s'
  end subroutine report_step

  !> Local mass conservation of the step: the largest cell residual of the
  !> mass balance rows, relative to the largest sum of the magnitudes of a
  !> cell's terms (volume change, storage, net outflow). Collective.
  real(rp) function mass_balance(phys)
    type(poromechanics_t), intent(inout) :: phys
    real(rp), allocatable :: r(:), t1(:), t2(:), t3(:)
    integer(ip) :: u0, u1, q0, q1, p0, p1
    type(parallel_comm_t) :: comm
    real(rp) :: scale
    comm = phys%mech%u%map%comm
    call phys%sys%block_range(iu, u0, u1)
    call phys%sys%block_range(iq, q0, q1)
    call phys%sys%block_range(ipr, p0, p1)
    allocate(r(size(phys%rhs)), t1(p1 - p0 + 1), t2(p1 - p0 + 1), t3(p1 - p0 + 1))
    call phys%sys%apply(phys%x, r)
    r = phys%rhs - r
    call phys%sys%apply_block(ipr, iu, phys%x(u0:u1) - phys%x_old(u0:u1), t1)
    call phys%sys%apply_block(ipr, iq, phys%x(q0:q1), t2)
    call phys%sys%apply_block(ipr, ipr, phys%x(p0:p1) - phys%x_old(p0:p1), t3)
    scale = 0.0_rp
    if (p1 >= p0) scale = maxval(abs(t1) + abs(t2) + abs(t3))
    scale = comm%max(scale)
    mass_balance = 0.0_rp
    if (p1 >= p0) mass_balance = maxval(abs(r(p0:p1)))
    mass_balance = comm%max(mass_balance) / max(scale, tiny(1.0_rp))
  end function mass_balance

  subroutine free(self)
    class(biot_simulation_t), intent(inout) :: self
    call self%bpc%free()
    call self%mgr%free()
    call self%phys%free()
    if (allocated(self%dscale)) deallocate(self%dscale)
    self%setup_done = .false.
    self%dt_used = -1.0_rp
    self%direct_dt = -1.0_rp
  end subroutine free
  !> The resolved groups: the shared ones, then &biot and every &source.
  subroutine parameter_groups(self, groups)
    class(biot_simulation_t), intent(in) :: self
    type(param_group_t), allocatable, intent(out) :: groups(:)
    type(param_group_t), allocatable :: common(:)
    integer :: k, n
    call common_parameter_groups(self, common)
    n = size(common)
    allocate(groups(n + size(self%srcs) + 1))
    groups(1:n) = common
    call self%bcfg%describe(groups(n + 1))
    do k = 1, size(self%srcs)
      call self%srcs(k)%describe(groups(n + 1 + k))
    end do
  end subroutine parameter_groups

  !> Groups and variables of other physics, refused in this one's deck.
  subroutine foreign_inputs(self, list)
    class(biot_simulation_t), intent(in) :: self
    character(len=foreign_len), allocatable, intent(out) :: list(:)
    list = [character(len=foreign_len) :: 'fault', 'contact', 'fracture_flow', 'well', 'fracture_pressure']
  end subroutine foreign_inputs
end module biot_simulation
