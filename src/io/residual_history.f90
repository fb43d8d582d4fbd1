!> The residual history of every linear solve of a run, one CSV file
!> (<dir>/<prefix>_residuals.csv, written by rank 0), with the columns
!>   step, time, newton, iteration, relative_residual
!> (newton: the Newton / active-set iteration of the step; iteration: the
!> Krylov iteration, 0 the initial residual). postproc/plot_convergence.py
!> draws it. A restarted run continues the file of the run it resumes: the
!> rows of the steps up to the checkpoint's stay, later ones (written before
!> the earlier run stopped) are dropped, and the new rows follow.
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
  !> history off; the run goes on). keep_through: a restarted run's last
  !> completed step; the rows of the existing file up to it are kept.
  subroutine open_history(self, comm, path, keep_through)
    class(residual_history_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    integer, intent(in), optional :: keep_through
    character(len=256), allocatable :: kept(:)
    integer :: ios, k
    self%path = path
    self%active = .false.
    if (.not. comm%is_root()) return
    if (present(keep_through)) call rows_through(path, keep_through, kept)
    open(newunit=self%unit, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) return
    write(self%unit, '(a)') 'step,time,newton,iteration,relative_residual'
    if (allocated(kept)) then
      do k = 1, size(kept)
        write(self%unit, '(a)') trim(kept(k))
      end do
    end if
    self%active = .true.
  end subroutine open_history

  !> The data rows of the history file at path whose step is at most last
  !> (none when the file cannot be read).
  subroutine rows_through(path, last, kept)
    character(len=*), intent(in) :: path
    integer, intent(in) :: last
    character(len=256), allocatable, intent(out) :: kept(:)
    character(len=256), allocatable :: grown(:)
    character(len=256) :: line
    integer :: u, ios, ios2, step, n, comma
    allocate(kept(64))
    n = 0
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) then
      kept = kept(1:0)
      return
    end if
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      comma = index(line, ',')
      if (comma <= 1) cycle
      read(line(1:comma-1), *, iostat=ios2) step
      if (ios2 /= 0 .or. step > last) cycle                ! the header, or a later step
      if (n == size(kept)) then
        allocate(grown(2 * n))
        grown(1:n) = kept
        call move_alloc(grown, kept)
      end if
      n = n + 1
      kept(n) = line
    end do
    close(u)
    kept = kept(1:n)
  end subroutine rows_through

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
