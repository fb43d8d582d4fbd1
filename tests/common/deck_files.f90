!> Test helper: write a deck (or any text file) from rank 0, then wait for it
!> on every rank.
module deck_files
  use parallel_comm, only: parallel_comm_t
  implicit none
  private

  public :: write_lines

contains

  subroutine write_lines(comm, path, lines)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path, lines(:)
    integer :: u, i
    if (comm%is_root()) then
      open(newunit=u, file=path, status='replace', action='write')
      do i = 1, size(lines)
        write(u, '(a)') trim(lines(i))
      end do
      close(u)
    end if
    call comm%barrier()
  end subroutine write_lines
end module deck_files
