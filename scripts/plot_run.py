#!/usr/bin/env python3
"""Draws a run directory, or a sweep directory with its cases overlaid, into PNGs beside it.

    python3 scripts/plot_run.py RUN_DIR [--times 5,35]
    python3 scripts/plot_run.py SWEEP_DIR

plot_history.png: force, probe pressure and H/W against time, the plate protocol's phases
(ramp, hold, release) shaded, the summary's peak force and contact opening marked; without
plates, the run's probe columns. plot_fields.png (meridian runs): p, σ_VM and ‖E_p‖ on the
deformed meridian at the output times (at most 6, or those nearest --times). A sweep directory
(summary.csv, cases/) gets plot_history.png with every case that ended ok.
"""
import argparse

from poroplast_tools import runplots


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="a run directory (history.csv) or a sweep directory (summary.csv, cases/)")
    ap.add_argument("--times", help="output times of the fields figure, comma-separated (s; the nearest written)")
    a = ap.parse_args()
    wanted = [float(t) for t in a.times.split(",")] if a.times else None
    written, note = runplots.plot(a.dir, wanted)
    for p in written:
        print(p)
    if note:
        print(f"note: {note}")


if __name__ == "__main__":
    main()
