"""The paper's claims, one row each (data/claims.csv), with our numbers read from the converged
references (data/references.csv) and, where the paper gives a number, the verdict by a written
rule (RULE). Rendered as the Markdown table of docs/reproduction.md.

claims.csv columns: id, where (section, figure), claim (the paper's statement), paper (its number
or "yes"), measure (for a numeric claim: `CASE|OBSERVABLE`, or two of them joined by " - " or
" / "), ours (text; `{CASE|OBSERVABLE}` is replaced by the converged value ± its error bar, and
`{SOURCE:ROW|COLUMN}` by a value of one of the committed SOURCES, not converged, to 4 digits),
verdict (of a statement without a number; a numeric claim's is the rule's), cause (measured,
argued, derived, or "none measured"), paper_value (the paper's number in the table's units),
precision_note (the paper's words the number is printed in, quoted: its precision is read from
them by `printed`).
"""

import math
import re
from functools import lru_cache
from pathlib import Path

from .refs import combined, references
from .tables import read_rows

DATA = Path(__file__).resolve().parent.parent / "data"
FIGURE_DATA = DATA.parent.parent / "docs" / "figures" / "data"

# Values that are not converged references, by source: (file, its key column, or key columns
# whose values joined by "@" name a row). `meridian` and `3d` are reproduce.py's summaries of the
# shipped scenes (--axisymmetric, and 3-D), `fields` the causes runs' rows read from fields
# (causes.py --fields), `flow` reproduce.py's outflow by phase on the meridian, `zones` the region means of Figs 5-6 (rows "CASE@T"); the others are
# the figures' data (reproduce.py), the causes (causes.py), the tensiometry study
# (tensiometry.py) and the linearised coverage (coverage.py: rows "PARAMS@NOISE@PARAM", and the
# tension case's per-experiment predictions, rows "EXPERIMENT@PARAM") and the inverse question
# (inverse.py: its claims and check tables' rows named by their `what`, the profile's "PARAM@FACTOR";
# its points are read only as a whole: count, min, max), which the docs' prose quotes (poroplast_tools.doc_numbers).
SOURCES = {"meridian": (FIGURE_DATA / "summary_meridian.csv", "case"),
           "3d": (FIGURE_DATA / "summary_3d.csv", "case"),
           "flow": (DATA / "flow_meridian.csv", "case"),
           "stabilisation_fade": (DATA / "stabilisation_fade.csv", ("scene", "geometry", "rule", "observable")),
           "fields": (DATA / "hypothesis_40a_fields.csv", "variant"),
           "zones": (FIGURE_DATA / "fig5_6_zones.csv", "row"),
           "causes": (DATA / "causes.csv", "variant"),
           "causes_reference": (DATA / "causes_reference.csv", "variant"),
           "hypothesis": (DATA / "hypothesis_40a.csv", "variant"),
           "reported_meridian": (FIGURE_DATA / "reported_meridian.csv", "quantity"),
           "reported_3d": (FIGURE_DATA / "reported_3d.csv", "quantity"),
           "fig3": (FIGURE_DATA / "fig3_pressure.csv", ("case", "t_s")),
           "fig3_later": (FIGURE_DATA / "fig3_later_pressure.csv", ("case", "t_s")),
           "fig4": (FIGURE_DATA / "fig4_probe.csv", ("case", "time")),
           "fig9_share": (FIGURE_DATA / "fig9_share.csv", "case"),
           "fig10": (FIGURE_DATA / "fig10_hw.csv", ("set", "t_end_s")),
           "fig11c": (FIGURE_DATA / "fig11c_pressure.csv", ("case", "t_s")),
           "fig_soft_pressure": (FIGURE_DATA / "fig_soft_pressure.csv", ("case", "t_s")),
           "tensiometry": (FIGURE_DATA / "tensiometry.csv", ("case", "compression")),
           "tensiometry_medium": (FIGURE_DATA / "tensiometry_medium.csv", "case"),
           "coverage_lin": (FIGURE_DATA / "coverage_linearised.csv", ("params", "noise", "param")),
           "coverage_lin_tst": (FIGURE_DATA / "coverage_linearised_tst.csv", ("params", "noise", "param")),
           "jitter_tst": (FIGURE_DATA / "jitter_tst.csv", ("experiment", "param")),
           "creep_bench": (DATA / "creep_bench.csv", ("case", "hold")),
           "inverse_level": (DATA / "inverse_level.csv", "observable"),
           "inverse_screen": (DATA / "inverse_screen.csv", "point"),
           "inverse_fit": (DATA / "inverse_fit.csv", "param"),
           "calibration_forgacs": (DATA / "calibration_forgacs.csv", "row"),
           "inverse_claims": (DATA / "inverse_claims.csv", "what"),
           "inverse_iterations": (DATA / "inverse_iterations.csv", "iteration"),
           "inverse_profile": (DATA / "inverse_profile.csv", ("param", "factor")),
           "inverse_check": (DATA / "inverse_check.csv", "what"),
           "inverse_points": (DATA / "inverse_points.csv", "overrides")}

VERDICTS = ("reproduced", "partly", "no", "open", "not comparable")

RULE = (
    "A claim with a number is **reproduced** when ours lies within the paper's precision of it "
    "(widened by twice our error bar; a value that is not converged has none), **partly** when it "
    "has the same sign and is off by less than a factor 2, and **no** otherwise. The paper's "
    "precision is read from the words it prints the number in, the same way for every number: half "
    "a unit of the last digit printed, every printed digit counting (\"40 s\" and \"28 s\" alike "
    "±0.5 s; \"4.0 × 10³ Pa\" ±0.05 kPa; \"1/4\", a count of quarters, ±1/8); words such as "
    "\"about\" or \"close to\" add nothing, since a rounded number says as much; a number the "
    "paper gives as the difference of two it prints carries the sum of their precisions; \"an "
    "order of magnitude\" is a factor within √10 of 10. Each row quotes the words. A statement "
    "without a number is taken in its parts (each clause, each region or case it names): "
    "reproduced when every part is measured and holds; partly when a measured part holds and "
    "another fails, is not measured or cannot be, the row saying which (holds: …; fails: …; not "
    "measured: …; not comparable: …); "
    "no when parts are measured and none holds; open when no part is measured yet though the "
    "model could say; not comparable where the model cannot (what it lacks is named). Each "
    "observable is defined once: the region means use the contact zones (r < 40 µm within 30 µm "
    "of a plate) and the centre (r < 30 µm, |z − R| < 30 µm) of the reference configuration, "
    "X_U = (40, 0, 190) µm."
)

# A number as the paper prints it: digits, or a fraction, times a power of ten, in a unit the
# table converts (the paper's Pa are the table's kPa).
_PRINTED = re.compile(r"(\d+(?:\.\d+)?)(?:\s*/\s*(\d+))?(?:\s*× 10([⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+))?(?:\s*(Pa)\b)?")
_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
TO_TABLE_UNITS = {"Pa": 1e-3}
ORDER_OF_MAGNITUDE = "order of magnitude"
FACTOR_ORDER = "×3.1623"   # within √10 of 10: half an order either way


def printed(quote):
    """(value, precision) of the one number a quote of the paper prints, in the table's units, by
    RULE: half a unit of its last printed digit (of a fraction a/b: 1/(2b)); "an order of
    magnitude" is 10 within a factor √10."""
    if ORDER_OF_MAGNITUDE in quote:
        return 10.0, FACTOR_ORDER
    hits = _PRINTED.findall(quote)
    if len(hits) != 1:
        raise ValueError(f"claims.csv: the quote {quote!r} prints {len(hits)} numbers; quote the words of one")
    digits, denominator, power, unit = hits[0]
    scale = 10.0 ** int(power.translate(_SUPERSCRIPT)) if power else 1.0
    scale *= TO_TABLE_UNITS.get(unit, 1.0)
    if denominator:
        return int(digits) / int(denominator) * scale, 0.5 / int(denominator) * scale
    decimals = len(digits.split(".")[1]) if "." in digits else 0
    return float(digits) * scale, 0.5 * 10.0 ** -decimals * scale


def quotes(note):
    """The quotes of the paper in a row's precision_note, in order."""
    return re.findall(r'"([^"]+)"', note)


def paper_number(note):
    """(value, precision) of a row's precision_note: one quote of the paper (`printed`), or two
    joined by " minus " (their difference, the sum of their precisions)."""
    said = quotes(note)
    if len(said) == 1:
        return printed(said[0])
    if len(said) == 2 and '" minus "' in note:
        (a, pa), (b, pb) = printed(said[0]), printed(said[1])
        if isinstance(pa, str) or isinstance(pb, str):
            raise ValueError(f"claims.csv: a difference of factors in {note!r}")
        return a - b, pa + pb
    raise ValueError(f"claims.csv: precision_note {note!r}: quote the paper once, or twice joined by \" minus \"")


def precision_text(value, precision):
    """The paper's number with its precision, as the table prints it: to the digit the precision
    is half a unit of, where it is one."""
    if isinstance(precision, str):
        return f"{value:g}, within a factor {precision[1:]}"
    digit = math.log10(2 * precision)
    if abs(digit - round(digit)) < 1e-9:
        return f"{value:.{max(0, -round(digit))}f} ± {precision:g}"
    return f"{value:g} ± {precision:g}"


PLACEHOLDER = re.compile(r"\{([^{}|]+)\|([^{}]+)\}")


def load(path=DATA / "claims.csv"):
    return read_rows(path)


def fmt(value, bar):
    """value ± bar, the bar to 2 significant digits and the value to the same decimal; a value
    without a bar (NaN: not converged) to 4 significant digits."""
    if not math.isfinite(value):
        return "—"
    if math.isnan(bar):   # without an exponent below 1e9: "18030", not "1.803e+04"
        if 1e4 <= abs(value) < 1e9:
            return f"{round(value, 3 - math.floor(math.log10(abs(value)))):.0f}"
        return f"{value:.4g}"
    if bar <= 0 or not math.isfinite(bar):
        return f"{value:.6g}"
    decimals = max(0, 1 - math.floor(math.log10(bar)))
    return f"{value:.{decimals}f} ± {bar:.{decimals}f}"


def row_key(row, key):
    """The name of a SOURCES row: its key column's value, or its key columns' joined by "@"."""
    return "@".join(row[k] for k in key) if isinstance(key, tuple) else row[key]


def source_value(source, row, column):
    """A value of one of the SOURCES (row: its row_key)."""
    if source not in SOURCES:
        raise KeyError(f"no source {source!r} (one of {', '.join(SOURCES)})")
    path, key = SOURCES[source]
    for r in _rows(path):
        if row_key(r, key) == row:
            if column not in r:
                raise KeyError(f"no column {column!r} in {path.name}")
            return float(r[column])
    raise KeyError(f"no row {row} in {path.name}")


@lru_cache(maxsize=None)
def _rows(path):
    """A source's rows, read once for all the table's placeholders."""
    return read_rows(path)


def lookup(refs, key):
    case, observable = key.split("|", 1)
    if ":" in case:
        return source_value(*case.split(":", 1), observable), math.nan
    if (case, observable) not in refs:
        raise KeyError(f"claims.csv: no converged value {case} | {observable} in references.csv")
    return refs[(case, observable)]


def measure(refs, expression):
    """(value, error bar) of `A`, `A - B` or `A / B` (keys CASE|OBSERVABLE; the bars combined as
    references.py combines them: `refs.combined`)."""
    for op, name in ((" - ", "difference"), (" / ", "ratio")):
        if op in expression:
            return combined(name, *(lookup(refs, k.strip()) for k in expression.split(op)))
    return lookup(refs, expression.strip())


def rule(value, bar, paper, precision):
    """The verdict of RULE for ours = value ± bar (NaN: not converged, no bar) against the paper's
    number and precision (a float, or a string "×F" for a factor)."""
    bar = 0.0 if math.isnan(bar) else bar
    if isinstance(precision, str) and precision.startswith("×"):
        factor = float(precision[1:])
        if value + 2 * bar >= paper / factor and value - 2 * bar <= paper * factor:
            return "reproduced"
    elif abs(value - paper) <= float(precision) + 2 * bar:
        return "reproduced"
    ratio = value / paper if paper else math.inf
    return "partly" if 0.5 <= ratio <= 2 else "no"


def expand(refs, text):
    return PLACEHOLDER.sub(lambda m: fmt(*lookup(refs, f"{m.group(1)}|{m.group(2)}")), text)


def resolved(refs, row):
    """(our text, the verdict) of a row: measured ones by RULE, the others as recorded."""
    ours = expand(refs, row["ours"])
    if not row["measure"]:
        return ours, row["verdict"]
    value, bar = measure(refs, row["measure"])
    paper, precision = paper_number(row["precision_note"])
    verdict = rule(value, bar, paper, precision)
    text = f"**{fmt(value, bar)}** {ours}".strip()
    return text + f" (the paper: {precision_text(paper, precision)}, from {row['precision_note']})", verdict


def table(rows=None, refs=None):
    """The Markdown claims table with its counts."""
    rows = load() if rows is None else rows
    refs = references() if refs is None else refs
    lines = ["| # | where | the paper says | paper | ours (converged ± error) | verdict | cause |",
             "|---|---|---|---|---|---|---|"]
    counts = dict.fromkeys(VERDICTS, 0)
    for r in rows:
        ours, verdict = resolved(refs, r)
        counts[verdict] += 1
        cells = [r["id"], r["where"], r["claim"], r["paper"], ours, verdict, r["cause"]]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    summary = ", ".join(f"{n} {v}" for v, n in counts.items())
    return f"{len(rows)} rows: {summary}.\n\n" + "\n".join(lines) + "\n"


BEGIN = "<!-- claims table: written by scripts/claims.py --write; do not edit -->"
END = "<!-- end of the claims table -->"


def replace_in(text, generated, begin=BEGIN, end_marker=END):
    """`text` with the part between the markers (default the claims table's) replaced by
    `generated`."""
    start, end = text.index(begin) + len(begin), text.index(end_marker)
    return text[:start] + "\n" + generated + text[end:]
