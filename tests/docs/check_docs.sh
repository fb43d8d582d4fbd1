#!/usr/bin/env bash
# The documentation cannot go stale unnoticed:
#  1. every relative link (file and #anchor) of README.md and doc/**/*.md
#     resolves, and every deck block tied to a file (<!-- deck: PATH -->)
#     equals that file (tests/docs/check_links.py);
#  2. every deck in input/ and doc/ (*.nml) passes `geoblock --check`
#     (paths in a deck are relative to its own directory, so each is
#     checked where it lies);
#  3. doc/reference/decks.md is what `geoblock --reference` writes now
#     (make reference rewrites it), and `--help GROUP` gives every group of
#     it; an unknown group and a deck given to --reference are refused.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
exe=${GEOBLOCK:-bin/geoblock}
out=build/test-out/docs
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

# 1. links and deck blocks
pages=$(ls README.md; find doc -name '*.md' | sort)
$PY tests/docs/check_links.py $pages > "$out/links.log" 2>&1
grep -E '^  (ok|FAIL)' "$out/links.log"
p=$(grep -c '^  ok' "$out/links.log"); f=$(grep -c '^  FAIL' "$out/links.log")
pass=$((pass + p)); fail=$((fail + f))
[ "$p" -gt 0 ] || ko "the link check ran on no page: $(tail -3 "$out/links.log")"

# 2. every deck in input/ and doc/ passes --check
n=0; bad=""
for deck in $(find input doc -name '*.nml' | sort); do
  n=$((n + 1))
  if ! timeout 60 "$exe" --check "$deck" > "$out/check.out" 2> "$out/check.err" < /dev/null; then
    bad="$bad $deck ($(head -1 "$out/check.err"))"
  fi
done
if [ -z "$bad" ] && [ "$n" -gt 0 ]; then ok "--check accepts all $n decks of input/ and doc/"; else ko "--check refuses:$bad"; fi

# 3. the deck reference is up to date
if timeout 60 "$exe" --reference > "$out/decks.md" 2> "$out/reference.err" < /dev/null; then
  if diff -u doc/reference/decks.md "$out/decks.md" > "$out/reference.diff"; then
    ok "doc/reference/decks.md is what geoblock --reference writes ($(wc -l < "$out/decks.md") lines)"
  else
    ko "doc/reference/decks.md is stale: run make reference and commit it (diff: $out/reference.diff, $(grep -c '^[-+][^-+]' "$out/reference.diff") lines differ)"
  fi
else
  ko "geoblock --reference failed: $(head -3 "$out/reference.err")"
fi
missing=""
for g in $(grep -E '^## &' doc/reference/decks.md | sed 's/^## &//'); do
  timeout 60 "$exe" --help "$g" > "$out/help.out" 2>&1 < /dev/null && grep -q "^&$g:" "$out/help.out" || missing="$missing $g"
done
if [ -z "$missing" ]; then ok "--help GROUP prints every group of the reference"; else ko "--help GROUP fails for:$missing"; fi
if timeout 60 "$exe" --help no_such_group > /dev/null 2> "$out/help.err" < /dev/null; then
  ko "--help no_such_group was accepted"
elif [ $? -eq 2 ] && grep -q "geoblock: error: --help: no deck group 'no_such_group'" "$out/help.err"; then
  ok "--help no_such_group: exit 2, $(head -c 80 "$out/help.err")..."
else
  ko "--help no_such_group: $(cat "$out/help.err")"
fi
if timeout 60 "$exe" --reference input/cube.nml > /dev/null 2> "$out/ref.err" < /dev/null; then
  ko "--reference with a deck was accepted"
elif grep -q "takes no deck" "$out/ref.err"; then
  ok "--reference with a deck: refused with one line"
else
  ko "--reference with a deck: $(cat "$out/ref.err")"
fi

echo "suite check_docs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
