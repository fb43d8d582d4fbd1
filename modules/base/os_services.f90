!> The operating system services geoblock needs, through the C library
!> (POSIX, glibc) and never through a shell: creating a directory with its
!> parents, asking what a path is, ending the process with a status, and
!> catching SIGTERM / SIGUSR1 so that a run can stop cleanly at the end of a
!> step.
!>
!> The signal flag is the one piece of global state in the project: a signal
!> handler cannot receive an argument, so it can only set a variable the
!> program polls (stop_requested). It is written only by the handler.
module os_services
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_funptr, c_funloc, c_associated, &
    c_f_pointer, c_size_t, c_long
  use kinds, only: msg_len
  use error_status, only: error_status_t
  implicit none
  private

  public :: make_directory, rename_path, path_kind, path_missing, path_file, path_directory, end_process, &
            catch_stop_signals, stop_requested, signal_name, file_size, &
            absolute_path, process_id

  !> what a path names (path_kind)
  integer, parameter :: path_missing = 0, path_file = 1, path_directory = 2

  integer(c_int), parameter :: sig_term = 15, sig_usr1 = 10
  integer(c_int), parameter :: e_exist = 17
  integer, parameter :: mode_dir = int(o'755')

  !> set by the signal handler, read by stop_requested
  integer(c_int), volatile, save :: signal_seen = 0

  interface
    !> int mkdir(const char *path, mode_t mode)
    integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
    end function c_mkdir
    !> int *__errno_location(void) (glibc: the thread's errno)
    type(c_ptr) function c_errno_location() bind(C, name='__errno_location')
      import :: c_ptr
    end function c_errno_location
    !> char *strerror(int errnum)
    type(c_ptr) function c_strerror(errnum) bind(C, name='strerror')
      import :: c_ptr, c_int
      integer(c_int), value :: errnum
    end function c_strerror
    !> size_t strlen(const char *s)
    integer(c_size_t) function c_strlen(s) bind(C, name='strlen')
      import :: c_size_t, c_ptr
      type(c_ptr), value :: s
    end function c_strlen
    !> void exit(int status)
    subroutine c_exit(status) bind(C, name='exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit
    !> sighandler_t signal(int signum, sighandler_t handler)
    type(c_funptr) function c_signal(signum, handler) bind(C, name='signal')
      import :: c_int, c_funptr
      integer(c_int), value :: signum
      type(c_funptr), value :: handler
    end function c_signal
    !> int rename(const char *old, const char *new)
    integer(c_int) function c_rename(old, new) bind(C, name='rename')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: old(*), new(*)
    end function c_rename
    !> char *getcwd(char *buf, size_t size)
    type(c_ptr) function c_getcwd(buf, size) bind(C, name='getcwd')
      import :: c_ptr, c_char, c_size_t
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_size_t), value :: size
    end function c_getcwd
    !> DIR *opendir(const char *name); int closedir(DIR *dirp)
    type(c_ptr) function c_opendir(path) bind(C, name='opendir')
      import :: c_ptr, c_char
      character(kind=c_char), intent(in) :: path(*)
    end function c_opendir
    integer(c_int) function c_closedir(dir) bind(C, name='closedir')
      import :: c_int, c_ptr
      type(c_ptr), value :: dir
    end function c_closedir
    !> pid_t getpid(void)
    integer(c_int) function c_getpid() bind(C, name='getpid')
      import :: c_int
    end function c_getpid
  end interface

contains

  !> Create directory path and its missing parents (mkdir -p). status
  !> names the path and the system's reason on failure (a component that is
  !> a file, no permission, a name the file system refuses, ...).
  subroutine make_directory(path, status)
    character(len=*), intent(in) :: path
    type(error_status_t), intent(inout) :: status
    integer :: i, n, err
    n = len_trim(path)
    if (n == 0) then
      call status%set('cannot create a directory with an empty name')
      return
    end if
    if (index(path(1:n), achar(0)) > 0) then
      call status%set("cannot create directory '"//path(1:n)//"': the name contains a NUL character")
      return
    end if
    do i = 2, n
      if (path(i:i) == '/' .and. path(i-1:i-1) /= '/') then
        call make_one(path(1:i-1), err)
        if (err /= 0) then
          call status%set("cannot create directory '"//path(1:i-1)//"' (for '"//path(1:n)//"'): "//errno_text(err))
          return
        end if
      end if
    end do
    call make_one(path(1:n), err)
    if (err /= 0) call status%set("cannot create directory '"//path(1:n)//"': "//errno_text(err))
  contains
    !> mkdir of one level; an existing directory is fine, anything else
    !> that exists is not (err = ENOTDIR then).
    subroutine make_one(p, err)
      character(len=*), intent(in) :: p
      integer, intent(out) :: err
      err = 0
      if (c_mkdir(p//c_null_char, int(mode_dir, c_int)) == 0) return
      err = errno()
      if (err == e_exist) then
        err = 0
        if (kind_of(p) /= path_directory) err = 20     ! ENOTDIR
      end if
    end subroutine make_one
  end subroutine make_directory

  !> Give file old the name new, replacing a file of that name in one step
  !> (rename(2): a reader sees the old or the new file, never a half-written
  !> one). Trailing blanks of both names are ignored; status names both
  !> paths and the system's reason on failure.
  subroutine rename_path(old, new, status)
    character(len=*), intent(in) :: old, new
    type(error_status_t), intent(inout) :: status
    if (c_rename(trim(old)//c_null_char, trim(new)//c_null_char) /= 0) &
      call status%set("cannot rename '"//trim(old)//"' to '"//trim(new)//"': "//errno_text(errno()))
  end subroutine rename_path

  !> The process id (unique among the running processes: names of
  !> temporary files).
  integer function process_id()
    process_id = int(c_getpid())
  end function process_id

  !> path (trailing blanks ignored) as an absolute path: a relative one is
  !> put after the working directory ('' stays ''; a path that already
  !> starts with '/' is returned as it is, as is any path when the working
  !> directory cannot be found).
  function absolute_path(path) result(p)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: p
    character(kind=c_char, len=4096) :: buf
    integer :: n
    p = trim(path)
    if (len(p) == 0) return
    if (p(1:1) == '/') return
    if (.not. c_associated(c_getcwd(buf, int(len(buf), c_size_t)))) return
    n = index(buf, c_null_char) - 1
    if (n < 1) return
    if (len(p) > 1) then
      if (p(1:2) == './') p = p(3:)
    end if
    p = buf(1:n)//'/'//p
  end function absolute_path

  !> What path (trailing blanks ignored) names: path_missing, path_file (a
  !> regular file or anything that can be opened as one), path_directory.
  integer function path_kind(path)
    character(len=*), intent(in) :: path
    path_kind = path_missing
    if (len_trim(path) > 0) path_kind = kind_of(path(1:len_trim(path)))
  end function path_kind

  !> path_kind of the name p exactly as given (blanks included).
  integer function kind_of(p)
    character(len=*), intent(in) :: p
    logical :: exists
    type(c_ptr) :: dir
    integer(c_int) :: rc
    kind_of = path_missing
    dir = c_opendir(p//c_null_char)
    if (c_associated(dir)) then
      rc = c_closedir(dir)
      kind_of = path_directory
      return
    end if
    inquire(file=p, exist=exists)
    if (exists) kind_of = path_file
  end function kind_of

  !> Size of the file at path in bytes (-1 when it cannot be asked).
  integer(c_long) function file_size(path)
    character(len=*), intent(in) :: path
    integer :: s, ios
    inquire(file=trim(path), size=s, iostat=ios)
    file_size = -1
    if (ios == 0) file_size = s
  end function file_size

  !> errno of the last failed C call.
  integer function errno()
    integer(c_int), pointer :: e
    call c_f_pointer(c_errno_location(), e)
    errno = e
  end function errno

  !> The system's text for errno value err.
  function errno_text(err) result(s)
    integer, intent(in) :: err
    character(len=msg_len) :: s
    character(kind=c_char), pointer :: chars(:)
    type(c_ptr) :: p
    integer :: n, i
    s = ''
    p = c_strerror(int(err, c_int))
    if (.not. c_associated(p)) return
    n = int(min(c_strlen(p), int(len(s), c_size_t)))
    call c_f_pointer(p, chars, [n])
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function errno_text

  !> End the process with exit status code, without the Fortran run-time's
  !> STOP line or its notes on floating-point flags.
  subroutine end_process(code)
    integer, intent(in) :: code
    call c_exit(int(code, c_int))
  end subroutine end_process

  !> From now on SIGTERM and SIGUSR1 set a flag (stop_requested) instead of
  !> killing the process.
  subroutine catch_stop_signals()
    type(c_funptr) :: old
    old = c_signal(sig_term, c_funloc(on_signal))
    old = c_signal(sig_usr1, c_funloc(on_signal))
  end subroutine catch_stop_signals

  !> The signal handler: remembers the signal.
  subroutine on_signal(sig) bind(C)
    integer(c_int), value :: sig
    signal_seen = sig
  end subroutine on_signal

  !> The name of a stop signal number ('SIGTERM', 'SIGUSR1', else 'signal N').
  function signal_name(sig) result(s)
    integer, intent(in) :: sig
    character(len=:), allocatable :: s
    character(len=16) :: buf
    select case (sig)
    case (sig_term)
      s = 'SIGTERM'
    case (sig_usr1)
      s = 'SIGUSR1'
    case default
      write(buf, '(a,i0)') 'signal ', sig
      s = trim(buf)
    end select
  end function signal_name

  !> A stop signal has arrived on this process (0: none, else its number).
  integer function stop_requested()
    stop_requested = signal_seen
  end function stop_requested
end module os_services
