#!/usr/bin/env python3
"""One observable of several `scripts/study.py` studies on one figure: the observable against a
grid key, a line per study (e.g. Fig 11a: H/W after the rest against compression time, with the
isotropic and the remodelling-dependent permeability). Prints the table it plots.

    python3 scripts/compare_studies.py --x plates.t_end --observable last:height/width \\
        "isotropic=studies/shape_recovery_k0a" "c = 2=studies/shape_recovery_c2" \\
        [--where material.remodelling.lambda_p=0.001] [--xlabel ...] [--out fig.png]
"""
import argparse
import csv
import math
from pathlib import Path

from poroplast_tools import labels


def series(study, x, observable, where):
    rows = list(csv.DictReader(open(Path(study) / "summary.csv")))
    for k, v in where:
        rows = [r for r in rows if k not in r or r[k] == v]
    missing = [c for c in (x, observable) if rows and c not in rows[0]]
    if missing:
        raise SystemExit(f"compare_studies.py: {study}/summary.csv has no column {missing[0]}")
    pts = sorted((float(r[x]) * labels.axis_factor(x), float(r[observable])) for r in rows if r["status"] == "ok")
    return [p for p in pts if math.isfinite(p[1])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("studies", nargs="+", metavar="LABEL=DIR")
    ap.add_argument("--x", required=True, help="grid key on the x axis")
    ap.add_argument("--observable", required=True)
    ap.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                    help="keep only the rows with this grid value (in studies that have the key)")
    ap.add_argument("--xlabel", default=None)
    ap.add_argument("--ylabel", default=None)
    ap.add_argument("--title", default=None)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    where = [tuple(w.split("=", 1)) for w in a.where]
    data = []
    for spec in a.studies:
        label, _, d = spec.rpartition("=")
        data.append((label or d, series(d, a.x, a.observable, where)))

    xs = sorted({x for _, pts in data for x, _ in pts})
    print(f"{a.observable} against {a.x}")
    print("study".ljust(36) + "".join(f"{x:>10g}" for x in xs))
    for label, pts in data:
        v = dict(pts)
        print(label[:36].ljust(36) + "".join(f"{v[x]:>10.4f}" if x in v else " " * 10 for x in xs))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for (label, pts), marker in zip(data, "osD^v<>" * 3):
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker + "-", label=label)
    ax.set_xlabel(a.xlabel or labels.key(a.x))
    ax.set_ylabel(a.ylabel or labels.observable(a.observable))
    if a.title:
        ax.set_title(a.title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"figure: {a.out}")


if __name__ == "__main__":
    main()
