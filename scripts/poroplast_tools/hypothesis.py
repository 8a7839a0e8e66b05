"""The (40a) hypothesis against alternatives of the same size on the syringe crossing: each
remodelling row the causes runs can give, under the base flow rule ((40b)), under (40a), with
λp × 1.1 (which shifts the crossing as (40a) does) and with γp of the Kirchhoff stress (another
place a J can enter), beside the paper's number, and the share of the base's gap to the paper
that each change closes. Read from data/hypothesis_40a.csv, the table `causes.py --dir DIR --only`
writes for HYPOTHESIS_VARIANTS, and data/hypothesis_40a_fields.csv, the table `causes.py --fields`
writes (the rows read from fields and shapes); rendered into docs/reproduction.md."""

from pathlib import Path

from .tables import read_rows

DATA = Path(__file__).resolve().parent.parent / "data"

# The three models, and per model the variants of its isotropic, c = 2 and λp = 0.1 cases.
MODELS = {
    "(40b), the base": ("base", "c2", "lambda_01"),
    "(40a)": ("form_40a", "c2_40a", "lambda_01_40a"),
    "λp × 1.1": ("lambda_x110", "c2_lambda_x110", "lambda_01_x110"),
    "γp of τ = J σ": ("form_tau", "c2_tau", "lambda_01_tau"),
}
# λp's factor in the λp-scaled variants: the crossing's shift against it.
FACTORS = {"lambda_x110": 1.1, "lambda_x115": 1.15, "lambda_x120": 1.2, "lambda_x125": 1.25}
HYPOTHESIS_VARIANTS = [v for trio in MODELS.values() for v in trio] + [v for v in FACTORS if v != "lambda_x110"]

# (row, the paper's number, its value from a model's (isotropic, c = 2, λp = 0.1) rows)
ROWS = [
    ("crossing of p(X_U) (s)", 40.0, lambda i, c, l: i["zero:probe_p"]),
    ("c = 2: its crossing minus the isotropic one (s)", -12.0, lambda i, c, l: c["zero:probe_p"] - i["zero:probe_p"]),
    ("c = 2 over isotropic, p(X_U, 30 s)", 0.25, lambda i, c, l: c["probe_p@30"] / i["probe_p@30"]),
    ("λp 1 → 0.1: total-force peak change (mg)", 2.0,
     lambda i, c, l: l["max:force_total_mg"] - i["max:force_total_mg"]),
    ("λp 1 → 0.1: constitutive-force peak change (mg)", 4.0,
     lambda i, c, l: l["max:force_constitutive_mg"] - i["max:force_constitutive_mg"]),
]


# The rows read from fields and shapes: (row, the paper's number or None, the column of
# hypothesis_40a_fields.csv); each model's value is its row there (the isotropic case).
FIELD_ROWS = [
    # the paper's 4.0 kPa "before the detachment" at 37 s, as claim P24a reads it
    ("σ_VM, contact-zone mean at 35 s (kPa)", None, "remodel_40|vm_contact@35"),
    ("σ_VM, contact-zone mean at 37 s, before the upper detachment (kPa)", 4.0, "remodel_40|vm_contact@37"),
    ("σ_VM, contact-zone mean at 40 s (kPa)", 3.5, "remodel_40|vm_contact@40"),
    ("σ_VM, contact zones over centre at 40 s", 10.0, "remodel_40|vm_contact/centre@40"),
    ("‖E_p‖, contact zones over centre at 60 s", 0.0, "remodel_40|ep_contact/centre@60"),
    ("p > 0 share of the volume at 45 s", None, "remodel_155|bubble_share@45"),
    ("H/W after 65 s of compression and 60 s of rest", None, "hw_65|last:height/width"),
]


def load(path=DATA / "hypothesis_40a.csv"):
    rows = {r["variant"]: r for r in read_rows(path)}
    for r in rows.values():
        for k, v in r.items():
            try:
                r[k] = float(v)
            except (TypeError, ValueError):
                pass
    return rows


def values(rows, field_rows=None):
    """{row name: (paper or None, {model: value})}."""
    out = {}
    for name, paper, f in ROWS:
        out[name] = (paper, {m: f(*(rows[v] for v in trio)) for m, trio in MODELS.items()})
    for name, paper, col in FIELD_ROWS if field_rows else []:
        out[name] = (paper, {m: field_rows[trio[0]][col] for m, trio in MODELS.items()})
    return out


def closed(paper, base, value):
    """The share of the base's gap to the paper's number that `value` closes (negative: widens)."""
    return 1.0 - abs(value - paper) / abs(base - paper)


# A model moves a row towards the paper when it closes at least this share of the base's gap.
MOVES = 0.1


def table(rows=None, field_rows=None):
    rows = load() if rows is None else rows
    field_rows = load(DATA / "hypothesis_40a_fields.csv") if field_rows is None else field_rows
    models = list(MODELS)
    lines = ["| row | paper | " + " | ".join(models) + " |", "|---|---|" + "---|" * len(models)]
    moved = dict.fromkeys(models[1:], 0)
    numbered = 0
    for name, (paper, by) in values(rows, field_rows).items():
        base = by[models[0]]
        cells = [f"{base:.3g}"]
        numbered += paper is not None
        for m in models[1:]:
            if paper is None:
                cells.append(f"{by[m]:.3g} ({by[m] - base:+.2g})")
                continue
            share = closed(paper, base, by[m])
            moved[m] += share >= MOVES
            cells.append(f"{by[m]:.3g} (closes {int(round(100 * share))}% of the gap)")
        lines.append(f"| {name} | {'—' if paper is None else f'{paper:g}'} | " + " | ".join(cells) + " |")
    shift = lambda v: rows[v]["zero:probe_p"] - rows["base"]["zero:probe_p"]
    scale = ", ".join(f"×{f:g}: {shift(v):+.2f} s" for v, f in FACTORS.items())
    counts = "; ".join(f"{m} closes at least {100 * MOVES:.0f}% of the gap in {n} of {numbered} rows"
                       for m, n in moved.items())
    return ("\n".join(lines) + f"\n\n{counts}. The crossing's shift against λp's factor: {scale}; "
            f"(40a): {shift('form_40a'):+.2f} s; γp of τ: {shift('form_tau'):+.2f} s.\n")


BEGIN = "<!-- (40a) table: written by scripts/claims.py --write; do not edit -->"
END = "<!-- end of the (40a) table -->"
