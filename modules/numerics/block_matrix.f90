!> A distributed block matrix: an nb x nb array of csr_matrix_t blocks (each
!> addressable alone, absent blocks are zero) acting on block vectors.
!>
!> A block vector on a rank is the concatenation of the owned parts of its
!> fields, in block order: x = [x_1; x_2; ...; x_nb] with x_i of length
!> n_owned(i) (offset(i)+1 .. offset(i+1)). The block matrix is a
!> linear_operator_t on such vectors, so the Krylov solvers see one operator;
!> the block preconditioners address the blocks.
module block_matrix
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use linear_operator, only: linear_operator_t
  use csr_matrix, only: csr_matrix_t
  implicit none
  private

  public :: block_matrix_t, block_columns_t

  type, extends(linear_operator_t) :: block_matrix_t
    integer :: nb = 0
    type(csr_matrix_t), allocatable :: a(:,:)     !< blocks; a(i,j) is used when has(i,j)
    logical, allocatable :: has(:,:)
    integer(ip), allocatable :: offset(:)         !< (nb+1) offsets of the owned block parts
    real(rp), allocatable :: work(:)
  contains
    procedure :: init
    procedure :: set_pattern
    procedure :: zero
    procedure :: finalize_assembly
    procedure :: apply => block_apply
    procedure :: n_owned => block_n_owned
    procedure :: block_range
    procedure :: apply_block
    procedure :: apply_columns
    procedure :: monolithic
    procedure :: free
  end type block_matrix_t

  !> y = A x for x nonzero only in the column blocks cols (A: a block
  !> matrix kept by pointer): the products of the other blocks are skipped.
  type, extends(linear_operator_t) :: block_columns_t
    type(block_matrix_t), pointer :: a => null()
    logical, allocatable :: cols(:)
  contains
    procedure :: apply => columns_apply
    procedure :: n_owned => columns_n_owned
  end type block_columns_t

contains

  !> nb block rows; n_owned(i) owned entries of block i on this rank.
  subroutine init(self, n_owned)
    class(block_matrix_t), intent(inout) :: self
    integer(ip), intent(in) :: n_owned(:)
    integer :: i
    call self%free()
    self%nb = size(n_owned)
    allocate(self%a(self%nb, self%nb), self%has(self%nb, self%nb), self%offset(self%nb + 1))
    self%has = .false.
    self%offset(1) = 0
    do i = 1, self%nb
      self%offset(i + 1) = self%offset(i) + n_owned(i)
    end do
  end subroutine init

  !> Give block (i, j) its pattern (see csr_matrix%init).
  subroutine set_pattern(self, i, j, row_map, col_map, row_ptr, col)
    class(block_matrix_t), intent(inout) :: self
    integer, intent(in) :: i, j
    type(index_map_t), intent(in), target :: row_map, col_map
    integer(ip), intent(in) :: row_ptr(:), col(:)
    if (row_map%n_owned /= self%offset(i+1) - self%offset(i)) error stop 'block_matrix: row map size'
    if (col_map%n_owned /= self%offset(j+1) - self%offset(j)) error stop 'block_matrix: column map size'
    call self%a(i, j)%init(row_map, col_map, row_ptr, col)
    self%has(i, j) = .true.
  end subroutine set_pattern

  subroutine zero(self)
    class(block_matrix_t), intent(inout) :: self
    integer :: i, j
    do j = 1, self%nb
      do i = 1, self%nb
        if (self%has(i, j)) call self%a(i, j)%zero()
      end do
    end do
  end subroutine zero

  !> Send every block's off-rank contributions to their owners. Collective.
  subroutine finalize_assembly(self)
    class(block_matrix_t), intent(inout) :: self
    integer :: i, j
    do j = 1, self%nb
      do i = 1, self%nb
        if (self%has(i, j)) call self%a(i, j)%finalize_assembly()
      end do
    end do
  end subroutine finalize_assembly

  !> First and last position of block i in a block vector.
  subroutine block_range(self, i, first, last)
    class(block_matrix_t), intent(in) :: self
    integer, intent(in) :: i
    integer(ip), intent(out) :: first, last
    first = self%offset(i) + 1
    last = self%offset(i + 1)
  end subroutine block_range

  !> y_i = A(i, j) x_j for one block (y_i = 0 when the block is absent).
  subroutine apply_block(self, i, j, x, y)
    class(block_matrix_t), intent(inout) :: self
    integer, intent(in) :: i, j
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    if (self%has(i, j)) then
      call self%a(i, j)%apply(x, y)
    else
      y = 0.0_rp
    end if
  end subroutine apply_block

  !> y = A x on block vectors. Collective.
  subroutine block_apply(self, x, y)
    class(block_matrix_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer :: j
    call self%apply_columns([(.true., j = 1, self%nb)], x, y)
  end subroutine block_apply

  !> y = A(:, j) x_j summed over the column blocks j with cols(j): A x for
  !> an x that vanishes in the other blocks, without their products.
  !> Collective.
  subroutine apply_columns(self, cols, x, y)
    class(block_matrix_t), intent(inout) :: self
    logical, intent(in) :: cols(:)
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer :: i, j
    integer(ip) :: r0, r1, c0, c1
    if (.not. allocated(self%work)) allocate(self%work(self%offset(self%nb + 1)))
    y = 0.0_rp
    do i = 1, self%nb
      call self%block_range(i, r0, r1)
      do j = 1, self%nb
        if (.not. (self%has(i, j) .and. cols(j))) cycle
        call self%block_range(j, c0, c1)
        call self%a(i, j)%apply(x(c0:c1), self%work(r0:r1))
        y(r0:r1) = y(r0:r1) + self%work(r0:r1)
      end do
    end do
  end subroutine apply_columns

  !> The operator of the column blocks `cols` of a block matrix (apply_columns).
  subroutine columns_apply(self, x, y)
    class(block_columns_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    call self%a%apply_columns(self%cols, x, y)
  end subroutine columns_apply

  integer(ip) function columns_n_owned(self)
    class(block_columns_t), intent(in) :: self
    columns_n_owned = self%a%n_owned()
  end function columns_n_owned

  integer(ip) function block_n_owned(self)
    class(block_matrix_t), intent(in) :: self
    block_n_owned = self%offset(self%nb + 1)
  end function block_n_owned

  !> The whole block matrix as one distributed CSR matrix (for MUMPS and for
  !> exports), over a combined index map in which each rank owns its block
  !> vector: global id = first id of the rank + position in the block vector.
  !> cmap must stay alive as long as m. Collective.
  subroutine monolithic(self, cmap, m)
    class(block_matrix_t), intent(in), target :: self
    type(index_map_t), intent(inout), target :: cmap
    type(csr_matrix_t), intent(inout) :: m
    type(parallel_comm_t) :: comm
    integer(gp), allocatable :: sizes(:,:), first(:), ghost_gid(:)
    integer(ip), allocatable :: row_ptr(:), col(:), nnz_row(:)
    integer(ip) :: i, r, k, n, nghost, p, bi, bj, r0, r1
    integer(gp) :: g
    type(index_map_t), pointer :: cm
    integer(ip), allocatable :: order(:)
    integer(gp), allocatable :: keys(:)
    integer :: np

    ! a row map of some block row, for the communicator
    cm => first_map(self)
    comm = cm%comm
    np = comm%size
    ! per-rank sizes of each block (to place other ranks' entries)
    allocate(sizes(self%nb, 0:np-1), first(0:np))
    do i = 1, self%nb
      sizes(i, :) = comm%allgather(int(self%offset(i+1) - self%offset(i), gp))
    end do
    first(0) = 1
    do p = 1, np
      first(p) = first(p-1) + sum(sizes(:, p-1))
    end do
    ! the ghost columns of every block, as combined global ids
    nghost = 0
    do bj = 1, self%nb
      do bi = 1, self%nb
        if (self%has(bi, bj)) then
          nghost = nghost + self%a(bi, bj)%col_map%n_ghost
          exit
        end if
      end do
    end do
    allocate(ghost_gid(nghost))
    n = 0
    do bj = 1, self%nb
      cm => column_map(self, bj)
      if (.not. associated(cm)) cycle
      do k = 1, cm%n_ghost
        n = n + 1
        p = cm%ghost_owner(k)
        ghost_gid(n) = first(p) + sum(sizes(1:bj-1, p)) + (cm%ghost_gid(k) - cm%offsets(p))
      end do
    end do
    call cmap%init(comm, self%offset(self%nb + 1), ghost_gid(1:n))
    ! rows
    allocate(nnz_row(self%offset(self%nb + 1)))
    nnz_row = 0
    do bi = 1, self%nb
      call self%block_range(bi, r0, r1)
      do bj = 1, self%nb
        if (.not. self%has(bi, bj)) cycle
        do r = 1, r1 - r0 + 1
          nnz_row(r0 + r - 1) = nnz_row(r0 + r - 1) + self%a(bi, bj)%row_ptr(r+1) - self%a(bi, bj)%row_ptr(r)
        end do
      end do
    end do
    allocate(row_ptr(size(nnz_row) + 1))
    row_ptr(1) = 1
    do r = 1, size(nnz_row)
      row_ptr(r + 1) = row_ptr(r) + nnz_row(r)
    end do
    allocate(col(row_ptr(size(nnz_row) + 1) - 1))
    nnz_row = 0
    do bi = 1, self%nb
      call self%block_range(bi, r0, r1)
      do bj = 1, self%nb
        if (.not. self%has(bi, bj)) cycle
        do r = 1, r1 - r0 + 1
          do k = self%a(bi, bj)%row_ptr(r), self%a(bi, bj)%row_ptr(r+1) - 1
            g = combined_gid(bi, bj, self%a(bi, bj)%col(k))
            i = r0 + r - 1
            col(row_ptr(i) + nnz_row(i)) = cmap%local_id(g)
            nnz_row(i) = nnz_row(i) + 1
          end do
        end do
      end do
    end do
    ! sort each row's columns (blocks interleave local ids)
    do r = 1, size(nnz_row)
      n = row_ptr(r + 1) - row_ptr(r)
      if (n <= 1) cycle
      keys = int(col(row_ptr(r):row_ptr(r+1)-1), gp)
      if (allocated(order)) deallocate(order)
      allocate(order(n))
      call sort_ids(keys, order)
      col(row_ptr(r):row_ptr(r+1)-1) = int(keys, ip)
    end do
    call m%init(cmap, cmap, row_ptr, col)
    ! values
    do bi = 1, self%nb
      call self%block_range(bi, r0, r1)
      do bj = 1, self%nb
        if (.not. self%has(bi, bj)) cycle
        do r = 1, r1 - r0 + 1
          do k = self%a(bi, bj)%row_ptr(r), self%a(bi, bj)%row_ptr(r+1) - 1
            g = combined_gid(bi, bj, self%a(bi, bj)%col(k))
            call m%add_value(r0 + r - 1, cmap%local_id(g), self%a(bi, bj)%val(k))
          end do
        end do
      end do
    end do
  contains
    !> Combined global id of local column j of block (bi, bj).
    integer(gp) function combined_gid(bi, bj, j)
      integer(ip), intent(in) :: bi, bj, j
      type(index_map_t), pointer :: colm
      integer(ip) :: owner
      colm => self%a(bi, bj)%col_map
      if (j <= colm%n_owned) then
        combined_gid = cmap%first + self%offset(bj) + j - 1
      else
        owner = colm%ghost_owner(j - colm%n_owned)
        combined_gid = first(owner) + sum(sizes(1:bj-1, owner)) + (colm%ghost_gid(j - colm%n_owned) - colm%offsets(owner))
      end if
    end function combined_gid
  end subroutine monolithic

  !> The column map of block column j (from any present block), or null.
  function column_map(self, j) result(cm)
    type(block_matrix_t), intent(in), target :: self
    integer, intent(in) :: j
    type(index_map_t), pointer :: cm
    integer :: i
    cm => null()
    do i = 1, self%nb
      if (self%has(i, j)) then
        cm => self%a(i, j)%col_map
        return
      end if
    end do
  end function column_map

  function first_map(self) result(m)
    type(block_matrix_t), intent(in), target :: self
    type(index_map_t), pointer :: m
    integer :: i, j
    m => null()
    do j = 1, self%nb
      do i = 1, self%nb
        if (self%has(i, j)) then
          m => self%a(i, j)%row_map
          return
        end if
      end do
    end do
    error stop 'block_matrix: no block present'
  end function first_map

  subroutine sort_ids(keys, order)
    use index_map, only: sort_gids
    integer(gp), intent(inout) :: keys(:)
    integer(ip), intent(out) :: order(:)
    call sort_gids(keys, order)
  end subroutine sort_ids

  subroutine free(self)
    class(block_matrix_t), intent(inout) :: self
    integer :: i, j
    if (allocated(self%a)) then
      do j = 1, self%nb
        do i = 1, self%nb
          if (self%has(i, j)) call self%a(i, j)%free()
        end do
      end do
      deallocate(self%a, self%has)
    end if
    if (allocated(self%offset)) deallocate(self%offset)
    if (allocated(self%work)) deallocate(self%work)
    self%nb = 0
  end subroutine free
end module block_matrix
