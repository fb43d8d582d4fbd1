!> The general block preconditioning framework (seed, "General framework"):
!> an n x n block matrix A is brought to block-diagonal form S = G A F by a
!> unit lower block-triangular G and a unit upper block-triangular F, so that
!> A^-1 = F S^-1 G; the preconditioner applies approximations of the three:
!>
!>     z = F~ S~^-1 G~ r, as block substitutions:
!>                          y_i = r_i + sum_{j<i} G(i,j) y_j     (i = 1..n)
!>                          w_i = S_i^-1 y_i
!>                          z_i = w_i + sum_{j>i} F(i,j) z_j     (i = n..1)
!>
!> F(i,j) = -S_i^-1 A_ij and G(i,j) = -A_ij S_j^-1 are the blocks of the
!> unit triangular factors themselves (not of their inverses): applied to
!> the substituted y_j and z_j, they give A^-1 exactly when every S_i is
!> the exact i-th Schur complement, for any number of blocks. (Applied to
!> r_j and w_j, as this module did before the fracture-flow systems, the
!> products of couplings through a middle block, G(p,u) G(u,t) and
!> F(t,u) F(u,p) of the (t, u, p) system, were lost: with exact inner
!> solves GMRES then needed 400 iterations where 77 suffice.) Where the
!> couplings through middle blocks vanish (Biot: A_uq = A_qu = 0; any
!> two-block system) both forms are the same.
!> Every off-diagonal factor block here has its own approximation:
!>   explicit : a sparse matrix times a scale (block aFSAI of K^-1 Q, or
!>              -gamma F^T for G), applied by a product;
!>   implicit : a product with the coupling block and an inner preconditioner,
!>              F(i,j) x = -M (A_ij x) with M ~ A_ii^-1, G(i,j) x = -A_ij (M x)
!>              with M ~ A_jj^-1 (A_ij, or a coupling matrix the physics
!>              gives in its place: the block as an earlier elimination or
!>              change of unknowns left it); M is the diagonal preconditioner S_i (S_j)
!>              of the framework or a preconditioner of the factor's own
!>              (e.g. Jacobi, which makes the cheap lower factor of ldu_cheap);
!> and every S_i^-1 is any precon_t: AMG or aFSAI of a diagonal block, or of
!> a Schur complement given by the physics (fixed stress, scaled Laplacian)
!> or computed here explicitly, S_n = A_nn - sum_i G(n,i) A_ii F(i,n) with
!> G(n,i) = -c_i F(i,n)^T (symmetric couplings A_ni = -c_i A_in^T, as the
!> Biot rows with c = 1 and gamma): S_n = A_nn + sum_i c_i F_i^T A_ii F_i.
!>
!> Where all factors F(i,.) of a row are implicit with S_i as their inner
!> preconditioner, the framework fuses
!> w_i + sum_j F(i,j) z_j = S_i^-1 (y_i - sum_j A_ij z_j), so that S_i is
!> applied once; likewise S_j y_j computed for G(i,j) is reused for w_j.
!> Consecutive blocks i..k may share one S (set_group): S_i^-1 then
!> approximates the inverse of the Schur complement of the blocks i..k
!> together, applied to their concatenated part of the block vector (the
!> fields that one Schur complement couples too tightly to be split, as the
!> matrix and fracture pressures of 'poromechanics_faults'); no factor
!> couples blocks of a group.
!> The Biot (u, q, p) system uses this module now; the contact systems (u, t)
!> and (u, t, p_f) are the same framework with other blocks and choices.
module block_precon
  use kinds, only: rp, ip, gp, name_len
  use precon, only: precon_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  implicit none
  private

  public :: block_precon_t, precon_box_t, block_factor_t
  public :: factor_none, factor_explicit, factor_implicit

  integer, parameter :: factor_none = 0, factor_explicit = 1, factor_implicit = 2

  !> A polymorphic preconditioner in a box (arrays of class(...) need one).
  type :: precon_box_t
    class(precon_t), allocatable :: p
  end type precon_box_t

  !> One off-diagonal block of F or G.
  type :: block_factor_t
    integer :: kind = factor_none
    type(csr_matrix_t) :: m                  !< explicit: the block (rows of block i, columns of block j)
    real(rp) :: alpha = 1.0_rp               !< explicit: the block is alpha * m
    integer :: inner = 0                     !< implicit: use the framework's S_inner; 0: use own
    logical :: own_coupling = .false.        !< implicit: coupling in place of A_ij
    type(csr_matrix_t) :: coupling           !< implicit: the coupling when own_coupling
    class(precon_t), allocatable :: own      !< implicit: the inner preconditioner when inner = 0
  end type block_factor_t

  type, extends(precon_t) :: block_precon_t
    character(len=name_len) :: label = 'block'
    type(block_matrix_t), pointer :: a => null()
    integer :: nb = 0
    type(precon_box_t), allocatable :: s(:)          !< (nb) S_i^-1
    type(block_factor_t), allocatable :: f(:,:)      !< (nb, nb) F(i,j), i < j
    type(block_factor_t), allocatable :: g(:,:)      !< (nb, nb) G(i,j), i > j
    real(rp), allocatable :: y(:), w(:), t(:), u(:)  !< work block vectors
    logical, allocatable :: fused(:), cached(:)
    integer, allocatable :: group_first(:), group_last(:)  !< the group of each block (itself alone)
    integer :: n_apply = 0
  contains
    procedure :: init
    procedure :: set_explicit
    procedure :: set_implicit
    procedure :: set_group
    procedure :: apply => bp_apply
    procedure :: name => bp_name
    procedure :: nnz_explicit
    procedure :: free => bp_free
  end type block_precon_t

contains

  !> Attach the block matrix (kept by pointer) with every factor absent; the
  !> caller then sets up s(1..nb) and the factors it wants. label names the
  !> configuration in logs.
  subroutine init(self, a, label)
    class(block_precon_t), intent(inout) :: self
    type(block_matrix_t), intent(in), target :: a
    character(len=*), intent(in) :: label
    integer :: n, i
    call self%free()
    self%a => a
    self%label = label
    n = a%nb
    self%nb = n
    allocate(self%s(n), self%f(n, n), self%g(n, n), self%fused(n), self%cached(n))
    self%group_first = [(i, i = 1, n)]
    self%group_last = self%group_first
    allocate(self%y(a%offset(n + 1)), self%w(a%offset(n + 1)), self%t(a%offset(n + 1)), self%u(a%offset(n + 1)))
  end subroutine init

  !> Make block (i, j) of F (i < j) or G (i > j) explicit: alpha * m, where m
  !> is moved in (the caller's m is left empty). A block already explicit
  !> with the same matrix may only change alpha: pass no m.
  subroutine set_explicit(self, i, j, alpha, m)
    class(block_precon_t), intent(inout) :: self
    integer, intent(in) :: i, j
    real(rp), intent(in) :: alpha
    type(csr_matrix_t), intent(inout), optional :: m
    if (i == j) error stop 'block_precon%set_explicit: factor blocks are off the diagonal'
    if (i < j) then
      call put(self%f(i, j))
    else
      call put(self%g(i, j))
    end if
  contains
    subroutine put(b)
      type(block_factor_t), intent(inout) :: b
      if (present(m)) then
        call b%m%free()
        call move_csr(m, b%m)
      else if (b%kind /= factor_explicit) then
        error stop 'block_precon%set_explicit: no matrix given for a new explicit block'
      end if
      b%kind = factor_explicit
      b%alpha = alpha
    end subroutine put
  end subroutine set_explicit

  !> Make block (i, j) of F (i < j) or G (i > j) implicit, with the
  !> framework's S_inner as inner preconditioner (inner > 0), or with own
  !> (moved in) when inner = 0. S_inner must be the preconditioner of the
  !> block the factor inverts: inner = i for F(i,j), inner = j for G(i,j).
  !> coupling (moved in): the matrix used in place of A_ij (rows of block i,
  !> columns of block j); without it the factor uses A_ij.
  subroutine set_implicit(self, i, j, inner, own, coupling)
    class(block_precon_t), intent(inout) :: self
    integer, intent(in) :: i, j, inner
    class(precon_t), allocatable, intent(inout), optional :: own
    type(csr_matrix_t), intent(inout), optional :: coupling
    if (i == j) error stop 'block_precon%set_implicit: factor blocks are off the diagonal'
    ! the inner preconditioner of F(i,j) approximates A_ii^-1, that of G(i,j) A_jj^-1
    if (inner /= 0 .and. inner /= min(i, j)) error stop 'block_precon%set_implicit: inner must be 0 or min(i, j)'
    if (i < j) then
      call put(self%f(i, j))
    else
      call put(self%g(i, j))
    end if
  contains
    subroutine put(b)
      type(block_factor_t), intent(inout) :: b
      b%kind = factor_implicit
      b%inner = inner
      call b%coupling%free()
      b%own_coupling = present(coupling)
      if (present(coupling)) call move_csr(coupling, b%coupling)
      if (inner == 0) then
        if (.not. present(own)) error stop 'block_precon%set_implicit: inner = 0 needs own'
        call move_alloc(own, b%own)
      end if
    end subroutine put
  end subroutine set_implicit

  !> Blocks first..last share S_first (set by the caller): the
  !> preconditioner of their Schur complement together, applied to their
  !> concatenated part of the block vector. No factor may couple two blocks
  !> of the group, nor use S of a block in it as an inner preconditioner.
  subroutine set_group(self, first, last)
    class(block_precon_t), intent(inout) :: self
    integer, intent(in) :: first, last
    integer :: i, j
    if (first >= last) error stop 'block_precon%set_group: a group has at least two blocks'
    do i = first, last
      do j = first, last
        if (i < j) then
          if (self%f(i, j)%kind /= factor_none) error stop 'block_precon%set_group: a factor inside the group'
        else if (i > j) then
          if (self%g(i, j)%kind /= factor_none) error stop 'block_precon%set_group: a factor inside the group'
        end if
      end do
      self%group_first(i) = first
      self%group_last(i) = last
    end do
  end subroutine set_group

  !> Move the arrays of a csr_matrix_t (pointers to maps are copied; an owned
  !> column map changes hands).
  subroutine move_csr(src, dst)
    type(csr_matrix_t), intent(inout) :: src, dst
    dst%row_map => src%row_map
    dst%col_map => src%col_map
    dst%owned_col_map => src%owned_col_map
    src%owned_col_map => null()
    dst%n_rows = src%n_rows
    call move_alloc(src%row_ptr, dst%row_ptr)
    call move_alloc(src%col, dst%col)
    call move_alloc(src%val, dst%val)
    call move_alloc(src%x_ext, dst%x_ext)
    call move_alloc(src%stash_row, dst%stash_row)
    call move_alloc(src%stash_col, dst%stash_col)
    call move_alloc(src%stash_val, dst%stash_val)
    call src%free()
  end subroutine move_csr

  !> Decide which rows are fused and which S_i r_i can be reused (see the
  !> module header). Cheap; done at every application so that factors may
  !> change between applications.
  subroutine plan(self)
    type(block_precon_t), intent(inout) :: self
    integer :: i, j, n
    logical :: any_f
    n = self%nb
    do i = 1, n
      any_f = .false.
      self%fused(i) = .true.
      do j = i + 1, n
        if (self%f(i, j)%kind == factor_none) cycle
        any_f = .true.
        if (self%f(i, j)%kind /= factor_implicit .or. self%f(i, j)%inner /= i) self%fused(i) = .false.
      end do
      if (.not. any_f .or. self%group_first(i) /= self%group_last(i)) self%fused(i) = .false.
    end do
  end subroutine plan

  subroutine bp_apply(self, r, z)
    class(block_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer :: i, j, n
    integer(ip) :: a0, a1, b0, b1
    n = self%nb
    self%n_apply = self%n_apply + 1
    call plan(self)
    self%cached = .false.
    ! forward substitution: y_i = r_i + sum_{j<i} G(i,j) y_j
    do i = 1, n
      call self%a%block_range(i, a0, a1)
      self%y(a0:a1) = r(a0:a1)
      do j = 1, i - 1
        if (self%g(i, j)%kind == factor_none) cycle
        call self%a%block_range(j, b0, b1)
        call g_times(self, i, j, self%y(b0:b1), self%t(a0:a1))
        self%y(a0:a1) = self%y(a0:a1) + self%t(a0:a1)
      end do
    end do
    ! back substitution: w_i = S_i^-1 y_i, z_i = w_i + sum_{j>i} F(i,j) z_j
    do i = n, 1, -1
      call self%a%block_range(i, a0, a1)
      if (self%fused(i)) then
        self%t(a0:a1) = self%y(a0:a1)
        do j = i + 1, n
          if (self%f(i, j)%kind == factor_none) cycle
          call self%a%block_range(j, b0, b1)
          call coupling_times(self, i, j, z(b0:b1), self%u(a0:a1))
          self%t(a0:a1) = self%t(a0:a1) - self%u(a0:a1)
        end do
        call self%s(i)%p%apply(self%t(a0:a1), z(a0:a1))
        cycle
      end if
      if (self%group_last(i) == i .and. self%group_first(i) < i) then
        ! the group's S over its blocks' concatenated part: every w_k at once
        call self%a%block_range(self%group_first(i), b0, b1)
        call self%s(self%group_first(i))%p%apply(self%y(b0:a1), self%w(b0:a1))
        self%cached(self%group_first(i):i) = .true.
      end if
      ! w_i = S_i^-1 y_i may be left by a G(., i) with S_i inside
      if (.not. self%cached(i)) call self%s(i)%p%apply(self%y(a0:a1), self%w(a0:a1))
      z(a0:a1) = self%w(a0:a1)
      do j = i + 1, n
        if (self%f(i, j)%kind == factor_none) cycle
        call self%a%block_range(j, b0, b1)
        call f_times(self, i, j, z(b0:b1), self%t(a0:a1))
        z(a0:a1) = z(a0:a1) + self%t(a0:a1)
      end do
    end do
  end subroutine bp_apply

  !> yi = G(i,j) xj (i > j). An implicit block with S_j inside leaves
  !> S_j xj in w_j for reuse (xj = y_j there).
  subroutine g_times(self, i, j, xj, yi)
    type(block_precon_t), intent(inout) :: self
    integer, intent(in) :: i, j
    real(rp), intent(in) :: xj(:)
    real(rp), intent(out) :: yi(:)
    integer(ip) :: b0, b1
    associate (b => self%g(i, j))
      if (b%kind == factor_explicit) then
        call b%m%apply(xj, yi)
        yi = b%alpha * yi
      else
        call self%a%block_range(j, b0, b1)
        if (b%inner > 0) then
          if (.not. self%cached(j)) call self%s(b%inner)%p%apply(xj, self%w(b0:b1))
          self%cached(j) = .true.
          call coupling_times(self, i, j, self%w(b0:b1), yi)
        else
          call b%own%apply(xj, self%u(b0:b1))
          call coupling_times(self, i, j, self%u(b0:b1), yi)
        end if
        yi = -yi
      end if
    end associate
  end subroutine g_times

  !> yi = F(i,j) xj (i < j).
  subroutine f_times(self, i, j, xj, yi)
    type(block_precon_t), intent(inout) :: self
    integer, intent(in) :: i, j
    real(rp), intent(in) :: xj(:)
    real(rp), intent(out) :: yi(:)
    integer(ip) :: a0, a1
    associate (b => self%f(i, j))
      if (b%kind == factor_explicit) then
        call b%m%apply(xj, yi)
        yi = b%alpha * yi
      else
        call self%a%block_range(i, a0, a1)
        call coupling_times(self, i, j, xj, self%u(a0:a1))
        if (b%inner > 0) then
          call self%s(b%inner)%p%apply(self%u(a0:a1), yi)
        else
          call b%own%apply(self%u(a0:a1), yi)
        end if
        yi = -yi
      end if
    end associate
  end subroutine f_times

  !> yi = B xj with B the coupling of the implicit factor (i, j) (F for
  !> i < j, G for i > j): its own or A_ij.
  subroutine coupling_times(self, i, j, xj, yi)
    type(block_precon_t), intent(inout), target :: self
    integer, intent(in) :: i, j
    real(rp), intent(in) :: xj(:)
    real(rp), intent(out) :: yi(:)
    type(block_factor_t), pointer :: b
    if (i < j) then
      b => self%f(i, j)
    else
      b => self%g(i, j)
    end if
    if (b%own_coupling) then
      call b%coupling%apply(xj, yi)
    else
      call self%a%apply_block(i, j, xj, yi)
    end if
  end subroutine coupling_times

  function bp_name(self) result(s)
    class(block_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = self%label
  end function bp_name

  !> Global non-zeros of the explicit factor blocks (each F block counted;
  !> G blocks that are scaled transposes of F blocks are the caller's to
  !> count or not). Collective.
  integer(gp) function nnz_explicit(self, which)
    class(block_precon_t), intent(in) :: self
    character(len=1), intent(in) :: which      !< 'F' or 'G'
    integer :: i, j
    nnz_explicit = 0
    do j = 1, self%nb
      do i = 1, self%nb
        if (which == 'F' .and. i < j) then
          if (self%f(i, j)%kind == factor_explicit) nnz_explicit = nnz_explicit + self%f(i, j)%m%global_nnz()
        else if (which == 'G' .and. i > j) then
          if (self%g(i, j)%kind == factor_explicit) nnz_explicit = nnz_explicit + self%g(i, j)%m%global_nnz()
        end if
      end do
    end do
  end function nnz_explicit

  subroutine bp_free(self)
    class(block_precon_t), intent(inout) :: self
    integer :: i, j
    if (allocated(self%s)) then
      do i = 1, size(self%s)
        if (allocated(self%s(i)%p)) call self%s(i)%p%free()
      end do
      deallocate(self%s)
    end if
    if (allocated(self%f)) then
      do j = 1, size(self%f, 2)
        do i = 1, size(self%f, 1)
          call free_factor(self%f(i, j))
          call free_factor(self%g(i, j))
        end do
      end do
      deallocate(self%f, self%g)
    end if
    if (allocated(self%y)) deallocate(self%y, self%w, self%t, self%u, self%fused, self%cached)
    if (allocated(self%group_first)) deallocate(self%group_first, self%group_last)
    self%a => null()
    self%nb = 0
    self%n_apply = 0
  contains
    subroutine free_factor(b)
      type(block_factor_t), intent(inout) :: b
      call b%m%free()
      call b%coupling%free()
      b%own_coupling = .false.
      if (allocated(b%own)) then
        call b%own%free()
        deallocate(b%own)
      end if
      b%kind = factor_none
    end subroutine free_factor
  end subroutine bp_free
end module block_precon
