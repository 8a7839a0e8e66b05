#!/usr/bin/env python3
"""The rigid tools against their closed forms: a sphere (R = 100 µm) indenting a linear block on
the meridian (G = 1 kPa, ν = 0.2, bottom on rollers), against Hertz and Sneddon
(poroplast_tools/indentation_refs.py), undrained (ν = ½) at several meshes and block
heights, and drained at two depths with the mesh scaled with the contact, all from
tests/data/hertz_block.toml with overrides. Writes one row per
case and step to scripts/data/tools_hertz.csv (docs/verification.md, "Rigid tools"); the tests
of tests/tools.rs run the cheapest of these cases.

    python3 scripts/tools_verification.py [--bin target/release/poroplast] [--ranks 1]
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.environ.get("POROPLAST_BIN", str(ROOT / "target/release/poroplast")))
    ap.add_argument("--ranks", type=int, default=1)
    args = ap.parse_args()
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
