!> Interfaces to amg_cycle.c: geoblock's own V-cycle over a BoomerAMG
!> hierarchy, with its own l1 Gauss-Seidel sweep (see that file). The
!> handles are hypre's (HYPRE_Solver, HYPRE_ParVector), passed by value.
module amg_cycle_c
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int
  implicit none
  private
  public :: gb_amg_cycle_fits, gb_amg_cycle, gb_amg_refresh_fine

  interface
    !> 1 when the set-up hierarchy of `solver` is one gb_amg_cycle
    !> reproduces (l1 Gauss-Seidel, V-cycle, ...), else 0.
    function gb_amg_cycle_fits(solver) bind(C, name='gb_amg_cycle_fits') result(fits)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver
      integer(c_int) :: fits
    end function gb_amg_cycle_fits

    !> x <- one V-cycle on A x = b from x = 0; hypre's error flag.
    function gb_amg_cycle(solver, b, x) bind(C, name='gb_amg_cycle') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver, b, x
      integer(c_int) :: ierr
    end function gb_amg_cycle

    !> The finest level of solver's hierarchy becomes a (same rows), with
    !> its l1 norms; the coarse levels stay. 0 on success.
    function gb_amg_refresh_fine(solver, a) bind(C, name='gb_amg_refresh_fine') result(ierr)
      import :: c_ptr, c_int
      type(c_ptr), value :: solver, a
      integer(c_int) :: ierr
    end function gb_amg_refresh_fine
  end interface
end module amg_cycle_c
