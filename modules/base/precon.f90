!> Abstract preconditioner: z = M^-1 r on owned entries.
!>
!> Every sub-solver (Jacobi, BoomerAMG, MUMPS, aFSAI) and every block
!> preconditioner extends it. Set-up is specific to each type (it needs a
!> matrix, a block system, parameters); application and release are common.
module precon
  use kinds, only: rp, ip, gp, name_len
  implicit none
  private

  public :: precon_t, identity_precon_t

  type, abstract :: precon_t
    real(rp) :: setup_time = 0.0_rp        !< seconds spent in the last set-up
    integer(gp) :: setup_rise = 0          !< rise of the peak resident memory in the last set-up [bytes]
  contains
    procedure(apply_iface), deferred :: apply
    procedure(name_iface), deferred :: name
    procedure :: free => precon_free
  end type precon_t

  abstract interface
    !> z = M^-1 r (owned entries).
    subroutine apply_iface(self, r, z)
      import :: precon_t, rp
      class(precon_t), intent(inout) :: self
      real(rp), intent(in) :: r(:)
      real(rp), intent(out) :: z(:)
    end subroutine apply_iface
    !> Short name, as in the deck.
    function name_iface(self) result(s)
      import :: precon_t, name_len
      class(precon_t), intent(in) :: self
      character(len=name_len) :: s
    end function name_iface
  end interface

  !> M = I.
  type, extends(precon_t) :: identity_precon_t
  contains
    procedure :: apply => identity_apply
    procedure :: name => identity_name
  end type identity_precon_t

contains

  subroutine precon_free(self)
    class(precon_t), intent(inout) :: self
    self%setup_time = 0.0_rp
    self%setup_rise = 0
  end subroutine precon_free

  subroutine identity_apply(self, r, z)
    class(identity_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    z = r
  end subroutine identity_apply

  function identity_name(self) result(s)
    class(identity_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'none'
  end function identity_name
end module precon
