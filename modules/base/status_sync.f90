!> Make a status the same on every rank: the first failing rank's code and
!> message (so that the ranks can stop together).
module status_sync
  use kinds, only: msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  implicit none
  private

  public :: agree

contains

  !> Collective: on return every rank has the lowest failing rank's status.
  subroutine agree(comm, status)
    type(parallel_comm_t), intent(in) :: comm
    type(error_status_t), intent(inout) :: status
    integer :: code
    character(len=msg_len) :: msg
    code = status%code
    msg = status%msg
    call comm%sync_error(code, msg)
    if (code /= 0) call status%set(msg, code)
  end subroutine agree
end module status_sync
