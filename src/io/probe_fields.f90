!> What a physics hands to the probes after an accepted step
!> (simulation_t%sample): the fields a &probe may name, as local arrays of
!> the distributed mesh, and named scalars of its own (e.g. per fault the
!> largest slip) that go into the probe file as columns.
module probe_fields
  use kinds, only: rp
  implicit none
  private

  public :: probe_fields_t, scalar_name_len

  integer, parameter :: scalar_name_len = 96

  type :: probe_fields_t
    !> displacement, 3 interleaved components per local node (owned and
    !> ghost nodes, ghosts up to date) [m]
    real(rp), allocatable :: u(:)
    real(rp), allocatable :: p(:)            !< pressure per owned cell [Pa]
    real(rp), allocatable :: stress(:,:)     !< (6, owned cells) xx yy zz xy yz xz [Pa], tension positive
    !> column headers with their unit, e.g. 'fault:max_slip [m]', and the
    !> values (the same on every rank)
    character(len=scalar_name_len), allocatable :: names(:)
    real(rp), allocatable :: values(:)
  end type probe_fields_t
end module probe_fields
