"""The converged reference values: scripts/data/references.csv (written by scripts/references.py:
case, observable, extrapolated value, error bar, ...), the one source of converged values in
the scripts."""
import csv
from pathlib import Path

SHIPPED = Path(__file__).resolve().parent.parent / "data" / "references.csv"


def references(path=SHIPPED):
    """A references.csv as {(case, observable): (extrapolated, error bar)}."""
    with open(path) as f:
        return {(r["case"], r["observable"]): (float(r["extrapolated"]), float(r["error_bar"]))
                for r in csv.DictReader(f)}


def converged(case, observable, path=SHIPPED):
    """The extrapolated value of `observable` of the reference case `case`."""
    refs = references(path)
    if (case, observable) not in refs:
        raise SystemExit(f"{path}: no converged value of {observable} for the case {case}")
    return refs[(case, observable)][0]


def combined(op, a, b):
    """(value, error bar) of the "difference" a − b or the "ratio" a / b of two converged values
    a, b = (value, error bar): the bars add (a difference), or the relative bars (a ratio), a
    bound that does not assume the two errors independent."""
    (x, dx), (y, dy) = a, b
    if op == "difference":
        return x - y, dx + dy
    if op == "ratio":
        return x / y, abs(x / y) * (dx / abs(x) + dy / abs(y))
    raise ValueError(f"unknown combination {op!r}")
