!> Block preconditioner for "arrow" block systems: the leading blocks
!> 1..n-1 are coupled only through the last block,
!>
!>     [ A11          A1n ]
!>     [      ...     ... ]
!>     [ An1  ...     Ann ],
!>
!> as the three-field Biot system (u, q, p) and the contact system (u, t) are.
!> The block LDU factorization gives, with M_i ~ A_ii^-1 and S^-1 ~ the
!> inverse of the Schur complement S = Ann - sum_i An_i A_ii^-1 A_in:
!>   lower : z_i = M_i r_i;  z_n = S^-1 (r_n - sum_i An_i z_i)
!>   upper : z_n = S^-1 r_n; z_i = M_i (r_i - A_in z_n)
!>   ldu   : lower, then z_i <- z_i - M_i (A_in z_n)
!>   diagonal: z_i = M_i r_i; z_n = S^-1 r_n
!>   ldu_cheap: z_n = S^-1 (r_n - sum_i An_i L_i r_i); z_i = M_i (r_i - A_in z_n)
!>           with a cheap L_i ~ A_ii^-1 (e.g. Jacobi) in the lower factor only,
!>           so that each M_i (e.g. an AMG cycle) is applied once per iteration
!> The sub-preconditioners (BoomerAMG, Jacobi, MUMPS, aFSAI, ...) are any
!> precon_t; the Schur approximation is built by the physics (e.g. fixed
!> stress + scaled Laplacian) and handed over as a preconditioner of S.
!> This is the implicit variant of the general framework of the seed: the
!> decoupling factors F and G are applied as products with the coupling
!> blocks and the inner preconditioners.
module schur_block_precon
  use kinds, only: rp, ip, name_len
  use precon, only: precon_t
  use block_matrix, only: block_matrix_t
  implicit none
  private

  public :: schur_block_precon_t, precon_box_t

  !> A polymorphic preconditioner in a box (arrays of class(...) need one).
  type :: precon_box_t
    class(precon_t), allocatable :: p
  end type precon_box_t

  type, extends(precon_t) :: schur_block_precon_t
    character(len=16) :: mode = 'ldu'            !< diagonal | lower | upper | ldu
    type(block_matrix_t), pointer :: a => null()
    type(precon_box_t), allocatable :: sub(:)    !< (n): sub(n) approximates S^-1
    type(precon_box_t), allocatable :: lower(:)  !< (n-1): the cheap L_i of ldu_cheap
    real(rp), allocatable :: t(:), y(:)
    integer :: n_apply = 0
  contains
    procedure :: init
    procedure :: apply => sbp_apply
    procedure :: name => sbp_name
    procedure :: free => sbp_free
  end type schur_block_precon_t

contains

  !> Attach the block matrix (kept by pointer) and the mode; the caller then
  !> allocates and sets up sub(1..n).
  subroutine init(self, a, mode)
    class(schur_block_precon_t), intent(inout) :: self
    type(block_matrix_t), intent(in), target :: a
    character(len=*), intent(in) :: mode
    self%a => a
    self%mode = mode
    if (allocated(self%sub)) deallocate(self%sub)
    allocate(self%sub(a%nb))
    if (allocated(self%lower)) deallocate(self%lower)
    allocate(self%lower(a%nb))
    if (allocated(self%t)) deallocate(self%t, self%y)
    allocate(self%t(a%offset(a%nb + 1)), self%y(a%offset(a%nb + 1)))
  end subroutine init

  subroutine sbp_apply(self, r, z)
    class(schur_block_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    integer :: i, n
    integer(ip) :: a0, a1, n0, n1
    n = self%a%nb
    self%n_apply = self%n_apply + 1
    call self%a%block_range(n, n0, n1)
    select case (self%mode)
    case ('diagonal')
      do i = 1, n
        call self%a%block_range(i, a0, a1)
        call self%sub(i)%p%apply(r(a0:a1), z(a0:a1))
      end do
    case ('ldu_cheap')
      self%y(n0:n1) = r(n0:n1)
      do i = 1, n - 1
        call self%a%block_range(i, a0, a1)
        call self%lower(i)%p%apply(r(a0:a1), self%t(a0:a1))
        call self%a%apply_block(n, i, self%t(a0:a1), z(n0:n1))    ! z_n is free until S is applied
        self%y(n0:n1) = self%y(n0:n1) - z(n0:n1)
      end do
      call self%sub(n)%p%apply(self%y(n0:n1), z(n0:n1))
      do i = 1, n - 1
        call self%a%block_range(i, a0, a1)
        call self%a%apply_block(i, n, z(n0:n1), self%t(a0:a1))
        self%t(a0:a1) = r(a0:a1) - self%t(a0:a1)
        call self%sub(i)%p%apply(self%t(a0:a1), z(a0:a1))
      end do
    case ('upper')
      call self%sub(n)%p%apply(r(n0:n1), z(n0:n1))
      do i = 1, n - 1
        call self%a%block_range(i, a0, a1)
        call self%a%apply_block(i, n, z(n0:n1), self%t(a0:a1))
        self%t(a0:a1) = r(a0:a1) - self%t(a0:a1)
        call self%sub(i)%p%apply(self%t(a0:a1), z(a0:a1))
      end do
    case default   ! lower and ldu
      self%y(n0:n1) = r(n0:n1)
      do i = 1, n - 1
        call self%a%block_range(i, a0, a1)
        call self%sub(i)%p%apply(r(a0:a1), z(a0:a1))
        call self%a%apply_block(n, i, z(a0:a1), self%t(n0:n1))
        self%y(n0:n1) = self%y(n0:n1) - self%t(n0:n1)
      end do
      call self%sub(n)%p%apply(self%y(n0:n1), z(n0:n1))
      if (self%mode == 'ldu') then
        do i = 1, n - 1
          call self%a%block_range(i, a0, a1)
          call self%a%apply_block(i, n, z(n0:n1), self%t(a0:a1))
          call self%sub(i)%p%apply(self%t(a0:a1), self%y(a0:a1))
          z(a0:a1) = z(a0:a1) - self%y(a0:a1)
        end do
      end if
    end select
  end subroutine sbp_apply

  function sbp_name(self) result(s)
    class(schur_block_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'block-'//trim(self%mode)
  end function sbp_name

  subroutine sbp_free(self)
    class(schur_block_precon_t), intent(inout) :: self
    integer :: i
    if (allocated(self%sub)) then
      do i = 1, size(self%sub)
        if (allocated(self%sub(i)%p)) call self%sub(i)%p%free()
      end do
      deallocate(self%sub)
    end if
    if (allocated(self%lower)) then
      do i = 1, size(self%lower)
        if (allocated(self%lower(i)%p)) call self%lower(i)%p%free()
      end do
      deallocate(self%lower)
    end if
    if (allocated(self%t)) deallocate(self%t, self%y)
    self%a => null()
  end subroutine sbp_free
end module schur_block_precon
