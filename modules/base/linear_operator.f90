!> Abstract linear operator y = A x on distributed vectors (owned parts only).
!> Matrices, block systems and matrix-free operators extend it; the Krylov
!> solvers see nothing else.
module linear_operator
  use kinds, only: rp, ip
  implicit none
  private

  public :: linear_operator_t

  type, abstract :: linear_operator_t
  contains
    procedure(apply_iface), deferred :: apply
    procedure(size_iface), deferred :: n_owned
  end type linear_operator_t

  abstract interface
    !> y = A x; x and y hold the owned entries of this rank.
    subroutine apply_iface(self, x, y)
      import :: linear_operator_t, rp
      class(linear_operator_t), intent(inout) :: self
      real(rp), intent(in) :: x(:)
      real(rp), intent(out) :: y(:)
    end subroutine apply_iface
    !> Number of owned rows on this rank.
    integer(ip) function size_iface(self)
      import :: linear_operator_t, ip
      class(linear_operator_t), intent(in) :: self
    end function size_iface
  end interface
end module linear_operator
