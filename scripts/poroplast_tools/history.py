"""Reading a run directory: history.csv as columns, timings.txt as numbers, a column at a time.

The observables of a history (`max:COL`, `COL@T`, `zero:COL`, ...) are not evaluated here but
by `poroplast sweep` (the one grammar); `at` is the plain interpolation that figures and fits need.
"""
import csv
from pathlib import Path

import numpy as np


def _file(path, name):
    path = Path(path)
    return path / name if path.is_dir() else path


def history(path):
    """history.csv (of a run directory, or the file) as {column: array}; rows that do not parse
    (a run still writing) are dropped; {} without rows."""
    return read(path)[0]


def read(path):
    """history.csv as ({column: array}, [what was dropped, in words]). Dropped: rows of the wrong
    length or not numbers, and a last line without its newline (cut while written: its last
    number may be cut short too). ({}, [why]) for an empty file or one with only its header."""
    raw = Path(_file(path, "history.csv")).read_bytes().decode("utf-8", errors="replace")
    lines = raw.split("\n")
    cut = lines.pop() if lines else ""   # "" when the file ends with its newline
    problems = [f"history.csv: its last line is cut ({cut[:40]!r}...): dropped"] if cut.strip() else []
    lines = [l.rstrip("\r") for l in lines if l.strip()]
    if not lines:
        return {}, problems + ["history.csv is empty"]
    head = next(csv.reader([lines[0]]))
    rows, bad = [], []
    for n, row in enumerate(csv.reader(lines[1:]), start=2):
        try:
            if len(row) != len(head):
                raise ValueError
            rows.append([float(x) for x in row])
        except ValueError:
            bad.append(n)
    if bad:
        problems.append(f"history.csv: {len(bad)} line(s) not {len(head)} numbers, dropped (line {bad[0]}"
                        + (", ..." if len(bad) > 1 else "") + ")")
    if not rows:
        return {}, problems + ["history.csv has no rows"]
    a = np.array(rows)
    return {k: a[:, i] for i, k in enumerate(head)}, problems


def given_steps(h):
    """The `time.steps` value that makes a run take the accepted steps of history `h` (every
    time after the first row, exactly as written)."""
    return "[" + ",".join(repr(float(t)) for t in h["time"][1:]) + "]"


def timings(path):
    """timings.txt (of a run directory, or the file) as {key: number}; {} without the file."""
    out = {}
    path = _file(path, "timings.txt")
    if not path.exists():
        return out
    for line in open(path):
        if " = " in line:
            k, v = line.split(" = ", 1)
            try:
                out[k.strip()] = float(v)
            except ValueError:
                pass
    return out


def at(h, col, when):
    """Column `col` of a history interpolated linearly at time `when` (NaN outside the run or
    without the column)."""
    if col not in h or len(h.get("time", ())) == 0:
        return float("nan")
    t, v = h["time"], h[col]
    if not t[0] <= when <= t[-1]:
        return float("nan")
    i = max(1, int(np.searchsorted(t, when, side="left")))
    w = (when - t[i - 1]) / (t[i] - t[i - 1]) if t[i] > t[i - 1] else 1.0
    return float(v[i - 1] + w * (v[i] - v[i - 1]))


def relaxation_time(t, f, plateau, t_max, fraction=0.95):
    """The time after its peak at which the force f(t) has covered `fraction` of the way from the
    peak down to `plateau` (interpolated between output times), or None if not by t_max: one
    number for "relaxes in 400-1000 s" that does not assume one exponential."""
    k = int(np.argmax(f))
    target = f[k] - fraction * (f[k] - plateau)
    after = np.nonzero((t > t[k]) & (t <= t_max) & (f <= target))[0]
    if not len(after):
        return None
    j = after[0]
    return float(t[j - 1] + (t[j] - t[j - 1]) * (f[j - 1] - target) / (f[j - 1] - f[j]))
