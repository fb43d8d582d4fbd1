!> Export of a linear system as MatrixMarket files (for inspection and for
!> other solvers): <base>_K.mtx (the operator, a block operator assembled
!> into one matrix in the row order of the block vector) and <base>_rhs.mtx.
module system_export
  use kinds, only: gp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use dist_vector, only: write_vector_market
  use linear_system, only: linear_system_t
  implicit none
  private

  public :: export_system

contains

  !> Write sys%a and sys%b (as assembled, before any scaling). Collective.
  subroutine export_system(comm, sys, base, status)
    type(parallel_comm_t), intent(in) :: comm
    type(linear_system_t), intent(in) :: sys
    character(len=*), intent(in) :: base
    type(error_status_t), intent(inout) :: status
    type(csr_matrix_t) :: mono
    type(index_map_t) :: mono_map
    integer :: ios
    integer(gp) :: n
    ios = 0
    select type (a => sys%a)
    type is (csr_matrix_t)
      call a%write_matrix_market(base//'_K.mtx', ios)
      n = a%row_map%n_global
    type is (block_matrix_t)
      call a%monolithic(mono_map, mono)
      call mono%write_matrix_market(base//'_K.mtx', ios)
      n = mono%row_map%n_global
      call mono%free()
    class default
      call status%set('matrix export: the operator is not an assembled matrix')
      return
    end select
    if (ios == 0) call write_vector_market(comm, base//'_rhs.mtx', sys%b, n, ios)
    if (ios /= 0) call status%set('cannot write the matrix export '//base//'_K.mtx / _rhs.mtx')
  end subroutine export_system
end module system_export
