!> Distributed sparse matrix in CSR form: this rank's owned rows, columns
!> numbered locally through a column index map (owned columns then ghost
!> columns), so that a global column id is col_map%global_id(col(k)).
!>
!> Assembly is element by element with add_block(). Contributions to rows
!> that another rank owns (ghost rows of row_map) are stashed with global ids
!> and sent to their owner by finalize_assembly(); that is the only step of
!> assembly that communicates.
module csr_matrix
  use kinds, only: rp, ip, gp, path_len
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t
  use linear_operator, only: linear_operator_t
  implicit none
  private

  public :: csr_matrix_t

  type, extends(linear_operator_t) :: csr_matrix_t
    type(index_map_t), pointer :: row_map => null()
    type(index_map_t), pointer :: col_map => null()
    integer(ip) :: n_rows = 0                   !< owned rows
    integer(ip), allocatable :: row_ptr(:)      !< (n_rows+1)
    integer(ip), allocatable :: col(:)          !< local column ids, ascending per row
    real(rp), allocatable :: val(:)
    ! stash of contributions to rows owned elsewhere
    integer(ip) :: n_stash = 0
    integer(gp), allocatable :: stash_row(:), stash_col(:)
    real(rp), allocatable :: stash_val(:)
    real(rp), allocatable :: x_ext(:)           !< work: x with ghost columns
    !> a column map built for this matrix (global_csr%to_csr), freed with it
    type(index_map_t), pointer :: owned_col_map => null()
  contains
    procedure :: init
    procedure :: zero
    procedure :: nnz
    procedure :: find
    procedure :: add_block
    procedure :: add_value
    procedure :: finalize_assembly
    procedure :: apply => csr_apply
    procedure :: abs_apply
    procedure :: n_owned => csr_n_owned
    procedure :: diagonal
    procedure :: global_nnz
    procedure :: write_matrix_market
    procedure :: free
  end type csr_matrix_t

contains

  !> Set the pattern. row_ptr/col describe the owned rows with local column ids
  !> of col_map (each row sorted ascending, no repeats). Values start at zero.
  subroutine init(self, row_map, col_map, row_ptr, col)
    class(csr_matrix_t), intent(inout) :: self
    type(index_map_t), intent(in), target :: row_map, col_map
    integer(ip), intent(in) :: row_ptr(:), col(:)
    call self%free()
    self%row_map => row_map
    self%col_map => col_map
    self%n_rows = row_map%n_owned
    if (size(row_ptr) /= self%n_rows + 1) error stop 'csr_matrix%init: row_ptr has the wrong size'
    self%row_ptr = row_ptr
    self%col = col
    allocate(self%val(size(col)))
    self%val = 0.0_rp
    allocate(self%stash_row(1024), self%stash_col(1024), self%stash_val(1024))
    allocate(self%x_ext(col_map%n_local()))
  end subroutine init

  subroutine zero(self)
    class(csr_matrix_t), intent(inout) :: self
    self%val = 0.0_rp
    self%n_stash = 0
  end subroutine zero

  integer(ip) function nnz(self)
    class(csr_matrix_t), intent(in) :: self
    nnz = self%row_ptr(self%n_rows + 1) - 1
  end function nnz

  integer(gp) function global_nnz(self)
    class(csr_matrix_t), intent(in) :: self
    global_nnz = self%row_map%comm%sum(int(self%nnz(), gp))
  end function global_nnz

  !> Position of local column j in owned row i, or 0 when not in the pattern.
  integer(ip) function find(self, i, j)
    class(csr_matrix_t), intent(in) :: self
    integer(ip), intent(in) :: i, j
    integer(ip) :: lo, hi, mid
    lo = self%row_ptr(i)
    hi = self%row_ptr(i+1) - 1
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (self%col(mid) == j) then
        find = mid
        return
      else if (self%col(mid) < j) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
    find = 0
  end function find

  !> A(rows, cols) += a. rows: local ids of row_map (owned or ghost; 0 skips
  !> the row); cols: local ids of col_map (0 skips the column).
  subroutine add_block(self, rows, cols, a)
    class(csr_matrix_t), intent(inout) :: self
    integer(ip), intent(in) :: rows(:), cols(:)
    real(rp), intent(in) :: a(:,:)
    integer(ip) :: i, j
    do i = 1, size(rows)
      if (rows(i) == 0) cycle
      do j = 1, size(cols)
        if (cols(j) == 0) cycle
        call self%add_value(rows(i), cols(j), a(i, j))
      end do
    end do
  end subroutine add_block

  !> A(i, j) += v with local row id i (owned or ghost) and local column id j.
  subroutine add_value(self, i, j, v)
    class(csr_matrix_t), intent(inout) :: self
    integer(ip), intent(in) :: i, j
    real(rp), intent(in) :: v
    integer(ip) :: k
    if (i <= self%n_rows) then
      k = self%find(i, j)
      if (k == 0) error stop 'csr_matrix%add_value: entry outside the pattern'
      self%val(k) = self%val(k) + v
    else
      if (self%n_stash == size(self%stash_val)) call grow_stash(self)
      self%n_stash = self%n_stash + 1
      self%stash_row(self%n_stash) = self%row_map%global_id(i)
      self%stash_col(self%n_stash) = self%col_map%global_id(j)
      self%stash_val(self%n_stash) = v
    end if
  end subroutine add_value

  subroutine grow_stash(self)
    type(csr_matrix_t), intent(inout) :: self
    integer(gp), allocatable :: r(:), c(:)
    real(rp), allocatable :: v(:)
    integer(ip) :: n
    n = size(self%stash_val)
    allocate(r(2*n), c(2*n), v(2*n))
    r(1:n) = self%stash_row
    c(1:n) = self%stash_col
    v(1:n) = self%stash_val
    call move_alloc(r, self%stash_row)
    call move_alloc(c, self%stash_col)
    call move_alloc(v, self%stash_val)
  end subroutine grow_stash

  !> Send the stashed contributions to the owners of their rows and add them.
  !> Collective.
  subroutine finalize_assembly(self)
    class(csr_matrix_t), intent(inout) :: self
    type(parallel_comm_t) :: comm
    integer(ip), allocatable :: scount(:), rcount(:), pos(:), order(:)
    integer(gp), allocatable :: sidx(:), ridx(:)
    real(rp), allocatable :: sval(:), rval(:)
    integer(ip) :: np, p, s, k, i, j, n_in
    comm = self%row_map%comm
    np = comm%size
    if (np == 1) then
      self%n_stash = 0
      return
    end if
    allocate(scount(0:np-1), rcount(0:np-1), pos(0:np))
    scount = 0
    allocate(order(self%n_stash))
    do s = 1, self%n_stash
      order(s) = self%row_map%owner_of(self%stash_row(s))
      scount(order(s)) = scount(order(s)) + 1
    end do
    call comm%alltoall_i(scount, rcount)
    pos(0) = 0
    do p = 1, np
      pos(p) = pos(p-1) + scount(p-1)
    end do
    allocate(sidx(2*self%n_stash), sval(self%n_stash))
    do s = 1, self%n_stash
      p = order(s)
      pos(p) = pos(p) + 1
      sidx(2*pos(p)-1) = self%stash_row(s)
      sidx(2*pos(p)) = self%stash_col(s)
      sval(pos(p)) = self%stash_val(s)
    end do
    n_in = sum(rcount)
    allocate(ridx(2*n_in), rval(n_in))
    call comm%alltoallv(sidx, 2*scount, ridx, 2*rcount)
    call comm%alltoallv(sval, scount, rval, rcount)
    do k = 1, n_in
      i = self%row_map%local_id(ridx(2*k-1))
      j = self%col_map%local_id(ridx(2*k))
      if (i < 1 .or. i > self%n_rows .or. j < 1) &
        error stop 'csr_matrix%finalize_assembly: a stashed entry has no place on its owner'
      call self%add_value(i, j, rval(k))
    end do
    self%n_stash = 0
  end subroutine finalize_assembly

  !> y = A x (x: owned columns; ghost columns fetched from their owners).
  subroutine csr_apply(self, x, y)
    class(csr_matrix_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer(ip) :: i, k, k0, k1, nown
    real(rp) :: s0, s1, s2, s3
    nown = self%col_map%n_owned
    self%x_ext(1:nown) = x(1:nown)
    call self%col_map%import(self%x_ext)
    ! four partial sums a row: one sum is a chain of dependent additions
    ! whose latency, not the memory, bounds the loop (tools/spmv.f90)
    do i = 1, self%n_rows
      k0 = self%row_ptr(i)
      k1 = self%row_ptr(i+1) - 1
      s0 = 0.0_rp
      s1 = 0.0_rp
      s2 = 0.0_rp
      s3 = 0.0_rp
      do k = k0, k1 - 3, 4
        s0 = s0 + self%val(k) * self%x_ext(self%col(k))
        s1 = s1 + self%val(k+1) * self%x_ext(self%col(k+1))
        s2 = s2 + self%val(k+2) * self%x_ext(self%col(k+2))
        s3 = s3 + self%val(k+3) * self%x_ext(self%col(k+3))
      end do
      do k = k1 - mod(k1 - k0 + 1, 4) + 1, k1
        s0 = s0 + self%val(k) * self%x_ext(self%col(k))
      end do
      y(i) = (s0 + s1) + (s2 + s3)
    end do
  end subroutine csr_apply

  !> y = |A| |x| entry by entry, and row_max(i) = max_j |a_ij| (x: owned
  !> columns, ghosts fetched): the denominators of a componentwise backward
  !> error. Collective.
  subroutine abs_apply(self, x, y, row_max)
    class(csr_matrix_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:), row_max(:)
    integer(ip) :: i, k, nown
    real(rp) :: s, m
    nown = self%col_map%n_owned
    self%x_ext(1:nown) = abs(x(1:nown))
    call self%col_map%import(self%x_ext)
    do i = 1, self%n_rows
      s = 0.0_rp
      m = 0.0_rp
      do k = self%row_ptr(i), self%row_ptr(i+1) - 1
        s = s + abs(self%val(k)) * self%x_ext(self%col(k))
        m = max(m, abs(self%val(k)))
      end do
      y(i) = s
      row_max(i) = m
    end do
  end subroutine abs_apply

  integer(ip) function csr_n_owned(self)
    class(csr_matrix_t), intent(in) :: self
    csr_n_owned = self%n_rows
  end function csr_n_owned

  !> Diagonal of a square matrix (row_map and col_map number the same entries).
  subroutine diagonal(self, d)
    class(csr_matrix_t), intent(in) :: self
    real(rp), intent(out) :: d(:)
    integer(ip) :: i, k
    do i = 1, self%n_rows
      k = self%find(i, i)
      d(i) = 0.0_rp
      if (k > 0) d(i) = self%val(k)
    end do
  end subroutine diagonal

  !> Write the matrix in MatrixMarket coordinate format (1-based global ids).
  !> Ranks append their rows in turn. Collective; ios /= 0 on failure.
  subroutine write_matrix_market(self, path, ios)
    class(csr_matrix_t), intent(in) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: ios
    type(parallel_comm_t) :: comm
    integer :: u, p, ios_all
    integer(ip) :: i, k
    integer(gp) :: nnz_all
    comm = self%row_map%comm
    nnz_all = self%global_nnz()
    ios = 0
    do p = 0, comm%size - 1
      if (comm%rank == p) then
        if (p == 0) then
          open(newunit=u, file=path, status='replace', action='write', iostat=ios)
          if (ios == 0) then
            write(u, '(a)') '%%MatrixMarket matrix coordinate real general'
            write(u, '(a)') '% written by geoblock'
            write(u, '(3(i0,1x))') self%row_map%n_global, self%col_map%n_global, nnz_all
          end if
        else
          open(newunit=u, file=path, status='old', position='append', action='write', iostat=ios)
        end if
        if (ios == 0) then
          do i = 1, self%n_rows
            do k = self%row_ptr(i), self%row_ptr(i+1) - 1
              write(u, '(i0,1x,i0,1x,es24.16e3)') self%row_map%global_id(i), &
                self%col_map%global_id(self%col(k)), self%val(k)
            end do
          end do
          close(u)
        end if
      end if
      call comm%barrier()
    end do
    ios_all = comm%max(int(abs(ios), ip))
    ios = ios_all
  end subroutine write_matrix_market

  subroutine free(self)
    class(csr_matrix_t), intent(inout) :: self
    if (allocated(self%row_ptr)) deallocate(self%row_ptr)
    if (allocated(self%col)) deallocate(self%col)
    if (allocated(self%val)) deallocate(self%val)
    if (allocated(self%stash_row)) deallocate(self%stash_row)
    if (allocated(self%stash_col)) deallocate(self%stash_col)
    if (allocated(self%stash_val)) deallocate(self%stash_val)
    if (allocated(self%x_ext)) deallocate(self%x_ext)
    self%row_map => null()
    self%col_map => null()
    if (associated(self%owned_col_map)) then
      call self%owned_col_map%free()
      deallocate(self%owned_col_map)
    end if
    self%n_rows = 0
    self%n_stash = 0
  end subroutine free
end module csr_matrix
