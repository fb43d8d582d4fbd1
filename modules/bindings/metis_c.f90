!> Raw interfaces to METIS 5.1 (idx_t and real_t are 32-bit in Debian's build).
module metis_c
  use, intrinsic :: iso_c_binding, only: c_int, c_ptr
  use kinds, only: metis_idx
  implicit none
  private

  public :: metis_part_mesh_dual, metis_set_default_options
  integer, parameter, public :: metis_noptions = 40
  integer, parameter, public :: metis_ok = 1
  !> Positions (1-based here) in the options array, from the enum in metis.h.
  integer, parameter, public :: metis_option_seed = 9
  integer, parameter, public :: metis_option_numbering = 18

  interface
    function metis_part_mesh_dual(ne, nn, eptr, eind, vwgt, vsize, ncommon, nparts, tpwgts, &
                                  options, objval, epart, npart) bind(C, name='METIS_PartMeshDual') result(ierr)
      import :: metis_idx, c_ptr, c_int
      integer(metis_idx), intent(in) :: ne, nn
      integer(metis_idx), intent(in) :: eptr(*), eind(*)
      type(c_ptr), value :: vwgt, vsize
      integer(metis_idx), intent(in) :: ncommon, nparts
      type(c_ptr), value :: tpwgts
      integer(metis_idx), intent(in) :: options(*)
      integer(metis_idx), intent(out) :: objval
      integer(metis_idx), intent(out) :: epart(*), npart(*)
      integer(c_int) :: ierr
    end function metis_part_mesh_dual

    function metis_set_default_options(options) bind(C, name='METIS_SetDefaultOptions') result(ierr)
      import :: metis_idx, c_int
      integer(metis_idx), intent(out) :: options(*)
      integer(c_int) :: ierr
    end function metis_set_default_options
  end interface
end module metis_c
