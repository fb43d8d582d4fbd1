!> One linear system of a Newton iteration as a physics hands it to the
!> solve path: views (pointers) of the physics' own operator, right-hand
!> side, unknown, preconditioner and scaling, so that one solve path serves
!> every physics without copying its data.
!>
!> The unknown x holds the initial guess on entry to the solve (the previous
!> state for a linear problem solved for its state, zero for a Newton
!> update) and the solution on exit. The preconditioner is only used by
!> Krylov methods; a direct solver factorizes the operator itself when
!> `changed` says it differs from the one it factorized last.
module linear_system
  use kinds, only: rp
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  use csr_matrix, only: csr_matrix_t
  implicit none
  private

  public :: linear_system_t

  type :: linear_system_t
    class(linear_operator_t), pointer :: a => null()   !< the operator (a csr_matrix_t or a block_matrix_t)
    real(rp), pointer :: b(:) => null()                !< right-hand side, owned entries
    real(rp), pointer :: x(:) => null()                !< unknown: initial guess in, solution out
    class(precon_t), pointer :: m => null()            !< preconditioner of a (Krylov methods)
    real(rp), pointer :: d(:) => null()                !< symmetric scaling D (solve D A D y = D b); null: none
    logical :: symmetric = .false.                     !< a is symmetric (a direct solver may use LDL^T)
    logical :: changed = .true.                        !< a changed since the last solve (refactorize)
    real(rp) :: setup_time = 0.0_rp                    !< seconds the physics spent setting up m and d
    !> the fields of the operator's blocks in block order, comma separated
    !> ('u'; 'u,q,p'; 't,u'; 't,u,p'): named in the matrix export
    character(len=16) :: fields = ''
    !> The mechanics block and its right-hand side, for the benchmarks'
    !> elastic reference solve (null where the physics has none), and a
    !> BoomerAMG of it that the reference may reuse (null: it makes its own).
    type(csr_matrix_t), pointer :: k_ref => null()
    real(rp), pointer :: b_ref(:) => null()
    class(precon_t), pointer :: m_ref => null()
  contains
    procedure :: reset
  end type linear_system_t

contains

  !> Drop every view (before a physics fills the record anew).
  subroutine reset(self)
    class(linear_system_t), intent(inout) :: self
    nullify(self%a, self%b, self%x, self%m, self%d, self%k_ref, self%b_ref, self%m_ref)
    self%symmetric = .false.
    self%changed = .true.
    self%setup_time = 0.0_rp
    self%fields = ''
  end subroutine reset
end module linear_system
