!> The resolved deck of a run, gathered from its parts: &run, &time and
!> &output (run_config), &mesh (mesh_config) and the physics' own groups
!> (simulation_t%parameter_groups), without what the physics does not use
!> (simulation_t%unused_inputs: the deck reader refuses those, so a written
!> deck that held them could not be run again).
module run_parameters
  use kinds, only: name_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use run_config, only: run_config_t
  use mesh_config, only: mesh_config_t
  use param_group, only: param_group_t
  use simulation, only: simulation_t, foreign_len
  use probe_config, only: probe_config_t, describe_probe
  use parameters_file, only: write_parameters, print_parameters
  implicit none
  private

  public :: resolved_groups, record_parameters, show_parameters, parameters_path

contains

  !> <out_dir>/<prefix>_parameters.nml
  function parameters_path(run) result(p)
    type(run_config_t), intent(in) :: run
    character(len=:), allocatable :: p
    p = trim(run%out_dir)//'/'//trim(run%prefix)//'_parameters.nml'
  end function parameters_path

  !> Every group the run uses, resolved, in deck order: &run, &time,
  !> &output, &mesh, &region, then the physics' groups; unused groups and variables
  !> left out.
  subroutine resolved_groups(run, mcfg, sim, probes, groups)
    type(run_config_t), intent(in) :: run
    type(mesh_config_t), intent(in) :: mcfg
    class(simulation_t), intent(in) :: sim
    type(probe_config_t), intent(in) :: probes(:)
    type(param_group_t), allocatable, intent(out) :: groups(:)
    type(param_group_t) :: head(4)
    type(param_group_t), allocatable :: own(:), all(:), probe_groups(:), region_groups(:)
    character(len=foreign_len), allocatable :: unused(:)
    logical, allocatable :: keep(:)
    integer :: g, j, p
    call run%describe(head(1:3))
    call mcfg%describe(head(4))
    call mcfg%describe_regions(region_groups)
    call sim%parameter_groups(own)
    allocate(probe_groups(size(probes)))
    do g = 1, size(probes)
      call describe_probe(probes(g), probe_groups(g))
    end do
    all = [head, region_groups, own, probe_groups]
    call sim%unused_inputs(unused)
    allocate(keep(size(all)))
    keep = .true.
    do g = 1, size(all)
      do j = 1, size(unused)
        p = index(unused(j), '%')
        if (p == 0) then
          if (trim(unused(j)) == trim(all(g)%name)) keep(g) = .false.
        else if (unused(j)(1:p-1) == trim(all(g)%name)) then
          call all(g)%drop(trim(unused(j)(p+1:)))
        end if
      end do
    end do
    groups = pack(all, keep)
  end subroutine resolved_groups

  !> Header lines of the written deck.
  function header_lines(run, deck_path) result(h)
    type(run_config_t), intent(in) :: run
    character(len=*), intent(in) :: deck_path
    character(len=240) :: h(4)
    h(1) = 'geoblock: the resolved deck of '//trim(deck_path)//' (physics '//trim(run%physics)//')'
    h(2) = 'Every variable the run used, defaults included, with its unit and meaning;'
    h(3) = 'a commented variable was not set. Running this file repeats the run (change'
    h(4) = '&output dir or prefix to keep the first outputs).'
  end function header_lines

  !> Echo the resolved deck to the log and write <out_dir>/<prefix>_parameters.nml
  !> (rank 0). Collective; status is the same on every rank.
  subroutine record_parameters(comm, log, deck_path, run, mcfg, sim, probes, status)
    type(parallel_comm_t), intent(in) :: comm
    type(logger_t), intent(inout) :: log
    character(len=*), intent(in) :: deck_path
    type(run_config_t), intent(in) :: run
    type(mesh_config_t), intent(in) :: mcfg
    class(simulation_t), intent(in) :: sim
    type(probe_config_t), intent(in) :: probes(:)
    type(error_status_t), intent(inout) :: status
    type(param_group_t), allocatable :: groups(:)
    call resolved_groups(run, mcfg, sim, probes, groups)
    call write_parameters(comm, log, parameters_path(run), groups, header_lines(run, deck_path), status)
  end subroutine record_parameters

  !> Print the resolved deck on standard output (geoblock --check).
  subroutine show_parameters(comm, deck_path, run, mcfg, sim, probes)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: deck_path
    type(run_config_t), intent(in) :: run
    type(mesh_config_t), intent(in) :: mcfg
    class(simulation_t), intent(in) :: sim
    type(probe_config_t), intent(in) :: probes(:)
    type(param_group_t), allocatable :: groups(:)
    call resolved_groups(run, mcfg, sim, probes, groups)
    call print_parameters(comm, groups, header_lines(run, deck_path))
  end subroutine show_parameters
end module run_parameters
