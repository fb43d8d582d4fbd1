#!/usr/bin/env bash
# Strong scaling (issue 15): the same problem on 1 and 2 ranks (this
# machine has 2 cores), with the wall times of the timing summary:
#   mandel   Mandel at the seed's size (80 x 80 x 8 cells, 389,627 unknowns),
#            one step with gamma = dt = 1 s, FGMRES + the default implicit
#            block preconditioner to 1e-8 (as bench/run_bench_biot.sh makes it)
#   contact  the fault in a block at n = 40 (tests/decks/contact_block.nml,
#            the 'slip' mix: friction 10 degrees), FGMRES + the reordered
#            preconditioner to 1e-8 (as bench/run_bench_contact.sh makes it)
# (the AMG alone, CG + BoomerAMG on the cube of 823,875 unknowns on 1 and 2
# ranks, is in bench/run_bench.sh's table)
# Per case and rank count: iterations, mesh (made and partitioned on rank
# 0), assembly, preconditioner set-up, linear solve, total, peak resident
# memory of a rank; then the speed-up
# total(1) / total(N) and the parallel efficiency speed-up / N.
# Usage: bench/run_bench_scaling.sh [cases] [ranks]
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
cases=${1:-"mandel contact"}
ranks=${2:-"1 2"}
out=build/bench/scaling
mkdir -p "$out"
table=build/bench/scaling.md
echo "| case | ranks | iterations | mesh [s] | assembly [s] | set-up [s] | solve [s] | total [s] | speed-up | efficiency | peak memory of a rank [MB] |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|---|---|" >> "$table"

deck() {  # case -> deck on stdout
  case $1 in
    mandel)
      sed -e "s#nx = 20, ny = 20, nz = 1#nx = 80, ny = 80, nz = 8#" \
          -e "s#upper = 1.0, 1.0, 0.05#upper = 1.0, 1.0, 0.1#" \
          -e "s#dt = 0.05, t_end = 200.0, dt_growth = 1.12, dt_max = 5.0#dt = 1, t_end = 1, undrained = .false.#" \
          -e "s#dir = 'out', prefix = 'mandel'#dir = '$out/mandel', prefix = 'mandel', fields = .false.#" \
          -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" input/mandel.nml ;;
    contact)
      sed -e "s/nx = 12, ny = 12, nz = 12/nx = 40, ny = 40, nz = 40/" \
          -e "s/method = 'mumps'/method = 'fgmres', rtol = 1.0e-8/" -e "s/n_steps = 2/n_steps = 1/" \
          -e "s#prefix = 'contact_block'#prefix = 'contact', fields = .false.#" \
          -e "s#dir = 'out'#dir = '$out/contact'#" tests/decks/contact_block.nml ;;
  esac
}

summary() {  # log label -> seconds of that timing-summary line
  awk -v k="$2" '/^timing summary/ {on = 1; next}
    on && substr($0, 3, length(k)) == k && substr($0, 3 + length(k), 1) == " " {print $(NF - 2); exit}' "$1"
}

for c in $cases; do
  t1=""
  for np in $ranks; do
    name=${c}_np$np
    deck "$c" > "$out/$name.nml"
    mpirun -np "$np" bin/geoblock "$out/$name.nml" > "$out/$name.log" 2>&1 < /dev/null
    log=$out/$name.log
    if ! grep -q '^timing summary' "$log"; then
      echo "| $c | $np | failed: $(grep -m1 -i 'error' "$log" | cut -c1-100) | | | | | | | | |" | tee -a "$table"
      continue
    fi
    case $c in
      contact) its=$(grep -E '^  newton' "$log" | awk '{printf "%s ", $5}' | sed 's/ $//') ;;
      *)       its=$(grep -m1 -E '^step +1 ' "$log" | sed -E 's/.*iterations +([0-9]+).*/\1/') ;;
    esac
    setup=$(summary "$log" 'preconditioner set-up')
    solve=$(summary "$log" 'linear solve')
    asm=$(summary "$log" 'assembly')
    mesh=$(summary "$log" 'mesh')
    total=$(summary "$log" 'total')
    mem=$(grep -m1 '^peak resident memory' "$log" | sed -E 's/peak resident memory: ([0-9]+) MB on the largest rank.*/\1/')
    [ -z "$t1" ] && t1=$total
    sp=$(awk -v a="$t1" -v b="$total" 'BEGIN {printf "%.2f", a / b}')
    eff=$(awk -v a="$t1" -v b="$total" -v n="$np" -v n1="${ranks%% *}" 'BEGIN {printf "%.2f", a / b * n1 / n}')
    echo "| $c | $np | $its | $mesh | $asm | $setup | $solve | $total | $sp | $eff | $mem |" | tee -a "$table"
  done
done
echo "table: $table"
