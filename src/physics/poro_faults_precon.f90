!> The block preconditioner of 'poromechanics_faults' (mechanics u, matrix
!> flow q and pm, interface contact t, fracture flow p), built in the general
!> framework (block_precon.f90) from the contact's preconditioner
!> (contact_precon.f90, its 'reordered' variant with the fracture pressure's
!> second level) and the matrix fluid's parts of 'biot' (biot_precon.f90):
!>
!>   block order  t, u, q, [pm, p]   (the two pressures one group: one S)
!>   S_t  = -H~                       the contact's regular diagonal (exact)
!>   S_u  = BoomerAMG(S*),  S* = K + C1 H~^-1 C2   (the contact's)
!>   S_q  = Jacobi (&solver flux_precon: or BoomerAMG, aFSAI) of A
!>   S_P  = BoomerAMG of the joint pressure
!>          Schur complement of (pm, p), with D_q = ||A(f,:)||_2:
!>     (pm,pm)  P + J + b^2 |c| / K_dr + dt B^T D_q^-1 B      (fixed stress
!>              and scaled Laplacian, as 'biot'; schur = 'algebraic': Q^T
!>              diag(S*)^-1 Q for the per-cell b^2 |c| / K_dr)
!>     (pm,p), (p,pm)  -A_(pm,q) D_q^-1 A_(q,p), -A_(p,q) D_q^-1 A_(q,pm):
!>              the exchange through the fault faces, a two-point
!>              conductance dt / D_q between a fracture element and the cells
!>              on its faces (0 on a sealing face)
!>     (p,p)    the contact's S_p (A_pp - A_pu diag(S*)^-1 B_up for the
!>              total traction) + dt / D_q of the element's open faces
!>   factors  implicit: F(t,u), G(u,t) through S_t; F(u,pm), F(u,p) (B_up),
!>            G(pm,u), G(p,u) through S_u; F(q,pm), F(q,p), G(pm,q), G(p,q)
!>            through S_q; F(t,p) explicit (the total traction, contact).
!>
!> Why the two pressures together: where the exchange is open the fracture
!> element's pressure is the pressure of the matrix faces on it, so after q
!> is eliminated the two pressures form one diffusion problem (matrix cells
!> and fracture elements as the nodes of a graph Laplacian with storage);
!> either pressure eliminated before the other by a diagonal loses the
!> matrix's diffusion around the fracture (a fracture in a permeable matrix
!> sees the matrix through dt / D_q alone) or the fracture's flow along
!> itself. The joint matrix is an M-matrix for BoomerAMG.
!>
!> Set-up: S_q once (A does not change); S_P whenever the contact part is
!> rebuilt (every Newton iteration, or kept with it while every element
!> sticks and dt holds: &contact reuse).
module poro_faults_precon
  use kinds, only: rp, ip, gp, name_len
  use parallel_comm, only: wall_time
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, from_csr, to_csr, gcsr_multiply, gcsr_add, gcsr_stack
  use precon_factory, only: precon_params_t, make_and_setup
  use linear_system, only: linear_system_t
  use physics_component, only: coupling_t
  use matrix_flow_component, only: matrix_flow_component_t, matrix_flow_of
  use contact_precon, only: contact_precon_t
  implicit none
  private

  public :: poro_faults_precon_t

  type :: poro_faults_precon_t
    logical :: ready = .false.
    real(rp), allocatable :: dq(:)               !< D_q: ||A(f,:)||_2 of the owned flux rows
    type(index_map_t), pointer :: jmap => null() !< the joint pressure's rows: owned pm, then owned p
    type(csr_matrix_t) :: sj                     !< S_P, the joint pressure Schur matrix
    character(len=name_len) :: schur = 'fixed_stress', schur_precon = 'boomeramg', flux_precon = 'jacobi'
    character(len=name_len) :: sprec_name = ''
    integer(gp) :: nnz_joint = 0
    real(rp) :: t_q = 0.0_rp, t_smat = 0.0_rp, t_sprec = 0.0_rp   !< seconds of the last set-up's parts
  contains
    procedure :: setup
    procedure :: add_parts
    procedure :: free
  end type poro_faults_precon_t

contains

  !> After cpc%setup (with cpc%joint_pressure) on the same Jacobian: the
  !> matrix fluid's blocks of the framework cpc%bp. schur ('fixed_stress'
  !> or 'algebraic'), schur_precon and flux_precon: the &solver choices;
  !> params: the scalar BoomerAMG settings and the &afsai ones for S_P and
  !> A. Collective.
  subroutine setup(self, cpc, ctx, schur, schur_precon, flux_precon, params, status)
    class(poro_faults_precon_t), intent(inout) :: self
    type(contact_precon_t), intent(inout), target :: cpc
    type(coupling_t), intent(inout), target :: ctx
    character(len=*), intent(in) :: schur, schur_precon, flux_precon
    type(precon_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    integer :: bu, bq, bm, bp
    real(rp) :: t0
    bu = ctx%block('u')
    bq = ctx%block('q')
    bm = ctx%block('pm')
    bp = ctx%block('p')
    self%t_q = 0.0_rp
    self%t_smat = 0.0_rp
    self%t_sprec = 0.0_rp
    if (.not. allocated(cpc%bp%s(bq)%p)) then
      ! a fresh framework (the contact's first set-up): the matrix fluid's parts
      self%schur = schur
      self%schur_precon = schur_precon
      self%flux_precon = flux_precon
      call make_and_setup(flux_precon, cpc%bp%s(bq)%p, ctx%sys%a(bq, bq), params, status)
      if (.not. status%ok()) return
      self%t_q = cpc%bp%s(bq)%p%setup_time
      call row_norms(ctx%sys%a(bq, bq), self%dq)
      call cpc%bp%set_implicit(bu, bm, bu)
      call cpc%bp%set_implicit(bm, bu, bu)
      call cpc%bp%set_implicit(bq, bm, bq)
      call cpc%bp%set_implicit(bq, bp, bq)
      call cpc%bp%set_implicit(bm, bq, bq)
      call cpc%bp%set_implicit(bp, bq, bq)
      call cpc%bp%set_group(bm, bp)
      self%ready = .true.
    end if
    if (.not. cpc%rebuilt .and. allocated(cpc%bp%s(bm)%p)) return
    t0 = wall_time()
    ! the old S_P's preconditioner goes before its matrix
    if (allocated(cpc%bp%s(bm)%p)) then
      call cpc%bp%s(bm)%p%free()
      deallocate(cpc%bp%s(bm)%p)
    end if
    call joint_schur(self, cpc, ctx)
    self%t_smat = wall_time() - t0
    call make_and_setup(self%schur_precon, cpc%bp%s(bm)%p, self%sj, params, status)
    if (.not. status%ok()) return
    self%t_sprec = cpc%bp%s(bm)%p%setup_time
    self%sprec_name = cpc%bp%s(bm)%p%name()
  end subroutine setup

  !> S_P (header) into sj, over jmap. Collective.
  subroutine joint_schur(self, cpc, ctx)
    type(poro_faults_precon_t), intent(inout) :: self
    type(contact_precon_t), intent(in) :: cpc
    type(coupling_t), intent(in) :: ctx
    type(global_csr_t) :: b(2, 2), aq(2), qa(2), prod, tmp, gd
    type(global_csr_t) :: joint
    logical :: has(2, 2)
    integer :: bu, bq, bm, bp, i, j, blk(2)
    bu = ctx%block('u')
    bq = ctx%block('q')
    bm = ctx%block('pm')
    bp = ctx%block('p')
    blk = [bm, bp]
    ! A_(P,q) and D_q^-1 A_(q,P) for P = pm, p
    do i = 1, 2
      call from_csr(ctx%sys%a(blk(i), bq), aq(i))
      call from_csr(ctx%sys%a(bq, blk(i)), qa(i))
      call divide_rows(qa(i), self%dq)
    end do
    call from_csr(ctx%sys%a(bm, bm), b(1, 1))
    call pressure_solid_part(self, cpc, ctx, gd)
    call gcsr_add(1.0_rp, b(1, 1), 1.0_rp, gd, tmp)
    b(1, 1) = tmp
    call from_csr(cpc%sp, b(2, 2))
    do j = 1, 2
      do i = 1, 2
        call gcsr_multiply(aq(i), qa(j), prod)
        if (i == j) then
          call gcsr_add(1.0_rp, b(i, j), -1.0_rp, prod, tmp)
          b(i, j) = tmp
        else
          b(i, j) = prod
          call b(i, j)%scale(-1.0_rp)
        end if
      end do
    end do
    has = .true.
    call gcsr_stack(b, has, joint)
    if (.not. associated(self%jmap)) then
      allocate(self%jmap)
      call self%jmap%init(ctx%mesh%comm, joint%n_rows, [integer(gp) ::])
    end if
    call self%sj%free()
    call to_csr(joint, self%jmap, self%sj)
    self%nnz_joint = self%sj%global_nnz()
  end subroutine joint_schur

  !> The solid's part of the (pm, pm) block: fixed stress, b^2 |c| / K_dr
  !> per cell; 'algebraic', Q^T diag(S*)^-1 Q (A_(pm,u) diag(S*)^-1 A_(u,pm),
  !> negated). Collective.
  subroutine pressure_solid_part(self, cpc, ctx, g)
    type(poro_faults_precon_t), intent(in) :: self
    type(contact_precon_t), intent(in) :: cpc
    type(coupling_t), intent(in) :: ctx
    type(global_csr_t), intent(out) :: g
    type(matrix_flow_component_t), pointer :: mf
    type(global_csr_t) :: gmu, gum
    type(csr_matrix_t) :: d
    real(rp), allocatable :: ds(:)
    integer(ip), allocatable :: ptr(:), col(:)
    integer(ip) :: c, n
    integer :: bu, bm
    bu = ctx%block('u')
    bm = ctx%block('pm')
    if (self%schur == 'algebraic') then
      allocate(ds(cpc%s%n_rows))
      call cpc%s%diagonal(ds)
      call from_csr(ctx%sys%a(bm, bu), gmu)
      call from_csr(ctx%sys%a(bu, bm), gum)
      call divide_rows(gum, ds)
      call gcsr_multiply(gmu, gum, g)
      call g%scale(-1.0_rp)
      return
    end if
    mf => matrix_flow_of(ctx)
    n = mf%pd%n_owned()
    ptr = [(c, c = 1, n + 1)]
    col = [(c, c = 1, n)]
    call d%init(mf%pd%map, mf%pd%map, ptr, col)
    do c = 1, n
      d%val(c) = mf%med%vol(c) * mf%med%biot(ctx%mesh%cell_region(c))**2 / mf%med%kdr(ctx%mesh%cell_region(c))
    end do
    call from_csr(d, g)
    call d%free()
  end subroutine pressure_solid_part

  !> The 2-norms of the owned rows of a.
  subroutine row_norms(a, d)
    type(csr_matrix_t), intent(in) :: a
    real(rp), allocatable, intent(out) :: d(:)
    integer(ip) :: i
    allocate(d(a%n_rows))
    do i = 1, a%n_rows
      d(i) = norm2(a%val(a%row_ptr(i):a%row_ptr(i + 1) - 1))
    end do
  end subroutine row_norms

  !> Rows of g divided by d (owned rows).
  subroutine divide_rows(g, d)
    type(global_csr_t), intent(inout) :: g
    real(rp), intent(in) :: d(:)
    integer(ip) :: i
    do i = 1, g%n_rows
      g%val(g%row_ptr(i):g%row_ptr(i + 1) - 1) = g%val(g%row_ptr(i):g%row_ptr(i + 1) - 1) / d(i)
    end do
  end subroutine divide_rows

  !> The parts built by the last set-up, into the set-up lines of sys.
  subroutine add_parts(self, sys)
    class(poro_faults_precon_t), intent(in) :: self
    type(linear_system_t), intent(inout) :: sys
    if (self%t_q > 0.0_rp) call sys%add_part('A (flux): '//trim(self%flux_precon), self%t_q)
    if (self%t_smat > 0.0_rp) call sys%add_part('S_P (pm, p): product', self%t_smat)
    if (self%t_sprec > 0.0_rp) call sys%add_part('S_P (pm, p): '//trim(self%sprec_name), self%t_sprec)
  end subroutine add_parts

  subroutine free(self)
    class(poro_faults_precon_t), intent(inout) :: self
    call self%sj%free()
    if (associated(self%jmap)) then
      call self%jmap%free()
      deallocate(self%jmap)
    end if
    if (allocated(self%dq)) deallocate(self%dq)
    self%ready = .false.
  end subroutine free
end module poro_faults_precon
