#!/usr/bin/env bash
# Every variable of the parameter registry, walked. Good decks that together
# use every physics and every deck group are resolved by geoblock --check
# (every variable of every group the run uses, set or not: the registry's
# written deck, itself a deck). For each group and variable (the first place
# it appears), copies of that resolved deck set it to nan (in the last place
# of its list, before a comment), to inf (the first place) and to a quoted
# string left open; geoblock --check must refuse each within 20 s with exit
# status 2 and one "geoblock: error:" line naming the group (and the line it
# starts on) and the variable. A string, logical or list of strings only gets
# the open string.
set -u
cd "$(dirname "$0")/../.."
exe=${GEOBLOCK:-bin/geoblock}
out=build/test-out/registry_walk
rm -rf "$out"; mkdir -p "$out/cases"
decks="input/gmsh_block.nml tests/decks/reservoir_small.nml tests/decks/hi24l_small.nml tests/decks/flow_split.nml"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
start=$(date +%s)

# the resolved decks; each must pass --check itself, or its walk means nothing
k=0; bases=""
for d in $decks; do
  k=$((k + 1))
  if timeout 20 "$exe" --check "$d" > "$out/base_$k.nml" 2> "$out/base_$k.err" < /dev/null && \
     timeout 20 "$exe" --check "$out/base_$k.nml" > /dev/null 2>&1 < /dev/null; then
    ok "$d: resolved ($(head -1 "$out/base_$k.nml" | sed 's/.*(physics \(.*\))/physics \1/'), $(grep -c '^&' "$out/base_$k.nml") groups), and the resolved deck is valid"
    bases="$bases $out/base_$k.nml"
  else
    ko "$d: --check fails on it or on its resolved deck, see $out/base_$k.err"
  fi
done
[ -n "$bases" ] || { echo "suite registry_walk: $pass passed, $((fail + 1)) failed"; exit 1; }

# every physics and every group of --help is walked
# shellcheck disable=SC2086
for p in elasticity biot contact fracture_flow; do
  if grep -q "(physics $p)" $bases; then ok "physics $p walked"; else ko "no deck of physics $p"; fi
done
missing=""
for g in $("$exe" --help | sed -n 's/^  &\([a-z_]*\).*/\1/p'); do
  # shellcheck disable=SC2086
  grep -qx "&$g" $bases || missing="$missing &$g"
done
if [ -z "$missing" ]; then ok "every group of geoblock --help is walked"; else ko "groups not walked:$missing"; fi

# the variables: "file line group group_line name set kind value", at the
# first place each group and name appears. A variable line is "  name = value
# ! [unit] meaning", or "  ! name = shown  [unit] meaning" when not set; a value
# too long for one line goes on over the next lines (its comment is above it).
# shellcheck disable=SC2086
awk '
  /^&/ { g = substr($1, 2); gline = FNR; next }
  /^\// { g = ""; next }
  g != "" && match($0, /^  (! )?[a-z_0-9]+(\([0-9]+\))? *= /) {
    head = substr($0, 1, RLENGTH); v = substr($0, RLENGTH + 1)
    set = (head !~ /^  ! /)
    name = head; sub(/^  (! )?/, "", name); sub(/ *= $/, "", name)
    if ((g, name) in have) next
    have[g, name] = 1
    if (set) sub(/ +! \[.*$/, "", v); else sub(/ +\[.*$/, "", v)
    kind = "number"
    if (v ~ /^'\''/) kind = "string"
    else if (v ~ /^\.(true|false)\.$/) kind = "logical"
    else if (!set) kind = "unset"
    print FILENAME, FNR, g, gline, name, set, kind, v
  }
' $bases > "$out/variables.txt"
n_var=$(wc -l < "$out/variables.txt")
n_group=$(awk '{print $3}' "$out/variables.txt" | sort -u | wc -l)

# mutate FILE LINE TEXT > deck: line LINE replaced by TEXT, and the lines a
# value went on over (after a line ending in ',') dropped
mutate() {
  awk -v L="$2" -v T="$3" '
    NR == L { print T; cont = ($0 ~ /, *$/); next }
    cont && NR > L && $0 !~ /=/ && $0 !~ /^[\/&]/ && $0 !~ /^ *!/ { cont = ($0 ~ /, *$/); next }
    { cont = 0; print }
  ' "$1"
}
nans=(nan NaN -nan 'NaN(0x1)'); infs=(inf -Inf +Infinity INFINITY)
n_case=0
while read -r file line g gline name set kind value; do
  base=${name%%(*}
  comment=$(sed -n "${line}p" "$file" | sed -n 's/^[^[]*\(\[.*\)$/! \1/p')
  cases="string"
  [ "$kind" = number ] || [ "$kind" = unset ] && cases="nan inf string"
  for c in $cases; do
    n_case=$((n_case + 1))
    i=$((n_case % 4))
    case $c in
      nan)  # the last place of a list, then a comment
        if [[ $value == *", "* ]]; then v="${value%, *}, ${nans[$i]}"; else v=${nans[$i]}; fi
        text="  $name = $v $comment" ;;
      inf)  # the first place
        if [[ $value == *", "* ]]; then v="${infs[$i]}, ${value#*, }"; else v=${infs[$i]}; fi
        text="  $name = $v" ;;
      string)
        text="  $name = 'walked $comment" ;;
    esac
    mutate "$file" "$line" "$text" > "$out/cases/$n_case.nml"
    printf '%s\t%s\t%s\t%s\t%s\n' "$n_case" "$g" "$gline" "$base" "$c $name" >> "$out/cases.txt"
  done
done < "$out/variables.txt"

# one case: exit status 2, one error line naming the group, its line and the variable
one() {
  local id=$1 g=$2 gline=$3 base=$4 what=$5 rc err n
  # its own Open MPI session directory (two cases run at once: in the shared
  # default one, a job that ends removes the tree the other creates its
  # directory in; Open MPI 4.x, open-mpi/ompi#8510)
  mkdir -p "$ompi_tmp/$id"
  OMPI_MCA_orte_tmpdir_base=$ompi_tmp/$id timeout 20 "$exe" --check "$out/cases/$id.nml" > /dev/null \
    2> "$out/cases/$id.err" < /dev/null
  rc=$?
  rm -rf "${ompi_tmp:?}/$id"
  err=$(grep '^geoblock: error: ' "$out/cases/$id.err")
  n=$(grep -c '^geoblock: error: ' "$out/cases/$id.err")
  if [ "$rc" -eq 124 ]; then
    echo "  FAIL  &$g $what: hung (timeout 20 s)"
  elif [ "$rc" -ne 2 ] || [ "$n" -ne 1 ]; then
    echo "  FAIL  &$g $what: exit status $rc, $n error lines: $(head -c 300 "$out/cases/$id.err")"
  elif grep -qiE 'backtrace|#0 |SIGSEGV|Floating-point exception|^STOP' "$out/cases/$id.err"; then
    echo "  FAIL  &$g $what: a backtrace or signal: $(head -c 300 "$out/cases/$id.err")"
  elif ! grep -qF "group &$g (line $gline)" <<< "$err" || ! grep -qE "variable ($base[(:]|'$base')" <<< "$err"; then
    echo "  FAIL  &$g $what: the message does not name group &$g (line $gline) and variable $base: $err"
  else
    echo "  ok    &$g $what: ${err#*, variable }" | cut -c1-160
  fi
}
export -f one
ompi_tmp=$(mktemp -d)
trap 'rm -rf "$ompi_tmp"' EXIT
export exe out ompi_tmp
# two at a time (most of a case is MPI's start-up)
xargs -P 2 -n 1 -d '\n' bash -c 'IFS=$'"'"'\t'"'"' read -r id g gline base what <<< "$0"; one "$id" "$g" "$gline" "$base" "$what" > "$out/cases/$id.out"' \
  < "$out/cases.txt"
for ((i = 1; i <= n_case; i++)); do
  if [ -f "$out/cases/$i.out" ] && grep -q '^  ok' "$out/cases/$i.out"; then
    pass=$((pass + 1)); cat "$out/cases/$i.out"
  else
    fail=$((fail + 1)); cat "$out/cases/$i.out" 2> /dev/null || echo "  FAIL  case $i: not run"
  fi
done
[ "$n_var" -gt 0 ] && ok "walked $n_var variables of $n_group groups: $n_case cases in $(( $(date +%s) - start )) s" || \
  ko "no variable found in the resolved decks"
echo "suite registry_walk: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
