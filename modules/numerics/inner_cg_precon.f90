!> z = A^-1 r by an inner CG (with a preconditioner of A) to a tight relative
!> tolerance: a stand-in for an exact block solve inside a block
!> preconditioner. It is a diagnostic: comparing it with one cycle of the
!> inner preconditioner separates the error of a Schur-complement
!> approximation from that of its multigrid. The result is a nonlinear
!> function of r, so the outer method must be flexible (FGMRES).
!>
!> With steps > 0 (init_steps) it is instead a fixed number of PCG steps
!> from zero, with no residual check: a stronger preconditioner than one
!> cycle of the inner one (steps cycles and steps products with A), still
!> cheap, whose error does not grow with the mesh as one cycle's may (the
!> idea of the K-cycle: Notay, Vassilevski, Numer. Linear Algebra Appl. 15
!> (2008) 473, who put the Krylov steps on the coarse levels; here they
!> are around the whole cycle).
module inner_cg_precon
  use kinds, only: rp, name_len
  use dist_vector, only: pdot
  use error_status, only: error_status_t
  use parallel_comm, only: parallel_comm_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  use boomeramg_precon, only: boomeramg_precon_t
  use cg, only: cg_t
  use krylov, only: solve_info_t
  implicit none
  private

  public :: inner_cg_precon_t

  type, extends(precon_t) :: inner_cg_precon_t
    type(csr_matrix_t), pointer :: a => null()    !< the block (must outlive this); null: products_by_inner
    type(parallel_comm_t) :: comm                 !< the block's communicator
    class(precon_t), allocatable :: inner         !< preconditioner of the inner CG
    type(cg_t) :: solver
    integer :: iterations = 0                     !< inner CG iterations, summed over applications
    integer :: steps = 0                          !< > 0: that many PCG steps, no tolerance
    !> the steps' products with A by the inner BoomerAMG's copy of A (a may
    !> then be absent: boomeramg_precon's setup_rows)
    logical :: products_by_inner = .false.
    real(rp), allocatable :: res(:), w(:), p(:), q(:)   !< work vectors of the steps
    integer :: applications = 0
  contains
    procedure :: init => inner_cg_init
    procedure :: init_steps => inner_cg_init_steps
    procedure :: apply => inner_cg_apply
    procedure :: name => inner_cg_name
    procedure :: free => inner_cg_free
  end type inner_cg_precon_t

contains

  !> Solve with a (pointed to) and inner (moved in, set up on a) to rtol
  !> within max_iter iterations.
  subroutine inner_cg_init(self, a, inner, rtol, max_iter, status)
    class(inner_cg_precon_t), intent(inout) :: self
    type(csr_matrix_t), target, intent(in) :: a
    class(precon_t), allocatable, intent(inout) :: inner
    real(rp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    type(error_status_t), intent(inout) :: status
    call attach(self, inner, a)
    call self%solver%init(a%row_map%comm, rtol, 0.0_rp, max_iter, status)
  end subroutine inner_cg_init

  !> steps (>= 1) PCG steps with a (pointed to) and inner (moved in, set up
  !> on a) from zero at every application. by_inner: the products with A
  !> are the inner BoomerAMG's (its copy of a; a BoomerAMG inner only); a
  !> may then be absent (the matrix was given to the BoomerAMG row by row).
  subroutine inner_cg_init_steps(self, inner, steps, a, by_inner)
    class(inner_cg_precon_t), intent(inout) :: self
    class(precon_t), allocatable, intent(inout) :: inner
    integer, intent(in) :: steps
    type(csr_matrix_t), target, intent(in), optional :: a
    logical, intent(in), optional :: by_inner
    call attach(self, inner, a)
    self%steps = max(steps, 1)
    if (present(by_inner)) self%products_by_inner = by_inner
    if (self%products_by_inner .or. .not. present(a)) then
      select type (m => self%inner)
      type is (boomeramg_precon_t)
        self%products_by_inner = .true.
        self%comm = m%comm
      class default
        error stop 'inner_cg_precon%init_steps: products by the inner preconditioner need a BoomerAMG'
      end select
    end if
    allocate(self%res(0), self%w(0), self%p(0), self%q(0))
  end subroutine inner_cg_init_steps

  !> A fresh start on a (pointed to) with inner (moved in).
  subroutine attach(self, inner, a)
    class(inner_cg_precon_t), intent(inout) :: self
    class(precon_t), allocatable, intent(inout) :: inner
    type(csr_matrix_t), target, intent(in), optional :: a
    call self%free()
    if (present(a)) then
      self%a => a
      self%comm = a%row_map%comm
    end if
    call move_alloc(inner, self%inner)
    self%setup_time = self%inner%setup_time
  end subroutine attach

  !> z = steps PCG steps on A z = r from z = 0: steps applications of the
  !> inner preconditioner and products with A, two reductions a step. A
  !> breakdown (r^T M r or p^T A p not positive: M or A not SPD) ends the
  !> steps with what was made (the first: z = M r, one cycle).
  subroutine apply_steps(self, r, z)
    class(inner_cg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    real(rp) :: rz, rz_old, pq, alpha
    integer :: k
    if (size(self%res) /= size(r)) then
      deallocate(self%res, self%w, self%p, self%q)
      allocate(self%res(size(r)), self%w(size(r)), self%p(size(r)), self%q(size(r)))
    end if
    associate (res => self%res, w => self%w, p => self%p, q => self%q)
    res = r
    z = 0.0_rp
    rz_old = 1.0_rp
    do k = 1, self%steps
      call self%inner%apply(res, w)
      rz = pdot(self%comm, res, w)
      if (.not. (rz > 0.0_rp)) then
        if (k == 1) z = w
        exit
      end if
      if (k == 1) then
        p = w
      else
        p = w + (rz / rz_old) * p
      end if
      call product(self, p, q)
      pq = pdot(self%comm, p, q)
      if (.not. (pq > 0.0_rp)) then
        if (k == 1) z = w
        exit
      end if
      alpha = rz / pq
      z = z + alpha * p
      if (k < self%steps) res = res - alpha * q
      rz_old = rz
      self%iterations = self%iterations + 1
    end do
    end associate
  end subroutine apply_steps

  !> q = A p: a's product, or the inner BoomerAMG's (products_by_inner).
  subroutine product(self, p, q)
    class(inner_cg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: p(:)
    real(rp), intent(out) :: q(:)
    if (self%products_by_inner) then
      select type (m => self%inner)
      type is (boomeramg_precon_t)
        call m%matrix_product(p, q)
      end select
    else
      call self%a%apply(p, q)
    end if
  end subroutine product

  subroutine inner_cg_apply(self, r, z)
    class(inner_cg_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    type(solve_info_t) :: info
    if (self%steps > 0) then
      call apply_steps(self, r, z)
      self%applications = self%applications + 1
      return
    end if
    z = 0.0_rp
    call self%solver%solve(self%a, self%inner, r, z, info)
    self%iterations = self%iterations + info%iterations
    self%applications = self%applications + 1
  end subroutine inner_cg_apply

  function inner_cg_name(self) result(s)
    class(inner_cg_precon_t), intent(in) :: self
    character(len=name_len) :: s
    if (self%steps > 0) then
      write(s, '(a,i0,a)') 'PCG (', self%steps, ' steps) + '//trim(self%inner%name())
    else
      s = 'inner CG + '//trim(self%inner%name())
    end if
  end function inner_cg_name

  subroutine inner_cg_free(self)
    class(inner_cg_precon_t), intent(inout) :: self
    if (allocated(self%inner)) then
      call self%inner%free()
      deallocate(self%inner)
    end if
    self%a => null()
    self%iterations = 0
    self%applications = 0
    self%steps = 0
    self%products_by_inner = .false.
    if (allocated(self%res)) deallocate(self%res, self%w, self%p, self%q)
    self%setup_time = 0.0_rp
  end subroutine inner_cg_free
end module inner_cg_precon
