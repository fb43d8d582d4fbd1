!> Vector-valued functions of position, for loads and prescribed values that
!> vary in space (manufactured solutions, gravity profiles). The deck's
!> constant values use constant_vector_t.
module vector_function
  use kinds, only: rp
  implicit none
  private

  public :: vector_function_t, constant_vector_t

  type, abstract :: vector_function_t
  contains
    procedure(eval_iface), deferred :: eval
  end type vector_function_t

  abstract interface
    !> Value at position x [m].
    function eval_iface(self, x) result(v)
      import :: vector_function_t, rp
      class(vector_function_t), intent(in) :: self
      real(rp), intent(in) :: x(3)
      real(rp) :: v(3)
    end function eval_iface
  end interface

  type, extends(vector_function_t) :: constant_vector_t
    real(rp) :: value(3) = 0.0_rp
  contains
    procedure :: eval => constant_eval
  end type constant_vector_t

contains

  function constant_eval(self, x) result(v)
    class(constant_vector_t), intent(in) :: self
    real(rp), intent(in) :: x(3)
    real(rp) :: v(3)
    v = self%value
  end function constant_eval
end module vector_function
