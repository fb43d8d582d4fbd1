!> From the &mesh group to the distributed mesh: rank 0 generates or reads the
!> global mesh and partitions it with METIS; then every rank takes its part.
module mesh_builder
  use kinds, only: ip
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use logger, only: logger_t
  use mesh, only: mesh_t
  use box_mesh, only: build_box_mesh
  use gmsh_reader, only: read_gmsh
  use partition, only: partition_cells
  use dist_mesh, only: dist_mesh_t
  use mesh_config, only: mesh_config_t
  use strings, only: itoa
  implicit none
  private

  public :: build_mesh

contains

  !> Build dmesh from cfg. Collective; status is the same on every rank.
  subroutine build_mesh(comm, cfg, log, dmesh, status)
    type(parallel_comm_t), intent(in) :: comm
    type(mesh_config_t), intent(in) :: cfg
    type(logger_t), intent(inout) :: log
    type(dist_mesh_t), intent(inout) :: dmesh
    type(error_status_t), intent(inout) :: status
    type(mesh_t) :: gmesh
    integer(ip), allocatable :: part(:)

    if (comm%is_root()) then
      select case (cfg%source)
      case ('box')
        call build_box_mesh(gmesh, cfg%n, cfg%lower, cfg%upper, cfg%grading, status)
      case ('gmsh')
        call read_gmsh(cfg%file, gmesh, status)
      end select
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
    end if
    call dmesh%build(comm, gmesh, part, status)
    call log%info('partition: '//itoa(comm%size)//' rank(s), owned cells per rank '// &
                  itoa(comm%min(dmesh%cell_map%n_owned))//' to '//itoa(comm%max(dmesh%cell_map%n_owned))// &
                  ', ghost cells per rank up to '//itoa(comm%max(dmesh%cell_map%n_ghost)))
  end subroutine build_mesh
end module mesh_builder
