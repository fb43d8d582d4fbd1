!> The physics a deck can name (&run physics) and the types that implement
!> them: the one place that knows every concrete simulation.
module simulation_factory
  use error_status, only: error_status_t
  use simulation, only: simulation_t
  use elastic_simulation, only: elastic_simulation_t
  use biot_simulation, only: biot_simulation_t
  use contact_simulation, only: contact_simulation_t
  implicit none
  private

  public :: make_simulation, physics_names

  !> The valid names, for messages.
  character(len=*), parameter :: physics_names = "'elasticity', 'biot', 'contact', 'fracture_flow'"

contains

  !> Allocate sim as the simulation of physics name; status lists the valid
  !> names when name is unknown.
  subroutine make_simulation(name, sim, status)
    character(len=*), intent(in) :: name
    class(simulation_t), allocatable, intent(inout) :: sim
    type(error_status_t), intent(inout) :: status
    if (allocated(sim)) then
      call sim%free()
      deallocate(sim)
    end if
    select case (name)
    case ('elasticity')
      allocate(elastic_simulation_t :: sim)
    case ('biot')
      allocate(biot_simulation_t :: sim)
    case ('contact')
      allocate(contact_simulation_t :: sim)
    case ('fracture_flow')
      allocate(contact_simulation_t :: sim)
      select type (sim)
      type is (contact_simulation_t)
        sim%flow = .true.
      end select
    case default
      call status%set("unknown physics '"//trim(name)//"' (valid: "//physics_names//")")
    end select
  end subroutine make_simulation
end module simulation_factory
