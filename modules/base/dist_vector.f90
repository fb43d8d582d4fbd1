!> Distributed vectors: owned values plus ghost copies, laid out as an
!> index_map numbers them, and the reductions over owned entries.
module dist_vector
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t
  implicit none
  private

  public :: dist_vector_t, pdot, pnorm2, pmax_abs, write_vector_market

  type :: dist_vector_t
    type(index_map_t), pointer :: map => null()
    real(rp), allocatable :: x(:)          !< (n_owned + n_ghost)
  contains
    procedure :: init
    procedure :: owned
    procedure :: import
    procedure :: export_add
    procedure :: norm2 => vec_norm2
    procedure :: free
  end type dist_vector_t

contains

  subroutine init(self, map)
    class(dist_vector_t), intent(inout) :: self
    type(index_map_t), intent(in), target :: map
    self%map => map
    if (allocated(self%x)) deallocate(self%x)
    allocate(self%x(map%n_local()))
    self%x = 0.0_rp
  end subroutine init

  !> Copy of the owned part.
  function owned(self) result(v)
    class(dist_vector_t), intent(in) :: self
    real(rp), allocatable :: v(:)
    v = self%x(1:self%map%n_owned)
  end function owned

  subroutine import(self)
    class(dist_vector_t), intent(inout) :: self
    call self%map%import(self%x)
  end subroutine import

  subroutine export_add(self)
    class(dist_vector_t), intent(inout) :: self
    call self%map%export_add(self%x)
  end subroutine export_add

  real(rp) function vec_norm2(self)
    class(dist_vector_t), intent(in) :: self
    vec_norm2 = pnorm2(self%map%comm, self%x(1:self%map%n_owned))
  end function vec_norm2

  subroutine free(self)
    class(dist_vector_t), intent(inout) :: self
    if (allocated(self%x)) deallocate(self%x)
    self%map => null()
  end subroutine free

  !> Global dot product of owned parts.
  real(rp) function pdot(comm, x, y)
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in) :: x(:), y(:)
    pdot = comm%sum(dot_product(x, y))
  end function pdot

  !> Global Euclidean norm of owned parts.
  real(rp) function pnorm2(comm, x)
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in) :: x(:)
    pnorm2 = sqrt(comm%sum(dot_product(x, x)))
  end function pnorm2

  !> Global maximum absolute entry.
  real(rp) function pmax_abs(comm, x)
    type(parallel_comm_t), intent(in) :: comm
    real(rp), intent(in) :: x(:)
    real(rp) :: m
    m = 0.0_rp
    if (size(x) > 0) m = maxval(abs(x))
    pmax_abs = comm%max(m)
  end function pmax_abs

  !> Write the owned parts of a distributed vector (global length n_global) as
  !> one MatrixMarket array file; ranks append in turn. integer: the values
  !> are whole numbers, written as an integer array; comment: a line of the
  !> header. Collective.
  subroutine write_vector_market(comm, path, v, n_global, ios, integer, comment)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    real(rp), intent(in) :: v(:)
    integer(gp), intent(in) :: n_global
    integer, intent(out) :: ios
    logical, intent(in), optional :: integer
    character(len=*), intent(in), optional :: comment
    integer :: u, p, i
    logical :: whole
    whole = .false.
    if (present(integer)) whole = integer
    ios = 0
    do p = 0, comm%size - 1
      if (comm%rank == p) then
        if (p == 0) then
          open(newunit=u, file=path, status='replace', action='write', iostat=ios)
          if (ios == 0) write(u, '(a)') '%%MatrixMarket matrix array '//trim(merge('integer', 'real   ', whole))// &
                                        ' general'
          if (ios == 0) write(u, '(a)') '% written by geoblock'
          if (ios == 0 .and. present(comment)) write(u, '(a)') '% '//comment
          if (ios == 0) write(u, '(i0,1x,i0)') n_global, 1
        else
          open(newunit=u, file=path, status='old', position='append', action='write', iostat=ios)
        end if
        if (ios == 0) then
          do i = 1, size(v)
            if (whole) then
              write(u, '(i0)') nint(v(i))
            else
              write(u, '(es24.16e3)') v(i)
            end if
          end do
          close(u)
        end if
      end if
      call comm%barrier()
    end do
    ios = comm%max(int(abs(ios), ip))
  end subroutine write_vector_market
end module dist_vector
