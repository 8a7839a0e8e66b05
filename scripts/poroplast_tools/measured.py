"""A measured curve, as a lab writes it: a CSV file of times and values, read with an error that
names the problem (and its line) for every malformed file, never a traceback.

The format (lines starting with # are comments; blank lines are skipped):

    # aggregate 3, 30% compression, 2026-11-02
    time,force_uN,sigma_uN
    0.5,1.234,0.02
    1.0,1.618,0.02

* a header line first: the column names, separated by commas;
* `time`: seconds (also accepted: `time_s`, `t`);
* the value: for the model's force columns (`force_total_mg`, ...) a column `force_uN`,
  `force_nN` or `force_mg` (or the model's own name, or `value`, or one named by the caller);
  its unit is read from the suffix (`_mg`, `_uN` or `_µN`, `_nN`), or given (`unit`), and
  converted to the model's mg (milligram-force: 1 mg = 9.80665 µN);
* optionally `sigma` (or `sigma_<unit>`): each point's standard deviation, in the value's unit;
* times strictly increasing (no duplicates) and positive; every cell a finite number.
"""
import math

# mg (milligram-force, the model's force unit) per unit.
FORCE_UNITS = {"mg": 1.0, "uN": 1.0 / 9.80665, "µN": 1.0 / 9.80665, "nN": 1e-3 / 9.80665}
TIME_NAMES = ("time", "time_s", "t")


class DataError(Exception):
    """A malformed data file: the message names the file, the problem and where."""


def unit_of(name):
    """The force unit named by a column's suffix (`force_uN` -> uN), or None."""
    for u in FORCE_UNITS:
        if name.endswith("_" + u):
            return u
    return None


def read_curve(path, column, unit=None, data_column=None):
    """(times, values, sigmas or None) of the data for the model's history column `column` in
    the CSV file `path` (its column `data_column`, or found by name: `_value_column`), values
    (and sigmas) in mg when the column is a force with a unit (suffix or `unit`). Raises
    DataError."""
    def fail(msg, line=None):
        where = f"{path}" + (f", line {line}" if line is not None else "")
        raise DataError(f"{where}: {msg}")

    try:
        with open(path, encoding="utf-8") as f:
            lines = [(i + 1, ln.strip()) for i, ln in enumerate(f)]
    except FileNotFoundError:
        fail("no such file")
    except IsADirectoryError:
        fail("a directory, not a data file")
    except UnicodeDecodeError:
        fail("not a text file (expected CSV: a header line, then time,value rows)")
    lines = [(n, ln) for n, ln in lines if ln and not ln.startswith("#")]
    if not lines:
        fail("empty: expected a header line (e.g. `time,force_uN`) and rows of numbers")
    hline, header = lines[0]
    names = [h.strip() for h in header.split(",")]
    if all(_is_number(h) for h in names):
        fail("no header line: the first line holds numbers; expected column names "
             "(e.g. `time,force_uN`)", hline)
    if len(set(names)) != len(names):
        fail(f"a column name appears twice in the header {names}", hline)
    t_col = next((names.index(n) for n in TIME_NAMES if n in names), None)
    if t_col is None:
        fail(f"no time column: expected one named {' or '.join(TIME_NAMES)} (seconds); "
             f"the header has {names}", hline)
    if data_column:
        v_col = names.index(data_column) if data_column in names else None
    else:
        v_col = _value_column(names, column)
    if v_col is None:
        want = f"`{data_column}`" if data_column else (
            f"`{column}`, `force_uN`, `force_nN`, `force_mg` or `value`" if column.startswith("force_")
            else f"`{column}` or `value`")
        fail(f"no data column: expected {want}; the header has {names}", hline)
    u = unit or unit_of(names[v_col])
    if u is not None and u not in FORCE_UNITS:
        fail(f"unknown unit `{u}`: expected one of {', '.join(FORCE_UNITS)}")
    s_col = next((names.index(n) for n in ("sigma", f"sigma_{u}") if n in names), None)
    scale = FORCE_UNITS[u] if u else 1.0
    times, values, sigmas = [], [], []
    for n, ln in lines[1:]:
        cells = [c.strip() for c in ln.split(",")]
        if len(cells) != len(names):
            fail(f"{len(cells)} fields, the header has {len(names)}", n)
        row = []
        for k in [t_col, v_col] + ([s_col] if s_col is not None else []):
            try:
                x = float(cells[k])
            except ValueError:
                fail(f"`{cells[k]}` in column `{names[k]}` is not a number", n)
            if not math.isfinite(x):
                fail(f"`{cells[k]}` in column `{names[k]}`: every value must be a finite number", n)
            row.append(x)
        t = row[0]
        if t <= 0.0:
            fail(f"time {t:g} s: the data's times must be after the start of the run (t > 0)", n)
        if times and t <= times[-1]:
            what = "repeats" if t == times[-1] else "comes before"
            fail(f"time {t:g} s {what} the previous row's {times[-1]:g} s: times must increase", n)
        if s_col is not None and row[2] <= 0.0:
            fail(f"sigma {row[2]:g}: a standard deviation must be positive", n)
        times.append(t)
        values.append(row[1] * scale)
        if s_col is not None:
            sigmas.append(row[2] * scale)
    if not times:
        fail("a header but no rows of data")
    return times, values, (sigmas if s_col is not None else None)


def check_within(path, times, t_end):
    """DataError if a data time lies beyond the run's end `t_end` (s)."""
    late = [t for t in times if t > t_end * (1 + 1e-12)]
    if late:
        raise DataError(f"{path}: {len(late)} data times after the run's end (t_end = {t_end:g} s), "
                        f"the first {late[0]:g} s: lengthen time.t_end or leave them out (--t-max)")


def _value_column(names, column):
    """The data's column for the model's `column`: the same name, `<stem>_<unit>` (the stem
    without the model's `_mg`), `force_<unit>` for a force, or `value`."""
    stem = column[:-3] if column.endswith("_mg") else column
    wanted = [column] + [f"{stem}_{u}" for u in FORCE_UNITS]
    if column.startswith("force_"):
        wanted += [f"force_{u}" for u in FORCE_UNITS]
    for w in wanted + ["value"]:
        if w in names:
            return names.index(w)
    return None


def _is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def write_curve(path, times, values, sigmas=None, comment="", column="force_mg"):
    """A curve as a lab writes it, for `read_curve`: a comment line, then `time,COLUMN[,sigma]`."""
    with open(path, "w") as f:
        if comment:
            f.write(f"# {comment}\n")
        f.write(f"time,{column}" + (",sigma" if sigmas is not None else "") + "\n")
        for i, (t, v) in enumerate(zip(times, values)):
            f.write(f"{float(t)!r},{float(v)!r}" + (f",{float(sigmas[i])!r}" if sigmas is not None else "") + "\n")
