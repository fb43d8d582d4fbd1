!> Unit tests of block_precon_t (the general framework z = F~ S~^-1 G~ r) on
!> a 3 x 3 "arrow" block system shaped like three-field Biot:
!>
!>     A = [ K     0     -Q ]      K, M, P symmetric positive definite,
!>         [ 0     M     -B ]      Q, B rectangular, c = 0.7,
!>         [ Q^T   c B^T  P ]
!>
!> Every rank builds the same dense blocks, takes its contiguous rows of each
!> field and computes the exact pieces densely with LAPACK: F1 = K^-1 Q,
!> F2 = M^-1 B, S = P + Q^T F1 + c B^T F2. The diagonal preconditioners are
!> MUMPS factorizations of K, M and S, so that with exact factors the block
!> LDU preconditioner is A^-1 and FGMRES stops after one iteration, and the
!> other configurations have iteration counts known from theory:
!> - F only or G only (exact): A M^-1 is block unit triangular (in a similar
!>   basis) with a nilpotent part of degree 2, hence 2 iterations;
!> - ldu_cheap (G with Jacobi inside) and an inexact explicit F: A M^-1 =
!>   G^-1 G~, resp. similar to F^-1 F~, is again unit triangular with a
!>   nilpotent part of degree 2, so also 2 iterations, on any number of ranks;
!> - block diagonal: the eigenvalues of A D^-1 other than 1 are the roots of
!>   (mu + 1) l^2 - (mu + 2) l + (mu + 1) = 0 for every generalized eigenvalue
!>   mu of (Q^T K^-1 Q + c B^T M^-1 B, P), so at most 2 n3 + 1 distinct values
!>   (Murphy, Golub, Wathen, SIAM J. Sci. Comput. 21, 2000, give 3 when P = 0).
!> Any number of ranks (each should own rows of every field: up to 8).
program test_block_precon
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t, to_csr
  use block_matrix, only: block_matrix_t
  use block_precon, only: block_precon_t
  use precon, only: precon_t
  use jacobi_precon, only: jacobi_precon_t
  use mumps_solver, only: mumps_solver_t
  use fgmres, only: fgmres_t
  use krylov, only: solve_info_t
  use assertions, only: test_suite_t, max_rel_diff
  implicit none

  interface
    subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: rp
      character, intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(rp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: info
    end subroutine dposv
    subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: rp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(rp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv
  end interface

  integer, parameter :: n1 = 30, n2 = 20, n3 = 8, nt = n1 + n2 + n3
  integer, parameter :: gbase(3) = [0, n1, n1 + n2]     !< position of each field in a global vector
  real(rp), parameter :: cc = 0.7_rp, rtol = 1.0e-10_rp, sol_tol = 1.0e-8_rp

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(error_status_t) :: st
  type(index_map_t), target :: maps(3), cmap
  type(block_matrix_t), target :: a, a0
  type(csr_matrix_t) :: smat, smat0, mono
  type(csr_matrix_t) :: mf
  type(block_precon_t) :: bp, bq
  type(fgmres_t) :: gmres
  type(mumps_solver_t) :: direct
  class(precon_t), allocatable :: own
  real(rp) :: dk(n1, n1), dm(n2, n2), dp(n3, n3), dq(n1, n3), db(n2, n3)
  real(rp) :: df1(n1, n3), df2(n2, n3), ds(n3, n3), df1_cut(n1, n3), da(nt, nt), bg(nt), xg(nt)
  integer(gp), allocatable :: off(:,:)            !< (0:np, 3) first global row of each rank, per field
  real(rp), allocatable :: b(:), xref(:), xref0(:), x(:), v(:), za(:), zb(:)
  integer :: its, its_cheap, i, n_keep
  integer(ip) :: n_loc
  real(rp) :: err, res, thr
  real(rp), allocatable :: mags(:)
  integer(gp) :: nnz_f, nnz_g
  type(block_matrix_t), target :: ac                 !< section 10: every block coupled
  type(csr_matrix_t) :: sm(3)                        !< its exact Schur complements
  real(rp) :: c23(n2, n3), c32(n3, n2)               !< its reduced couplings

  call comm%init_world()
  call suite%init('block_precon', comm)

  ! ---- dense blocks and the exact pieces (the same on every rank) ----
  call make_spd(dk, 5, 1.0_rp)
  call make_spd(dm, 3, 2.0_rp)
  call make_spd(dp, 4, 0.5_rp)
  call make_rect(dq, 3, 5)
  call make_rect(db, 2, 7)
  df1 = dq
  call spd_solve(dk, df1)
  df2 = db
  call spd_solve(dm, df2)
  ds = dp + matmul(transpose(dq), df1) + cc * matmul(transpose(db), df2)
  ds = 0.5_rp * (ds + transpose(ds))
  da = 0.0_rp
  da(1:n1, 1:n1) = dk
  da(1:n1, n1+n2+1:nt) = -dq
  da(n1+1:n1+n2, n1+1:n1+n2) = dm
  da(n1+1:n1+n2, n1+n2+1:nt) = -db
  da(n1+n2+1:nt, 1:n1) = transpose(dq)
  da(n1+n2+1:nt, n1+1:n1+n2) = cc * transpose(db)
  da(n1+n2+1:nt, n1+n2+1:nt) = dp
  do i = 1, nt
    bg(i) = sin(0.71_rp * i) + 0.3_rp * cos(1.3_rp * i * i)
  end do
  call dense_solve(da, bg, xg)

  ! ---- distribution: contiguous rows of every field, full ghosting ----
  allocate(off(0:comm%size, 3))
  do i = 1, 3
    call split(field_size(i), off(:, i))
    call build_map(i)
  end do
  call a%init([(int(off(comm%rank + 1, i) - off(comm%rank, i), ip), i = 1, 3)])
  call set_block(a, 1, 1, dk)
  call set_block(a, 1, 3, -dq)
  call set_block(a, 2, 2, dm)
  call set_block(a, 2, 3, -db)
  call set_block(a, 3, 1, transpose(dq))
  call set_block(a, 3, 2, cc * transpose(db))
  call set_block(a, 3, 3, dp)
  call a%finalize_assembly()
  call dense_csr(ds, 3, 3, smat)
  n_loc = a%n_owned()
  allocate(b(n_loc), xref(n_loc), xref0(n_loc), x(n_loc), v(n_loc), za(n_loc), zb(n_loc))
  call scatter(bg, b)
  call scatter(xg, xref)
  call a%apply(xref, x)
  call suite%assert_true(max_rel_diff(comm, x, b) < 1.0e-12_rp, 'block matrix: A x_dense = b (assembly of the 7 blocks)')

  ! the monolithic matrix through MUMPS gives the dense solution
  call a%monolithic(cmap, mono)
  call direct%setup(mono, st)
  call suite%assert_true(st%ok(), 'MUMPS factorizes the monolithic matrix: '//trim(st%msg))
  call direct%solve(b, x)
  call suite%assert_true(max_rel_diff(comm, x, xref) < sol_tol, 'MUMPS on the monolithic matrix = dense solve')

  call gmres%init(comm, rtol=rtol, atol=0.0_rp, max_iter=200, restart=50, status=st)
  call suite%assert_true(st%ok(), 'fgmres init')

  ! ---- 1. implicit LDU: M = A^-1, one iteration ----
  call new_precon(bp, 'ldu implicit', a, smat)
  call bp%set_implicit(3, 1, 1)
  call bp%set_implicit(3, 2, 2)
  call bp%set_implicit(1, 3, 1)
  call bp%set_implicit(2, 3, 2)
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 1, 'ldu implicit: 1 iteration')
  call suite%assert_true(res <= rtol, 'ldu implicit: converged')
  call suite%assert_true(bp%n_apply == its, 'ldu implicit: one application per iteration')
  call suite%assert_true(bp%fused(1) .and. bp%fused(2) .and. .not. bp%fused(3), &
                         'ldu implicit: rows 1 and 2 are fused, row 3 is not')
  call suite%assert_true(err < sol_tol, 'ldu implicit: solution = dense solve')
  call direct%solve(b, za)
  call suite%assert_true(max_rel_diff(comm, x, za) < sol_tol, 'ldu implicit: solution = MUMPS on the monolithic matrix')
  call bp%free()

  ! ---- 2. explicit LDU with the exact factors: one iteration ----
  call new_precon(bp, 'ldu explicit', a, smat)
  call explicit_block(df1, 1, 3, mf)
  call bp%set_explicit(1, 3, 1.0_rp, mf)
  call suite%assert_true(.not. allocated(mf%val), 'set_explicit moves the matrix in (the caller''s is empty)')
  call explicit_block(df2, 2, 3, mf)
  call bp%set_explicit(2, 3, 1.0_rp, mf)
  call explicit_block(transpose(df1), 3, 1, mf)
  call bp%set_explicit(3, 1, -1.0_rp, mf)
  call explicit_block(transpose(df2), 3, 2, mf)
  call bp%set_explicit(3, 2, -cc, mf)
  nnz_f = int(count(df1 /= 0.0_rp) + count(df2 /= 0.0_rp), gp)
  nnz_g = bp%nnz_explicit('G')
  call suite%assert_true(bp%nnz_explicit('F') == nnz_f, 'ldu explicit: nnz_explicit counts the F blocks')
  call suite%assert_true(nnz_g == nnz_f, 'ldu explicit: nnz_explicit counts the G blocks')
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 1, 'ldu explicit: 1 iteration')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'ldu explicit: converged to the dense solution')
  ! changing only the scale of an explicit block (no matrix passed): G(3,2) = -c F2^T needs -c
  call bp%set_explicit(3, 2, 0.0_rp)
  bp%label = 'ldu explicit, G(3,2) = 0'
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_true(its > 1, 'ldu explicit with G(3,2) scaled to zero: more than 1 iteration')
  call bp%set_explicit(3, 2, -cc)
  bp%label = 'ldu explicit again'
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 1, 'ldu explicit, scale of G(3,2) restored: 1 iteration')
  call bp%free()

  ! ---- 3. mixed: F(1,3), G(3,1) explicit; F(2,3), G(3,2) implicit ----
  call new_precon(bp, 'ldu mixed', a, smat)
  call explicit_block(df1, 1, 3, mf)
  call bp%set_explicit(1, 3, 1.0_rp, mf)
  call bp%set_implicit(2, 3, 2)
  call explicit_block(transpose(df1), 3, 1, mf)
  call bp%set_explicit(3, 1, -1.0_rp, mf)
  call bp%set_implicit(3, 2, 2)
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 1, 'ldu mixed: 1 iteration')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'ldu mixed: converged to the dense solution')
  call suite%assert_true(.not. bp%fused(1) .and. bp%fused(2), 'ldu mixed: row 1 not fused, row 2 fused')
  call bp%free()

  ! ---- 4. block triangular with the exact Schur complement: two iterations ----
  call new_precon(bp, 'upper implicit', a, smat)
  call bp%set_implicit(1, 3, 1)
  call bp%set_implicit(2, 3, 2)
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 2, 'upper only (F implicit): 2 iterations')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'upper only: converged to the dense solution')
  call bp%free()
  call new_precon(bp, 'lower implicit', a, smat)
  call bp%set_implicit(3, 1, 1)
  call bp%set_implicit(3, 2, 2)
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_equal_int(its, 2, 'lower only (G implicit): 2 iterations')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'lower only: converged to the dense solution')
  call bp%free()

  ! ---- 5. block diagonal: at most 2 n3 + 1 iterations (see the header) ----
  call new_precon(bp, 'diagonal', a, smat)
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_true(its > 2 .and. its <= 2 * n3 + 1, 'diagonal: more than 2, at most 2 n3 + 1 iterations')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'diagonal: converged to the dense solution')
  call bp%free()

  ! with P = 0 (S = Q^T K^-1 Q + c B^T M^-1 B) the eigenvalues of A D^-1 are 1
  ! and the roots of l^2 - l + 1: 3 iterations (Murphy, Golub and Wathen)
  call a0%init([(int(off(comm%rank + 1, i) - off(comm%rank, i), ip), i = 1, 3)])
  call set_block(a0, 1, 1, dk)
  call set_block(a0, 1, 3, -dq)
  call set_block(a0, 2, 2, dm)
  call set_block(a0, 2, 3, -db)
  call set_block(a0, 3, 1, transpose(dq))
  call set_block(a0, 3, 2, cc * transpose(db))
  call dense_csr(ds - dp, 3, 3, smat0)
  da(n1+n2+1:nt, n1+n2+1:nt) = 0.0_rp
  call dense_solve(da, bg, xg)
  call scatter(xg, xref0)
  call new_precon(bp, 'diagonal, P = 0', a0, smat0)
  call run(bp, a0, xref0, its, res, err, x)
  call suite%assert_true(its <= 3, 'diagonal, P = 0: at most 3 iterations')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'diagonal, P = 0: converged to the dense solution')
  call bp%free()
  call new_precon(bp, 'ldu implicit, P = 0', a0, smat0)
  call bp%set_implicit(3, 1, 1)
  call bp%set_implicit(3, 2, 2)
  call bp%set_implicit(1, 3, 1)
  call bp%set_implicit(2, 3, 2)
  call run(bp, a0, xref0, its, res, err, x)
  call suite%assert_equal_int(its, 1, 'ldu implicit, P = 0 (no block (3,3)): 1 iteration')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'ldu implicit, P = 0: converged to the dense solution')
  call bp%free()
  call smat0%free()
  call a0%free()

  ! ---- 6. ldu_cheap: Jacobi of K and M inside G, exact F (implicit) ----
  call new_precon(bp, 'ldu_cheap', a, smat)
  call own_jacobi(1, own)
  call bp%set_implicit(3, 1, 0, own)
  call suite%assert_true(.not. allocated(own), 'set_implicit moves the own preconditioner in')
  call own_jacobi(2, own)
  call bp%set_implicit(3, 2, 0, own)
  call bp%set_implicit(1, 3, 1)
  call bp%set_implicit(2, 3, 2)
  call run(bp, a, xref, its_cheap, res, err, x)
  call suite%assert_true(its_cheap > 1 .and. its_cheap <= 40, 'ldu_cheap: more than 1, at most 40 iterations')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'ldu_cheap: converged to the dense solution')
  ! A M^-1 = G^-1 G~ is unit lower triangular: 2 iterations whatever the ranks
  call suite%assert_equal_int(its_cheap, 2, 'ldu_cheap: 2 iterations (A M^-1 = G^-1 G~), on any number of ranks')
  call bp%free()

  ! ---- 7. the fused row and the explicit (non-fused) row give the same z ----
  do i = 1, size(v)
    v(i) = cos(0.37_rp * i + 0.1_rp * comm%rank) + 0.5_rp
  end do
  call new_precon(bp, 'ldu implicit', a, smat)
  call bp%set_implicit(3, 1, 1)
  call bp%set_implicit(3, 2, 2)
  call bp%set_implicit(1, 3, 1)
  call bp%set_implicit(2, 3, 2)
  call bp%apply(v, za)
  call new_precon(bq, 'ldu, F(1,3) explicit', a, smat)
  call bq%set_implicit(3, 1, 1)
  call bq%set_implicit(3, 2, 2)
  call explicit_block(df1, 1, 3, mf)
  call bq%set_explicit(1, 3, 1.0_rp, mf)
  call bq%set_implicit(2, 3, 2)
  call bq%apply(v, zb)
  call suite%assert_true(bp%fused(1) .and. .not. bq%fused(1), 'fused vs explicit: row 1 fused in one, not in the other')
  call suite%assert_true(max_rel_diff(comm, za, zb) < 1.0e-10_rp, 'fused vs explicit F(1,3): the same z to 1e-10')
  call a%apply(za, zb)
  call suite%assert_true(max_rel_diff(comm, zb, v) < 1.0e-10_rp, 'fused: A z = v (the preconditioner is A^-1)')
  ! a second application (plan and caches reset) gives the same z; not to
  ! the bit: MUMPS' distributed solve is not bitwise reproducible from one
  ! call to the next on 3 ranks (differences of 1e-17 seen with K)
  call bq%apply(v, zb)
  call bq%apply(v, x)
  err = max_rel_diff(comm, zb, x)
  call suite%assert_true(err < 1.0e-14_rp, 'repeated application: the same z to round-off')
  err = max_rel_diff(comm, za, x)
  call suite%assert_true(err < 1.0e-10_rp, 'repeated application: the same z as the fused one')
  call bp%free()
  call bq%free()

  ! ---- 8. inexact explicit F1 (the smaller half of its entries dropped) ----
  mags = pack(abs(df1), df1 /= 0.0_rp)
  call sort_reals(mags)
  n_keep = size(mags) - size(mags) / 2
  thr = mags(size(mags) / 2)
  df1_cut = merge(df1, 0.0_rp, abs(df1) > thr)
  call new_precon(bp, 'ldu explicit, F1 cut', a, smat)
  call explicit_block(df1_cut, 1, 3, mf)
  call bp%set_explicit(1, 3, 1.0_rp, mf)
  call explicit_block(df2, 2, 3, mf)
  call bp%set_explicit(2, 3, 1.0_rp, mf)
  call explicit_block(transpose(df1), 3, 1, mf)
  call bp%set_explicit(3, 1, -1.0_rp, mf)
  call explicit_block(transpose(df2), 3, 2, mf)
  call bp%set_explicit(3, 2, -cc, mf)
  call suite%assert_true(bp%f(1, 3)%m%global_nnz() == int(n_keep, gp), 'F1 cut keeps the larger half of the entries')
  call run(bp, a, xref, its, res, err, x)
  call suite%assert_true(its > 1, 'inexact F1: more iterations than the exact factor (1)')
  ! A M^-1 is similar to S F^-1 F~ S^-1, unit upper triangular: 2 iterations
  call suite%assert_equal_int(its, 2, 'inexact F1: 2 iterations (A M^-1 ~ F^-1 F~)')
  call suite%assert_true(res <= rtol .and. err < sol_tol, 'inexact F1: converged to the dense solution')
  call bp%free()

  ! ---- 9. an implicit factor with its own coupling matrix in place of A_ij ----
  call new_precon(bp, 'ldu implicit', a, smat)
  call all_implicit(bp)
  call bp%apply(v, za)
  call new_precon(bq, 'ldu implicit, own couplings equal to A_13 and A_31', a, smat)
  call explicit_block(transpose(dq), 3, 1, mf)
  call bq%set_implicit(3, 1, 1, coupling=mf)
  call suite%assert_true(.not. allocated(mf%val), 'set_implicit moves the coupling in')
  call bq%set_implicit(3, 2, 2)
  call explicit_block(-dq, 1, 3, mf)
  call bq%set_implicit(1, 3, 1, coupling=mf)
  call bq%set_implicit(2, 3, 2)
  call bq%apply(v, zb)
  call suite%assert_true(bq%fused(1), 'own coupling: the row stays fused')
  call suite%assert_true(max_rel_diff(comm, za, zb) < 1.0e-10_rp, 'own couplings equal to A_13, A_31: the same z to 1e-10')
  ! the coupling is used: F(1,3) built on 2 A_13 is F1 doubled, z_1 changes
  ! by F1 w_3 exactly (w_3 is the same, F(1,3) only feeds row 1)
  call explicit_block(-2.0_rp * dq, 1, 3, mf)
  call bq%set_implicit(1, 3, 1, coupling=mf)
  call bq%apply(v, zb)
  call suite%assert_true(max_rel_diff(comm, za, zb) > 1.0e-3_rp, 'own coupling 2 A_13: z differs')
  call explicit_block(df1, 1, 3, mf)
  call bp%set_explicit(1, 3, 2.0_rp, mf)
  call bp%apply(v, za)
  call suite%assert_true(max_rel_diff(comm, za, zb) < 1.0e-10_rp, 'own coupling 2 A_13 = explicit F(1,3) = 2 F1, to 1e-10')
  call run(bq, a, xref, its, res, err, x)
  call suite%assert_true(its > 1 .and. res <= rtol .and. err < sol_tol, &
                         'own coupling 2 A_13: more than 1 iteration, converged to the dense solution')
  call bp%free()
  call bq%free()

  ! ---- 10. every block coupled (a chain 1 - 2 - 3 as the fracture flow's
  ! (t, u, p)): the substitutions with the exact Schur complements
  ! S_2 = A_22 - A_21 A_11^-1 A_12, S_3 = A_33 - [A_31 A_32] A_12,12^-1 [A_13; A_23]
  ! and the reduced couplings A_23 - A_21 A_11^-1 A_13, A_32 - A_31 A_11^-1 A_12
  ! are A^-1: one iteration. (Applying F(1,2) to w_2 and G(3,2) to r_2
  ! loses F(1,2) F(2,3) and G(3,2) G(2,1): checked to need more.)
  block
    real(rp) :: dc(nt, nt), e(nt, nt), s2(n2, n2), s3(n3, n3)
    real(rp) :: a11i_12(n1, n2), a11i_13(n1, n3), lead(n1 + n2, n1 + n2), lead_i(n1 + n2, n3)
    integer :: f, g, r0, r1, c0, c1
    integer, parameter :: lo(3) = [1, n1 + 1, n1 + n2 + 1], hi(3) = [n1, n1 + n2, nt]
    dc = da                                    ! as section 5 left it (A_33 = 0)
    call make_rect(e, 5, 11)
    dc(1:n1, n1+1:n1+n2) = 0.3_rp * e(1:n1, 1:n2)                 ! A_12
    dc(n1+1:n1+n2, 1:n1) = 0.2_rp * transpose(e(1:n1, n2+1:2*n2))  ! A_21 (not A_12^T)
    dc(n1+1:n1+n2, n1+n2+1:nt) = -db                              ! A_23
    a11i_12 = dc(1:n1, n1+1:n1+n2)
    call dense_solve_many(dc(1:n1, 1:n1), a11i_12)
    a11i_13 = dc(1:n1, n1+n2+1:nt)
    call dense_solve_many(dc(1:n1, 1:n1), a11i_13)
    s2 = dc(n1+1:n1+n2, n1+1:n1+n2) - matmul(dc(n1+1:n1+n2, 1:n1), a11i_12)
    c23 = dc(n1+1:n1+n2, n1+n2+1:nt) - matmul(dc(n1+1:n1+n2, 1:n1), a11i_13)
    c32 = dc(n1+n2+1:nt, n1+1:n1+n2) - matmul(dc(n1+n2+1:nt, 1:n1), a11i_12)
    lead = dc(1:n1+n2, 1:n1+n2)
    lead_i = dc(1:n1+n2, n1+n2+1:nt)
    call dense_solve_many(lead, lead_i)
    s3 = dc(n1+n2+1:nt, n1+n2+1:nt) - matmul(dc(n1+n2+1:nt, 1:n1+n2), lead_i)
    call ac%init([(int(off(comm%rank + 1, f) - off(comm%rank, f), ip), f = 1, 3)])
    do f = 1, 3
      do g = 1, 3
        r0 = lo(f); r1 = hi(f); c0 = lo(g); c1 = hi(g)
        call set_block(ac, f, g, dc(r0:r1, c0:c1))
      end do
    end do
    call ac%finalize_assembly()
    call dense_csr(dc(1:n1, 1:n1), 1, 1, sm(1))
    call dense_csr(s2, 2, 2, sm(2))
    call dense_csr(s3, 3, 3, sm(3))
    call dense_solve(dc, bg, xg)
    call scatter(xg, xref0)
    call chain_precon(bp, .true.)
    call run(bp, ac, xref0, its, res, err, x)
    call suite%assert_equal_int(its, 1, 'all blocks coupled, exact Schur complements and reduced couplings: 1 iteration')
    call suite%assert_true(res <= rtol .and. err < sol_tol, 'all blocks coupled: converged to the dense solution')
    call suite%assert_true(bp%fused(1) .and. bp%fused(2), 'all blocks coupled: rows 1 and 2 fused (S_i applied once)')
    call bp%free()
    ! the chain products matter: without the reduced couplings (A_23, A_32
    ! as they are) the preconditioner is no longer A^-1
    call chain_precon(bp, .false.)
    call run(bp, ac, xref0, its, res, err, x)
    call suite%assert_true(its > 1 .and. res <= rtol, 'all blocks coupled, plain A_23 and A_32: more than 1 iteration')
    call bp%free()
    do f = 1, 3
      call sm(f)%free()
    end do
    call ac%free()
  end block

  call direct%free()
  call mono%free()
  call smat%free()
  call a%free()
  call suite%finish()

contains

  !> The chain test's preconditioner: S_i by MUMPS (general), every factor
  !> implicit; reduced: F(2,3) and G(3,2) on the reduced couplings.
  subroutine chain_precon(p, reduced)
    type(block_precon_t), intent(inout) :: p
    logical, intent(in) :: reduced
    type(csr_matrix_t) :: cm
    integer :: f
    call p%init(ac, merge('chain, reduced couplings', 'chain, plain couplings  ', reduced))
    do f = 1, 3
      block
        type(mumps_solver_t), allocatable :: ms
        type(error_status_t) :: s
        allocate(ms)
        call ms%setup(sm(f), s, symmetric=.false.)
        if (.not. s%ok()) error stop 'test_block_precon: MUMPS failed on a Schur complement'
        call move_alloc(ms, p%s(f)%p)
      end block
    end do
    call p%set_implicit(1, 2, 1)
    call p%set_implicit(1, 3, 1)
    call p%set_implicit(2, 1, 1)
    call p%set_implicit(3, 1, 1)
    if (reduced) then
      call explicit_block(c23, 2, 3, cm)
      call p%set_implicit(2, 3, 2, coupling=cm)
      call explicit_block(c32, 3, 2, cm)
      call p%set_implicit(3, 2, 2, coupling=cm)
    else
      call p%set_implicit(2, 3, 2)
      call p%set_implicit(3, 2, 2)
    end if
  end subroutine chain_precon

  integer function field_size(f)
    integer, intent(in) :: f
    integer, parameter :: nf(3) = [n1, n2, n3]
    field_size = nf(f)
  end function field_size

  !> Symmetric, strictly diagonally dominant with a positive diagonal (hence
  !> SPD): a chain plus the pairs with i + j a multiple of seed.
  subroutine make_spd(d, seed, shift)
    real(rp), intent(out) :: d(:,:)
    integer, intent(in) :: seed
    real(rp), intent(in) :: shift
    integer :: i, j
    d = 0.0_rp
    do j = 1, size(d, 2)
      do i = 1, size(d, 1)
        if (i /= j .and. (abs(i - j) == 1 .or. mod(i + j, seed) == 0)) d(i, j) = -(0.2_rp + 0.01_rp * mod(i * j, 7))
      end do
    end do
    do i = 1, size(d, 1)
      d(i, i) = sum(abs(d(i, :))) + shift + 0.05_rp * i
    end do
  end subroutine make_spd

  !> A dense-ish rectangular block: about three quarters of the entries.
  subroutine make_rect(d, s1, s2)
    real(rp), intent(out) :: d(:,:)
    integer, intent(in) :: s1, s2
    integer :: i, j
    d = 0.0_rp
    do j = 1, size(d, 2)
      do i = 1, size(d, 1)
        if (mod(s1 * i + s2 * j, 4) /= 0) d(i, j) = sin(0.37_rp * s1 * i + 0.91_rp * j) + 0.2_rp
      end do
    end do
  end subroutine make_rect

  !> x = d^-1 x for a general square d (LAPACK dgesv), many right-hand sides.
  subroutine dense_solve_many(d, x)
    real(rp), intent(in) :: d(:,:)
    real(rp), intent(inout) :: x(:,:)
    real(rp) :: lu(size(d, 1), size(d, 2))
    integer :: ipiv(size(d, 1)), info
    lu = d
    call dgesv(size(d, 1), size(x, 2), lu, size(d, 1), ipiv, x, size(x, 1), info)
    if (info /= 0) error stop 'test_block_precon: dgesv failed'
  end subroutine dense_solve_many

  !> x = d^-1 rhs (LU, LAPACK dgesv).
  subroutine dense_solve(d, rhs, x)
    real(rp), intent(in) :: d(:,:), rhs(:)
    real(rp), intent(out) :: x(:)
    real(rp) :: lu(size(d, 1), size(d, 2)), y(size(rhs), 1)
    integer :: ipiv(size(d, 1)), info
    lu = d
    y(:, 1) = rhs
    call dgesv(size(d, 1), 1, lu, size(d, 1), ipiv, y, size(d, 1), info)
    if (info /= 0) error stop 'test_block_precon: dgesv failed'
    x = y(:, 1)
  end subroutine dense_solve

  !> x = s^-1 x for the SPD matrix s (Cholesky, LAPACK dposv).
  subroutine spd_solve(s, x)
    real(rp), intent(in) :: s(:,:)
    real(rp), intent(inout) :: x(:,:)
    real(rp) :: c(size(s, 1), size(s, 2))
    integer :: info
    c = s
    call dposv('L', size(s, 1), size(x, 2), c, size(s, 1), x, size(x, 1), info)
    if (info /= 0) error stop 'test_block_precon: dposv failed'
  end subroutine spd_solve

  !> Contiguous split of n rows over the ranks.
  subroutine split(n, o)
    integer, intent(in) :: n
    integer(gp), intent(out) :: o(0:)
    integer :: p
    do p = 0, comm%size
      o(p) = 1 + (int(n, gp) * p) / comm%size
    end do
  end subroutine split

  !> The map of field f: the owned rows, every other row as a ghost (the
  !> blocks are dense-ish; every block of a block column shares the map, as
  !> block_matrix%monolithic expects).
  subroutine build_map(f)
    integer, intent(in) :: f
    integer(gp), allocatable :: ghosts(:)
    integer(gp) :: g
    integer(ip) :: k
    allocate(ghosts(field_size(f) - (off(comm%rank + 1, f) - off(comm%rank, f))))
    k = 0
    do g = 1, int(field_size(f), gp)
      if (g >= off(comm%rank, f) .and. g < off(comm%rank + 1, f)) cycle
      k = k + 1
      ghosts(k) = g
    end do
    call maps(f)%init(comm, int(off(comm%rank + 1, f) - off(comm%rank, f), ip), ghosts)
  end subroutine build_map

  !> Pattern and values of the owned rows of field fr of the dense d (columns
  !> of field fc) in the local column ids of maps(fc), sorted per row.
  subroutine dense_rows(d, fr, fc, row_ptr, col, val)
    real(rp), intent(in) :: d(:,:)
    integer, intent(in) :: fr, fc
    integer(ip), allocatable, intent(out) :: row_ptr(:), col(:)
    real(rp), allocatable, intent(out) :: val(:)
    integer(ip) :: nr, i, m, k, m0, ct
    integer(gp) :: r, g
    real(rp) :: vt
    nr = int(off(comm%rank + 1, fr) - off(comm%rank, fr), ip)
    allocate(row_ptr(nr + 1), col(count(d(off(comm%rank, fr):off(comm%rank + 1, fr) - 1, :) /= 0.0_rp)))
    allocate(val(size(col)))
    row_ptr(1) = 1
    m = 0
    do i = 1, nr
      r = off(comm%rank, fr) + i - 1
      m0 = m
      do g = 1, size(d, 2, kind=gp)
        if (d(r, g) == 0.0_rp) cycle
        m = m + 1
        col(m) = maps(fc)%local_id(g)
        val(m) = d(r, g)
        ! insertion into the sorted part of the row
        k = m
        do while (k > m0 + 1)
          if (col(k - 1) < col(k)) exit
          ct = col(k); col(k) = col(k - 1); col(k - 1) = ct
          vt = val(k); val(k) = val(k - 1); val(k - 1) = vt
          k = k - 1
        end do
      end do
      row_ptr(i + 1) = m + 1
    end do
  end subroutine dense_rows

  !> Block (i, j) of the block matrix from the dense d.
  subroutine set_block(am, i, j, d)
    type(block_matrix_t), intent(inout) :: am
    integer, intent(in) :: i, j
    real(rp), intent(in) :: d(:,:)
    integer(ip), allocatable :: row_ptr(:), col(:)
    real(rp), allocatable :: val(:)
    call dense_rows(d, i, j, row_ptr, col, val)
    call am%set_pattern(i, j, maps(i), maps(j), row_ptr, col)
    am%a(i, j)%val = val
  end subroutine set_block

  !> A csr_matrix_t on maps(fr) x maps(fc) from the dense d.
  subroutine dense_csr(d, fr, fc, m)
    real(rp), intent(in) :: d(:,:)
    integer, intent(in) :: fr, fc
    type(csr_matrix_t), intent(inout) :: m
    integer(ip), allocatable :: row_ptr(:), col(:)
    real(rp), allocatable :: val(:)
    call dense_rows(d, fr, fc, row_ptr, col, val)
    call m%init(maps(fr), maps(fc), row_ptr, col)
    m%val = val
  end subroutine dense_csr

  !> An explicit factor block as the framework's users build it: a
  !> global_csr_t (rows of field fr, columns of field fc) turned into a
  !> csr_matrix_t with its own column map.
  subroutine explicit_block(d, fr, fc, m)
    real(rp), intent(in) :: d(:,:)
    integer, intent(in) :: fr, fc
    type(csr_matrix_t), intent(inout) :: m
    type(global_csr_t) :: g
    integer :: i, j, k
    integer(gp) :: r0
    g%comm = comm
    ! explicit bounds: an assigned array section would start at 1
    allocate(g%row_offsets(0:comm%size), g%col_offsets(0:comm%size))
    g%row_offsets(:) = off(:, fr)
    g%col_offsets(:) = off(:, fc)
    r0 = off(comm%rank, fr)
    g%n_rows = int(off(comm%rank + 1, fr) - r0, ip)
    allocate(g%row_ptr(g%n_rows + 1), g%gcol(count(d(r0:r0 + g%n_rows - 1, :) /= 0.0_rp)), g%key(g%n_rows))
    allocate(g%val(size(g%gcol)))
    g%row_ptr(1) = 1
    k = 0
    do i = 1, g%n_rows
      do j = 1, size(d, 2)
        if (d(r0 + i - 1, j) == 0.0_rp) cycle
        k = k + 1
        g%gcol(k) = j
        g%val(k) = d(r0 + i - 1, j)
      end do
      g%row_ptr(i + 1) = k + 1
      g%key(i) = r0 + i - 1
    end do
    call m%free()
    call to_csr(g, maps(fr), m)
    call g%free()
  end subroutine explicit_block

  !> Every factor block of p implicit with the framework's S_i inside.
  subroutine all_implicit(p)
    type(block_precon_t), intent(inout) :: p
    call p%set_implicit(3, 1, 1)
    call p%set_implicit(3, 2, 2)
    call p%set_implicit(1, 3, 1)
    call p%set_implicit(2, 3, 2)
  end subroutine all_implicit

  !> A framework on the block matrix am with MUMPS factorizations of K, M and
  !> the exact Schur complement sm as S_1, S_2, S_3 and no factor blocks.
  subroutine new_precon(p, label, am, sm)
    type(block_precon_t), intent(inout) :: p
    character(len=*), intent(in) :: label
    type(block_matrix_t), intent(in), target :: am
    type(csr_matrix_t), intent(in) :: sm
    integer :: f
    call p%init(am, label)
    do f = 1, 3
      block
        type(mumps_solver_t), allocatable :: ms
        type(error_status_t) :: s
        allocate(ms)
        if (f < 3) then
          call ms%setup(am%a(f, f), s, symmetric=.true.)
        else
          call ms%setup(sm, s, symmetric=.true.)
        end if
        if (.not. s%ok()) error stop 'test_block_precon: MUMPS failed on a diagonal block'
        call move_alloc(ms, p%s(f)%p)
      end block
    end do
  end subroutine new_precon

  !> A Jacobi preconditioner of diagonal block f, as a class(precon_t).
  subroutine own_jacobi(f, p)
    integer, intent(in) :: f
    class(precon_t), allocatable, intent(out) :: p
    type(jacobi_precon_t), allocatable :: jp
    type(error_status_t) :: s
    allocate(jp)
    call jp%setup(a%a(f, f), s)
    if (.not. s%ok()) error stop 'test_block_precon: Jacobi set-up failed'
    call move_alloc(jp, p)
  end subroutine own_jacobi

  !> FGMRES on am x = b from x = 0 with p: iterations, true relative residual
  !> (huge when not converged) and error against the dense solution xr.
  subroutine run(p, am, xr, its, res, err, x)
    type(block_precon_t), intent(inout) :: p
    type(block_matrix_t), intent(inout) :: am
    real(rp), intent(in) :: xr(:)
    integer, intent(out) :: its
    real(rp), intent(out) :: res, err
    real(rp), intent(out) :: x(:)
    type(solve_info_t) :: info
    x = 0.0_rp
    call gmres%solve(am, p, b, x, info)
    its = info%iterations
    res = info%rel_res
    if (.not. info%converged) res = huge(1.0_rp)
    err = max_rel_diff(comm, x, xr)
    if (comm%rank == 0) print '(a,a24,a,i3,a,es10.3,a,es10.3)', '  ', trim(p%label), ': iterations ', its, &
      ', rel. residual ', info%rel_res, ', error ', err
  end subroutine run

  !> The owned entries of a global vector [x_1; x_2; x_3] as a block vector.
  subroutine scatter(vg, vb)
    real(rp), intent(in) :: vg(:)
    real(rp), intent(out) :: vb(:)
    integer :: f
    integer(ip) :: i0, i1, i
    do f = 1, 3
      call a%block_range(f, i0, i1)
      do i = i0, i1
        vb(i) = vg(gbase(f) + off(comm%rank, f) + i - i0)
      end do
    end do
  end subroutine scatter

  !> Ascending insertion sort (small arrays).
  subroutine sort_reals(s)
    real(rp), intent(inout) :: s(:)
    integer :: i, k
    real(rp) :: t
    do i = 2, size(s)
      t = s(i)
      k = i - 1
      do while (k >= 1)
        if (s(k) <= t) exit
        s(k + 1) = s(k)
        k = k - 1
      end do
      s(k + 1) = t
    end do
  end subroutine sort_reals
end program test_block_precon
