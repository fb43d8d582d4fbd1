!> Distributed index map: owned entries (a contiguous range of global ids per
!> rank, in rank order) and ghost entries (copies of entries owned elsewhere).
!>
!> Local numbering: owned entries are 1..n_owned (global id first+i-1), ghosts
!> are n_owned+1..n_owned+n_ghost in the order given at init. The map knows the
!> communication plan of the halo exchange in both directions:
!>   import     : owner values -> ghost copies   (before a matrix-vector product)
!>   export_add : ghost contributions -> owner, added (after assembly)
!>   export_min : ghost values -> owner, which keeps the smallest (labels)
module index_map
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  implicit none
  private

  public :: insertion_sort, index_map_t, sort_gids, rank_of

  type :: index_map_t
    type(parallel_comm_t) :: comm
    integer(ip) :: n_owned = 0
    integer(ip) :: n_ghost = 0
    integer(gp) :: first = 1                    !< global id of local entry 1
    integer(gp) :: n_global = 0
    integer(gp), allocatable :: offsets(:)      !< (0:size) first global id of each rank, 1-based
    integer(gp), allocatable :: ghost_gid(:)    !< global id of each ghost
    integer(ip), allocatable :: ghost_owner(:)  !< owning rank of each ghost
    integer(gp), allocatable :: sorted_gid(:)   !< ghost ids sorted (for lookups)
    integer(ip), allocatable :: sorted_pos(:)   !< ghost position of sorted_gid(k)
    ! halo plan
    integer(ip), allocatable :: nbr(:)          !< neighbour ranks
    integer(ip), allocatable :: send_ptr(:), send_idx(:)   !< owned local ids sent to nbr(k)
    integer(ip), allocatable :: recv_ptr(:), recv_idx(:)   !< ghost local ids received from nbr(k)
  contains
    procedure :: init
    procedure :: n_local
    procedure :: global_id
    procedure :: local_id
    procedure :: owner_of
    procedure :: import
    procedure :: export_add
    procedure :: export_min
    procedure :: free
  end type index_map_t

contains

  !> Build the map from the number of owned entries and the ghost global ids.
  !> Collective. Ghost ids must not be owned by this rank and must exist.
  subroutine init(self, comm, n_owned, ghost_gid)
    class(index_map_t), intent(inout) :: self
    type(parallel_comm_t), intent(in) :: comm
    integer(ip), intent(in) :: n_owned
    integer(gp), intent(in) :: ghost_gid(:)
    integer(gp), allocatable :: counts(:), req(:), got(:)
    integer(ip), allocatable :: scount(:), rcount(:), order(:)
    integer(ip) :: p, k, i, np, nn
    logical, allocatable :: is_nbr(:)

    call self%free()
    self%comm = comm
    np = comm%size
    self%n_owned = n_owned
    self%n_ghost = size(ghost_gid, kind=ip)
    allocate(counts(0:np-1))
    counts = comm%allgather(int(n_owned, gp))
    allocate(self%offsets(0:np))
    self%offsets(0) = 1
    do p = 1, np
      self%offsets(p) = self%offsets(p-1) + counts(p-1)
    end do
    self%first = self%offsets(comm%rank)
    self%n_global = self%offsets(np) - 1
    self%ghost_gid = ghost_gid
    allocate(self%ghost_owner(self%n_ghost))
    do i = 1, self%n_ghost
      self%ghost_owner(i) = self%owner_of(ghost_gid(i))
    end do
    ! sorted lookup of ghosts
    allocate(self%sorted_pos(self%n_ghost))
    self%sorted_gid = ghost_gid
    call sort_gids(self%sorted_gid, self%sorted_pos)

    ! requests to owners, grouped by owner rank (stable order)
    allocate(scount(0:np-1), rcount(0:np-1))
    scount = 0
    do i = 1, self%n_ghost
      scount(self%ghost_owner(i)) = scount(self%ghost_owner(i)) + 1
    end do
    call comm%alltoall_i(scount, rcount)
    allocate(order(self%n_ghost), req(self%n_ghost))
    call group_by_rank(self%ghost_owner, np, order)
    req = ghost_gid(order)
    allocate(got(sum(rcount)))
    call comm%alltoallv(req, scount, got, rcount)

    ! neighbours: ranks we receive ghosts from, or send owned entries to
    allocate(is_nbr(0:np-1))
    is_nbr = scount > 0 .or. rcount > 0
    is_nbr(comm%rank) = .false.
    nn = count(is_nbr)
    allocate(self%nbr(nn), self%send_ptr(nn+1), self%recv_ptr(nn+1))
    k = 0
    do p = 0, np-1
      if (is_nbr(p)) then
        k = k + 1
        self%nbr(k) = p
      end if
    end do
    self%send_ptr(1) = 1
    self%recv_ptr(1) = 1
    do k = 1, nn
      self%send_ptr(k+1) = self%send_ptr(k) + rcount(self%nbr(k))
      self%recv_ptr(k+1) = self%recv_ptr(k) + scount(self%nbr(k))
    end do
    ! send list: the owned entries other ranks asked for (got is in rank order)
    allocate(self%send_idx(size(got)))
    do i = 1, size(got)
      if (got(i) < self%first .or. got(i) >= self%first + n_owned) then
        error stop 'index_map: a rank asked for an entry this rank does not own'
      end if
      self%send_idx(i) = int(got(i) - self%first, ip) + 1
    end do
    ! receive list: ghosts grouped by owner in the same order as the requests
    allocate(self%recv_idx(self%n_ghost))
    self%recv_idx = n_owned + order
  end subroutine init

  !> Stable grouping of positions 1..n by rank (counting sort).
  subroutine group_by_rank(rank_of, np, order)
    integer(ip), intent(in) :: rank_of(:)
    integer(ip), intent(in) :: np
    integer(ip), intent(out) :: order(:)
    integer(ip) :: start(0:np), i, p
    start = 0
    do i = 1, size(rank_of)
      start(rank_of(i)+1) = start(rank_of(i)+1) + 1
    end do
    do p = 1, np
      start(p) = start(p) + start(p-1)
    end do
    do i = 1, size(rank_of)
      p = rank_of(i)
      start(p) = start(p) + 1
      order(start(p)) = i
    end do
  end subroutine group_by_rank

  integer(ip) function n_local(self)
    class(index_map_t), intent(in) :: self
    n_local = self%n_owned + self%n_ghost
  end function n_local

  !> Global id of local entry i (owned or ghost).
  integer(gp) function global_id(self, i)
    class(index_map_t), intent(in) :: self
    integer(ip), intent(in) :: i
    if (i <= self%n_owned) then
      global_id = self%first + i - 1
    else
      global_id = self%ghost_gid(i - self%n_owned)
    end if
  end function global_id

  !> Local id of global id g, or 0 when this rank has no copy of it.
  integer(ip) function local_id(self, g)
    class(index_map_t), intent(in) :: self
    integer(gp), intent(in) :: g
    integer(ip) :: lo, hi, mid
    if (g >= self%first .and. g < self%first + self%n_owned) then
      local_id = int(g - self%first, ip) + 1
      return
    end if
    local_id = 0
    lo = 1
    hi = self%n_ghost
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (self%sorted_gid(mid) == g) then
        local_id = self%n_owned + self%sorted_pos(mid)
        return
      else if (self%sorted_gid(mid) < g) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function local_id

  !> Rank that owns global id g.
  integer(ip) function owner_of(self, g)
    class(index_map_t), intent(in) :: self
    integer(gp), intent(in) :: g
    owner_of = rank_of(self%offsets, g)
  end function owner_of

  !> Rank owning global id g under contiguous ownership: offsets(0:np) holds
  !> the first global id of each rank (offsets(np) = n_global + 1).
  pure integer(ip) function rank_of(offsets, g)
    integer(gp), intent(in) :: offsets(0:)
    integer(gp), intent(in) :: g
    integer(ip) :: lo, hi, mid
    lo = 0
    hi = int(ubound(offsets, 1), ip) - 1
    do while (lo < hi)
      mid = (lo + hi + 1) / 2
      if (offsets(mid) <= g) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    rank_of = lo
  end function rank_of

  !> Fill the ghost part of x (size n_local) with the owners' values.
  subroutine import(self, x)
    class(index_map_t), intent(in) :: self
    real(rp), intent(inout) :: x(:)
    real(rp), allocatable :: sbuf(:), rbuf(:)
    if (self%comm%size == 1) return
    allocate(sbuf(size(self%send_idx)), rbuf(size(self%recv_idx)))
    sbuf = x(self%send_idx)
    call self%comm%exchange_r(self%nbr, self%send_ptr, sbuf, self%recv_ptr, rbuf)
    x(self%recv_idx) = rbuf
  end subroutine import

  !> Add the ghost part of x to the owners' entries, then zero the ghosts.
  subroutine export_add(self, x)
    class(index_map_t), intent(in) :: self
    real(rp), intent(inout) :: x(:)
    real(rp), allocatable :: sbuf(:), rbuf(:)
    integer :: i
    if (self%comm%size > 1) then
      allocate(sbuf(size(self%recv_idx)), rbuf(size(self%send_idx)))
      sbuf = x(self%recv_idx)
      call self%comm%exchange_r(self%nbr, self%recv_ptr, sbuf, self%send_ptr, rbuf)
      do i = 1, size(self%send_idx)
        x(self%send_idx(i)) = x(self%send_idx(i)) + rbuf(i)
      end do
    end if
    x(self%n_owned+1:) = 0.0_rp
  end subroutine export_add

  !> Owners take the minimum of their entry and every ghost copy of it;
  !> ghosts keep their values.
  subroutine export_min(self, x)
    class(index_map_t), intent(in) :: self
    real(rp), intent(inout) :: x(:)
    real(rp), allocatable :: sbuf(:), rbuf(:)
    integer :: i
    if (self%comm%size == 1) return
    allocate(sbuf(size(self%recv_idx)), rbuf(size(self%send_idx)))
    sbuf = x(self%recv_idx)
    call self%comm%exchange_r(self%nbr, self%recv_ptr, sbuf, self%send_ptr, rbuf)
    do i = 1, size(self%send_idx)
      x(self%send_idx(i)) = min(x(self%send_idx(i)), rbuf(i))
    end do
  end subroutine export_min

  subroutine free(self)
    class(index_map_t), intent(inout) :: self
    if (allocated(self%offsets)) deallocate(self%offsets)
    if (allocated(self%ghost_gid)) deallocate(self%ghost_gid)
    if (allocated(self%ghost_owner)) deallocate(self%ghost_owner)
    if (allocated(self%sorted_gid)) deallocate(self%sorted_gid)
    if (allocated(self%sorted_pos)) deallocate(self%sorted_pos)
    if (allocated(self%nbr)) deallocate(self%nbr)
    if (allocated(self%send_ptr)) deallocate(self%send_ptr)
    if (allocated(self%send_idx)) deallocate(self%send_idx)
    if (allocated(self%recv_ptr)) deallocate(self%recv_ptr)
    if (allocated(self%recv_idx)) deallocate(self%recv_idx)
    self%n_owned = 0
    self%n_ghost = 0
  end subroutine free

  !> Sort a short integer array ascending in place, by insertion (no work
  !> arrays; for rows of tens of entries).
  pure subroutine insertion_sort(a)
    integer(ip), intent(inout) :: a(:)
    integer(ip) :: i, j, t
    do i = 2, size(a, kind=ip)
      t = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= t) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = t
    end do
  end subroutine insertion_sort

  !> Sort global ids ascending (heap sort); pos returns the original positions.
  subroutine sort_gids(a, pos)
    integer(gp), intent(inout) :: a(:)
    integer(ip), intent(out) :: pos(:)
    integer(ip) :: n, i, last
    integer(gp) :: t
    integer(ip) :: tp
    n = size(a, kind=ip)
    do i = 1, n
      pos(i) = i
    end do
    do i = n / 2, 1, -1
      call sift(i, n)
    end do
    do last = n, 2, -1
      t = a(1); a(1) = a(last); a(last) = t
      tp = pos(1); pos(1) = pos(last); pos(last) = tp
      call sift(1_ip, last - 1)
    end do
  contains
    subroutine sift(start, bottom)
      integer(ip), intent(in) :: start, bottom
      integer(ip) :: root, child
      root = start
      do while (2 * root <= bottom)
        child = 2 * root
        if (child < bottom) then
          if (a(child + 1) > a(child)) child = child + 1
        end if
        if (a(root) < a(child)) then
          t = a(root); a(root) = a(child); a(child) = t
          tp = pos(root); pos(root) = pos(child); pos(child) = tp
          root = child
        else
          return
        end if
      end do
    end subroutine sift
  end subroutine sort_gids
end module index_map
