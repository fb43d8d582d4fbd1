#!/usr/bin/env bash
# make bench / make bench-large: benchmark scripts in turn, each timed, then
# one report: the machine, the date, the commit, each script's wall time and
# every table it wrote (the files its last "table:" or "tables:" line names),
# in the order they ran. doc/benchmarks.md is the REPORT.md of the last
# make bench run, copied over (doc/development.md).
#   standard (make bench, build/bench/REPORT.md, about 1.5-2 hours here):
#     elasticity, Mandel and the seed's explicit/implicit table, the peers
#     on the same systems, strong scaling, contact on 5 levels with the
#     four contact preconditioners a user runs, aFSAI against hypre's FSAI,
#     the robustness matrix, the solve phase's bandwidth against the triad
#   large (make bench-large, build/bench/REPORT_large.md, about 3.5 hours
#     here): the contact preconditioners' diagnostics (stronger AMG, exact
#     inner solves of S*), the fluid in the fractures on 4 and 2 m cells
#     (MUMPS: 11 minutes of factorizations), the Treporti and Reservoir
#     stand-ins at the seed's sizes, HI24L up to its full size (16 GB),
#     poromechanics with faults on 8^3 to 32^3 cells (MUMPS at 32^3: about
#     20 minutes of factorizations), the coupled field case
# The two tiers together took more than this machine's 3-hour sessions;
# each fits in one.
# Usage: bench/run_all.sh [standard | large | script ...]   (default: standard)
set -u
cd "$(dirname "$0")/.."
standard="run_bench.sh run_bench_biot.sh run_bench_peers.sh run_bench_scaling.sh run_bench_contact.sh run_bench_fsai.sh run_bench_robustness.sh run_bench_bandwidth.sh"
large="run_bench_contact_diagnostics.sh run_bench_flow.sh run_bench_standins.sh run_bench_hi24l.sh run_bench_poro_faults.sh run_bench_field_coupled.sh"
report=build/bench/REPORT.md
case "${1:-standard}" in
  standard) scripts=$standard ;;
  large)    scripts=$large; report=build/bench/REPORT_large.md ;;
  *)        scripts=$*; report=build/bench/REPORT_partial.md ;;
esac
for s in $scripts; do
  [ -f "bench/$s" ] || { echo "run_all.sh: error: no benchmark script bench/$s" >&2; exit 2; }
done
mkdir -p build/bench
times=${report%.md}_durations.txt
: > "$times"
start=$(date -u '+%Y-%m-%d %H:%M UTC')
# the report, rewritten after every script: a run stopped part way leaves
# the tables of the scripts that finished
write_report() {
  {
    echo "# geoblock benchmark report"
    echo
    echo "- started $start, ended $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "- commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with local changes)')"
    echo "- machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores," \
         "$(awk '/MemTotal/ {printf "%.1f GiB", $2 / 1048576}' /proc/meminfo), load average at the end" \
         "$(cut -d' ' -f1-3 /proc/loadavg)"
    echo
    echo "| script | wall time [s] | exit status |"
    echo "|---|---|---|"
    while read -r s t rc; do echo "| $s | $t | $rc |"; done < "$times"
    while read -r s t rc; do
      for table in $(grep -E '^tables?: ' "build/bench/${s%.sh}.out" 2>/dev/null | tail -1 | cut -d: -f2-); do
        [ -f "$table" ] || continue
        echo
        echo "## $(basename "$table" .md) (bench/$s)"
        echo
        cat "$table"
      done
    done < "$times"
  } > "$report"
}
for s in $scripts; do
  t0=$(date +%s)
  echo "== bench/$s ($(date -u '+%H:%M:%S UTC'))"
  bash "bench/$s" 2>&1 | tee "build/bench/${s%.sh}.out"
  rc=${PIPESTATUS[0]}
  echo "$s $(( $(date +%s) - t0 )) $rc" >> "$times"
  write_report
done
echo "report: $report"
