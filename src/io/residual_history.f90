!> The residual history of every linear solve of a run, one CSV file
!> (<dir>/<prefix>_residuals.csv, written by rank 0), with the columns
!>   step, time, newton, iteration, relative_residual
!> (newton: the Newton / active-set iteration of the step; iteration: the
!> Krylov iteration, 0 the initial residual). postproc/plot_convergence.py
!> draws it.
module residual_history
  use kinds, only: rp
  use parallel_comm, only: parallel_comm_t
  implicit none
  private

  public :: residual_history_t

  type :: residual_history_t
    integer :: unit = 0
    logical :: active = .false.
    character(len=:), allocatable :: path
  contains
    procedure :: open => open_history
    procedure :: write => write_history
    procedure :: close => close_history
  end type residual_history_t

contains

  !> Create the file on rank 0 (a file that cannot be created leaves the
  !> history off; the run goes on).
  subroutine open_history(self, comm, path)
    class(residual_history_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    integer :: ios
    self%path = path
    self%active = .false.
    if (.not. comm%is_root()) return
    open(newunit=self%unit, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) return
    write(self%unit, '(a)') 'step,time,newton,iteration,relative_residual'
    self%active = .true.
  end subroutine open_history

  !> The history of one solve (relative residuals of iterations 0, 1, ...).
  subroutine write_history(self, step, t, newton, history)
    class(residual_history_t), intent(inout) :: self
    integer, intent(in) :: step, newton
    real(rp), intent(in) :: t
    real(rp), intent(in) :: history(0:)
    integer :: k, ios
    if (.not. self%active) return
    do k = 0, ubound(history, 1)
      write(self%unit, '(i0,a,es16.8,a,i0,a,i0,a,es16.8)', iostat=ios) step, ',', t, ',', newton, ',', k, ',', &
        history(k)
    end do
    flush(self%unit)
  end subroutine write_history

  subroutine close_history(self)
    class(residual_history_t), intent(inout) :: self
    if (self%active) close(self%unit)
    self%active = .false.
  end subroutine close_history
end module residual_history
