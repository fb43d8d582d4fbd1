!> Small string helpers for messages, the log echo and written decks.
module strings
  use, intrinsic :: iso_fortran_env, only: int64
  use kinds, only: rp
  implicit none
  private

  public :: itoa, lower, rtoa, real_text, logical_text, quoted

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
    character(len=40) :: t
    integer :: p, e
    if (x /= x) then
      s = 'NaN'
      return
    else if (abs(x) > huge(x)) then
      s = merge('-Infinity', ' Infinity', x < 0.0_rp)
      s = trim(adjustl(s))
      return
    else if (x == 0.0_rp) then
      s = '0'
      return
    end if
    ! six significant digits, trailing zeros dropped: 0.5, 2500, -1.0e+09
    write(t, '(es14.5e3)') x
    p = index(t, 'E')
    read(t(p+1:), *) e
    if (e >= -4 .and. e < 6) then
      write(t, '(f0.'//itoa(5 - e)//')') x
      s = trim_zeros(trim(adjustl(t)))
      if (s(1:1) == '.') s = '0'//s
      if (s(1:2) == '-.') s = '-0'//s(2:)
    else
      s = trim_zeros(trim(adjustl(t(1:p-1))))
      if (index(s, '.') == 0) s = s//'.0'
      write(t, '(a,sp,i0.2)') 'e', e
      s = s//trim(adjustl(t))
    end if
  end function rtoa

  !> Decimal text without the zeros that end its fraction ('2.50' -> '2.5',
  !> '3.000' -> '3').
  function trim_zeros(t) result(s)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: s
    integer :: n
    s = t
    if (index(s, '.') == 0) return
    n = len(s)
    do while (n > 1 .and. s(n:n) == '0')
      n = n - 1
    end do
    if (s(n:n) == '.') n = n - 1
    s = s(1:n)
  end function trim_zeros

  !> A real as the shortest text that reads back as the very same double
  !> (bit for bit), in a form a person reads at a glance: plain decimals for
  !> magnitudes from 1e-4 to below 1e6 (0.25, 2500, 1.1), otherwise a
  !> mantissa and a two-digit exponent at least (1.0e+10, 2.5e-12). Valid as
  !> a value in a namelist deck.
  function real_text(x) result(s)
    real(rp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=40) :: t
    integer :: d, e, ios
    if (x /= x .or. abs(x) > huge(x)) then
      write(t, '(g0)') x                      ! NaN or Infinity: no short form
      s = trim(adjustl(t))
      return
    end if
    ! the fewest significant digits d that read back exactly (17 always do)
    do d = 1, 17
      write(t, '(es40.' // itoa(d - 1) // 'e3)') x
      if (same_bits(t, x)) exit
    end do
    read(t(index(t, 'E') + 1:), *, iostat=ios) e
    if (x == 0.0_rp) e = 0
    if (e >= -4 .and. e < 6) then
      write(t, '(f40.' // itoa(max(d - 1 - e, 0)) // ')') x
      s = trim(adjustl(t))
      if (index(s, '.') > 0) then
        do while (s(len(s):len(s)) == '0')
          s = s(1:len(s) - 1)
        end do
        if (s(len(s):len(s)) == '.') s = s(1:len(s) - 1)
      end if
      if (s(1:1) == '.') s = '0'//s
      if (len(s) > 1) then
        if (s(1:2) == '-.') s = '-0'//s(2:)
      end if
    else
      write(t, '(es40.' // itoa(max(d - 1, 1)) // 'e3)') x
      s = trim(adjustl(t))
      s = mantissa_exponent(s)
    end if
    if (.not. same_bits(s, x)) then
      write(t, '(es24.16e3)') x               ! never expected; exact all the same
      s = trim(adjustl(t))
    end if
  end function real_text

  !> 'd.dddE+eee' as 'd.ddde+ee' (at least two exponent digits).
  function mantissa_exponent(es) result(s)
    character(len=*), intent(in) :: es
    character(len=:), allocatable :: s
    integer :: p
    character :: sgn
    p = index(es, 'E')
    sgn = es(p+1:p+1)
    s = es(p+2:)
    do while (len(s) > 2 .and. s(1:1) == '0')
      s = s(2:)
    end do
    s = es(1:p-1)//'e'//sgn//s
  end function mantissa_exponent

  !> Whether text t reads as exactly x (sign of zero included).
  logical function same_bits(t, x)
    character(len=*), intent(in) :: t
    real(rp), intent(in) :: x
    real(rp) :: y
    integer :: ios
    read(t, *, iostat=ios) y
    same_bits = ios == 0
    if (same_bits) same_bits = transfer(y, 1_int64) == transfer(x, 1_int64)
  end function same_bits

  !> .true. or .false.
  function logical_text(l) result(s)
    logical, intent(in) :: l
    character(len=:), allocatable :: s
    s = merge('.true. ', '.false.', l)
    s = trim(s)
  end function logical_text

  !> s (trailing blanks removed) between single quotes, a quote inside
  !> doubled: a character value as a namelist reads it.
  function quoted(s) result(q)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: q
    integer :: i
    q = "'"
    do i = 1, len_trim(s)
      q = q//s(i:i)
      if (s(i:i) == "'") q = q//"'"
    end do
    q = q//"'"
  end function quoted

  !> s with the letters A-Z in lower case.
  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower
end module strings
