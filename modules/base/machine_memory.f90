!> The memory of the machine, for refusing a run that cannot fit before it
!> allocates: MemTotal of /proc/meminfo (Linux), in bytes; and the peak
!> resident memory of this process (VmHWM of /proc/self/status), for the
!> timing summary.
module machine_memory
  use kinds, only: gp
  implicit none
  private

  public :: total_memory_bytes, peak_resident_bytes

contains

  !> MemTotal of /proc/meminfo [bytes]; -1 when the file cannot be read or
  !> has no such line (another system: no limit is then known).
  function total_memory_bytes() result(bytes)
    integer(gp) :: bytes
    bytes = proc_kb('/proc/meminfo', 'MemTotal:')
    if (bytes > 0 .and. bytes < 2_gp**40) then
      bytes = bytes * 1024
    else
      bytes = -1
    end if
  end function total_memory_bytes

  !> VmHWM of /proc/self/status, the peak resident set of this process
  !> [bytes]; -1 when it cannot be read.
  function peak_resident_bytes() result(bytes)
    integer(gp) :: bytes
    bytes = proc_kb('/proc/self/status', 'VmHWM:')
    if (bytes >= 0) bytes = bytes * 1024
  end function peak_resident_bytes

  !> The number of kB on the line of file that starts with key (e.g.
  !> "MemTotal:   16318412 kB"); -1 when the file or the line is missing.
  function proc_kb(file, key) result(kb)
    character(len=*), intent(in) :: file, key
    integer(gp) :: kb
    integer :: unit, ios
    character(len=256) :: line
    kb = -1
    open(newunit=unit, file=file, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, key) /= 1) cycle
      read(line(len(key) + 1:), *, iostat=ios) kb
      if (ios /= 0) kb = -1
      exit
    end do
    close(unit)
  end function proc_kb
end module machine_memory
