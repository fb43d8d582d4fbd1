/*
 * geoblock's own V-cycle over a BoomerAMG hierarchy (hypre 2.26).
 *
 * hypre's backward l1 Gauss-Seidel sweep (relax type 14, the up-cycle's
 * smoother of the l1-gs pair) visits the rows from the last to the first
 * but reads each row's entries upwards in memory: runs of ~1 KB that go
 * up while the rows go down, which the hardware prefetch does not follow.
 * On the clamped cube at n = 64 (1 rank, 2026-12-04) hypre's backward sweep
 * of the finest level took 0.18 s against 0.035 s for the forward one, and
 * the sweeps were 60-70 % of the CG solve.
 *
 * BoomerAMG takes no user smoother, so this file runs the cycle that
 * hypre_BoomerAMGCycle runs for the hierarchies geoblock builds with l1
 * Gauss-Seidel (relax type 13 down, 14 up, Gaussian elimination (9) on the
 * coarsest level, one V-cycle, lexicographic order, unit weights,
 * restriction by P^T), with its own sweep. Every other part of the cycle is
 * hypre's (the residual, P^T, P, the coarse solve), on hypre's level
 * matrices, vectors and l1 norms, reached through its internal header
 * _hypre_parcsr_ls.h (installed by Debian's libhypre-dev). The sweep is the
 * same relaxation as hypre's,
 *   u_i <- u_i + (f_i - sum_j a_ij u_j) / l1_i,
 * Gauss-Seidel within the rank, Jacobi across ranks (the halo of u taken
 * once a sweep); the backward sweep reads every array downwards, and each
 * row is summed in four accumulators (no chain of dependent additions), so
 * one cycle agrees with hypre's to round-off, not bit for bit.
 *
 * gb_amg_cycle_fits(solver)          1 when the set-up hierarchy is one
 *                                    this cycle reproduces, else 0
 * gb_amg_cycle(solver, par_b, par_x) x <- one V-cycle on A x = b from
 *                                    x = 0 (x is zeroed here); returns
 *                                    hypre's error flag
 * gb_amg_refresh_fine(solver, par_a) the finest level becomes par_a (a
 *                                    matrix of the same rows) with its l1
 *                                    norms; the coarse levels stay (a
 *                                    lagged hierarchy)
 */
#include <stdlib.h>
#include <string.h>
#include <mpi.h>
#include "_hypre_parcsr_ls.h"

/* the relax types this cycle reproduces: l1 hybrid Gauss-Seidel forward
   (13) down, backward (14) up, Gaussian elimination (9) on the coarsest */
enum { DOWN_TYPE = 13, UP_TYPE = 14, COARSE_TYPE = 9 };

int gb_amg_cycle_fits(void *solver)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  HYPRE_Int l, num_levels, *relax, *sweeps;
  HYPRE_Real *weight, *omega;
  if (amg == NULL) return 0;
  num_levels = hypre_ParAMGDataNumLevels(amg);
  relax = hypre_ParAMGDataGridRelaxType(amg);
  sweeps = hypre_ParAMGDataNumGridSweeps(amg);
  weight = hypre_ParAMGDataRelaxWeight(amg);
  omega = hypre_ParAMGDataOmega(amg);
  if (num_levels < 2 || relax == NULL || sweeps == NULL) return 0;
  if (relax[1] != DOWN_TYPE || relax[2] != UP_TYPE || relax[3] != COARSE_TYPE) return 0;
  if (sweeps[3] != 1) return 0;
  if (hypre_ParAMGDataCycleType(amg) != 1 || hypre_ParAMGDataFCycle(amg)) return 0;
  if (hypre_ParAMGDataRelaxOrder(amg) != 0 || hypre_ParAMGDataGridRelaxPoints(amg) != NULL) return 0;
  if (hypre_ParAMGDataSmoothNumLevels(amg) > 0 || hypre_ParAMGDataBlockMode(amg)) return 0;
  if (hypre_ParAMGDataRestriction(amg) != 0) return 0;
  if (hypre_ParAMGDataPartialCycleCoarsestLevel(amg) >= 0) return 0;
  if (hypre_ParAMGDataAdditive(amg) >= 0 && hypre_ParAMGDataAdditive(amg) < num_levels) return 0;
  if (hypre_ParAMGDataMultAdditive(amg) >= 0 && hypre_ParAMGDataMultAdditive(amg) < num_levels) return 0;
  if (hypre_ParAMGDataSimple(amg) >= 0 && hypre_ParAMGDataSimple(amg) < num_levels) return 0;
  if (hypre_ParAMGDataParticipate(amg)) return 0;
  if (hypre_ParAMGDataL1Norms(amg) == NULL || weight == NULL || omega == NULL) return 0;
  for (l = 0; l < num_levels - 1; l++)
  {
    if (weight[l] != 1.0 || omega[l] != 1.0) return 0;
    if (hypre_ParAMGDataL1Norms(amg)[l] == NULL) return 0;
  }
  return 1;
}

/* The values of u that A's off-rank columns need (the halo), into v_ext. */
static void halo(hypre_ParCSRMatrix *A, const HYPRE_Real *u, HYPRE_Real *v_buf, HYPRE_Real *v_ext)
{
  hypre_ParCSRCommPkg *pkg;
  hypre_ParCSRCommHandle *handle;
  HYPRE_Int j, begin, end, *elmts;
  pkg = hypre_ParCSRMatrixCommPkg(A);
  begin = hypre_ParCSRCommPkgSendMapStart(pkg, 0);
  end = hypre_ParCSRCommPkgSendMapStart(pkg, hypre_ParCSRCommPkgNumSends(pkg));
  elmts = hypre_ParCSRCommPkgSendMapElmts(pkg);
  for (j = begin; j < end; j++) v_buf[j - begin] = u[elmts[j]];
  handle = hypre_ParCSRCommHandleCreate(1, pkg, v_buf, v_ext);
  hypre_ParCSRCommHandleDestroy(handle);
}

/* f_i - sum_j a_ij x_j over row i of (ia, ja, a), reading the row upwards
   in memory (up) or downwards, with four accumulators. */
static inline HYPRE_Real row_rest_up(const HYPRE_Int *ia, const HYPRE_Int *ja, const HYPRE_Real *a,
                                     const HYPRE_Real *x, HYPRE_Int i, HYPRE_Real fi)
{
  HYPRE_Real r0 = fi, r1 = 0.0, r2 = 0.0, r3 = 0.0;
  HYPRE_Int jj = ia[i], end = ia[i + 1];
  for (; jj + 3 < end; jj += 4)
  {
    r0 -= a[jj] * x[ja[jj]];
    r1 -= a[jj + 1] * x[ja[jj + 1]];
    r2 -= a[jj + 2] * x[ja[jj + 2]];
    r3 -= a[jj + 3] * x[ja[jj + 3]];
  }
  for (; jj < end; jj++) r0 -= a[jj] * x[ja[jj]];
  return (r0 + r1) + (r2 + r3);
}

static inline HYPRE_Real row_rest_down(const HYPRE_Int *ia, const HYPRE_Int *ja, const HYPRE_Real *a,
                                       const HYPRE_Real *x, HYPRE_Int i, HYPRE_Real fi)
{
  HYPRE_Real r0 = fi, r1 = 0.0, r2 = 0.0, r3 = 0.0;
  HYPRE_Int jj = ia[i + 1] - 1, begin = ia[i];
  for (; jj - 3 >= begin; jj -= 4)
  {
    r0 -= a[jj] * x[ja[jj]];
    r1 -= a[jj - 1] * x[ja[jj - 1]];
    r2 -= a[jj - 2] * x[ja[jj - 2]];
    r3 -= a[jj - 3] * x[ja[jj - 3]];
  }
  for (; jj >= begin; jj--) r0 -= a[jj] * x[ja[jj]];
  return (r0 + r1) + (r2 + r3);
}

/* One l1 hybrid Gauss-Seidel sweep on the rank's rows, forward (dir > 0)
   or backward, with the off-rank values v_ext held fixed. The backward
   sweep reads every array downwards, rows and their entries alike: read
   row by row upwards within each row (hypre's backward kernel), the
   memory is walked in runs that go up while the rows go down, which the
   hardware prefetch does not follow (5x the forward sweep's time on the
   cube's finest level, 2026-12-04). */
static void sweep_rows(const hypre_CSRMatrix *diag, const hypre_CSRMatrix *offd, const HYPRE_Real *f,
                       const HYPRE_Real *l1, const HYPRE_Real *v_ext, HYPRE_Real *u, int dir)
{
  const HYPRE_Int n = hypre_CSRMatrixNumRows(diag);
  const HYPRE_Int *di = hypre_CSRMatrixI(diag), *dj = hypre_CSRMatrixJ(diag);
  const HYPRE_Real *da = hypre_CSRMatrixData(diag);
  const HYPRE_Int *oi = hypre_CSRMatrixI(offd), *oj = hypre_CSRMatrixJ(offd);
  const HYPRE_Real *oa = hypre_CSRMatrixData(offd);
  const int has_offd = hypre_CSRMatrixNumCols(offd) > 0 && oi != NULL;
  HYPRE_Int i;
  if (dir > 0)
  {
    for (i = 0; i < n; i++)
    {
      HYPRE_Real r;
      if (l1[i] == 0.0) continue;
      r = has_offd ? row_rest_up(oi, oj, oa, v_ext, i, f[i]) : f[i];
      u[i] += row_rest_up(di, dj, da, u, i, r) / l1[i];
    }
  }
  else
  {
    for (i = n - 1; i >= 0; i--)
    {
      HYPRE_Real r;
      if (l1[i] == 0.0) continue;
      r = has_offd ? row_rest_down(oi, oj, oa, v_ext, i, f[i]) : f[i];
      u[i] += row_rest_down(di, dj, da, u, i, r) / l1[i];
    }
  }
}

/* One sweep on a level: the halo, then the rank's rows. */
static void sweep(hypre_ParCSRMatrix *A, hypre_ParVector *f, hypre_ParVector *u, const HYPRE_Real *l1,
                  int dir)
{
  hypre_CSRMatrix *offd = hypre_ParCSRMatrixOffd(A);
  HYPRE_Real *uu = hypre_VectorData(hypre_ParVectorLocalVector(u));
  HYPRE_Real *v_ext = NULL, *v_buf = NULL;
  HYPRE_Int n_ext = hypre_CSRMatrixNumCols(offd);
  int procs;
  MPI_Comm_size(hypre_ParCSRMatrixComm(A), &procs);
  if (procs > 1)
  {
    hypre_ParCSRCommPkg *pkg;
    if (hypre_ParCSRMatrixCommPkg(A) == NULL) hypre_MatvecCommPkgCreate(A);
    pkg = hypre_ParCSRMatrixCommPkg(A);
    v_buf = (HYPRE_Real *) malloc(sizeof(HYPRE_Real) *
                                  (1 + hypre_ParCSRCommPkgSendMapStart(pkg, hypre_ParCSRCommPkgNumSends(pkg))));
    v_ext = (HYPRE_Real *) malloc(sizeof(HYPRE_Real) * (1 + n_ext));
    halo(A, uu, v_buf, v_ext);
  }
  sweep_rows(hypre_ParCSRMatrixDiag(A), offd, hypre_VectorData(hypre_ParVectorLocalVector(f)), l1, v_ext, uu,
             dir);
  free(v_buf);
  free(v_ext);
}

int gb_amg_cycle(void *solver, void *par_b, void *par_x)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  hypre_ParCSRMatrix **A = hypre_ParAMGDataAArray(amg);
  hypre_ParCSRMatrix **P = hypre_ParAMGDataPArray(amg);
  hypre_ParCSRMatrix **R = hypre_ParAMGDataRArray(amg);
  hypre_ParVector **F = hypre_ParAMGDataFArray(amg);
  hypre_ParVector **U = hypre_ParAMGDataUArray(amg);
  hypre_ParVector *Vtemp = hypre_ParAMGDataVtemp(amg);
  hypre_Vector **l1 = hypre_ParAMGDataL1Norms(amg);
  const HYPRE_Int *sweeps = hypre_ParAMGDataNumGridSweeps(amg);
  const HYPRE_Int num_levels = hypre_ParAMGDataNumLevels(amg);
  const HYPRE_Int coarsest = num_levels - 1;
  HYPRE_Int l, s;

  F[0] = (hypre_ParVector *) par_b;
  U[0] = (hypre_ParVector *) par_x;
  hypre_ParVectorSetConstantValues(U[0], 0.0);
  for (l = 0; l < coarsest; l++)
  {
    hypre_ParVectorSetLocalSize(Vtemp, hypre_VectorSize(hypre_ParVectorLocalVector(F[l])));
    for (s = 0; s < sweeps[1]; s++) sweep(A[l], F[l], U[l], hypre_VectorData(l1[l]), 1);
    hypre_ParCSRMatrixMatvecOutOfPlace(-1.0, A[l], U[l], 1.0, F[l], Vtemp);
    hypre_ParCSRMatrixMatvecT(1.0, R[l], Vtemp, 0.0, F[l + 1]);
    hypre_ParVectorSetConstantValues(U[l + 1], 0.0);
  }
  hypre_ParVectorSetLocalSize(Vtemp, hypre_VectorSize(hypre_ParVectorLocalVector(F[coarsest])));
  hypre_GaussElimSolve(amg, coarsest, COARSE_TYPE);
  for (l = coarsest - 1; l >= 0; l--)
  {
    hypre_ParVectorSetLocalSize(Vtemp, hypre_VectorSize(hypre_ParVectorLocalVector(F[l])));
    hypre_ParCSRMatrixMatvec(1.0, P[l], U[l + 1], 1.0, U[l]);
    for (s = 0; s < sweeps[2]; s++) sweep(A[l], F[l], U[l], hypre_VectorData(l1[l]), -1);
  }
  return hypre_error_flag;
}

int gb_amg_refresh_fine(void *solver, void *par_a)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  hypre_ParCSRMatrix *A = (hypre_ParCSRMatrix *) par_a;
  hypre_Vector *l1 = hypre_ParAMGDataL1Norms(amg)[0];
  HYPRE_Real *norms = NULL;
  HYPRE_Int n = hypre_CSRMatrixNumRows(hypre_ParCSRMatrixDiag(A));
  if (n != hypre_VectorSize(l1)) return 1;
  hypre_ParAMGDataAArray(amg)[0] = A;
  if (hypre_ParCSRMatrixCommPkg(A) == NULL) hypre_MatvecCommPkgCreate(A);
  /* the l1 norms hypre's set-up computes for relax types 13 and 14 */
  hypre_ParCSRComputeL1Norms(A, 4, NULL, &norms);
  memcpy(hypre_VectorData(l1), norms, sizeof(HYPRE_Real) * (size_t) n);
  hypre_TFree(norms, HYPRE_MEMORY_HOST);
  return hypre_error_flag;
}
