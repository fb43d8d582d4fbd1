!> A simulation's state as named arrays: what a physics must keep to go back
!> to the start of a step (a step cut) or to resume a run (a checkpoint).
!>
!> A physics puts its arrays in (put) and takes them back (get) by name; the
!> record owns copies. Arrays are this rank's local arrays (owned entries
!> first, ghosts after, as the physics keeps them), so a record is only valid
!> on the same partition: a checkpoint written from it resumes on the same
!> number of ranks. Real, integer and text arrays are kept apart so that a
!> writer can store each with its own type (text: names, e.g. of the output
!> fields a checkpoint lists; entries are read back through e(find(name))).
module state_record
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  implicit none
  private

  public :: state_record_t, state_entry_t

  !> One named array: exactly one of r, i and s is allocated.
  type :: state_entry_t
    character(len=name_len) :: name = ''
    real(rp), allocatable :: r(:)
    integer, allocatable :: i(:)
    character(len=name_len), allocatable :: s(:)
  end type state_entry_t

  type :: state_record_t
    integer :: n = 0
    type(state_entry_t), allocatable :: e(:)
    real(rp) :: time = 0.0_rp                !< the time (or load factor) the state belongs to
    integer :: step = 0                      !< the last completed step
  contains
    procedure :: clear
    generic :: put => put_real, put_int, put_text
    generic :: get => get_real, get_int
    procedure, private :: put_real, put_int, put_text, get_real, get_int
    procedure, private :: slot
    procedure :: find
  end type state_record_t

contains

  !> Forget every entry.
  subroutine clear(self)
    class(state_record_t), intent(inout) :: self
    if (allocated(self%e)) deallocate(self%e)
    self%n = 0
    self%time = 0.0_rp
    self%step = 0
  end subroutine clear

  !> Index of the entry called name, 0 if there is none.
  integer function find(self, name)
    class(state_record_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer :: k
    find = 0
    do k = 1, self%n
      if (self%e(k)%name == name) then
        find = k
        return
      end if
    end do
  end function find

  !> The entry called name, made if it does not exist yet (its old array is
  !> dropped either way).
  integer function slot(self, name)
    class(state_record_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    type(state_entry_t), allocatable :: grown(:)
    slot = self%find(name)
    if (slot == 0) then
      if (.not. allocated(self%e)) allocate(self%e(8))
      if (self%n == size(self%e)) then
        allocate(grown(2 * self%n))
        grown(1:self%n) = self%e(1:self%n)
        call move_alloc(grown, self%e)
      end if
      self%n = self%n + 1
      slot = self%n
      self%e(slot)%name = name
    end if
    if (allocated(self%e(slot)%r)) deallocate(self%e(slot)%r)
    if (allocated(self%e(slot)%i)) deallocate(self%e(slot)%i)
    if (allocated(self%e(slot)%s)) deallocate(self%e(slot)%s)
  end function slot

  !> Keep a copy of the real array v under name.
  subroutine put_real(self, name, v)
    class(state_record_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in) :: v(:)
    integer :: k
    k = self%slot(name)
    self%e(k)%r = v
  end subroutine put_real

  !> Keep a copy of the integer array v under name.
  subroutine put_int(self, name, v)
    class(state_record_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: v(:)
    integer :: k
    k = self%slot(name)
    self%e(k)%i = v
  end subroutine put_int

  !> Keep a copy of the text array v (names of at most name_len characters).
  subroutine put_text(self, name, v)
    class(state_record_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: v(:)
    integer :: k
    k = self%slot(name)
    allocate(self%e(k)%s(size(v)))
    self%e(k)%s = v
  end subroutine put_text

  !> Copy the real array called name into v, which must have its size.
  !> status: no such entry, or another size or type.
  subroutine get_real(self, name, v, status)
    class(state_record_t), intent(in) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(inout) :: v(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    k = self%find(name)
    if (k == 0) then
      call status%set("state record: no entry '"//trim(name)//"'")
    else if (.not. allocated(self%e(k)%r)) then
      call status%set("state record: entry '"//trim(name)//"' is not a real array")
    else if (size(self%e(k)%r) /= size(v)) then
      call status%set(size_message(name, size(self%e(k)%r), size(v)))
    else
      v = self%e(k)%r
    end if
  end subroutine get_real

  !> Copy the integer array called name into v, which must have its size.
  subroutine get_int(self, name, v, status)
    class(state_record_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(inout) :: v(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    k = self%find(name)
    if (k == 0) then
      call status%set("state record: no entry '"//trim(name)//"'")
    else if (.not. allocated(self%e(k)%i)) then
      call status%set("state record: entry '"//trim(name)//"' is not an integer array")
    else if (size(self%e(k)%i) /= size(v)) then
      call status%set(size_message(name, size(self%e(k)%i), size(v)))
    else
      v = self%e(k)%i
    end if
  end subroutine get_int

  function size_message(name, have, want) result(m)
    character(len=*), intent(in) :: name
    integer, intent(in) :: have, want
    character(len=msg_len) :: m
    write(m, '(a,i0,a,i0,a)') "state record: entry '"//trim(name)//"' has ", have, ' values, the state needs ', &
      want, ' (another mesh or partition?)'
  end function size_message
end module state_record
