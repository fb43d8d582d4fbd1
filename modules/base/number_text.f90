!> Numbers as text, judged before they are converted: whether a token is a
!> real literal, names a non-finite value (nan, inf) or lies beyond the
!> double range (1e400). The checked build traps floating-point overflow and
!> invalid operations, and the run-time's conversion of such text can raise
!> them, so input readers look at the text first and convert only what is
!> known to be a finite double.
module number_text
  use kinds, only: rp
  use strings, only: lower
  implicit none
  private

  public :: non_finite_word, numeric_literal, beyond_double, real_token_problem

contains

  !> nan, inf, infinity with an optional sign or payload, any case.
  pure logical function non_finite_word(tok)
    character(len=*), intent(in) :: tok
    character(len=len(tok)) :: t
    integer :: b
    t = lower(tok)
    b = 1
    if (len(t) == 0) then
      non_finite_word = .false.
      return
    end if
    if (t(1:1) == '+' .or. t(1:1) == '-') b = 2
    non_finite_word = .false.
    if (b > len(t)) return
    non_finite_word = t(b:) == 'nan' .or. t(b:) == 'inf' .or. t(b:) == 'infinity' .or. index(t(b:), 'nan(') == 1
  end function non_finite_word

  !> Whether tok is made of the characters of a Fortran numeric literal
  !> (sign, digits, point, exponent letter e, d or q) with at least one digit.
  pure logical function numeric_literal(tok)
    character(len=*), intent(in) :: tok
    numeric_literal = .false.
    if (len(tok) == 0) return
    if (verify(tok(1:1), '+-.0123456789') /= 0) return
    numeric_literal = verify(lower(tok), '+-.0123456789edq') == 0 .and. scan(tok, '0123456789') > 0
  end function numeric_literal

  !> Whether the numeric literal tok is larger in magnitude than the largest
  !> double (about 1.8e308), found from its digits and exponent without
  !> arithmetic that could overflow (the checked build traps overflow).
  !> The exponent may follow e, d or q, or only its sign (1.0+400: the
  !> run-time reads that as 1.0e400, F editing).
  logical function beyond_double(tok)
    character(len=*), intent(in) :: tok
    character(len=len(tok)) :: t, mant
    integer :: e, p, expo, mag, k, first
    logical :: huge_expo
    real(rp) :: lead
    beyond_double = .false.
    t = lower(tok)
    e = scan(t, 'edq')
    if (e == 0 .and. len_trim(t) > 1) then
      e = scan(t(2:), '+-')
      if (e > 0) e = e + 1
    end if
    expo = 0
    huge_expo = .false.
    mant = t
    if (e > 0) then
      if (scan(t(e:e), 'edq') > 0) then
        call exponent_value(t(e+1:), expo, huge_expo)
      else
        call exponent_value(t(e:), expo, huge_expo)
      end if
      mant = t(1:e-1)
    end if
    if (mant(1:1) == '+' .or. mant(1:1) == '-') mant = mant(2:)
    ! magnitude: position of the first non-zero digit relative to the point
    first = scan(mant, '123456789')
    if (first == 0) return                      ! zero
    if (huge_expo) then
      beyond_double = expo > 0
      return
    end if
    p = index(mant, '.')
    if (p == 0) p = len_trim(mant) + 1
    if (first < p) then
      mag = p - first - 1 + expo
    else
      mag = p - first + expo
    end if
    if (mag > 308) beyond_double = .true.
    if (mag /= 308) return
    ! 308: compare the leading digits d.ddd with 1.7976931348623157
    lead = 0.0_rp
    do k = len_trim(mant), first, -1
      if (mant(k:k) == '.') cycle
      lead = lead / 10.0_rp + real(iachar(mant(k:k)) - iachar('0'), rp)
    end do
    beyond_double = lead > 1.7976931348623157_rp
  end function beyond_double

  !> The value of an exponent s (an optional sign, then digits); one of more
  !> than six digits is huge (only its sign, +-1 in expo, matters) and is
  !> not converted, which could overflow an integer. Not digits: expo 0.
  pure subroutine exponent_value(s, expo, huge_expo)
    character(len=*), intent(in) :: s
    integer, intent(out) :: expo
    logical, intent(out) :: huge_expo
    integer :: b, k, sgn
    expo = 0
    huge_expo = .false.
    b = 1
    sgn = 1
    if (len_trim(s) == 0) return
    if (s(1:1) == '+' .or. s(1:1) == '-') then
      if (s(1:1) == '-') sgn = -1
      b = 2
    end if
    if (b > len_trim(s)) return
    if (verify(s(b:len_trim(s)), '0123456789') /= 0) return
    do while (b < len_trim(s) .and. s(b:b) == '0')
      b = b + 1
    end do
    if (len_trim(s) - b + 1 > 6) then
      huge_expo = .true.
      expo = sgn
      return
    end if
    do k = b, len_trim(s)
      expo = 10 * expo + iachar(s(k:k)) - iachar('0')
    end do
    expo = sgn * expo
  end subroutine exponent_value

  !> Why the token tok is not a finite double ('' when it is one): not a
  !> finite number (nan, inf), out of the double range, or not a number.
  !> A token that passes converts with list-directed input without raising
  !> a floating-point exception the checked build traps.
  function real_token_problem(tok) result(why)
    character(len=*), intent(in) :: tok
    character(len=:), allocatable :: why
    real(rp) :: x
    integer :: ios
    why = ''
    if (non_finite_word(tok)) then
      why = 'is not a finite number'
    else if (.not. numeric_literal(tok)) then
      why = 'is not a number'
    else if (beyond_double(tok)) then
      why = 'is out of the range of double precision numbers'
    else
      read(tok, *, iostat=ios) x
      if (ios /= 0) why = 'is not a number'
    end if
  end function real_token_problem
end module number_text
