#!/usr/bin/env bash
# make bench: every benchmark script in turn, each timed, then one report,
# build/bench/REPORT.md: the machine, the date, the commit, each script's
# wall time and every table it wrote (build/bench/<name>.md), in the order
# they ran. The README's benchmark tables are copied from one such report.
# Usage: bench/run_all.sh [script ...]   (default: all, in the order below)
set -u
cd "$(dirname "$0")/.."
# the longest last: the seed's large cases (the full HI24L: some 16 GB, 31 min)
scripts=${*:-"run_bench.sh run_bench_biot.sh run_bench_peers.sh run_bench_scaling.sh run_bench_contact.sh \
run_bench_fsai.sh run_bench_flow.sh run_bench_standins.sh run_bench_hi24l.sh"}
mkdir -p build/bench
times=build/bench/durations.txt
: > "$times"
start=$(date -u '+%Y-%m-%d %H:%M UTC')
report=build/bench/REPORT.md
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
    echo "| script | wall time [s] |"
    echo "|---|---|"
    while read -r s t; do echo "| $s | $t |"; done < "$times"
    for s in $(cut -d' ' -f1 "$times"); do
      for table in $(grep -ho '\(build/bench\|\$out\)/[a-z_]*\.md' "bench/$s" | sed 's#^\$out/#build/bench/#' | sort -u); do
        [ -f "$table" ] || continue
        echo
        echo "## $(basename "$table" .md) (bench/$s)"
        echo
        cat "$table"
      done
    done
  } > "$report"
}
for s in $scripts; do
  t0=$(date +%s)
  echo "== bench/$s ($(date -u '+%H:%M:%S UTC'))"
  bash "bench/$s"
  echo "$s $(( $(date +%s) - t0 ))" >> "$times"
  write_report
done
echo "report: $report"
