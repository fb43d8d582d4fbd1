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
 * gb_amg_cycle(solver, compact, par_b, par_x)
 *                                    x <- one V-cycle on A x = b from
 *                                    x = 0 (x is zeroed here), with the
 *                                    single-precision values of compact
 *                                    where it is not NULL; returns
 *                                    hypre's error flag
 * gb_amg_refresh_fine(solver, compact, par_a)
 *                                    the finest level becomes par_a (a
 *                                    matrix of the same rows) with its l1
 *                                    norms (and its values in single
 *                                    precision in place where compact is
 *                                    given); the coarse levels stay (a
 *                                    lagged hierarchy)
 * gb_amg_regalerkin(solver, par_a)   the finest level becomes par_a and
 *                                    every coarse level P^T A P anew with
 *                                    the interpolation of the set-up,
 *                                    with the l1 norms and the coarsest
 *                                    level's Gaussian elimination (its
 *                                    single-precision values are then to
 *                                    be made anew)
 * gb_amg_compact_create(solver, old) the values of every level's matrix but
 *                                    the coarsest in single precision, in
 *                                    place in hypre's arrays (NULL: none;
 *                                    old, the last set-up's or NULL, is
 *                                    reused): afterwards only this cycle,
 *                                    with compact, may run the hierarchy,
 *                                    and the finest level's matrix (the
 *                                    caller's IJ matrix) holds floats
 * gb_amg_fine_narrowed(compact)      1 when the finest level's values are
 *                                    floats in place, else 0
 * gb_amg_fine_product(compact, par_a, par_x, par_y)
 *                                    y <- A x for the hierarchy's finest
 *                                    level A, with the values compact
 *                                    holds (floats, or on a rank that
 *                                    kept them, doubles); 1 without one
 * gb_amg_compact_free(compact)       frees compact's buffers
 *
 * Single precision (&amg precision = 'single'): the sweeps and the
 * residual of a level read its matrix's values as floats (4 bytes an entry
 * instead of 8; with the 4-byte column index, 8 bytes instead of 12), and
 * sum them in double precision against double vectors. Every level is
 * converted in place, in the first half of hypre's value arrays: no new
 * memory and no fresh pages (a first version's copies cost 0.8 s of page
 * faults and copying per set-up of the seed's nine fractures' S**, and a
 * copy of the finest level kept from one set-up to the next was 390 MB a
 * rank on HI24L at the seed's size, on top of the set-up's peak). The
 * finest level is the caller's IJ matrix (hypre_ij): its doubles are gone
 * until new values are written into it (hypre_ij's rebuild_rows), and its
 * products are gb_amg_fine_product's. The cycle is then the same V-cycle
 * for the matrices rounded to single precision (relative change 6e-8 an
 * entry): still a fixed, symmetric preconditioner, whose quality the
 * rounding does not touch. The transfers (P, P^T) and the coarse solve
 * stay hypre's, in double. A level with an entry that single precision
 * cannot hold as a normal number (beyond 3.4e38 or, nonzero, below
 * 1.2e-38) keeps its double values, on its rank (the halo exchange is the
 * same either way).
 */
#include <float.h>
#include <math.h>
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
   in memory (up) or downwards, with four accumulators; a's values are
   double (row_rest_up, row_rest_down) or float (..._s, summed in double). */
#define GB_ROW_REST(UP, DOWN, VALUE)                                                                \
  static inline HYPRE_Real UP(const HYPRE_Int *ia, const HYPRE_Int *ja, const VALUE *a,            \
                              const HYPRE_Real *x, HYPRE_Int i, HYPRE_Real fi)                     \
  {                                                                                                 \
    HYPRE_Real r0 = fi, r1 = 0.0, r2 = 0.0, r3 = 0.0;                                               \
    HYPRE_Int jj = ia[i], end = ia[i + 1];                                                          \
    for (; jj + 3 < end; jj += 4)                                                                   \
    {                                                                                               \
      r0 -= (HYPRE_Real) a[jj] * x[ja[jj]];                                                         \
      r1 -= (HYPRE_Real) a[jj + 1] * x[ja[jj + 1]];                                                 \
      r2 -= (HYPRE_Real) a[jj + 2] * x[ja[jj + 2]];                                                 \
      r3 -= (HYPRE_Real) a[jj + 3] * x[ja[jj + 3]];                                                 \
    }                                                                                               \
    for (; jj < end; jj++) r0 -= (HYPRE_Real) a[jj] * x[ja[jj]];                                    \
    return (r0 + r1) + (r2 + r3);                                                                   \
  }                                                                                                 \
  static inline HYPRE_Real DOWN(const HYPRE_Int *ia, const HYPRE_Int *ja, const VALUE *a,          \
                                const HYPRE_Real *x, HYPRE_Int i, HYPRE_Real fi)                   \
  {                                                                                                 \
    HYPRE_Real r0 = fi, r1 = 0.0, r2 = 0.0, r3 = 0.0;                                               \
    HYPRE_Int jj = ia[i + 1] - 1, begin = ia[i];                                                    \
    for (; jj - 3 >= begin; jj -= 4)                                                                \
    {                                                                                               \
      r0 -= (HYPRE_Real) a[jj] * x[ja[jj]];                                                         \
      r1 -= (HYPRE_Real) a[jj - 1] * x[ja[jj - 1]];                                                 \
      r2 -= (HYPRE_Real) a[jj - 2] * x[ja[jj - 2]];                                                 \
      r3 -= (HYPRE_Real) a[jj - 3] * x[ja[jj - 3]];                                                 \
    }                                                                                               \
    for (; jj >= begin; jj--) r0 -= (HYPRE_Real) a[jj] * x[ja[jj]];                                 \
    return (r0 + r1) + (r2 + r3);                                                                   \
  }

GB_ROW_REST(row_rest_up, row_rest_down, HYPRE_Real)
GB_ROW_REST(row_rest_up_s, row_rest_down_s, float)

/* One l1 hybrid Gauss-Seidel sweep over the rows 0..n-1, forward (dir > 0)
   or backward, with the row kernels UP / DOWN on the values DA (diagonal
   part) and OA (off-rank part). */
#define GB_SWEEP(UP, DOWN, DA, OA)                                                                  \
  if (dir > 0)                                                                                      \
  {                                                                                                 \
    for (i = 0; i < n; i++)                                                                         \
    {                                                                                               \
      HYPRE_Real r;                                                                                 \
      if (l1[i] == 0.0) continue;                                                                   \
      r = has_offd ? UP(oi, oj, OA, v_ext, i, f[i]) : f[i];                                         \
      u[i] += UP(di, dj, DA, u, i, r) / l1[i];                                                      \
    }                                                                                               \
  }                                                                                                 \
  else                                                                                              \
  {                                                                                                 \
    for (i = n - 1; i >= 0; i--)                                                                    \
    {                                                                                               \
      HYPRE_Real r;                                                                                 \
      if (l1[i] == 0.0) continue;                                                                   \
      r = has_offd ? DOWN(oi, oj, OA, v_ext, i, f[i]) : f[i];                                       \
      u[i] += DOWN(di, dj, DA, u, i, r) / l1[i];                                                    \
    }                                                                                               \
  }

/* Where a hierarchy's level values are floats (all levels but the
   coarsest, in place in hypre's arrays), NULL for a level that keeps its
   double values, and the halo buffers, sized for the largest level. */
typedef struct
{
  HYPRE_Int levels;
  float **diag, **offd;
  HYPRE_Real *buf, *ext;
  HYPRE_Int n_buf, n_ext;
} gb_compact;

/* One l1 hybrid Gauss-Seidel sweep on the rank's rows, forward (dir > 0)
   or backward, with the off-rank values v_ext held fixed; the values from
   da/oa where they are given (single precision), else from the matrices.
   The backward sweep reads every array downwards, rows and their entries
   alike: read row by row upwards within each row (hypre's backward
   kernel), the memory is walked in runs that go up while the rows go
   down, which the hardware prefetch does not follow (5x the forward
   sweep's time on the cube's finest level, 2026-12-04). */
static void sweep_rows(const hypre_CSRMatrix *diag, const hypre_CSRMatrix *offd, const float *da_s,
                       const float *oa_s, const HYPRE_Real *f, const HYPRE_Real *l1, const HYPRE_Real *v_ext,
                       HYPRE_Real *u, int dir)
{
  const HYPRE_Int n = hypre_CSRMatrixNumRows(diag);
  const HYPRE_Int *di = hypre_CSRMatrixI(diag), *dj = hypre_CSRMatrixJ(diag);
  const HYPRE_Real *da = hypre_CSRMatrixData(diag);
  const HYPRE_Int *oi = hypre_CSRMatrixI(offd), *oj = hypre_CSRMatrixJ(offd);
  const HYPRE_Real *oa = hypre_CSRMatrixData(offd);
  const int has_offd = hypre_CSRMatrixNumCols(offd) > 0 && oi != NULL;
  HYPRE_Int i;
  if (da_s != NULL)
  {
    GB_SWEEP(row_rest_up_s, row_rest_down_s, da_s, oa_s)
  }
  else
  {
    GB_SWEEP(row_rest_up, row_rest_down, da, oa)
  }
}

/* The number of values A's halo sends from this rank. */
static HYPRE_Int send_size(hypre_ParCSRMatrix *A)
{
  hypre_ParCSRCommPkg *pkg;
  if (hypre_ParCSRMatrixCommPkg(A) == NULL) hypre_MatvecCommPkgCreate(A);
  pkg = hypre_ParCSRMatrixCommPkg(A);
  return hypre_ParCSRCommPkgSendMapStart(pkg, hypre_ParCSRCommPkgNumSends(pkg));
}

/* The halo of u on a level, into v_ext (NULL on one rank): the buffers of
   c where given, else allocated here (*own set to free them). */
static HYPRE_Real *level_halo(hypre_ParCSRMatrix *A, const HYPRE_Real *u, gb_compact *c, HYPRE_Real **own_buf,
                              HYPRE_Real **own_ext)
{
  int procs;
  *own_buf = NULL;
  *own_ext = NULL;
  MPI_Comm_size(hypre_ParCSRMatrixComm(A), &procs);
  if (procs == 1) return NULL;
  if (c != NULL)
  {
    halo(A, u, c->buf, c->ext);
    return c->ext;
  }
  *own_buf = (HYPRE_Real *) malloc(sizeof(HYPRE_Real) * (1 + send_size(A)));
  *own_ext = (HYPRE_Real *) malloc(sizeof(HYPRE_Real) * (1 + hypre_CSRMatrixNumCols(hypre_ParCSRMatrixOffd(A))));
  halo(A, u, *own_buf, *own_ext);
  return *own_ext;
}

/* One sweep on level l: the halo, then the rank's rows. */
static void sweep(hypre_ParCSRMatrix *A, gb_compact *c, HYPRE_Int l, hypre_ParVector *f, hypre_ParVector *u,
                  const HYPRE_Real *l1, int dir)
{
  HYPRE_Real *uu = hypre_VectorData(hypre_ParVectorLocalVector(u));
  HYPRE_Real *b1, *b2, *v_ext;
  const float *da_s = (c != NULL) ? c->diag[l] : NULL;
  const float *oa_s = (c != NULL) ? c->offd[l] : NULL;
  v_ext = level_halo(A, uu, c, &b1, &b2);
  sweep_rows(hypre_ParCSRMatrixDiag(A), hypre_ParCSRMatrixOffd(A), da_s, oa_s,
             hypre_VectorData(hypre_ParVectorLocalVector(f)), l1, v_ext, uu, dir);
  free(b1);
  free(b2);
}

/* v = f - A u on level l with the single-precision values of c. */
static void residual_s(hypre_ParCSRMatrix *A, gb_compact *c, HYPRE_Int l, hypre_ParVector *f,
                       hypre_ParVector *u, hypre_ParVector *v)
{
  const hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(A), *offd = hypre_ParCSRMatrixOffd(A);
  const HYPRE_Int n = hypre_CSRMatrixNumRows(diag);
  const HYPRE_Int *di = hypre_CSRMatrixI(diag), *dj = hypre_CSRMatrixJ(diag);
  const HYPRE_Int *oi = hypre_CSRMatrixI(offd), *oj = hypre_CSRMatrixJ(offd);
  const int has_offd = hypre_CSRMatrixNumCols(offd) > 0 && oi != NULL;
  const float *da = c->diag[l], *oa = c->offd[l];
  const HYPRE_Real *ff = hypre_VectorData(hypre_ParVectorLocalVector(f));
  HYPRE_Real *uu = hypre_VectorData(hypre_ParVectorLocalVector(u));
  HYPRE_Real *vv = hypre_VectorData(hypre_ParVectorLocalVector(v));
  HYPRE_Real *b1, *b2, *v_ext;
  HYPRE_Int i;
  v_ext = level_halo(A, uu, c, &b1, &b2);
  for (i = 0; i < n; i++)
  {
    HYPRE_Real r = has_offd ? row_rest_up_s(oi, oj, oa, v_ext, i, ff[i]) : ff[i];
    vv[i] = row_rest_up_s(di, dj, da, uu, i, r);
  }
  free(b1);
  free(b2);
}

int gb_amg_cycle(void *solver, void *compact, void *par_b, void *par_x)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  gb_compact *c = (gb_compact *) compact;
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

  /* the floats belong to this hierarchy (its levels hold them: no double
     cycle can run them any more) */
  if (c != NULL && c->levels != coarsest) return 1;
  F[0] = (hypre_ParVector *) par_b;
  U[0] = (hypre_ParVector *) par_x;
  hypre_ParVectorSetConstantValues(U[0], 0.0);
  for (l = 0; l < coarsest; l++)
  {
    hypre_ParVectorSetLocalSize(Vtemp, hypre_VectorSize(hypre_ParVectorLocalVector(F[l])));
    for (s = 0; s < sweeps[1]; s++) sweep(A[l], c, l, F[l], U[l], hypre_VectorData(l1[l]), 1);
    if (c != NULL && c->diag[l] != NULL)
      residual_s(A[l], c, l, F[l], U[l], Vtemp);
    else
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
    for (s = 0; s < sweeps[2]; s++) sweep(A[l], c, l, F[l], U[l], hypre_VectorData(l1[l]), -1);
  }
  return hypre_error_flag;
}

/* 1 when every nonzero of the n values a is a normal single-precision
   number (NaN is not). No early exit: the loop vectorizes. */
static int single_fits(const HYPRE_Real *a, HYPRE_Int n)
{
  HYPRE_Int k;
  int bad = 0;
  if (n > 0 && a == NULL) return 0;
  for (k = 0; k < n; k++)
  {
    const HYPRE_Real m = fabs(a[k]);
    bad |= (m != 0.0) & !((m >= FLT_MIN) & (m <= FLT_MAX));
  }
  return !bad;
}

/* The values of a level's part as floats in place, in the first half of
   hypre's own array (going up, each float lands on bytes already read);
   hypre frees the array as before. The doubles are gone: only this cycle
   (and gb_amg_fine_product on the finest level) reads them afterwards. */
static float *convert_in_place(hypre_CSRMatrix *part)
{
  enum { CHUNK = 1024 };
  HYPRE_Real *a = hypre_CSRMatrixData(part);
  const HYPRE_Int n = hypre_CSRMatrixNumNonzeros(part);
  float chunk[CHUNK];
  HYPRE_Int k, m, j;
  if (n == 0 || a == NULL) return (float *) a;
  /* through a local chunk and memcpy, which may alias a: every float is
     stored after the doubles it overwrites were read */
  for (k = 0; k < n; k += m)
  {
    m = (n - k < CHUNK) ? n - k : CHUNK;
    for (j = 0; j < m; j++) chunk[j] = (float) a[k + j];
    memcpy((char *) a + sizeof(float) * (size_t) k, chunk, sizeof(float) * (size_t) m);
  }
  return (float *) a;
}

/* Level l's values in single precision, in place in hypre's arrays; a
   level with a value out of range keeps its doubles (NULL). */
static void compact_level(gb_compact *c, hypre_ParCSRMatrix *A, HYPRE_Int l)
{
  hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(A), *offd = hypre_ParCSRMatrixOffd(A);
  c->diag[l] = NULL;
  c->offd[l] = NULL;
  /* in place the doubles are lost: every value is checked first */
  if (!single_fits(hypre_CSRMatrixData(diag), hypre_CSRMatrixNumNonzeros(diag)) ||
      !single_fits(hypre_CSRMatrixData(offd), hypre_CSRMatrixNumNonzeros(offd)))
    return;
  if (!hypre_CSRMatrixOwnsData(diag) || !hypre_CSRMatrixOwnsData(offd)) return;
  c->diag[l] = convert_in_place(diag);
  c->offd[l] = convert_in_place(offd);
}

/* Room for the halo of every level of A (levels matrices) in c's buffers;
   0 when there is no memory. */
static int halo_room(gb_compact *c, hypre_ParCSRMatrix **A, HYPRE_Int levels)
{
  HYPRE_Int l, nb = 1, ne = 1;
  HYPRE_Real *t;
  for (l = 0; l < levels; l++)
  {
    const HYPRE_Int s = send_size(A[l]) + 1, e = hypre_CSRMatrixNumCols(hypre_ParCSRMatrixOffd(A[l])) + 1;
    if (s > nb) nb = s;
    if (e > ne) ne = e;
  }
  if (nb > c->n_buf)
  {
    t = (HYPRE_Real *) realloc(c->buf, sizeof(HYPRE_Real) * (size_t) nb);
    if (t == NULL) return 0;
    c->buf = t;
    c->n_buf = nb;
  }
  if (ne > c->n_ext)
  {
    t = (HYPRE_Real *) realloc(c->ext, sizeof(HYPRE_Real) * (size_t) ne);
    if (t == NULL) return 0;
    c->ext = t;
    c->n_ext = ne;
  }
  return 1;
}

void gb_amg_compact_free(void *compact)
{
  gb_compact *c = (gb_compact *) compact;
  if (c == NULL) return;
  free(c->diag);
  free(c->offd);
  free(c->buf);
  free(c->ext);
  free(c);
}

void *gb_amg_compact_create(void *solver, void *old)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  hypre_ParCSRMatrix **A = hypre_ParAMGDataAArray(amg);
  const HYPRE_Int levels = hypre_ParAMGDataNumLevels(amg) - 1;
  gb_compact *c = (gb_compact *) old;
  HYPRE_Int l;
  if (levels < 1)
  {
    gb_amg_compact_free(c);
    return NULL;
  }
  if (c == NULL) c = (gb_compact *) calloc(1, sizeof(gb_compact));
  if (c == NULL) return NULL;
  free(c->diag);
  free(c->offd);
  c->levels = levels;
  c->diag = (float **) calloc((size_t) levels, sizeof(float *));
  c->offd = (float **) calloc((size_t) levels, sizeof(float *));
  if (c->diag == NULL || c->offd == NULL || !halo_room(c, A, levels))
  {
    gb_amg_compact_free(c);
    return NULL;
  }
  for (l = 0; l < levels; l++) compact_level(c, A[l], l);
  return c;
}

int gb_amg_fine_narrowed(void *compact)
{
  const gb_compact *c = (const gb_compact *) compact;
  return (c != NULL && c->levels > 0 && c->diag[0] != NULL) ? 1 : 0;
}

int gb_amg_fine_product(void *compact, void *par_a, void *par_x, void *par_y)
{
  gb_compact *c = (gb_compact *) compact;
  hypre_ParCSRMatrix *A = (hypre_ParCSRMatrix *) par_a;
  const hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(A), *offd = hypre_ParCSRMatrixOffd(A);
  const HYPRE_Int n = hypre_CSRMatrixNumRows(diag);
  const HYPRE_Int *di = hypre_CSRMatrixI(diag), *dj = hypre_CSRMatrixJ(diag);
  const HYPRE_Int *oi = hypre_CSRMatrixI(offd), *oj = hypre_CSRMatrixJ(offd);
  const HYPRE_Real *da = hypre_CSRMatrixData(diag), *oa = hypre_CSRMatrixData(offd);
  const int has_offd = hypre_CSRMatrixNumCols(offd) > 0 && oi != NULL;
  const float *da_s, *oa_s;
  const HYPRE_Real *xx = hypre_VectorData(hypre_ParVectorLocalVector((hypre_ParVector *) par_x));
  HYPRE_Real *yy = hypre_VectorData(hypre_ParVectorLocalVector((hypre_ParVector *) par_y));
  HYPRE_Real *b1, *b2, *v_ext;
  HYPRE_Int i;
  if (c == NULL || c->levels < 1) return 1;
  da_s = c->diag[0];
  oa_s = c->offd[0];
  if (hypre_ParCSRMatrixCommPkg(A) == NULL) hypre_MatvecCommPkgCreate(A);
  v_ext = level_halo(A, xx, c, &b1, &b2);
  /* -(0 - sum_j a_ij x_j), the off-rank part first as in the residual */
  for (i = 0; i < n; i++)
  {
    HYPRE_Real r = 0.0;
    if (da_s != NULL)
    {
      if (has_offd) r = row_rest_up_s(oi, oj, oa_s, v_ext, i, 0.0);
      yy[i] = -row_rest_up_s(di, dj, da_s, xx, i, r);
    }
    else
    {
      if (has_offd) r = row_rest_up(oi, oj, oa, v_ext, i, 0.0);
      yy[i] = -row_rest_up(di, dj, da, xx, i, r);
    }
  }
  free(b1);
  free(b2);
  return 0;
}

int gb_amg_refresh_fine(void *solver, void *compact, void *par_a)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  gb_compact *c = (gb_compact *) compact;
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
  if (c != NULL)
  {
    /* the new matrix's halo may be larger than the old one's */
    if (!halo_room(c, &A, 1)) return 1;
    compact_level(c, A, 0);
  }
  return hypre_error_flag;
}

/* The coarse levels anew for the finest level's new matrix, with the
   interpolation of the last set-up: A_{l+1} = P_l^T A_l P_l (hypre's
   Galerkin product, the call of its set-up), their l1 norms, the coarsest
   level's gathered matrix for Gaussian elimination, and the single-
   What is saved against a new set-up: the strength graphs, the
   coarsening and the interpolation. */
int gb_amg_regalerkin(void *solver, void *par_a)
{
  hypre_ParAMGData *amg = (hypre_ParAMGData *) solver;
  hypre_ParCSRMatrix **A = hypre_ParAMGDataAArray(amg);
  hypre_ParCSRMatrix **P = hypre_ParAMGDataPArray(amg);
  hypre_Vector **l1 = hypre_ParAMGDataL1Norms(amg);
  const HYPRE_Int num_levels = hypre_ParAMGDataNumLevels(amg);
  hypre_ParCSRMatrix *An = (hypre_ParCSRMatrix *) par_a;
  MPI_Comm gs_comm = hypre_ParAMGDataNewComm(amg);
  HYPRE_Int l;
  int procs;
  if (num_levels < 2 || l1 == NULL) return 1;
  if (hypre_CSRMatrixNumRows(hypre_ParCSRMatrixDiag(An)) != hypre_VectorSize(l1[0])) return 1;
  MPI_Comm_size(hypre_ParCSRMatrixComm(An), &procs);
  A[0] = An;
  if (hypre_ParCSRMatrixCommPkg(An) == NULL) hypre_MatvecCommPkgCreate(An);
  for (l = 0; l < num_levels - 1; l++)
  {
    hypre_ParCSRMatrix *AH = NULL;
    hypre_BoomerAMGBuildCoarseOperatorKT(P[l], A[l], P[l], 0, &AH);
    if (AH == NULL) return 1;
    if (procs > 1 && hypre_ParCSRMatrixCommPkg(AH) == NULL) hypre_MatvecCommPkgCreate(AH);
    hypre_ParCSRMatrixSetNumNonzeros(AH);
    hypre_ParCSRMatrixSetDNumNonzeros(AH);
    hypre_ParCSRMatrixDestroy(A[l + 1]);
    A[l + 1] = AH;
  }
  /* the l1 norms hypre's set-up computes for relax types 13 and 14 */
  for (l = 0; l < num_levels - 1; l++)
  {
    HYPRE_Real *norms = NULL;
    hypre_ParCSRComputeL1Norms(A[l], 4, NULL, &norms);
    memcpy(hypre_VectorData(l1[l]), norms, sizeof(HYPRE_Real) * (size_t) hypre_VectorSize(l1[l]));
    hypre_TFree(norms, HYPRE_MEMORY_HOST);
  }
  /* the coarsest level's dense copy, gathered anew (hypre_GaussElimSetup) */
  hypre_TFree(hypre_ParAMGDataAMat(amg), HYPRE_MEMORY_HOST);
  hypre_TFree(hypre_ParAMGDataBVec(amg), HYPRE_MEMORY_HOST);
  hypre_TFree(hypre_ParAMGDataCommInfo(amg), HYPRE_MEMORY_HOST);
  hypre_ParAMGDataAMat(amg) = NULL;
  hypre_ParAMGDataBVec(amg) = NULL;
  hypre_ParAMGDataCommInfo(amg) = NULL;
  if (gs_comm != hypre_MPI_COMM_NULL) hypre_MPI_Comm_free(&gs_comm);
  hypre_ParAMGDataNewComm(amg) = hypre_MPI_COMM_NULL;
  hypre_GaussElimSetup(amg, num_levels - 1, COARSE_TYPE);
  return hypre_error_flag;
}
