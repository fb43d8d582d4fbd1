!> The block preconditioner of the three-field Biot system, built in the
!> general framework (block_precon.f90) from the &solver choices:
!>
!>   S_1 ~ K^-1   : BoomerAMG or aFSAI;   S_2 ~ A^-1 : Jacobi, BoomerAMG or aFSAI
!>   S_3 ~ Schur^-1 (BoomerAMG or aFSAI) of
!>       fixed stress / algebraic + scaled Laplacian (physics-based), or the
!>       explicit P + F1^T K F1 + gamma F2^T A F2 (seed, "Approximate inverses")
!>   F(1,3) ~ K^-1 Q, F(2,3) ~ A^-1 B and G(3,1) = -F(1,3)^T,
!>   G(3,2) = -gamma F(2,3)^T: implicit (products with Q, B and S_1, S_2, or
!>   Jacobi in G for ldu_cheap) or explicit (block aFSAI).
!>
!> Set-up is split as in the seed: setup_fixed() is the gamma-independent
!> part T_p1 (S_1, S_2, the explicit factors and the products F^T K F,
!> F^T A F), done once; setup_dt() the gamma-dependent part T_p2 (the Schur
!> matrix and its preconditioner, the scale of G(3,2)), redone when dt
!> changes. Ordering keys of the unknowns (original mesh ids) make the
!> explicit factors independent of the number of ranks.
module biot_precon
  use kinds, only: rp, ip, gp, name_len
  use parallel_comm, only: wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, from_csr, to_csr, gcsr_transpose, gcsr_multiply, gcsr_add, drop_small
  use amg_params, only: amg_params_t
  use precon, only: precon_t
  use jacobi_precon, only: jacobi_precon_t
  use precon_factory, only: precon_params_t, make_and_setup, stored_nnz
  use linear_system, only: linear_system_t
  use fsai_params, only: fsai_params_t
  use block_fsai, only: decoupling_factor
  use block_precon, only: block_precon_t
  use dist_mesh, only: dist_mesh_t
  use poromechanics, only: poromechanics_t, iu, iq, ipr
  use solver_config, only: solver_config_t
  use fsai_config, only: fsai_config_t
  implicit none
  private

  public :: biot_precon_t

  type :: biot_precon_t
    type(block_precon_t) :: bp
    type(csr_matrix_t) :: s                      !< the Schur matrix given to S_3
    type(global_csr_t) :: hk, ha                 !< explicit: F1^T K F1 and F2^T A F2
    integer(gp), allocatable :: key_u(:), key_q(:), key_p(:)
    character(len=name_len) :: schur = 'fixed_stress', schur_precon = 'boomeramg', mode = 'ldu_cheap'
    logical :: explicit = .false.
    type(amg_params_t) :: amg_s
    type(fsai_params_t) :: fsai
    real(rp) :: schur_drop = 0.0_rp
    real(rp) :: t_p1 = 0.0_rp, t_p2 = 0.0_rp       !< seconds of the last set-up of each part
    !> its components: the preconditioners of K and A, the explicit factors,
    !> the Schur matrix and its preconditioner; fresh_*: built since the
    !> caller last took them (add_parts)
    real(rp) :: t_u = 0.0_rp, t_q = 0.0_rp, t_factors = 0.0_rp, t_smat = 0.0_rp, t_sprec = 0.0_rp
    logical :: fresh_fixed = .false., fresh_dt = .false.
    real(rp) :: resid_f(2) = 0.0_rp               !< ||K F1 - Q|| / ||Q||, ||A F2 - B|| / ||B|| (Frobenius)
    integer(gp) :: nnz_matrix = 0                 !< non-zeros of the block matrix
    integer(gp) :: nnz_fixed = 0, nnz_dt = 0      !< stored non-zeros of the preconditioner (T_p1, T_p2 parts)
  contains
    procedure :: setup_fixed
    procedure :: setup_dt
    procedure :: density
    procedure :: add_parts
    procedure :: free
  end type biot_precon_t

contains

  !> The gamma-independent part (T_p1): diagonal preconditioners of K and A,
  !> the factor blocks and, for the explicit Schur complement, F^T K F and
  !> F^T A F. Call after the first assembly. Collective.
  subroutine setup_fixed(self, phys, mesh, scfg, fcfg, amg, amg_s, status)
    class(biot_precon_t), intent(inout), target :: self
    type(poromechanics_t), intent(inout), target :: phys
    type(dist_mesh_t), intent(in) :: mesh
    type(solver_config_t), intent(in) :: scfg
    type(fsai_config_t), intent(in) :: fcfg
    type(amg_params_t), intent(in) :: amg, amg_s
    type(error_status_t), intent(inout) :: status
    class(precon_t), allocatable :: own
    type(global_csr_t) :: gk, ga, gq, gb, f1, f2, f1t, f2t, tmp
    type(csr_matrix_t) :: m
    real(rp) :: t0, t1
    integer :: i, j

    t0 = wall_time()
    call self%free()
    self%mode = scfg%block_mode
    self%schur = scfg%schur
    self%schur_precon = scfg%schur_precon
    self%explicit = scfg%decoupling == 'explicit'
    self%amg_s = amg_s
    self%fsai = fcfg%precon
    self%schur_drop = fcfg%schur_drop
    call make_keys(self, phys, mesh)
    call self%bp%init(phys%sys, 'block-'//trim(scfg%decoupling)//'-'//trim(scfg%block_mode))

    call diagonal_precon(self, iu, phys%sys%a(iu, iu), scfg%k_precon, amg, self%key_u, status)
    if (status%ok()) call diagonal_precon(self, iq, phys%sys%a(iq, iq), scfg%flux_precon, amg_s, self%key_q, status)
    if (.not. status%ok()) return
    self%t_u = self%bp%s(iu)%p%setup_time
    self%t_q = self%bp%s(iq)%p%setup_time
    t1 = wall_time()

    if (.not. self%explicit) then
      do i = 1, 2
        if (self%mode == 'ldu_cheap') then
          allocate(jacobi_precon_t :: own)
          select type (own)
          type is (jacobi_precon_t)
            call own%setup(phys%sys%a(i, i), status)
          end select
          call self%bp%set_implicit(ipr, i, 0, own)
          call self%bp%set_implicit(i, ipr, i)
        else
          if (self%mode == 'ldu' .or. self%mode == 'lower') call self%bp%set_implicit(ipr, i, i)
          if (self%mode == 'ldu' .or. self%mode == 'upper') call self%bp%set_implicit(i, ipr, i)
        end if
      end do
    else
      ! F1 ~ K^-1 Q and F2 ~ A^-1 B (Q = -A_13, B = -A_23), column by column
      call from_csr(phys%sys%a(iu, iu), gk)
      call gk%set_keys(self%key_u)
      call from_csr(phys%sys%a(iu, ipr), gq)
      call gq%scale(-1.0_rp)
      call decoupling_factor(gk, gq, fcfg%factor, f1, status, self%resid_f(1))
      if (.not. status%ok()) return
      call from_csr(phys%sys%a(iq, iq), ga)
      call ga%set_keys(self%key_q)
      call from_csr(phys%sys%a(iq, ipr), gb)
      call gb%scale(-1.0_rp)
      call decoupling_factor(ga, gb, fcfg%factor, f2, status, self%resid_f(2))
      if (.not. status%ok()) return
      call gcsr_transpose(f1, f1t)
      call gcsr_transpose(f2, f2t)
      if (self%schur == 'explicit') then
        call gcsr_multiply(gk, f1, tmp)
        call gcsr_multiply(f1t, tmp, self%hk)
        call gcsr_multiply(ga, f2, tmp)
        call gcsr_multiply(f2t, tmp, self%ha)
      end if
      if (self%mode == 'ldu' .or. self%mode == 'upper') then
        call to_csr(f1, phys%mech%u%map, m)
        call self%bp%set_explicit(iu, ipr, 1.0_rp, m)
        call to_csr(f2, phys%qd%map, m)
        call self%bp%set_explicit(iq, ipr, 1.0_rp, m)
      end if
      if (self%mode == 'ldu' .or. self%mode == 'lower') then
        call to_csr(f1t, phys%pd%map, m)
        call self%bp%set_explicit(ipr, iu, -1.0_rp, m)
        call to_csr(f2t, phys%pd%map, m)
        call self%bp%set_explicit(ipr, iq, 0.0_rp, m)       ! -gamma, set by setup_dt
      end if
    end if

    self%t_factors = wall_time() - t1
    self%nnz_matrix = 0
    do j = 1, 3
      do i = 1, 3
        if (phys%sys%has(i, j)) self%nnz_matrix = self%nnz_matrix + phys%sys%a(i, j)%global_nnz()
      end do
    end do
    self%nnz_fixed = self%bp%nnz_explicit('F') + stored_nnz(self%bp%s(iu)%p) + stored_nnz(self%bp%s(iq)%p)
    if (self%mode == 'lower') self%nnz_fixed = self%nnz_fixed + self%bp%nnz_explicit('G')
    self%t_p1 = wall_time() - t0
    self%fresh_fixed = .true.
  end subroutine setup_fixed

  !> S_i for a diagonal block: the preconditioner called which (the deck
  !> allows 'boomeramg', 'jacobi', 'afsai'), with settings amg and the &afsai
  !> ones, ordering keys key.
  subroutine diagonal_precon(self, i, a, which, amg, key, status)
    type(biot_precon_t), intent(inout) :: self
    integer, intent(in) :: i
    type(csr_matrix_t), intent(in), target :: a
    character(len=*), intent(in) :: which
    type(amg_params_t), intent(in) :: amg
    integer(gp), intent(in) :: key(:)
    type(error_status_t), intent(inout) :: status
    type(precon_params_t) :: params
    params%amg = amg
    params%fsai = self%fsai
    call make_and_setup(which, self%bp%s(i)%p, a, params, status, keys=key)
  end subroutine diagonal_precon

  !> The gamma-dependent part (T_p2) for the step size dt (gamma = dt; 0 in
  !> the undrained step): the Schur matrix and its preconditioner, and the
  !> scale of G(3,2). Call after the assembly of a step whose dt differs from
  !> the last. Collective.
  subroutine setup_dt(self, phys, mesh, dt, status)
    class(biot_precon_t), intent(inout), target :: self
    type(poromechanics_t), intent(inout), target :: phys
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: dt
    type(error_status_t), intent(inout) :: status
    type(global_csr_t) :: gp_, t1, t2
    real(rp) :: t0
    t0 = wall_time()
    select case (self%schur)
    case ('explicit')
      call from_csr(phys%sys%a(ipr, ipr), gp_)
      call gcsr_add(1.0_rp, gp_, 1.0_rp, self%hk, t1)
      call gcsr_add(1.0_rp, t1, dt, self%ha, t2)
      call drop_small(t2, self%schur_drop)
      call t2%set_keys(self%key_p)
      call self%s%free()
      call to_csr(t2, phys%pd%map, self%s)
    case ('algebraic')
      call phys%algebraic_schur(mesh, dt, self%s)
    case default
      call phys%fixed_stress_schur(mesh, dt, self%s)
    end select
    self%t_smat = wall_time() - t0
    call diagonal_precon(self, ipr, self%s, self%schur_precon, self%amg_s, self%key_p, status)
    if (status%ok()) self%t_sprec = self%bp%s(ipr)%p%setup_time
    if (self%explicit .and. (self%mode == 'ldu' .or. self%mode == 'lower')) call self%bp%set_explicit(ipr, iq, -dt)
    self%nnz_dt = stored_nnz(self%bp%s(ipr)%p)
    if (self%schur == 'explicit') self%nnz_dt = self%nnz_dt + self%s%global_nnz()
    self%t_p2 = wall_time() - t0
    self%fresh_dt = .true.
  end subroutine setup_dt

  !> The components built since the last call, into the set-up lines of sys.
  subroutine add_parts(self, sys)
    class(biot_precon_t), intent(inout) :: self
    type(linear_system_t), intent(inout) :: sys
    if (self%fresh_fixed) then
      call sys%add_part('K: '//trim(self%bp%s(iu)%p%name()), self%t_u, self%bp%s(iu)%p%setup_rise)
      call sys%add_part('A (flux): '//trim(self%bp%s(iq)%p%name()), self%t_q, self%bp%s(iq)%p%setup_rise)
      if (self%explicit) call sys%add_part('decoupling factors (aFSAI)', self%t_factors)
    end if
    if (self%fresh_dt) then
      call sys%add_part('Schur matrix ('//trim(self%schur)//')', self%t_smat)
      call sys%add_part('Schur: '//trim(self%bp%s(ipr)%p%name()), self%t_sprec, self%bp%s(ipr)%p%setup_rise)
    end if
    self%fresh_fixed = .false.
    self%fresh_dt = .false.
  end subroutine add_parts

  !> Density mu of the seed's tables: stored non-zeros of the preconditioner
  !> (explicit factor blocks F, aFSAI factors, the explicit Schur matrix;
  !> not the AMG hierarchies) over the non-zeros of the block matrix.
  real(rp) function density(self)
    class(biot_precon_t), intent(in) :: self
    density = real(self%nnz_fixed + self%nnz_dt, rp) / real(max(self%nnz_matrix, 1_gp), rp)
  end function density

  !> Partition-independent keys of the owned unknowns: 3 (node - 1) + c for
  !> displacements, the original face and cell ids for fluxes and pressures.
  subroutine make_keys(self, phys, mesh)
    type(biot_precon_t), intent(inout) :: self
    type(poromechanics_t), intent(in) :: phys
    type(dist_mesh_t), intent(in) :: mesh
    call mesh%node_keys(3, self%key_u)
    self%key_q = mesh%face_orig(1:mesh%face_map%n_owned)
    self%key_p = mesh%cell_orig(1:mesh%cell_map%n_owned)
    if (size(self%key_q) /= phys%qd%n_owned() .or. size(self%key_p) /= phys%pd%n_owned()) &
      error stop 'biot_precon: the dof maps do not follow the mesh entities'
  end subroutine make_keys

  subroutine free(self)
    class(biot_precon_t), intent(inout) :: self
    call self%bp%free()
    call self%s%free()
    call self%hk%free()
    call self%ha%free()
    if (allocated(self%key_u)) deallocate(self%key_u)
    if (allocated(self%key_q)) deallocate(self%key_q)
    if (allocated(self%key_p)) deallocate(self%key_p)
  end subroutine free
end module biot_precon
