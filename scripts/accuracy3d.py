"""3-D accuracy per second: the candidate discretisations of the `reference` experiment (quarter
sphere, the whole experiment to t_end = 60 s) against the meridian's, on one chart of error
against wall time for the peak force and F(35 s). Errors are against the converged meridian
values (scripts/data/references.csv, written by `scripts/references.py`; --peak-ref / --f35-ref). Every case runs alone on --ranks ranks
(one at a time, so the wall times are comparable); prints a table and writes the chart.

    python3 scripts/accuracy3d.py [--dir studies/accuracy3d] [--ranks 2] [--quick]
        [--out docs/figures/accuracy3d.png]

Candidates: Taylor–Hood P2–P1 on uniform meshes with the scene's pole grading (h_pole = 0.3 h),
on finer pole gradings and a surface grading; the pressure stabilisation faded (the scene's),
constant and off; stabilised equal-order P1–P1 (contact on the vertices); and the meridian
(P2–P1 on triangles) at h = 20 ... 5. --quick runs the cheap half (no case above ~20 s).
"""
import argparse
import math
from pathlib import Path

from poroplast_tools.cases import run_cases
from poroplast_tools.refs import converged
from poroplast_tools.tables import write_rows

OBS = ("max:force_total_mg", "force_total_mg@35")
P1 = ("fem.element", '"P1-P1"')
AXI = ("mesh.geometry", "axisymmetric")


def mesh(h, hp=None, rp=None, **more):
    """Mesh overrides: h, h_pole (default 0.3 h), r_pole and any other .geo parameter."""
    o = [("mesh.params.h", h), ("mesh.params.h_pole", round(hp if hp is not None else 0.3 * h, 3))]
    if rp is not None:
        o.append(("mesh.params.r_pole", rp))
    return o + [(f"mesh.params.{k}", v) for k, v in more.items()]


# (series, label, overrides, cheap?)
CASES = [
    ("3-D P2–P1, pole-graded (h_pole = 0.3 h)", "h = 30", mesh(30), True),
    ("3-D P2–P1, pole-graded (h_pole = 0.3 h)", "h = 25", mesh(25), True),
    ("3-D P2–P1, pole-graded (h_pole = 0.3 h)", "h = 20", mesh(20, 6), True),
    ("3-D P2–P1, pole-graded (h_pole = 0.3 h)", "h = 15", mesh(15), False),
    ("3-D P2–P1, pole-graded (h_pole = 0.3 h)", "h = 12", mesh(12), False),
    ("3-D P2–P1, finer pole grading", "h 20, h_pole 3 (default)", mesh(20, 3), True),
    ("3-D P2–P1, finer pole grading", "h 25, h_pole 3", mesh(25, 3), True),
    ("3-D P2–P1, finer pole grading", "h 15, h_pole 3", mesh(15, 3), False),
    ("3-D P2–P1, finer pole grading", "h 20, h_pole 4, r_pole 70", mesh(20, 4, 70), True),
    ("3-D P2–P1, finer pole grading", "h 20, h_pole 2, r_pole 80", mesh(20, 2, 80), False),
    ("3-D P2–P1, surface-graded", "h 20, h_pole 3, r_pole 80, h_surf 10", mesh(20, 3, 80, h_surf=10, w_surf=20),
     False),
    ("3-D P2–P1, stabilisation", "h 20, h_pole 3, constant stabilisation",
     mesh(20, 3) + [("fem.stabilisation_fade", 1e9), ("fem.stabilisation_steps", 1e9)], True),
    ("3-D P2–P1, stabilisation", "h 20, h_pole 3, no stabilisation", mesh(20, 3) + [("fem.stabilisation", 0.0)], True),
    ("3-D P2–P1, 1/4 of the steps", "h 20, h_pole 3, 1/4 steps", mesh(20, 3) + [("time.dt", 0.005), ("time.dt_max", 0.5)],
     False),
    ("3-D P1–P1 (stabilised)", "P1–P1 h = 40", mesh(40, 12) + [P1], True),
    ("3-D P1–P1 (stabilised)", "P1–P1 h = 20", mesh(20, 6) + [P1], True),
    ("3-D P1–P1 (stabilised)", "P1–P1 h = 20, h_pole 3", mesh(20, 3) + [P1], True),
    ("3-D P1–P1 (stabilised)", "P1–P1 h = 15", mesh(15) + [P1], False),
    ("meridian P2–P1", "meridian h = 20", [AXI] + mesh(20, 6), True),
    ("meridian P2–P1", "meridian h = 14", [AXI] + mesh(14), True),
    ("meridian P2–P1", "meridian h = 10", [AXI] + mesh(10), True),
    ("meridian P2–P1", "meridian h = 5", [AXI] + mesh(5), True),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", type=Path, default=Path("studies/accuracy3d"))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="only the cases of about 20 s or less")
    ap.add_argument("--peak-ref", type=float, default=None,
                    help="converged peak (mg; default: scripts/data/references.csv's)")
    ap.add_argument("--f35-ref", type=float, default=None,
                    help="converged F(35 s) (mg; default: scripts/data/references.csv's)")
    ap.add_argument("--out", type=Path, default=Path("docs/figures/accuracy3d.png"))
    a = ap.parse_args()
    a.peak_ref = a.peak_ref or converged("reference", OBS[0])
    a.f35_ref = a.f35_ref or converged("reference", OBS[1])
    cases = [c for c in CASES if c[3] or not a.quick]
    sets = [("time.t_end", 60), ("output.fields", "false")]
    results = run_cases("reference", [c[2] for c in cases], sets, a.dir, a.ranks, observe=OBS,
                        sweep=True, ranks_per_case=a.ranks)
    rows = []
    for (series, label, _, _), (_, r) in zip(cases, results):
        if r.get("status") != "ok":
            print(f"{label}: {r.get('status')} {r.get('error', '')}")
            continue
        rows.append({"series": series, "label": label, "dofs": int(r.get("dofs", 0)), "wall_s": r["wall_s"],
                     "steps": int(r["steps"]), "peak": r[OBS[0]], "f35": r[OBS[1]],
                     "peak_err": 100 * (r[OBS[0]] / a.peak_ref - 1), "f35_err": 100 * (r[OBS[1]] / a.f35_ref - 1)})
    print(f"\nerrors against the converged meridian values (peak {a.peak_ref:.6g} mg, F(35 s) {a.f35_ref:.6g} mg); "
          f"wall time of the whole experiment (t_end = 60 s) on {a.ranks} rank(s)\n")
    print("| case | dofs | wall (s) | steps | peak (mg) | F(35 s) (mg) |\n|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['label']} | {r['dofs']:,} | {r['wall_s']:.1f} | {r['steps']} | {r['peak']:.3f} "
              f"({r['peak_err']:+.2f}%) | {r['f35']:.3f} ({r['f35_err']:+.2f}%) |")
    write_rows(a.dir / "accuracy3d.csv", rows)
    plot(rows, a.out, a.ranks)


def replot(csv_path, out, ranks=2):
    """The chart again from a study's accuracy3d.csv (no runs)."""
    import csv
    rows = list(csv.DictReader(open(csv_path)))
    for r in rows:
        for k in ("wall_s", "peak_err", "f35_err"):
            r[k] = float(r[k])
    plot(rows, out, ranks)


def plot(rows, out, ranks):
    import matplotlib
    import matplotlib.ticker
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 6), sharex=True)
    series = list(dict.fromkeys(r["series"] for r in rows))
    markers = "osD^v<>ph*"
    for ax, key, title in ((axes[0], "peak_err", "peak force"), (axes[1], "f35_err", "F(35 s)")):
        for i, s in enumerate(series):
            pts = sorted((r for r in rows if r["series"] == s), key=lambda r: r["wall_s"])
            ax.plot([r["wall_s"] for r in pts], [r[key] for r in pts], marker=markers[i % len(markers)],
                    ls="-" if "pole-graded" in s or "meridian" in s else "", label=s)
        for r in rows:
            if "(default)" in r["label"]:
                ax.plot([r["wall_s"]], [r[key]], marker="*", ms=16, mfc="none", mec="k", ls="",
                        label="the 3-D default" if key == "peak_err" else None)
        for lim in (-1.0, 1.0):
            ax.axhline(lim, color="0.6", lw=0.8, ls="--")
        if key == "f35_err":
            for lim in (-0.5, 0.5):
                ax.axhline(lim, color="0.6", lw=0.8, ls=":")
        ax.axvline(60, color="0.6", lw=0.8, ls="-.")
        ax.axhline(0, color="k", lw=0.6)
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator([1, 2, 5, 10, 20, 50, 100, 200, 500]))
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel(f"wall time, whole experiment, {ranks} ranks (s)")
        ax.set_ylabel(f"error of the {title} (%)")
        ax.set_title(f"{title}: error against wall time")
        vals = [r[key] for r in rows if math.isfinite(r[key])] or [0.0]
        ax.set_ylim(min(-4.0, min(vals) - 0.5), max(1.5, min(6.0, max(vals) + 0.5)))
        ax.set_xlim(left=min(r["wall_s"] for r in rows) * 0.8)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=4, fontsize=8)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"chart: {out}")


if __name__ == "__main__":
    main()
