#!/usr/bin/env python3
"""The rigid tools against their closed forms: a sphere (R = 100 µm) indenting a linear block on
the meridian (G = 1 kPa, ν = 0.2, bottom on rollers), against Hertz and Sneddon
(poroplast_tools/indentation_refs.py), undrained (ν = ½) at several meshes and block
heights, and drained at two depths with the mesh scaled with the contact, all from
tests/data/hertz_block.toml with overrides. Writes one row per
case and step to scripts/data/tools_hertz.csv (docs/verification.md, "Rigid tools"); the tests
of tests/tools.rs run the cheapest of these cases.

The poroelastic relaxation under a held sphere (tests/data/indent_relaxation.toml, δ = 0.25 µm,
a = 5 µm, ramp τ_r = 1e-3, held to τ = 10), normalised by the same mesh's own undrained and
drained forces (two short runs), against Hu et al.'s g(τ − 0.6 τ_r) (the ramp's first-order
shift), at two meshes and two step growths: one row per case and step from τ = 10 τ_r to
scripts/data/tools_relaxation.csv (`--relaxation`; `--hertz` for the first table only).

    python3 scripts/tools_verification.py [--bin target/release/poroplast] [--ranks 1] [--hertz | --relaxation]
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from poroplast_tools import indentation_refs as ir

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "scripts" / "data" / "tools_hertz.csv"
OUT_RELAXATION = ROOT / "scripts" / "data" / "tools_relaxation.csv"
RELAXATION_SCENE = ROOT / "tests" / "data" / "indent_relaxation.toml"
# δ (µm) and its ramp (s: τ_r = 1e-3 with D = 8/3 µm²/s, a² = Rδ), as the scene has them.
RELAX_DELTA, RELAX_RAMP = 0.25, 0.009375
# (case, h_c µm, step growth)
RELAX_CASES = [("hc1_g1.25", 1.0, 1.25), ("hc0.5_g1.25", 0.5, 1.25), ("hc1_g1.1", 1.0, 1.1)]
R_SPHERE, G, NU = 100.0, 1.0, 0.2

SCENE = ROOT / "tests" / "data" / "hertz_block.toml"

# (case, drained, δ µm, H µm, h_c µm)
CASES = [
    ("undrained_H500_hc1", False, 1.0, 500.0, 1.0),
    ("undrained_H500_hc0.5", False, 1.0, 500.0, 0.5),
    ("undrained_H1000_hc0.5", False, 1.0, 1000.0, 0.5),
    ("drained_d0.1", True, 0.1, 500.0, 0.1 ** 0.5),
    ("drained_d0.025", True, 0.025, 500.0, 0.025 ** 0.5),
]


def overrides(drained, delta, height, h_c):
    """tests/data/hertz_block.toml's keys for one case (the mesh scaled with H, h_c at the contact;
    drained: a huge permeability and the top drained)."""
    sets = {
        "material.permeability": 1e6 if drained else 1e-6,
        "mesh.params.H": height, "mesh.params.h": height / 8, "mesh.params.w_c": 0.4 * height,
        "mesh.params.h_c": h_c, "mesh.params.d_c": 40 * h_c,
        "tools.0.origin": f"[0,0,{height + R_SPHERE}]",
        "tools.0.protocol": f"[{{t=0.0,displacement=0.0}},{{t=1.0,displacement={delta}}}]",
    }
    if drained:
        sets["bc"] = '[{group="bottom",displacement={z=0.0}},{group="top",pressure=0.0}]'
    return [a for k, v in sets.items() for a in ("--set", f"{k}={v}")]


def run(args, scene, out, sets):
    """One run of `scene` with `sets` ({key: value}) into `out`: its history rows and wall time."""
    cmd = ["mpirun", "-n", str(args.ranks), args.bin, "run", str(scene), "-q", "--out", str(out)]
    cmd += [a for k, v in sets.items() for a in ("--set", f"{k}={v}")]
    t0 = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"tools_verification.py: {out.name} failed:\n{proc.stderr}")
    return list(csv.DictReader(open(out / "history.csv"))), time.time() - t0


def relaxation_rows(hist, f0, f_inf, case, h_c, growth):
    """The rows of one relaxation run from τ = 10 τ_r to 10 (the scene's end): its g
    against Hu et al.'s."""
    diffusivity = ir.poroelastic_diffusivity(G, NU, 1.0)
    a2 = R_SPHERE * RELAX_DELTA
    rows = []
    for r in hist:
        t = float(r["time"])
        tau = diffusivity * t / a2
        if t < 10 * RELAX_RAMP * (1 - 1e-9) or tau > 10 * (1 + 1e-9):
            continue
        force = 1e3 * float(r["bead_force_uN"])
        g_fe = (force - f_inf) / (f0 - f_inf)
        g_hu = ir.relaxation_g(diffusivity * (t - 0.6 * RELAX_RAMP) / a2)
        rows.append({"case": case, "h_c": h_c, "growth": growth, "t": t, "tau": tau, "force_nN": force,
                     "f0_nN": f0, "f_inf_nN": f_inf, "g_fe": g_fe, "g_hu": g_hu, "diff": g_fe - g_hu})
    return rows


def relaxation(args, tmp):
    """The relaxation cases (module docs) into OUT_RELAXATION."""
    rows = []
    for case, h_c, growth in RELAX_CASES:
        # The first step a quarter of the ramp at growth 1.25, shorter with the growth.
        base = {"mesh.params.h_c": h_c, "mesh.params.d_c": 30 * h_c,
                "time.dt": RELAX_RAMP / 4 * (growth - 1) / 0.25, "time.growth": growth}
        limits = []
        for name, extra in [
            ("undrained", {"material.permeability": 1e-8}),
            ("drained", {"material.permeability": 1e6,
                         "bc": '[{group="bottom",displacement={z=0.0}},{group="top",pressure=0.0}]'}),
        ]:
            hist, _ = run(args, RELAXATION_SCENE, Path(tmp) / f"{case}_{name}",
                          {**base, **extra, "time.t_end": RELAX_RAMP})
            limits.append(1e3 * float(hist[-1]["bead_force_uN"]))
        hist, wall = run(args, RELAXATION_SCENE, Path(tmp) / case, base)
        case_rows = relaxation_rows(hist, limits[0], limits[1], case, h_c, growth)
        worst = max(case_rows, key=lambda r: abs(r["diff"]))
        print(f"relaxation {case}: F0 = {limits[0]:.4f}, F∞ = {limits[1]:.4f} nN, max |g − g_Hu| = "
              f"{abs(worst['diff']):.4f} at τ = {worst['tau']:.3g}, {wall:.1f} s")
        rows += case_rows
    with open(OUT_RELAXATION, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {OUT_RELAXATION.relative_to(ROOT)}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.environ.get("POROPLAST_BIN", str(ROOT / "target/release/poroplast")))
    ap.add_argument("--ranks", type=int, default=1)
    only = ap.add_mutually_exclusive_group()
    only.add_argument("--hertz", action="store_true", help="the Hertz table only")
    only.add_argument("--relaxation", action="store_true", help="the relaxation table only")
    args = ap.parse_args()
    if not args.hertz:
        with tempfile.TemporaryDirectory() as tmp:
            relaxation(args, tmp)
        if args.relaxation:
            return
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, drained, delta, height, h_c in CASES:
            out = Path(tmp) / name
            cmd = ["mpirun", "-n", str(args.ranks), args.bin, "run", str(SCENE), "-q", "--out", str(out)]
            cmd += overrides(drained, delta, height, h_c)
            t0 = time.time()
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"tools_verification.py: {name} failed:\n{run.stderr}")
            wall = time.time() - t0
            e_star = ir.contact_modulus(G, NU if drained else 0.5)
            hist = list(csv.DictReader(open(out / "history.csv")))
            for r in hist[1:]:
                d = float(r["bead_position"])
                f = 1e3 * float(r["bead_force_uN"])
                hertz = ir.hertz_force(d, R_SPHERE, e_star)
                rows.append({
                    "case": name, "drained": int(drained), "H": height, "h_c": h_c, "delta": d,
                    "a_over_R": ir.hertz_contact_radius(d, R_SPHERE) / R_SPHERE,
                    "force_nN": f, "hertz_nN": hertz, "err_hertz": f / hertz - 1,
                    "err_sneddon": f / ir.sneddon_force(d, R_SPHERE, e_star) - 1,
                    "contact_radius": float(r["bead_contact_radius"]),
                    "penetration": float(r["bead_penetration"]),
                    "wall_s": round(wall, 2),
                })
            print(f"{name}: F/F_Hertz − 1 = {rows[-1]['err_hertz']:+.4%} at δ = {delta}, "
                  f"penetration {rows[-1]['penetration']:.1e} µm, {wall:.1f} s")
    with open(OUT, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
