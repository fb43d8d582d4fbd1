!> Sparsity patterns of the blocks, from element connectivity.
!>
!> An element couples the row entities row_conn(:, e) with the column entities
!> col_conn(:, e) (nodes, faces or cells of the same element). Only owned row
!> entities (local id <= n_row_owned) get rows; with the ghost-cell layer of
!> dist_mesh every element that touches an owned entity is local, so the pattern
!> is complete without communication. Entity couplings are expanded to dofs with
!> nr components per row entity and nc per column entity (interleaved layout of
!> dof_map), which keeps each row's columns ascending.
module sparsity
  use kinds, only: ip
  use index_map, only: insertion_sort
  implicit none
  private

  public :: element_pattern

contains

  !> CSR pattern (row_ptr, col: local dof ids) of the owned rows.
  subroutine element_pattern(n_row_owned, row_conn, col_conn, nr, nc, row_ptr, col)
    integer(ip), intent(in) :: n_row_owned
    integer(ip), intent(in) :: row_conn(:,:), col_conn(:,:)
    integer(ip), intent(in) :: nr, nc
    integer(ip), allocatable, intent(out) :: row_ptr(:), col(:)
    integer(ip), allocatable :: ptr(:), adj(:), fill(:), eptr(:), ecol(:)
    integer(ip) :: ne, e, a, b, r, k, i, n, first, ndof_rows, d, c
    ne = size(row_conn, 2, kind=ip)
    ! entity-level adjacency with repeats
    allocate(ptr(n_row_owned + 1), fill(n_row_owned))
    ptr = 0
    do e = 1, ne
      do a = 1, size(row_conn, 1)
        r = row_conn(a, e)
        if (r >= 1 .and. r <= n_row_owned) ptr(r + 1) = ptr(r + 1) + size(col_conn, 1, kind=ip)
      end do
    end do
    ptr(1) = 1
    do r = 1, n_row_owned
      ptr(r + 1) = ptr(r + 1) + ptr(r)
    end do
    allocate(adj(ptr(n_row_owned + 1) - 1))
    fill = ptr(1:n_row_owned)
    do e = 1, ne
      do a = 1, size(row_conn, 1)
        r = row_conn(a, e)
        if (r < 1 .or. r > n_row_owned) cycle
        do b = 1, size(col_conn, 1)
          adj(fill(r)) = col_conn(b, e)
          fill(r) = fill(r) + 1
        end do
      end do
    end do
    ! sort and remove repeats per row, compacting in place
    allocate(eptr(n_row_owned + 1))
    eptr(1) = 1
    k = 0
    do r = 1, n_row_owned
      first = ptr(r)
      n = ptr(r + 1) - first
      call insertion_sort(adj(first:first + n - 1))
      do i = first, first + n - 1
        if (adj(i) < 1) cycle
        if (k >= eptr(r)) then
          if (adj(k) == adj(i)) cycle
        end if
        k = k + 1
        adj(k) = adj(i)
      end do
      eptr(r + 1) = k + 1
    end do
    allocate(ecol(k))
    ecol = adj(1:k)
    ! expand to dofs
    ndof_rows = nr * n_row_owned
    allocate(row_ptr(ndof_rows + 1), col(nr * nc * k))
    row_ptr(1) = 1
    i = 0
    do r = 1, n_row_owned
      do a = 1, nr
        d = nr * (r - 1) + a
        do e = eptr(r), eptr(r + 1) - 1
          do c = 1, nc
            i = i + 1
            col(i) = nc * (ecol(e) - 1) + c
          end do
        end do
        row_ptr(d + 1) = i + 1
      end do
    end do
  end subroutine element_pattern
end module sparsity
