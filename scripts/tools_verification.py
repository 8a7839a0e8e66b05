#!/usr/bin/env python3
"""The rigid tools against their closed forms: a sphere (R = 100 µm) indenting a linear block on
the meridian (G = 1 kPa, ν = 0.2, bottom on rollers), against Hertz and Sneddon
(poroplast_tools/indentation_refs.py), undrained (sealed, ν = ½) at several meshes and block
heights, and drained at two depths with the mesh scaled with the contact. Writes one row per
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

# (case, sealed, δ µm, H µm, h_c µm)
CASES = [
    ("undrained_H500_hc1", True, 1.0, 500.0, 1.0),
    ("undrained_H500_hc0.5", True, 1.0, 500.0, 0.5),
    ("undrained_H1000_hc0.5", True, 1.0, 1000.0, 0.5),
    ("drained_d0.1", False, 0.1, 500.0, 0.1 ** 0.5),
    ("drained_d0.025", False, 0.025, 500.0, 0.025 ** 0.5),
]


def scene(sealed, delta, height, h_c):
    k, drain = ("1e-6", "") if sealed else ("1e6", '\n[[bc]]\ngroup = "top"\npressure = 0.0\n')
    return f"""name = "hertz"
[mesh]
geo = "block_meridian.geo"
geometry = "axisymmetric"
params = {{ H = {height}, h = {height / 8}, h_c = {h_c}, d_c = {40 * h_c}, w_c = {0.4 * height} }}

[material]
model = "linear"
mu = {G}
nu = {NU}
permeability = {k}

[[bc]]
group = "bottom"
displacement = {{ z = 0.0 }}
{drain}
[[tools]]
name = "bead"
kind = "sphere"
radius = {R_SPHERE}
origin = [0.0, 0.0, {height + R_SPHERE}]
axis = [0.0, 0.0, -1.0]
group = "top"
protocol = [ {{ t = 0.0, displacement = 0.0 }}, {{ t = 1.0, displacement = {delta} }} ]

[time]
t_end = 1.0
dt = 0.25
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.environ.get("POROPLAST_BIN", str(ROOT / "target/release/poroplast")))
    ap.add_argument("--ranks", type=int, default=1)
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, sealed, delta, height, h_c in CASES:
            path = Path(tmp) / f"{name}.toml"
            path.write_text(scene(sealed, delta, height, h_c))
            out = Path(tmp) / name
            cmd = ["mpirun", "-n", str(args.ranks), args.bin, "run", str(path), "-q", "--out", str(out)]
            t0 = time.time()
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"tools_verification.py: {name} failed:\n{run.stderr}")
            wall = time.time() - t0
            e_star = ir.contact_modulus(G, 0.5 if sealed else NU)
            hist = list(csv.DictReader(open(out / "history.csv")))
            for r in hist[1:]:
                d = float(r["bead_position"])
                f = 1e3 * float(r["bead_force_uN"])
                hertz = ir.hertz_force(d, R_SPHERE, e_star)
                rows.append({
                    "case": name, "drained": int(not sealed), "H": height, "h_c": h_c, "delta": d,
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
