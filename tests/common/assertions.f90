!> The project's small assertion module (pFUnit is not reachable here).
!>
!> A test program creates one test_suite_t, calls the assert_* procedures,
!> and ends with suite%finish(), which prints one line per failure, a
!> summary line "suite NAME: N passed, N failed" (rank 0), and sets the exit
!> status. Assertions are collective-safe: each rank checks its own values;
!> finish() combines the results over ranks so that all ranks agree.
module assertions
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds, only: rp, ip, msg_len
  use parallel_comm, only: parallel_comm_t
  implicit none
  private

  public :: test_suite_t, max_rel_diff

  type :: test_suite_t
    character(len=64) :: name = ''
    type(parallel_comm_t) :: comm
    integer :: passed = 0
    integer :: failed = 0
  contains
    procedure :: init
    procedure :: assert_true
    procedure :: assert_close
    procedure :: assert_close_array
    procedure :: assert_equal_int
    procedure :: finish
  end type test_suite_t

contains

  subroutine init(self, name, comm)
    class(test_suite_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    type(parallel_comm_t), intent(in) :: comm
    self%name = name
    self%comm = comm
  end subroutine init

  subroutine record(self, ok, what)
    class(test_suite_t), intent(inout) :: self
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    logical :: ok_all
    ok_all = .not. self%comm%any_true(.not. ok)
    if (ok_all) then
      self%passed = self%passed + 1
      if (self%comm%rank == 0) write(output_unit, '(a)') '  ok    '//trim(what)
    else
      self%failed = self%failed + 1
      if (self%comm%rank == 0) write(output_unit, '(a)') '  FAIL  '//trim(what)
    end if
    flush(output_unit)
  end subroutine record

  !> Collective: every rank must call each assertion.
  subroutine assert_true(self, cond, what)
    class(test_suite_t), intent(inout) :: self
    logical, intent(in) :: cond
    character(len=*), intent(in) :: what
    call record(self, cond, what)
  end subroutine assert_true

  !> |a - b| <= tol (absolute), reported with the values.
  subroutine assert_close(self, a, b, tol, what)
    class(test_suite_t), intent(inout) :: self
    real(rp), intent(in) :: a, b, tol
    character(len=*), intent(in) :: what
    character(len=msg_len) :: m
    write(m, '(a,a,es12.4,a,es12.4,a,es10.2,a)') trim(what), ' (', a, ' vs ', b, ', tol ', tol, ')'
    call record(self, abs(a - b) <= tol, m)
  end subroutine assert_close

  subroutine assert_close_array(self, a, b, tol, what)
    class(test_suite_t), intent(inout) :: self
    real(rp), intent(in) :: a(:), b(:), tol
    character(len=*), intent(in) :: what
    character(len=msg_len) :: m
    real(rp) :: err
    err = 0.0_rp
    if (size(a) > 0) err = maxval(abs(a - b))
    write(m, '(a,a,es12.4,a,es10.2,a)') trim(what), ' (max diff ', err, ', tol ', tol, ')'
    call record(self, size(a) == size(b) .and. err <= tol, m)
  end subroutine assert_close_array

  subroutine assert_equal_int(self, a, b, what)
    class(test_suite_t), intent(inout) :: self
    integer, intent(in) :: a, b
    character(len=*), intent(in) :: what
    character(len=msg_len) :: m
    write(m, '(a,a,i0,a,i0,a)') trim(what), ' (', a, ' vs ', b, ')'
    call record(self, a == b, m)
  end subroutine assert_equal_int

  !> Print the summary line, finalize MPI and exit nonzero on failure.
  subroutine finish(self)
    class(test_suite_t), intent(inout) :: self
    if (self%comm%rank == 0) then
      write(output_unit, '(a,i0,a,i0,a)') 'suite '//trim(self%name)//': ', self%passed, ' passed, ', &
        self%failed, ' failed'
      flush(output_unit)
    end if
    call self%comm%finalize()
    if (self%failed > 0) stop 1
  end subroutine finish

  !> max |a - b| / max |b| over all ranks of comm (0 when b is 0 everywhere):
  !> the relative difference of two distributed vectors. Collective.
  real(rp) function max_rel_diff(comm, a, b)
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in) :: a(:), b(:)
    real(rp) :: diff, scale
    diff = 0.0_rp
    scale = 0.0_rp
    if (size(b) > 0) then
      diff = maxval(abs(a - b))
      scale = maxval(abs(b))
    end if
    diff = comm%max(diff)
    scale = comm%max(scale)
    max_rel_diff = 0.0_rp
    if (scale > 0.0_rp) max_rel_diff = diff / scale
  end function max_rel_diff
end module assertions
