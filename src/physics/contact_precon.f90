!> Block preconditioners of the contact Jacobian [K C1; C2 -H] (C2 and the
!> (t,t) block as the statuses make them), built in the general framework
!> (block_precon.f90) as the seed's contact part describes:
!>
!>   classical  (u first)  upper block triangular with S_1 = BoomerAMG(K) and
!>              the explicit Schur complement S = J_tt - C2 diag(K)^-1 C1,
!>              preconditioned by BoomerAMG or Jacobi of -S;
!>   reordered  (t first)  LDU of A* = [-H~ C2; C1 K] with H~ a regular
!>              diagonal that dominates H_t (interface_contact%ht_diagonal): S_1 = -H~
!>              (exact), S_2 = BoomerAMG(S*), S* = K + C1 H~^-1 C2, a
!>              stiffness-like matrix on which elasticity AMG works; the
!>              factors are implicit (C2 and C1 times S_1^-1), so A*^-1 is
!>              applied up to the AMG (schur_solve = 'pcg': a few CG steps
!>              with the AMG; 'inner_cg': up to an inner CG to 1e-10, the
!>              diagnostic of an exact S*);
!>   augmented  the same with H~ = D, the augmentation diagonal (the row
!>              scales s of contact), for the unstabilized saddle point:
!>              built on A* = [-D C2; C1 K] and applied to the Jacobian. It
!>              is the default of the stable face-bubble space (contact's
!>              space 'bubble', a pure saddle point), where S* has the
!>              bubbles' rows (3 consecutive unknowns each, like a node's).
!>
!> With the fluid in the fractures (physics 'fracture_flow', blocks t, u, p)
!> the reordered preconditioner gets the seed's second level: the (t, u)
!> block A_cm is the first level as above, and the pressure's Schur
!> complement uses the diagonal of the first level's S* in place of A_cm^-1
!> (the seed's "second Schur complement from the diagonal of the first").
!> The pressure enters the momentum rows as the normal traction does
!> (A_up = Q1 = -C1 P, P putting p on the normal component), so the
!> preconditioner is built for the total traction tau = t - P p, which
!> carries the pressure out of the momentum rows and into the contact rows
!> (A_tp = J_tt P): the system in (tau, u, p) is A E with E the unit upper
!> block matrix that gives t = tau + P p, and the preconditioner of A is E
!> times the framework's one of A E. After t is eliminated with S_t = -H~:
!>   F(t,p) = P - S_t^-1 J_tt P = (I + H~^-1 J_tt) P      (explicit, sparse)
!>   B_up = -C1 S_t^-1 J_tt P = Q1 + C1 F(t,p)            (the reduced (u,p) block)
!>   F(u,p) = -S*^-1 B_up,  G(p,u) = -A_pu S*^-1           (implicit, u AMG)
!>   S_p = A_pp - A_pu diag(S*)^-1 B_up                     (BoomerAMG or Jacobi)
!> On an open element J_tt = -s I = -H~, so F(t,p) = 0 and B_up = Q1: the
!> pressure pushes the faces apart. On a closed one the traction takes the
!> pressure (F(t,p) ~ P) and B_up keeps only what the stabilization lets
!> through (and, slipping, the friction's drop with the effective normal
!> traction). Built on Q1 directly, diag(S*)^-1 would give every closed
!> element a compliance it does not have; on closed fractures fed by a well
!> GMRES then stalled for hundreds of iterations.
!>
!> The alternative (pressure_block = 'eliminated', blocks t, p, u): the
!> pressure is eliminated as the tractions are, before the displacement,
!> with S_p = D_p the row sums of |A_pp| (like H~, a diagonal that dominates
!> its block), so that the last block is
!>   S** = K + C1 H~^-1 C2 - Q1 D_p^-1 A_pu,
!> S* with the fluid's constraint on the opening (the undrained limit of
!> each element: on a closed element the contact's constraint is already
!> there, on an open one this is the only stiffness of the opening), and
!> every factor implicit with a diagonal or the one AMG of S**: one V-cycle
!> per iteration, against two and the AMG of S_p for 'schur'. On the
!> reduced nine-fracture case with exact inner solves, 35-60 iterations
!> where 'schur' needs 77-101 (contact alone: 19-20).
!>
!> With the fluid, either way, the fractures' subspace correction
!> (element_subspace below) goes before the block preconditioner: per
!> element the pressure with the normal traction following it, L = A_pp -
!> J_tt(n, n) on those pairs by BoomerAMG. On the nine-fracture case it took
!> 'eliminated' from 65/36 (stick), 50-90 (slip) to 23/14 and 22-37 on 4 m
!> cells, and from 112/63 and 80-199 to 24/15 and 28-43 on 2 m cells
!> (contact alone: 28 and 25-34).
!>
!> K does not change during a run: its AMG (classical) is made once; the
!> Schur parts are rebuilt at every Newton iteration (kept while every
!> element sticks, &contact reuse), because C2 and the (t,t) block follow
!> the statuses. S* = K + C1 H~^-1 C2 (reordered_schur) is given to its
!> BoomerAMG row by row, K's rows merged with the product's as hypre asks
!> for them (sum_rows), and never stored here: no copy of K, no S*, no S*
!> pattern between set-ups; the PCG steps of schur_solve = 'pcg' use the
!> product of hypre's copy. HI24L medium, 2 ranks: the peak 1,206 -> 1,023
!> MB a rank when S* kept its pattern only, and contact n = 40 405 -> 341
!> MB with S* given by rows. (schur_solve = 'inner_cg', whose CG needs S*
!> here, keeps it: assembled_schur refreshes it in place, its first build
!> on the union of K's and the product's patterns.)
module contact_precon
  use kinds, only: rp, ip, gp, name_len
  use parallel_comm, only: wall_time
  use machine_memory, only: peak_resident_bytes
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, from_csr, to_csr, gcsr_multiply, gcsr_add, add_to_csr, add_csr_to_csr, &
    union_to_csr
  use amg_params, only: amg_params_t
  use precon, only: precon_t
  use precon_factory, only: precon_params_t, make_and_setup
  use jacobi_precon, only: jacobi_precon_t
  use negated_precon, only: negated_precon_t
  use inner_cg_precon, only: inner_cg_precon_t
  use boomeramg_precon, only: boomeramg_precon_t
  use sum_rows, only: sum_rows_t
  use block_precon, only: block_precon_t
  use subspace_precon, only: subspace_precon_t
  use dist_mesh, only: dist_mesh_t
  use block_matrix, only: block_matrix_t, block_columns_t
  use physics_component, only: physics_component_t, coupling_t
  use mechanics_component, only: mechanics_component_t, mechanics_of
  use interface_contact, only: interface_contact_t, interface_contact_of, state_stick, state_open
  use fracture_flow_component, only: fracture_flow_component_t, fracture_flow_of
  use contact_config, only: contact_config_t
  use linear_system, only: linear_system_t
  implicit none
  private

  public :: contact_precon_t

  !> The blocks and components the preconditioner works on: the mechanics
  !> (u), the interface contact (t) and, when the composition has one, the
  !> fracture flow (p).
  type :: contact_view_t
    type(coupling_t), pointer :: ctx => null()
    type(block_matrix_t), pointer :: sys => null()
    integer :: bu = 0, bt = 0, bp = 0
    logical :: flow = .false.
    real(rp) :: dt = 1.0_rp                       !< the fluid's time step (1 without the fluid)
    type(mechanics_component_t), pointer :: mc => null()
    type(interface_contact_t), pointer :: ic => null()
    type(fracture_flow_component_t), pointer :: fc => null()
  end type contact_view_t

  type :: contact_precon_t
    type(block_precon_t) :: bp
    !> -S (classical), or S* for schur_solve = 'inner_cg' (else S* lives in
    !> its BoomerAMG's copy only: reordered_schur)
    type(csr_matrix_t) :: s
    real(rp), allocatable :: s_diag(:)           !< flow, pressure_block = 'schur': S*'s diagonal (owned rows)
    type(global_csr_t) :: gc1                    !< C1 (classical: diag(K)^-1 C1)
    type(csr_matrix_t) :: sp                     !< S_p, the pressure's Schur complement (flow)
    type(global_csr_t) :: gup                    !< A_up = Q1 (flow, constant)
    logical :: p_eliminated = .false.            !< flow: pressure_block = 'eliminated'
    integer(gp) :: nnz_pressure = 0              !< non-zeros of the last S_p
    character(len=name_len) :: variant = ''
    logical :: ready = .false.
    integer, allocatable :: built_state(:)       !< owned statuses when the Schur part was built (&contact reuse)
    integer :: reused = 0                        !< set-ups that kept the Schur part
    integer :: lagged = 0                        !< refreshes of S*'s finest level since its AMG was built (&contact amg_lag)
    logical :: step_start = .true.               !< set-up of a step's first Newton iteration (the AMG of S* is built anew)
    real(rp) :: built_dt = -1.0_rp               !< flow: the time step of that build (the mass rows depend on it)
    real(rp) :: t_setup = 0.0_rp                 !< seconds of the last set-up
    !> its components' seconds in the last set-up (0: not rebuilt): the AMG
    !> of K (first set-up, classical), the Schur matrix (S*, S**, -S), its
    !> preconditioner, S_p with its preconditioner ('schur'), the subspace's L
    real(rp) :: t_k = 0.0_rp, t_smat = 0.0_rp, t_sprec = 0.0_rp, t_sp = 0.0_rp, t_sub = 0.0_rp
    !> the same parts' rises of the peak resident memory [bytes]
    integer(gp) :: m_k = 0, m_smat = 0, m_sprec = 0, m_sp = 0, m_sub = 0
    character(len=name_len) :: sprec_name = ''   !< the Schur matrix's preconditioner
    type(subspace_precon_t) :: sub               !< flow: bp with the per-element subspace correction
    type(block_columns_t) :: tp_columns          !< the Jacobian's t and p column blocks (products with Z)
    type(csr_matrix_t) :: lsub                   !< its operator L = Y^T A Z
    class(precon_t), allocatable :: plsub        !< BoomerAMG of L
    logical :: subspace = .false.                !< flow: the subspace correction (&fracture_flow)
    !> flow: S_p's matrix only, its preconditioner left to the caller (the
    !> joint pressure Schur complement of 'poromechanics_faults',
    !> poro_faults_precon.f90); rebuilt: the last set-up made the Schur part
    logical :: joint_pressure = .false., rebuilt = .false.
    integer(gp) :: nnz_schur = 0                 !< non-zeros of the last Schur matrix
  contains
    procedure :: setup
    procedure :: add_parts
    procedure :: free
  end type contact_precon_t

contains

  !> Set up (first call) or refresh (later calls: the Schur part) for the
  !> current Jacobian of the composition of ctx (mechanics, interface
  !> contact and maybe fracture flow). amg: elasticity settings (for K and
  !> S*). Collective.
  subroutine setup(self, ctx, mesh, ccfg, amg, status, pressure_precon)
    class(contact_precon_t), intent(inout), target :: self
    type(coupling_t), intent(inout), target :: ctx
    type(dist_mesh_t), intent(in) :: mesh
    type(contact_config_t), intent(in) :: ccfg
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in), optional :: pressure_precon   !< flow: 'boomeramg' or 'jacobi' for S_p
    class(precon_t), allocatable :: p
    type(precon_params_t) :: params
    real(rp) :: t0, t1
    integer(gp) :: m1
    real(rp), allocatable :: h(:)
    type(contact_view_t) :: phys
    phys = view_of(ctx)
    t0 = wall_time()
    self%t_k = 0.0_rp
    self%t_smat = 0.0_rp
    self%t_sprec = 0.0_rp
    self%t_sp = 0.0_rp
    self%t_sub = 0.0_rp
    self%m_k = 0
    self%m_smat = 0
    self%m_sprec = 0
    self%m_sp = 0
    self%m_sub = 0
    self%rebuilt = .false.
    if (.not. self%ready) then
      self%variant = ccfg%block
      call self%bp%init(phys%sys, 'contact-'//trim(ccfg%block))
      call from_csr(phys%sys%a(phys%bu, phys%bt), self%gc1)
      if (self%variant == 'classical') then
        params%amg = amg
        call make_and_setup('boomeramg', p, phys%sys%a(phys%bu, phys%bu), params, status)
        if (.not. status%ok()) return
        self%t_k = p%setup_time
        self%m_k = p%setup_rise
        call move_alloc(p, self%bp%s(phys%bu)%p)
        call scale_rows_by_diagonal(phys%sys%a(phys%bu, phys%bu), self%gc1)
        call self%bp%set_implicit(phys%bu, phys%bt, phys%bu)
      else
        call self%bp%set_implicit(phys%bt, phys%bu, phys%bt)
        call self%bp%set_implicit(phys%bu, phys%bt, phys%bt)
        if (phys%flow) then
          call from_csr(phys%sys%a(phys%bu, phys%bp), self%gup)
          ! the physics' block order says which: t, p, u for pressure_block =
          ! 'eliminated', t, u, p for 'schur'
          self%p_eliminated = phys%bp < phys%bu
          if (self%p_eliminated) then
            call self%bp%set_implicit(phys%bp, phys%bu, phys%bp)
            call self%bp%set_implicit(phys%bu, phys%bp, phys%bp)
          else
            call self%bp%set_implicit(phys%bp, phys%bu, phys%bu)
          end if
        end if
      end if
      self%ready = .true.
    end if
    if (ccfg%reuse .and. allocated(self%built_state) .and. (.not. phys%flow .or. phys%dt == self%built_dt)) then
      ! every element sticks, as when the Schur part was built (and, with the
      ! fluid, the step size is the same): the Jacobian is the same, keep it.
      ! (Kept through slipping iterations too, it cost more solve time than
      ! it saved set-up: 421 iterations against 90 on the nine fractures.)
      if (.not. mesh%comm%any_true(any(phys%ic%state(1:mesh%iface_map%n_owned) /= state_stick) .or. &
                                   any(self%built_state /= state_stick))) then
        self%reused = self%reused + 1
        self%t_setup = wall_time() - t0
        return
      end if
    end if
    if (self%variant == 'classical') then
      call classical_schur(self, phys, ccfg, amg, status)
    else
      call reordered_schur(self, phys, mesh, ccfg, amg, h, status)
      t1 = wall_time()
      m1 = peak_resident_bytes()
      if (status%ok() .and. phys%flow .and. .not. self%p_eliminated) then
        call pressure_schur(self, phys, h, amg, pressure_precon, status)
        self%t_sp = wall_time() - t1
        self%m_sp = peak_resident_bytes() - m1
      end if
      t1 = wall_time()
      m1 = peak_resident_bytes()
      if (status%ok() .and. phys%flow .and. self%subspace) then
        call element_subspace(self, phys, mesh, amg, status)
        self%t_sub = wall_time() - t1
        self%m_sub = peak_resident_bytes() - m1
      end if
    end if
    if (status%ok()) self%built_state = phys%ic%state(1:mesh%iface_map%n_owned)
    self%rebuilt = status%ok()
    self%built_dt = phys%dt
    self%t_setup = wall_time() - t0
  end subroutine setup

  !> -S = -J_tt + C2 diag(K)^-1 C1 and its preconditioner, negated into S_2.
  subroutine classical_schur(self, phys, ccfg, amg, status)
    type(contact_precon_t), intent(inout) :: self
    type(contact_view_t), intent(in) :: phys
    type(contact_config_t), intent(in) :: ccfg
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    type(global_csr_t) :: gc2, gtt, prod, negs
    class(precon_t), allocatable :: p
    type(precon_params_t) :: params
    real(rp) :: t0
    integer(gp) :: m0
    t0 = wall_time()
    m0 = peak_resident_bytes()
    call from_csr(phys%sys%a(phys%bt, phys%bu), gc2)
    call from_csr(phys%sys%a(phys%bt, phys%bt), gtt)
    call gcsr_multiply(gc2, self%gc1, prod)
    call gcsr_add(-1.0_rp, gtt, 1.0_rp, prod, negs)
    call self%s%free()
    call to_csr(negs, phys%ic%t%map, self%s)
    self%nnz_schur = self%s%global_nnz()
    ! -S is a scalar (one unknown per row) operator
    params%amg = amg%scalar()
    self%t_smat = wall_time() - t0
    self%m_smat = peak_resident_bytes() - m0
    call make_and_setup(ccfg%schur_precon, p, self%s, params, status)
    if (.not. status%ok()) return
    self%t_sprec = p%setup_time
    self%m_sprec = p%setup_rise
    self%sprec_name = p%name()
    call replace_negated(self%bp%s(phys%bt)%p, p)
  end subroutine classical_schur

  !> S_1 = -H~ and S_2 = BoomerAMG(K + C1 H~^-1 C2).
  !> S* is given to its BoomerAMG row by row, each row K's merged with the
  !> product's (and S**'s correction) when hypre asks for it (sum_rows): no
  !> S* is stored here, and a refresh builds hypre's copy and hierarchy anew
  !> on the new values, after the old hierarchy is freed; the PCG steps of
  !> schur_solve = 'pcg' take hypre's products. Only schur_solve =
  !> 'inner_cg' keeps S* here for its CG's products (assembled_schur).
  subroutine reordered_schur(self, phys, mesh, ccfg, amg, h, status)
    type(contact_precon_t), intent(inout), target :: self
    type(contact_view_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(contact_config_t), intent(in) :: ccfg
    type(amg_params_t), intent(in) :: amg
    real(rp), allocatable, intent(out) :: h(:)   !< H~ (owned t rows)
    type(error_status_t), intent(inout) :: status
    type(global_csr_t), target :: gc2, prod, corr
    type(sum_rows_t) :: src
    class(precon_t), allocatable :: p, w
    type(boomeramg_precon_t), allocatable :: samg
    type(boomeramg_precon_t), pointer :: old
    type(precon_params_t) :: params
    real(rp) :: t0
    integer(gp) :: m0
    t0 = wall_time()
    m0 = peak_resident_bytes()
    allocate(h(phys%ic%t%n_owned()))
    call phys%ic%ht_diagonal(phys%ctx, ccfg%aug_scale, ccfg%block == 'reordered', h)
    call put_diagonal(self%bp%s(phys%bt)%p, -h)
    call from_csr(phys%sys%a(phys%bt, phys%bu), gc2)
    call divide_rows(gc2, h)
    call gcsr_multiply(self%gc1, gc2, prod)
    call gc2%free()
    ! S** (pressure_block = 'eliminated') takes away Q1 D_p^-1 A_pu
    if (self%p_eliminated) call pressure_correction(self, phys, corr)
    if (ccfg%schur_solve == 'inner_cg') then
      call assembled_schur(self, phys, mesh, amg, prod, corr, t0, m0, status)
      return
    end if
    if (self%p_eliminated) then
      call src%init(phys%sys%a(phys%bu, phys%bu), prod, 1.0_rp, corr, -1.0_rp)
    else
      call src%init(phys%sys%a(phys%bu, phys%bu), prod, 1.0_rp)
    end if
    if (phys%flow .and. .not. self%p_eliminated) then
      if (allocated(self%s_diag)) deallocate(self%s_diag)
      allocate(self%s_diag(phys%sys%a(phys%bu, phys%bu)%n_rows))
      call src%diagonal(self%s_diag)
    end if
    self%t_smat = wall_time() - t0
    self%m_smat = peak_resident_bytes() - m0
    m0 = peak_resident_bytes()
    old => null()
    if (allocated(self%bp%s(phys%bu)%p)) old => schur_amg(self%bp%s(phys%bu)%p)
    if (associated(old)) then
      ! a refresh: the preconditioner (and the PCG steps around it) stay;
      ! within amg_lag Newton iterations of its build, and within the step,
      ! only the finest level of S*'s hierarchy is renewed (geoblock's
      ! cycle); a step's first iteration builds it anew, so that a restart
      ! (at a step) meets the same hierarchies as the run it continues
      if (self%lagged + 1 < ccfg%amg_lag .and. .not. self%step_start .and. old%own_cycle) then
        call old%refresh_rows(src, status, galerkin=ccfg%amg_refresh == 'galerkin')
        self%lagged = self%lagged + 1
      else
        call old%update_rows(src, status)
        self%lagged = 0
      end if
      call prod%free()
      call corr%free()
      if (.not. status%ok()) return
      self%t_sprec = old%setup_time
      self%m_sprec = peak_resident_bytes() - m0
      self%bp%s(phys%bu)%p%setup_time = old%setup_time
      self%nnz_schur = mesh%comm%sum(int(old%ij%nnz, gp))
      return
    end if
    call discard(self%bp%s(phys%bu)%p)
    self%lagged = 0
    params%amg = amg
    ! S* has K's near-null space: the rigid-body modes, where asked (&amg)
    if (amg%interp_vec_variant > 0) params%modes = phys%mc%mech%rigid_body_modes(mesh)
    allocate(samg)
    if (allocated(params%modes)) then
      call samg%setup_rows(src, params%amg, status, params%modes)
    else
      call samg%setup_rows(src, params%amg, status)
    end if
    call prod%free()
    call corr%free()
    if (.not. status%ok()) return
    samg%setup_rise = max(peak_resident_bytes() - m0, 0_gp)
    self%nnz_schur = mesh%comm%sum(int(samg%ij%nnz, gp))
    self%t_sprec = samg%setup_time
    self%m_sprec = samg%setup_rise
    self%sprec_name = samg%name()
    call move_alloc(samg, p)
    if (ccfg%schur_solve == 'pcg') then
      allocate(inner_cg_precon_t :: w)
      select type (w)
      type is (inner_cg_precon_t)
        call w%init_steps(p, ccfg%schur_its)
      end select
      call move_alloc(w, p)
    end if
    call replace(self%bp%s(phys%bu)%p, p)
  end subroutine reordered_schur

  !> reordered_schur for schur_solve = 'inner_cg', whose CG needs S*'s
  !> values here: while S*'s pattern holds the product's, the new values go
  !> into the S* already built, K's and the product's added in place, and
  !> its BoomerAMG is rebuilt on them; a first build (or a new pattern) forms
  !> S* as a sum of distributed matrices, after the old S* and its hierarchy
  !> are freed. t0, m0: the set-up's start (time, peak memory).
  subroutine assembled_schur(self, phys, mesh, amg, prod, corr, t0, m0, status)
    type(contact_precon_t), intent(inout), target :: self
    type(contact_view_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(amg_params_t), intent(in) :: amg
    type(global_csr_t), intent(inout) :: prod, corr
    real(rp), intent(in) :: t0
    integer(gp), intent(in) :: m0
    type(error_status_t), intent(inout) :: status
    logical :: fits
    class(precon_t), allocatable :: p, w
    type(boomeramg_precon_t), pointer :: samg
    type(precon_params_t) :: params
    !> tolerance and cap of the inner CG
    real(rp), parameter :: inner_rtol = 1.0e-10_rp
    integer, parameter :: inner_max_iter = 500
    integer(gp) :: m1
    if (allocated(self%bp%s(phys%bu)%p)) then
      samg => schur_amg(self%bp%s(phys%bu)%p)
      if (associated(samg)) then
        if (refreshed(self, phys, mesh, prod, corr)) then
          call prod%free()
          call corr%free()
          call keep_diagonal(self, phys)
          self%t_smat = wall_time() - t0
          self%m_smat = peak_resident_bytes() - m0
          m1 = peak_resident_bytes()
          call samg%update(self%s, status)
          self%t_sprec = samg%setup_time
          self%m_sprec = peak_resident_bytes() - m1
          self%bp%s(phys%bu)%p%setup_time = samg%setup_time
          return
        end if
      end if
    end if
    call discard(self%bp%s(phys%bu)%p)
    call self%s%free()
    if (self%p_eliminated) then
      call union_to_csr(phys%sys%a(phys%bu, phys%bu), prod, phys%mc%mech%u%map, self%s, corr)
    else
      call union_to_csr(phys%sys%a(phys%bu, phys%bu), prod, phys%mc%mech%u%map, self%s)
    end if
    call add_to_csr(1.0_rp, prod, self%s, fits)
    if (fits .and. self%p_eliminated) call add_to_csr(-1.0_rp, corr, self%s, fits)
    if (.not. fits) error stop 'contact_precon: S* misses an entry of its union pattern'
    call prod%free()
    call corr%free()
    self%nnz_schur = self%s%global_nnz()
    params%amg = amg
    if (amg%interp_vec_variant > 0) params%modes = phys%mc%mech%rigid_body_modes(mesh)
    call keep_diagonal(self, phys)
    self%t_smat = wall_time() - t0
    self%m_smat = peak_resident_bytes() - m0
    call make_and_setup('boomeramg', p, self%s, params, status)
    if (.not. status%ok()) return
    self%t_sprec = p%setup_time
    self%m_sprec = p%setup_rise
    self%sprec_name = p%name()
    allocate(inner_cg_precon_t :: w)
    select type (w)
    type is (inner_cg_precon_t)
      call w%init(self%s, p, inner_rtol, inner_max_iter, status)
    end select
    call move_alloc(w, p)
    call replace(self%bp%s(phys%bu)%p, p)
  end subroutine assembled_schur

  !> S*'s diagonal, while its values are here, for pressure_schur (the
  !> fluid with pressure_block = 'schur').
  subroutine keep_diagonal(self, phys)
    type(contact_precon_t), intent(inout) :: self
    type(contact_view_t), intent(in) :: phys
    if (.not. phys%flow .or. self%p_eliminated) return
    if (allocated(self%s_diag)) deallocate(self%s_diag)
    allocate(self%s_diag(self%s%n_rows))
    call self%s%diagonal(self%s_diag)
  end subroutine keep_diagonal

  !> The BoomerAMG of S*'s preconditioner p: p itself ('vcycle') or the one
  !> inside its CG ('pcg', 'inner_cg', which point to S*); null otherwise.
  function schur_amg(p) result(amg)
    class(precon_t), intent(in), target :: p
    type(boomeramg_precon_t), pointer :: amg
    amg => null()
    select type (p)
    type is (boomeramg_precon_t)
      amg => p
    type is (inner_cg_precon_t)
      select type (q => p%inner)
      type is (boomeramg_precon_t)
        amg => q
      end select
    end select
  end function schur_amg

  !> S*'s values anew in place, K + prod (- corr), when S*'s pattern holds
  !> them on every rank. Collective.
  logical function refreshed(self, phys, mesh, prod, corr)
    type(contact_precon_t), intent(inout) :: self
    type(contact_view_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(global_csr_t), intent(in) :: prod, corr
    logical :: fits
    if (.not. allocated(self%s%val)) allocate(self%s%val(self%s%nnz()))
    self%s%val = 0.0_rp
    call add_csr_to_csr(1.0_rp, phys%sys%a(phys%bu, phys%bu), self%s, fits)
    if (fits) call add_to_csr(1.0_rp, prod, self%s, fits)
    if (fits .and. self%p_eliminated) call add_to_csr(-1.0_rp, corr, self%s, fits)
    refreshed = .not. mesh%comm%any_true(.not. fits)
  end function refreshed

  !> The fractures' subspace correction (&fracture_flow subspace_correction,
  !> subspace_precon.f90), one vector per element: on a closed element its
  !> pressure with its normal traction rising by as much, on an open one its
  !> pressure. On a closed element that pair moves nothing in the momentum
  !> rows (the total traction t - P p is unchanged); the contact rows see it
  !> through the stabilization H_t and the mass rows through the flow, the
  !> storage and the wells. With a stiff fluid and a small residual aperture
  !> the Jacobian nearly annihilates these vectors, and the block
  !> preconditioner, with the diagonals -H~ and D_p for J_tt and A_pp, does
  !> not resolve them: GMRES found them one at a time (plateaus of its
  !> residual) and needed more of them on every finer mesh. With the left
  !> vectors pressure minus normal traction, L = Y^T A Z = A_pp - J_tt(n, n)
  !> on the closed pairs: a Laplacian on the fracture surfaces (flow plus
  !> stabilization), for BoomerAMG. (Tried first and left: one vector per
  !> fracture, its mean, by a least-squares coarse step: it halved the stick
  !> counts but not their growth.) Collective.
  subroutine element_subspace(self, phys, mesh, amg, status)
    type(contact_precon_t), intent(inout), target :: self
    type(contact_view_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(amg_params_t), intent(in) :: amg
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: ptr(:), idx(:)
    real(rp), allocatable :: zval(:), yval(:)
    integer(ip) :: t0, t1, p0, p1, e, k, c, n, kt
    type(precon_params_t) :: params
    class(precon_t), allocatable :: p
    call phys%sys%block_range(phys%bt, t0, t1)
    call phys%sys%block_range(phys%bp, p0, p1)
    call self%lsub%free()
    self%lsub = phys%sys%a(phys%bp, phys%bp)
    nullify(self%lsub%owned_col_map)
    associate (jtt => phys%sys%a(phys%bt, phys%bt), l => self%lsub, st => phys%ic%state)
      do e = 1, l%n_rows
        if (st(e) == state_open) cycle
        do k = l%row_ptr(e), l%row_ptr(e + 1) - 1
          c = l%col(k)
          if (st(c) == state_open) cycle
          do kt = jtt%row_ptr(3 * (e - 1) + 1), jtt%row_ptr(3 * (e - 1) + 2) - 1
            if (jtt%col(kt) == 3 * (c - 1) + 1) l%val(k) = l%val(k) - jtt%val(kt)
          end do
        end do
      end do
      if (associated(phys%ctx)) then
        if (associated(phys%ctx%find('matrix_flow'))) call add_leakoff(phys, l)
      end if
      n = l%n_rows
      allocate(ptr(n + 1), idx(2 * n), zval(2 * n), yval(2 * n))
      ptr(1) = 1
      k = 0
      do e = 1, n
        if (st(e) /= state_open) then
          k = k + 1
          idx(k) = t0 + 3 * (e - 1)
          zval(k) = 1.0_rp
          yval(k) = -1.0_rp
        end if
        k = k + 1
        idx(k) = p0 + e - 1
        zval(k) = 1.0_rp
        yval(k) = 1.0_rp
        ptr(e + 1) = k + 1
      end do
    end associate
    params%amg = amg%scalar()
    call make_and_setup('boomeramg', p, self%lsub, params, status)
    if (.not. status%ok()) return
    call replace(self%plsub, p)
    idx = idx(1:k)
    zval = zval(1:k)
    yval = yval(1:k)
    self%tp_columns%a => phys%sys
    self%tp_columns%cols = [(k == phys%bt .or. k == phys%bp, k = 1, phys%sys%nb)]
    call self%sub%setup(self%bp, self%tp_columns, self%plsub, ptr, idx, zval, yval, phys%sys%n_owned())
  end subroutine element_subspace

  !> With the matrix's fluid (poromechanics_faults), the leak-off on L's
  !> diagonal: per element -sum_f A_pq(e, f) A_qp(f, e) / A_qq(f, f) over
  !> its faces f on the fault, the matrix's flux eliminated with the
  !> diagonal of its Darcy block. In the mixed form the matrix takes the
  !> fractures' fluid through those face fluxes, outside the correction's
  !> vectors; without them L had the flow along the fractures only, and
  !> where the matrix drains the fractures faster (the HI24L field case:
  !> 100 mD sands, elements of 1e4 m^2) the correction moved their
  !> pressures against it: FGMRES stalled at a relative residual of 0.3-0.6
  !> down to dt / 256. With them, its production steps converge (small
  !> mesh: 5 Newton iterations, 343 FGMRES iterations, as without the
  !> correction). Collective.
  subroutine add_leakoff(phys, l)
    type(contact_view_t), intent(in) :: phys
    type(csr_matrix_t), intent(inout) :: l
    real(rp), allocatable :: w(:)
    integer(ip) :: e, f, k, kd
    integer :: bq
    real(rp) :: dex
    bq = phys%ctx%block('q')
    associate (apq => phys%sys%a(phys%bp, bq), aqp => phys%sys%a(bq, phys%bp), aqq => phys%sys%a(bq, bq))
      ! w(f) = A_qp(f, e) / A_qq(f, f) on the owned faces (one element
      ! column on a fault face, none elsewhere), then on the ghost faces
      allocate(w(apq%col_map%n_local()))
      w = 0.0_rp
      call aqq%diagonal(w(1:aqq%n_rows))
      do f = 1, aqp%n_rows
        if (w(f) /= 0.0_rp) w(f) = sum(aqp%val(aqp%row_ptr(f):aqp%row_ptr(f + 1) - 1)) / w(f)
      end do
      call apq%col_map%import(w)
      do e = 1, l%n_rows
        dex = 0.0_rp
        do k = apq%row_ptr(e), apq%row_ptr(e + 1) - 1
          f = apq%col(k)
          dex = dex - apq%val(k) * w(f)
        end do
        kd = l%find(e, e)
        if (kd > 0) l%val(kd) = l%val(kd) + max(dex, 0.0_rp)
      end do
    end associate
  end subroutine add_leakoff

  !> pressure_block = 'eliminated' (header): S_p = D_p, the row sums of
  !> |A_pp|, into its slot, and corr = Q1 D_p^-1 A_pu, which S** takes away
  !> from S*. (Built for the total traction as 'schur' is, with B_up in place
  !> of Q1, it kept the closed elements' coupling out of S** and needed more
  !> iterations: 72/41 against 64/36 in stick, up to 121 against 89
  !> slipping, on the reduced nine-fracture case.)
  subroutine pressure_correction(self, phys, corr)
    type(contact_precon_t), intent(inout) :: self
    type(contact_view_t), intent(in) :: phys
    type(global_csr_t), intent(out) :: corr
    type(global_csr_t) :: gpu
    real(rp), allocatable :: dp(:)
    integer(ip) :: i
    associate (app => phys%sys%a(phys%bp, phys%bp))
      allocate(dp(app%n_rows))
      do i = 1, app%n_rows
        dp(i) = sum(abs(app%val(app%row_ptr(i):app%row_ptr(i + 1) - 1)))
      end do
    end associate
    call from_csr(phys%sys%a(phys%bp, phys%bu), gpu)
    call divide_rows(gpu, dp)
    call gcsr_multiply(self%gup, gpu, corr)
    call put_diagonal(self%bp%s(phys%bp)%p, dp)
  end subroutine pressure_correction

  !> Rows of g divided by d (owned rows).
  subroutine divide_rows(g, d)
    type(global_csr_t), intent(inout) :: g
    real(rp), intent(in) :: d(:)
    integer(ip) :: i, k
    do i = 1, g%n_rows
      do k = g%row_ptr(i), g%row_ptr(i + 1) - 1
        g%val(k) = g%val(k) / d(i)
      end do
    end do
  end subroutine divide_rows

  !> The diagonal matrix d (z = r / d) into slot.
  subroutine put_diagonal(slot, d)
    class(precon_t), allocatable, intent(inout) :: slot
    real(rp), intent(in) :: d(:)
    class(precon_t), allocatable :: p
    allocate(jacobi_precon_t :: p)
    select type (p)
    type is (jacobi_precon_t)
      p%d = d
    end select
    call replace(slot, p)
  end subroutine put_diagonal

  !> The pressure's part (header): F(t,p), B_up with F(u,p), and S_p with
  !> its preconditioner in S_3. h: H~ of the owned t rows.
  subroutine pressure_schur(self, phys, h, amg, choice, status)
    type(contact_precon_t), intent(inout), target :: self
    type(contact_view_t), intent(in) :: phys
    real(rp), intent(in) :: h(:)
    type(amg_params_t), intent(in) :: amg
    character(len=*), intent(in) :: choice
    type(error_status_t), intent(inout) :: status
    type(global_csr_t) :: gftp, gbup, gup_d, gpu, gpp, prod, sp
    type(csr_matrix_t) :: ftp, bup
    class(precon_t), allocatable :: p
    type(precon_params_t) :: params
    call traction_pressure_factor(phys, h, ftp)
    call from_csr(ftp, gftp)
    call gcsr_multiply(self%gc1, gftp, prod)
    call gcsr_add(1.0_rp, self%gup, 1.0_rp, prod, gbup)
    call to_csr(gbup, phys%mc%mech%u%map, bup)
    call self%bp%set_explicit(phys%bt, phys%bp, 1.0_rp, ftp)
    gup_d = gbup
    call divide_rows(gup_d, self%s_diag)
    call from_csr(phys%sys%a(phys%bp, phys%bu), gpu)
    call from_csr(phys%sys%a(phys%bp, phys%bp), gpp)
    call gcsr_multiply(gpu, gup_d, prod)
    call gcsr_add(1.0_rp, gpp, -1.0_rp, prod, sp)
    call self%bp%set_implicit(phys%bu, phys%bp, phys%bu, coupling=bup)
    call self%sp%free()
    call to_csr(sp, phys%fc%pd%map, self%sp)
    self%nnz_pressure = self%sp%global_nnz()
    if (self%joint_pressure) return
    params%amg = amg%scalar()
    call make_and_setup(choice, p, self%sp, params, status)
    if (.not. status%ok()) return
    call replace(self%bp%s(phys%bp)%p, p)
  end subroutine pressure_schur

  !> F(t,p) = (I + H~^-1 J_tt) P on the owned t rows, columns the local
  !> pressures: J_tt's entries in normal columns (local t index 3 (e-1) + 1
  !> of local element e, whose pressure has local index e) divided by the
  !> row's H~, plus 1 where the row is its element's normal component.
  subroutine traction_pressure_factor(phys, h, f)
    type(contact_view_t), intent(in) :: phys
    real(rp), intent(in) :: h(:)
    type(csr_matrix_t), intent(inout) :: f
    integer(ip), allocatable :: ptr(:), col(:)
    real(rp), allocatable :: val(:)
    integer(ip) :: i, k, n, c, e_row
    logical :: diag_done
    associate (jtt => phys%sys%a(phys%bt, phys%bt))
      allocate(ptr(jtt%n_rows + 1), col(jtt%nnz() + jtt%n_rows), val(jtt%nnz() + jtt%n_rows))
      n = 0
      ptr(1) = 1
      do i = 1, jtt%n_rows
        e_row = (i - 1) / 3 + 1
        diag_done = mod(i - 1, 3) /= 0          ! only normal rows carry the identity
        do k = jtt%row_ptr(i), jtt%row_ptr(i + 1) - 1
          c = jtt%col(k)
          if (mod(c - 1, 3) /= 0) cycle
          if (.not. diag_done .and. (c - 1) / 3 + 1 > e_row) then
            n = n + 1
            col(n) = e_row
            val(n) = 1.0_rp
            diag_done = .true.
          end if
          n = n + 1
          col(n) = (c - 1) / 3 + 1
          val(n) = jtt%val(k) / h(i)
          if (col(n) == e_row .and. .not. diag_done) then
            val(n) = val(n) + 1.0_rp
            diag_done = .true.
          end if
        end do
        if (.not. diag_done) then
          n = n + 1
          col(n) = e_row
          val(n) = 1.0_rp
        end if
        ptr(i + 1) = n + 1
      end do
      call f%init(phys%ic%t%map, phys%fc%pd%map, ptr, col(1:n))
      f%val = val(1:n)
    end associate
  end subroutine traction_pressure_factor

  !> Rows of g divided by the diagonal of k (same row space).
  subroutine scale_rows_by_diagonal(k, g)
    type(csr_matrix_t), intent(in) :: k
    type(global_csr_t), intent(inout) :: g
    real(rp), allocatable :: d(:)
    allocate(d(k%n_rows))
    call k%diagonal(d)
    call divide_rows(g, d)
  end subroutine scale_rows_by_diagonal

  !> Free the preconditioner in slot and move p in.
  subroutine replace(slot, p)
    class(precon_t), allocatable, intent(inout) :: slot, p
    call discard(slot)
    call move_alloc(p, slot)
  end subroutine replace

  !> Free the preconditioner in slot, if any, and leave the slot empty.
  subroutine discard(slot)
    class(precon_t), allocatable, intent(inout) :: slot
    if (allocated(slot)) then
      call slot%free()
      deallocate(slot)
    end if
  end subroutine discard

  !> As replace, wrapping p (a preconditioner of -A) as one of A.
  subroutine replace_negated(slot, p)
    class(precon_t), allocatable, intent(inout) :: slot, p
    class(precon_t), allocatable :: w
    allocate(negated_precon_t :: w)
    select type (w)
    type is (negated_precon_t)
      call w%init(p)
    end select
    call replace(slot, w)
  end subroutine replace_negated

  !> The components built by the last set-up, into the set-up lines of sys.
  subroutine add_parts(self, sys)
    class(contact_precon_t), intent(in) :: self
    type(linear_system_t), intent(inout) :: sys
    character(len=8) :: sname
    sname = merge('-S      ', 'S*      ', self%variant == 'classical')
    if (self%p_eliminated) sname = 'S**'
    if (self%t_k > 0.0_rp) call sys%add_part('K: boomeramg', self%t_k, self%m_k)
    if (self%t_smat > 0.0_rp) call sys%add_part(trim(sname)//': product', self%t_smat, self%m_smat)
    if (self%t_sprec > 0.0_rp) call sys%add_part(trim(sname)//': '//trim(self%sprec_name), self%t_sprec, &
                                                 self%m_sprec)
    if (self%t_sp > 0.0_rp) call sys%add_part('S_p: product and precon', self%t_sp, self%m_sp)
    if (self%t_sub > 0.0_rp) call sys%add_part('subspace: L and its AMG', self%t_sub, self%m_sub)
  end subroutine add_parts

  subroutine free(self)
    class(contact_precon_t), intent(inout) :: self
    call self%bp%free()
    call self%s%free()
    if (allocated(self%s_diag)) deallocate(self%s_diag)
    call self%gc1%free()
    call self%sp%free()
    call self%gup%free()
    call self%sub%free()
    call self%lsub%free()
    if (allocated(self%plsub)) then
      call self%plsub%free()
      deallocate(self%plsub)
    end if
    self%ready = .false.
    self%variant = ''
    self%p_eliminated = .false.
    if (allocated(self%built_state)) deallocate(self%built_state)
    self%reused = 0
    self%lagged = 0
  end subroutine free

  !> The view of ctx's composition: its components and blocks.
  function view_of(ctx) result(v)
    type(coupling_t), intent(in), target :: ctx
    type(contact_view_t) :: v
    v%ctx => ctx
    v%sys => ctx%sys
    v%bu = ctx%block('u')
    v%bt = ctx%block('t')
    v%bp = ctx%block('p')
    v%mc => mechanics_of(ctx)
    v%ic => interface_contact_of(ctx)
    v%fc => fracture_flow_of(ctx)
    if (associated(v%fc)) then
      v%flow = .true.
      v%dt = v%fc%dt
    end if
  end function view_of
end module contact_precon
