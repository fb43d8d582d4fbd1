!> The resolved parameters of one deck group, as the run uses them: each
!> variable with its value, its unit and a one-line meaning. The one helper
!> behind both the log echo (echo) and the written deck <prefix>_parameters.nml
!> (lines): each config type fills a param_group_t with its describe method.
!>
!> Values are texts made by module strings: reals in the shortest form
!> that reads back bit for bit (real_text), so a written deck reproduces
!> the run exactly. A value the run leaves unset (an optional variable
!> whose absence means something, e.g. dt_max: no limit) is kept with what
!> its absence means: the echo shows that meaning, the written deck a
!> comment line (writing a number would set it).
!>
!> For the deck reference (geoblock --reference, doc/reference/decks.md)
!> each variable also carries its kind (inferred from the add procedure:
!> 'real', 'integer(3)', 'string', ...; add_unset names it) and the values
!> it allows ('> 0', "'box' or 'gmsh'"), and a group a one-line account of
!> itself (init's about). Neither is written into the echo or the deck.
module param_group
  use kinds, only: rp, name_len, path_len
  use logger, only: logger_t
  use strings, only: itoa, real_text, logical_text, quoted
  implicit none
  private

  public :: push_line, param_group_t, param_line_len, base_name

  !> length of the lines returned by lines() (the deck reader takes 256)
  integer, parameter :: param_line_len = 256
  !> values longer than this go on over several lines
  integer, parameter :: wrap_at = 160
  !> length of a piece of a value (a whole path fits)
  integer, parameter :: piece_len = path_len + 16

  type :: param_t
    character(len=:), allocatable :: name, value, unit, meaning
    character(len=:), allocatable :: kind      !< 'real', 'integer(3)', 'string', 'real list', ...
    character(len=:), allocatable :: allowed   !< the values the reader accepts ('' unstated)
    logical :: set = .true.        !< false: value is the meaning of its absence
  end type param_t

  type :: param_group_t
    character(len=name_len) :: name = ''
    !> one line on what the group is (fixed length: gfortran 12 copies a
    !> deferred-length component of an array element shallowly)
    character(len=256) :: about = ''
    type(param_t), allocatable :: p(:)
    integer :: n = 0
  contains
    procedure :: init
    procedure, private :: add_real, add_reals, add_int, add_ints, add_logical, add_string, add_strings
    generic :: add => add_real, add_reals, add_int, add_ints, add_logical, add_string, add_strings
    procedure :: add_unset
    procedure :: add_bounds
    procedure :: add_optional
    procedure :: drop
    procedure :: echo
    procedure :: lines
    procedure, private :: push
  end type param_group_t

contains

  !> An empty group called name (without '&'); about: one line on what it
  !> is, for the deck reference.
  subroutine init(self, name, about)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    character(len=*), intent(in), optional :: about
    self%name = name
    self%about = ''
    if (present(about)) self%about = about
    self%n = 0
    if (allocated(self%p)) deallocate(self%p)
    allocate(self%p(16))
  end subroutine init

  subroutine push(self, name, value, unit, meaning, set, kind, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, value, unit, meaning, kind
    logical, intent(in) :: set
    character(len=*), intent(in), optional :: allowed
    type(param_t), allocatable :: tmp(:)
    character(len=:), allocatable :: a
    if (.not. allocated(self%p)) allocate(self%p(16))
    if (self%n == size(self%p)) then
      allocate(tmp(2 * self%n))
      tmp(1:self%n) = self%p(1:self%n)
      call move_alloc(tmp, self%p)
    end if
    a = ''
    if (present(allowed)) a = allowed
    self%n = self%n + 1
    self%p(self%n) = param_t(name=name, value=value, unit=unit, meaning=meaning, kind=kind, allowed=a, set=set)
  end subroutine push

  !> A real variable; unit without brackets ('Pa', 'm^2', '-'); allowed:
  !> the values the reader accepts, e.g. '> 0' (every add procedure takes it).
  subroutine add_real(self, name, x, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    real(rp), intent(in) :: x
    character(len=*), intent(in), optional :: allowed
    call self%push(name, real_text(x), unit, meaning, .true., 'real', allowed)
  end subroutine add_real

  !> An array of reals; kind: 'real(n)' with n its size unless given (a
  !> list of any length: 'real list').
  subroutine add_reals(self, name, x, unit, meaning, allowed, kind)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    real(rp), intent(in) :: x(:)
    character(len=*), intent(in), optional :: allowed, kind
    character(len=:), allocatable :: v
    integer :: i
    v = ''
    do i = 1, size(x)
      if (i > 1) v = v//', '
      v = v//real_text(x(i))
    end do
    call self%push(name, v, unit, meaning, .true., array_kind('real', size(x), kind), allowed)
  end subroutine add_reals

  subroutine add_int(self, name, i, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    integer, intent(in) :: i
    character(len=*), intent(in), optional :: allowed
    call self%push(name, itoa(i), unit, meaning, .true., 'integer', allowed)
  end subroutine add_int

  subroutine add_ints(self, name, i, unit, meaning, allowed, kind)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    integer, intent(in) :: i(:)
    character(len=*), intent(in), optional :: allowed, kind
    character(len=:), allocatable :: v
    integer :: k
    v = ''
    do k = 1, size(i)
      if (k > 1) v = v//', '
      v = v//itoa(i(k))
    end do
    call self%push(name, v, unit, meaning, .true., array_kind('integer', size(i), kind), allowed)
  end subroutine add_ints

  subroutine add_logical(self, name, l, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    logical, intent(in) :: l
    character(len=*), intent(in), optional :: allowed
    call self%push(name, logical_text(l), unit, meaning, .true., 'logical', allowed)
  end subroutine add_logical

  !> A character variable (trailing blanks dropped, quoted).
  subroutine add_string(self, name, s, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    character(len=*), intent(in) :: s
    character(len=*), intent(in), optional :: allowed
    call self%push(name, quoted(s), unit, meaning, .true., 'string', allowed)
  end subroutine add_string

  !> A list of character values, each quoted.
  subroutine add_strings(self, name, s, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, meaning
    character(len=*), intent(in) :: s(:)
    character(len=*), intent(in), optional :: allowed
    character(len=:), allocatable :: v
    integer :: k
    v = ''
    do k = 1, size(s)
      if (k > 1) v = v//', '
      v = v//quoted(s(k))
    end do
    call self%push(name, v, unit, meaning, .true., 'string list', allowed)
  end subroutine add_strings

  !> A variable the run leaves unset; shown says what that means, e.g.
  !> '(none)' or '(not set: no limit)'; kind as the add procedure of a
  !> value would infer it ('real', 'real(3)', 'string', ...).
  subroutine add_unset(self, name, shown, unit, meaning, kind, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, shown, unit, meaning
    character(len=*), intent(in), optional :: kind, allowed
    if (present(kind)) then
      call self%push(name, shown, unit, meaning, .false., kind, allowed)
    else
      call self%push(name, shown, unit, meaning, .false., '', allowed)
    end if
  end subroutine add_unset

  !> name(1..n) of values: each element whose magnitude is below huge is
  !> set, the others (a bound left open, +-huge) are shown as `shown`.
  subroutine add_bounds(self, name, values, shown, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, shown, unit, meaning
    real(rp), intent(in) :: values(:)
    character(len=*), intent(in), optional :: allowed
    character(len=len(name) + 12) :: v
    integer :: i
    do i = 1, size(values)
      write(v, '(a,a,i0,a)') name, '(', i, ')'
      if (abs(values(i)) < huge(1.0_rp)) then
        call self%add(trim(v), values(i), unit, meaning, allowed)
      else
        call self%add_unset(trim(v), shown, unit, meaning, 'real', allowed)
      end if
    end do
  end subroutine add_bounds

  !> An optional array (a point): its values when the run gives them
  !> (has), else `shown` (what leaving it out means).
  subroutine add_optional(self, name, has, values, shown, unit, meaning, allowed)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: name, shown, unit, meaning
    logical, intent(in) :: has
    real(rp), intent(in) :: values(:)
    character(len=*), intent(in), optional :: allowed
    if (has) then
      call self%add(name, values, unit, meaning, allowed)
    else
      call self%add_unset(name, shown, unit, meaning, array_kind('real', size(values)), allowed)
    end if
  end subroutine add_optional

  !> 'real(3)' for an array of 3 reals, or the kind the caller gives.
  function array_kind(base, n, kind) result(k)
    character(len=*), intent(in) :: base
    integer, intent(in) :: n
    character(len=*), intent(in), optional :: kind
    character(len=:), allocatable :: k
    if (present(kind)) then
      k = kind
    else
      k = base//'('//itoa(n)//')'
    end if
  end function array_kind

  !> Remove variable var (and its elements var(i)), e.g. one the physics
  !> does not use.
  subroutine drop(self, var)
    class(param_group_t), intent(inout) :: self
    character(len=*), intent(in) :: var
    integer :: i, k
    k = 0
    do i = 1, self%n
      if (base_name(self%p(i)%name) == var) cycle
      k = k + 1
      if (k /= i) self%p(k) = self%p(i)
    end do
    self%n = k
  end subroutine drop

  !> The name without an element index: 'lower(2)' -> 'lower'.
  pure function base_name(s) result(b)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: b
    b = s
    if (index(s, '(') > 1) b = s(1:index(s, '(') - 1)
  end function base_name

  !> Echo the group to the log (detail lines: the log file always, the
  !> screen at verbosity 2): '&group', then 'name = value [unit]' per
  !> variable.
  subroutine echo(self, log)
    class(param_group_t), intent(in) :: self
    type(logger_t), intent(inout) :: log
    character(len=piece_len), allocatable :: pieces(:)
    integer :: i, j, w
    call log%detail('  &'//trim(self%name))
    w = name_width(self)
    do i = 1, self%n
      associate (p => self%p(i))
        call split_value(p%value, p%set, pieces)
        do j = 1, size(pieces)
          if (j == 1) then
            call log%detail('    '//pad(p%name, w)//' = '//trim(pieces(j))//merge(' ['//p%unit//']', &
                            repeat(' ', len(p%unit) + 3), j == size(pieces)))
          else
            call log%detail('    '//repeat(' ', w + 3)//trim(pieces(j))//merge(' ['//p%unit//']', &
                            repeat(' ', len(p%unit) + 3), j == size(pieces)))
          end if
        end do
      end associate
    end do
  end subroutine echo

  !> The group as deck text: '&name', one 'name = value  ! [unit] meaning'
  !> per variable (an unset one as a comment line), '/'. Every line is at
  !> most param_line_len long; a long value goes on over several lines.
  function lines(self) result(out)
    class(param_group_t), intent(in) :: self
    character(len=param_line_len), allocatable :: out(:)
    character(len=piece_len), allocatable :: pieces(:)
    character(len=:), allocatable :: head, note
    integer :: i, j, w
    allocate(out(0))
    call push_line(out, '&'//trim(self%name))
    w = name_width(self)
    do i = 1, self%n
      associate (p => self%p(i))
        call split_value(p%value, p%set, pieces)
        if (.not. p%set) then
          head = '  ! '//pad(p%name, w)//' = '//trim(pieces(1))
          note = '['//p%unit//'] '//p%meaning
        else
          head = '  '//pad(p%name, w)//' = '//trim(pieces(1))
          note = '! ['//p%unit//'] '//p%meaning
        end if
        if (size(pieces) > 1 .or. len(head) + 2 + len(note) > param_line_len) then
          ! the comment on a line of its own, before the value
          call push_line(out, '  ! ['//p%unit//'] '//p%meaning)
          call push_line(out, head)
          do j = 2, size(pieces)
            call push_line(out, '  '//repeat(' ', w + 3)//trim(pieces(j)))
          end do
        else
          call push_line(out, pad(head, 44)//'  '//note)
        end if
      end associate
    end do
    call push_line(out, '/')
  end function lines

  !> Append one line to out (no array constructor: gfortran 12's checked
  !> build mistakes the length of a character function result in one).
  subroutine push_line(out, text)
    character(len=param_line_len), allocatable, intent(inout) :: out(:)
    character(len=*), intent(in) :: text
    character(len=param_line_len), allocatable :: tmp(:)
    integer :: n
    n = size(out)
    allocate(tmp(n + 1))
    tmp(1:n) = out
    tmp(n + 1) = text
    call move_alloc(tmp, out)
  end subroutine push_line

  integer function name_width(self)
    type(param_group_t), intent(in) :: self
    integer :: i
    name_width = 0
    do i = 1, self%n
      name_width = max(name_width, len(self%p(i)%name))
    end do
  end function name_width

  pure function pad(s, w) result(t)
    character(len=*), intent(in) :: s
    integer, intent(in) :: w
    character(len=max(len(s), w)) :: t
    t = s
  end function pad

  !> value cut after ', ' into pieces of at most about wrap_at characters
  !> (a string value, or an unset one, stays whole); each piece but the
  !> last ends with ','.
  subroutine split_value(value, set, pieces)
    character(len=*), intent(in) :: value
    logical, intent(in) :: set
    character(len=piece_len), allocatable, intent(out) :: pieces(:)
    character(len=piece_len) :: buf(len(value) / max(wrap_at / 2, 1) + 2)
    integer :: n, b, c
    if (.not. set .or. len(value) <= wrap_at .or. value(1:1) == "'") then
      pieces = [character(len=piece_len) :: value]
      return
    end if
    n = 0
    b = 1
    do while (b <= len(value))
      c = b + wrap_at
      if (c >= len(value)) then
        c = len(value) + 1
      else
        c = index(value(1:c), ', ', back=.true.)
        if (c < b) c = b + index(value(b:), ', ') - 1
        if (c < b) c = len(value) + 1
      end if
      n = n + 1
      if (c <= len(value)) then
        buf(n) = value(b:c)
      else
        buf(n) = value(b:)
      end if
      b = c + 2
    end do
    pieces = buf(1:n)
  end subroutine split_value
end module param_group
