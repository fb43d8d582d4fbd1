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
  use kinds, only: rp, gp
  use linear_operator, only: linear_operator_t
  use precon, only: precon_t
  use csr_matrix, only: csr_matrix_t
  implicit none
  private

  public :: linear_system_t

  integer, parameter :: max_parts = 8

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
    !> The preconditioner's components built by this set-up (a reused one
    !> is not listed), with their seconds: the timing summary's set-up lines.
    integer :: n_parts = 0
    character(len=48) :: part_name(max_parts) = ''
    real(rp) :: part_time(max_parts) = 0.0_rp
    integer(gp) :: part_rise(max_parts) = 0       !< rise of the peak resident memory in the part [bytes]
  contains
    procedure :: reset
    procedure :: add_part
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
    self%n_parts = 0
  end subroutine reset

  !> A component of the set-up, its seconds and the rise of the peak
  !> resident memory in it [bytes] (ignored beyond max_parts).
  subroutine add_part(self, name, seconds, rise)
    class(linear_system_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in) :: seconds
    integer(gp), intent(in), optional :: rise
    if (self%n_parts == max_parts) return
    self%n_parts = self%n_parts + 1
    self%part_name(self%n_parts) = name
    self%part_time(self%n_parts) = seconds
    self%part_rise(self%n_parts) = 0
    if (present(rise)) self%part_rise(self%n_parts) = rise
  end subroutine add_part
end module linear_system
