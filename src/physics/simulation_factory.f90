!> The physics a deck can name (&run physics) and the types that implement
!> them: the one place that knows every concrete simulation. A coupled
!> physics is built as a list of components (coupled_simulation.f90):
!>   'contact'       = [mechanics, interface contact]
!>   'fracture_flow' = [mechanics, interface contact, fracture flow]
!>   'poromechanics_faults' = [mechanics, matrix flow, interface contact, fracture flow]
module simulation_factory
  use error_status, only: error_status_t
  use simulation, only: simulation_t, foreign_len
  use elastic_simulation, only: elastic_simulation_t
  use biot_simulation, only: biot_simulation_t
  use physics_component, only: physics_component_t
  use mechanics_component, only: mechanics_component_t
  use interface_contact, only: interface_contact_t
  use fracture_flow_component, only: fracture_flow_component_t
  use matrix_flow_component, only: matrix_flow_component_t
  use coupled_simulation, only: coupled_simulation_t
  implicit none
  private

  public :: make_simulation, physics_names

  !> The valid names, for messages.
  character(len=*), parameter :: physics_names = "'elasticity', 'biot', 'contact', 'fracture_flow', "// &
                                             "'poromechanics_faults'"

  !> The components a composition can have, in the order of their rows.
  character(len=*), parameter :: component_kinds(4) = [character(len=13) :: 'mechanics', 'matrix_flow', &
                                                        'contact', 'fracture_flow']

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
      call compose(sim, 'contact', [character(len=13) :: 'mechanics', 'contact'])
    case ('fracture_flow')
      call compose(sim, 'fracture_flow', [character(len=13) :: 'mechanics', 'contact', 'fracture_flow'])
    case ('poromechanics_faults')
      call compose(sim, 'poromechanics_faults', [character(len=13) :: 'mechanics', 'matrix_flow', 'contact', &
                                                 'fracture_flow'])
    case default
      call status%set("unknown physics '"//trim(name)//"' (valid: "//physics_names//")")
    end select
  end subroutine make_simulation

  !> sim as the composition named physics of the components kinds (in
  !> order); the deck groups of the other components are refused.
  subroutine compose(sim, physics, kinds)
    class(simulation_t), allocatable, intent(inout) :: sim
    character(len=*), intent(in) :: physics, kinds(:)
    type(coupled_simulation_t), allocatable :: cs
    class(physics_component_t), allocatable :: c
    character(len=foreign_len), allocatable :: groups(:)
    integer :: k
    allocate(cs)
    cs%physics = physics
    cs%controls = 'contact'
    allocate(cs%refused(0))
    do k = 1, size(component_kinds)
      call make_component(component_kinds(k), c)
      if (any(kinds == component_kinds(k))) then
        call cs%add(c)
      else
        call c%groups(groups)
        cs%refused = [cs%refused, groups]
        deallocate(c)
      end if
    end do
    call move_alloc(cs, sim)
  end subroutine compose

  !> A new component of kind.
  subroutine make_component(kind, c)
    character(len=*), intent(in) :: kind
    class(physics_component_t), allocatable, intent(out) :: c
    select case (kind)
    case ('mechanics')
      allocate(mechanics_component_t :: c)
    case ('contact')
      allocate(interface_contact_t :: c)
    case ('fracture_flow')
      allocate(fracture_flow_component_t :: c)
    case ('matrix_flow')
      allocate(matrix_flow_component_t :: c)
    end select
    c%kind = kind
  end subroutine make_component
end module simulation_factory
