#!/usr/bin/env bash
# The contact preconditioners' diagnostics (make bench-large): the variants
# of bench/run_bench_contact.sh that take the preconditioners apart rather
# than the ones a user runs: a stronger BoomerAMG (to separate the AMG's own
# growth from the contact's) and S* solved by an inner CG to 1e-10 (the
# growth of the Schur approximation alone), for the reordered preconditioner
# and for the augmented one on the bubble space, with aug_scale 0.5 and 2
# beside the default for the latter, and both with BoomerAMG's W-cycle
# (W(1,1) and W(3,3)), and S* by two CG steps (schur_solve = 'pcg');
# 5 levels, 3 mixes, no MUMPS.
# Tables: build/bench/contact_diagnostics.md, contact_diagnostics_growth.md.
# Usage: bench/run_bench_contact_diagnostics.sh [levels] [ranks]
set -u
cd "$(dirname "$0")/.."
TABLE_TAG=contact_diagnostics bash bench/run_bench_contact.sh "${1:-8 16 24 32 40}" "${2:-2}" \
  "reordered_strong_amg reordered_inner_cg bubble_augmented_strong_amg bubble_augmented_inner_cg \
bubble_augmented_inner_cg_0.5 bubble_augmented_inner_cg_2 reordered_wcycle bubble_augmented_wcycle reordered_w3 bubble_augmented_w3 \
reordered_pcg bubble_augmented_pcg" \
  "stick slip open" "none"
