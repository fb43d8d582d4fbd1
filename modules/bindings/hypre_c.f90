!> Raw bind(C) interfaces to the part of the hypre 2.26 C API that geoblock uses
!> (IJ matrices and vectors, ParCSR mat-vec, BoomerAMG, FSAI, MGR, error
!> handling).
!>
!> Prototypes follow /usr/include/hypre/{HYPRE_utilities,HYPRE_IJ_mv,
!> HYPRE_parcsr_mv,HYPRE_parcsr_ls}.h of Debian's build: HYPRE_Int and
!> HYPRE_BigInt are C int (no --enable-bigint), HYPRE_Real and HYPRE_Complex
!> are double. Every handle (HYPRE_IJMatrix, HYPRE_ParCSRMatrix, HYPRE_Solver,
!> ...) is an opaque C pointer, and so is MPI_Comm in Open MPI: pass
!> parallel_comm_t%c_handle() by value. Every HYPRE_ function returns hypre's
!> global error flag (0 on success); the flag is sticky, so callers clear it
!> with HYPRE_ClearAllErrors before a sequence of calls they want to check.
!>
!> HYPRE_Init/HYPRE_Finalize are bound but optional on a host-only build:
!> hypre 2.26 creates its global handle on first use (hypre_handle()).
!> Nothing here holds state; the wrapper hypre_ij owns the handles.
module hypre_c
  use, intrinsic :: iso_c_binding, only: c_ptr, c_funptr, c_int, c_char, c_size_t
  use kinds, only: hypre_int, hypre_bigint, hypre_real
  implicit none
  private

  !> HYPRE_PARCSR (HYPRE.h): the only object type of IJ matrices and vectors.
  integer(hypre_int), parameter, public :: HYPRE_PARCSR = 5555
  !> HYPRE_MEMORY_HOST of the HYPRE_MemoryLocation enum (HYPRE_utilities.h).
  integer(c_int), parameter, public :: HYPRE_MEMORY_HOST = 0
  !> HYPRE_ERROR_CONV: a solver did not converge (HYPRE_utilities.h).
  integer(hypre_int), parameter, public :: HYPRE_ERROR_CONV = 256

  public :: HYPRE_Init, HYPRE_Finalize
  public :: HYPRE_GetError, HYPRE_ClearAllErrors, HYPRE_DescribeError, hypre_CAlloc
  public :: HYPRE_IJMatrixCreate, HYPRE_IJMatrixDestroy, HYPRE_IJMatrixSetObjectType
  public :: HYPRE_IJMatrixSetRowSizes, HYPRE_IJMatrixSetDiagOffdSizes
  public :: HYPRE_IJMatrixInitialize, HYPRE_IJMatrixSetValues, HYPRE_IJMatrixAssemble
  public :: HYPRE_IJMatrixGetObject
  public :: HYPRE_IJVectorCreate, HYPRE_IJVectorDestroy, HYPRE_IJVectorSetObjectType
  public :: HYPRE_IJVectorInitialize, HYPRE_IJVectorSetValues, HYPRE_IJVectorAssemble
  public :: HYPRE_IJVectorGetValues, HYPRE_IJVectorGetObject
  public :: HYPRE_ParVectorSetConstantValues, HYPRE_ParCSRMatrixMatvec
  public :: HYPRE_BoomerAMGCreate, HYPRE_BoomerAMGDestroy, HYPRE_BoomerAMGSetup
  public :: HYPRE_BoomerAMGSolve, HYPRE_BoomerAMGGetNumIterations
  public :: HYPRE_BoomerAMGGetFinalRelativeResidualNorm, HYPRE_BoomerAMGGetGridHierarchy
  public :: HYPRE_BoomerAMGSetTol, HYPRE_BoomerAMGSetMaxIter, HYPRE_BoomerAMGSetPrintLevel
  public :: HYPRE_BoomerAMGSetNumFunctions, HYPRE_BoomerAMGSetDofFunc, HYPRE_BoomerAMGSetNodal
  public :: HYPRE_BoomerAMGSetCoarsenType, HYPRE_BoomerAMGSetInterpType
  public :: HYPRE_BoomerAMGSetAggNumLevels, HYPRE_BoomerAMGSetAggInterpType
  public :: HYPRE_BoomerAMGSetAggPMaxElmts, HYPRE_BoomerAMGSetNumPaths
  public :: HYPRE_BoomerAMGSetStrongThreshold, HYPRE_BoomerAMGSetMaxRowSum
  public :: HYPRE_BoomerAMGSetMaxLevels, HYPRE_BoomerAMGSetMaxCoarseSize
  public :: HYPRE_BoomerAMGSetRelaxType, HYPRE_BoomerAMGSetCycleRelaxType
  public :: HYPRE_BoomerAMGSetRelaxOrder
  public :: HYPRE_BoomerAMGSetNumSweeps, HYPRE_BoomerAMGSetRelaxWt, HYPRE_BoomerAMGSetCycleType
  public :: HYPRE_BoomerAMGSetTruncFactor, HYPRE_BoomerAMGSetPMaxElmts
  public :: HYPRE_FSAICreate, HYPRE_FSAIDestroy, HYPRE_FSAISetup, HYPRE_FSAISolve
  public :: HYPRE_FSAISetAlgoType, HYPRE_FSAISetMaxSteps, HYPRE_FSAISetMaxStepSize
  public :: HYPRE_FSAISetKapTolerance, HYPRE_FSAISetOmega, HYPRE_FSAISetMaxIterations
  public :: HYPRE_FSAISetEigMaxIters, HYPRE_FSAISetTolerance, HYPRE_FSAISetPrintLevel
  public :: HYPRE_FSAISetZeroGuess
  public :: HYPRE_BoomerAMGSetInterpVectors, HYPRE_BoomerAMGSetInterpVecVariant, HYPRE_BoomerAMGSetInterpVecQMax
  public :: HYPRE_MGRCreate, HYPRE_MGRDestroy, HYPRE_MGRSetup, HYPRE_MGRSolve
  public :: HYPRE_MGRSetCpointsByPointMarkerArray, HYPRE_MGRSetNonCpointsToFpoints
  public :: HYPRE_MGRSetMaxCoarseLevels, HYPRE_MGRSetLevelFRelaxType, HYPRE_MGRSetCoarseGridMethod
  public :: HYPRE_MGRSetLevelInterpType, HYPRE_MGRSetLevelRestrictType, HYPRE_MGRSetLevelNumRelaxSweeps
  public :: HYPRE_MGRSetFSolver, HYPRE_MGRSetCoarseSolver, HYPRE_MGRSetMaxIter, HYPRE_MGRSetTol
  public :: HYPRE_MGRSetPrintLevel, HYPRE_MGRSetPMaxElmts, HYPRE_MGRSetMaxGlobalSmoothIters

  interface

    ! ---- library state and errors (HYPRE_utilities.h) ----------------------

    !> HYPRE_Int HYPRE_Init(void)
    function HYPRE_Init() bind(C, name='HYPRE_Init') result(ierr)
      import :: hypre_int
      integer(hypre_int) :: ierr
    end function HYPRE_Init

    !> HYPRE_Int HYPRE_Finalize(void)
    function HYPRE_Finalize() bind(C, name='HYPRE_Finalize') result(ierr)
      import :: hypre_int
      integer(hypre_int) :: ierr
    end function HYPRE_Finalize

    !> HYPRE_Int HYPRE_GetError(void): the current global error flag.
    function HYPRE_GetError() bind(C, name='HYPRE_GetError') result(ierr)
      import :: hypre_int
      integer(hypre_int) :: ierr
    end function HYPRE_GetError

    !> HYPRE_Int HYPRE_ClearAllErrors(void)
    function HYPRE_ClearAllErrors() bind(C, name='HYPRE_ClearAllErrors') result(ierr)
      import :: hypre_int
      integer(hypre_int) :: ierr
    end function HYPRE_ClearAllErrors

    !> void HYPRE_DescribeError(HYPRE_Int hypre_ierr, char *descr)
    !> descr must hold at least a few hundred characters; it is NUL-terminated.
    subroutine HYPRE_DescribeError(hypre_ierr, descr) bind(C, name='HYPRE_DescribeError')
      import :: hypre_int, c_char
      integer(hypre_int), value :: hypre_ierr
      character(kind=c_char), intent(out) :: descr(*)
    end subroutine HYPRE_DescribeError

    !> void *hypre_CAlloc(size_t count, size_t elt_size, HYPRE_MemoryLocation location)
    !> (_hypre_utilities.h). Needed for arrays whose ownership passes to hypre,
    !> which later releases them with hypre_TFree (e.g. the BoomerAMG dof_func).
    function hypre_CAlloc(count, elt_size, location) bind(C, name='hypre_CAlloc') result(p)
      import :: c_ptr, c_size_t, c_int
      integer(c_size_t), value :: count, elt_size
      integer(c_int), value :: location
      type(c_ptr) :: p
    end function hypre_CAlloc

    ! ---- IJ matrix (HYPRE_IJ_mv.h) -----------------------------------------

    !> HYPRE_Int HYPRE_IJMatrixCreate(MPI_Comm comm, HYPRE_BigInt ilower,
    !>   HYPRE_BigInt iupper, HYPRE_BigInt jlower, HYPRE_BigInt jupper, HYPRE_IJMatrix *matrix)
    !> Row and column ranges are 0-based and inclusive.
    function HYPRE_IJMatrixCreate(comm, ilower, iupper, jlower, jupper, matrix) &
        bind(C, name='HYPRE_IJMatrixCreate') result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint
      type(c_ptr), value :: comm
      integer(hypre_bigint), value :: ilower, iupper, jlower, jupper
      type(c_ptr), intent(out) :: matrix
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixCreate

    !> HYPRE_Int HYPRE_IJMatrixDestroy(HYPRE_IJMatrix matrix)
    function HYPRE_IJMatrixDestroy(matrix) bind(C, name='HYPRE_IJMatrixDestroy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixDestroy

    !> HYPRE_Int HYPRE_IJMatrixSetObjectType(HYPRE_IJMatrix matrix, HYPRE_Int type)
    function HYPRE_IJMatrixSetObjectType(matrix, type) &
        bind(C, name='HYPRE_IJMatrixSetObjectType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int), value :: type
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixSetObjectType

    !> HYPRE_Int HYPRE_IJMatrixSetRowSizes(HYPRE_IJMatrix matrix, const HYPRE_Int *sizes)
    function HYPRE_IJMatrixSetRowSizes(matrix, sizes) &
        bind(C, name='HYPRE_IJMatrixSetRowSizes') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int), intent(in) :: sizes(*)
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixSetRowSizes

    !> HYPRE_Int HYPRE_IJMatrixSetDiagOffdSizes(HYPRE_IJMatrix matrix,
    !>   const HYPRE_Int *diag_sizes, const HYPRE_Int *offdiag_sizes)
    !> Exact entries per owned row in the owned (diag) and other (offd) columns.
    function HYPRE_IJMatrixSetDiagOffdSizes(matrix, diag_sizes, offdiag_sizes) &
        bind(C, name='HYPRE_IJMatrixSetDiagOffdSizes') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int), intent(in) :: diag_sizes(*), offdiag_sizes(*)
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixSetDiagOffdSizes

    !> HYPRE_Int HYPRE_IJMatrixInitialize(HYPRE_IJMatrix matrix)
    !> Also re-opens an assembled matrix for new values in the same pattern.
    function HYPRE_IJMatrixInitialize(matrix) bind(C, name='HYPRE_IJMatrixInitialize') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixInitialize

    !> HYPRE_Int HYPRE_IJMatrixSetValues(HYPRE_IJMatrix matrix, HYPRE_Int nrows,
    !>   HYPRE_Int *ncols, const HYPRE_BigInt *rows, const HYPRE_BigInt *cols,
    !>   const HYPRE_Complex *values)
    function HYPRE_IJMatrixSetValues(matrix, nrows, ncols, rows, cols, values) &
        bind(C, name='HYPRE_IJMatrixSetValues') result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint, hypre_real
      type(c_ptr), value :: matrix
      integer(hypre_int), value :: nrows
      integer(hypre_int), intent(in) :: ncols(*)
      integer(hypre_bigint), intent(in) :: rows(*), cols(*)
      real(hypre_real), intent(in) :: values(*)
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixSetValues

    !> HYPRE_Int HYPRE_IJMatrixAssemble(HYPRE_IJMatrix matrix); collective.
    function HYPRE_IJMatrixAssemble(matrix) bind(C, name='HYPRE_IJMatrixAssemble') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixAssemble

    !> HYPRE_Int HYPRE_IJMatrixGetObject(HYPRE_IJMatrix matrix, void **object)
    !> object: the HYPRE_ParCSRMatrix, owned by the IJ matrix.
    function HYPRE_IJMatrixGetObject(matrix, object) &
        bind(C, name='HYPRE_IJMatrixGetObject') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: matrix
      type(c_ptr), intent(out) :: object
      integer(hypre_int) :: ierr
    end function HYPRE_IJMatrixGetObject

    ! ---- IJ vector (HYPRE_IJ_mv.h) -----------------------------------------

    !> HYPRE_Int HYPRE_IJVectorCreate(MPI_Comm comm, HYPRE_BigInt jlower,
    !>   HYPRE_BigInt jupper, HYPRE_IJVector *vector)
    function HYPRE_IJVectorCreate(comm, jlower, jupper, vector) &
        bind(C, name='HYPRE_IJVectorCreate') result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint
      type(c_ptr), value :: comm
      integer(hypre_bigint), value :: jlower, jupper
      type(c_ptr), intent(out) :: vector
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorCreate

    !> HYPRE_Int HYPRE_IJVectorDestroy(HYPRE_IJVector vector)
    function HYPRE_IJVectorDestroy(vector) bind(C, name='HYPRE_IJVectorDestroy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: vector
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorDestroy

    !> HYPRE_Int HYPRE_IJVectorSetObjectType(HYPRE_IJVector vector, HYPRE_Int type)
    function HYPRE_IJVectorSetObjectType(vector, type) &
        bind(C, name='HYPRE_IJVectorSetObjectType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: vector
      integer(hypre_int), value :: type
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorSetObjectType

    !> HYPRE_Int HYPRE_IJVectorInitialize(HYPRE_IJVector vector)
    function HYPRE_IJVectorInitialize(vector) bind(C, name='HYPRE_IJVectorInitialize') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: vector
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorInitialize

    !> HYPRE_Int HYPRE_IJVectorSetValues(HYPRE_IJVector vector, HYPRE_Int nvalues,
    !>   const HYPRE_BigInt *indices, const HYPRE_Complex *values)
    function HYPRE_IJVectorSetValues(vector, nvalues, indices, values) &
        bind(C, name='HYPRE_IJVectorSetValues') result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint, hypre_real
      type(c_ptr), value :: vector
      integer(hypre_int), value :: nvalues
      integer(hypre_bigint), intent(in) :: indices(*)
      real(hypre_real), intent(in) :: values(*)
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorSetValues

    !> HYPRE_Int HYPRE_IJVectorAssemble(HYPRE_IJVector vector); collective.
    function HYPRE_IJVectorAssemble(vector) bind(C, name='HYPRE_IJVectorAssemble') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: vector
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorAssemble

    !> HYPRE_Int HYPRE_IJVectorGetValues(HYPRE_IJVector vector, HYPRE_Int nvalues,
    !>   const HYPRE_BigInt *indices, HYPRE_Complex *values); not collective.
    function HYPRE_IJVectorGetValues(vector, nvalues, indices, values) &
        bind(C, name='HYPRE_IJVectorGetValues') result(ierr)
      import :: c_ptr, hypre_int, hypre_bigint, hypre_real
      type(c_ptr), value :: vector
      integer(hypre_int), value :: nvalues
      integer(hypre_bigint), intent(in) :: indices(*)
      real(hypre_real), intent(out) :: values(*)
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorGetValues

    !> HYPRE_Int HYPRE_IJVectorGetObject(HYPRE_IJVector vector, void **object)
    !> object: the HYPRE_ParVector, owned by the IJ vector.
    function HYPRE_IJVectorGetObject(vector, object) &
        bind(C, name='HYPRE_IJVectorGetObject') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: vector
      type(c_ptr), intent(out) :: object
      integer(hypre_int) :: ierr
    end function HYPRE_IJVectorGetObject

    ! ---- ParCSR objects (HYPRE_parcsr_mv.h) --------------------------------

    !> HYPRE_Int HYPRE_ParVectorSetConstantValues(HYPRE_ParVector vector, HYPRE_Complex value)
    function HYPRE_ParVectorSetConstantValues(vector, value) &
        bind(C, name='HYPRE_ParVectorSetConstantValues') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: vector
      real(hypre_real), value :: value
      integer(hypre_int) :: ierr
    end function HYPRE_ParVectorSetConstantValues

    !> HYPRE_Int HYPRE_ParCSRMatrixMatvec(HYPRE_Complex alpha, HYPRE_ParCSRMatrix A,
    !>   HYPRE_ParVector x, HYPRE_Complex beta, HYPRE_ParVector y): y = alpha A x + beta y.
    function HYPRE_ParCSRMatrixMatvec(alpha, a, x, beta, y) &
        bind(C, name='HYPRE_ParCSRMatrixMatvec') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      real(hypre_real), value :: alpha
      type(c_ptr), value :: a, x
      real(hypre_real), value :: beta
      type(c_ptr), value :: y
      integer(hypre_int) :: ierr
    end function HYPRE_ParCSRMatrixMatvec

    ! ---- BoomerAMG (HYPRE_parcsr_ls.h) -------------------------------------

    !> HYPRE_Int HYPRE_BoomerAMGCreate(HYPRE_Solver *solver)
    function HYPRE_BoomerAMGCreate(solver) bind(C, name='HYPRE_BoomerAMGCreate') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), intent(out) :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGCreate

    !> HYPRE_Int HYPRE_BoomerAMGDestroy(HYPRE_Solver solver)
    function HYPRE_BoomerAMGDestroy(solver) bind(C, name='HYPRE_BoomerAMGDestroy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGDestroy

    !> HYPRE_Int HYPRE_BoomerAMGSetup(HYPRE_Solver solver, HYPRE_ParCSRMatrix A,
    !>   HYPRE_ParVector b, HYPRE_ParVector x); b and x are ignored.
    function HYPRE_BoomerAMGSetup(solver, a, b, x) bind(C, name='HYPRE_BoomerAMGSetup') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetup

    !> HYPRE_Int HYPRE_BoomerAMGSolve(HYPRE_Solver solver, HYPRE_ParCSRMatrix A,
    !>   HYPRE_ParVector b, HYPRE_ParVector x); x holds the initial guess.
    function HYPRE_BoomerAMGSolve(solver, a, b, x) bind(C, name='HYPRE_BoomerAMGSolve') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSolve

    !> HYPRE_Int HYPRE_BoomerAMGGetNumIterations(HYPRE_Solver solver, HYPRE_Int *num_iterations)
    function HYPRE_BoomerAMGGetNumIterations(solver, num_iterations) &
        bind(C, name='HYPRE_BoomerAMGGetNumIterations') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(out) :: num_iterations
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGGetNumIterations

    !> HYPRE_Int HYPRE_BoomerAMGGetFinalRelativeResidualNorm(HYPRE_Solver solver,
    !>   HYPRE_Real *rel_resid_norm)
    function HYPRE_BoomerAMGGetFinalRelativeResidualNorm(solver, rel_resid_norm) &
        bind(C, name='HYPRE_BoomerAMGGetFinalRelativeResidualNorm') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), intent(out) :: rel_resid_norm
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGGetFinalRelativeResidualNorm

    !> HYPRE_Int HYPRE_BoomerAMGGetGridHierarchy(HYPRE_Solver solver, HYPRE_Int *cgrid)
    !> After set-up: cgrid(i) = last (0-based) level that contains owned row i.
    function HYPRE_BoomerAMGGetGridHierarchy(solver, cgrid) &
        bind(C, name='HYPRE_BoomerAMGGetGridHierarchy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(out) :: cgrid(*)
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGGetGridHierarchy

    !> HYPRE_Int HYPRE_BoomerAMGSetTol(HYPRE_Solver solver, HYPRE_Real tol)
    function HYPRE_BoomerAMGSetTol(solver, tol) bind(C, name='HYPRE_BoomerAMGSetTol') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: tol
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetTol

    !> HYPRE_Int HYPRE_BoomerAMGSetMaxIter(HYPRE_Solver solver, HYPRE_Int max_iter)
    function HYPRE_BoomerAMGSetMaxIter(solver, max_iter) &
        bind(C, name='HYPRE_BoomerAMGSetMaxIter') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_iter
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetMaxIter

    !> HYPRE_Int HYPRE_BoomerAMGSetPrintLevel(HYPRE_Solver solver, HYPRE_Int print_level)
    function HYPRE_BoomerAMGSetPrintLevel(solver, print_level) &
        bind(C, name='HYPRE_BoomerAMGSetPrintLevel') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: print_level
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetPrintLevel

    !> HYPRE_Int HYPRE_BoomerAMGSetNumFunctions(HYPRE_Solver solver, HYPRE_Int num_functions)
    function HYPRE_BoomerAMGSetNumFunctions(solver, num_functions) &
        bind(C, name='HYPRE_BoomerAMGSetNumFunctions') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: num_functions
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetNumFunctions

    !> HYPRE_Int HYPRE_BoomerAMGSetDofFunc(HYPRE_Solver solver, HYPRE_Int *dof_func)
    !> hypre takes ownership of dof_func (n_owned entries, 0-based function ids)
    !> and frees it with hypre_TFree: allocate it with hypre_CAlloc, never pass
    !> Fortran memory.
    function HYPRE_BoomerAMGSetDofFunc(solver, dof_func) &
        bind(C, name='HYPRE_BoomerAMGSetDofFunc') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      type(c_ptr), value :: dof_func
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetDofFunc

    !> HYPRE_Int HYPRE_BoomerAMGSetNodal(HYPRE_Solver solver, HYPRE_Int nodal)
    function HYPRE_BoomerAMGSetNodal(solver, nodal) bind(C, name='HYPRE_BoomerAMGSetNodal') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: nodal
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetNodal

    !> HYPRE_Int HYPRE_BoomerAMGSetCoarsenType(HYPRE_Solver solver, HYPRE_Int coarsen_type)
    function HYPRE_BoomerAMGSetCoarsenType(solver, coarsen_type) &
        bind(C, name='HYPRE_BoomerAMGSetCoarsenType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: coarsen_type
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetCoarsenType

    !> HYPRE_Int HYPRE_BoomerAMGSetInterpType(HYPRE_Solver solver, HYPRE_Int interp_type)
    function HYPRE_BoomerAMGSetInterpType(solver, interp_type) &
        bind(C, name='HYPRE_BoomerAMGSetInterpType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: interp_type
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetInterpType

    !> HYPRE_Int HYPRE_BoomerAMGSetAggNumLevels(HYPRE_Solver solver, HYPRE_Int agg_num_levels)
    function HYPRE_BoomerAMGSetAggNumLevels(solver, agg_num_levels) &
        bind(C, name='HYPRE_BoomerAMGSetAggNumLevels') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: agg_num_levels
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetAggNumLevels

    !> HYPRE_Int HYPRE_BoomerAMGSetAggInterpType(HYPRE_Solver solver, HYPRE_Int agg_interp_type)
    function HYPRE_BoomerAMGSetAggInterpType(solver, agg_interp_type) &
        bind(C, name='HYPRE_BoomerAMGSetAggInterpType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: agg_interp_type
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetAggInterpType

    !> HYPRE_Int HYPRE_BoomerAMGSetAggPMaxElmts(HYPRE_Solver solver, HYPRE_Int agg_P_max_elmts)
    function HYPRE_BoomerAMGSetAggPMaxElmts(solver, agg_p_max_elmts) &
        bind(C, name='HYPRE_BoomerAMGSetAggPMaxElmts') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: agg_p_max_elmts
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetAggPMaxElmts

    !> HYPRE_Int HYPRE_BoomerAMGSetNumPaths(HYPRE_Solver solver, HYPRE_Int num_paths)
    function HYPRE_BoomerAMGSetNumPaths(solver, num_paths) &
        bind(C, name='HYPRE_BoomerAMGSetNumPaths') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: num_paths
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetNumPaths

    !> HYPRE_Int HYPRE_BoomerAMGSetStrongThreshold(HYPRE_Solver solver, HYPRE_Real strong_threshold)
    function HYPRE_BoomerAMGSetStrongThreshold(solver, strong_threshold) &
        bind(C, name='HYPRE_BoomerAMGSetStrongThreshold') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: strong_threshold
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetStrongThreshold

    !> HYPRE_Int HYPRE_BoomerAMGSetMaxRowSum(HYPRE_Solver solver, HYPRE_Real max_row_sum)
    function HYPRE_BoomerAMGSetMaxRowSum(solver, max_row_sum) &
        bind(C, name='HYPRE_BoomerAMGSetMaxRowSum') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: max_row_sum
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetMaxRowSum

    !> HYPRE_Int HYPRE_BoomerAMGSetMaxLevels(HYPRE_Solver solver, HYPRE_Int max_levels)
    function HYPRE_BoomerAMGSetMaxLevels(solver, max_levels) &
        bind(C, name='HYPRE_BoomerAMGSetMaxLevels') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_levels
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetMaxLevels

    !> HYPRE_Int HYPRE_BoomerAMGSetMaxCoarseSize(HYPRE_Solver solver, HYPRE_Int max_coarse_size)
    function HYPRE_BoomerAMGSetMaxCoarseSize(solver, max_coarse_size) &
        bind(C, name='HYPRE_BoomerAMGSetMaxCoarseSize') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_coarse_size
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetMaxCoarseSize

    !> HYPRE_Int HYPRE_BoomerAMGSetRelaxType(HYPRE_Solver solver, HYPRE_Int relax_type)
    !> Sets the smoother of the down and up cycles and Gaussian elimination (9)
    !> on the coarsest level.
    function HYPRE_BoomerAMGSetRelaxType(solver, relax_type) &
        bind(C, name='HYPRE_BoomerAMGSetRelaxType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: relax_type
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetRelaxType

    !> HYPRE_Int HYPRE_BoomerAMGSetCycleRelaxType(HYPRE_Solver solver, HYPRE_Int relax_type, HYPRE_Int k)
    !> k = 1 down cycle, 2 up cycle, 3 coarsest level.
    function HYPRE_BoomerAMGSetCycleRelaxType(solver, relax_type, k) &
        bind(C, name='HYPRE_BoomerAMGSetCycleRelaxType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: relax_type, k
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetCycleRelaxType

    !> HYPRE_Int HYPRE_BoomerAMGSetCycleType(HYPRE_Solver solver, HYPRE_Int cycle_type)
    !> (1 V-cycle, 2 W-cycle)
    function HYPRE_BoomerAMGSetCycleType(solver, cycle_type) &
        bind(C, name='HYPRE_BoomerAMGSetCycleType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: cycle_type
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetCycleType

    !> HYPRE_Int HYPRE_BoomerAMGSetRelaxOrder(HYPRE_Solver solver, HYPRE_Int relax_order)
    function HYPRE_BoomerAMGSetRelaxOrder(solver, relax_order) &
        bind(C, name='HYPRE_BoomerAMGSetRelaxOrder') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: relax_order
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetRelaxOrder

    !> HYPRE_Int HYPRE_BoomerAMGSetNumSweeps(HYPRE_Solver solver, HYPRE_Int num_sweeps)
    function HYPRE_BoomerAMGSetNumSweeps(solver, num_sweeps) &
        bind(C, name='HYPRE_BoomerAMGSetNumSweeps') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: num_sweeps
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetNumSweeps

    !> HYPRE_Int HYPRE_BoomerAMGSetRelaxWt(HYPRE_Solver solver, HYPRE_Real relax_weight)
    function HYPRE_BoomerAMGSetRelaxWt(solver, relax_weight) &
        bind(C, name='HYPRE_BoomerAMGSetRelaxWt') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: relax_weight
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetRelaxWt

    !> HYPRE_Int HYPRE_BoomerAMGSetTruncFactor(HYPRE_Solver solver, HYPRE_Real trunc_factor)
    function HYPRE_BoomerAMGSetTruncFactor(solver, trunc_factor) &
        bind(C, name='HYPRE_BoomerAMGSetTruncFactor') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: trunc_factor
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetTruncFactor

    !> HYPRE_Int HYPRE_BoomerAMGSetPMaxElmts(HYPRE_Solver solver, HYPRE_Int P_max_elmts)
    function HYPRE_BoomerAMGSetPMaxElmts(solver, p_max_elmts) &
        bind(C, name='HYPRE_BoomerAMGSetPMaxElmts') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: p_max_elmts
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetPMaxElmts

    ! ---- FSAI (HYPRE_parcsr_ls.h, "ParCSR FSAI Solver and Preconditioner") ---
    ! Adaptive factorized sparse approximate inverse: a sparse lower triangular
    ! G with G^T G ~ A^-1. The solve is Richardson's iteration
    ! x <- x + omega G^T G (b - A x); from a zero guess its first step is
    ! x = omega G^T G b.

    !> HYPRE_Int HYPRE_FSAICreate(HYPRE_Solver *solver)
    function HYPRE_FSAICreate(solver) bind(C, name='HYPRE_FSAICreate') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), intent(out) :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_FSAICreate

    !> HYPRE_Int HYPRE_FSAIDestroy(HYPRE_Solver solver)
    function HYPRE_FSAIDestroy(solver) bind(C, name='HYPRE_FSAIDestroy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_FSAIDestroy

    !> HYPRE_Int HYPRE_FSAISetup(HYPRE_Solver solver, HYPRE_ParCSRMatrix A,
    !>   HYPRE_ParVector b, HYPRE_ParVector x); b and x are ignored.
    function HYPRE_FSAISetup(solver, a, b, x) bind(C, name='HYPRE_FSAISetup') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetup

    !> HYPRE_Int HYPRE_FSAISolve(HYPRE_Solver solver, HYPRE_ParCSRMatrix A,
    !>   HYPRE_ParVector b, HYPRE_ParVector x)
    function HYPRE_FSAISolve(solver, a, b, x) bind(C, name='HYPRE_FSAISolve') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISolve

    !> HYPRE_Int HYPRE_FSAISetAlgoType(HYPRE_Solver solver, HYPRE_Int algo_type)
    !> 1: native, 2: OpenMP with dynamic scheduling.
    function HYPRE_FSAISetAlgoType(solver, algo_type) &
        bind(C, name='HYPRE_FSAISetAlgoType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: algo_type
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetAlgoType

    !> HYPRE_Int HYPRE_FSAISetMaxSteps(HYPRE_Solver solver, HYPRE_Int max_steps)
    function HYPRE_FSAISetMaxSteps(solver, max_steps) &
        bind(C, name='HYPRE_FSAISetMaxSteps') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_steps
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetMaxSteps

    !> HYPRE_Int HYPRE_FSAISetMaxStepSize(HYPRE_Solver solver, HYPRE_Int max_step_size)
    function HYPRE_FSAISetMaxStepSize(solver, max_step_size) &
        bind(C, name='HYPRE_FSAISetMaxStepSize') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_step_size
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetMaxStepSize

    !> HYPRE_Int HYPRE_FSAISetKapTolerance(HYPRE_Solver solver, HYPRE_Real kap_tolerance)
    function HYPRE_FSAISetKapTolerance(solver, kap_tolerance) &
        bind(C, name='HYPRE_FSAISetKapTolerance') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: kap_tolerance
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetKapTolerance

    !> HYPRE_Int HYPRE_FSAISetOmega(HYPRE_Solver solver, HYPRE_Real omega)
    function HYPRE_FSAISetOmega(solver, omega) bind(C, name='HYPRE_FSAISetOmega') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: omega
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetOmega

    !> HYPRE_Int HYPRE_FSAISetMaxIterations(HYPRE_Solver solver, HYPRE_Int max_iterations)
    function HYPRE_FSAISetMaxIterations(solver, max_iterations) &
        bind(C, name='HYPRE_FSAISetMaxIterations') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: max_iterations
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetMaxIterations

    !> HYPRE_Int HYPRE_FSAISetEigMaxIters(HYPRE_Solver solver, HYPRE_Int eig_max_iters)
    !> Power-method iterations in the set-up that replace omega by
    !> 1 / lambda_max(G^T G A); 0 keeps the omega that was set.
    function HYPRE_FSAISetEigMaxIters(solver, eig_max_iters) &
        bind(C, name='HYPRE_FSAISetEigMaxIters') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: eig_max_iters
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetEigMaxIters

    !> HYPRE_Int HYPRE_FSAISetTolerance(HYPRE_Solver solver, HYPRE_Real tolerance)
    function HYPRE_FSAISetTolerance(solver, tolerance) &
        bind(C, name='HYPRE_FSAISetTolerance') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: tolerance
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetTolerance

    !> HYPRE_Int HYPRE_FSAISetPrintLevel(HYPRE_Solver solver, HYPRE_Int print_level)
    function HYPRE_FSAISetPrintLevel(solver, print_level) &
        bind(C, name='HYPRE_FSAISetPrintLevel') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: print_level
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetPrintLevel

    !> HYPRE_Int HYPRE_FSAISetZeroGuess(HYPRE_Solver solver, HYPRE_Int zero_guess)
    function HYPRE_FSAISetZeroGuess(solver, zero_guess) &
        bind(C, name='HYPRE_FSAISetZeroGuess') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: zero_guess
      integer(hypre_int) :: ierr
    end function HYPRE_FSAISetZeroGuess


    ! ---- BoomerAMG interpolation vectors (rigid-body modes) -----------------
    ! hypre keeps the array of vectors by pointer; the caller destroys the
    ! vectors after the solver.

    !> HYPRE_Int HYPRE_BoomerAMGSetInterpVectors(HYPRE_Solver, HYPRE_Int num_vectors,
    !>   HYPRE_ParVector *interp_vectors)
    function HYPRE_BoomerAMGSetInterpVectors(solver, n, vectors) bind(C, name='HYPRE_BoomerAMGSetInterpVectors') &
        result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: n
      type(c_ptr), value :: vectors
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetInterpVectors

    !> HYPRE_Int HYPRE_BoomerAMGSetInterpVecVariant(HYPRE_Solver, HYPRE_Int var)
    function HYPRE_BoomerAMGSetInterpVecVariant(solver, v) bind(C, name='HYPRE_BoomerAMGSetInterpVecVariant') &
        result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: v
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetInterpVecVariant

    !> HYPRE_Int HYPRE_BoomerAMGSetInterpVecQMax(HYPRE_Solver, HYPRE_Int q_max)
    function HYPRE_BoomerAMGSetInterpVecQMax(solver, v) bind(C, name='HYPRE_BoomerAMGSetInterpVecQMax') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: v
      integer(hypre_int) :: ierr
    end function HYPRE_BoomerAMGSetInterpVecQMax

    ! ---- MGR (HYPRE_parcsr_ls.h) -------------------------------------------
    ! The level arrays are copied by hypre at the call; the point marker
    ! array is kept by pointer until the solver is destroyed.

    !> HYPRE_Int HYPRE_MGRCreate(HYPRE_Solver *solver)
    function HYPRE_MGRCreate(solver) bind(C, name='HYPRE_MGRCreate') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), intent(out) :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_MGRCreate

    !> HYPRE_Int HYPRE_MGRDestroy(HYPRE_Solver solver)
    function HYPRE_MGRDestroy(solver) bind(C, name='HYPRE_MGRDestroy') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int) :: ierr
    end function HYPRE_MGRDestroy

    !> HYPRE_Int HYPRE_MGRSetup(HYPRE_Solver, HYPRE_ParCSRMatrix A, HYPRE_ParVector b, HYPRE_ParVector x)
    function HYPRE_MGRSetup(solver, a, b, x) bind(C, name='HYPRE_MGRSetup') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetup

    !> HYPRE_Int HYPRE_MGRSolve(HYPRE_Solver, HYPRE_ParCSRMatrix A, HYPRE_ParVector b, HYPRE_ParVector x)
    function HYPRE_MGRSolve(solver, a, b, x) bind(C, name='HYPRE_MGRSolve') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver, a, b, x
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSolve

    !> HYPRE_Int HYPRE_MGRSetCpointsByPointMarkerArray(HYPRE_Solver, HYPRE_Int block_size,
    !>   HYPRE_Int max_num_levels, HYPRE_Int *num_block_coarse_points,
    !>   HYPRE_Int **lvl_block_coarse_indexes, HYPRE_Int *point_marker_array)
    function HYPRE_MGRSetCpointsByPointMarkerArray(solver, block_size, max_num_levels, num_coarse, &
        coarse_indexes, point_marker) bind(C, name='HYPRE_MGRSetCpointsByPointMarkerArray') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: block_size, max_num_levels
      integer(hypre_int), intent(in) :: num_coarse(*)
      type(c_ptr), intent(in) :: coarse_indexes(*)
      type(c_ptr), value :: point_marker
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetCpointsByPointMarkerArray

    !> HYPRE_Int HYPRE_MGRSetNonCpointsToFpoints(HYPRE_Solver, HYPRE_Int flag)
    function HYPRE_MGRSetNonCpointsToFpoints(solver, flag) bind(C, name='HYPRE_MGRSetNonCpointsToFpoints') &
        result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: flag
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetNonCpointsToFpoints

    !> HYPRE_Int HYPRE_MGRSetMaxCoarseLevels(HYPRE_Solver, HYPRE_Int maxlev)
    function HYPRE_MGRSetMaxCoarseLevels(solver, maxlev) bind(C, name='HYPRE_MGRSetMaxCoarseLevels') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: maxlev
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetMaxCoarseLevels

    !> HYPRE_Int HYPRE_MGRSetLevelFRelaxType(HYPRE_Solver, HYPRE_Int *relax_type)
    function HYPRE_MGRSetLevelFRelaxType(solver, v) bind(C, name='HYPRE_MGRSetLevelFRelaxType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(in) :: v(*)
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetLevelFRelaxType

    !> HYPRE_Int HYPRE_MGRSetCoarseGridMethod(HYPRE_Solver, HYPRE_Int *cg_method)
    function HYPRE_MGRSetCoarseGridMethod(solver, v) bind(C, name='HYPRE_MGRSetCoarseGridMethod') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(in) :: v(*)
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetCoarseGridMethod

    !> HYPRE_Int HYPRE_MGRSetLevelInterpType(HYPRE_Solver, HYPRE_Int *interp_type)
    function HYPRE_MGRSetLevelInterpType(solver, v) bind(C, name='HYPRE_MGRSetLevelInterpType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(in) :: v(*)
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetLevelInterpType

    !> HYPRE_Int HYPRE_MGRSetLevelRestrictType(HYPRE_Solver, HYPRE_Int *restrict_type)
    function HYPRE_MGRSetLevelRestrictType(solver, v) bind(C, name='HYPRE_MGRSetLevelRestrictType') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(in) :: v(*)
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetLevelRestrictType

    !> HYPRE_Int HYPRE_MGRSetLevelNumRelaxSweeps(HYPRE_Solver, HYPRE_Int *nsweeps)
    function HYPRE_MGRSetLevelNumRelaxSweeps(solver, v) bind(C, name='HYPRE_MGRSetLevelNumRelaxSweeps') &
        result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), intent(in) :: v(*)
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetLevelNumRelaxSweeps

    !> HYPRE_Int HYPRE_MGRSetFSolver(HYPRE_Solver, HYPRE_PtrToParSolverFcn solve,
    !>   HYPRE_PtrToParSolverFcn setup, HYPRE_Solver fsolver)
    function HYPRE_MGRSetFSolver(solver, solve, setup, fsolver) bind(C, name='HYPRE_MGRSetFSolver') result(ierr)
      import :: c_ptr, c_funptr, hypre_int
      type(c_ptr), value :: solver
      type(c_funptr), value :: solve, setup
      type(c_ptr), value :: fsolver
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetFSolver

    !> HYPRE_Int HYPRE_MGRSetCoarseSolver(HYPRE_Solver, HYPRE_PtrToParSolverFcn solve,
    !>   HYPRE_PtrToParSolverFcn setup, HYPRE_Solver coarse_grid_solver)
    function HYPRE_MGRSetCoarseSolver(solver, solve, setup, csolver) bind(C, name='HYPRE_MGRSetCoarseSolver') &
        result(ierr)
      import :: c_ptr, c_funptr, hypre_int
      type(c_ptr), value :: solver
      type(c_funptr), value :: solve, setup
      type(c_ptr), value :: csolver
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetCoarseSolver

    !> HYPRE_Int HYPRE_MGRSetMaxIter(HYPRE_Solver, HYPRE_Int max_iter)
    function HYPRE_MGRSetMaxIter(solver, n) bind(C, name='HYPRE_MGRSetMaxIter') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: n
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetMaxIter

    !> HYPRE_Int HYPRE_MGRSetTol(HYPRE_Solver, HYPRE_Real tol)
    function HYPRE_MGRSetTol(solver, tol) bind(C, name='HYPRE_MGRSetTol') result(ierr)
      import :: c_ptr, hypre_int, hypre_real
      type(c_ptr), value :: solver
      real(hypre_real), value :: tol
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetTol

    !> HYPRE_Int HYPRE_MGRSetPrintLevel(HYPRE_Solver, HYPRE_Int print_level)
    function HYPRE_MGRSetPrintLevel(solver, n) bind(C, name='HYPRE_MGRSetPrintLevel') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: n
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetPrintLevel

    !> HYPRE_Int HYPRE_MGRSetPMaxElmts(HYPRE_Solver, HYPRE_Int P_max_elmts)
    function HYPRE_MGRSetPMaxElmts(solver, n) bind(C, name='HYPRE_MGRSetPMaxElmts') result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: n
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetPMaxElmts

    !> HYPRE_Int HYPRE_MGRSetMaxGlobalSmoothIters(HYPRE_Solver, HYPRE_Int smooth_iter)
    function HYPRE_MGRSetMaxGlobalSmoothIters(solver, n) bind(C, name='HYPRE_MGRSetMaxGlobalSmoothIters') &
        result(ierr)
      import :: c_ptr, hypre_int
      type(c_ptr), value :: solver
      integer(hypre_int), value :: n
      integer(hypre_int) :: ierr
    end function HYPRE_MGRSetMaxGlobalSmoothIters

  end interface

end module hypre_c
