!> Deck group &mesh: where the mesh comes from.
!>
!>   source   'box' (generated) or 'gmsh' (an MSH 4.1 ASCII file)          [box]
!>   file     the .msh file, for source = 'gmsh' (relative to the run dir)
!>   nx, ny, nz                cells per axis, for the box (>= 1)          [required for box]
!>   lower(3), upper(3)        box extents [m]                            [0,0,0], [1,1,1]
!>   grading(3)                last/first cell size ratio per axis (> 0)  [1,1,1]
!>   core_n(3)                 box: uniform cells in a core refinement per axis;
!>                             0 = no core on that axis (>= 0)             [0,0,0]
!>   core_lower(3), core_upper(3)  box: the core [m] along the axes with
!>                             core_n > 0, inside [lower, upper]; the other
!>                             n - core_n cells grow geometrically away from
!>                             the core (its size next to it), shared by the
!>                             parts below and above by length, at least one
!>                             each: core_n <= n - 2 when the core touches
!>                             neither end, n - 1 when it touches one, = n when
!>                             it spans the box; grading is ignored on that axis
!>                             (values on axes with core_n = 0 are ignored)
!>                                                                  [required there]
!>   memory_limit              box: the memory the run may use [GB]; a box
!>                             whose estimate (below) exceeds it is refused
!>                             before anything is allocated; 0 = the
!>                             machine's MemTotal (/proc/meminfo, read on
!>                             rank 0; on a cluster give the job's total)  [0]
!>
!> Box sizes: nx*ny*nz cells and (nx+1)(ny+1)(nz+1) nodes must fit default
!> integers; the estimate is cells x bytes_per_cell, a figure measured as the
!> peak memory of a run over its cells (a 30^3 box against a 10^3 box, one
!> rank, BoomerAMG): about 10 kB per cell for elasticity and 19 kB for Biot;
!> with margin, 12 kB (elasticity, contact) and 24 kB (biot) are used.
module mesh_config
  use kinds, only: rp, ip, gp, path_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_int, unset_real
  use strings, only: itoa, rtoa
  use os_services, only: absolute_path
  use param_group, only: param_group_t
  use machine_memory, only: total_memory_bytes
  use region_config, only: region_config_t, read_regions
  implicit none
  private

  public :: mesh_config_t

  !> Largest box extent magnitude [m] (as the Gmsh reader's coordinates).
  real(rp), parameter :: max_extent = 1.0e30_rp

  type :: mesh_config_t
    character(len=16) :: source = 'box'
    character(len=path_len) :: file = ''
    integer(ip) :: n(3) = 0
    real(rp) :: lower(3) = 0.0_rp, upper(3) = 1.0_rp, grading(3) = 1.0_rp
    integer(ip) :: core_n(3) = 0
    real(rp) :: core_lower(3) = 0.0_rp, core_upper(3) = 0.0_rp   !< [m], used where core_n > 0
    real(rp) :: memory_limit = 0.0_rp                            !< [GB], 0 = MemTotal
    type(region_config_t), allocatable :: regions(:)             !< &region groups (box only)
  contains
    procedure :: read => read_mesh_config
    procedure :: describe => describe_mesh_config
    procedure :: describe_regions
    procedure :: check_size
  end type mesh_config_t

contains

  !> Read and check &mesh (describe gives its resolved values).
  subroutine read_mesh_config(self, d, log, status)
    class(mesh_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    character(len=16) :: source
    character(len=path_len) :: file
    integer :: nx, ny, nz, ios
    real(rp) :: lower(3), upper(3), grading(3), core_lower(3), core_upper(3)
    integer :: core_n(3), n_parts, nn(3)
    real(rp) :: tol, memory_limit
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=32) :: got
    integer :: i
    namelist /mesh/ source, file, nx, ny, nz, lower, upper, grading, core_n, core_lower, core_upper, memory_limit

    source = 'box'; file = ''; nx = unset_int; ny = unset_int; nz = unset_int; memory_limit = 0.0_rp
    lower = 0.0_rp; upper = 1.0_rp; grading = 1.0_rp
    core_n = 0; core_lower = unset_real; core_upper = unset_real
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
      if (memory_limit < 0.0_rp) call d%fail(status, 'mesh', 1, 'memory_limit', &
        'must be 0 (the machine''s memory) or positive [GB] (got '//rtoa(memory_limit)//')')
      if (status%ok()) call check_counts(d, [nx, ny, nz], status)
      do i = 1, 3
        if (upper(i) <= lower(i)) then
          write(got, '(i0)') i
          call d%fail(status, 'mesh', 1, 'upper('//trim(got)//')', 'must be greater than lower('//trim(got)//')')
        end if
        if (abs(lower(i)) > max_extent .or. abs(upper(i)) > max_extent) then
          write(got, '(i0)') i
          call d%fail(status, 'mesh', 1, 'upper('//trim(got)//')', 'lower and upper must be within 1e30 m '// &
                      'of the origin')
        end if
        if (grading(i) <= 0.0_rp) then
          write(got, '(i0)') i
          call d%fail(status, 'mesh', 1, 'grading('//trim(got)//')', 'must be positive')
        end if
      end do
      if (.not. status%ok()) return
      nn = [nx, ny, nz]
      do i = 1, 3
        write(got, '(i0)') i
        if (core_n(i) < 0) call d%fail(status, 'mesh', 1, 'core_n('//trim(got)//')', 'must not be negative (got '// &
                                       itoa(core_n(i))//')')
        if (core_n(i) <= 0) cycle
        if (core_lower(i) == unset_real) call d%fail(status, 'mesh', 1, 'core_lower('//trim(got)//')', &
                                                     'required with core_n('//trim(got)//') > 0')
        if (core_upper(i) == unset_real) call d%fail(status, 'mesh', 1, 'core_upper('//trim(got)//')', &
                                                     'required with core_n('//trim(got)//') > 0')
        if (.not. status%ok()) return
        tol = 1.0e-12_rp * (upper(i) - lower(i))
        if (core_lower(i) < lower(i) - tol .or. core_upper(i) > upper(i) + tol .or. core_upper(i) <= core_lower(i)) &
          call d%fail(status, 'mesh', 1, 'core_lower('//trim(got)//')', 'the core ['//rtoa(core_lower(i))//', '// &
                      rtoa(core_upper(i))//'] must be a non-empty interval inside ['//rtoa(lower(i))//', '// &
                      rtoa(upper(i))//']')
        n_parts = count([core_lower(i) - lower(i) > tol, upper(i) - core_upper(i) > tol])
        if (status%ok() .and. core_n(i) > nn(i) - n_parts) &
          call d%fail(status, 'mesh', 1, 'core_n('//trim(got)//')', 'must be at most n - '//itoa(n_parts)//' = '// &
                      itoa(nn(i) - n_parts)//' (one cell at least for each part of the box outside the '// &
                      'core; got '//itoa(core_n(i))//')')
        if (status%ok() .and. n_parts == 0 .and. core_n(i) /= nn(i)) &
          call d%fail(status, 'mesh', 1, 'core_n('//trim(got)//')', 'must equal n = '//itoa(nn(i))// &
                      ' when the core spans the box (got '//itoa(core_n(i))//')')
      end do
      if (all(core_n == 0) .and. (any(core_lower /= unset_real) .or. any(core_upper /= unset_real))) &
        call d%fail(status, 'mesh', 1, 'core_n', 'core_lower and core_upper need core_n > 0 on some axis')
    case ('gmsh')
      if (len_trim(file) == 0) call d%fail(status, 'mesh', 1, 'file', "required when source = 'gmsh'")
      if (any(core_n /= 0)) call d%fail(status, 'mesh', 1, 'core_n', "only for source = 'box'")
      if (any(core_lower /= unset_real)) call d%fail(status, 'mesh', 1, 'core_lower', "only for source = 'box'")
      if (any(core_upper /= unset_real)) call d%fail(status, 'mesh', 1, 'core_upper', "only for source = 'box'")
      if (memory_limit /= 0.0_rp) call d%fail(status, 'mesh', 1, 'memory_limit', "only for source = 'box' (a "// &
        "Gmsh file's counts are bounded by its size)")
    case default
      call d%fail(status, 'mesh', 1, 'source', "must be 'box' or 'gmsh' (got '"//trim(source)//"')")
    end select
    if (.not. status%ok()) return
    self%source = source
    call d%input_path('mesh', 1, 'file', file, self%file, status)
    self%n = [nx, ny, nz]
    self%lower = lower
    self%upper = upper
    self%grading = grading
    self%core_n = core_n
    self%memory_limit = memory_limit
    self%core_lower = merge(core_lower, 0.0_rp, core_n > 0)
    self%core_upper = merge(core_upper, 0.0_rp, core_n > 0)
    where (core_lower == unset_real) core_lower = 0.0_rp
    where (core_upper == unset_real) core_upper = 0.0_rp
    if (status%ok()) call read_regions(d, log, self%source, self%regions, status)
  end subroutine read_mesh_config

  !> The resolved &mesh group: for a box its sizes (the core only when some
  !> axis has one), for a Gmsh mesh the file (as an absolute path).
  subroutine describe_mesh_config(self, g)
    class(mesh_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('mesh', 'where the mesh comes from: a generated box or a Gmsh file (required)')
    call g%add('source', self%source, '-', 'a generated box or a Gmsh MSH 4.1 ASCII file of hexahedra', &
               "'box' or 'gmsh'")
    if (self%source == 'gmsh') then
      call g%add('file', absolute_path(self%file), '-', "source = 'gmsh': the mesh file (relative to the deck's "// &
                 "directory)", 'MSH 4.1 ASCII, 8-node hexahedra')
      return
    end if
    call g%add('nx', int(self%n(1)), '-', 'box: cells along x', '>= 1')
    call g%add('ny', int(self%n(2)), '-', 'box: cells along y', '>= 1')
    call g%add('nz', int(self%n(3)), '-', 'box: cells along z', '>= 1')
    call g%add('lower', self%lower, 'm', 'box: lower corner', 'magnitude <= 1e30')
    call g%add('upper', self%upper, 'm', 'box: upper corner', '> lower, magnitude <= 1e30')
    call g%add('grading', self%grading, '-', 'box: last/first cell size ratio per axis', '> 0')
    call g%add('core_n', int(self%core_n), '-', 'box: uniform cells of a core refinement per axis (0: none); '// &
               'the other cells grow geometrically away from it, grading ignored there', &
               '0..n; <= n - 2 when the core touches neither end, n - 1 when one, n when it spans the box')
    if (self%memory_limit > 0.0_rp) then
      call g%add('memory_limit', self%memory_limit, 'GB', 'box: memory the run may use; a larger estimate '// &
                 '(12 kB a cell, biot 24 kB) is refused before anything is allocated', '>= 0')
    else
      call g%add_unset('memory_limit', '(0: the machine)', 'GB', 'box: memory the run may use; a larger '// &
                       "estimate (12 kB a cell, biot 24 kB) is refused before anything is allocated (0: rank 0's "// &
                       'MemTotal)', 'real', '>= 0')
    end if
    if (any(self%core_n > 0)) then
      call g%add('core_lower', self%core_lower, 'm', 'box: lower end of the core on the axes with core_n > 0 '// &
                 '(required there)', 'inside [lower, upper]')
      call g%add('core_upper', self%core_upper, 'm', 'box: upper end of the core on the axes with core_n > 0 '// &
                 '(required there)', '> core_lower, inside [lower, upper]')
    end if
  end subroutine describe_mesh_config

  !> The resolved &region groups, one per region (none without them).
  subroutine describe_regions(self, groups)
    class(mesh_config_t), intent(in) :: self
    type(param_group_t), allocatable, intent(out) :: groups(:)
    integer :: k
    allocate(groups(0))
    if (.not. allocated(self%regions)) return
    deallocate(groups)
    allocate(groups(size(self%regions)))
    do k = 1, size(self%regions)
      call self%regions(k)%describe(groups(k))
    end do
  end subroutine describe_regions

  !> Cells nx*ny*nz and nodes (nx+1)(ny+1)(nz+1) must be default integers
  !> (products formed in double precision: no integer overflow).
  subroutine check_counts(d, n, status)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: n(3)
    type(error_status_t), intent(inout) :: status
    real(rp) :: cells, nodes
    cells = real(n(1), rp) * real(n(2), rp) * real(n(3), rp)
    nodes = real(n(1) + 1_8, rp) * real(n(2) + 1_8, rp) * real(n(3) + 1_8, rp)
    if (nodes > real(huge(1), rp)) call d%fail(status, 'mesh', 1, 'nx, ny, nz', 'nx*ny*nz = '// &
      itoa(n(1))//'*'//itoa(n(2))//'*'//itoa(n(3))//' = '//count_text(cells)//' cells with '//count_text(nodes)// &
      ' nodes: more than the 2147483647 that default integers count')
  end subroutine check_counts

  !> The estimated memory of a box run of physics `physics` (cells x a
  !> measured figure per cell, see the module header) against memory_limit,
  !> or the machine's memory mem_total [bytes] (rank 0's MemTotal, -1 when
  !> unknown: then only an explicit limit applies). For a Gmsh mesh the
  !> reader bounds its counts by the file's size instead. The same on every
  !> rank when mem_total is.
  subroutine check_size(self, d, physics, mem_total, status)
    class(mesh_config_t), intent(in) :: self
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: physics
    integer(gp), intent(in) :: mem_total
    type(error_status_t), intent(inout) :: status
    real(rp) :: cells, need, limit, per_cell
    character(len=:), allocatable :: whose
    if (self%source /= 'box' .or. .not. status%ok()) return
    per_cell = merge(24.0e3_rp, 12.0e3_rp, physics == 'biot')
    cells = real(self%n(1), rp) * real(self%n(2), rp) * real(self%n(3), rp)
    need = cells * per_cell
    if (self%memory_limit > 0.0_rp) then
      limit = self%memory_limit * 1.0e9_rp
      whose = 'memory_limit'
    else if (mem_total > 0) then
      limit = real(mem_total, rp)
      whose = "the machine's memory (MemTotal of /proc/meminfo; set memory_limit [GB] to change it)"
    else
      return
    end if
    if (need > limit) call d%fail(status, 'mesh', 1, 'nx, ny, nz', itoa(self%n(1))//' x '//itoa(self%n(2))//' x '// &
      itoa(self%n(3))//' = '//count_text(cells)//' cells need about '//gb_text(need)//' GB for '//trim(physics)// &
      ' (about '//itoa(nint(per_cell / 1.0e3_rp))//' kB per cell), more than the '//gb_text(limit)//' GB of '//whose)
  end subroutine check_size

  !> A count held in a double as text (exact below 2**53).
  function count_text(x) result(s)
    real(rp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: t
    if (x < 1.0e15_rp) then
      write(t, '(i0)') nint(x, kind=gp)
    else
      write(t, '(es10.3)') x
    end if
    s = trim(adjustl(t))
  end function count_text

  !> Bytes as gigabytes with one decimal.
  function gb_text(bytes) result(s)
    real(rp), intent(in) :: bytes
    character(len=:), allocatable :: s
    character(len=32) :: t
    write(t, '(f0.1)') bytes / 1.0e9_rp
    if (t(1:1) == '.') t = '0'//trim(t)
    s = trim(t)
  end function gb_text
end module mesh_config
