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
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    screen = [r for r in read_rows(data / "inverse_screen.csv") if r.get("status") == "ok"]
    claims = read_rows(data / "inverse_claims.csv")
    fitted = {r["claim"]: _f(r["r_fitted"]) for r in claims if r["claim"]}
    prof = read_rows(data / "inverse_profile.csv") if (data / "inverse_profile.csv").exists() else []
    points = read_rows(data / "inverse_points.csv") if (data / "inverse_points.csv").exists() else []

    plt.rcParams.update({"font.size": 9})
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), gridspec_kw={"width_ratios": [1.3, 1, 1]})
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
        if abs(base) > 12:
            ax.annotate(f"{base:+.0f}", (clip(base), y), textcoords="offset points", xytext=(-4, 6), fontsize=7)
    ax.axvspan(-1, 1, color="tab:green", alpha=0.15, label="within the paper's precision")
    ax.set_yticks(range(len(ids)))
    ax.set_yticklabels([f"{c.id}: {c.what}" for c in inv.CLAIMS], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(-12.5, 12.5)
    ax.set_xlabel("residual (ours − paper) / precision  (clipped at ±12)")
    ax.set_title("(a) the claims: where the parameters can take them", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")

    ax = axes[1]
    if prof:
        name = prof[0]["param"]
        p = inv.PARAMS[name]
        xs = [_f(r["value"]) for r in prof]
        ax.semilogx(xs, [_f(r["cost"]) for r in prof], "o-", color="k", label="cost Σ r² (others re-fitted)")
        ax.axvline(p.table1 * p.paper_unit, color="0.5", ls=":", label="Table 1")
        ax.set_xlabel(f"{name} ({p.unit})" if p.unit else name)
        ax.set_ylabel("cost Σ r²")
        ax.set_yscale("log")
        tw = ax.twinx()
        tw.semilogx(xs, [_f(r.get("share_constitutive")) for r in prof], "s--", color="tab:blue",
                    label="constitutive share of the peak")
        tw.axhline(0.5, color="tab:blue", lw=0.8, alpha=0.5)
        tw.set_ylabel("constitutive share of the peak", color="tab:blue")
        tw.set_ylim(0, 1)
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = tw.get_legend_handles_labels()
        ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper center")
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
