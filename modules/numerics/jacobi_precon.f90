!> Jacobi (diagonal) preconditioner: z = r / d with d the diagonal of A.
!>
!> The cheapest sub-solver of the block preconditioners, and the reference
!> preconditioner of the Krylov tests.
module jacobi_precon
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, ip, gp, name_len, msg_len
  use parallel_comm, only: parallel_comm_t, wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use precon, only: precon_t
  implicit none
  private

  public :: jacobi_precon_t

  !> z = D^-1 r; d holds the owned diagonal entries of the matrix of setup().
  type, extends(precon_t) :: jacobi_precon_t
    real(rp), allocatable :: d(:)
  contains
    procedure :: setup => jacobi_setup
    procedure :: apply => jacobi_apply
    procedure :: name => jacobi_name
    procedure :: free => jacobi_free
  end type jacobi_precon_t

contains

  !> Take the diagonal of the square matrix a (rows and columns numbered by
  !> the same owned entries). Collective over the matrix's communicator, so
  !> that every rank returns the same status: a zero or non-finite diagonal
  !> entry anywhere is an error that names the first such global row.
  subroutine jacobi_setup(self, a, status)
    class(jacobi_precon_t), intent(inout) :: self
    class(csr_matrix_t), intent(in) :: a
    type(error_status_t), intent(inout) :: status
    type(parallel_comm_t) :: comm
    integer(ip) :: i, n, n_bad, kind_bad, kind_first
    integer(gp) :: g_bad, g_first
    character(len=msg_len) :: m
    character(len=*), parameter :: what(2) = [character(len=12) :: 'zero', 'not finite']
    real(rp) :: t0

    t0 = wall_time()
    call self%free()
    comm = a%row_map%comm
    n = a%n_owned()
    allocate(self%d(n))
    call a%diagonal(self%d)

    ! first bad row of this rank (global id), and its kind: 1 zero, 2 NaN/Inf
    n_bad = 0
    kind_bad = 0
    g_bad = huge(1_gp)
    do i = 1, n
      if (.not. ieee_is_finite(self%d(i))) then
        n_bad = n_bad + 1
        if (kind_bad == 0) kind_bad = 2
      else if (self%d(i) == 0.0_rp) then
        n_bad = n_bad + 1
        if (kind_bad == 0) kind_bad = 1
      else
        cycle
      end if
      if (g_bad == huge(1_gp)) g_bad = a%row_map%first + i - 1
    end do

    ! agree over ranks on the lowest bad global row (no min over int64: negate)
    n_bad = comm%sum(n_bad)
    if (n_bad == 0) then
      self%setup_time = wall_time() - t0
      return
    end if
    g_first = -comm%max(-g_bad)
    kind_first = 0
    if (g_bad == g_first) kind_first = kind_bad
    kind_first = comm%sum(kind_first)
    write(m, '(a,i0,a,a,a,i0,a)') 'jacobi_precon%setup: the diagonal entry of global row ', g_first, &
      ' is ', trim(what(max(1, min(2, kind_first)))), ' (', n_bad, ' bad diagonal entries in all)'
    call status%set(trim(m))
    ! an unusable diagonal must not be applied: apply() then stops loudly
    deallocate(self%d)
    self%setup_time = wall_time() - t0
  end subroutine jacobi_setup

  !> z = r / d on the owned entries.
  subroutine jacobi_apply(self, r, z)
    class(jacobi_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    if (.not. allocated(self%d)) error stop 'jacobi_precon%apply: called before setup'
    z = r / self%d
  end subroutine jacobi_apply

  function jacobi_name(self) result(s)
    class(jacobi_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'jacobi'
  end function jacobi_name

  subroutine jacobi_free(self)
    class(jacobi_precon_t), intent(inout) :: self
    if (allocated(self%d)) deallocate(self%d)
    self%setup_time = 0.0_rp
  end subroutine jacobi_free
end module jacobi_precon
