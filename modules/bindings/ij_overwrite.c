/*
 * New values into an assembled hypre IJ matrix whose pattern is the same,
 * written where hypre's assembly put them (hypre 2.26), without a new IJ
 * matrix.
 *
 * hypre_ij's build_matrix sizes the diagonal and off-diagonal blocks row
 * by row (HYPRE_IJMatrixSetDiagOffdSizes) and gives every row once. hypre
 * then stores a row's entries in the order given, those of the rank's own
 * columns in the diagonal block and the others in the off-diagonal one;
 * at assembly it swaps the diagonal entry with the first of the diagonal
 * block (hypre_IJMatrixAssembleParCSR) and numbers the off-rank columns by
 * their place in the sorted column map. The same rows given again in the
 * same order therefore land in known places: gb_ij_overwrite writes them
 * there and checks every entry's column against the one stored in that
 * place, so a row whose pattern changed (or a hypre that places entries
 * otherwise) is found, never written into the wrong place. What the new
 * IJ matrix cost and this saves (hypre_ij's rebuild_rows): its allocation
 * and fresh pages, the assembly's sort of the off-rank columns and their
 * binary searches, and a first pass over the rows for the block sizes.
 *
 * gb_ij_overwrite(par_a, nrows, ncols, rows, cols, values)
 *     rows[r] (0-based global ids, owned) with ncols[r] entries each,
 *     their 0-based global columns and values one row after another (as
 *     HYPRE_IJMatrixSetValues takes them): 0 when every entry was written,
 *     1 at the first row that does not fit the stored pattern (the rows
 *     before it are written, the rest not: the caller builds anew).
 */
#include "_hypre_parcsr_mv.h"

int gb_ij_overwrite(void *par_a, HYPRE_Int nrows, const HYPRE_Int *ncols, const HYPRE_BigInt *rows,
                    const HYPRE_BigInt *cols, const HYPRE_Real *values)
{
  hypre_ParCSRMatrix *A = (hypre_ParCSRMatrix *) par_a;
  hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(A), *offd = hypre_ParCSRMatrixOffd(A);
  const HYPRE_Int *di = hypre_CSRMatrixI(diag), *dj = hypre_CSRMatrixJ(diag);
  const HYPRE_Int *oi = hypre_CSRMatrixI(offd), *oj = hypre_CSRMatrixJ(offd);
  HYPRE_Real *da = hypre_CSRMatrixData(diag), *oa = hypre_CSRMatrixData(offd);
  const HYPRE_BigInt *cmap = hypre_ParCSRMatrixColMapOffd(A);
  const HYPRE_BigInt row0 = hypre_ParCSRMatrixFirstRowIndex(A);
  const HYPRE_BigInt col0 = hypre_ParCSRMatrixFirstColDiag(A), col1 = hypre_ParCSRMatrixLastColDiag(A);
  const HYPRE_Int n_local = hypre_CSRMatrixNumRows(diag);
  HYPRE_Int r, e, k = 0;
  for (r = 0; r < nrows; r++)
  {
    const HYPRE_BigInt gi = rows[r];
    const HYPRE_Int i = (HYPRE_Int) (gi - row0), n = ncols[r];
    HYPRE_Int pd, po, d_slot = -1, swap;
    if (gi < row0 || i >= n_local) return 1;
    /* the slot the diagonal entry took before the assembly's swap */
    pd = di[i];
    for (e = 0; e < n; e++)
    {
      const HYPRE_BigInt c = cols[k + e];
      if (c < col0 || c > col1) continue;
      if (c == gi)
      {
        d_slot = pd;
        break;
      }
      pd++;
    }
    pd = di[i];
    po = oi[i];
    for (e = 0; e < n; e++, k++)
    {
      const HYPRE_BigInt c = cols[k];
      if (c >= col0 && c <= col1)
      {
        if (pd >= di[i + 1]) return 1;
        swap = pd;
        if (d_slot >= 0 && pd == d_slot) swap = di[i];
        else if (d_slot >= 0 && pd == di[i]) swap = d_slot;
        if ((HYPRE_BigInt) dj[swap] != c - col0) return 1;
        da[swap] = values[k];
        pd++;
      }
      else
      {
        if (po >= oi[i + 1] || cmap == NULL || cmap[oj[po]] != c) return 1;
        oa[po] = values[k];
        po++;
      }
    }
    if (pd != di[i + 1] || po != oi[i + 1]) return 1;
  }
  return 0;
}
