"""The inverse question's figure (scripts/inverse.py): (a) each claim's residual at Table 1, the
range one-at-a-time moves reach within the bounds, and the fit's; (b) the profile of the cost
over one parameter; (c) every point evaluated: the constitutive share of the peak against the
cost of the other claims. Drawn from the CSVs the script writes."""
import math

from . import inverse as inv
from .tables import read_rows


def _f(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def figure(data, path):
    import matplotlib
    import matplotlib.ticker
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    screen = [r for r in read_rows(data / "inverse_screen.csv") if r.get("status") == "ok"]
    claims = read_rows(data / "inverse_claims.csv") if (data / "inverse_claims.csv").exists() else []
    fitted = {r["claim"]: _f(r["r_fitted"]) for r in claims if r["claim"]}
    check = read_rows(data / "inverse_check.csv") if (data / "inverse_check.csv").exists() else []
    fine = {r["claim"]: _f(r["r_converged_level"]) for r in check if r["claim"]}
    prof = read_rows(data / "inverse_profile.csv") if (data / "inverse_profile.csv").exists() else []
    points = read_rows(data / "inverse_points.csv") if (data / "inverse_points.csv").exists() else []

    plt.rcParams.update({"font.size": 9})
    fig, axes = plt.subplots(1, 3, figsize=(13, 5.2), gridspec_kw={"width_ratios": [1.3, 1, 1]})
    ax = axes[0]
    ids = [c.id for c in inv.CLAIMS]
    for y, c in enumerate(inv.CLAIMS):
        rs = [_f(r[f"r {c.id}"]) for r in screen]
        rs = [r for r in rs if math.isfinite(r)]
        base = next(_f(r[f"r {c.id}"]) for r in screen if r["point"] == "table1")
        clip = lambda v: max(-12, min(12, v))
        ax.plot([clip(min(rs)), clip(max(rs))], [y, y], color="0.6", lw=5, solid_capstyle="butt",
                label="one at a time, within the bounds" if y == 0 else None)
        ax.plot(clip(base), y, "ko", label="Table 1" if y == 0 else None)
        if c.id in fitted and math.isfinite(fitted[c.id]):
            ax.plot(clip(fitted[c.id]), y, "D", color="tab:red", label="the fit" if y == 0 else None)
        if c.id in fine and math.isfinite(fine[c.id]):
            ax.plot(clip(fine[c.id]), y, "D", mfc="none", color="tab:red", ms=9,
                    label="the fit, converged level" if y == 0 else None)
        if abs(base) > 12:
            ax.annotate(f"{base:+.0f}", (clip(base), y), textcoords="offset points", xytext=(-4, 6), fontsize=8)
    ax.axvspan(-1, 1, color="tab:green", alpha=0.15, label="within the paper's precision")
    ax.set_yticks(range(len(ids)))
    ax.set_yticklabels([f"{c.id}: {c.what}" for c in inv.CLAIMS], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(-12.5, 12.5)
    ax.set_xlabel("residual (ours − paper) / precision  (clipped at ±12)")
    ax.set_title("(a) the claims: where the parameters can take them", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.4, -0.16), ncol=2)

    ax = axes[1]
    if prof:
        name = prof[0]["param"]
        p = inv.PARAMS[name]
        xs = [_f(r["value"]) for r in prof]
        ax.semilogx(xs, [_f(r["cost"]) for r in prof], "o-", color="k", label="cost Σ r² (others re-fitted)")
        ax.axvline(p.table1 * p.paper_unit, color="0.5", ls=":", label="Table 1")
        ax.set_xlabel(f"{name} ({p.unit})" if p.unit else name)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_ylabel("cost Σ r²")
        ax.set_yscale("log")
        tw = ax.twinx()
        tw.semilogx(xs, [_f(r.get("share_constitutive")) for r in prof], "s--", color="tab:blue",
                    label="constitutive share of the peak")
        tw.axhline(0.5, color="tab:blue", lw=0.8, alpha=0.5)
        tw.set_ylabel("constitutive share of the peak", color="tab:blue")
        tw.set_ylim(0, 1)
        for a in (ax, tw):
            a.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = tw.get_legend_handles_labels()
        ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1)
    ax.set_title("(b) the profile", fontsize=9)

    ax = axes[2]
    if points:
        share = [_f(r["share_constitutive"]) for r in points]
        rest = [_f(r["cost_others"]) for r in points]
        peak = [_f(r["peak_total"]) for r in points]
        sc = ax.scatter(share, rest, c=peak, cmap="viridis", s=14)
        fig.colorbar(sc, ax=ax, label="peak force (mg)")
        ax.axvline(0.5, color="tab:blue", lw=0.8)
        ax.set_yscale("log")
        ax.set_xlabel("constitutive share of the peak (P35: ≥ 0.5)")
        ax.set_ylabel("cost of the other six claims Σ r²")
    ax.set_title("(c) every point evaluated", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


# ------------------------------------------------------------------ the page's tables

def _g(v, digits=3):
    x = _f(v)
    return "—" if not math.isfinite(x) else f"{x:.{digits}g}"


def _c(v):
    """A cost: 4 significant digits, whole numbers from 10⁴."""
    x = _f(v)
    return "—" if not math.isfinite(x) else f"{x:.0f}" if x >= 1e4 else f"{x:.4g}"


def _r(v):
    x = _f(v)
    return "—" if not math.isfinite(x) else f"{x:+.2f}".replace("-", "−")


OBS_NAMES = {
    "peak_total": "peak force (mg)", "peak_constitutive": "largest constitutive force (mg)",
    "share_constitutive": "constitutive share of the peak", "share_pressure": "pressure share of the peak",
    "t_cross": "crossing of p(X_U) (s)", "t_cross_c2": "c = 2: crossing of p(X_U) (s)", "p30": "p(X_U, 30 s) (kPa)",
    "p30_c2": "c = 2: p(X_U, 30 s) (kPa)", "p30_ratio": "c = 2 over isotropic, p(X_U, 30 s)",
    "d_peak_total": "λp 1 → 0.1: total-peak change (mg)", "d_peak_constitutive": "λp 1 → 0.1: constitutive-peak change (mg)",
    "vm_ratio": "σ_VM contact zones over centre, 40 s",
}


def claims_table(data):
    """Each claim: the paper's words, its interval, and our value and residual at Table 1 and at the fit."""
    lines = ["| claim | the paper says | interval (precision) | Table 1 | r | the fit | r |", "|---|---|---|---|---|---|---|"]
    for r in read_rows(data / "inverse_claims.csv"):
        if not r["claim"]:
            continue
        lines.append(f"| {r['claim']} | {r['what']} | [{_g(r['lo'])}, {_g(r['hi'])}] ({r['precision']}) | "
                     f"{_g(r['table1'], 4)} | {_r(r['r_table1'])} | {_g(r['fitted'], 4)} | {_r(r['r_fitted'])} |")
    for r in read_rows(data / "inverse_claims.csv"):
        if r["claim"]:
            continue
        lines.append(f"| | {OBS_NAMES.get(r['what'], r['what'])} | | {_g(r['table1'], 4)} | | {_g(r['fitted'], 4)} | |")
    return "\n".join(lines) + "\n"


def screen_table(data):
    """The one-at-a-time screen: each point's residuals, cost, constitutive share and peak."""
    ids = [c.id for c in inv.CLAIMS]
    lines = ["| point | " + " | ".join(ids) + " | cost | constitutive share | peak (mg) |",
             "|---|" + "---|" * (len(ids) + 3)]
    for r in read_rows(data / "inverse_screen.csv"):
        if r.get("status") != "ok":
            lines.append(f"| {r['what']} | failed |" + " |" * (len(ids) + 2))
            continue
        lines.append(f"| {r['what']} | " + " | ".join(_r(r[f'r {i}']) for i in ids)
                     + f" | {_c(r['cost'])} | {_g(r['share_constitutive'])} | {_g(r['peak_total'], 4)} |")
    return "\n".join(lines) + "\n"


def fit_table(data):
    """The fitted parameters against Table 1 and their bounds."""
    lines = ["| parameter | Table 1 | fitted | × Table 1 | bounds | why these bounds |", "|---|---|---|---|---|---|"]
    for r in read_rows(data / "inverse_fit.csv"):
        unit = f" {r['unit']}" if r["unit"] else ""
        bound = f" (at its {'lower' if r['at_bound'] == 'lo' else 'upper'} bound)" if r["at_bound"] else ""
        lines.append(f"| {r['param']} | {_g(r['table1'], 5)}{unit} | {_g(r['fitted'], 4)}{unit}{bound} | "
                     f"{_g(r['factor'], 3)} | {_g(r['lo'])}–{_g(r['hi'])} | {r['bounds_why']} |")
    return "\n".join(lines) + "\n"


def profile_table(data):
    """The profile points: the profiled value, the cost there, the constitutive share and peak, the others."""
    rows = read_rows(data / "inverse_profile.csv")
    if not rows:
        return ""
    name = rows[0]["param"]
    others = [k for k in rows[0] if k.startswith("at ") and k != f"at {name}"]
    ids = [c.id for c in inv.CLAIMS]
    lines = [f"| {name} (× Table 1) | cost | " + " | ".join(ids) + " | peak (mg) | " + " | ".join(k[3:] for k in others)
             + " | inner fit |", "|---|---|" + "---|" * (len(ids) + 1 + len(others) + 1)]
    for r in rows:
        lines.append(f"| {_g(r['factor'], 3)} | {_c(r['cost'])} | " + " | ".join(_r(r[f'r {i}']) for i in ids)
                     + f" | {_g(r['peak_total'], 4)} | " + " | ".join(_g(r[k], 3) for k in others) + f" | {r['status']} |")
    return "\n".join(lines) + "\n"


def level_table(data):
    """The scene level at Table 1 against the converged values."""
    lines = ["| observable | this level | converged | error |", "|---|---|---|---|"]
    for r in read_rows(data / "inverse_level.csv"):
        if r["observable"] not in OBS_NAMES or not math.isfinite(_f(r["converged"])):
            continue
        lines.append(f"| {OBS_NAMES[r['observable']]} | {_g(r['scene_level'], 4)} | {_g(r['converged'], 4)} | "
                     f"{_r(r['error'])} |")
    return "\n".join(lines) + "\n"


def check_table(data):
    """The fitted point at the scene level and at the converged level, claim by claim."""
    lines = ["| claim | what | this level | r | converged level | r |", "|---|---|---|---|---|---|"]
    for r in read_rows(data / "inverse_check.csv"):
        rs = [_r(r["r_scene_level"]), _r(r["r_converged_level"])] if r["claim"] else ["", ""]
        lines.append(f"| {r['claim']} | {OBS_NAMES.get(r['what'], r['what'])} | {_g(r['scene_level'], 4)} | {rs[0]} | "
                     f"{_g(r['converged_level'], 4)} | {rs[1]} |")
    return "\n".join(lines) + "\n"


# name -> (begin marker, end marker, renderer) of the page's generated inverse tables
TABLES = {name: (f"<!-- inverse {name} table: written by scripts/inverse.py --stages docs; do not edit -->",
                 f"<!-- end of the inverse {name} table -->", fn)
          for name, fn in (("claims", claims_table), ("screen", screen_table), ("fit", fit_table),
                           ("profile", profile_table), ("level", level_table),
                           ("check", check_table))}


def write_tables(text, data):
    """`text` with every inverse table present in it rewritten from the CSVs in `data`."""
    for begin, end, fn in TABLES.values():
        if begin in text:
            start, stop = text.index(begin) + len(begin), text.index(end)
            text = text[:start] + "\n" + fn(data) + text[stop:]
    return text
