!> Deck group &probe (any number): time histories of fields at points or
!> averaged over a surface set, one column each in <dir>/<prefix>_probes.csv.
!>
!>   name      the probe's name, used in the column headers
!>             (letters, digits, '_', unique)                         ['probe<k>']
!>   x, y, z   coordinates [m] of up to 64 points (lists of the same
!>             length); the value at a point is the value of the cell
!>             that contains it (cell fields) or the Q1 interpolation in
!>             that cell (displacement)                               [none]
!>   set       a surface set of the mesh instead of points: the mean
!>             over the set's nodes (displacement) or over the cells
!>             that have a face in the set (cell fields)               ['']
!>   fields    what to probe, up to 16 of: ux, uy, uz [m]; p [Pa]
!>             (physics biot); sxx, syy, szz, sxy, syz, sxz [Pa],
!>             total stress, tension positive                         [required]
!> Whether the physics has a field and whether the points lie in the mesh
!> and the set exists is checked once the mesh is built (probe_output).
module probe_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use strings, only: itoa
  use deck, only: deck_t, line_len, unset_real
  use param_group, only: param_group_t
  implicit none
  private

  public :: probe_config_t, read_probes, probe_quantities, probe_unit, describe_probe

  integer, parameter :: max_points = 64, max_fields = 16

  !> Every field a probe may name, and its unit.
  character(len=8), parameter :: probe_quantities(10) = [character(len=8) :: 'ux', 'uy', 'uz', 'p', &
    'sxx', 'syy', 'szz', 'sxy', 'syz', 'sxz']

  type :: probe_config_t
    character(len=name_len) :: name = ''
    real(rp), allocatable :: points(:,:)             !< (3, n) [m]; size 0 for a set probe
    character(len=name_len) :: set = ''
    character(len=8), allocatable :: fields(:)
    integer :: group = 0                             !< occurrence in the deck (for messages)
  end type probe_config_t

contains

  !> Read every &probe group (names, point lists and field names checked).
  subroutine read_probes(d, log, probes, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(probe_config_t), allocatable, intent(out) :: probes(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: name, set
    real(rp) :: x(max_points), y(max_points), z(max_points)
    character(len=8) :: fields(max_fields)
    integer :: k, ios, n(3), nf
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /probe/ name, x, y, z, set, fields
    allocate(probes(d%count('probe')))
    do k = 1, size(probes)
      name = 'probe'//itoa(k); set = ''; fields = ''
      x = unset_real; y = unset_real; z = unset_real
      call d%block('probe', k, b)
      read(b, nml=probe, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('probe', k, ios, msg, status)
        return
      end if
      n = [count(x /= unset_real), count(y /= unset_real), count(z /= unset_real)]
      nf = count(fields /= '')
      call check_probe(d, k, probes(1:k-1), name, set, x, y, z, n, fields, status)
      if (.not. status%ok()) return
      probes(k)%name = name
      probes(k)%set = set
      probes(k)%group = k
      allocate(probes(k)%points(3, n(1)))
      probes(k)%points(1, :) = x(1:n(1))
      probes(k)%points(2, :) = y(1:n(1))
      probes(k)%points(3, :) = z(1:n(1))
      probes(k)%fields = pack(fields, fields /= '')
    end do
  end subroutine read_probes

  subroutine describe_probe(p, g)
    type(probe_config_t), intent(in) :: p
    type(param_group_t), intent(out) :: g
    call g%init('probe', 'time histories of fields at points or averaged over a surface set, columns of '// &
                '<prefix>_probes.csv')
    call g%add('name', p%name, '-', 'column prefix in <prefix>_probes.csv', "letters, digits, '_'; unique")
    if (size(p%points, 2) > 0) then
      call g%add('x', p%points(1, :), 'm', 'x of the probed points (x, y, z or set)', 'up to 64', 'real list')
      call g%add('y', p%points(2, :), 'm', 'y of the probed points', 'as many as x', 'real list')
      call g%add('z', p%points(3, :), 'm', 'z of the probed points', 'as many as x', 'real list')
      call g%add_unset('set', '(none: points)', '-', 'a surface set instead of points: the mean over it', 'string')
    else
      call g%add_unset('x', '(none: a set)', 'm', 'x of the probed points (x, y, z or set)', 'real list', &
                       'up to 64')
      call g%add_unset('y', '(none: a set)', 'm', 'y of the probed points', 'real list', 'as many as x')
      call g%add_unset('z', '(none: a set)', 'm', 'z of the probed points', 'real list', 'as many as x')
      call g%add('set', p%set, '-', 'a surface set instead of points: the mean over it')
    end if
    call g%add('fields', p%fields, '-', "what to probe: ux, uy, uz [m]; p [Pa] (biot); sxx ... sxz [Pa], "// &
               "total stress, tension positive", "up to 16 of 'ux', 'uy', 'uz', 'p', 'sxx', 'syy', 'szz', "// &
               "'sxy', 'syz', 'sxz'")
  end subroutine describe_probe

  !> The checks of one group that need no mesh.
  subroutine check_probe(d, k, earlier, name, set, x, y, z, n, fields, status)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: k, n(3)
    type(probe_config_t), intent(in) :: earlier(:)
    character(len=*), intent(in) :: name, set, fields(:)
    real(rp), intent(in) :: x(:), y(:), z(:)
    type(error_status_t), intent(inout) :: status
    character(len=*), parameter :: name_chars = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_'
    integer :: i
    if (len_trim(name) == 0 .or. verify(trim(name), name_chars) /= 0) &
      call d%fail(status, 'probe', k, 'name', "letters, digits and '_' only (got '"//trim(name)//"')")
    if (any(earlier%name == name)) call d%fail(status, 'probe', k, 'name', "'"//trim(name)//"' is used twice")
    if (n(1) /= n(2) .or. n(1) /= n(3)) call d%fail(status, 'probe', k, 'x', 'x, y and z must list the same '// &
      'number of coordinates (got '//itoa(n(1))//', '//itoa(n(2))//', '//itoa(n(3))//')')
    if (count(x /= unset_real) > 0 .and. any(x(1:n(1)) == unset_real)) &
      call d%fail(status, 'probe', k, 'x', 'the coordinates must be a list without gaps')
    if (count(y /= unset_real) > 0 .and. any(y(1:n(2)) == unset_real)) &
      call d%fail(status, 'probe', k, 'y', 'the coordinates must be a list without gaps')
    if (count(z /= unset_real) > 0 .and. any(z(1:n(3)) == unset_real)) &
      call d%fail(status, 'probe', k, 'z', 'the coordinates must be a list without gaps')
    if (n(1) == 0 .and. len_trim(set) == 0) &
      call d%fail(status, 'probe', k, 'x', 'give points (x, y, z) or a surface set (set)')
    if (n(1) > 0 .and. len_trim(set) > 0) &
      call d%fail(status, 'probe', k, 'set', 'give either points (x, y, z) or a set, not both')
    if (count(fields /= '') == 0) call d%fail(status, 'probe', k, 'fields', 'required: one or more of '//quantity_list())
    do i = 1, size(fields)
      if (fields(i) == '') cycle
      if (.not. any(probe_quantities == fields(i))) call d%fail(status, 'probe', k, 'fields', "unknown field '"// &
        trim(fields(i))//"' (one of "//quantity_list()//')')
      if (count(fields(1:i) == fields(i)) > 1) call d%fail(status, 'probe', k, 'fields', "'"//trim(fields(i))// &
        "' is listed twice")
    end do
  end subroutine check_probe

  !> The names of probe_quantities, comma-separated.
  function quantity_list() result(s)
    character(len=:), allocatable :: s
    integer :: i
    s = trim(probe_quantities(1))
    do i = 2, size(probe_quantities)
      s = s//', '//trim(probe_quantities(i))
    end do
  end function quantity_list

  !> Unit of a probe quantity.
  function probe_unit(q) result(u)
    character(len=*), intent(in) :: q
    character(len=2) :: u
    u = 'Pa'
    if (q(1:1) == 'u') u = 'm'
  end function probe_unit
end module probe_config
