!> The deck reference: every group and variable of every physics with its
!> kind, unit, default, allowed values and meaning, as Markdown (geoblock
!> --reference, doc/reference/decks.md) or as text for one group (geoblock
!> --help GROUP).
!>
!> It knows no config type and no physics: it lays out readings, the
!> resolved groups (param_group_t, from the config types' describe
!> methods) that a physics made of an example deck, with whether the deck
!> wrote each variable (deck_catalogue makes them). A variable's default
!> for a physics is its value in the first reading of that physics that
!> left it out; a variable every reading had to write is required. A
!> physics takes a group, or a variable, when some reading of it resolved
!> it. Groups and variables keep the order the readings give them.
module deck_reference
  use kinds, only: name_len
  use param_group, only: param_group_t, base_name
  use strings, only: itoa
  implicit none
  private

  public :: reading_t, given_t, reference_t

  !> Per variable of a resolved group: whether the deck wrote it.
  type :: given_t
    logical, allocatable :: flag(:)
  end type given_t

  !> The groups physics number `physics` resolved from one example deck.
  type :: reading_t
    integer :: physics = 0
    type(param_group_t), allocatable :: groups(:)
    type(given_t), allocatable :: given(:)
  end type reading_t

  ! Fixed-length texts below: gfortran 12 copies deferred-length character
  ! components of arrays of derived types shallowly (growing these arrays
  ! left every group with the last one's texts).
  integer, parameter :: text_len = 512

  !> A text and whether it is a value (set) or says what its absence means.
  type :: text_t
    character(len=text_len) :: s = ''
    logical :: set = .true.
    logical :: seen = .false.               !< s holds a text
  end type text_t

  !> One variable (an array's elements together).
  type :: row_t
    character(len=name_len) :: name = '', kind = '', unit = ''
    character(len=text_len) :: meaning = '', allowed = ''
    logical, allocatable :: have(:)         !< per physics: resolved by some reading
    type(text_t), allocatable :: dflt(:)    !< per physics: the default (seen: some reading left it out)
  end type row_t

  type :: group_rows_t
    character(len=name_len) :: name = ''
    character(len=text_len) :: about = ''
    logical, allocatable :: have(:)         !< per physics
    type(row_t), allocatable :: rows(:)
  end type group_rows_t

  !> The reference being built: the physics, the groups that may repeat,
  !> defaults to be shown as a text ('group%variable=text': a value that
  !> depends on the deck, e.g. the output prefix), and the groups.
  type :: reference_t
    character(len=name_len), allocatable :: physics(:)
    logical, allocatable :: transient(:)
    character(len=name_len), allocatable :: repeatable(:)
    character(len=160), allocatable :: fixed(:)
    type(group_rows_t), allocatable :: groups(:)
  contains
    procedure :: init
    procedure :: add
    procedure :: finish
    procedure :: has_group
    procedure :: group_names
    procedure :: markdown
    procedure :: group_text
  end type reference_t

  character(len=*), parameter :: required_text = '(required)'

contains

  !> An empty reference for the physics names (transient: steps in time),
  !> the groups that may repeat and the fixed default texts.
  subroutine init(self, physics, transient, repeatable, fixed)
    class(reference_t), intent(inout) :: self
    character(len=*), intent(in) :: physics(:), repeatable(:), fixed(:)
    logical, intent(in) :: transient(:)
    self%physics = physics
    self%transient = transient
    self%repeatable = repeatable
    self%fixed = fixed
    allocate(self%groups(0))
  end subroutine init

  !> Take the groups of one reading.
  subroutine add(self, r)
    class(reference_t), intent(inout) :: self
    type(reading_t), intent(in) :: r
    integer :: g, gi, prev
    prev = 0
    do g = 1, size(r%groups)
      gi = group_index(self, r%groups(g)%name)
      if (gi == 0) then
        ! after the group before it in this reading and the groups that
        ! follow that one but are not in this reading
        gi = prev + 1
        do while (gi <= size(self%groups))
          if (any(r%groups%name == self%groups(gi)%name)) exit
          gi = gi + 1
        end do
        call insert_group(self, gi, r%groups(g)%name)
      end if
      prev = gi
      associate (grp => self%groups(gi))
        grp%have(r%physics) = .true.
        if (len_trim(grp%about) == 0) grp%about = r%groups(g)%about
        call add_items(grp, r%groups(g), r%given(g)%flag, r%physics)
      end associate
    end do
  end subroutine add

  integer function group_index(self, name)
    type(reference_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer :: k
    group_index = 0
    do k = 1, size(self%groups)
      if (trim(self%groups(k)%name) == trim(name)) then
        group_index = k
        return
      end if
    end do
  end function group_index

  subroutine insert_group(self, at, name)
    type(reference_t), intent(inout) :: self
    integer, intent(in) :: at
    character(len=*), intent(in) :: name
    type(group_rows_t), allocatable :: tmp(:)
    integer :: n
    n = size(self%groups)
    allocate(tmp(n + 1))
    tmp(1:at - 1) = self%groups(1:at - 1)
    tmp(at + 1:n + 1) = self%groups(at:n)
    tmp(at)%name = name
    allocate(tmp(at)%have(size(self%physics)), tmp(at)%rows(0))
    tmp(at)%have = .false.
    call move_alloc(tmp, self%groups)
  end subroutine insert_group

  !> The variables of one resolved group g into grp: an array given as
  !> elements name(1), name(2), ... becomes one row; a row new to grp goes
  !> after the row of the variable before it.
  subroutine add_items(grp, g, given, p)
    type(group_rows_t), intent(inout) :: grp
    type(param_group_t), intent(in) :: g
    logical, intent(in) :: given(:)
    integer, intent(in) :: p
    integer :: i, j, ri, prev
    type(text_t) :: value
    character(len=:), allocatable :: base, kind
    prev = 0
    i = 1
    do while (i <= g%n)
      base = base_name(g%p(i)%name)
      j = i
      if (base /= g%p(i)%name) then
        do while (j < g%n)
          if (base_name(g%p(j + 1)%name) /= base .or. g%p(j + 1)%name == base) exit
          j = j + 1
        end do
      end if
      call joined_value(g, i, j, value)
      kind = g%p(i)%kind
      if (j > i .and. index(kind, '(') == 0 .and. len(kind) > 0) kind = kind//'('//itoa(j - i + 1)//')'
      ri = row_index(grp, base)
      if (ri == 0) then
        ! after the row before it in g and the rows that follow that one
        ! but are not in g
        ri = prev + 1
        do while (ri <= size(grp%rows))
          if (has_variable(g, grp%rows(ri)%name)) exit
          ri = ri + 1
        end do
        call insert_row(grp, ri, base, size(grp%have))
      end if
      associate (row => grp%rows(ri))
        row%have(p) = .true.
        if (.not. given(i) .and. .not. row%dflt(p)%seen) row%dflt(p) = value
        if (len_trim(row%kind) == 0) row%kind = kind
        if (len_trim(row%unit) == 0) row%unit = g%p(i)%unit
        if (len_trim(row%meaning) == 0) row%meaning = g%p(i)%meaning
        if (len_trim(row%allowed) == 0) row%allowed = g%p(i)%allowed
      end associate
      prev = ri
      i = j + 1
    end do
  end subroutine add_items

  !> Whether g has variable name (or its elements name(i)).
  logical function has_variable(g, name)
    type(param_group_t), intent(in) :: g
    character(len=*), intent(in) :: name
    integer :: i
    has_variable = .false.
    do i = 1, g%n
      if (base_name(g%p(i)%name) == trim(name)) then
        has_variable = .true.
        return
      end if
    end do
  end function has_variable

  !> The value of the elements i..j of g: one text when they are all
  !> unset alike, else the values joined.
  subroutine joined_value(g, i, j, value)
    type(param_group_t), intent(in) :: g
    integer, intent(in) :: i, j
    type(text_t), intent(out) :: value
    integer :: k
    character(len=:), allocatable :: v
    value%seen = .true.
    value%s = g%p(i)%value
    value%set = g%p(i)%set
    if (j == i) return
    if (all([(.not. g%p(k)%set .and. g%p(k)%value == g%p(i)%value, k = i, j)])) return
    value%set = .true.
    v = g%p(i)%value
    do k = i + 1, j
      v = v//', '//g%p(k)%value
    end do
    value%s = v
  end subroutine joined_value

  integer function row_index(grp, name)
    type(group_rows_t), intent(in) :: grp
    character(len=*), intent(in) :: name
    integer :: k
    row_index = 0
    do k = 1, size(grp%rows)
      if (trim(grp%rows(k)%name) == name) then
        row_index = k
        return
      end if
    end do
  end function row_index

  subroutine insert_row(grp, at, name, np)
    type(group_rows_t), intent(inout) :: grp
    integer, intent(in) :: at, np
    character(len=*), intent(in) :: name
    type(row_t), allocatable :: tmp(:)
    integer :: n
    n = size(grp%rows)
    allocate(tmp(n + 1))
    tmp(1:at - 1) = grp%rows(1:at - 1)
    tmp(at + 1:n + 1) = grp%rows(at:n)
    tmp(at)%name = name
    allocate(tmp(at)%have(np), tmp(at)%dflt(np))
    tmp(at)%have = .false.
    call move_alloc(tmp, grp%rows)
  end subroutine insert_row

  !> After the last reading: a variable with no default for a physics that
  !> has it is required there; the fixed texts replace the defaults they
  !> name. Returns in status_msg what is incomplete ('' when nothing): a
  !> variable without a kind or a meaning.
  subroutine finish(self, status_msg)
    class(reference_t), intent(inout) :: self
    character(len=:), allocatable, intent(out) :: status_msg
    integer :: g, r, p, f, eq
    character(len=:), allocatable :: gname
    status_msg = ''
    do g = 1, size(self%groups)
      gname = trim(self%groups(g)%name)
      do r = 1, size(self%groups(g)%rows)
        associate (row => self%groups(g)%rows(r))
          do p = 1, size(self%physics)
            if (row%have(p) .and. .not. row%dflt(p)%seen) row%dflt(p) = text_t(required_text, .false., .true.)
          end do
          do f = 1, size(self%fixed)
            eq = index(self%fixed(f), '=')
            if (self%fixed(f)(1:eq - 1) /= gname//'%'//trim(row%name)) cycle
            do p = 1, size(self%physics)
              if (row%have(p)) row%dflt(p) = text_t(self%fixed(f)(eq + 1:), .false., .true.)
            end do
          end do
          if (len_trim(row%kind) == 0 .or. len_trim(row%meaning) == 0) &
            status_msg = status_msg//' &'//gname//' '//trim(row%name)//' has no kind or meaning;'
        end associate
      end do
      if (.not. any(self%groups(g)%have)) status_msg = status_msg//' &'//trim(self%groups(g)%name)//' in no physics;'
    end do
  end subroutine finish

  logical function has_group(self, name)
    class(reference_t), intent(in) :: self
    character(len=*), intent(in) :: name
    has_group = group_index(self, name) > 0
  end function has_group

  !> The group names, '&run, &time, ...'.
  function group_names(self) result(s)
    class(reference_t), intent(in) :: self
    character(len=:), allocatable :: s
    integer :: g
    s = ''
    do g = 1, size(self%groups)
      if (g > 1) s = s//', '
      s = s//'&'//trim(self%groups(g)%name)
    end do
  end function group_names

  !> The whole reference as Markdown lines on unit u; version names the
  !> program that wrote it.
  subroutine markdown(self, u, version)
    class(reference_t), intent(in) :: self
    integer, intent(in) :: u
    character(len=*), intent(in) :: version
    integer :: g
    call md_head(self, u, version)
    do g = 1, size(self%groups)
      call md_group(self, u, self%groups(g))
    end do
  end subroutine markdown

  subroutine md_head(self, u, version)
    type(reference_t), intent(in) :: self
    integer, intent(in) :: u
    character(len=*), intent(in) :: version
    integer :: p, g
    character(len=:), allocatable :: list
    write(u, '(a)') '# Deck reference', '', &
      '<!-- Generated by `geoblock --reference` ('//version//'); do not edit: `make reference` rewrites it, '// &
      'and `make test` fails when it differs from what the binary writes. -->', '', &
      'Every deck group and variable, for every physics: its type, unit, default, the values the reader '// &
      'accepts and its meaning. `geoblock --reference` writes this page from the parameter registry, the '// &
      'describe methods of `src/config/*_config.f90` (the same ones that write `<prefix>_parameters.nml` '// &
      'and the log echo), applied to what the deck readers make of small example decks of each physics. '// &
      '`geoblock --help GROUP` prints one group. How decks work (groups, paths, units, histories, regions, '// &
      'probes): [Decks](../decks.md).', '', &
      'A default in parentheses says what leaving the variable out means; *(required)*: the deck must give it '// &
      '(where the meaning says when, only then). Units are SI; `-`: none. A variable that only some physics '// &
      'take is named under its group''s table; a deck that sets a group or variable its physics does not take '// &
      'is refused.', '', '## Physics', '', '| physics (`&run physics`) | steps | groups |', '|---|---|---|'
    do p = 1, size(self%physics)
      list = ''
      do g = 1, size(self%groups)
        if (.not. self%groups(g)%have(p)) cycle
        if (len(list) > 0) list = list//', '
        list = list//'[`&'//trim(self%groups(g)%name)//'`](#'//anchor(self%groups(g)%name)//')'
      end do
      write(u, '(a)') '| `'//trim(self%physics(p))//'` | '//pick(self%transient(p), &
        'time steps: `&time dt`, `t_end` or `times`', 'load steps: `&time n_steps`')//' | '//list//' |'
    end do
    write(u, '(a)') '', '## Groups', '', '| group | physics | may repeat | what it is |', '|---|---|---|---|'
    do g = 1, size(self%groups)
      associate (grp => self%groups(g))
        write(u, '(a)') '| [`&'//trim(grp%name)//'`](#'//anchor(grp%name)//') | '//physics_list(self, grp%have)// &
          ' | '//pick(any(self%repeatable == grp%name), 'yes', 'no')//' | '//md_escape(trim(grp%about))//' |'
      end associate
    end do
  end subroutine md_head

  subroutine md_group(self, u, grp)
    type(reference_t), intent(in) :: self
    integer, intent(in) :: u
    type(group_rows_t), intent(in) :: grp
    integer :: r
    write(u, '(a)') '', '## &'//trim(grp%name), ''
    if (len_trim(grp%about) > 0) write(u, '(a)') md_escape(capital(trim(grp%about)))//'.', ''
    write(u, '(a)') 'Physics: '//physics_list(self, grp%have)//'. '// &
      pick(any(self%repeatable == grp%name), 'May repeat.', 'At most one per deck.'), '', &
      '| variable | type | unit | default | allowed | meaning |', '|---|---|---|---|---|---|'
    do r = 1, size(grp%rows)
      associate (row => grp%rows(r))
        write(u, '(a)') '| `'//trim(row%name)//'` | '//trim(row%kind)//' | '//md_escape(trim(row%unit))//' | '// &
          default_text(self, row, .true.)//' | '//md_escape(trim(row%allowed))//' | '// &
          md_escape(trim(row%meaning))//' |'
      end associate
    end do
    call md_partial(self, u, grp)
  end subroutine md_group

  !> The variables that only some of the group's physics take, grouped by
  !> those physics.
  subroutine md_partial(self, u, grp)
    type(reference_t), intent(in) :: self
    integer, intent(in) :: u
    type(group_rows_t), intent(in) :: grp
    logical :: done(size(grp%rows))
    character(len=:), allocatable :: names
    integer :: r, s
    logical :: first
    done = .false.
    first = .true.
    do r = 1, size(grp%rows)
      if (done(r) .or. all(grp%rows(r)%have .eqv. grp%have)) cycle
      names = ''
      do s = r, size(grp%rows)
        if (done(s) .or. any(grp%rows(s)%have .neqv. grp%rows(r)%have)) cycle
        if (len(names) > 0) names = names//', '
        names = names//'`'//trim(grp%rows(s)%name)//'`'
        done(s) = .true.
      end do
      if (first) write(u, '(a)') ''
      first = .false.
      write(u, '(a)') '- only '//physics_list(self, grp%rows(r)%have)//': '//names
    end do
  end subroutine md_partial

  !> One group as text (geoblock --help GROUP).
  subroutine group_text(self, u, name)
    class(reference_t), intent(in) :: self
    integer, intent(in) :: u
    character(len=*), intent(in) :: name
    integer :: g, r
    g = group_index(self, name)
    if (g == 0) return
    associate (grp => self%groups(g))
      write(u, '(a)') '&'//trim(grp%name)//': '//trim(grp%about), '  physics: '//physics_list(self, grp%have)// &
        pick(any(self%repeatable == grp%name), '; may repeat', ''), ''
      do r = 1, size(grp%rows)
        associate (row => grp%rows(r))
          write(u, '(a)') '  '//trim(row%name)//': '//trim(row%kind)//' ['//trim(row%unit)//'], default '// &
            default_text(self, row, .false.)
          if (len_trim(row%allowed) > 0) write(u, '(a)') '      allowed: '//trim(row%allowed)
          write(u, '(a)') '      '//trim(row%meaning)
          if (any(row%have .neqv. grp%have)) write(u, '(a)') '      only '//physics_list(self, row%have)
        end associate
      end do
    end associate
  end subroutine group_text

  !> The default of row: one text when every physics that has it agrees,
  !> else the first physics' and then '; biot, contact: ...' for the others.
  function default_text(self, row, md) result(s)
    type(reference_t), intent(in) :: self
    type(row_t), intent(in) :: row
    logical, intent(in) :: md
    character(len=:), allocatable :: s
    logical :: done(size(self%physics))
    integer :: p, q, first
    character(len=:), allocatable :: who
    s = ''
    done = .not. row%have
    first = 0
    do p = 1, size(self%physics)
      if (done(p)) cycle
      who = ''
      do q = p, size(self%physics)
        if (done(q)) cycle
        if (row%dflt(q)%s /= row%dflt(p)%s) cycle
        done(q) = .true.
        if (len(who) > 0) who = who//', '
        who = who//trim(self%physics(q))
      end do
      if (first == 0) then
        first = p
        s = shown(row%dflt(p), md)
      else
        s = s//'; '//who//': '//shown(row%dflt(p), md)
      end if
    end do
  end function default_text

  !> A value in backticks (Markdown) or as it is; a text on the absence of
  !> a value as it is (Markdown: escaped, the required mark in italics).
  function shown(t, md) result(s)
    type(text_t), intent(in) :: t
    logical, intent(in) :: md
    character(len=:), allocatable :: s
    if (.not. md) then
      s = trim(t%s)
    else if (t%set) then
      s = '`'//md_code(trim(t%s))//'`'
    else if (t%s == required_text) then
      s = '*'//required_text//'*'
    else
      s = md_escape(trim(t%s))
    end if
  end function shown

  !> 'all' or the physics that have the group or variable.
  function physics_list(self, have) result(s)
    type(reference_t), intent(in) :: self
    logical, intent(in) :: have(:)
    character(len=:), allocatable :: s
    integer :: p
    if (all(have)) then
      s = 'all'
      return
    end if
    s = ''
    do p = 1, size(have)
      if (.not. have(p)) cycle
      if (len(s) > 0) s = s//', '
      s = s//trim(self%physics(p))
    end do
  end function physics_list

  !> The anchor a Markdown renderer gives a heading '&name': name itself.
  function anchor(name) result(s)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    s = trim(name)
  end function anchor

  !> text with the characters Markdown would take for markup escaped.
  function md_escape(text) result(s)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, len(text)
      select case (text(k:k))
      case ('|', '*', '_', '`', '\', '[', ']')
        s = s//'\'//text(k:k)
      case ('<')
        s = s//'&lt;'
      case ('>')
        s = s//'&gt;'
      case default
        s = s//text(k:k)
      end select
    end do
  end function md_escape

  !> A value inside a code span of a table: only '|' needs escaping.
  function md_code(text) result(s)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, len(text)
      if (text(k:k) == '|') then
        s = s//'\|'
      else
        s = s//text(k:k)
      end if
    end do
  end function md_code

  function capital(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    t = s
    if (len(t) == 0) return
    if (t(1:1) >= 'a' .and. t(1:1) <= 'z') t(1:1) = achar(iachar(t(1:1)) - 32)
  end function capital

  !> a when l, else b (of any lengths, unlike merge).
  function pick(l, a, b) result(s)
    logical, intent(in) :: l
    character(len=*), intent(in) :: a, b
    character(len=:), allocatable :: s
    if (l) then
      s = a
    else
      s = b
    end if
  end function pick
end module deck_reference
