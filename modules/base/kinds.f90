!> Kinds used throughout geoblock.
!>
!> rp  : real kind of every floating-point quantity (IEEE double).
!> ip  : local integer kind (indices of owned and ghost entities on one rank).
!> gp  : global integer kind (global ids of nodes, cells, faces and dofs).
!> hypre_int, hypre_bigint : HYPRE_Int and HYPRE_BigInt of Debian's hypre 2.26
!>       (built without --enable-bigint: both are C int, see HYPRE_config.h).
!> metis_idx : idx_t of Debian's METIS 5.1 (IDXTYPEWIDTH 32 in metis.h).
!> mumps_int : MUMPS_INT of Debian's MUMPS 5.5 (32-bit).
module kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  implicit none
  private

  integer, parameter, public :: rp = real64
  integer, parameter, public :: ip = int32
  integer, parameter, public :: gp = int64
  integer, parameter, public :: hypre_int = c_int
  integer, parameter, public :: hypre_bigint = c_int
  integer, parameter, public :: hypre_real = c_double
  integer, parameter, public :: metis_idx = c_int
  integer, parameter, public :: mumps_int = int32

  !> Length of names (deck strings, set names) and of messages.
  integer, parameter, public :: name_len = 64
  integer, parameter, public :: path_len = 512
  integer, parameter, public :: msg_len = 1024
end module kinds
