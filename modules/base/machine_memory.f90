!> The memory of the machine, for refusing a run that cannot fit before it
!> allocates: MemTotal of /proc/meminfo (Linux), in bytes; the peak
!> resident memory of this process (VmHWM of /proc/self/status), for the
!> timing summary; and return_freed_memory, which lets glibc's malloc give
!> freed memory back to the system.
module machine_memory
  use, intrinsic :: iso_c_binding, only: c_int
  use kinds, only: gp
  implicit none
  private

  public :: total_memory_bytes, peak_resident_bytes, return_freed_memory

  !> mallopt's parameters (glibc's malloc.h)
  integer(c_int), parameter :: m_trim_threshold = -1_c_int, m_mmap_threshold = -3_c_int, &
                               m_mmap_max = -4_c_int
  !> blocks from this size up get their own mapping, returned on free [bytes]
  integer(c_int), parameter :: mmap_threshold = 8 * 2**20
  !> free memory at the top of the heap beyond this is returned [bytes]
  integer(c_int), parameter :: trim_threshold = 16 * 2**20
  !> glibc's default number of separate mappings
  integer(c_int), parameter :: mmap_max = 65536_c_int

  interface
    integer(c_int) function mallopt(param, value) bind(c, name='mallopt')
      import :: c_int
      integer(c_int), value :: param, value
    end function mallopt
  end interface

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

  !> Let malloc return freed memory to the system again. hypre's
  !> dependency SuperLU_DIST (Debian's libsuperlu-dist 8) carries CombBLAS
  !> code whose load-time initializer calls mallopt(M_MMAP_MAX, 0) and
  !> mallopt(M_TRIM_THRESHOLD, -1): every block then comes from the heap
  !> and nothing freed is ever returned, so the resident set only grows
  !> (each freed matrix or work array stays, and the next larger one is
  !> added above it). Here blocks of 8 MB and more (matrices, the large
  !> temporaries of a set-up) get their own mappings again, returned when
  !> freed; smaller ones (halo buffers, hypre's per-call work arrays, which
  !> would each cost a mapping and its page faults) stay in the heap, whose
  !> free top is returned beyond 16 MB. On HI24L's medium stand-in (2 ranks)
  !> the peak fell from 1,418 to about 1,220 MB a rank. Not collective;
  !> call it once, first thing.
  subroutine return_freed_memory()
    integer(c_int) :: ok
    ok = mallopt(m_mmap_max, mmap_max)
    ok = mallopt(m_mmap_threshold, mmap_threshold)
    ok = mallopt(m_trim_threshold, trim_threshold)
  end subroutine return_freed_memory

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
