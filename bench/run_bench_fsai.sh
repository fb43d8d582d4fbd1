#!/usr/bin/env bash
# FSAI benchmark (issue 4): our adaptive FSAI against hypre's FSAI
# (HYPRE_FSAI*, hypre 2.26) on the same elastic stiffness matrix (the clamped
# cube of bench/run_bench.sh, n = 40: 206,763 unknowns), with the same
# adaptive settings (start from the diagonal, max_steps x step_size entries
# at most per row), on 1 and 2 ranks: non-zeros of G, time of one application
# (mean of 20, measured by the program after set-up), set-up time, CG
# iterations and solve time to 1e-8. hypre does not report the non-zeros of
# its factor; the bound max_steps * step_size + 1 per row is given instead.
# Usage: bench/run_bench_fsai.sh [n] [ranks] [settings "steps:size ..."]
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
n=${1:-40}
ranks=${2:-"1 2"}
settings=${3:-"3:5 5:5 10:5"}
out=build/bench
mkdir -p "$out"
table=$out/fsai.md
echo "| unknowns | ranks | preconditioner | steps x size | nnz(G) per row | one application [ms] | set-up [s] | CG iterations | solve [s] |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|" >> "$table"
for np in $ranks; do
  for st in $settings; do
    steps=${st%%:*}; size=${st##*:}
    for p in afsai hypre_fsai; do
      name=fsai_${n}_${p}_${steps}x${size}_np${np}
      sed -e "s#nx = 16, ny = 16, nz = 16#nx = $n, ny = $n, nz = $n#" \
          -e "s#n_steps = 2 .*#n_steps = 1#" \
          -e "s#precon = 'boomeramg'#precon = '$p', max_iter = 5000#" \
          -e "s#dir = 'out'.*#dir = '$out/$name', fields = .false.#" \
          input/cube.nml > "$out/$name.nml"
      printf "&afsai\n  max_steps = %s, step_size = %s, tol = 1.0e-3, init = 'diagonal'\n/\n" "$steps" "$size" >> "$out/$name.nml"
      log=$out/$name.log
      mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1 < /dev/null
      unk=$(grep -m1 'displacement dofs' "$log" | sed -E 's/.*dofs: ([0-9]+).*/\1/')
      if [ "$p" = afsai ]; then
        per=$(grep -m1 'aFSAI:' "$log" | sed -E 's/.*\( *([0-9.]+) per row.*/\1/')
        app=$(grep -m1 'aFSAI:' "$log" | sed -E 's/.*application +([0-9.eE+-]+) ms.*/\1/')
      else
        per="<= $((steps * size + 1))"
        app=$(grep -m1 'hypre FSAI:' "$log" | sed -E 's/.*application +([0-9.eE+-]+) ms.*/\1/')
      fi
      step=$(grep -m1 '^step' "$log")
      its=$(echo "$step" | sed -E 's/.*iterations +([0-9]+).*/\1/')
      setup=$(echo "$step" | sed -E 's/.*setup +([0-9.]+) s.*/\1/')
      solve=$(echo "$step" | sed -E 's/.*solve +([0-9.]+) s.*/\1/')
      printf '| %s | %s | %s | %s x %s | %s | %s | %s | %s | %s |\n' "$unk" "$np" "$p" "$steps" "$size" "$per" "$app" \
        "$setup" "$its" "$solve" | tee -a "$table"
    done
  done
done
echo "table: $table"
