"""What the faded pressure stabilisation costs, with the fade by drainage alone (the rule until
2026-12-07) and with the fade by the steps' growth since a kink as well (the rule since;
docs/decisions/0012-stabilisation-fade-by-steps.md), on scenes unlike each other: the soft
aggregate (scripts/data/soft_aggregate.toml: E = 1.2 kPa, R = 220 µm, c_v t_ramp / R² = 1.26e-3)
and the `reference` experiment (c_v t_ramp / R² = 0.0604), on the meridian and in 3-D,
`remodel_40` and Cryer's sphere on the meridian. Errors against the converged values: the soft aggregate's
(scripts/data/soft_aggregate_reference.csv), the reference's (scripts/data/references.csv) and
Cryer's exact peak 1.3643. Writes scripts/data/stabilisation_fade.csv (scene, geometry, rule,
observable, value, converged, error_pct) and prints it as a table.

    python3 scripts/stabilisation_fade.py [--dir studies/stabilisation_fade] [--ranks 2]
    python3 scripts/stabilisation_fade.py --reference [--dir ...]   # the soft aggregate's converged peak

The rules: `drainage` (the old rule: fem.stabilisation_steps = 1e9, so only c_v Δt / h² fades it),
`shipped` (the scene's: drainage and steps), `none` (fem.stabilisation = 0), `constant`
(fem.stabilisation_fade and _steps = 1e9), and on the soft aggregate the old rule with τ₀ = 1e-4
and 1e-3 and the new one with fem.stabilisation_steps = 4.

--reference runs `scripts/convergence_study.py` on the soft aggregate's publication variant (the
meridian, h = 10 µm, poles and surface at 2 µm, no stabilisation; mesh levels h = 14.1, 10, 7.07 at
⅛ of the steps, step levels ¼, ⅛, 1/16 on h = 10; to the end of the ramp, t = 10 s; about 30 min on
2 busy cores) and writes its extrapolated peak force to scripts/data/soft_aggregate_reference.csv in
the format of references.csv.
"""
import argparse
import csv
import math
import subprocess
import sys
from pathlib import Path

from poroplast_tools.cases import run_cases
from poroplast_tools.refs import converged
from poroplast_tools.tables import write_rows

DATA = Path(__file__).resolve().parent / "data"
SOFT = DATA / "soft_aggregate.toml"
SOFT_REF = DATA / "soft_aggregate_reference.csv"
OUT = DATA / "stabilisation_fade.csv"
CRYER_PEAK = 1.3643
PEAK, F35, P_C = "max:force_total_mg", "force_total_mg@35", "max:p_center"
AXI = [("mesh.geometry", "axisymmetric")]
RULES = {
    "drainage": [("fem.stabilisation_steps", 1e9)],
    "shipped": [],
    "none": [("fem.stabilisation", 0.0)],
    "constant": [("fem.stabilisation_fade", 1e9), ("fem.stabilisation_steps", 1e9)],
    # The old rule with a smaller τ₀: the term gone after the first steps (1e-4) or kept for about
    # the first 1.3 s of the soft aggregate's ramp (1e-3).
    "tau0=1e-4": [("fem.stabilisation_fade", 1e-4), ("fem.stabilisation_steps", 1e9)],
    "tau0=1e-3": [("fem.stabilisation_fade", 1e-3), ("fem.stabilisation_steps", 1e9)],
    # The fade by the steps gone at 4 Δt₀ instead of the default 8.
    "steps=4": [("fem.stabilisation_steps", 4.0)],
}
# (scene, geometry, end time, rules, observables)
CASES = [
    (str(SOFT), "meridian", 10.0, ("drainage", "shipped", "none", "tau0=1e-4", "tau0=1e-3", "steps=4"), (PEAK,)),
    (str(SOFT), "3-D", 10.0, ("drainage", "shipped"), (PEAK,)),
    ("reference", "meridian", 35.0, ("drainage", "shipped", "none"), (PEAK, F35)),
    ("reference", "3-D", 35.0, ("drainage", "shipped"), (PEAK, F35)),
    ("remodel_40", "meridian", 35.0, ("drainage", "shipped"), (PEAK, F35)),
    ("cryer", "meridian", 6.0, ("constant", "drainage", "shipped", "none"), (P_C,)),
]


def truth(scene, observable):
    if scene == "cryer":
        return CRYER_PEAK
    if scene == str(SOFT):
        return converged("soft_aggregate", observable, SOFT_REF)
    return converged(scene, observable)


def compare(a):
    sets = [("output.fields", "false"), ("output.fields_at", "[]")]
    rows = []
    # One sweep per scene and geometry: a sweep checks every observable against every case.
    for scene, geo, t_end, rules, obs in CASES:
        overrides = [(AXI if geo == "meridian" else []) + [("time.t_end", t_end)] + RULES[rule] for rule in rules]
        results = run_cases(scene, overrides, sets, a.dir, a.ranks, observe=list(obs))
        for rule, (_, r) in zip(rules, results):
            if r.get("status") != "ok":
                sys.exit(f"{scene} {geo} {rule}: {r.get('status')} {r.get('error', '')}")
            for o in obs:
                ref = truth(scene, o)
                name = "soft_aggregate" if scene == str(SOFT) else scene
                rows.append({"scene": name, "geometry": geo, "rule": rule, "observable": o, "value": r[o],
                             "converged": ref, "error_pct": 100 * (r[o] / ref - 1)})
    write_rows(OUT, rows)
    print("| scene | geometry | observable | " + " | ".join(RULES) + " |\n|" + "---|" * (3 + len(RULES)))
    keys = sorted({(r["scene"], r["geometry"], r["observable"]) for r in rows}, key=lambda k: [x for x in k])
    for k in keys:
        err = {r["rule"]: r["error_pct"] for r in rows if (r["scene"], r["geometry"], r["observable"]) == k}
        cells = [f"{err[x]:+.2f}%" if x in err else "" for x in RULES]
        print(f"| {k[0]} | {k[1]} | {k[2]} | " + " | ".join(cells) + " |")
    print(f"wrote {OUT}")


def reference(a):
    """The soft aggregate's converged peak force (see the module's docstring)."""
    study = a.dir / "soft_reference"
    study.mkdir(parents=True, exist_ok=True)
    # The publication variant: absolute sizes (a study scales them level by level), no stabilisation.
    text = SOFT.read_text().replace("params = { R = 220.0 }",
                                    "params = { R = 220.0, h = 10.0, h_pole = 2.0, h_surf = 2.0, w_surf = 30.0 }")
    text = text.replace("relative_sizes = { h = 0.2, h_pole = 0.03, r_pole = 0.5 }   # mesh sizes / R",
                        'geometry = "axisymmetric"').replace("stabilisation_fade = 0.03", "stabilisation = 0.0")
    scene = study / "soft_aggregate_publication.toml"
    scene.write_text(text)
    cmd = [sys.executable, str(Path(__file__).parent / "convergence_study.py"), str(scene),
           "--h", "14.1,10,7.07", "--dt-scale", "0.25,0.125,0.0625", "--time-mesh", "10", "--mesh-steps", "0.125",
           "--set", "time.t_end=10", "--set", "output.fields=false", "--set", "output.fields_at=[]",
           "--observe", PEAK, "--ranks", str(a.ranks), "--dir", str(study / "study")]
    if subprocess.run(cmd).returncode != 0:
        sys.exit("stabilisation_fade.py: the convergence study failed (above)")
    with open(study / "study" / "convergence.csv") as f:
        rows = [{"case": "soft_aggregate", **r} for r in csv.DictReader(f) if r["observable"] == PEAK]
    if not rows or not math.isfinite(float(rows[0]["extrapolated"])):
        sys.exit("stabilisation_fade.py: no extrapolated peak in the study's convergence.csv")
    write_rows(SOFT_REF, rows)
    print(f"wrote {SOFT_REF}: peak {float(rows[0]['extrapolated']):.6g} ± {float(rows[0]['error_bar']):.2g} mg")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", type=Path, default=Path("studies/stabilisation_fade"))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--reference", action="store_true", help="measure the soft aggregate's converged peak")
    a = ap.parse_args()
    (reference if a.reference else compare)(a)


if __name__ == "__main__":
    main()
