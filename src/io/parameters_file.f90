!> The run's resolved deck, <out_dir>/<prefix>_parameters.nml: every group
!> the run used and every variable of it, defaults included, each with its
!> unit and meaning in a trailing comment. It is itself a deck: run with
!> geoblock it reproduces the run (the same outputs, bit for bit, given
!> another &output dir or prefix). The same groups are echoed to the log.
!>
!> The groups come from the config types' describe methods (module
!> param_group), gathered by the driver; this module only lays them out.
module parameters_file
  use, intrinsic :: iso_fortran_env, only: output_unit
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use param_group, only: param_group_t, param_line_len, push_line
  implicit none
  private

  public :: write_parameters, print_parameters, deck_text

contains

  !> The deck text of groups, after the comment lines of header.
  function deck_text(groups, header) result(text)
    type(param_group_t), intent(in) :: groups(:)
    character(len=*), intent(in) :: header(:)
    character(len=param_line_len), allocatable :: text(:)
    character(len=param_line_len), allocatable :: part(:)
    integer :: g, j
    ! no array constructors: gfortran 12's checked build mistakes their lengths
    allocate(text(0))
    do g = 1, size(header)
      call push_line(text, '! '//trim(header(g)))
    end do
    do g = 1, size(groups)
      call push_line(text, '')
      part = groups(g)%lines()
      do j = 1, size(part)
        call push_line(text, part(j))
      end do
    end do
  end function deck_text

  !> Echo groups to the log and write them as a deck to path (rank 0).
  !> Collective; status (the same on every rank) names the file when it
  !> cannot be written.
  subroutine write_parameters(comm, log, path, groups, header, status)
    type(parallel_comm_t), intent(in) :: comm
    type(logger_t), intent(inout) :: log
    character(len=*), intent(in) :: path
    type(param_group_t), intent(in) :: groups(:)
    character(len=*), intent(in) :: header(:)
    type(error_status_t), intent(inout) :: status
    character(len=param_line_len), allocatable :: text(:)
    integer :: g, u, ios
    character(len=256) :: msg
    call log%detail('parameters (all of them also in '//trim(path)//'):')
    do g = 1, size(groups)
      call groups(g)%echo(log)
    end do
    if (comm%is_root()) then
      text = deck_text(groups, header)
      open(newunit=u, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios == 0) then
        do g = 1, size(text)
          write(u, '(a)', iostat=ios, iomsg=msg) trim(text(g))
          if (ios /= 0) exit
        end do
        close(u)
      end if
      if (ios /= 0) call status%set("cannot write the parameters file '"//trim(path)//"': "//trim(msg))
    end if
    call agree(comm, status)
  end subroutine write_parameters

  !> Print groups as a deck on standard output (rank 0).
  subroutine print_parameters(comm, groups, header)
    type(parallel_comm_t), intent(in) :: comm
    type(param_group_t), intent(in) :: groups(:)
    character(len=*), intent(in) :: header(:)
    character(len=param_line_len), allocatable :: text(:)
    integer :: i
    if (.not. comm%is_root()) return
    text = deck_text(groups, header)
    do i = 1, size(text)
      write(output_unit, '(a)') trim(text(i))
    end do
    flush(output_unit)
  end subroutine print_parameters
end module parameters_file
