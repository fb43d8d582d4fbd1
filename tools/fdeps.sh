#!/usr/bin/env bash
# Generate make dependencies between Fortran objects from their module and
# use statements.  Usage: fdeps.sh OBJDIR file.f90 ...
# For each file: OBJDIR/name.o depends on the objects of the project modules it
# uses; a program's object also lands in the list of objects that provide modules.
objdir=$1; shift
awk -v objdir="$objdir" '
  function base(f,   b) { b = f; sub(/.*\//, "", b); sub(/\.[fF]90$/, "", b); return b }
  FNR == 1 { file = FILENAME }
  {
    line = tolower($0)
    sub(/!.*/, "", line)
    if (match(line, /^[ \t]*module[ \t]+[a-z0-9_]+[ \t]*$/)) {
      split(line, w, /[ \t]+/); m = (w[1] == "" ? w[3] : w[2])
      if (m != "procedure") provider[m] = base(file)
    }
    if (match(line, /^[ \t]*use[ \t,]+/)) {
      s = line
      sub(/^[ \t]*use[ \t]*(,[ \t]*(non_)?intrinsic[ \t]*::)?[ \t]*/, "", s)
      sub(/^::[ \t]*/, "", s)
      split(s, w, /[ \t,]+/)
      uses[base(file)] = uses[base(file)] " " w[1]
    }
  }
  END {
    for (f in uses) {
      n = split(uses[f], u, " ")
      deps = ""
      for (i = 1; i <= n; i++) {
        if (u[i] in provider && provider[u[i]] != f && index(deps, " " objdir "/" provider[u[i]] ".o") == 0)
          deps = deps " " objdir "/" provider[u[i]] ".o"
      }
      if (deps != "") print objdir "/" f ".o:" deps
    }
  }
' "$@"
