#!/usr/bin/env python3
"""Write the verification report of a `make test` run (build/reports/verification.md).

Its sources, all written by the run:
  build/reports/suites.tsv        one row per suite run by tests/run_tests.sh:
                                  section, name, passed, failed, seconds, command
  build/test-logs/<name>.log      each suite's output: its `ok` / `FAIL` lines
  build/reports/verification.tsv  the figures the verification suites record
                                  (tests/common/vreport.sh, vreport.py): suite,
                                  case, quantity, error, tolerance, order, result

The report covers the suites of the "# verification" part of
tests/suites.txt: a summary (checks passed and failed, time), the recorded
figures (case, quantity, error, tolerance, observed order, pass/fail), and
every check line of every suite, with the error and tolerance read from the
line where it states them ("1.2e-3 (tol 1e-2)", "1.2e-3 <= 1e-2", "order
1.97 >= 1.9"). The header names the commit (and whether the tree had local
changes), the date and the machine.

usage: verification_report.py [--out FILE] [--command TEXT]
"""
import argparse
import csv
import datetime
import os
import re
import subprocess
import sys

NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
RE_TOL = re.compile(r"\((?:tol(?:erance)?|required)\s*(?:<=\s*)?([^)]*?)\)")
RE_LE = re.compile(r"(" + NUM + r")\s*(<=|<)\s*(" + NUM + r")(?!\s*[A-Za-z(])")
RE_GE = re.compile(r"(" + NUM + r")\s*>=\s*(" + NUM + r")")
RE_NUM = re.compile(NUM)


def sh(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=False).stdout.strip()
    except OSError:
        return ""


def commit_text():
    sha = sh(["git", "rev-parse", "--short", "HEAD"]) or "unknown"
    dirty = subprocess.run(["git", "diff", "--quiet", "HEAD"], check=False).returncode != 0
    return sha + (" with local changes" if dirty else "")


def machine_text():
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
        with open("/proc/meminfo") as f:
            mem = next(int(l.split()[1]) for l in f if l.startswith("MemTotal"))
        return f"{model}, {os.cpu_count()} cores, {mem / 1048576:.1f} GiB"
    except (OSError, StopIteration):
        return model or "unknown"


def verification_suites(suites_txt="tests/suites.txt"):
    """(name, command) of the suites of the '# verification' part."""
    out, section = [], ""
    with open(suites_txt) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0].startswith("#"):
                section = " ".join(w[1:]).lower()
                continue
            if not section.startswith("verification"):
                continue
            if w[0] == "script":
                name = os.path.splitext(os.path.basename(w[1]))[0]
            else:
                name = f"{w[1]}-np{w[0]}"
            out.append((name, " ".join(w)))
    return out


def about(command):
    """What the suite verifies, in a few words: the first sentence (up to a
    colon or a full stop outside parentheses) of its header comment (a
    script's leading comment, a test program's comment above `program`)."""
    w = command.split()
    try:
        if w[0] == "script":
            with open(w[1]) as f:
                lines = f.read().split("\n")
            text = []
            for line in lines:
                t = line.strip()
                if t.startswith("#!"):
                    continue
                if t.startswith("#"):
                    text.append(t.lstrip("#").strip())
                elif t.startswith('"""'):
                    text.append(t.strip('"').strip())
                    break
                elif text or t:
                    break
        else:
            found = [os.path.join(d, w[1] + ".f90") for d, _, fs in os.walk("tests") if w[1] + ".f90" in fs]
            with open(found[0]) as f:
                lines = f.read().split("\n")
            k = next(i for i, l in enumerate(lines) if re.match(r"^\s*program\s", l, re.I))
            j = k
            while j > 0 and lines[j - 1].strip().startswith("!>"):
                j -= 1
            text = [l.strip()[2:].strip() for l in lines[j:k]]
    except (OSError, IndexError, StopIteration):
        return ""
    joined = " ".join(t for t in text if t)
    depth = 0
    for i, ch in enumerate(joined):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0 and (ch == ":" or (ch == "." and (i + 1 == len(joined) or joined[i + 1] == " "))):
            return joined[:i]
    return joined[:160]


def figures_of(text):
    """(error, tolerance, order) a check line states, '' where it states none."""
    m = RE_TOL.search(text)
    if m:
        before = RE_NUM.findall(text[:m.start()])
        return (before[-1] if before else ""), m.group(1).strip(), ""
    m = RE_GE.search(text)
    if m and "order" in text.lower():
        return "", ">= " + m.group(2), m.group(1)
    m = RE_LE.search(text)
    if m:
        return m.group(1), m.group(3), ""
    return "", "", ""


def checks_of(log):
    """(result, text) of every ok / FAIL line of a suite log."""
    out = []
    try:
        with open(log, errors="replace") as f:
            for line in f:
                m = re.match(r"^\s*(ok|FAIL)\s+(.*)$", line.rstrip("\n"))
                if m:
                    out.append(("pass" if m.group(1) == "ok" else "FAIL", m.group(2).strip()))
    except OSError:
        pass
    return out


def cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="build/reports/verification.md")
    ap.add_argument("--command", default="make test")
    a = ap.parse_args()
    runs = {}
    if os.path.exists("build/reports/suites.tsv"):
        with open("build/reports/suites.tsv") as f:
            for row in csv.reader(f, delimiter="\t"):
                if len(row) >= 5:
                    runs[row[1]] = row
    figures = {}
    if os.path.exists("build/reports/verification.tsv"):
        with open("build/reports/verification.tsv") as f:
            for row in csv.reader(f, delimiter="\t", quoting=csv.QUOTE_NONE):
                if len(row) == 7:
                    figures.setdefault(row[0], []).append(row[1:])
    suites = verification_suites()
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = []
    total_p = total_f = 0
    summary = []
    for name, command in suites:
        checks = checks_of(f"build/test-logs/{name}.log")
        if name in runs:
            p, f, secs = int(runs[name][2]), int(runs[name][3]), runs[name][4]
        else:
            p, f, secs = sum(c[0] == "pass" for c in checks), sum(c[0] == "FAIL" for c in checks), ""
            if not checks:
                f = 1
        total_p += p
        total_f += f
        summary.append((name, command, p, f, secs, checks))
    lines += ["# Verification report", "",
              f"Written by `{a.command}` (tests/run_tests.sh runs the suites, then tools/verification_report.py "
              f"writes this page) on {now}, commit {commit_text()}, on {machine_text()}.", "",
              f"The {len(suites)} verification suites of `tests/suites.txt` ran {total_p + total_f} checks: "
              f"**{total_p} passed, {total_f} failed**. Each suite compares geoblock against analytical "
              "solutions or independent computations at stated tolerances; the tables below give the figures the "
              "suites record, then every check as the suite printed it.", "",
              "## Summary", "", "| suite | what it verifies | passed | failed | time [s] |", "|---|---|---|---|---|"]
    for name, command, p, f, secs, _ in summary:
        lines.append(f"| [{name}](#{name.lower()}) | {cell(about(command))} | {p} | {f} | {secs} |")
    lines += ["", "## Figures", "",
              "Case, quantity, error, tolerance (or the smallest order accepted), observed order and result, "
              "as the suites record them (`vreport` in tests/common/vreport.sh and vreport.py).", ""]
    any_fig = False
    for name, _, _, _, _, _ in summary:
        rows = figures.get(name, [])
        if not rows:
            continue
        any_fig = True
        lines += [f"### {name} figures", "", "| case | quantity | error | tolerance | order | result |",
                  "|---|---|---|---|---|---|"]
        for case, q, e, t, o, r in rows:
            lines.append(f"| {cell(case)} | {cell(q)} | {cell(e)} | {cell(t)} | {cell(o)} | "
                         f"{'pass' if r == 'pass' else '**FAIL**'} |")
        lines.append("")
    if not any_fig:
        lines += ["(no figures recorded in this run)", ""]
    lines += ["## Every check", "",
              "Each suite's check lines; error and tolerance are read from the line where it states them.", ""]
    for name, command, p, f, secs, checks in summary:
        lines += [f"### {name}", "", f"`{command}`: {p} passed, {f} failed" + (f", {secs} s" if secs else "") + ".",
                  ""]
        if not checks:
            lines += ["(no check lines: the suite did not run, or crashed; see build/test-logs/" + name + ".log)", ""]
            continue
        lines += ["| result | check | error | tolerance |", "|---|---|---|---|"]
        for r, text in checks:
            e, t, o = figures_of(text)
            if o:
                e = f"order {o}"
            lines.append(f"| {'pass' if r == 'pass' else '**FAIL**'} | {cell(text)} | {cell(e)} | {cell(t)} |")
        lines.append("")
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines).rstrip("\n") + "\n")
    print(f"verification report: {a.out} ({len(suites)} suites, {total_p} passed, {total_f} failed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
