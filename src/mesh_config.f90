!> Deck group &mesh: where the mesh comes from.
!>
!>   source   'box' (generated) or 'gmsh' (an MSH 4.1 ASCII file)          [box]
!>   file     the .msh file, for source = 'gmsh' (relative to the run dir)
!>   nx, ny, nz                cells per axis, for the box (>= 1)          [required for box]
!>   lower(3), upper(3)        box extents [m]                            [0,0,0], [1,1,1]
!>   grading(3)                last/first cell size ratio per axis (> 0)  [1,1,1]
module mesh_config
  use kinds, only: rp, ip, path_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, echo_len, unset_int
  use strings, only: itoa
  implicit none
  private

  public :: mesh_config_t

  type :: mesh_config_t
    character(len=16) :: source = 'box'
    character(len=path_len) :: file = ''
    integer(ip) :: n(3) = 0
    real(rp) :: lower(3) = 0.0_rp, upper(3) = 1.0_rp, grading(3) = 1.0_rp
  contains
    procedure :: read => read_mesh_config
  end type mesh_config_t

contains

  !> Read and check &mesh; echo it to the log.
  subroutine read_mesh_config(self, d, log, status)
    class(mesh_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=16) :: source
    character(len=path_len) :: file
    integer :: nx, ny, nz, ios
    real(rp) :: lower(3), upper(3), grading(3)
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=echo_len) :: echo(32)
    character(len=32) :: got
    integer :: i
    namelist /mesh/ source, file, nx, ny, nz, lower, upper, grading

    source = 'box'; file = ''; nx = unset_int; ny = unset_int; nz = unset_int
    lower = 0.0_rp; upper = 1.0_rp; grading = 1.0_rp
    if (d%count('mesh') == 0) then
      call status%set("deck '"//trim(d%path)//"': group &mesh is missing")
      return
    end if
    call d%block('mesh', 1, b)
    read(b, nml=mesh, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call d%read_error('mesh', 1, ios, msg, status)
      return
    end if
    select case (source)
    case ('box')
      if (nx == unset_int) call d%fail(status, 'mesh', 1, 'nx', 'required for a box mesh')
      if (ny == unset_int) call d%fail(status, 'mesh', 1, 'ny', 'required for a box mesh')
      if (nz == unset_int) call d%fail(status, 'mesh', 1, 'nz', 'required for a box mesh')
      if (.not. status%ok()) return
      if (nx < 1) call d%fail(status, 'mesh', 1, 'nx', 'must be at least 1 (got '//itoa(nx)//')')
      if (ny < 1) call d%fail(status, 'mesh', 1, 'ny', 'must be at least 1 (got '//itoa(ny)//')')
      if (nz < 1) call d%fail(status, 'mesh', 1, 'nz', 'must be at least 1 (got '//itoa(nz)//')')
      do i = 1, 3
        if (upper(i) <= lower(i)) then
          write(got, '(i0)') i
          call d%fail(status, 'mesh', 1, 'upper('//trim(got)//')', 'must be greater than lower('//trim(got)//')')
        end if
        if (grading(i) <= 0.0_rp) then
          write(got, '(i0)') i
          call d%fail(status, 'mesh', 1, 'grading('//trim(got)//')', 'must be positive')
        end if
      end do
    case ('gmsh')
      if (len_trim(file) == 0) call d%fail(status, 'mesh', 1, 'file', "required when source = 'gmsh'")
    case default
      call d%fail(status, 'mesh', 1, 'source', "must be 'box' or 'gmsh' (got '"//trim(source)//"')")
    end select
    if (.not. status%ok()) return
    self%source = source
    self%file = file
    self%n = [nx, ny, nz]
    self%lower = lower
    self%upper = upper
    self%grading = grading
    echo = ''
    write(echo, nml=mesh, iostat=ios)
    call d%echo(log, echo)
  end subroutine read_mesh_config
end module mesh_config
