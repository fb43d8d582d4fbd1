!> Fortran-friendly owner of one hypre IJ/ParCSR copy of a square
!> csr_matrix_t and of two IJ vectors (b: right-hand side, x: solution).
!>
!> hypre numbers rows and columns from 0; geoblock from 1. The owned rows of
!> this rank are the contiguous global ids A%row_map%first..first+n_rows-1, so
!> the hypre range is [first-1, first+n_rows-2]. The 0-based global ids of the
!> rows are kept for set_rhs() and get_x(); those of the column entries are
!> made a block of rows at a time while hypre's copy is built, and only a
!> fingerprint of them is kept to check that update_values() gets the same
!> pattern (they were 4 bytes a non-zero beside hypre's own 12: 0.4 GB a
!> rank for HI24L's S* at the seed's size).
!>
!> The matrix comes as a csr_matrix_t or row by row from an ij_rows_t, a
!> source that makes each owned row's global column ids and values when
!> asked (a sum of matrices merged a row at a time, so that the sum itself
!> is never stored beside hypre's copy).
!>
!> A hypre_ij_t holds C handles: never copy one by assignment (the copy would
!> share, and might free twice, the handles); call free() when done.
module hypre_ij
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_char, c_null_char
  use kinds, only: rp, ip, gp, hypre_int, hypre_bigint, hypre_real, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use index_map, only: index_map_t
  use hypre_c, only: HYPRE_PARCSR, HYPRE_ClearAllErrors, HYPRE_GetError, HYPRE_DescribeError, &
    HYPRE_IJMatrixCreate, HYPRE_IJMatrixDestroy, HYPRE_IJMatrixSetObjectType, &
    HYPRE_IJMatrixSetDiagOffdSizes, HYPRE_IJMatrixInitialize, HYPRE_IJMatrixSetValues, &
    HYPRE_IJMatrixAssemble, HYPRE_IJMatrixGetObject, &
    HYPRE_IJVectorCreate, HYPRE_IJVectorDestroy, HYPRE_IJVectorSetObjectType, &
    HYPRE_IJVectorInitialize, HYPRE_IJVectorSetValues, HYPRE_IJVectorAssemble, &
    HYPRE_IJVectorGetValues, HYPRE_IJVectorGetObject, &
    HYPRE_ParVectorSetConstantValues, HYPRE_ParCSRMatrixMatvec
  implicit none
  private

  public :: hypre_ij_t, ij_rows_t, csr_rows_t, hypre_error_text, hypre_check

  interface
    !> ij_overwrite.c: new values of rows(1:nrows) (ncols entries each,
    !> 0-based global columns) into the assembled matrix par_a where its
    !> assembly put the same entries; 0 when all fit the stored pattern.
    function gb_ij_overwrite(par_a, nrows, ncols, rows, cols, values) bind(C, name='gb_ij_overwrite') &
        result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint, hypre_real
      type(c_ptr), value :: par_a
      integer(hypre_int), value :: nrows
      integer(hypre_int), intent(in) :: ncols(*)
      integer(hypre_bigint), intent(in) :: rows(*), cols(*)
      real(hypre_real), intent(in) :: values(*)
      integer(hypre_int) :: ierr
    end function gb_ij_overwrite
  end interface

  !> A square matrix given row by row: row_map holds its owned rows (its
  !> columns are split among ranks alike), row(i) makes owned row i.
  type, abstract :: ij_rows_t
    type(index_map_t), pointer :: row_map => null()
  contains
    procedure(max_row_iface), deferred :: max_row
    procedure(row_iface), deferred :: row
  end type ij_rows_t

  abstract interface
    !> An upper bound of the entries of an owned row.
    integer(ip) function max_row_iface(self)
      import :: ij_rows_t, ip
      class(ij_rows_t), intent(in) :: self
    end function max_row_iface
    !> Owned row i: n entries, global column ids gcol(1:n) (1-based, each
    !> once) and values val(1:n); gcol and val hold max_row() entries.
    subroutine row_iface(self, i, gcol, val, n)
      import :: ij_rows_t, ip, gp, rp
      class(ij_rows_t), intent(in) :: self
      integer(ip), intent(in) :: i
      integer(gp), intent(inout) :: gcol(:)
      real(rp), intent(inout) :: val(:)
      integer(ip), intent(out) :: n
    end subroutine row_iface
  end interface

  !> A csr_matrix_t as an ij_rows_t (a pointed to; sum_rows extends it).
  type, extends(ij_rows_t) :: csr_rows_t
    type(csr_matrix_t), pointer :: a => null()
  contains
    procedure :: max_row => csr_max_row
    procedure :: row => csr_row
  end type csr_rows_t

  !> hypre copy of one square distributed matrix, with work vectors b and x.
  type :: hypre_ij_t
    type(parallel_comm_t) :: comm
    type(c_ptr) :: ij_a = c_null_ptr            !< HYPRE_IJMatrix (owned here)
    type(c_ptr) :: par_a = c_null_ptr           !< its HYPRE_ParCSRMatrix (owned by ij_a)
    type(c_ptr) :: ij_b = c_null_ptr            !< HYPRE_IJVector b (owned here)
    type(c_ptr) :: par_b = c_null_ptr           !< its HYPRE_ParVector
    type(c_ptr) :: ij_x = c_null_ptr            !< HYPRE_IJVector x (owned here)
    type(c_ptr) :: par_x = c_null_ptr           !< its HYPRE_ParVector
    integer(ip) :: n_rows = 0                   !< owned rows
    integer(ip) :: nnz = 0                      !< owned entries
    integer(hypre_bigint) :: ilower = 0         !< first owned row, 0-based
    integer(hypre_bigint) :: iupper = -1        !< last owned row, 0-based
    integer(hypre_bigint), allocatable :: rows(:)   !< (n_rows) 0-based global row ids
    integer(hypre_int), allocatable :: ncols(:)     !< (n_rows) entries per row
    integer(gp) :: pattern_key = 0              !< fingerprint of the global column ids (pattern_of)
    integer :: overwrites = 0                   !< rebuild_rows that wrote into the matrix in place
    !> its values are floats in place (boomeramg_precon's single-precision
    !> cycle owns them): no product with hypre's, until rebuild_rows
    logical :: narrowed = .false.
    !> entries given to hypre at a time, at least (whole rows); kept by free()
    integer(ip) :: block_entries = 2**18
  contains
    procedure :: init
    procedure :: init_rows
    procedure :: is_ready
    procedure :: update_values
    procedure :: rebuild_rows
    procedure :: set_rhs
    procedure :: zero_x
    procedure :: get_x
    procedure :: matvec
    procedure :: new_vector
    procedure :: free
  end type hypre_ij_t

contains

  !> Build the IJ/ParCSR copy of the square matrix a (rows and columns owned
  !> alike) and the vectors b and x (zero). Collective over a's communicator.
  !> status reports, on every rank alike: a matrix without a pattern, a
  !> non-square matrix or different row and column ownership, global ids
  !> beyond HYPRE_BigInt, or a hypre failure.
  subroutine init(self, a, status)
    class(hypre_ij_t), intent(inout) :: self
    type(csr_matrix_t), intent(in), target :: a
    type(error_status_t), intent(inout) :: status
    logical :: bad
    character(len=msg_len) :: msg

    call self%free()
    if (.not. associated(a%row_map) .or. .not. associated(a%col_map) .or. &
        .not. allocated(a%row_ptr)) then
      call status%set('hypre_ij%init: the matrix has no pattern (csr_matrix%init not called)')
      return
    end if
    self%comm = a%row_map%comm
    bad = a%col_map%n_global /= a%row_map%n_global .or. a%col_map%first /= a%row_map%first &
          .or. a%col_map%n_owned /= a%row_map%n_owned .or. a%n_rows /= a%row_map%n_owned
    if (self%comm%any_true(bad)) then
      if (bad) then
        write(msg, '(a,i0,a,i0,a,i0,a,i0,a,i0)') 'hypre_ij%init: the matrix is not square with '// &
          'rows and columns owned alike on rank ', self%comm%rank, ': rows ', a%row_map%first, &
          '+', a%row_map%n_owned, ', columns ', a%col_map%first, '+', a%col_map%n_owned
      else
        msg = 'hypre_ij%init: the matrix is not square with rows and columns owned alike on some rank'
      end if
      call status%set(msg)
      return
    end if

    block
      type(csr_rows_t) :: src
      src%row_map => a%row_map
      src%a => a
      call self%init_rows(src, status)
    end block
    if (status%ok()) self%pattern_key = pattern_of(a)
  end subroutine init

  !> As init, for a matrix given row by row. Collective over the source's
  !> communicator; status reports global ids beyond HYPRE_BigInt or a hypre
  !> failure, on every rank alike.
  subroutine init_rows(self, src, status)
    class(hypre_ij_t), intent(inout) :: self
    class(ij_rows_t), intent(in) :: src
    type(error_status_t), intent(inout) :: status
    integer(hypre_int) :: ierr
    integer(ip) :: i
    character(len=msg_len) :: msg

    call self%free()
    if (.not. associated(src%row_map)) then
      call status%set('hypre_ij%init: the matrix has no row map')
      return
    end if
    self%comm = src%row_map%comm
    ! global ids must fit HYPRE_BigInt once shifted to 0-based (same on every rank)
    if (src%row_map%n_global - 1 > int(huge(0_hypre_bigint), gp)) then
      write(msg, '(a,i0,a,i0,a)') 'hypre_ij%init: ', src%row_map%n_global, &
        ' global rows do not fit hypre''s HYPRE_BigInt (at most ', &
        int(huge(0_hypre_bigint), gp) + 1, '); hypre would need --enable-bigint'
      call status%set(msg)
      return
    end if
    self%n_rows = src%row_map%n_owned
    self%ilower = int(src%row_map%first - 1, hypre_bigint)
    self%iupper = int(src%row_map%first - 1 + self%n_rows - 1, hypre_bigint)
    allocate(self%rows(self%n_rows), self%ncols(self%n_rows))
    do i = 1, self%n_rows
      self%rows(i) = self%ilower + int(i - 1, hypre_bigint)
    end do

    ierr = HYPRE_ClearAllErrors()
    call build_matrix(self, src)
    call create_vector(self, self%ij_b, self%par_b)
    call create_vector(self, self%ij_x, self%par_x)
    ! hypre's error flag is global and sticky: one look covers the whole sequence
    call hypre_check(self%comm, HYPRE_GetError(), 'hypre_ij%init: building the IJ matrix and vectors', &
                     status)
  end subroutine init_rows

  !> One IJ vector over the owned rows, assembled with zeros.
  subroutine create_vector(self, ij, par)
    type(hypre_ij_t), intent(in) :: self
    type(c_ptr), intent(out) :: ij, par
    integer(hypre_int) :: ierr
    ierr = HYPRE_IJVectorCreate(self%comm%c_handle(), self%ilower, self%iupper, ij)
    ierr = HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR)
    ierr = HYPRE_IJVectorInitialize(ij)
    ierr = HYPRE_IJVectorAssemble(ij)
    ierr = HYPRE_IJVectorGetObject(ij, par)
  end subroutine create_vector

  !> A new IJ vector over the matrix's rows holding the owned values v; the
  !> caller destroys ij (HYPRE_IJVectorDestroy). Collective.
  subroutine new_vector(self, v, ij, par)
    class(hypre_ij_t), intent(in) :: self
    real(rp), intent(in) :: v(:)
    type(c_ptr), intent(out) :: ij, par
    integer(hypre_int) :: ierr
    ierr = HYPRE_IJVectorCreate(self%comm%c_handle(), self%ilower, self%iupper, ij)
    ierr = HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR)
    ierr = HYPRE_IJVectorInitialize(ij)
    if (self%n_rows > 0) ierr = HYPRE_IJVectorSetValues(ij, int(self%n_rows, hypre_int), self%rows, v)
    ierr = HYPRE_IJVectorAssemble(ij)
    ierr = HYPRE_IJVectorGetObject(ij, par)
  end subroutine new_vector

  !> True once init() has built the hypre objects.
  logical function is_ready(self)
    class(hypre_ij_t), intent(in) :: self
    is_ready = c_associated(self%ij_a)
  end function is_ready

  !> New values of a matrix whose pattern (rows, global columns, entry
  !> order) is the one given to init(), in a new IJ matrix (par_a changes;
  !> the vectors stay). Collective; status reports a changed pattern (on
  !> every rank alike) or a hypre failure.
  subroutine update_values(self, a, status)
    class(hypre_ij_t), intent(inout) :: self
    type(csr_matrix_t), intent(in), target :: a
    type(error_status_t), intent(inout) :: status
    integer(ip) :: i
    integer(gp) :: key
    logical :: bad

    if (.not. self%is_ready()) then
      call status%set('hypre_ij%update_values: init() was not called')
      return
    end if
    bad = .not. associated(a%col_map) .or. .not. allocated(a%row_ptr)
    if (.not. bad) bad = a%n_rows /= self%n_rows
    if (.not. bad) bad = a%nnz() /= self%nnz
    if (.not. bad) then
      do i = 1, self%n_rows
        if (a%row_ptr(i+1) - a%row_ptr(i) /= self%ncols(i)) bad = .true.
      end do
    end if
    key = -1
    if (.not. bad) key = pattern_of(a)
    if (.not. bad) bad = key /= self%pattern_key
    if (self%comm%any_true(bad)) then
      call status%set('hypre_ij%update_values: the matrix pattern differs from the one given '// &
                      'to init(); call init() again')
      return
    end if

    block
      type(csr_rows_t) :: src
      src%row_map => a%row_map
      src%a => a
      call self%rebuild_rows(src, status)
    end block
    if (status%ok()) self%pattern_key = key
  end subroutine update_values

  !> New values, and maybe a new pattern, of the matrix over the same owned
  !> rows, row by row: written into hypre's arrays when every row has the
  !> pattern it had (par_a stays; counted in overwrites), else in a new IJ
  !> matrix (par_a changes). The vectors stay. Collective; status reports
  !> other owned rows or a hypre failure.
  subroutine rebuild_rows(self, src, status)
    class(hypre_ij_t), intent(inout) :: self
    class(ij_rows_t), intent(in) :: src
    type(error_status_t), intent(inout) :: status
    integer(hypre_int) :: ierr
    logical :: bad
    if (.not. self%is_ready()) then
      call status%set('hypre_ij%rebuild_rows: init() was not called')
      return
    end if
    bad = .not. associated(src%row_map)
    if (.not. bad) bad = src%row_map%n_owned /= self%n_rows .or. &
                         src%row_map%first - 1 /= int(self%ilower, gp)
    if (self%comm%any_true(bad)) then
      call status%set('hypre_ij%rebuild_rows: the matrix owns other rows than the one given to init()')
      return
    end if
    ierr = HYPRE_ClearAllErrors()
    ! the same pattern (the rows given in the same order): the new values
    ! straight into hypre's arrays (ij_overwrite.c). Doubles again where
    ! they held floats: every value is written, or on a failure the matrix
    ! is built anew
    self%narrowed = .false.
    if (overwrite(self, src)) then
      self%overwrites = self%overwrites + 1
      return
    end if
    ! else a new IJ matrix rather than new values into the assembled one
    ! through hypre: it looks every value's column up by a linear search of
    ! its row there, which made the refresh of HI24L's or the contact
    ! block's S* the slower (contact n = 40, 2 ranks: the whole run
    ! 0.90-0.95x the wall time, farm-bench pairs, medians of 5 in two
    ! calls; the same residuals)
    ierr = HYPRE_IJMatrixDestroy(self%ij_a)
    self%ij_a = c_null_ptr
    self%par_a = c_null_ptr
    self%pattern_key = 0
    call build_matrix(self, src)
    call hypre_check(self%comm, HYPRE_GetError(), 'hypre_ij%update_values', status)
  end subroutine rebuild_rows

  !> src's values into the assembled matrix, a block of rows at a time, as
  !> build_matrix gives them (gb_ij_overwrite checks every entry against
  !> the stored pattern): .true. on every rank when every row fitted, else
  !> .false. on every rank (the matrix is then to be built anew).
  !> Collective.
  logical function overwrite(self, src) result(done)
    type(hypre_ij_t), intent(inout) :: self
    class(ij_rows_t), intent(in) :: src
    integer(hypre_bigint), allocatable :: gcol(:)
    real(rp), allocatable :: val(:), rv(:)
    integer(gp), allocatable :: rg(:)
    integer(hypre_int), allocatable :: nc(:)
    integer(ip) :: i, i0, n, m, mx
    logical :: bad
    mx = max(src%max_row(), 1)
    allocate(rg(mx), rv(mx), nc(self%n_rows))
    allocate(gcol(min(self%nnz, self%block_entries) + mx), val(min(self%nnz, self%block_entries) + mx))
    bad = .false.
    i0 = 1
    m = 0
    do i = 1, self%n_rows
      call src%row(i, rg, rv, n)
      nc(i) = int(n, hypre_int)
      gcol(m + 1:m + n) = int(rg(1:n) - 1, hypre_bigint)
      val(m + 1:m + n) = rv(1:n)
      m = m + n
      if (m < self%block_entries .and. i < self%n_rows) cycle
      bad = gb_ij_overwrite(self%par_a, int(i - i0 + 1, hypre_int), nc(i0:i), self%rows(i0:i), gcol, val) /= 0
      if (bad) exit
      i0 = i + 1
      m = 0
    end do
    done = .not. self%comm%any_true(bad)
    if (done) self%ncols = nc
  end function overwrite

  !> The IJ matrix of src (rows set; ncols and nnz set here), assembled:
  !> sized row by row into its diagonal and off-diagonal blocks, so that
  !> hypre allocates them once (a first pass over the rows), then given its
  !> values a block of rows at a time (a second pass). Local but for
  !> hypre's collective assembly.
  subroutine build_matrix(self, src)
    type(hypre_ij_t), intent(inout) :: self
    class(ij_rows_t), intent(in) :: src
    integer(hypre_int), allocatable :: diag_sizes(:), offd_sizes(:)
    integer(hypre_bigint), allocatable :: gcol(:)
    real(rp), allocatable :: val(:), rv(:)
    integer(gp), allocatable :: rg(:)
    integer(gp) :: g0, g1
    integer(hypre_int) :: ierr
    integer(ip) :: i, i0, n, m, mx
    mx = max(src%max_row(), 1)
    allocate(rg(mx), rv(mx))
    allocate(diag_sizes(self%n_rows), offd_sizes(self%n_rows))
    g0 = int(self%ilower, gp) + 1
    g1 = int(self%iupper, gp) + 1
    self%nnz = 0
    do i = 1, self%n_rows
      call src%row(i, rg, rv, n)
      self%ncols(i) = int(n, hypre_int)
      self%nnz = self%nnz + n
      diag_sizes(i) = int(count(rg(1:n) >= g0 .and. rg(1:n) <= g1), hypre_int)
      offd_sizes(i) = self%ncols(i) - diag_sizes(i)
    end do
    ierr = HYPRE_IJMatrixCreate(self%comm%c_handle(), self%ilower, self%iupper, &
                                self%ilower, self%iupper, self%ij_a)
    ierr = HYPRE_IJMatrixSetObjectType(self%ij_a, HYPRE_PARCSR)
    if (self%n_rows > 0) ierr = HYPRE_IJMatrixSetDiagOffdSizes(self%ij_a, diag_sizes, offd_sizes)
    deallocate(diag_sizes, offd_sizes)
    ierr = HYPRE_IJMatrixInitialize(self%ij_a)
    allocate(gcol(min(self%nnz, self%block_entries) + mx), val(min(self%nnz, self%block_entries) + mx))
    i0 = 1
    m = 0
    do i = 1, self%n_rows
      ! rows i0..i: as many as fill a block
      call src%row(i, rg, rv, n)
      gcol(m + 1:m + n) = int(rg(1:n) - 1, hypre_bigint)
      val(m + 1:m + n) = rv(1:n)
      m = m + n
      if (m < self%block_entries .and. i < self%n_rows) cycle
      ierr = HYPRE_IJMatrixSetValues(self%ij_a, int(i - i0 + 1, hypre_int), self%ncols(i0:i), &
                                     self%rows(i0:i), gcol, val)
      i0 = i + 1
      m = 0
    end do
    ierr = HYPRE_IJMatrixAssemble(self%ij_a)
    ierr = HYPRE_IJMatrixGetObject(self%ij_a, self%par_a)
  end subroutine build_matrix

  integer(ip) function csr_max_row(self)
    class(csr_rows_t), intent(in) :: self
    csr_max_row = 0
    if (self%a%n_rows > 0) csr_max_row = maxval(self%a%row_ptr(2:self%a%n_rows + 1) - &
                                                self%a%row_ptr(1:self%a%n_rows))
  end function csr_max_row

  subroutine csr_row(self, i, gcol, val, n)
    class(csr_rows_t), intent(in) :: self
    integer(ip), intent(in) :: i
    integer(gp), intent(inout) :: gcol(:)
    real(rp), intent(inout) :: val(:)
    integer(ip), intent(out) :: n
    integer(ip) :: k, k0
    k0 = self%a%row_ptr(i)
    n = self%a%row_ptr(i + 1) - k0
    do k = 1, n
      gcol(k) = self%a%col_map%global_id(self%a%col(k0 + k - 1))
    end do
    val(1:n) = self%a%val(k0:k0 + n - 1)
  end subroutine csr_row

  !> A fingerprint of a's pattern: its rows' global column ids in CSR order
  !> hashed modulo the prime 2^31 - 1 (a changed pattern with the same
  !> entries per row goes unseen with odds of about 1 in 2e9).
  integer(gp) function pattern_of(a) result(key)
    type(csr_matrix_t), intent(in) :: a
    integer(gp), parameter :: prime = 2147483647_gp, mult = 1000003_gp
    integer(ip) :: k
    key = 0
    do k = 1, a%nnz()
      key = mod(key * mult + mod(a%col_map%global_id(a%col(k)), prime), prime)
    end do
  end function pattern_of

  !> b = r (owned entries). Collective. ierr: hypre's error flag after the
  !> call (global and sticky: it also holds errors not cleared before).
  subroutine set_rhs(self, r, ierr)
    class(hypre_ij_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    integer(hypre_int), intent(out), optional :: ierr
    integer(hypre_int) :: e
    if (size(r) < self%n_rows) error stop 'hypre_ij%set_rhs: r is shorter than the owned rows'
    e = HYPRE_IJVectorInitialize(self%ij_b)
    if (self%n_rows > 0) e = HYPRE_IJVectorSetValues(self%ij_b, int(self%n_rows, hypre_int), &
                                                    self%rows, r)
    e = HYPRE_IJVectorAssemble(self%ij_b)
    if (present(ierr)) ierr = HYPRE_GetError()
  end subroutine set_rhs

  !> x = 0 (the initial guess of a preconditioner application). Not
  !> collective. ierr as for set_rhs.
  subroutine zero_x(self, ierr)
    class(hypre_ij_t), intent(inout) :: self
    integer(hypre_int), intent(out), optional :: ierr
    integer(hypre_int) :: e
    e = HYPRE_ParVectorSetConstantValues(self%par_x, 0.0_hypre_real)
    if (present(ierr)) ierr = HYPRE_GetError()
  end subroutine zero_x

  !> z = x (owned entries). Not collective. ierr as for set_rhs.
  subroutine get_x(self, z, ierr)
    class(hypre_ij_t), intent(inout) :: self
    real(rp), intent(out) :: z(:)
    integer(hypre_int), intent(out), optional :: ierr
    integer(hypre_int) :: e
    if (size(z) < self%n_rows) error stop 'hypre_ij%get_x: z is shorter than the owned rows'
    if (self%n_rows > 0) e = HYPRE_IJVectorGetValues(self%ij_x, int(self%n_rows, hypre_int), &
                                                    self%rows, z)
    if (present(ierr)) ierr = HYPRE_GetError()
  end subroutine get_x

  !> y = A x with hypre's ParCSR product (through b and x, which it
  !> overwrites). Collective. ierr as for set_rhs.
  subroutine matvec(self, x, y, ierr)
    class(hypre_ij_t), intent(inout) :: self
    real(rp), intent(in) :: x(:)
    real(rp), intent(out) :: y(:)
    integer(hypre_int), intent(out), optional :: ierr
    integer(hypre_int) :: e
    if (self%narrowed) error stop 'hypre_ij%matvec: the values are floats in place (boomeramg_precon)'
    call self%set_rhs(x)
    e = HYPRE_ParCSRMatrixMatvec(1.0_hypre_real, self%par_a, self%par_b, 0.0_hypre_real, self%par_x)
    call self%get_x(y, ierr)
  end subroutine matvec

  !> Destroy the hypre objects and forget the index arrays.
  subroutine free(self)
    class(hypre_ij_t), intent(inout) :: self
    integer(hypre_int) :: ierr
    ! destroying an IJ object also destroys the ParCSR object it built
    if (c_associated(self%ij_a)) ierr = HYPRE_IJMatrixDestroy(self%ij_a)
    if (c_associated(self%ij_b)) ierr = HYPRE_IJVectorDestroy(self%ij_b)
    if (c_associated(self%ij_x)) ierr = HYPRE_IJVectorDestroy(self%ij_x)
    self%ij_a = c_null_ptr
    self%par_a = c_null_ptr
    self%ij_b = c_null_ptr
    self%par_b = c_null_ptr
    self%ij_x = c_null_ptr
    self%par_x = c_null_ptr
    if (allocated(self%rows)) deallocate(self%rows)
    if (allocated(self%ncols)) deallocate(self%ncols)
    self%pattern_key = 0
    self%narrowed = .false.
    self%n_rows = 0
    self%nnz = 0
    self%ilower = 0
    self%iupper = -1
  end subroutine free

  !> hypre's description of an error flag ierr.
  function hypre_error_text(ierr) result(text)
    integer(hypre_int), intent(in) :: ierr
    character(len=:), allocatable :: text
    character(kind=c_char) :: buf(1024)
    integer :: n
    buf = c_null_char
    call HYPRE_DescribeError(ierr, buf)
    n = 0
    do while (n < size(buf))
      if (buf(n+1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: text)
    text = transfer(buf(1:n), text)
  end function hypre_error_text

  !> Combine hypre's error flag ierr over the ranks of comm: when it is
  !> nonzero anywhere, status gets "what: <hypre's description>" on every rank.
  !> Collective.
  subroutine hypre_check(comm, ierr, what, status)
    type(parallel_comm_t), intent(in) :: comm
    integer(hypre_int), intent(in) :: ierr
    character(len=*), intent(in) :: what
    type(error_status_t), intent(inout) :: status
    integer(ip) :: worst
    worst = comm%max(int(ierr, ip))
    if (worst /= 0) then
      call status%set(trim(what)//': hypre error '//hypre_error_text(int(worst, hypre_int)))
    end if
  end subroutine hypre_check
end module hypre_ij
