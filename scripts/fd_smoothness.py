"""Is a run's curve a smooth function of a parameter? Forward differences of a history column at
data times, for relative steps 1e-2 ... 1e-6, with the neighbours choosing their own time steps
(adaptive) and taking the point's (`time.steps`, as calibrate.py's neighbours do).

For a smooth curve the difference quotient D_h(t) = (c(θ(1 + h), t) − c(θ, t)) / (θ h) converges
as h shrinks: between successive steps (a factor 10) it changes by O(h), ten times less each
time, at every data time, until round-off (about 1e-12 / h of the curve). An outlier is a data
time where it does not: a step cut or an error rejection in one run and not in the other.

    python3 scripts/fd_smoothness.py remodel_40 --param material.remodelling.lambda_p=0.002 \\
        --column force_total_mg --every 1 --set mesh.geometry=axisymmetric --dir studies/fd

Writes DIR/fd_smoothness.csv (mode, h, data time, D_h) and DIR/fd_smoothness.png, and prints per
mode and successive pair of steps the largest and the median change of D relative to max |D|.
Every run is a case of DIR/runs/cases (one `poroplast sweep` per batch)."""
import argparse
import csv
import math
import sys
from pathlib import Path

import numpy as np

from poroplast_tools.cases import rank_options, run_cases, use_rank_options
from poroplast_tools.history import given_steps, history

STEPS = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--param", required=True, metavar="KEY=VALUE", help="the parameter and its value")
    ap.add_argument("--column", default="force_total_mg")
    ap.add_argument("--every", type=float, default=1.0, help="data times every this many s, from it to t_end")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--dir", required=True)
    rank_options(ap)
    a = ap.parse_args()
    use_rank_options(a)
    key, value = a.param.split("=", 1)
    theta = float(value)
    root = Path(a.dir)
    root.mkdir(parents=True, exist_ok=True)
    sets = [tuple(s.split("=", 1)) for s in a.set]

    def runs(cases):
        out = run_cases(a.scene, cases, sets, root / "runs", a.ranks)
        bad = [str(d) for d, r in out if r["status"] != "ok"]
        if bad:
            sys.exit(f"fd_smoothness.py: runs failed: {', '.join(bad)}")
        return [history(d) for d, _ in out]

    [h0] = runs([[(key, repr(theta))]])
    t0 = np.asarray(h0["time"], dtype=float)
    times = np.arange(a.every, t0[-1] + 1e-9 * t0[-1], a.every)
    c0 = np.interp(times, t0, np.asarray(h0[a.column], dtype=float))
    modes = {"adaptive": [], "replayed": [("time.steps", given_steps(h0))]}
    cases = [[(key, repr(theta * (1 + h)))] + extra for extra in modes.values() for h in STEPS]
    hs = runs(cases)
    quotients = {}
    for m, mode in enumerate(modes):
        for i, h in enumerate(STEPS):
            hist = hs[m * len(STEPS) + i]
            c = np.interp(times, np.asarray(hist["time"], dtype=float), np.asarray(hist[a.column], dtype=float))
            quotients[mode, h] = (c - c0) / (theta * h)
    with open(root / "fd_smoothness.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mode", "h", "time", f"d{a.column}/d{key}"])
        for (mode, h), d in quotients.items():
            w.writerows([mode, h, t, repr(float(x))] for t, x in zip(times, d))
    print(f"d {a.column} / d {key} at {len(times)} data times ({a.every:g} s apart), {key} = {theta:g}:")
    changes = {}
    for mode in modes:
        scale = float(np.max(np.abs(quotients[mode, STEPS[1]])))
        print(f"  {mode}: max |D| {scale:.4g}")
        for h1, h2 in zip(STEPS, STEPS[1:]):
            d = np.abs(quotients[mode, h2] - quotients[mode, h1]) / scale
            k = int(np.argmax(d))
            changes[mode, h2] = d
            print(f"    h {h1:g} -> {h2:g}: largest change {d[k]:.2e} (t = {times[k]:g} s), median {np.median(d):.2e}")
    plot(root, a, key, times, quotients, changes, modes)
    print(f"{root / 'fd_smoothness.csv'}, {root / 'fd_smoothness.png'}")


def plot(root, a, key, times, quotients, changes, modes):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for h in STEPS:
        ax1.plot(times, quotients["replayed", h], lw=1, label=f"h = {h:g}")
    ax1.set_xlabel("t (s)")
    ax1.set_ylabel(f"d {a.column} / d {key}")
    ax1.set_title("replayed steps")
    ax1.legend(fontsize=7)
    for mode, style in zip(modes, ("o-", "s--")):
        ax2.loglog(STEPS[1:], [float(np.max(changes[mode, h])) for h in STEPS[1:]], style, label=f"{mode}: largest")
        ax2.loglog(STEPS[1:], [float(np.median(changes[mode, h])) for h in STEPS[1:]], style, alpha=0.4,
                   label=f"{mode}: median")
    ax2.set_xlabel("h (the smaller of two successive steps)")
    ax2.set_ylabel("change of D over the data times / max |D|")
    ax2.legend(fontsize=7)
    fig.suptitle(f"{a.scene} {' '.join(a.set)}"[:150], fontsize=7)
    fig.tight_layout()
    fig.savefig(root / "fd_smoothness.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
