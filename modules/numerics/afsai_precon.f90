!> geoblock's own adaptive FSAI as a preconditioner: M^-1 = G^T G with G the
!> lower triangular factor of afsai_factor (Janna and Ferronato, SIAM J. Sci.
!> Comput. 33 (2011) 3357-3380). Unlike hypre's FSAI (hypre_fsai_precon),
!> G is built from the whole distributed matrix (rows of other ranks are
!> fetched), so the preconditioner, and the iteration counts, do not depend
!> on the number of ranks when the rows carry partition-independent keys.
!>
!> setup() builds G and G^T as csr_matrix_t for fast application; apply()
!> is two sparse products, z = G^T (G r).
module afsai_precon
  use kinds, only: rp, gp, name_len
  use parallel_comm, only: wall_time
  use error_status, only: error_status_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, from_csr, to_csr, gcsr_transpose
  use precon, only: precon_t
  use fsai_params, only: fsai_params_t
  use afsai, only: afsai_factor
  implicit none
  private

  public :: afsai_precon_t

  !> M^-1 = G^T G. Set up by value: after setup() the object owns the column
  !> maps of G and G^T through pointers, and points at the row map of the
  !> matrix given to setup() (which must outlive it). Do not copy it by
  !> assignment (the copies would share, and free twice, those maps); call
  !> free() when done.
  type, extends(precon_t) :: afsai_precon_t
    type(fsai_params_t) :: params            !< settings of the last set-up
    type(csr_matrix_t) :: g                  !< the factor G
    type(csr_matrix_t) :: gt                 !< G^T
    real(rp), allocatable :: w(:)            !< work: G r
    integer(gp) :: nnz_g = 0                 !< global non-zeros of G
    logical :: ready = .false.
  contains
    procedure :: setup
    procedure :: apply => afsai_apply
    procedure :: name => afsai_name
    procedure :: nnz_factor
    procedure :: free => afsai_free
  end type afsai_precon_t

contains

  !> Build G for the SPD matrix a (square: rows and columns owned alike).
  !> keys (optional, one per owned row): partition-independent ordering keys
  !> of the rows, e.g. the dofs' ids in the original mesh numbering; they
  !> decide the triangular order and every tie, so that G does not depend
  !> on the number of ranks. Default: the global row ids (then G depends on
  !> the partition's numbering). a's row map becomes the row map of G and
  !> G^T: a must outlive this object. Collective; times itself into
  !> setup_time (seconds). status reports, on every rank alike, bad params,
  !> bad keys, or a matrix that is not SPD.
  subroutine setup(self, a, params, status, keys)
    class(afsai_precon_t), intent(inout) :: self
    type(csr_matrix_t), intent(in), target :: a
    type(fsai_params_t), intent(in) :: params
    type(error_status_t), intent(inout) :: status
    integer(gp), intent(in), optional :: keys(:)
    type(global_csr_t) :: ga, gg, ggt
    real(rp) :: t0
    logical :: bad

    t0 = wall_time()
    call self%free()
    call params%validate(status)
    if (.not. status%ok()) return
    if (.not. associated(a%row_map)) then
      call status%set('afsai_precon%setup: the matrix has no pattern')
      return
    end if
    bad = .false.
    if (present(keys)) bad = size(keys) /= a%n_rows
    if (a%row_map%comm%any_true(bad)) then
      call status%set('afsai_precon%setup: keys must hold one entry per owned row')
      return
    end if
    call from_csr(a, ga)
    if (present(keys)) call ga%set_keys(keys)
    call afsai_factor(ga, params, gg, status)
    if (.not. status%ok()) return
    call ga%free()
    call gcsr_transpose(gg, ggt)
    call to_csr(gg, a%row_map, self%g)
    call to_csr(ggt, a%row_map, self%gt)
    self%nnz_g = gg%global_nnz()
    allocate(self%w(a%n_rows))
    self%params = params
    self%ready = .true.
    self%setup_time = wall_time() - t0
  end subroutine setup

  !> z = G^T (G r) on the owned entries. Collective.
  subroutine afsai_apply(self, r, z)
    class(afsai_precon_t), intent(inout) :: self
    real(rp), intent(in) :: r(:)
    real(rp), intent(out) :: z(:)
    if (.not. self%ready) error stop 'afsai_precon%apply: setup() was not called or failed'
    call self%g%apply(r, self%w)
    call self%gt%apply(self%w, z)
  end subroutine afsai_apply

  function afsai_name(self) result(s)
    class(afsai_precon_t), intent(in) :: self
    character(len=name_len) :: s
    s = 'afsai'
  end function afsai_name

  !> Non-zeros of G over all ranks (known after setup; not collective).
  integer(gp) function nnz_factor(self)
    class(afsai_precon_t), intent(in) :: self
    nnz_factor = self%nnz_g
  end function nnz_factor

  !> Release G, G^T (with their column maps) and the work vector.
  subroutine afsai_free(self)
    class(afsai_precon_t), intent(inout) :: self
    call self%g%free()
    call self%gt%free()
    if (allocated(self%w)) deallocate(self%w)
    self%nnz_g = 0
    self%ready = .false.
    ! what precon_t%free does (a binding of an abstract parent cannot be called)
    self%setup_time = 0.0_rp
  end subroutine afsai_free
end module afsai_precon
