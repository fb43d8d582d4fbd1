!> From the &mesh group to the distributed mesh: rank 0 generates or reads the
!> global mesh, splits the nodes of its faults into interface elements and
!> partitions it with METIS; then every rank takes its part.
module mesh_builder
  use kinds, only: ip
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use mesh, only: mesh_t
  use box_mesh, only: build_box_mesh
  use box_regions, only: assign_box_regions
  use gmsh_reader, only: read_gmsh
  use fault_config, only: fault_config_t
  use fault_split, only: split_faults
  use partition, only: partition_cells
  use dist_mesh, only: dist_mesh_t
  use mesh_config, only: mesh_config_t
  use strings, only: itoa
  implicit none
  private

  public :: build_mesh

contains

  !> Build dmesh from cfg and the faults of the deck (optional; for a box
  !> their geometry is cfg's box, for gmsh their names are physical surfaces
  !> of the file). Collective; status is the same on every rank.
  subroutine build_mesh(comm, cfg, log, dmesh, status, faults)
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_config_t), intent(in) :: cfg
    type(logger_t), intent(inout) :: log
    type(dist_mesh_t), intent(inout) :: dmesh
    type(error_status_t), intent(inout) :: status
    type(fault_config_t), intent(in), optional :: faults(:)
    type(mesh_t) :: gmesh
    integer(ip), allocatable :: part(:)
    integer(ip) :: nf, i, n_before, n_split

    nf = 0
    if (present(faults)) nf = size(faults, kind=ip)
    n_split = 0
    n_before = 0
    if (comm%is_root()) then
      select case (cfg%source)
      case ('box')
        call build_box_mesh(gmesh, cfg%n, cfg%lower, cfg%upper, cfg%grading, status, &
                            cfg%core_lower, cfg%core_upper, cfg%core_n, faults)
        if (status%ok() .and. allocated(cfg%regions)) call assign_box_regions(gmesh, cfg%regions, status)
      case ('gmsh')
        call read_gmsh(cfg%file, gmesh, status)
      end select
      n_before = gmesh%n_nodes
      if (status%ok() .and. nf > 0) call split_faults(gmesh, faults(:)%name, status, n_split)
      if (status%ok()) then
        allocate(part(gmesh%n_cells))
        call partition_cells(gmesh, int(comm%size, ip), part, status)
      end if
    end if
    call agree(comm, status)
    if (.not. status%ok()) return
    if (comm%is_root()) then
      call log%info('mesh: '//itoa(gmesh%n_nodes)//' nodes, '//itoa(gmesh%n_cells)//' hexahedra, '// &
                    itoa(gmesh%n_faces)//' faces, '//itoa(size(gmesh%region_names))//' region(s), '// &
                    itoa(size(gmesh%set_names))//' surface set(s)')
      call log%info('regions: '//region_counts(gmesh))
      if (nf > 0) then
        do i = 1, nf
          call log%info("fault '"//trim(faults(i)%name)//"': "//itoa(count(gmesh%iface_fault == i))// &
                        ' interface elements')
        end do
        call log%info('faults: '//itoa(gmesh%n_ifaces)//' interface elements, '//itoa(n_split)// &
                      ' nodes split ('//itoa(gmesh%n_nodes - n_before)//' nodes added)')
      end if
    end if
    call dmesh%build(comm, gmesh, part, status)
    call log%info('partition: '//itoa(comm%size)//' rank(s), owned cells per rank '// &
                  itoa(comm%min(dmesh%cell_map%n_owned))//' to '//itoa(comm%max(dmesh%cell_map%n_owned))// &
                  ', ghost cells per rank up to '//itoa(comm%max(dmesh%cell_map%n_ghost)))
  end subroutine build_mesh

  !> "'a' n_a cells, 'b' n_b cells, ..." in the order of the region ids.
  function region_counts(gmesh) result(s)
    type(mesh_t), intent(in) :: gmesh
    character(len=:), allocatable :: s
    integer(ip) :: r
    s = ''
    do r = 1, size(gmesh%region_names, kind=ip)
      if (r > 1) s = s//', '
      s = s//"'"//trim(gmesh%region_names(r))//"' "//itoa(count(gmesh%cell_region == r))//' cells'
    end do
  end function region_counts
end module mesh_builder
