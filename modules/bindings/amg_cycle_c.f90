!> Interfaces to amg_cycle.c: geoblock's own V-cycle over a BoomerAMG
!> hierarchy, with its own l1 Gauss-Seidel sweep, and its level values in
!> single precision (see that file). The handles are hypre's
!> (HYPRE_Solver, HYPRE_ParVector, HYPRE_ParCSRMatrix) and amg_cycle.c's
!> (compact), passed by value.
module amg_cycle_c
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int
  implicit none
  private
  public :: gb_amg_cycle_fits, gb_amg_cycle, gb_amg_refresh_fine, gb_amg_regalerkin
  public :: gb_amg_compact_create, gb_amg_compact_free, gb_amg_fine_narrowed, gb_amg_fine_product

  interface
    !> 1 when the set-up hierarchy of `solver` is one gb_amg_cycle
    !> reproduces (l1 Gauss-Seidel, V-cycle, ...), else 0.
    function gb_amg_cycle_fits(solver) bind(C, name='gb_amg_cycle_fits') result(fits)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver
      integer(c_int) :: fits
    end function gb_amg_cycle_fits

    !> x <- one V-cycle on A x = b from x = 0, with the single-precision
    !> values of compact where it is not null; hypre's error flag.
    function gb_amg_cycle(solver, compact, b, x) bind(C, name='gb_amg_cycle') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver, compact, b, x
      integer(c_int) :: ierr
    end function gb_amg_cycle

    !> The finest level of solver's hierarchy becomes a (same rows), with
    !> its l1 norms and, where compact is not null, its values in single
    !> precision in place; the coarse levels stay. 0 on success.
    function gb_amg_refresh_fine(solver, compact, a) bind(C, name='gb_amg_refresh_fine') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver, compact, a
      integer(c_int) :: ierr
    end function gb_amg_refresh_fine

    !> The coarse levels of solver's hierarchy anew for its finest level's
    !> new matrix a (same rows), with the last set-up's interpolation:
    !> A_l+1 = P_l^T A_l P_l, their l1 norms, the coarsest level's Gaussian
    !> elimination. Single-precision values are gone afterwards (make them
    !> with gb_amg_compact_create). 0 on success. Collective.
    function gb_amg_regalerkin(solver, a) bind(C, name='gb_amg_regalerkin') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver, a
      integer(c_int) :: ierr
    end function gb_amg_regalerkin

    !> The values of every level of solver's hierarchy but the coarsest in
    !> single precision, in place in hypre's arrays (null: no memory or one
    !> level; a level with a value out of single precision's range keeps
    !> its double ones); old (the last set-up's compact, or null) is reused
    !> and not to be used again. Only gb_amg_cycle with compact may run the
    !> hierarchy afterwards, and the finest level's matrix (the caller's IJ
    !> matrix) holds floats where gb_amg_fine_narrowed says so.
    function gb_amg_compact_create(solver, old) bind(C, name='gb_amg_compact_create') result(compact)
      import :: c_ptr
      type(c_ptr), value :: solver, old
      type(c_ptr) :: compact
    end function gb_amg_compact_create

    !> 1 when compact holds the finest level's values as floats in place
    !> (its doubles are gone), else 0.
    function gb_amg_fine_narrowed(compact) bind(C, name='gb_amg_fine_narrowed') result(yes)
      import :: c_ptr, c_int
      type(c_ptr), value :: compact
      integer(c_int) :: yes
    end function gb_amg_fine_narrowed

    !> y = A x for the hierarchy's finest level a (ParCSR matrix and
    !> vectors) with the values compact holds (floats, or doubles on a rank
    !> that kept them); 1 when compact is null. Collective.
    function gb_amg_fine_product(compact, a, x, y) bind(C, name='gb_amg_fine_product') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: compact, a, x, y
      integer(c_int) :: ierr
    end function gb_amg_fine_product

    !> Frees compact (null: nothing).
    subroutine gb_amg_compact_free(compact) bind(C, name='gb_amg_compact_free')
      import :: c_ptr
      type(c_ptr), value :: compact
    end subroutine gb_amg_compact_free
  end interface
end module amg_cycle_c
