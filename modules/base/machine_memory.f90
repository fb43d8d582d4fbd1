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
    integer :: unit, ios
    integer(gp) :: kb
    character(len=256) :: line
    bytes = -1
    open(newunit=unit, file='/proc/meminfo', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, 'MemTotal:') /= 1) cycle
      read(line(10:), *, iostat=ios) kb          ! "MemTotal:   16318412 kB"
      if (ios == 0 .and. kb > 0 .and. kb < 2_gp**40) bytes = kb * 1024
      exit
    end do
    close(unit)
  end function total_memory_bytes

  !> VmHWM of /proc/self/status, the peak resident set of this process
  !> [bytes]; -1 when it cannot be read.
  function peak_resident_bytes() result(bytes)
    integer(gp) :: bytes
    integer :: unit, ios
    integer(gp) :: kb
    character(len=256) :: line
    bytes = -1
    open(newunit=unit, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, 'VmHWM:') /= 1) cycle
      read(line(7:), *, iostat=ios) kb           ! "VmHWM:     123456 kB"
      if (ios == 0 .and. kb >= 0) bytes = kb * 1024
      exit
    end do
    close(unit)
  end function peak_resident_bytes
end module machine_memory
