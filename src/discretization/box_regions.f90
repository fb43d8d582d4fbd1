!> Named regions of a generated box from the &region groups: a cell
!> belongs to the last group whose box [lower, upper] holds its centre (the
!> mean of its 8 nodes; a centre on a bound, to 1e-9 of the mesh's extent
!> along that axis, counts), else to 'domain'. The mesh's regions are then
!> 'domain' (only if some cell is left to it) followed by the groups in deck
!> order, so a region with no cell never appears. A group whose box holds no
!> cell centre, or whose cells all go to later groups, is an error naming
!> it: a &material or &source for it could only be a mistake.
module box_regions
  use kinds, only: rp, ip, name_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  use region_config, only: region_config_t, default_region
  use strings, only: itoa
  use face_box, only: box_text
  implicit none
  private

  public :: assign_box_regions

contains

  !> Set mesh%cell_region and mesh%region_names from regions (a box mesh
  !> with the single region 'domain' on entry). status names the first
  !> group that gets no cell.
  subroutine assign_box_regions(mesh, regions, status)
    type(mesh_t), intent(inout) :: mesh
    type(region_config_t), intent(in) :: regions(:)
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: group(:), inside(:), kept(:)
    integer(ip) :: c, k, nr, n_new
    real(rp) :: x(3), tol(3)
    character(len=name_len), allocatable :: names(:)

    nr = size(regions, kind=ip)
    if (nr == 0) return
    tol = 1.0e-9_rp * (maxval(mesh%coords, dim=2) - minval(mesh%coords, dim=2))
    allocate(group(mesh%n_cells), inside(nr), kept(0:nr))
    group = 0
    inside = 0
    do c = 1, mesh%n_cells
      x = sum(mesh%coords(:, mesh%cell_nodes(:, c)), dim=2) / 8.0_rp
      do k = 1, nr
        if (any(x < regions(k)%lower - tol) .or. any(x > regions(k)%upper + tol)) cycle
        group(c) = k
        inside(k) = inside(k) + 1
      end do
    end do
    kept = 0
    do c = 1, mesh%n_cells
      kept(group(c)) = kept(group(c)) + 1
    end do
    do k = 1, nr
      if (inside(k) == 0) then
        call status%set("box mesh: &region '"//trim(regions(k)%name)//"' ("//trim(regions(k)%origin)// &
          '): no cell centre lies in its box '//box_text(regions(k)%lower, regions(k)%upper)//'; widen the box or refine the mesh')
        return
      else if (kept(k) == 0) then
        call status%set("box mesh: &region '"//trim(regions(k)%name)//"' ("//trim(regions(k)%origin)//'): all '// &
          itoa(inside(k))//' cells of its box '//box_text(regions(k)%lower, regions(k)%upper)// &
          ' belong to later &region groups (later groups win); it would have no cell')
        return
      end if
    end do
    ! region ids: 'domain' first when it keeps cells, then the groups
    allocate(names(nr + 1))
    n_new = 0
    if (kept(0) > 0) then
      n_new = 1
      names(1) = default_region
    end if
    do k = 1, nr
      names(n_new + k) = regions(k)%name
    end do
    n_new = n_new + nr
    do c = 1, mesh%n_cells
      mesh%cell_region(c) = group(c) + merge(1_ip, 0_ip, kept(0) > 0)
    end do
    if (allocated(mesh%region_names)) deallocate(mesh%region_names)
    allocate(mesh%region_names(n_new))
    mesh%region_names = names(1:n_new)
  end subroutine assign_box_regions
end module box_regions
