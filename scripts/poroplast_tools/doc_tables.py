"""The generated tables of docs/reproduction.md besides the claims: the reported numbers (paper,
converged, the meridian and 3-D runs of the shipped scenes), the candidate causes, and the runs.
Each is rendered from committed CSVs only (scripts/data, docs/figures/data), so that
`claims.py --write` rewrites them without a run and a test can tell when the page is stale.

Each entry of TABLES: name -> (its markers' name, the function that renders it)."""

import math
from pathlib import Path

from .tables import read_rows

DATA = Path(__file__).resolve().parent.parent / "data"
FIGURE_DATA = DATA.parent.parent / "docs" / "figures" / "data"


def num(v):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return math.nan
    return x


def g(v, digits=4):
    """A value to `digits` significant digits, "—" where there is none."""
    x = num(v)
    return "—" if not math.isfinite(x) else f"{x:.{digits}g}"


def signed(v, digits=2):
    """A shift with its sign and `digits` decimals ("" where there is none)."""
    x = num(v)
    return "" if not math.isfinite(x) else f"{x:+.{digits}f}".replace("-", "−")


def reported():
    """Paper, converged ± bar (references.csv), and the shipped scenes' value on the meridian and
    in 3-D (reproduce.py's reported.csv of each set)."""
    mer = {r["quantity"]: r for r in read_rows(FIGURE_DATA / "reported_meridian.csv")}
    d3 = {r["quantity"]: r for r in read_rows(FIGURE_DATA / "reported_3d.csv")}
    lines = ["| quantity | paper | converged ± error | meridian, scene mesh | 3-D default |", "|---|---|---|---|---|"]
    for q, r in mer.items():
        c, bar = num(r["converged"]), num(r["error_bar"])
        conv = "—" if not math.isfinite(c) else f"{c:.4g} ± {bar:.2g}"
        lines.append(f"| {q} | {r['paper']} | {conv} | {g(r['meridian, scene mesh'])} | "
                     f"{g(d3.get(q, {}).get('3-D default'))} |")
    return "\n".join(lines) + "\n"


def causes():
    """The candidate causes on the syringe crossing and the peaks (causes.py's causes.csv)."""
    lines = ["| variant | what it changes | crossing of p(X_U) (s) | shift | peak force (mg) | shift | "
             "constitutive peak (mg) | shift |", "|---|---|---|---|---|---|---|---|"]
    for r in read_rows(DATA / "causes.csv"):
        cells = [r["variant"], r["changes"]]
        for col in ("zero:probe_p", "max:force_total_mg", "max:force_constitutive_mg"):
            x = num(r[col])
            cells += ["none by 60 s" if col == "zero:probe_p" and not math.isfinite(x) else g(x, 5),
                      "" if r["variant"] == "base" else signed(r["shift " + col], 2 if col == "zero:probe_p" else 3)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def causes_reference():
    """The no-remodelling gap's candidates (causes.py's causes_reference.csv)."""
    lines = ["| variant | what it changes | 90% of the hold's relaxation (s) | shift | 95% (s) | shift | "
             "F(60 s) (mg) | F(400 s) (mg) |", "|---|---|---|---|---|---|---|---|"]
    for r in read_rows(DATA / "causes_reference.csv"):
        base = r["variant"] == "ref_base"
        lines.append("| " + " | ".join([
            r["variant"], r["changes"], g(r["settle90:force_total_mg"], 4),
            "" if base else signed(r["shift settle90:force_total_mg"]), g(r["settle95:force_total_mg"], 5),
            "" if base else signed(r["shift settle95:force_total_mg"]), g(r["force_total_mg@60"], 5),
            g(r["force_total_mg@400"], 5)]) + " |")
    return "\n".join(lines) + "\n"


def runs():
    """The 3-D runs of the shipped scenes: steps, step cuts, Newton iterations, wall time
    (reproduce.py's summary.csv of the 3-D set)."""
    lines = ["| case | last time (s) | steps | step cuts | Newton | wall (s) |", "|---|---|---|---|---|---|"]
    for r in read_rows(FIGURE_DATA / "summary_3d.csv"):
        lines.append(f"| `{r['case']}` | {g(r['t_last_s'])} | {g(r['steps'])} | {g(r['step_cuts'])} | "
                     f"{g(r['newton'])} | {g(r['wall_s'], 3)} |")
    return "\n".join(lines) + "\n"


TABLES = {"reported": reported, "causes": causes, "causes_reference": causes_reference, "runs": runs}


def markers(name):
    return (f"<!-- {name} table: written by scripts/claims.py --write; do not edit -->",
            f"<!-- end of the {name} table -->")


def write_all(text, replace_in):
    """`text` with every table of TABLES written between its markers (`replace_in` as claims')."""
    for name, render in TABLES.items():
        begin, end = markers(name)
        if begin in text:
            text = replace_in(text, render(), begin, end)
    return text

