!> Logging: rank 0 writes to standard output and to an optional log file.
!>
!> The stops are here too: fatal() is collective (all ranks call it with the
!> same message, e.g. after a broadcast status), abort() is for an error seen
!> by one rank only and takes the others down with MPI_Abort, so that no rank
!> is left waiting.
module logger
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use kinds, only: rp, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use os_services, only: end_process
  implicit none
  private

  public :: logger_t

  type :: logger_t
    integer :: rank = 0
    integer :: unit = 0             !< log file unit on rank 0 (newunit numbers are negative)
    logical :: has_file = .false.
    !> lines logged before the file was opened (written to it when it opens)
    character(len=msg_len), allocatable :: pending(:)
    integer :: n_pending = 0
    !> what goes to the screen: 0 warnings and errors only, 1 also the info
    !> lines, 2 also the detail lines; the log file always gets them all
    integer :: verbosity = 1
  contains
    procedure :: init
    procedure :: open_file
    procedure :: close
    procedure :: info
    procedure :: detail
    procedure :: warn
    procedure :: fatal
    procedure :: abort
  end type logger_t

contains

  subroutine init(self, comm, verbosity)
    class(logger_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    integer, intent(in), optional :: verbosity
    self%rank = comm%rank
    if (present(verbosity)) self%verbosity = verbosity
  end subroutine init

  !> Also write the log to a file (rank 0 only). Returns ios /= 0 on failure.
  subroutine open_file(self, path, ios)
    class(logger_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: ios
    integer :: i
    ios = 0
    if (self%rank /= 0) return
    open(newunit=self%unit, file=path, status='replace', action='write', iostat=ios)
    self%has_file = ios == 0
    if (self%has_file) then
      do i = 1, self%n_pending
        write(self%unit, '(a)') trim(self%pending(i))
      end do
    end if
    self%n_pending = 0
    if (allocated(self%pending)) deallocate(self%pending)
  end subroutine open_file

  subroutine close(self)
    class(logger_t), intent(inout) :: self
    if (self%has_file) close(self%unit)
    self%has_file = .false.
  end subroutine close

  !> Write a line to the log file, or keep it until the file is opened.
  subroutine to_file(self, line)
    class(logger_t), intent(inout) :: self
    character(len=*), intent(in) :: line
    character(len=msg_len), allocatable :: tmp(:)
    if (self%has_file) then
      write(self%unit, '(a)') trim(line)
      return
    end if
    if (.not. allocated(self%pending)) allocate(self%pending(64))
    if (self%n_pending == size(self%pending)) then
      allocate(tmp(2 * size(self%pending)))
      tmp(1:self%n_pending) = self%pending
      call move_alloc(tmp, self%pending)
    end if
    self%n_pending = self%n_pending + 1
    self%pending(self%n_pending) = line
  end subroutine to_file

  !> A line for the user (rank 0): on the screen unless verbosity is 0, in
  !> the log file always.
  subroutine info(self, msg)
    class(logger_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    if (self%rank /= 0) return
    if (self%verbosity >= 1) then
      write(output_unit, '(a)') trim(msg)
      flush(output_unit)
    end if
    call to_file(self, msg)
  end subroutine info

  !> A line shown only with verbosity >= 2 (always written to the log file).
  subroutine detail(self, msg)
    class(logger_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    if (self%rank /= 0) return
    if (self%verbosity >= 2) write(output_unit, '(a)') trim(msg)
    call to_file(self, msg)
  end subroutine detail

  subroutine warn(self, msg)
    class(logger_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    if (self%rank /= 0) return
    write(error_unit, '(a)') 'geoblock: warning: '//trim(msg)
    call to_file(self, 'warning: '//trim(msg))
  end subroutine warn

  !> Collective stop: every rank calls it; rank 0 prints, all exit with status 2
  !> (no run-time STOP line).
  subroutine fatal(self, comm, msg)
    class(logger_t), intent(inout) :: self
    type(parallel_comm_t), intent(inout) :: comm
    character(len=*), intent(in) :: msg
    if (self%rank == 0) then
      flush(output_unit)      ! the progress lines first, then the error on a line of its own
      write(error_unit, '(a)') 'geoblock: error: '//trim(msg)
      flush(error_unit)
      if (self%has_file) write(self%unit, '(a)') 'error: '//trim(msg)
    end if
    call self%close()
    call comm%barrier()
    call comm%finalize()
    call end_process(2)
  end subroutine fatal

  !> Stop from one rank: prints with the rank number and aborts all ranks.
  subroutine abort(self, comm, msg)
    class(logger_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: msg
    character(len=16) :: r
    write(r, '(i0)') comm%rank
    write(error_unit, '(a)') 'geoblock: error (rank '//trim(r)//'): '//trim(msg)
    flush(error_unit)
    call self%close()
    call comm%abort(3)
  end subroutine abort
end module logger
