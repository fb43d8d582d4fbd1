!> Export of a linear system as MatrixMarket files (for inspection and for
!> other solvers): <base>_K.mtx (the operator, a block operator assembled
!> into one matrix in the row order of the block vector: on each rank its
!> owned rows of block 1, then of block 2, ..., ranks in turn) and
!> <base>_rhs.mtx. The scaled export (&solver export_step) writes the
!> system as the Krylov solver sees it, D A D and D b, with D in
!> <base>_scaling.mtx, and the block of every row in <base>_fields.mtx (an
!> integer array; its header names the blocks' fields).
module system_export
  use kinds, only: rp, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use dist_vector, only: write_vector_market
  use linear_system, only: linear_system_t
  use linear_solver, only: scale_matrix
  implicit none
  private

  public :: export_system

contains

  !> Write sys%a and sys%b: as assembled, or (scaled) as D A D and D b when
  !> the system has a scaling D, with D and the field map. Collective.
  subroutine export_system(comm, sys, base, status, scaled)
    type(parallel_comm_t), intent(in) :: comm
    type(linear_system_t), intent(in) :: sys
    character(len=*), intent(in) :: base
    type(error_status_t), intent(inout) :: status
    logical, intent(in), optional :: scaled
    type(csr_matrix_t) :: mono
    type(index_map_t) :: mono_map
    real(rp), allocatable :: field(:)
    integer :: ios, i
    integer(gp) :: n
    logical :: with_d
    with_d = .false.
    if (present(scaled)) with_d = scaled .and. associated(sys%d)
    ios = 0
    select type (a => sys%a)
    type is (csr_matrix_t)
      mono = a                           ! a copy (the scaling must not touch a)
      mono%owned_col_map => null()       ! the copy does not own a's column map
      allocate(field(a%n_rows))
      field = 1.0_rp
    type is (block_matrix_t)
      call a%monolithic(mono_map, mono)
      allocate(field(a%offset(a%nb + 1)))
      do i = 1, a%nb
        field(a%offset(i) + 1:a%offset(i + 1)) = real(i, rp)
      end do
    class default
      call status%set('matrix export: the operator is not an assembled matrix')
      return
    end select
    n = mono%row_map%n_global
    if (with_d) call scale_matrix(mono, sys%d)
    call mono%write_matrix_market(base//'_K.mtx', ios)
    call mono%free()
    if (ios == 0) then
      if (with_d) then
        call write_vector_market(comm, base//'_rhs.mtx', sys%d * sys%b, n, ios)
      else
        call write_vector_market(comm, base//'_rhs.mtx', sys%b, n, ios)
      end if
    end if
    if (ios == 0 .and. with_d) call write_vector_market(comm, base//'_scaling.mtx', sys%d, n, ios)
    if (ios == 0 .and. present(scaled)) call write_vector_market(comm, base//'_fields.mtx', field, n, ios, integer=.true., &
      comment='the block of every row of the exported matrix; blocks (1, 2, ...): '//trim(sys%fields))
    if (ios /= 0) call status%set('cannot write the matrix export '//base//'_K.mtx / _rhs.mtx')
  end subroutine export_system
end module system_export
