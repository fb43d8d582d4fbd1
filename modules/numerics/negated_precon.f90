!> M^-1 = -N^-1 for a preconditioner N of -A: lets a preconditioner that
!> wants a positive definite matrix (AMG, Jacobi) serve a negative definite
!> block, such as the Schur complement -H - C2 diag(K)^-1 C1 of contact.
module negated_precon
  use kinds, only: rp, name_len
  use precon, only: precon_t
  implicit none
  private

  public :: negated_precon_t

  type, extends(precon_t) :: negated_precon_t
    class(precon_t), allocatable :: inner      !< preconditioner of -A
  contains
    procedure :: init => negated_init
    procedure :: apply => negated_apply
    procedure :: name => negated_name
    procedure :: free => negated_free
  end type negated_precon_t

contains

  !> Take inner (moved in, already set up on -A).
  subroutine negated_init(self, inner)
    class(negated_precon_t), intent(inout) :: self
    class(precon_t), allocatable, intent(inout) :: inner
    call self%free()
    call move_alloc(inner, self%inner)
    self%setup_time = self%inner%setup_time
  end subroutine negated_init

  subroutine negated_apply(self, r, z)
    class(negated_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    call self%inner%apply(r, z)
    z = -z
  end subroutine negated_apply

  function negated_name(self) result(s)
    class(negated_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'negated '//trim(self%inner%name())
  end function negated_name

  subroutine negated_free(self)
    class(negated_precon_t), intent(inout) :: self
    if (allocated(self%inner)) then
      call self%inner%free()
      deallocate(self%inner)
    end if
    self%setup_time = 0.0_rp
  end subroutine negated_free
end module negated_precon
