!> Time histories of a run: <dir>/<prefix>_probes.csv, written by rank 0,
!> one row per accepted step with the step, its time (or load factor), the
!> &probe columns and the physics' own scalars (probe_fields_t names). The
!> header names every column with its unit:
!>   <probe>:<field> [unit]        a probe with one point, or with a set
!>   <probe>(<i>):<field> [unit]   point i (from 1) of a probe with several
!> A point belongs to the cell that contains it; of several (a point on a
!> face, edge or node) the one first in the mesh before the partition, so
!> that the choice and the values do not depend on the number of ranks. The
!> owner of that cell computes the value: the cell's value for p and the
!> stress, the Q1 interpolation in the cell for the displacement; the other
!> ranks add zero. A set probe is the mean over the set's owned nodes
!> (displacement) or over the (set face, owned cell) pairs (cell fields),
!> summed over the ranks. A restarted run keeps the rows of the file up to
!> the checkpoint's step and goes on, as residual_history does. Collective
!> unless said otherwise.
module probe_output
  use kinds, only: rp, ip, path_len, name_len
  use error_status, only: error_status_t
  use strings, only: itoa, rtoa
  use os_services, only: rename_path, make_directory
  use deck, only: deck_t
  use probe_config, only: probe_config_t, probe_quantities, probe_unit
  use dist_mesh, only: dist_mesh_t
  use hex_q1, only: hex_shape
  use probe_fields, only: probe_fields_t
  implicit none
  private

  public :: probe_output_t

  integer, parameter :: row_len = 65536

  !> Where the values of one probe come from on this rank.
  type :: probe_site_t
    integer(ip), allocatable :: cell(:)        !< per point: owned local cell, 0 if another rank's
    real(rp), allocatable :: xi(:,:)           !< (3, points) reference coordinates in that cell
    integer(ip) :: set = 0                     !< set probes: the mesh's set id
  end type probe_site_t

  type :: probe_output_t
    type(probe_config_t), allocatable :: cfg(:)
    type(probe_site_t), allocatable :: site(:)
    character(len=path_len) :: path = ''
    logical :: transient = .false.
    integer :: keep_through = -huge(1)         !< restart: rows up to this step are kept
    logical :: opened = .false.
    integer :: unit = 0
  contains
    procedure :: init
    procedure :: record
    procedure :: free
  end type probe_output_t

contains

  !> Locate the probes cfg of deck d on mesh; available: the quantities the
  !> physics (named physics) can give. path: the CSV file; transient: the
  !> second column is a time [s], else a load factor; keep_through: the last
  !> step of the run resumed from (restart), else absent. Errors name the
  !> deck, the group and the variable; the same on every rank.
  subroutine init(self, d, cfg, mesh, available, physics, path, transient, status, keep_through)
    class(probe_output_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(probe_config_t), intent(in) :: cfg(:)
    type(dist_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: available(:), physics, path
    logical, intent(in) :: transient
    type(error_status_t), intent(inout) :: status
    integer, intent(in), optional :: keep_through
    integer :: k, j
    self%cfg = cfg
    self%path = path
    self%transient = transient
    if (present(keep_through)) self%keep_through = keep_through
    allocate(self%site(size(cfg)))
    do k = 1, size(cfg)
      do j = 1, size(cfg(k)%fields)
        if (.not. any(available == cfg(k)%fields(j))) then
          call d%fail(status, 'probe', cfg(k)%group, 'fields', "field '"//trim(cfg(k)%fields(j))// &
            "' is not available in physics '"//trim(physics)//"'")
          return
        end if
      end do
      if (len_trim(cfg(k)%set) > 0) then
        self%site(k)%set = mesh%set_id(cfg(k)%set)
        if (self%site(k)%set == 0) then
          call d%fail(status, 'probe', cfg(k)%group, 'set', "probe '"//trim(cfg(k)%name)//"': set '"// &
                      trim(cfg(k)%set)//"', which the mesh does not have")
          return
        end if
      end if
      call locate(self%site(k), cfg(k), mesh, d, status)
      if (.not. status%ok()) return
    end do
  end subroutine init

  !> The owning cell and reference coordinates of every point of probe c.
  subroutine locate(site, c, mesh, d, status)
    type(probe_site_t), intent(inout) :: site
    type(probe_config_t), intent(in) :: c
    type(dist_mesh_t), intent(in) :: mesh
    type(deck_t), intent(in) :: d
    type(error_status_t), intent(inout) :: status
    integer :: i
    logical :: found
    allocate(site%cell(size(c%points, 2)), site%xi(3, size(c%points, 2)))
    do i = 1, size(c%points, 2)
      call mesh%locate_point(c%points(:, i), site%cell(i), site%xi(:, i), found)
      if (.not. found) then
        call d%fail(status, 'probe', c%group, 'x', "probe '"//trim(c%name)//"': point "//itoa(i)//' ('// &
          trim(rtoa(c%points(1, i)))//', '//trim(rtoa(c%points(2, i)))//', '//trim(rtoa(c%points(3, i)))// &
          ') lies outside the mesh')
        return
      end if
    end do
  end subroutine locate

  !> One row: step `step` accepted at time t with the physics' fields pf.
  !> The file is opened (header, kept rows of a restart) at the first row.
  subroutine record(self, mesh, step, t, pf, status)
    class(probe_output_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer, intent(in) :: step
    real(rp), intent(in) :: t
    type(probe_fields_t), intent(in) :: pf
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: vals(:), cnt(:)
    character(len=:), allocatable :: row
    character(len=32) :: num
    integer :: j, ios
    call probe_values(self, mesh, pf, vals, cnt)
    call mesh%comm%sum_all(vals)
    call mesh%comm%sum_all(cnt)
    where (cnt > 0.0_rp) vals = vals / cnt
    if (allocated(pf%values)) vals = [vals, pf%values]
    if (size(vals) == 0 .or. .not. mesh%comm%is_root()) return
    if (.not. self%opened) call open_file(self, pf, status)
    if (.not. status%ok()) return
    write(num, '(es24.16e3)') t
    row = itoa(step)//','//trim(adjustl(num))
    do j = 1, size(vals)
      write(num, '(es24.16e3)') vals(j)
      row = row//','//trim(adjustl(num))
    end do
    write(self%unit, '(a)', iostat=ios) row
    if (ios == 0) flush(self%unit)
    if (ios /= 0) call status%set('cannot write '//trim(self%path))
  end subroutine record

  !> This rank's parts of the probe columns (vals) and, for the set means,
  !> the number of values summed (cnt; 0 for point columns).
  subroutine probe_values(self, mesh, pf, vals, cnt)
    type(probe_output_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(probe_fields_t), intent(in) :: pf
    real(rp), allocatable, intent(out) :: vals(:), cnt(:)
    integer :: k, i, j, m
    integer(ip) :: c, q, node, s, f, side
    real(rp) :: n(8), dn(3, 8)
    allocate(vals(0), cnt(0))
    do k = 1, size(self%cfg)
      associate (site => self%site(k), fields => self%cfg(k)%fields)
        if (site%set > 0) then
          do j = 1, size(fields)
            q = quantity(fields(j))
            vals = [vals, 0.0_rp]
            cnt = [cnt, 0.0_rp]
            m = size(vals)
            if (q <= 3) then
              do i = mesh%set_node_ptr(site%set), mesh%set_node_ptr(site%set + 1) - 1
                node = mesh%set_nodes(i)
                if (node > mesh%node_map%n_owned) cycle
                vals(m) = vals(m) + pf%u(3 * (node - 1) + q)
                cnt(m) = cnt(m) + 1.0_rp
              end do
            else
              do s = 1, mesh%n_sfaces
                if (mesh%sface_set(s) /= site%set) cycle
                f = mesh%sface_face(s)
                do side = 1, 2
                  c = mesh%face_cells(side, f)
                  if (c < 1 .or. c > mesh%cell_map%n_owned) cycle
                  vals(m) = vals(m) + cell_value(pf, q, c)
                  cnt(m) = cnt(m) + 1.0_rp
                end do
              end do
            end if
          end do
        else
          do i = 1, size(site%cell)
            do j = 1, size(fields)
              q = quantity(fields(j))
              vals = [vals, 0.0_rp]
              cnt = [cnt, 0.0_rp]
              c = site%cell(i)
              if (c == 0) cycle
              if (q <= 3) then
                call hex_shape(site%xi(:, i), n, dn)
                vals(size(vals)) = dot_product(n, pf%u(3 * (mesh%cell_nodes(:, c) - 1) + q))
              else
                vals(size(vals)) = cell_value(pf, q, c)
              end if
            end do
          end do
        end if
      end associate
    end do
  end subroutine probe_values

  !> Index of a quantity in probe_quantities (1-3 displacement, 4 p, 5-10 stress).
  integer(ip) function quantity(name)
    character(len=*), intent(in) :: name
    integer :: i
    quantity = 0
    do i = 1, size(probe_quantities)
      if (probe_quantities(i) == name) quantity = int(i, ip)
    end do
  end function quantity

  real(rp) function cell_value(pf, q, c)
    type(probe_fields_t), intent(in) :: pf
    integer(ip), intent(in) :: q, c
    if (q == 4) then
      cell_value = pf%p(c)
    else
      cell_value = pf%stress(q - 4, c)
    end if
  end function cell_value

  !> Rank 0: write the file with its header and, after a restart, the rows
  !> of the earlier run up to keep_through (through <path>.tmp, renamed over
  !> the file); leave it open for the rows to come.
  subroutine open_file(self, pf, status)
    type(probe_output_t), intent(inout) :: self
    type(probe_fields_t), intent(in) :: pf
    type(error_status_t), intent(inout) :: status
    character(len=:), allocatable :: head
    character(len=path_len) :: tmp
    integer :: ios, k, i, j
    head = 'step,time [s]'
    if (.not. self%transient) head = 'step,load factor [-]'
    do k = 1, size(self%cfg)
      associate (c => self%cfg(k))
        do i = 1, max(size(c%points, 2), 1)
          do j = 1, size(c%fields)
            if (size(c%points, 2) > 1) then
              head = head//','//trim(c%name)//'('//itoa(i)//'):'//trim(c%fields(j))
            else
              head = head//','//trim(c%name)//':'//trim(c%fields(j))
            end if
            head = head//' ['//trim(probe_unit(c%fields(j)))//']'
          end do
        end do
      end associate
    end do
    if (allocated(pf%names)) then
      do j = 1, size(pf%names)
        head = head//','//trim(pf%names(j))
      end do
    end if
    tmp = trim(self%path)//'.tmp'
    ! the output directory exists only when the run also writes fields
    k = index(self%path, '/', back=.true.)
    if (k > 1) call make_directory(self%path(1:k-1), status)
    if (.not. status%ok()) return
    open(newunit=self%unit, file=trim(tmp), status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call status%set('cannot create '//trim(tmp))
      return
    end if
    write(self%unit, '(a)') head
    call copy_rows_through(self%path, self%keep_through, self%unit)
    close(self%unit)
    call rename_path(tmp, self%path, status)
    if (.not. status%ok()) return
    open(newunit=self%unit, file=trim(self%path), status='old', position='append', action='write', iostat=ios)
    if (ios /= 0) call status%set('cannot append to '//trim(self%path))
    self%opened = ios == 0
  end subroutine open_file

  !> Copy to unit the data rows of the file at path whose step is at most
  !> last (nothing without a file or when last is -huge).
  subroutine copy_rows_through(path, last, unit)
    character(len=*), intent(in) :: path
    integer, intent(in) :: last, unit
    character(len=row_len) :: line
    integer :: u, ios, ios2, step, comma
    if (last == -huge(1)) return
    open(newunit=u, file=trim(path), status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      comma = index(line, ',')
      if (comma <= 1) cycle
      read(line(1:comma-1), *, iostat=ios2) step
      if (ios2 /= 0 .or. step > last) cycle
      write(unit, '(a)') trim(line)
    end do
    close(u)
  end subroutine copy_rows_through

  subroutine free(self)
    class(probe_output_t), intent(inout) :: self
    if (self%opened) close(self%unit)
    self%opened = .false.
    if (allocated(self%cfg)) deallocate(self%cfg)
    if (allocated(self%site)) deallocate(self%site)
  end subroutine free
end module probe_output
