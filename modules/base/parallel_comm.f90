!> The MPI wrapper: the only module of geoblock that calls MPI.
!>
!> A parallel_comm_t holds one communicator and offers the collective and
!> point-to-point operations that the rest of the code needs, with the
!> Fortran types of the project (kinds module). Handles for the C libraries
!> (hypre wants a C MPI_Comm, MUMPS and HDF5 a Fortran integer) come from
!> here and nowhere else.
module parallel_comm
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int
  use mpi_f08
  use kinds, only: rp, ip, gp
  implicit none
  private

  public :: parallel_comm_t, wall_time, self_f_handle

  type :: parallel_comm_t
    type(MPI_Comm) :: comm
    integer :: rank = 0
    integer :: size = 1
  contains
    procedure :: init_world
    procedure :: finalize
    procedure :: is_root
    procedure :: barrier
    procedure :: abort => comm_abort
    procedure :: f_handle
    procedure :: c_handle
    procedure, private :: sum_r, sum_i, sum_g
    generic :: sum => sum_r, sum_i, sum_g
    procedure, private :: sum_rv, sum_iv, sum_gv
    generic :: sum_all => sum_rv, sum_iv, sum_gv
    procedure, private :: max_r, max_i, max_g
    generic :: max => max_r, max_i, max_g
    procedure, private :: min_r, min_i
    generic :: min => min_r, min_i
    procedure :: any_true
    procedure, private :: bcast_i, bcast_iv, bcast_g, bcast_gv, bcast_r, bcast_rv, bcast_l, bcast_s, bcast_r2, bcast_i2
    generic :: bcast => bcast_i, bcast_iv, bcast_g, bcast_gv, bcast_r, bcast_rv, bcast_l, bcast_s, bcast_r2, bcast_i2
    procedure, private :: allgather_i, allgather_g
    generic :: allgather => allgather_i, allgather_g
    procedure :: alltoall_i
    procedure, private :: alltoallv_i, alltoallv_g, alltoallv_r
    generic :: alltoallv => alltoallv_i, alltoallv_g, alltoallv_r
    procedure, private :: send_i, send_g, send_r
    generic :: send => send_i, send_g, send_r
    procedure, private :: recv_i, recv_g, recv_r
    generic :: recv => recv_i, recv_g, recv_r
    procedure :: exchange_r
    procedure :: exscan_g
    procedure :: sync_error
  end type parallel_comm_t

  interface
    !> Open MPI's C conversion of a Fortran communicator (MPI_Comm is a pointer there).
    function ompi_comm_f2c(fcomm) bind(C, name='MPI_Comm_f2c') result(ccomm)
      import :: c_ptr, c_int
      integer(c_int), value :: fcomm
      type(c_ptr) :: ccomm
    end function ompi_comm_f2c
  end interface

contains

  !> Start MPI (if needed) and attach to MPI_COMM_WORLD.
  subroutine init_world(self)
    class(parallel_comm_t), intent(inout) :: self
    logical :: started
    call MPI_Initialized(started)
    if (.not. started) call MPI_Init()
    self%comm = MPI_COMM_WORLD
    call MPI_Comm_rank(self%comm, self%rank)
    call MPI_Comm_size(self%comm, self%size)
  end subroutine init_world

  !> Finish MPI; every rank must call it.
  subroutine finalize(self)
    class(parallel_comm_t), intent(inout) :: self
    logical :: done
    call MPI_Finalized(done)
    if (.not. done) call MPI_Finalize()
    self%rank = 0
  end subroutine finalize

  logical function is_root(self)
    class(parallel_comm_t), intent(in) :: self
    is_root = self%rank == 0
  end function is_root

  subroutine barrier(self)
    class(parallel_comm_t), intent(in) :: self
    call MPI_Barrier(self%comm)
  end subroutine barrier

  !> Stop every rank at once (for an error seen by one rank only).
  subroutine comm_abort(self, code)
    class(parallel_comm_t), intent(in) :: self
    integer, intent(in) :: code
    call MPI_Abort(self%comm, code)
  end subroutine comm_abort

  !> Fortran integer handle (for MUMPS and HDF5).
  integer function f_handle(self)
    class(parallel_comm_t), intent(in) :: self
    f_handle = self%comm%MPI_VAL
  end function f_handle

  !> Fortran handle of MPI_COMM_SELF (a library instance private to one rank,
  !> e.g. the host layout of mumps_solver).
  integer function self_f_handle()
    self_f_handle = MPI_COMM_SELF%MPI_VAL
  end function self_f_handle

  !> C MPI_Comm handle (for hypre); the one place where the conversion is made.
  function c_handle(self) result(h)
    class(parallel_comm_t), intent(in) :: self
    type(c_ptr) :: h
    h = ompi_comm_f2c(int(self%comm%MPI_VAL, c_int))
  end function c_handle

  ! ---- reductions ----------------------------------------------------------

  function sum_r(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(in) :: x
    real(rp) :: s
    call MPI_Allreduce(x, s, 1, MPI_DOUBLE_PRECISION, MPI_SUM, self%comm)
  end function sum_r

  subroutine sum_rv(self, x)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(inout) :: x(:)
    real(rp) :: y(size(x))
    call MPI_Allreduce(x, y, size(x), MPI_DOUBLE_PRECISION, MPI_SUM, self%comm)
    x = y
  end subroutine sum_rv

  function sum_i(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: x
    integer(ip) :: s
    call MPI_Allreduce(x, s, 1, MPI_INTEGER4, MPI_SUM, self%comm)
  end function sum_i

  subroutine sum_iv(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(inout) :: x(:)
    integer(ip) :: y(size(x))
    call MPI_Allreduce(x, y, size(x), MPI_INTEGER4, MPI_SUM, self%comm)
    x = y
  end subroutine sum_iv

  function sum_g(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: x
    integer(gp) :: s
    call MPI_Allreduce(x, s, 1, MPI_INTEGER8, MPI_SUM, self%comm)
  end function sum_g

  subroutine sum_gv(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(inout) :: x(:)
    integer(gp) :: y(size(x))
    call MPI_Allreduce(x, y, size(x), MPI_INTEGER8, MPI_SUM, self%comm)
    x = y
  end subroutine sum_gv

  function max_r(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(in) :: x
    real(rp) :: s
    call MPI_Allreduce(x, s, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%comm)
  end function max_r

  function max_i(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: x
    integer(ip) :: s
    call MPI_Allreduce(x, s, 1, MPI_INTEGER4, MPI_MAX, self%comm)
  end function max_i

  function max_g(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: x
    integer(gp) :: s
    call MPI_Allreduce(x, s, 1, MPI_INTEGER8, MPI_MAX, self%comm)
  end function max_g

  function min_r(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(in) :: x
    real(rp) :: s
    call MPI_Allreduce(x, s, 1, MPI_DOUBLE_PRECISION, MPI_MIN, self%comm)
  end function min_r

  function min_i(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: x
    integer(ip) :: s
    call MPI_Allreduce(x, s, 1, MPI_INTEGER4, MPI_MIN, self%comm)
  end function min_i

  !> True on every rank when x is true on at least one rank.
  logical function any_true(self, x)
    class(parallel_comm_t), intent(in) :: self
    logical, intent(in) :: x
    call MPI_Allreduce(x, any_true, 1, MPI_LOGICAL, MPI_LOR, self%comm)
  end function any_true

  !> Exclusive prefix sum over ranks (0 on rank 0).
  function exscan_g(self, x) result(s)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: x
    integer(gp) :: s
    integer(gp) :: all(0:self%size-1)
    call MPI_Allgather(x, 1, MPI_INTEGER8, all, 1, MPI_INTEGER8, self%comm)
    s = sum(all(0:self%rank-1))
  end function exscan_g

  ! ---- broadcasts from rank 0 ----------------------------------------------

  subroutine bcast_i(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(inout) :: x
    call MPI_Bcast(x, 1, MPI_INTEGER4, 0, self%comm)
  end subroutine bcast_i

  subroutine bcast_iv(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(inout) :: x(:)
    if (size(x) > 0) call MPI_Bcast(x, size(x), MPI_INTEGER4, 0, self%comm)
  end subroutine bcast_iv

  subroutine bcast_i2(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(inout), contiguous :: x(:,:)
    if (size(x) > 0) call MPI_Bcast(x, size(x), MPI_INTEGER4, 0, self%comm)
  end subroutine bcast_i2

  subroutine bcast_g(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(inout) :: x
    call MPI_Bcast(x, 1, MPI_INTEGER8, 0, self%comm)
  end subroutine bcast_g

  subroutine bcast_gv(self, x)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(inout) :: x(:)
    if (size(x) > 0) call MPI_Bcast(x, size(x), MPI_INTEGER8, 0, self%comm)
  end subroutine bcast_gv

  subroutine bcast_r(self, x)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(inout) :: x
    call MPI_Bcast(x, 1, MPI_DOUBLE_PRECISION, 0, self%comm)
  end subroutine bcast_r

  subroutine bcast_rv(self, x)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(inout) :: x(:)
    if (size(x) > 0) call MPI_Bcast(x, size(x), MPI_DOUBLE_PRECISION, 0, self%comm)
  end subroutine bcast_rv

  subroutine bcast_r2(self, x)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(inout), contiguous :: x(:,:)
    if (size(x) > 0) call MPI_Bcast(x, size(x), MPI_DOUBLE_PRECISION, 0, self%comm)
  end subroutine bcast_r2

  subroutine bcast_l(self, x)
    class(parallel_comm_t), intent(in) :: self
    logical, intent(inout) :: x
    call MPI_Bcast(x, 1, MPI_LOGICAL, 0, self%comm)
  end subroutine bcast_l

  subroutine bcast_s(self, x)
    class(parallel_comm_t), intent(in) :: self
    character(len=*), intent(inout) :: x
    call MPI_Bcast(x, len(x), MPI_CHARACTER, 0, self%comm)
  end subroutine bcast_s

  ! ---- gathers and all-to-all ----------------------------------------------

  !> Every rank's x, indexed by rank 0..size-1.
  function allgather_i(self, x) result(all)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: x
    integer(ip) :: all(0:self%size-1)
    call MPI_Allgather(x, 1, MPI_INTEGER4, all, 1, MPI_INTEGER4, self%comm)
  end function allgather_i

  function allgather_g(self, x) result(all)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: x
    integer(gp) :: all(0:self%size-1)
    call MPI_Allgather(x, 1, MPI_INTEGER8, all, 1, MPI_INTEGER8, self%comm)
  end function allgather_g

  !> send(p) is what this rank sends to p; recv(p) what it gets from p.
  subroutine alltoall_i(self, send, recv)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: send(0:)
    integer(ip), intent(out) :: recv(0:)
    call MPI_Alltoall(send, 1, MPI_INTEGER4, recv, 1, MPI_INTEGER4, self%comm)
  end subroutine alltoall_i

  !> Personalized all-to-all; counts per rank, buffers packed by rank order.
  subroutine alltoallv_i(self, sbuf, scount, rbuf, rcount)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: sbuf(:)
    integer(ip), intent(in) :: scount(0:), rcount(0:)
    integer(ip), intent(out) :: rbuf(:)
    integer :: sdispl(0:self%size-1), rdispl(0:self%size-1)
    call displacements(scount, sdispl)
    call displacements(rcount, rdispl)
    call MPI_Alltoallv(sbuf, scount, sdispl, MPI_INTEGER4, rbuf, rcount, rdispl, MPI_INTEGER4, self%comm)
  end subroutine alltoallv_i

  subroutine alltoallv_g(self, sbuf, scount, rbuf, rcount)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: sbuf(:)
    integer(ip), intent(in) :: scount(0:), rcount(0:)
    integer(gp), intent(out) :: rbuf(:)
    integer :: sdispl(0:self%size-1), rdispl(0:self%size-1)
    call displacements(scount, sdispl)
    call displacements(rcount, rdispl)
    call MPI_Alltoallv(sbuf, scount, sdispl, MPI_INTEGER8, rbuf, rcount, rdispl, MPI_INTEGER8, self%comm)
  end subroutine alltoallv_g

  subroutine alltoallv_r(self, sbuf, scount, rbuf, rcount)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(in) :: sbuf(:)
    integer(ip), intent(in) :: scount(0:), rcount(0:)
    real(rp), intent(out) :: rbuf(:)
    integer :: sdispl(0:self%size-1), rdispl(0:self%size-1)
    call displacements(scount, sdispl)
    call displacements(rcount, rdispl)
    call MPI_Alltoallv(sbuf, scount, sdispl, MPI_DOUBLE_PRECISION, rbuf, rcount, rdispl, &
                       MPI_DOUBLE_PRECISION, self%comm)
  end subroutine alltoallv_r

  subroutine displacements(count, displ)
    integer(ip), intent(in) :: count(0:)
    integer, intent(out) :: displ(0:)
    integer :: p
    displ(0) = 0
    do p = 1, ubound(count, 1)
      displ(p) = displ(p-1) + count(p-1)
    end do
  end subroutine displacements

  ! ---- point to point (blocking, for the rank-0 distribution of the mesh) ---

  subroutine send_i(self, x, dest, tag)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: x(:)
    integer, intent(in) :: dest, tag
    call MPI_Send(x, size(x), MPI_INTEGER4, dest, tag, self%comm)
  end subroutine send_i

  subroutine send_g(self, x, dest, tag)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(in) :: x(:)
    integer, intent(in) :: dest, tag
    call MPI_Send(x, size(x), MPI_INTEGER8, dest, tag, self%comm)
  end subroutine send_g

  subroutine send_r(self, x, dest, tag)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(in) :: x(:)
    integer, intent(in) :: dest, tag
    call MPI_Send(x, size(x), MPI_DOUBLE_PRECISION, dest, tag, self%comm)
  end subroutine send_r

  subroutine recv_i(self, x, source, tag)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(out) :: x(:)
    integer, intent(in) :: source, tag
    call MPI_Recv(x, size(x), MPI_INTEGER4, source, tag, self%comm, MPI_STATUS_IGNORE)
  end subroutine recv_i

  subroutine recv_g(self, x, source, tag)
    class(parallel_comm_t), intent(in) :: self
    integer(gp), intent(out) :: x(:)
    integer, intent(in) :: source, tag
    call MPI_Recv(x, size(x), MPI_INTEGER8, source, tag, self%comm, MPI_STATUS_IGNORE)
  end subroutine recv_g

  subroutine recv_r(self, x, source, tag)
    class(parallel_comm_t), intent(in) :: self
    real(rp), intent(out) :: x(:)
    integer, intent(in) :: source, tag
    call MPI_Recv(x, size(x), MPI_DOUBLE_PRECISION, source, tag, self%comm, MPI_STATUS_IGNORE)
  end subroutine recv_r

  !> Sparse neighbour exchange of reals (the halo exchange kernel).
  !> For each neighbour k: send sbuf(sptr(k):sptr(k+1)-1) to ranks(k) and
  !> receive rbuf(rptr(k):rptr(k+1)-1) from ranks(k).
  subroutine exchange_r(self, ranks, sptr, sbuf, rptr, rbuf)
    class(parallel_comm_t), intent(in) :: self
    integer(ip), intent(in) :: ranks(:), sptr(:), rptr(:)
    real(rp), intent(in), contiguous, target :: sbuf(:)
    real(rp), intent(inout), contiguous, target :: rbuf(:)
    type(MPI_Request) :: req(2*size(ranks))
    integer :: k, n, nreq
    integer, parameter :: tag = 7301
    nreq = 0
    do k = 1, size(ranks)
      n = rptr(k+1) - rptr(k)
      if (n > 0) then
        nreq = nreq + 1
        call MPI_Irecv(rbuf(rptr(k):rptr(k+1)-1), n, MPI_DOUBLE_PRECISION, ranks(k), tag, &
                       self%comm, req(nreq))
      end if
    end do
    do k = 1, size(ranks)
      n = sptr(k+1) - sptr(k)
      if (n > 0) then
        nreq = nreq + 1
        call MPI_Isend(sbuf(sptr(k):sptr(k+1)-1), n, MPI_DOUBLE_PRECISION, ranks(k), tag, &
                       self%comm, req(nreq))
      end if
    end do
    call MPI_Waitall(nreq, req(1:nreq), MPI_STATUSES_IGNORE)
  end subroutine exchange_r

  !> Make an error seen by some ranks known to all: on return every rank has
  !> the code and message of the lowest rank whose code was nonzero (or 0).
  subroutine sync_error(self, code, msg)
    class(parallel_comm_t), intent(in) :: self
    integer, intent(inout) :: code
    character(len=*), intent(inout) :: msg
    integer :: first, mine
    mine = huge(1)
    if (code /= 0) mine = self%rank
    call MPI_Allreduce(mine, first, 1, MPI_INTEGER, MPI_MIN, self%comm)
    if (first == huge(1)) return
    call MPI_Bcast(code, 1, MPI_INTEGER, first, self%comm)
    call MPI_Bcast(msg, len(msg), MPI_CHARACTER, first, self%comm)
  end subroutine sync_error

  !> Wall-clock time in seconds.
  function wall_time() result(t)
    real(rp) :: t
    t = MPI_Wtime()
  end function wall_time

end module parallel_comm
