#!/usr/bin/env python3
"""Draws a run directory, or a sweep directory with its cases overlaid, into PNGs beside it.
No ParaView and no display needed (matplotlib, h5py, numpy).

    python3 scripts/plot_run.py RUN_DIR [--times 5,35] [--fields p,von_mises,porosity] [--mid-plane]
    python3 scripts/plot_run.py SWEEP_DIR

plot_history.png: the force on the upper plate in µN (mg on the right axis; 1 mg = 9.81 µN),
p at the probe point and H/W against time, with a surface tension the apparent tension σ_app;
the plate protocol's ramps, holds and releases shaded (phases or a table), each hold's end
dashed, the summary's peak force and contact opening marked; without plates, the run's probe
columns. The title says when the run is in progress, stopped or failed.

plot_fields.png: p, σ_VM, porosity and ‖E_p‖ (those written; --fields to choose) at the output
times (at most 6, or those nearest --times; a panel says when its time differs from the one
asked): a meridian run on its deformed meridian, a 3-D run on the section through the axis
(y = 0) of the deformed body; --mid-plane adds plot_fields_mid.png, the section at mid-height.

A sweep directory (summary.csv, cases/) gets plot_history.png with every case that ended ok (and
those running, so far). What could not be drawn is printed as `note: ...` lines; the exit code
is 0 when a figure was drawn, 1 when none could be.
"""
import argparse
import re
import sys

from poroplast_tools import fieldplots, runplots

# Time units --times accepts, in s.
UNITS = {"": 1.0, "s": 1.0, "min": 60.0, "h": 3600.0, "ms": 1e-3}
TIME = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-z]*)$")


def times(text):
    """`5,35`, `5s, 35 s`, `1min 90s`: times in s (argparse's type: ValueError says what is wrong)."""
    out = []
    for item in (x for x in re.split(r"[,;\s]+(?![a-z])", text.strip()) if x):
        m = TIME.match(item)
        if not m or m.group(2) not in UNITS:
            raise argparse.ArgumentTypeError(
                f"{item!r} is not a time: give numbers in s, e.g. 5,35 or 5s,35s or 1min (units: s, min, h, ms)")
        t = float(m.group(1)) * UNITS[m.group(2)]
        if not t >= 0:
            raise argparse.ArgumentTypeError(f"{item!r}: a time is at least 0 s")
        out.append(t)
    if not out:
        raise argparse.ArgumentTypeError("no time given: e.g. --times 5,35")
    return out


def names(text):
    out = [x for x in re.split(r"[,\s]+", text.strip()) if x]
    bad = [x for x in out if not re.fullmatch(r"[A-Za-z0-9_.-]+", x)]
    if bad or not out:
        raise argparse.ArgumentTypeError(
            f"{', '.join(map(repr, bad)) or 'nothing'}: give field names, e.g. p,von_mises,porosity "
            f"(fields.h5's: {', '.join(fieldplots.LABELS)})")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="a run directory (history.csv) or a sweep directory (summary.csv, cases/)")
    ap.add_argument("--times", type=times, metavar="T1,T2,...",
                    help="times of the field pictures, comma-separated, in s unless a unit is given "
                         "(5,35 or 5s,35s or 1min); the nearest written output is drawn")
    ap.add_argument("--fields", type=names, metavar="F1,F2,...",
                    help="fields to draw (default: " + ",".join(fieldplots.DEFAULT) + ", those written)")
    ap.add_argument("--mid-plane", action="store_true",
                    help="a 3-D run: also the section at mid-height (plot_fields_mid.png)")
    a = ap.parse_args()
    try:
        written, notes = runplots.plot(a.dir, a.times, a.fields, a.mid_plane)
    except runplots.Nothing as e:
        sys.exit(f"plot_run.py: {a.dir}: nothing drawn: {e}")
    except OSError as e:
        sys.exit(f"plot_run.py: {a.dir}: {e.strerror or e}: {e.filename or ''}")
    except Exception as e:  # a file in a shape not foreseen: one line, not a traceback
        sys.exit(f"plot_run.py: {a.dir}: nothing drawn: {type(e).__name__}: {e} (please report this)")
    for p, what in written:
        print(f"{p}: {what}")
    for n in dict.fromkeys(notes):
        print(f"note: {n}")


if __name__ == "__main__":
    main()
