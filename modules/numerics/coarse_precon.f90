!> A preconditioner M with a small coarse space Z (a few global vectors)
!> added multiplicatively, the coarse step a least-squares one: c minimizes
!> the weighted residual ||W^1/2 (r - A Z c)||, that is
!>
!>   E c = (A Z)^T W r,  E = (A Z)^T W (A Z)   (n_c x n_c, on every rank)
!>   z = Z c + M^-1 (r - A Z c)
!>
!> W is the squared scaling of the system the Krylov method sees, so the
!> coarse step never increases the residual it minimizes. It costs n_c dot
!> products and updates per application (A Z is kept from the set-up).
!> Tried and left: the Galerkin choice E = Z^T A Z (on sliding fractures
!> Z^T A Z nearly vanishes while A Z does not, and the counts doubled); the
!> same step after M as well (its coefficients came out at 1e-24: on the
!> nine-fracture case M leaves nothing there).
!>
!> Made for modes that M misses and that the physics knows in closed form:
!> the mean pressure of a closed, sealed fracture with its traction (the
!> pressure and the normal traction rising together move nothing, so the
!> Jacobian nearly vanishes on it; see contact_precon.f90).
!>
!> The columns are kept sparse (the entries that are not exactly zero).
module coarse_precon
  use kinds, only: rp, ip, name_len
  use strings, only: itoa
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  implicit none
  private

  public :: coarse_precon_t, sparse_columns_t

  !> n columns of length n_owned, sparse: column j has the entries
  !> ptr(j) .. ptr(j+1)-1 of idx (owned positions) and val.
  type :: sparse_columns_t
    integer :: n = 0
    integer(ip), allocatable :: ptr(:), idx(:)
    real(rp), allocatable :: val(:)
  contains
    procedure :: from_dense
    procedure :: dot
    procedure :: axpy
  end type sparse_columns_t

  type, extends(precon_t) :: coarse_precon_t
    class(precon_t), pointer :: m => null()
    class(linear_operator_t), pointer :: a => null()
    type(parallel_comm_t) :: comm
    type(sparse_columns_t) :: z, az, waz          !< Z, A Z, W A Z
    real(rp), allocatable :: e(:,:)                !< LU factors of E (LAPACK dgetrf)
    integer, allocatable :: piv(:)
    real(rp), allocatable :: w(:)
  contains
    procedure :: setup
    procedure :: apply => cp_apply
    procedure :: name => cp_name
    procedure :: free => cp_free
  end type coarse_precon_t

  interface
    subroutine dgetrf(m, n, a, lda, ipiv, info)
      import :: rp
      integer, intent(in) :: m, n, lda
      real(rp), intent(inout) :: a(lda, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgetrf
    subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: rp
      character, intent(in) :: trans
      integer, intent(in) :: n, nrhs, lda, ldb
      real(rp), intent(in) :: a(lda, *)
      integer, intent(in) :: ipiv(*)
      real(rp), intent(inout) :: b(ldb, *)
      integer, intent(out) :: info
    end subroutine dgetrs
  end interface

contains

  !> Columns from a dense (n_owned, n) array, keeping the non-zeros.
  subroutine from_dense(self, d)
    class(sparse_columns_t), intent(inout) :: self
    real(rp), intent(in) :: d(:,:)
    integer :: j
    integer(ip) :: k
    self%n = size(d, 2)
    if (allocated(self%ptr)) deallocate(self%ptr, self%idx, self%val)
    allocate(self%ptr(self%n + 1), self%idx(count(d /= 0.0_rp)), self%val(count(d /= 0.0_rp)))
    self%ptr(1) = 1
    k = 0
    do j = 1, self%n
      self%idx(k + 1:k + count(d(:, j) /= 0.0_rp)) = pack([(int(k, ip), k = 1, size(d, 1))], d(:, j) /= 0.0_rp)
      k = self%ptr(j) - 1 + count(d(:, j) /= 0.0_rp)
      self%val(self%ptr(j):k) = d(self%idx(self%ptr(j):k), j)
      self%ptr(j + 1) = k + 1
    end do
  end subroutine from_dense

  !> c(j) = column j . x (owned parts; the caller sums over the ranks).
  subroutine dot(self, x, c)
    class(sparse_columns_t), intent(in) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: c(:)
    integer :: j
    integer(ip) :: k
    do j = 1, self%n
      c(j) = 0.0_rp
      do k = self%ptr(j), self%ptr(j + 1) - 1
        c(j) = c(j) + self%val(k) * x(self%idx(k))
      end do
    end do
  end subroutine dot

  !> y += s * sum_j c(j) column j.
  subroutine axpy(self, s, c, y)
    class(sparse_columns_t), intent(in) :: self
    real(rp), intent(in) :: s, c(:)
    real(rp), intent(inout) :: y(:)
    integer :: j
    integer(ip) :: k
    do j = 1, self%n
      do k = self%ptr(j), self%ptr(j + 1) - 1
        y(self%idx(k)) = y(self%idx(k)) + s * c(j) * self%val(k)
      end do
    end do
  end subroutine axpy

  !> Set up with the preconditioner m (set up already) of the operator a,
  !> the coarse vectors z (dense owned columns; overwritten) and the weights
  !> w (owned, > 0). Collective. A singular E (columns of A Z that are
  !> linearly dependent) is an error.
  subroutine setup(self, m, a, comm, z, w, status)
    class(coarse_precon_t), intent(inout) :: self
    class(precon_t), intent(in), target :: m
    class(linear_operator_t), intent(in), target :: a
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(inout) :: z(:,:)
    real(rp), intent(in) :: w(:)
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: az(:,:)
    integer :: j, nc, info
    call self%free()
    self%m => m
    self%a => a
    self%comm = comm
    nc = size(z, 2)
    allocate(az(size(z, 1), nc), self%w(size(z, 1)))
    do j = 1, nc
      call self%a%apply(z(:, j), az(:, j))
    end do
    call self%z%from_dense(z)
    call self%az%from_dense(az)
    do j = 1, nc
      az(:, j) = w * az(:, j)
    end do
    call self%waz%from_dense(az)
    allocate(self%e(nc, nc), self%piv(nc))
    do j = 1, nc
      call self%waz%dot(az(:, j) / w, self%e(:, j))
    end do
    do j = 1, nc
      call self%comm%sum_all(self%e(:, j))
    end do
    if (nc == 0) return
    call dgetrf(nc, nc, self%e, nc, self%piv, info)
    if (info /= 0) call status%set('coarse correction: the coarse matrix (A Z)^T W A Z is singular (column '// &
                                   itoa(info)//')')
  end subroutine setup

  !> c = E^-1 (W A Z)^T x (summed over the ranks).
  subroutine coarse_solve(self, x, c)
    type(coarse_precon_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: c(:)
    integer :: info
    call self%waz%dot(x, c)
    call self%comm%sum_all(c)
    call dgetrs('N', self%z%n, 1, self%e, self%z%n, self%piv, c, self%z%n, info)
  end subroutine coarse_solve

  subroutine cp_apply(self, r, z)
    class(coarse_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    real(rp) :: c(self%z%n)
    if (self%z%n == 0) then
      call self%m%apply(r, z)
      return
    end if
    call coarse_solve(self, r, c)
    self%w = r
    call self%az%axpy(-1.0_rp, c, self%w)
    call self%m%apply(self%w, z)
    call self%z%axpy(1.0_rp, c, z)
  end subroutine cp_apply

  function cp_name(self) result(s)
    class(coarse_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'coarse+'//trim(self%m%name())
  end function cp_name

  subroutine cp_free(self)
    class(coarse_precon_t), intent(inout) :: self
    nullify(self%m, self%a)
    if (allocated(self%e)) deallocate(self%e, self%piv)
    if (allocated(self%w)) deallocate(self%w)
    self%z%n = 0
    self%az%n = 0
    self%waz%n = 0
    self%setup_time = 0.0_rp
  end subroutine cp_free

end module coarse_precon
