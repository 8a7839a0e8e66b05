"""Candidate causes of the paper's quantitative gaps, each measured on its own: one variant of
the axisymmetric `remodel_155` at the converged level (the meridian at h = 10 µm, surface and
poles at 2 µm, no pressure stabilisation, the runs stopped at 60 s; docs/studies.md), one cause
per variant, and each one's shift of the syringe crossing time and of the peaks against the base.

Shifts converge faster than the values: at ⅛ of the scene's steps (the default here) the base
crossing is 0.3 s above its converged value (docs/studies.md), and the `steps` rows show how a
shift itself moves with the steps.

    python3 scripts/causes.py [--dir studies/causes] [--steps 0.125] [--ranks 2] [--only NAME ...]

Writes DIR/causes.csv (variant, what it changes, the observables, their shifts; with --only, the
rows of those variants replace theirs in an existing DIR/causes.csv) and prints the table; then
the same for the no-remodelling gap (`reference_405`, its settling times:
DIR/causes_reference.csv; --no-reference skips it). The variants of each table run as one
batch (one `poroplast sweep`) whose cases are kept in DIR/cases, so an interrupted run continues.
"""
import argparse
import csv
import math
import sys
from pathlib import Path

from poroplast_tools import fields
from poroplast_tools.cases import rank_options, run_cases, scene_values, use_rank_options
from poroplast_tools.levels import CONVERGED_LEVEL, refined_steps
from poroplast_tools.tables import write_rows

SCENE = "remodel_155"
BASE = [tuple(s.split("=", 1)) for s in CONVERGED_LEVEL] + [("time.t_end", "60"), ("output.fields", "false"),
                                                            ("output.fields_at", "[]")]
OBSERVE = ["zero:probe_p", "max:force_total_mg", "max:force_constitutive_mg", "probe_p@30"]

# X_U = (0.4 R, 0, 1.9 R) of the sphere of R = 100 µm centred at z = R: its outward normal n and
# the meridian tangent t, for the probe's ±1 µm variants.
_XU = (40.0, 0.0, 190.0)
_N = (0.4 / math.hypot(0.4, 0.9), 0.0, 0.9 / math.hypot(0.4, 0.9))
_T = (_N[2], 0.0, -_N[0])


def _point(d, s):
    return "[" + ", ".join(f"{x + s * e:.6f}" for x, e in zip(_XU, d)) + "]"


# Table 1's α's as printed match ν ≈ 0.1 and µ = 2 α0 (α3 − α2) ≈ 0.22 kPa, not (20 kPa, 0.2);
# α3 = α1 + 2 α2 = 1 (stress-free reference). "Rescaled": α1, α2 as printed, α0 for µ = 20 kPa.
ALPHA_PRINTED = [0.125, 0.78, 0.11]
ALPHA_RESCALED = [20.0 / (2 * (1.0 - 0.11)), 0.78, 0.11]

C2 = [("material.k0", "2.5779"), ("material.permeability_c", "2")]

# name -> (what it changes, --set overrides, scene-text edits (old line start -> new line or None))
VARIANTS = {
    "base": ("the converged level (Table 1, (56)'s α's from µ = 20 kPa, ν = 0.2)", [], []),
    "alpha_printed": ("Table 1's α's as printed (α0 = 0.125 kPa, α1 = 0.78, α2 = 0.11)", [],
                      [("mu = ", None), ("nu = ", f"alpha = {ALPHA_PRINTED}")]),
    "alpha_rescaled": (f"α1, α2 as printed, α0 = {ALPHA_RESCALED[0]:.3f} kPa (µ = 20 kPa)", [],
                       [("mu = ", None), ("nu = ", f"alpha = {ALPHA_RESCALED}")]),
    "form_40a": ("(40a)'s flow rule: the rate with the 1/J factor (the base: (40b))",
                 [("material.remodelling.form", '"40a"')], []),
    "steps_default": ("the scene's own steps (×1 instead of ×⅛)", "steps:1", []),
    "steps_16": ("steps × 1/16", "steps:0.0625", []),
    "probe_out": ("X_U 1 µm outward along the surface normal", [("plates.probe_point", _point(_N, 1.0))], []),
    "probe_in": ("X_U 1 µm inward along the surface normal", [("plates.probe_point", _point(_N, -1.0))], []),
    "probe_equator": ("X_U 1 µm along the surface, towards the equator", [("plates.probe_point", _point(_T, 1.0))], []),
    "probe_pole": ("X_U 1 µm along the surface, towards the pole", [("plates.probe_point", _point(_T, -1.0))], []),
    "seal_gap_025": ("seal gap 1 → 0.25 µm", [("plates.seal_gap", "0.25")], []),
    "gravity_off": ("no gravity", [("material.gravity", "[0.0, 0.0, 0.0]")], []),
    "penalty_off": ("no compaction penalty", [], [("penalty = ", None)]),
    # The paper's slightly permeable plates as a Robin outflow k_β / L through the contact area
    # (src/physics/contact.rs): Table 1's k_β with L = 100 µm (the plates' thickness is not given;
    # Fig 2 draws them about as thick as the aggregate), then 100 times the conductance (L = 1 µm),
    # then plates as permeable as the aggregate (k_β = k0, 10⁴ times Table 1's).
    "plates_permeable": ("permeable plates, k_β = 3.7729e-7 mm⁴/(N s) (Table 1), L = 100 µm",
                         [("plates.permeability", "3.7729e-4"), ("plates.thickness", "100")], []),
    "plates_permeable_thin": ("permeable plates, Table 1's k_β, L = 1 µm (100× the conductance)",
                              [("plates.permeability", "3.7729e-4"), ("plates.thickness", "1")], []),
    "plates_as_aggregate": ("permeable plates, k_β = k0 of the aggregate (10⁴× Table 1's), L = 100 µm",
                            [("plates.permeability", "3.7729"), ("plates.thickness", "100")], []),
    # The other gaps' cases (Fig 11: c = 2 crosses at 28 s; Figs 7b-8b: λp = 0.1 raises the peaks)
    # with and without the one cause that moves the crossing.
    "c2": ("Fig 11's permeability: c = 2, k0 = 2.5779e-3 mm⁴/(N s)", C2, []),
    "c2_40a": ("c = 2 with (40a)", C2 + [("material.remodelling.form", '"40a"')], []),
    "lambda_01": ("λp = 0.1 (MPa s)⁻¹", [("material.remodelling.lambda_p", "0.0001")], []),
    "lambda_01_40a": ("λp = 0.1 (MPa s)⁻¹ with (40a)",
                      [("material.remodelling.lambda_p", "0.0001"), ("material.remodelling.form", '"40a"')], []),
    # What the paper's +4 / +2 mg would take: the same tenfold step in λp, ten and a hundred times faster.
    "lambda_10": ("λp = 10 (MPa s)⁻¹", [("material.remodelling.lambda_p", "0.01")], []),
    "lambda_100": ("λp = 100 (MPa s)⁻¹", [("material.remodelling.lambda_p", "0.1")], []),
    # (40a)'s −2.13 s on the crossing could as well be a faster rate: the λp that gives the same
    # shift, and what each predicts for the c = 2 and λp = 0.1 rows.
    "lambda_x115": ("λp × 1.15 (1.15 (MPa s)⁻¹)", [("material.remodelling.lambda_p", "0.00115")], []),
    "lambda_x125": ("λp × 1.25 (1.25 (MPa s)⁻¹)", [("material.remodelling.lambda_p", "0.00125")], []),
    "lambda_x120": ("λp × 1.2 (1.2 (MPa s)⁻¹)", [("material.remodelling.lambda_p", "0.0012")], []),
    "lambda_x110": ("λp × 1.1 (1.1 (MPa s)⁻¹): the crossing's shift of (40a)", [("material.remodelling.lambda_p", "0.0011")], []),
    "c2_lambda_x110": ("c = 2 with λp × 1.1", C2 + [("material.remodelling.lambda_p", "0.0011")], []),
    "lambda_01_x110": ("λp = 0.11 (MPa s)⁻¹: λp = 0.1 with λp × 1.1", [("material.remodelling.lambda_p", "0.00011")], []),
    # A third place a J can enter: γp of the Kirchhoff stress τ = J σ in (41) ("40b_tau").
    "form_tau": ("γp of τ = J σ: (41) with the Kirchhoff stress", [("material.remodelling.form", '"40b_tau"')], []),
    "c2_tau": ("c = 2 with γp of τ", C2 + [("material.remodelling.form", '"40b_tau"')], []),
    "lambda_01_tau": ("λp = 0.1 (MPa s)⁻¹ with γp of τ",
                      [("material.remodelling.lambda_p", "0.0001"), ("material.remodelling.form", '"40b_tau"')], []),
    "lambda_01_alpha_rescaled": ("λp = 0.1 (MPa s)⁻¹ with α1, α2 as printed, α0 for µ = 20 kPa",
                                 [("material.remodelling.lambda_p", "0.0001")],
                                 [("mu = ", None), ("nu = ", f"alpha = {ALPHA_RESCALED}")]),
}


# The gap without remodelling (the paper: a plateau soon after the ramp; ours settles over ~100 s):
# `reference_405` at the same level, its settling times with each candidate that could drain it
# faster. name -> (what it changes, --set overrides)
REFERENCE_SCENE = "reference_405"
REFERENCE_OBSERVE = ["settle90:force_total_mg", "settle95:force_total_mg", "force_total_mg@60", "force_total_mg@400"]
REFERENCE_VARIANTS = {
    "ref_base": ("no remodelling, the converged level", []),
    "ref_plates_permeable": ("permeable plates, Table 1's k_β, L = 100 µm", [("plates.permeability", "3.7729e-4"),
                                                                             ("plates.thickness", "100")]),
    "ref_plates_thin": ("permeable plates, Table 1's k_β, L = 1 µm", [("plates.permeability", "3.7729e-4"),
                                                                     ("plates.thickness", "1")]),
    "ref_k0_x10": ("k0 × 10 (3.7729e-2 mm⁴/(N s))", [("material.k0", "37.729")]),
}


# The remodelling rows read from fields and shapes (σ_VM, ‖E_p‖, the positive-pressure region,
# H/W), under each same-size candidate for the crossing: name -> (what it changes, --set
# overrides), each run on the FIELD_CASES below (scene, --set overrides, observables).
FIELD_VARIANTS = {
    "base": ("(40b), the base", []),
    "form_40a": ("(40a)", [("material.remodelling.form", '"40a"')]),
    "lambda_x110": ("λp × 1.1", [("material.remodelling.lambda_p", "0.0011")]),
    "form_tau": ("γp of τ = J σ", [("material.remodelling.form", '"40b_tau"')]),
}
_FIELDS = [("output.fields", "true"), ("output.fields_every", "100000")]
FIELD_CASES = {
    # Figs 5-6: σ_VM around the upper detachment (35-37 s) and after the release, ‖E_p‖ frozen.
    "remodel_40": ("remodel_40", _FIELDS + [("output.fields_at", "[35.0, 36.0, 37.0, 40.0, 60.0]")],
                   ["vm_contact@35", "vm_contact@40", "vm_contact/centre@40", "ep_contact/centre@60",
                    "vm_centre@35", "vm_centre@36", "vm_centre@37", "vm_contact@36", "vm_contact@37"]),
    # Fig 3: the positive-pressure region.
    "remodel_155": ("remodel_155", _FIELDS + [("output.fields_at", "[35.0, 45.0, 60.0]")],
                    ["bubble_share@45", "bubble_where@45"]),
    # Fig 10-11a: H/W after 65 s of compression and 60 s of rest (k0 = 2.5779e-3, as references.py's hw_65).
    "hw_65": ("remodel_40", [("plates.t_end", "65"), ("time.t_end", "125"), ("material.k0", "2.5779")],
              ["last:height/width"]),
}


def field_rows(root, ranks, step_scale, only=None):
    """Each FIELD_VARIANTS' observables on every FIELD_CASES (one row per variant), and shifts
    from the base; --only keeps the variants named."""
    names = [n for n in FIELD_VARIANTS if not only or n in only or n == "base"]
    rows = {n: {"variant": n, "changes": FIELD_VARIANTS[n][0], "status": "ok"} for n in names}
    for case, (scene, sets, observe) in FIELD_CASES.items():
        steps = [(k, f"{v:g}") for k, v in refined_steps(scene_values(scene)["time"], {}, step_scale)]
        # The converged level, its t_end (60 s) unless the case has its own, with fields.
        base = [(k, v) for k, v in BASE if not k.startswith("output.") and k not in dict(sets)]
        done = run_cases(scene, [steps + sets + FIELD_VARIANTS[n][1] for n in names], base, root, ranks, [],
                         fields.history_observables(observe))
        for n, (cdir, r) in zip(names, done):
            ok = r["status"] == "ok"
            rows[n]["status"] = rows[n]["status"] if ok else f"{case}: {r['status']}"
            for o in observe:
                rows[n][f"{case}|{o}"] = fields.observed(cdir, r, o) if ok else float("nan")
    rows = list(rows.values())
    for r in rows:
        for k in [k for k in rows[0] if "|" in k]:
            r["shift " + k] = r[k] - rows[0][k]
    return rows


def reference_rows(root, ranks, step_scale):
    """The REFERENCE_VARIANTS' settling times and forces, each with its shift from ref_base."""
    t = scene_values(REFERENCE_SCENE)["time"]
    steps = [(k, f"{v:g}") for k, v in refined_steps(t, {}, step_scale)]
    base = [(k, v) for k, v in BASE if k != "time.t_end"]
    rows = []
    done = run_cases(REFERENCE_SCENE, [steps + sets for _, sets in REFERENCE_VARIANTS.values()], base, root, ranks,
                     [], fields.history_observables(REFERENCE_OBSERVE))
    for (name, (what, _)), (cdir, r) in zip(REFERENCE_VARIANTS.items(), done):
        ok = r["status"] == "ok"
        val = lambda o: fields.observed(cdir, r, o) if ok else float("nan")
        rows.append({"variant": name, "changes": what, "status": r["status"], **{o: val(o) for o in REFERENCE_OBSERVE}})
    for r in rows:
        for o in REFERENCE_OBSERVE:
            r["shift " + o] = r[o] - rows[0][o]
    return rows


def scene_text(edits, out):
    """The shipped scene with lines starting with `old` replaced by `new` (None: dropped)."""
    src = (Path(__file__).resolve().parent.parent / "meshes" / "scenes" / f"{SCENE}.toml").read_text().splitlines()
    missing = [old for old, _ in edits if not any(line.startswith(old) for line in src)]
    if missing:
        sys.exit(f"causes.py: {SCENE}.toml has no line starting with {missing}")
    lines = []
    for line in src:
        hit = next((e for e in edits if line.startswith(e[0])), None)
        if hit is None:
            lines.append(line)
        elif hit[1] is not None:
            lines.append(hit[1])
    out.write_text("\n".join(lines) + "\n")
    return str(out)


def merged(path, rows):
    """`rows` in place of the rows of the same variants of the table at `path` (if it exists),
    the others kept in their order: `--only` updates the variants it runs."""
    if not path.exists():
        return rows
    with open(path, newline="") as f:
        kept = list(csv.DictReader(f))
    for r in kept:
        for o in OBSERVE + ["wall_s"]:
            r[o] = float(r[o]) if r[o] not in ("", None) else float("nan")
    new = {r["variant"]: r for r in rows}
    out = [new.pop(r["variant"], r) for r in kept]
    return out + list(new.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dir", default="studies/causes")
    ap.add_argument("--steps", type=float, default=0.125, help="step scale of every variant but the steps rows")
    rank_options(ap)
    ap.add_argument("--only", nargs="+", choices=list(VARIANTS))
    ap.add_argument("--no-reference", action="store_true", help="skip the reference_405 variants")
    ap.add_argument("--fields", action="store_true", help="only the remodelling rows read from fields, for the "
                    "FIELD_VARIANTS (with --only: those of them): DIR/causes_fields.csv")
    a = ap.parse_args()
    use_rank_options(a)
    root = Path(a.dir)
    (root / "scenes").mkdir(parents=True, exist_ok=True)
    scene_time = scene_values(SCENE)["time"]
    steps = lambda s: [(k, f"{v:g}") for k, v in refined_steps(scene_time, {}, s)]
    if a.fields:
        rows = field_rows(root, a.ranks, a.steps, a.only)
        write_rows(root / "causes_fields.csv", rows)
        for r in rows:
            print(r["variant"], ", ".join(f"{k} {v:.4g}" for k, v in r.items() if "|" in k and not k.startswith("shift")))
        return
    names, scenes, cases = a.only or list(VARIANTS), [], []
    for name in names:
        what, sets, edits = VARIANTS[name]
        if isinstance(sets, str):   # "steps:S": the base at another step scale
            sets = steps(float(sets.split(":")[1]))
        else:
            sets = steps(a.steps) + sets
        scenes.append(scene_text(edits, root / "scenes" / f"{name}.toml") if edits else SCENE)
        cases.append(sets)
    rows = []
    for name, (_, r) in zip(names, run_cases(scenes, cases, BASE, root, a.ranks, [], OBSERVE)):
        rows.append({"variant": name, "changes": VARIANTS[name][0], "status": r["status"], "wall_s": r.get("wall_s"),
                     **{o: r.get(o, float("nan")) for o in OBSERVE}})
    rows = merged(root / "causes.csv", rows)
    base = next((r for r in rows if r["variant"] == "base"), None)
    for r in rows:
        for o in OBSERVE:
            r["shift " + o] = r[o] - base[o] if base and r["status"] == "ok" else float("nan")
    write_rows(root / "causes.csv", rows)
    print(f"\n{'variant':16} {'crossing (s)':>13} {'shift':>7} {'peak (mg)':>10} {'shift':>7} "
          f"{'constit. (mg)':>13} {'shift':>7}  changes")
    for r in rows:
        print(f"{r['variant']:16} {r['zero:probe_p']:13.3f} {r['shift zero:probe_p']:+7.2f} "
              f"{r['max:force_total_mg']:10.3f} {r['shift max:force_total_mg']:+7.3f} "
              f"{r['max:force_constitutive_mg']:13.3f} {r['shift max:force_constitutive_mg']:+7.3f}  {r['changes']}")
    if a.no_reference or a.only:
        return
    ref = reference_rows(root, a.ranks, a.steps)
    write_rows(root / "causes_reference.csv", ref)
    print(f"\n{'variant':22} {'90% (s)':>8} {'shift':>7} {'95% (s)':>8} {'shift':>7} {'F(60 s)':>8} {'F(400 s)':>9}  changes")
    for r in ref:
        print(f"{r['variant']:22} {r['settle90:force_total_mg']:8.2f} {r['shift settle90:force_total_mg']:+7.2f} "
              f"{r['settle95:force_total_mg']:8.2f} {r['shift settle95:force_total_mg']:+7.2f} "
              f"{r['force_total_mg@60']:8.3f} {r['force_total_mg@400']:9.3f}  {r['changes']}")


if __name__ == "__main__":
    main()
