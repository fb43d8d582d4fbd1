!> Status returned by library-like routines: they report, drivers decide to stop.
module error_status
  use kinds, only: msg_len
  implicit none
  private

  public :: error_status_t

  type :: error_status_t
    integer :: code = 0                      !< 0: success
    character(len=msg_len) :: msg = ''       !< what went wrong, and where
  contains
    procedure :: ok
    procedure :: set
    procedure :: clear
  end type error_status_t

contains

  logical function ok(self)
    class(error_status_t), intent(in) :: self
    ok = self%code == 0
  end function ok

  !> Record a failure (code defaults to 1).
  subroutine set(self, msg, code)
    class(error_status_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    integer, intent(in), optional :: code
    self%code = 1
    if (present(code)) self%code = code
    self%msg = msg
  end subroutine set

  subroutine clear(self)
    class(error_status_t), intent(inout) :: self
    self%code = 0
    self%msg = ''
  end subroutine clear
end module error_status
