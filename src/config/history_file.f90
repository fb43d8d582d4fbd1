!> Load histories: two-column text files "time factor" (lines starting with
!> '#' and blank lines are skipped, times strictly increasing) that scale a
!> boundary condition (&boundary history), a fault pressure (&fault
!> pressure_history), a well's rate, a fracture pressure or a pressure
!> change (their history) in time, linearly between the rows and constant
!> outside them.
module history_file
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, msg_len
  use parallel_comm, only: parallel_comm_t
  use os_services, only: path_kind, path_directory
  use number_text, only: real_token_problem
  implicit none
  private

  public :: read_history, history_factor

contains

  !> Read the history file path on rank 0 and broadcast it into hist_t and
  !> hist_f. On failure msg says what is wrong (with the line), on every
  !> rank alike, and the arrays are not allocated; msg is blank on success.
  !> Collective.
  subroutine read_history(comm, path, hist_t, hist_f, msg)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    real(rp), allocatable, intent(out) :: hist_t(:), hist_f(:)
    character(len=msg_len), intent(out) :: msg
    real(rp), allocatable :: t(:), f(:)
    integer :: n
    n = 0
    msg = ''
    if (comm%is_root()) call read_rows(path, t, f, n, msg)
    call comm%bcast(n)
    if (n < 0) then
      call comm%bcast(msg)
      return
    end if
    allocate(hist_t(n), hist_f(n))
    if (comm%is_root()) then
      hist_t = t(1:n)
      hist_f = f(1:n)
    end if
    call comm%bcast(hist_t)
    call comm%bcast(hist_f)
  end subroutine read_history

  !> The rows of the file at path: n rows in t, f, or n = -1 and msg.
  subroutine read_rows(path, t, f, n, msg)
    character(len=*), intent(in) :: path
    real(rp), allocatable, intent(out) :: t(:), f(:)
    integer, intent(out) :: n
    character(len=msg_len), intent(out) :: msg
    integer :: u, ios, line
    real(rp) :: row(2), extra(3)
    character(len=1024) :: buf
    character(len=:), allocatable :: why
    n = -1
    msg = ''
    if (path_kind(path) == path_directory) then
      msg = 'is a directory, not a file'
      return
    end if
    open(newunit=u, file=trim(path), status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) return
    allocate(t(1024), f(1024))
    n = 0
    line = 0
    do
      read(u, '(a)', iostat=ios) buf
      if (ios /= 0) exit
      line = line + 1
      buf = adjustl(buf)
      if (len_trim(buf) == 0 .or. buf(1:1) == '#') cycle
      ! the values are checked as text first: nan, inf or 1e400 must not
      ! reach the conversion (the checked build traps it)
      why = row_problem(buf)
      if (why == 'not finite') then
        write(msg, '(a,i0,a)') 'line ', line, ': a value is not a finite number'
        exit
      end if
      read(buf, *, iostat=ios) row
      if (ios /= 0 .or. why == 'not a number') then
        write(msg, '(a,i0,a)') 'line ', line, ': expected two numbers "time factor"'
      else
        read(buf, *, iostat=ios) extra
        if (ios == 0) then
          write(msg, '(a,i0,a)') 'line ', line, ': more than two numbers (expected "time factor")'
        else if (.not. all(ieee_is_finite(row))) then
          write(msg, '(a,i0,a)') 'line ', line, ': a value is not a finite number'
        else if (n > 0) then
          if (row(1) <= t(n)) write(msg, '(a,i0,a)') 'line ', line, ': times must increase'
        end if
      end if
      if (len_trim(msg) > 0) exit
      if (n == size(t)) then
        t = [t, t]
        f = [f, f]
      end if
      n = n + 1
      t(n) = row(1)
      f(n) = row(2)
    end do
    if (ios > 0 .and. len_trim(msg) == 0) write(msg, '(a,i0)') 'cannot read line ', line + 1
    close(u)
    if (len_trim(msg) == 0 .and. n == 0) msg = 'no rows'
    if (len_trim(msg) > 0) n = -1
  end subroutine read_rows

  !> 'not finite' when one of the first two blank- or comma-separated words
  !> of a row is nan, inf or beyond the doubles; 'not a number' when one is
  !> no number (or missing); '' otherwise.
  function row_problem(buf) result(why)
    character(len=*), intent(in) :: buf
    character(len=:), allocatable :: why
    character(len=*), parameter :: seps = ' ,'//achar(9)
    character(len=:), allocatable :: problem
    integer :: k, i, j
    why = ''
    i = 1
    do k = 1, 2
      do while (i <= len_trim(buf))
        if (index(seps, buf(i:i)) == 0) exit
        i = i + 1
      end do
      if (i > len_trim(buf)) then
        why = 'not a number'
        return
      end if
      j = i
      do while (j <= len_trim(buf))
        if (index(seps, buf(j:j)) > 0) exit
        j = j + 1
      end do
      problem = real_token_problem(buf(i:j-1))
      if (index(problem, 'finite') > 0 .or. index(problem, 'range') > 0) then
        why = 'not finite'
        return
      else if (len(problem) > 0) then
        why = 'not a number'
      end if
      i = j
    end do
  end function row_problem

  !> The factor of the history (hist_t, hist_f) at time t: linear between the
  !> rows, the first / last value before / after them.
  pure real(rp) function history_factor(hist_t, hist_f, t) result(factor)
    real(rp), intent(in) :: hist_t(:), hist_f(:)
    real(rp), intent(in) :: t
    integer :: i, n
    n = size(hist_t)
    if (t <= hist_t(1)) then
      factor = hist_f(1)
    else if (t >= hist_t(n)) then
      factor = hist_f(n)
    else
      factor = hist_f(n)
      do i = 1, n - 1
        if (t <= hist_t(i+1)) then
          factor = hist_f(i) + (hist_f(i+1) - hist_f(i)) * (t - hist_t(i)) / (hist_t(i+1) - hist_t(i))
          return
        end if
      end do
    end if
  end function history_factor
end module history_file
