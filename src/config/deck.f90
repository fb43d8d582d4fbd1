!> The input deck: a file of Fortran namelist groups.
!>
!> Rank 0 reads the file (iostat/iomsg) and broadcasts its lines; every rank
!> then splits it into group blocks (a group may appear several times, e.g.
!> &material, &boundary) and reads each block from an internal file. So every
!> rank sees the same errors and can stop together. Error messages name the
!> deck, the group, the line and, where it can be found, the variable.
!>
!> The text is checked before any namelist read sees it, so that the
!> run-time library only ever reads well-formed groups: a scan of the whole
!> deck finds the groups and refuses, naming the group and the line, a
!> quoted string left open (it may go on over one line end only), a group
!> not closed with / before the next group or the end of the file, text
!> outside the groups and a stray '&'. Then a character string continued
!> on the next line is joined to its first line without the blanks that pad
!> the stored line (the end of a record is not part of a continued string,
!> Fortran 2008, 10.11.3.3), and every number must be finite (a namelist
!> read accepts nan, inf and 1e400 into a real as NaN or Infinity without a
!> word, and the checked build traps on the last): a check of every value
!> token of every group, whatever the variable's type.
module deck
  use kinds, only: ip, rp, path_len, msg_len, name_len
  use parallel_comm, only: parallel_comm_t
  use os_services, only: path_kind, path_directory
  use strings, only: itoa, lower
  use error_status, only: error_status_t
  use number_text, only: non_finite_word, numeric_literal, beyond_double
  implicit none
  private

  public :: deck_t, line_len, unset_real, unset_int, is_set

  integer, parameter :: line_len = 256
  character(len=*), parameter :: name_chars = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_'
  character(len=*), parameter :: letters = name_chars(1:52)
  character, parameter :: tab = achar(9)
  !> what ends a value token (gfortran also takes ';' as a separator)
  character(len=*), parameter :: token_end = ' ,=/!;&"'''//tab
  !> what may stand right before an opening quote, and right after a closing one
  character(len=*), parameter :: before_string = ' ,=*;'//tab, after_string = ' ,/!;'//tab
  !> Sentinels for values the deck did not set.
  real(rp), parameter :: unset_real = -huge(1.0_rp)
  integer, parameter :: unset_int = -huge(1)

  type :: deck_t
    character(len=path_len) :: path = ''
    character(len=line_len), allocatable :: lines(:)
    integer :: n_groups = 0
    character(len=name_len), allocatable :: group_name(:)
    !> lines of each group; the column of its '&' on its first line
    integer, allocatable :: group_first(:), group_last(:), group_col(:)
  contains
    procedure :: load
    procedure :: count => count_groups
    procedure :: block
    procedure :: first_line
    procedure :: check_groups
    procedure :: read_error
    procedure :: fail
    procedure :: assigned
    procedure :: input_path
  end type deck_t

  interface is_set
    module procedure is_set_real, is_set_int
  end interface is_set

  !> A value written in a group and the variable it is assigned to, or
  !> (is_name) the name of an assigned variable itself.
  type :: value_token_t
    character(len=:), allocatable :: text, var
    logical :: is_name = .false.
  end type value_token_t

  !> Where the scan of the deck's text (scan_groups) stands, and what an
  !> error there names.
  type :: text_scan_t
    logical :: in_group = .false.
    character :: q = ' '                  !< quote of the open string (' ': none)
    integer :: q_line = 0                 !< line where that string opened
    character(len=line_len) :: q_var = '' !< the variable it is assigned to
    character(len=line_len) :: var = ''   !< the variable assigned last in the group
    character :: last = ' '               !< last character of the group outside strings and comments
    integer :: ended = 0                  !< column of the '/' that ended a group on this line (0: none)
    integer :: i = 0, j = 0               !< line and column scanned
    character(len=line_len) :: ln = ''    !< line i
  end type text_scan_t

contains

  logical elemental function is_set_real(x)
    real(rp), intent(in) :: x
    is_set_real = x /= unset_real
  end function is_set_real

  logical elemental function is_set_int(x)
    integer, intent(in) :: x
    is_set_int = x /= unset_int
  end function is_set_int

  !> Read the deck at path on rank 0, broadcast it and split it into groups.
  !> Collective; status is the same on every rank.
  subroutine load(self, comm, path, status)
    class(deck_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    type(error_status_t), intent(inout) :: status
    integer :: u, ios, n, i, k
    character(len=msg_len) :: msg
    character(len=4096) :: buf
    character(len=line_len), allocatable :: tmp(:)
    self%path = path
    n = 0
    msg = ''
    if (comm%is_root()) then
      allocate(tmp(256))
      ios = 0
      if (path_kind(path) == path_directory) then
        ios = 1
        msg = 'it is a directory'
      end if
      if (ios == 0) open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios == 0) then
        do
          read(u, '(a)', iostat=ios, iomsg=msg) buf
          if (ios /= 0) exit
          if (len_trim(buf) > line_len) then
            write(msg, '(a,i0,a,i0,a)') 'line ', n + 1, ' is longer than ', line_len, ' characters'
            ios = 1
            exit
          end if
          n = n + 1
          if (n > size(tmp)) tmp = [tmp, tmp]
          ! a file written on Windows: a carriage return is a blank to a namelist read
          k = index(buf, achar(13))
          do while (k > 0)
            buf(k:k) = ' '
            k = index(buf, achar(13))
          end do
          tmp(n) = buf(1:line_len)
        end do
        close(u)
        if (ios < 0) ios = 0     ! end of file
      end if
      if (ios /= 0) n = -1
    end if
    call comm%bcast(n)
    call comm%bcast(msg)
    if (n < 0) then
      call status%set("cannot read deck '"//trim(path)//"': "//trim(msg))
      return
    end if
    allocate(self%lines(n))
    if (comm%is_root()) self%lines = tmp(1:n)
    do i = 1, n
      call comm%bcast(self%lines(i))
    end do
    call scan_groups(self, status)
    if (status%ok()) call join_strings(self, status)
    if (status%ok()) call check_numbers(self, status)
  end subroutine load

  !> A quoted string left open at the end of a line goes on at the start of
  !> the next: that text is moved up to the first line (the rest of the next
  !> line stays where it is, so line numbers keep their meaning). Runs after
  !> scan_groups, which made sure that every such string closes on the next
  !> line.
  subroutine join_strings(self, status)
    type(deck_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer :: i, j, n
    character :: q
    character(len=msg_len) :: m
    do i = 1, size(self%lines) - 1
      q = open_quote(self%lines(i), ' ')
      if (q == ' ') cycle
      n = len_trim(self%lines(i))
      j = string_end(self%lines(i + 1), q)
      if (j == 0) then
        call status%set("deck '"//trim(self%path)//"', line "//itoa(i)//": a quoted string is not closed")
        return
      end if
      if (n + j > line_len) then
        write(m, '(a,i0,a,i0,a)') "deck '"//trim(self%path)//"', line ", i, &
          ": a quoted string continued on the next line makes the line longer than ", line_len, " characters"
        call status%set(m)
        return
      end if
      self%lines(i)(n + 1:n + j) = self%lines(i + 1)(1:j)
      self%lines(i + 1) = repeat(' ', j)//self%lines(i + 1)(j + 1:)
    end do
  end subroutine join_strings

  !> Position in s of the quote q that closes a string open at the start of
  !> s (0 if none); a doubled quote stands for one and does not close it.
  pure integer function string_end(s, q)
    character(len=*), intent(in) :: s
    character, intent(in) :: q
    integer :: k, n
    string_end = 0
    n = len_trim(s)
    k = 1
    do while (k <= n)
      if (s(k:k) == q) then
        if (k == n) exit
        if (s(k+1:k+1) /= q) exit
        k = k + 1
      end if
      k = k + 1
    end do
    if (k <= n) string_end = k
  end function string_end

  !> The quote character still open at the end of line s (' ' if none),
  !> given the one open at its start; a '!' outside quotes ends the scan.
  pure function open_quote(s, q0) result(q)
    character(len=*), intent(in) :: s
    character, intent(in) :: q0
    character :: q
    integer :: k
    q = q0
    do k = 1, len_trim(s)
      if (q /= ' ') then
        if (s(k:k) == q) q = ' '
      else if (s(k:k) == '"' .or. s(k:k) == "'") then
        q = s(k:k)
      else if (s(k:k) == '!') then
        return
      end if
    end do
  end function open_quote

  !> Every number in the groups must be finite: a value token that is nan,
  !> inf or infinity (any case, signed or not), or a numeric literal that
  !> overflows to infinity, is an error naming the group and the variable.
  subroutine check_numbers(self, status)
    type(deck_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer :: g, v
    type(value_token_t), allocatable :: vals(:)
    do g = 1, self%n_groups
      call group_values(self, g, vals)
      do v = 1, size(vals)
        if (vals(v)%is_name) cycle
        associate(tok => vals(v)%text)
          if (non_finite_word(tok)) then
            call self%fail(status, self%group_name(g), occurrence(self, g), vals(v)%var, &
                           "'"//tok//"' is not a finite number")
            return
          end if
          if (.not. numeric_literal(tok)) cycle
          if (beyond_double(tok)) then
            call self%fail(status, self%group_name(g), occurrence(self, g), vals(v)%var, &
                           "'"//tok//"' is out of the range of double precision numbers")
            return
          end if
        end associate
      end do
    end do
  end subroutine check_numbers

  !> The tokens of group g (unquoted, outside comments): the names of the
  !> assigned variables and the values (a repeat count r* removed), each
  !> with the variable it is assigned to.
  subroutine group_values(self, g, vals)
    type(deck_t), intent(in) :: self
    integer, intent(in) :: g
    type(value_token_t), allocatable, intent(out) :: vals(:)
    integer :: i, j, k, n
    character :: q
    character(len=line_len) :: ln
    character(len=:), allocatable :: tok, var
    allocate(vals(16))
    n = 0
    var = '?'
    q = ' '
    do i = self%group_first(g), self%group_last(g)
      ln = self%lines(i)
      j = 0
      if (i == self%group_first(g)) then
        ! skip '&' and the group's name
        j = self%group_col(g)
        do while (j < len_trim(ln))
          if (index(name_chars, ln(j+1:j+1)) == 0) exit
          j = j + 1
        end do
      end if
      do while (j < len_trim(ln))
        j = j + 1
        if (q /= ' ') then
          if (ln(j:j) == q) q = ' '
          cycle
        end if
        if (ln(j:j) == '"' .or. ln(j:j) == "'") then
          q = ln(j:j)
          cycle
        end if
        if (ln(j:j) == '!' .or. ln(j:j) == '/') exit
        if (index(' ,=;'//tab, ln(j:j)) > 0) cycle
        k = token_last(ln, j)
        tok = ln(j:k)
        j = k
        if (n == size(vals)) vals = [vals, vals]
        n = n + 1
        if (followed_by_equals(ln, k)) then
          var = tok
          if (index(var, '(') > 1) var = var(1:index(var, '(') - 1)
          vals(n) = value_token_t(text='', var=var, is_name=.true.)
          cycle
        end if
        if (index(tok, '*') > 0) tok = tok(index(tok, '*') + 1:)
        ! the whole token: vals grew by copies, whose is_name may be true
        vals(n) = value_token_t(text=tok, var=var, is_name=.false.)
      end do
    end do
    vals = vals(1:n)
  end subroutine group_values



  !> Whether the token ending at position k of s is followed by '=' (then it
  !> names a variable, possibly with an array section).
  pure logical function followed_by_equals(s, k)
    character(len=*), intent(in) :: s
    integer, intent(in) :: k
    integer :: e
    followed_by_equals = .false.
    e = k + 1
    do while (e <= len_trim(s))
      if (s(e:e) /= ' ' .and. s(e:e) /= char(9)) exit
      e = e + 1
    end do
    if (e <= len_trim(s)) followed_by_equals = s(e:e) == '='
  end function followed_by_equals


  !> Which occurrence of its name group g is (1 for the first).
  integer function occurrence(self, g)
    type(deck_t), intent(in) :: self
    integer, intent(in) :: g
    occurrence = count(self%group_name(1:g) == self%group_name(g))
  end function occurrence

  !> The last position of the token that starts at position j of s.
  pure integer function token_last(s, j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: j
    token_last = j
    do while (token_last < len_trim(s))
      if (index(token_end, s(token_last+1:token_last+1)) > 0) exit
      token_last = token_last + 1
    end do
  end function token_last

  !> Find the group blocks, from '&name' to the '/' that ends it outside
  !> quotes and comments, and refuse the text a namelist read could not take
  !> or could mistake: a quoted string not closed on its line or the next
  !> (or closed right before more text), a group not closed before the next
  !> one or the end of the file, text outside the groups, a stray '&'.
  !> Every error names the group, the line and, where it is known, the
  !> variable.
  subroutine scan_groups(self, status)
    type(deck_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    type(text_scan_t) :: s
    integer :: n
    allocate(self%group_name(16), self%group_first(16), self%group_last(16), self%group_col(16))
    do while (s%i < size(self%lines))
      s%i = s%i + 1
      s%ln = self%lines(s%i)
      if (s%q /= ' ') call continued_string(self, s, status)
      s%ended = 0
      n = len_trim(s%ln)
      s%j = 0
      do while (s%j < n .and. status%ok())
        s%j = s%j + 1
        if (s%q /= ' ') then
          call string_char(self, s, status)
        else if (s%ln(s%j:s%j) == '!') then
          exit
        else if (s%in_group) then
          call group_char(self, s, status)
        else
          call outside_char(self, s, status)
        end if
      end do
      if (.not. status%ok()) return
      if (s%q /= ' ' .and. s%q_line < s%i) then
        call scan_fail(self, s%q_var, 'the quoted string opened on line '//itoa(s%q_line)// &
                       ' is not closed on that line or the next', status)
        return
      end if
    end do
    if (s%q /= ' ') then
      call scan_fail(self, s%q_var, 'the quoted string opened on line '//itoa(s%q_line)// &
                     ' is not closed before the end of the file', status)
    else if (s%in_group .and. (s%last == '=' .or. s%last == ',')) then
      call scan_fail(self, s%var, 'the file ends (line '//itoa(size(self%lines))// &
                     ') in its value; the group is not closed with /', status)
    else if (s%in_group) then
      call scan_fail(self, '', 'the group is not closed with / before the end of the file (line '// &
                     itoa(size(self%lines))//')', status)
    end if
  end subroutine scan_groups

  !> The line goes on with a string left open at the end of the line before:
  !> it must not be where a group ends or starts (then the string is what
  !> was not closed).
  subroutine continued_string(self, s, status)
    type(deck_t), intent(in) :: self
    type(text_scan_t), intent(in) :: s
    type(error_status_t), intent(inout) :: status
    character(len=line_len) :: t
    t = adjustl(s%ln)
    if (t(1:1) == '/' .and. index(' !', t(2:2)) > 0) then
      call scan_fail(self, s%q_var, 'the quoted string opened on line '//itoa(s%q_line)// &
                     " is not closed before the '/' on line "//itoa(s%i), status)
    else if (t(1:1) == '&' .and. index(letters, t(2:2)) > 0) then
      call scan_fail(self, s%q_var, 'the quoted string opened on line '//itoa(s%q_line)// &
                     ' is not closed before group '//trim(t(1:token_last(t, 2)))//' on line '//itoa(s%i), status)
    end if
  end subroutine continued_string

  !> Character j inside a quoted string: the string's quote closes it unless
  !> doubled; what follows must end the value.
  subroutine string_char(self, s, status)
    type(deck_t), intent(in) :: self
    type(text_scan_t), intent(inout) :: s
    type(error_status_t), intent(inout) :: status
    integer :: j, n
    j = s%j
    n = len_trim(s%ln)
    if (s%ln(j:j) /= s%q) return
    if (j < n) then
      if (s%ln(j+1:j+1) == s%q) then
        s%j = j + 1
        return
      end if
    end if
    s%q = ' '
    s%last = s%ln(j:j)
    if (j == n) return
    ! the value must end there: a separator, a comment, the next value of
    ! a list or the next assignment (a quote further on in a comment, an
    ! apostrophe, is no closing one)
    if (index(after_string, s%ln(j+1:j+1)) > 0 .and. ends_value(s%ln, j + 1)) return
    call scan_fail(self, s%q_var, 'the quoted string opened on line '//itoa(s%q_line)//' ends on line '// &
                   itoa(s%i)//" right before '"//s%ln(j+1:min(n, token_last(s%ln, j+1), j+20))// &
                   "' (a quote missing, or one too many?)", status)
  end subroutine string_char

  !> What follows column k of line ln ends a value: nothing, a separator
  !> (',', '/', '!', ';'), the next string of a list or the next assignment
  !> (name, optional subscripts, '=') after blanks.
  pure logical function ends_value(ln, k)
    character(len=*), intent(in) :: ln
    integer, intent(in) :: k
    integer :: i, n
    n = len_trim(ln)
    i = k
    do while (i <= n)
      if (ln(i:i) /= ' ' .and. ln(i:i) /= tab) exit
      i = i + 1
    end do
    ends_value = i > n
    if (ends_value) return
    ends_value = index(',/!;''"', ln(i:i)) > 0
    if (ends_value .or. index(letters, ln(i:i)) == 0) return
    do while (i <= n)
      if (index(name_chars, ln(i:i)) == 0) exit
      i = i + 1
    end do
    if (i <= n) then
      if (ln(i:i) == '(') i = i + index(ln(i:n), ')')
    end if
    do while (i <= n)
      if (ln(i:i) /= ' ' .and. ln(i:i) /= tab) exit
      i = i + 1
    end do
    ends_value = i <= n
    if (ends_value) ends_value = ln(i:i) == '='
  end function ends_value

  !> Character j inside a group, outside strings: a quote opens a string,
  !> '/' ends the group, a name followed by '=' is the variable assigned
  !> next; '&' is refused.
  subroutine group_char(self, s, status)
    type(deck_t), intent(inout) :: self
    type(text_scan_t), intent(inout) :: s
    type(error_status_t), intent(inout) :: status
    integer :: j, k
    character :: ch
    j = s%j
    ch = s%ln(j:j)
    if (ch == ' ' .or. ch == tab) return
    if (ch == '"' .or. ch == "'") then
      if (j > 1 .and. index(before_string, s%ln(max(j-1, 1):max(j-1, 1))) == 0) then
        k = j - 1
        do while (k > 1)
          if (index(token_end, s%ln(k-1:k-1)) > 0) exit
          k = k - 1
        end do
        call scan_fail(self, s%var, 'a quote right after '''//s%ln(max(k, j-40):j-1)//''' on line '//itoa(s%i)// &
                       ' (a quote missing, or one too many?)', status)
        return
      end if
      s%q = ch
      s%q_line = s%i
      s%q_var = s%var
    else if (ch == '/') then
      self%group_last(self%n_groups) = s%i
      s%in_group = .false.
      s%ended = j
    else if (ch == '&') then
      if (index(letters, s%ln(min(j+1, line_len):min(j+1, line_len))) > 0) then
        call scan_fail(self, '', 'the group is not closed with / before group '//s%ln(j:token_last(s%ln, j+1))// &
                       ' on line '//itoa(s%i), status)
      else
        call scan_fail(self, s%var, "'&' on line "//itoa(s%i)//' outside quotes (values go on over lines'// &
                       ' without a continuation mark; a group ends with /)', status)
      end if
      return
    else if (index(token_end, ch) == 0) then
      k = token_last(s%ln, j)
      if (followed_by_equals(s%ln, k)) then
        s%var = s%ln(j:k)
        if (index(s%var, '(') > 1) s%var = s%var(1:index(s%var, '(') - 1)
      end if
      s%j = k
    end if
    s%last = s%ln(s%j:s%j)
  end subroutine group_char

  !> Character j outside the groups: '&name' starts a group; anything else
  !> is refused.
  subroutine outside_char(self, s, status)
    type(deck_t), intent(inout) :: self
    type(text_scan_t), intent(inout) :: s
    type(error_status_t), intent(inout) :: status
    integer :: j, k
    j = s%j
    if (s%ln(j:j) == ' ' .or. s%ln(j:j) == tab) return
    if (s%ln(j:j) /= '&') then
      if (s%ended > 0) then
        call scan_fail(self, s%var, "the '/' on line "//itoa(s%i)//' ends the group, and text follows: '''// &
                       s%ln(j:min(len_trim(s%ln), j + 40))//''' (is a quote missing?)', status)
      else if (self%n_groups > 0) then
        call status%set("deck '"//trim(self%path)//"', line "//itoa(s%i)//': text outside a namelist group'// &
          ' (after group &'//trim(self%group_name(self%n_groups))//' of line '// &
          itoa(self%group_first(self%n_groups))//'; groups start with &name and end with /)')
      else
        call status%set("deck '"//trim(self%path)//"', line "//itoa(s%i)// &
          ': text outside a namelist group (groups start with &name and end with /)')
      end if
      return
    end if
    k = j + 1
    do while (k <= len_trim(s%ln))
      if (index(name_chars, s%ln(k:k)) == 0) exit
      k = k + 1
    end do
    if (k == j + 1) then
      call status%set("deck '"//trim(self%path)//"', line "//itoa(s%i)// &
        ": '&' without a group name (groups start with &name and end with /)")
      return
    end if
    if (self%n_groups == size(self%group_name)) then
      self%group_name = [self%group_name, self%group_name]
      self%group_first = [self%group_first, self%group_first]
      self%group_last = [self%group_last, self%group_last]
      self%group_col = [self%group_col, self%group_col]
    end if
    self%n_groups = self%n_groups + 1
    self%group_name(self%n_groups) = lower(s%ln(j+1:k-1))
    self%group_first(self%n_groups) = s%i
    self%group_col(self%n_groups) = j
    s%in_group = .true.
    s%var = ''
    s%last = ' '
    s%j = k - 1
  end subroutine outside_char

  !> An error of the scan in the last group found: "deck 'path', group
  !> &name (line of its start)[, variable var]: what".
  subroutine scan_fail(self, var, what, status)
    type(deck_t), intent(in) :: self
    character(len=*), intent(in) :: var, what
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: m
    m = "deck '"//trim(self%path)//"', group &"//trim(self%group_name(self%n_groups))//' (line '// &
        itoa(self%group_first(self%n_groups))//')'
    if (len_trim(var) > 0) m = m//', variable '//trim(var)
    call status%set(m//': '//what)
  end subroutine scan_fail

  !> Number of occurrences of group name.
  integer function count_groups(self, name)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name
    count_groups = 0
    if (self%n_groups > 0) count_groups = count(self%group_name(1:self%n_groups) == name)
  end function count_groups

  !> Lines of the k-th occurrence of group name (text before '&' on its first
  !> line and after its last line is not included).
  subroutine block(self, name, k, b)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: k
    character(len=line_len), allocatable, intent(out) :: b(:)
    integer :: g, n, first, last
    n = 0
    do g = 1, self%n_groups
      if (self%group_name(g) /= name) cycle
      n = n + 1
      if (n == k) then
        first = self%group_first(g)
        last = self%group_last(g)
        b = self%lines(first:last)
        b(1) = b(1)(self%group_col(g):)
        return
      end if
    end do
    allocate(b(0))
  end subroutine block

  !> Deck line where the k-th occurrence of group name starts.
  integer function first_line(self, name, k)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: k
    integer :: g, n
    first_line = 0
    n = 0
    do g = 1, self%n_groups
      if (self%group_name(g) /= name) cycle
      n = n + 1
      if (n == k) first_line = self%group_first(g)
    end do
  end function first_line

  !> Every group must be one of known(:); single ones at most once.
  subroutine check_groups(self, known, repeatable, status)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: known(:), repeatable(:)
    type(error_status_t), intent(inout) :: status
    integer :: g
    character(len=msg_len) :: m
    do g = 1, self%n_groups
      if (.not. any(known == self%group_name(g))) then
        write(m, '(a,i0,a)') "deck '"//trim(self%path)//"', line ", self%group_first(g), ": unknown group &"// &
          trim(self%group_name(g))//" (known groups: "//join(known)//")"
        call status%set(m)
        return
      end if
      if (.not. any(repeatable == self%group_name(g)) .and. self%count(self%group_name(g)) > 1) then
        write(m, '(a)') "deck '"//trim(self%path)//"': group &"//trim(self%group_name(g))// &
          " appears more than once"
        call status%set(m)
        return
      end if
    end do
  end subroutine check_groups

  function join(words) result(s)
    character(len=*), intent(in) :: words(:)
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(words)
      if (i > 1) s = s//', '
      s = s//trim(words(i))
    end do
  end function join

  !> Turn a failed namelist read into a message naming the variable.
  !> gfortran reports the token it could not match; if that token is followed
  !> by '=' it is an unknown variable, otherwise a bad value of the variable
  !> assigned before it.
  subroutine read_error(self, name, k, ios, iomsg, status)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name, iomsg
    integer, intent(in) :: k, ios
    type(error_status_t), intent(inout) :: status
    character(len=line_len), allocatable :: b(:)
    character(len=:), allocatable :: text, tok
    integer :: p, e, i, l0
    character(len=msg_len) :: m, where
    l0 = self%first_line(name, k)
    write(where, '(a,i0)') "deck '"//trim(self%path)//"', group &"//trim(name)//" (line ", l0
    if (index(iomsg, 'Integer overflow') > 0) then
      call integer_overflow(self, name, k, trim(where), status)
      if (.not. status%ok()) return
    end if
    p = index(iomsg, 'object name ')
    if (p == 0) then
      write(m, '(a,i0,a)') trim(where)//"): "//trim(iomsg)//" (iostat ", ios, ")"
      call status%set(m)
      return
    end if
    tok = trim(adjustl(iomsg(p + 12:)))
    call self%block(name, k, b)
    text = ''
    do i = 1, size(b)
      text = text//' '//trim(strip_comment(b(i)))
    end do
    p = index(lower(text), lower(tok))
    if (p > 0) then
      e = p + len(tok)
      do while (e <= len(text))
        if (text(e:e) /= ' ') exit
        e = e + 1
      end do
      if (e <= len(text)) then
        if (text(e:e) == '=' .or. text(e:e) == '(' .or. text(e:e) == '%') then
          write(m, '(a)') trim(where)//"): unknown variable '"//tok//"'"
          call status%set(m)
          return
        end if
      end if
      if (tok(1:1) /= "'" .and. tok(1:1) /= '"') tok = "'"//tok//"'"
      write(m, '(a)') trim(where)//"): variable '"//trim(last_name(text(1:p-1)))// &
        "' has a value of the wrong type or form: "//tok
      call status%set(m)
      return
    end if
    write(m, '(a)') trim(where)//"): "//trim(iomsg)
    call status%set(m)
  end subroutine read_error

  !> Name the variable whose integer value does not fit (status set when one
  !> is found): the first whole-number token beyond the default integer range.
  subroutine integer_overflow(self, name, k, where, status)
    type(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name, where
    integer, intent(in) :: k
    type(error_status_t), intent(inout) :: status
    type(value_token_t), allocatable :: vals(:)
    integer :: g, n, v, ios, gk
    real(rp) :: x
    allocate(vals(0))
    n = 0
    gk = 0
    do g = 1, self%n_groups
      if (self%group_name(g) /= name) cycle
      n = n + 1
      if (n == k) gk = g
    end do
    if (gk == 0) return
    call group_values(self, gk, vals)
    do v = 1, size(vals)
      if (vals(v)%is_name .or. verify(vals(v)%text, '+-0123456789') /= 0) cycle
      read(vals(v)%text, *, iostat=ios) x
      if (ios /= 0) cycle
      if (abs(x) > real(huge(1), rp)) then
        call status%set(where//"), variable "//vals(v)%var//": "//vals(v)%text// &
                        " is out of the integer range (at most 2147483647 in magnitude)")
        return
      end if
    end do
  end subroutine integer_overflow

  !> The last "name =" in s.
  function last_name(s) result(v)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: v
    integer :: e, b
    v = '?'
    e = index(s, '=', back=.true.)
    if (e == 0) return
    e = e - 1
    do while (e > 0)
      if (s(e:e) /= ' ') exit
      e = e - 1
    end do
    if (e > 0) then
      if (s(e:e) == ')') e = index(s(1:e), '(', back=.true.) - 1
    end if
    b = e
    do while (b > 1)
      if (index(name_chars, s(b-1:b-1)) == 0) exit
      b = b - 1
    end do
    if (e >= b .and. b >= 1) v = s(b:e)
  end function last_name

  !> The line without a trailing '!' comment (quotes respected).
  function strip_comment(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    character :: q
    t = s
    q = ' '
    do i = 1, len_trim(s)
      if (q /= ' ') then
        if (s(i:i) == q) q = ' '
      else if (s(i:i) == '"' .or. s(i:i) == "'") then
        q = s(i:i)
      else if (s(i:i) == '!') then
        t = s(1:i-1)
        return
      end if
    end do
  end function strip_comment

  !> Record a semantic error (missing or out-of-range value) for a variable.
  subroutine fail(self, status, name, k, var, what)
    class(deck_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    character(len=*), intent(in) :: name, var, what
    integer, intent(in) :: k
    character(len=msg_len) :: m
    if (.not. status%ok()) return     ! keep the first error
    write(m, '(a,i0,a)') "deck '"//trim(self%path)//"', group &"//trim(name)//" (line ", &
      self%first_line(name, k), "), variable "//trim(var)//": "//trim(what)
    call status%set(m)
  end subroutine fail

  !> An input file named by variable var of the k-th group name, resolved
  !> against the deck's own directory (an absolute path stays as it is), so
  !> that a deck and its mesh or tables can be moved together and run from
  !> anywhere. Refused, naming the variable, when the result would not fit
  !> path_len characters (nothing is cut).
  subroutine input_path(self, name, k, var, path, resolved, status)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name, var, path
    integer, intent(in) :: k
    character(len=*), intent(out) :: resolved
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: full
    integer :: slash
    resolved = ''
    if (len_trim(path) == 0) return
    slash = index(self%path, '/', back=.true.)
    if (path(1:1) == '/' .or. slash == 0) then
      full = trim(path)
    else
      full = self%path(1:slash)//trim(path)
    end if
    if (len(full) > len(resolved)) then
      call self%fail(status, name, k, var, "'"//trim(path)//"' relative to the deck's directory is longer than "// &
                     itoa(len(resolved))//' characters')
      return
    end if
    resolved = full
  end subroutine input_path

  !> Whether the k-th occurrence of group name assigns variable var (any
  !> case, with or without an array section).
  logical function assigned(self, name, k, var)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: name, var
    integer, intent(in) :: k
    type(value_token_t), allocatable :: vals(:)
    integer :: g, n
    assigned = .false.
    allocate(vals(0))
    n = 0
    do g = 1, self%n_groups
      if (self%group_name(g) /= name) cycle
      n = n + 1
      if (n /= k) cycle
      call group_values(self, g, vals)
      assigned = any([(vals(n)%is_name .and. lower(vals(n)%var) == lower(var), n = 1, size(vals))])
      return
    end do
  end function assigned
end module deck
