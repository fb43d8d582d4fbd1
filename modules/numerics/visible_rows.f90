!> The rows of a distributed square matrix that one rank can see while it
!> grows sparse approximate inverses (afsai, block_fsai): its owned rows and
!> the rows fetched from other ranks into a row store.
!>
!> Visible ids number them: owned row i is i, stored row r is n_rows + r.
!> Visible ids of stored rows move when the store grows, so they only live
!> between two fetches; after every fetch the tables (key and diagonal entry
!> of every visible row, visible id of every column) are rebuilt. A column
!> whose row this rank cannot see has visible id 0.
module visible_rows
  use kinds, only: rp, ip, gp
  use error_status, only: error_status_t
  use index_map, only: sort_gids
  use global_csr, only: global_csr_t, row_store_t, fetch_rows, search_gid
  implicit none
  private

  public :: visible_rows_t, check_square

  !> The visible rows of matrix a on this rank.
  type :: visible_rows_t
    !> the matrix (owned rows; keys are its partition-independent order)
    type(global_csr_t), pointer :: a => null()
    !> the fetched rows
    type(row_store_t) :: store
    !> key and diagonal entry by visible id
    integer(gp), allocatable :: key(:)
    real(rp), allocatable :: diag(:)
    !> visible id of the column of every entry of a and of the store
    integer(ip), allocatable :: vcol_a(:), vcol_s(:)
  contains
    procedure :: start
    procedure :: expand
    procedure :: count => visible_count
    procedure :: id => visible_id
    procedure :: gid => visible_gid
    procedure :: row => visible_row
    procedure :: owns
  end type visible_rows_t

contains

  !> Status error (alike on every rank) unless a is square (same row and
  !> column split) and has one key per owned row. Collective.
  subroutine check_square(a, who, status)
    type(global_csr_t), intent(in) :: a
    character(len=*), intent(in) :: who
    type(error_status_t), intent(inout) :: status
    logical :: bad
    if (.not. allocated(a%row_offsets) .or. .not. allocated(a%col_offsets)) then
      call status%set(who//': the matrix has no row or column split')
      return
    end if
    if (size(a%row_offsets) /= size(a%col_offsets)) then
      call status%set(who//': the matrix is not square')
    else if (any(a%row_offsets /= a%col_offsets)) then
      call status%set(who//': the matrix is not square (rows and columns split differently)')
    end if
    if (.not. status%ok()) return
    bad = .not. allocated(a%key)
    if (.not. bad) bad = size(a%key) /= a%n_rows
    if (a%comm%any_true(bad)) call status%set(who//': the matrix needs one ordering key per owned row')
  end subroutine check_square

  !> See the rows of a one step outside this rank (its ghost columns) and
  !> the rows extra (any, with repeats; owned ones are skipped). Collective.
  subroutine start(self, a, extra)
    class(visible_rows_t), intent(inout) :: self
    type(global_csr_t), intent(in), target :: a
    integer(gp), intent(in) :: extra(:)
    integer(gp), allocatable :: req(:)
    integer(ip) :: k, m, nz
    self%a => a
    nz = a%nnz()
    allocate(req(nz + size(extra)))
    m = 0
    do k = 1, nz
      if (self%owns(a%gcol(k))) cycle
      m = m + 1
      req(m) = a%gcol(k)
    end do
    do k = 1, size(extra)
      if (self%owns(extra(k))) cycle
      m = m + 1
      req(m) = extra(k)
    end do
    call fetch_rows(a, req(1:m), self%store)
    call tables(self)
  end subroutine start

  !> Make the neighbours of the visible rows gids visible too: fetch the
  !> columns of the stored rows among gids that are neither owned nor
  !> stored (the owned rows' neighbours are visible since start). Every row
  !> in gids must be visible. Collective (one fetch on every rank).
  subroutine expand(self, gids)
    class(visible_rows_t), intent(inout) :: self
    integer(gp), intent(in) :: gids(:)
    integer(gp), allocatable :: u(:), req(:)
    integer(ip), allocatable :: pos(:)
    integer(ip) :: k, nu, r, m, q
    allocate(u(size(gids)), pos(size(gids)))
    u(:) = gids
    call sort_gids(u, pos)
    nu = 0
    m = 0
    do k = 1, size(u, kind=ip)
      if (nu > 0) then
        if (u(k) == u(nu)) cycle
      end if
      if (self%owns(u(k))) cycle
      nu = nu + 1
      u(nu) = u(k)
      r = self%store%find(u(k))
      if (r == 0) error stop 'visible_rows%expand: a row to expand is not visible'
      m = m + self%store%ptr(r+1) - self%store%ptr(r)
    end do
    allocate(req(m))
    m = 0
    do k = 1, nu
      r = self%store%find(u(k))
      do q = self%store%ptr(r), self%store%ptr(r+1) - 1
        if (self%owns(self%store%gcol(q))) cycle
        if (self%store%find(self%store%gcol(q)) > 0) cycle
        m = m + 1
        req(m) = self%store%gcol(q)
      end do
    end do
    call fetch_rows(self%a, req(1:m), self%store)
    call tables(self)
  end subroutine expand

  !> Number of visible rows.
  pure integer(ip) function visible_count(self)
    class(visible_rows_t), intent(in) :: self
    visible_count = self%a%n_rows + self%store%n
  end function visible_count

  !> Whether global row g is owned by this rank.
  pure logical function owns(self, g)
    class(visible_rows_t), intent(in) :: self
    integer(gp), intent(in) :: g
    owns = g >= self%a%row_offsets(self%a%comm%rank) .and. g < self%a%row_offsets(self%a%comm%rank + 1)
  end function owns

  !> Visible id of global row g, 0 when this rank cannot see that row.
  pure integer(ip) function visible_id(self, g)
    class(visible_rows_t), intent(in) :: self
    integer(gp), intent(in) :: g
    integer(gp) :: first
    first = self%a%row_offsets(self%a%comm%rank)
    if (g >= first .and. g < self%a%row_offsets(self%a%comm%rank + 1)) then
      visible_id = int(g - first, ip) + 1
    else
      visible_id = 0
      if (self%store%n > 0) visible_id = search_gid(self%store%gid(1:self%store%n), g)
      if (visible_id > 0) visible_id = visible_id + self%a%n_rows
    end if
  end function visible_id

  !> Global id of visible row t.
  pure integer(gp) function visible_gid(self, t)
    class(visible_rows_t), intent(in) :: self
    integer(ip), intent(in) :: t
    if (t <= self%a%n_rows) then
      visible_gid = self%a%row_offsets(self%a%comm%rank) + t - 1
    else
      visible_gid = self%store%gid(t - self%a%n_rows)
    end if
  end function visible_gid

  !> Visible column ids and values of visible row t (pointers into the
  !> tables and a, or into the store).
  subroutine visible_row(self, t, cols, vals)
    class(visible_rows_t), intent(in), target :: self
    integer(ip), intent(in) :: t
    integer(ip), pointer, contiguous, intent(out) :: cols(:)
    real(rp), pointer, contiguous, intent(out) :: vals(:)
    integer(ip) :: r
    if (t <= self%a%n_rows) then
      cols => self%vcol_a(self%a%row_ptr(t):self%a%row_ptr(t+1)-1)
      vals => self%a%val(self%a%row_ptr(t):self%a%row_ptr(t+1)-1)
    else
      r = t - self%a%n_rows
      cols => self%vcol_s(self%store%ptr(r):self%store%ptr(r+1)-1)
      vals => self%store%val(self%store%ptr(r):self%store%ptr(r+1)-1)
    end if
  end subroutine visible_row

  !> Rebuild the key and diagonal of every visible row and the visible id
  !> of every column (after every fetch).
  subroutine tables(self)
    type(visible_rows_t), intent(inout) :: self
    integer(ip) :: n, r, k, nz
    integer(gp) :: first, last
    associate(a => self%a, store => self%store)
      n = a%n_rows
      first = a%row_offsets(a%comm%rank)
      last = a%row_offsets(a%comm%rank + 1) - 1
      if (allocated(self%key)) deallocate(self%key, self%diag, self%vcol_a, self%vcol_s)
      nz = a%nnz()
      allocate(self%key(n + store%n), self%diag(n + store%n), self%vcol_a(nz), &
               self%vcol_s(store%ptr(store%n + 1) - 1))
      do k = 1, nz
        if (a%gcol(k) >= first .and. a%gcol(k) <= last) then
          self%vcol_a(k) = int(a%gcol(k) - first, ip) + 1
        else
          self%vcol_a(k) = self%id(a%gcol(k))
        end if
      end do
      do k = 1, size(self%vcol_s)
        self%vcol_s(k) = self%id(store%gcol(k))
      end do
      self%key(1:n) = a%key(1:n)
      do r = 1, n
        self%diag(r) = 0.0_rp
        do k = a%row_ptr(r), a%row_ptr(r+1) - 1
          if (self%vcol_a(k) == r) self%diag(r) = a%val(k)
        end do
      end do
      do r = 1, store%n
        self%key(n + r) = store%key(r)
        self%diag(n + r) = 0.0_rp
        do k = store%ptr(r), store%ptr(r+1) - 1
          if (self%vcol_s(k) == n + r) self%diag(n + r) = store%val(k)
        end do
      end do
    end associate
  end subroutine tables
end module visible_rows
