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
