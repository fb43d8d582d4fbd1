#!/usr/bin/env bash
# Rank independence of geoblock's adaptive FSAI and block-FSAI decoupling
# factors: test_afsai and test_block_fsai write their factors (by keys) on
# 1, 2 and 3 ranks (3 oversubscribed; each rank count numbers the rows
# differently and perturbs the values by a few ulps); the factors must have
# exactly the same pattern and values within 1e-10 of the largest entry of
# each factor. Builds nothing: run after `make tests`.
set -u
cd "$(dirname "$0")/../../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/fsai_ranks
rm -rf "$out"
mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

for prog in test_afsai test_block_fsai; do
  if [ ! -x "bin/tests/$prog" ]; then
    ko "$prog: bin/tests/$prog is missing (make tests)"
    continue
  fi
  for np in 1 2 3; do
    if timeout 600 mpirun --oversubscribe -np $np "bin/tests/$prog" "$out/$prog.np$np.txt" \
         > "$out/$prog.np$np.log" 2>&1 < /dev/null; then
      ok "$prog on $np rank(s)"
    else
      ko "$prog on $np rank(s), see $out/$prog.np$np.log"
    fi
  done
  for np in 2 3; do
    if r=$($PY - "$out/$prog.np1.txt" "$out/$prog.np$np.txt" 1e-10 <<'PY' 2>&1
import sys
import numpy as np

def blocks(path):
    """The factors of a file: {title: (row keys, column keys, values)}, in file order."""
    out, title, rows = {}, None, []
    def close():
        if title is not None:
            a = np.array(rows, dtype=float).reshape(-1, 3)
            out[title] = (a[:, 0].astype(np.int64), a[:, 1].astype(np.int64), a[:, 2])
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                close()
                title, rows = line[1:].strip(), []
            elif line.strip():
                k1, k2, v = line.split()
                rows.append((int(k1), int(k2), float(v)))
    close()
    return out

ref, new = blocks(sys.argv[1]), blocks(sys.argv[2])
tol = float(sys.argv[3])
bad = list(ref) != list(new) or not ref
msgs = [] if not bad else ["different factors: %s vs %s" % (list(ref), list(new))]
for t in ref:
    if t not in new:
        continue
    (r1, c1, v1), (r2, c2, v2) = ref[t], new[t]
    if len(r1) != len(r2) or np.any(r1 != r2) or np.any(c1 != c2):
        same = 0
        if len(r1) == len(r2):
            same = int(np.sum((r1 == r2) & (c1 == c2)))
        msgs.append("%s: patterns differ (%d vs %d entries, %d in the same place)" % (t, len(r1), len(r2), same))
        bad = True
        continue
    err = np.max(np.abs(v1 - v2)) / np.max(np.abs(v1))
    msgs.append("%s: %d entries, same pattern, max difference %.1e of the largest entry" % (t, len(r1), err))
    if not err <= tol:
        bad = True
print("; ".join(msgs))
sys.exit(1 if bad else 0)
PY
    ); then
      ok "$prog 1 vs $np ranks: $r"
    else
      ko "$prog 1 vs $np ranks: $r"
    fi
  done
done
echo "suite fsai_ranks: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
