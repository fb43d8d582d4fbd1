!> Small string helpers for messages.
module strings
  use kinds, only: rp
  implicit none
  private

  public :: itoa, rtoa

contains

  !> Integer as text.
  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: t
    write(t, '(i0)') i
    s = trim(t)
  end function itoa

  !> Real as short text (general format, trailing blanks removed).
  function rtoa(x) result(s)
    real(rp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: t
    write(t, '(g0.6)') x
    s = trim(adjustl(t))
  end function rtoa
end module strings
