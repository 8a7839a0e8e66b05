"""CSV tables the scripts write and read, and the Pareto front of (wall time, error) points."""
import csv
import math


def read_rows(path):
    """A CSV file with a header as a list of dicts (strings)."""
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def write_rows(path, rows, fields=None):
    """Rows (dicts) as a CSV file with a header: `fields` (default: the first row's keys; keys a row
    has beyond them are left out)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields or list(rows[0]), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def pareto(points):
    """The points (dicts with wall_s and error) no other point beats in both time and error,
    sorted by time."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p["wall_s"], p["error"])):
        if p["error"] < best:
            front.append(p)
            best = p["error"]
    return front
