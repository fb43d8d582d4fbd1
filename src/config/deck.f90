!> The input deck: a file of Fortran namelist groups.
!>
!> Rank 0 reads the file (iostat/iomsg) and broadcasts its lines; every rank
!> then splits it into group blocks (a group may appear several times, e.g.
!> &material, &boundary) and reads each block from an internal file. So every
!> rank sees the same errors and can stop together. Error messages name the
!> deck, the group, the line and, where it can be found, the variable.
module deck
  use kinds, only: ip, rp, path_len, msg_len, name_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  implicit none
  private

  public :: deck_t, line_len, echo_len, unset_real, unset_int, is_set

  integer, parameter :: line_len = 256
  integer, parameter :: echo_len = 1024    !< records of a namelist written for the log
  !> Sentinels for values the deck did not set.
  real(rp), parameter :: unset_real = -huge(1.0_rp)
  integer, parameter :: unset_int = -huge(1)

  type :: deck_t
    character(len=path_len) :: path = ''
    character(len=line_len), allocatable :: lines(:)
    integer :: n_groups = 0
    character(len=name_len), allocatable :: group_name(:)
    integer, allocatable :: group_first(:), group_last(:)
  contains
    procedure :: load
    procedure :: count => count_groups
    procedure :: block
    procedure :: first_line
    procedure :: check_groups
    procedure :: read_error
    procedure :: fail
    procedure :: echo
  end type deck_t

  interface is_set
    module procedure is_set_real, is_set_int
  end interface is_set

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
    integer :: u, ios, n, i
    character(len=msg_len) :: msg
    character(len=4096) :: buf
    character(len=line_len), allocatable :: tmp(:)
    self%path = path
    n = 0
    msg = ''
    if (comm%is_root()) then
      allocate(tmp(256))
      open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
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
    call split_groups(self, status)
  end subroutine load

  !> Find the group blocks: from '&name' to the '/' that ends it (outside
  !> quotes and comments).
  subroutine split_groups(self, status)
    type(deck_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer :: i, j, k, cap
    character :: q, ch
    character(len=line_len) :: ln
    logical :: in_group
    character(len=msg_len) :: m
    cap = 16
    allocate(self%group_name(cap), self%group_first(cap), self%group_last(cap))
    in_group = .false.
    q = ' '
    do i = 1, size(self%lines)
      j = 0
      ln = self%lines(i)
      do while (j < len_trim(ln))
        j = j + 1
        ch = ln(j:j)
        if (q /= ' ') then
          if (ch == q) q = ' '
          cycle
        end if
        if (ch == '!') exit
        if (.not. in_group) then
          if (ch == '&') then
            k = j + 1
            do while (k <= len_trim(self%lines(i)))
              if (index('abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_', &
                        self%lines(i)(k:k)) == 0) exit
              k = k + 1
            end do
            if (self%n_groups == cap) then
              cap = 2 * cap
              self%group_name = [self%group_name, self%group_name]
              self%group_first = [self%group_first, self%group_first]
              self%group_last = [self%group_last, self%group_last]
            end if
            self%n_groups = self%n_groups + 1
            self%group_name(self%n_groups) = lower(self%lines(i)(j+1:k-1))
            self%group_first(self%n_groups) = i
            in_group = .true.
            j = k - 1
          else if (ch /= ' ' .and. ch /= char(9)) then
            write(m, '(a,i0,a)') "deck '"//trim(self%path)//"', line ", i, &
              ": text outside a namelist group (groups start with &name and end with /)"
            call status%set(m)
            return
          end if
        else
          if (ch == '"' .or. ch == "'") then
            q = ch
          else if (ch == '/') then
            self%group_last(self%n_groups) = i
            in_group = .false.
          else if (ch == '&') then
            write(m, '(a,i0,a)') "deck '"//trim(self%path)//"', line ", i, ": group &"// &
              trim(self%group_name(self%n_groups))//" is not closed with / before the next group"
            call status%set(m)
            return
          end if
        end if
      end do
    end do
    if (in_group) then
      call status%set("deck '"//trim(self%path)//"': group &"//trim(self%group_name(self%n_groups))// &
                      " is not closed with /")
    end if
  end subroutine split_groups

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower

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
        b(1) = b(1)(index(b(1), '&'):)
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
      if (index('abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_', s(b-1:b-1)) == 0) exit
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

  !> Write lines (e.g. a namelist written to an internal file) to the log.
  subroutine echo(self, log, lines)
    class(deck_t), intent(in) :: self
    type(logger_t), intent(inout) :: log
    character(len=*), intent(in) :: lines(:)
    integer :: i
    do i = 1, size(lines)
      if (len_trim(lines(i)) > 0) call log%detail('  '//trim(lines(i)))
    end do
  end subroutine echo
end module deck
