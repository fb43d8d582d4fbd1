"""The verification report's rows from Python checkers (the shell side:
tests/common/vreport.sh). record() appends one row to
build/reports/verification.tsv (or $VREPORT_TSV): suite (the shell suite
that runs the checker, $VREPORT_SUITE, else the checker's name), case,
quantity, error, tolerance, observed order and pass/FAIL."""
import os
import sys


def _text(x):
    if x is None:
        return ""
    if isinstance(x, float):
        return f"{x:.3g}"
    return str(x)


def record(case, quantity, error, tolerance, order=None, passed=None):
    """One row; passed defaults to error <= tolerance (numbers). Returns passed."""
    if passed is None:
        passed = float(error) <= float(tolerance)
    path = os.environ.get("VREPORT_TSV", "build/reports/verification.tsv")
    suite = os.environ.get("VREPORT_SUITE") or os.path.splitext(os.path.basename(sys.argv[0]))[0]
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    row = [suite, case, quantity, _text(error), _text(tolerance), _text(order), "pass" if passed else "FAIL"]
    with open(path, "a", encoding="utf-8") as f:
        f.write("\t".join(r.replace("\t", " ").replace("\n", " ") for r in row) + "\n")
    return passed
