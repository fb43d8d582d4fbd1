!> Partition of the cells among ranks: METIS's dual-graph partitioner on
!> rank 0 (cells are neighbours when they share a face).
module partition
  use, intrinsic :: iso_c_binding, only: c_null_ptr
  use kinds, only: ip, metis_idx, msg_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  use metis_c, only: metis_part_mesh_dual, metis_set_default_options, metis_noptions, metis_ok, &
                     metis_option_seed, metis_option_numbering
  implicit none
  private

  public :: partition_cells

contains

  !> part(c) in 0..nparts-1 for every cell of the global mesh.
  subroutine partition_cells(mesh, nparts, part, status)
    type(mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: nparts
    integer(ip), intent(out) :: part(:)
    type(error_status_t), intent(inout) :: status
    integer(metis_idx), allocatable :: eptr(:), eind(:), epart(:), npart(:)
    integer(metis_idx) :: options(metis_noptions), ne, nn, ncommon, np, objval
    integer :: ierr, c
    character(len=msg_len) :: m

    if (nparts == 1) then
      part = 0
      return
    end if
    if (mesh%n_cells < nparts) then
      write(m, '(a,i0,a,i0,a)') 'partition: ', mesh%n_cells, ' cells cannot be shared among ', nparts, ' ranks'
      call status%set(m)
      return
    end if
    ne = mesh%n_cells
    nn = mesh%n_nodes
    allocate(eptr(ne + 1), eind(8 * ne), epart(ne), npart(nn))
    do c = 1, ne
      eptr(c) = 8 * (c - 1)
      eind(8*(c-1)+1:8*c) = mesh%cell_nodes(:, c) - 1
    end do
    eptr(ne + 1) = 8 * ne
    ierr = metis_set_default_options(options)
    options(metis_option_numbering) = 0
    options(metis_option_seed) = 7
    ncommon = 4
    np = nparts
    ierr = metis_part_mesh_dual(ne, nn, eptr, eind, c_null_ptr, c_null_ptr, ncommon, np, c_null_ptr, &
                                options, objval, epart, npart)
    if (ierr /= metis_ok) then
      write(m, '(a,i0)') 'partition: METIS_PartMeshDual failed with code ', ierr
      call status%set(m)
      return
    end if
    part = epart
    do c = 0, nparts - 1
      if (count(part == c) == 0) then
        write(m, '(a,i0,a)') 'partition: METIS left rank ', c, ' without cells'
        call status%set(m)
        return
      end if
    end do
  end subroutine partition_cells
end module partition
