!> Deck group &region (any number; &mesh source = 'box' only): a named
!> region of a generated box, carved out by a box of cell centres.
!>
!>   name       the region's name, as &material region and &source region
!>              name it (unique; not 'domain', which holds the cells of no
!>              &region)                                                 [required]
!>   lower(3), upper(3)  the box [m]: the cells whose centres lie in
!>              [lower, upper] (bounds included, to 1e-9 of the mesh's
!>              extent) belong to the region; a component left out is open
!>              on that side; lower < upper on every axis         [the whole space]
!>
!> Later groups win over earlier ones where their boxes overlap; the cells
!> of no group stay in region 'domain', which exists only when some cell is
!> left to it. A group whose box holds no cell centre, or all of whose
!> cells later groups take, is refused by the mesh (box_regions), naming
!> the group. A Gmsh mesh has its regions (physical volumes) already: a
!> &region with &mesh source = 'gmsh' is refused.
module region_config
  use kinds, only: rp, name_len, msg_len, path_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use strings, only: itoa, rtoa
  use param_group, only: param_group_t
  implicit none
  private

  public :: region_config_t, read_regions, default_region

  !> the region of the cells no &region takes
  character(len=*), parameter :: default_region = 'domain'

  type :: region_config_t
    character(len=name_len) :: name = ''
    real(rp) :: lower(3) = -huge(1.0_rp), upper(3) = huge(1.0_rp)   !< [m], +-huge: open
    !> "deck 'x.nml', group &region (line N)": where the mesh's messages point
    character(len=path_len + 48) :: origin = ''
  contains
    procedure :: describe => describe_region
  end type region_config_t

contains

  !> Read and check every &region group; source is &mesh source ('box' or
  !> 'gmsh': the latter refuses any &region).
  subroutine read_regions(d, log, source, regions, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    character(len=*), intent(in) :: source
    type(region_config_t), allocatable, intent(out) :: regions(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: name
    real(rp) :: lower(3), upper(3)
    integer :: k, j, i, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    character(len=1) :: ax
    namelist /region/ name, lower, upper

    allocate(regions(d%count('region')))
    do k = 1, size(regions)
      name = ''; lower = -huge(1.0_rp); upper = huge(1.0_rp)
      call d%block('region', k, b)
      read(b, nml=region, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('region', k, ios, msg, status)
        return
      end if
      if (source /= 'box') call d%fail(status, 'region', k, 'name', "&region carves a generated box (&mesh "// &
        "source = 'box'); a Gmsh mesh's regions are its physical volumes (got source = '"//trim(source)//"')")
      if (len_trim(name) == 0) then
        call d%fail(status, 'region', k, 'name', 'required')
      else if (trim(name) == default_region) then
        call d%fail(status, 'region', k, 'name', "'"//default_region//"' is the region of the cells that no "// &
                    '&region takes; give this one another name')
      end if
      do j = 1, k - 1
        if (regions(j)%name == name) call d%fail(status, 'region', k, 'name', "'"//trim(name)// &
          "' is already the name of &region number "//itoa(j)//' (one group per region)')
      end do
      do i = 1, 3
        write(ax, '(i1)') i
        if (.not. lower(i) < upper(i)) call d%fail(status, 'region', k, 'upper('//ax//')', &
          'must be greater than lower('//ax//') (got lower '//rtoa(lower(i))//', upper '//rtoa(upper(i))//')')
      end do
      if (.not. status%ok()) return
      regions(k)%name = name
      regions(k)%lower = lower
      regions(k)%upper = upper
      write(regions(k)%origin, '(a,i0,a)') "deck '"//trim(d%path)//"', group &region (line ", &
        d%first_line('region', k), ")"
    end do
  end subroutine read_regions

  !> The resolved &region group.
  subroutine describe_region(self, g)
    class(region_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('region', "a named region of a generated box, the cells whose centres lie in a box "// &
                "(box meshes only; later groups win where they overlap)")
    call g%add('name', self%name, '-', 'region name, as &material region and &source region name it', &
               "unique, not 'domain'")
    call g%add_bounds('lower', self%lower, '(open)', 'm', 'lower corner of the box of cell centres (a '// &
                      'component left out is open)')
    call g%add_bounds('upper', self%upper, '(open)', 'm', 'upper corner of the box of cell centres', '> lower')
  end subroutine describe_region
end module region_config
