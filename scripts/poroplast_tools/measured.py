"""A measured curve, as a lab writes it: a table of times and values from Excel, an instrument's
software or a script, read right or refused with an error that names the problem, its line and
the fix, never a traceback. The accepted formats are tabulated in docs/reference-data-files.md.

    # aggregate 3, 30% compression, 2026-11-02        (lines starting with # are comments)
    time [min];force (µN);sigma_uN;phase
    0,5;1,234;0,02;ramp
    1,0;1,618;0,02;ramp

* the text: UTF-8 (with or without a byte-order mark), UTF-16 with one, else Windows-1252 (or
  Latin-1 where that does not decode); lines end in LF, CRLF or CR;
* the separator: comma, semicolon or tab, the one that splits the header and every row into
  the same cells (or the one a first line `sep=;` names, as Excel writes it); cells may be quoted (`"1.5"`); empty cells after the last column (Excel's
  trailing separators) and blank rows are ignored;
* the decimal mark: a point, or a comma in a semicolon- or tab-separated file; a comma in a
  comma-separated file's number, thousands separators (`1,234.5`, `1.234,5`, `1 234`) and
  a file that mixes the two marks are refused, since they cannot be read for certain;
* the header: the column names, each with its unit (units.py: `force [uN]`, `force (µN)`,
  `Force_uN`, `F/mN`, `time_min`, `t (h)`) or with the units on a line of their own below
  (`s;µN`); names are matched without regard to case; text above the header must be comments;
* the time: a column `time` or `t` in s, ms, min or h (s without a unit), converted to s;
* the value: the model's column (`column`) by name, a `force` or `F` column for a force, `value`,
  the one column `data_column` names, or else the only column of the model's quantity; in
  its unit (the name's, or `unit`), converted to the model's (mg for forces: 1 mg = 9.81 µN);
* optionally `sigma` (also `sd`, `std`, with a unit or in the value's): each point's standard
  deviation;
* times strictly increasing and after 0; every used cell a finite number; other columns (a
  `phase` of words, notes) are not read.
"""
import csv
import difflib
import math
import re

from . import units

SEPARATORS = {",": "comma", ";": "semicolon", "\t": "tab"}
TIME_NAMES = ("time", "t")
VALUE_NAMES = {"force": ("force", "f"), "length": ("length", "l")}
SIGMA_NAMES = ("sigma", "sd", "std", "stdev", "stddev")
NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")
THOUSANDS = re.compile(r"^[+-]?\d{1,3}([ \u00a0\u202f']\d{3})+([.,]\d+)?$|^[+-]?\d{1,3}([.,])\d{3}(\3\d{3})+$")


class DataError(Exception):
    """A malformed data file: the message names the file, the problem and where."""


class Curve(tuple):
    """(times in s, values and sigmas (None without) in the model's unit) of a data file, with
    `detected`: one line saying how it was read (encoding, line ends, separator, decimal mark,
    the columns used and their units), and `unit`, `scale`: the values' unit in the file (None
    if it has none) and the factor from it to the model's."""

    def __new__(cls, times, values, sigmas, detected, unit=None, scale=1.0):
        c = super().__new__(cls, (times, values, sigmas))
        c.detected = detected
        c.unit, c.scale = unit, scale      # the file's unit of the values; its factor to the model's
        return c


def closest(word, choices):
    """The choice nearest `word` (case aside), or None."""
    by_lower = {str(c).lower(): str(c) for c in choices}
    hit = difflib.get_close_matches(str(word).lower(), list(by_lower), n=1, cutoff=0.6)
    return by_lower[hit[0]] if hit else None


def nearest(word, choices):
    """` (did you mean `X`?)` for the choice nearest `word`, or ``."""
    hit = closest(word, choices)
    return f" (did you mean `{hit}`?)" if hit else ""


def read_curve(path, column, unit=None, data_column=None):
    """The Curve of the data for the model's history column `column` in the file `path`: its
    value column `data_column` (or found from `column`, see the module), in its unit (or
    `unit`), converted to the model's. Raises DataError."""
    def fail(msg, line=None):
        where = f"{path}" + (f", line {line}" if line is not None else "")
        raise DataError(f"{where}: {msg}")

    text, encoding = _decode(path, fail)
    lines, ends = _lines(text)
    rows = [(n, ln) for n, ln in lines if ln.strip() and not ln.strip().startswith("#")]
    if not rows:
        fail("empty: expected a header line (e.g. `time,force_uN`) and rows of numbers")
    hline, header = rows[0]
    said = re.match(r"^\s*\"?sep=(.)\"?\s*$", header)       # Excel's `sep=;` line names the separator
    if said:
        if said.group(1) not in SEPARATORS:
            fail(f"`{header.strip()}`: the separator must be a comma, a semicolon or a tab", hline)
        rows = rows[1:]
        if not rows:
            fail("empty: expected a header line (e.g. `time,force_uN`) and rows of numbers")
        hline, header = rows[0]
    _no_preamble(rows, fail)
    sep = said.group(1) if said else _separator(header, rows[1:], fail, hline)
    names = _cells(header, sep)
    while names and not names[-1]:
        names.pop()
    if all(_looks_numeric(h) for h in names if h):
        fail("no header line: the first line holds numbers; expected column names (e.g. `time,force_uN`)", hline)
    unit_line = _unit_row(rows[1] if len(rows) > 1 else None, names, sep)
    if unit_line:                                # a second header line of units (`s;µN`)
        names, rows = unit_line, rows[:1] + rows[2:]
    low = [h.lower() for h in names]
    dup = next((h for h in names if h and low.count(h.lower()) > 1), None)
    if dup:
        fail(f"the column name `{dup}` appears twice in the header {names}", hline)
    t_col, t_unit = _time_column(names, fail, hline)
    v_col, v_unit, v_scale, how = _value_column(names, column, unit, data_column, t_col, fail, hline)
    s_col, s_scale, s_how = _sigma_column(names, v_col, t_col, column, v_scale, fail, hline)
    data = []
    for n, ln in rows[1:]:
        cells = _cells(ln, sep)
        while len(cells) > len(names) and not cells[-1]:
            cells.pop()
        if not any(cells):
            continue                              # a row of empty cells (Excel's blank row)
        if len(cells) != len(names):
            fail(f"{len(cells)} fields, the header has {len(names)}"
                 + (": a decimal comma? In a comma-separated file the comma cannot also be the decimal mark: "
                    "save the file with `;` as the separator, or with decimal points" if sep == "," and
                    len(cells) > len(names) else ""), n)
        data.append((n, cells))
    if not data:
        fail("a header but no rows of data")

    used = [t_col, v_col] + ([s_col] if s_col is not None else [])
    comma = _decimal_comma(data, used, names, sep, fail)
    times, values, sigmas = [], [], []
    t_scale = units.factor(t_unit)
    for n, cells in data:
        row = [_number(cells[k], names[k], comma, fail, n) for k in used]
        t = row[0] * t_scale
        if t <= 0.0:
            fail(f"time {row[0]:g} {t_unit}: the data's times must be after the start of the run (t > 0, the "
                 "plates' start): leave out the rows at t <= 0, or shift the times", n)
        if times and t <= times[-1]:
            what = "repeats" if t == times[-1] else "comes before"
            fail(f"time {row[0]:g} {t_unit} {what} the previous row's {times[-1] / t_scale:g} {t_unit}: "
                 "times must increase", n)
        if s_col is not None and row[2] <= 0.0:
            fail(f"sigma {row[2]:g}: a standard deviation must be positive", n)
        times.append(t)
        values.append(row[1] * v_scale)
        if s_col is not None:
            sigmas.append(row[2] * s_scale)

    ignored = [h for k, h in enumerate(names) if k not in used and h]
    detected = (f"{path}: {encoding}, {ends} line ends, separator {SEPARATORS.get(sep, 'none (one column)')}, "
                + ("units from the line below the header, " if unit_line else "") + 
                f"decimal {'comma' if comma else 'point'}; {len(times)} row{'s' if len(times) > 1 else ''}; time `{names[t_col]}` in {t_unit}"
                + (f" (x {t_scale:g} to s)" if t_scale != 1 else "")
                + f"; value `{names[v_col]}` {how}"
                + (f"; sigma `{names[s_col]}` {s_how}"
                   if s_col is not None else "; no sigma column")
                + (f"; not read: {', '.join(f'`{h}`' for h in ignored)}" if ignored else ""))
    return Curve(times, values, sigmas if s_col is not None else None, detected, v_unit, v_scale)


def _decode(path, fail):
    """(text, what the encoding was) of the file: UTF-8 (a BOM said), UTF-16 with a BOM, else
    Windows-1252, else Latin-1; text with control characters is not a text file."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except FileNotFoundError:
        fail("no such file")
    except IsADirectoryError:
        fail("a directory, not a data file")
    except OSError as e:
        fail(f"cannot be read: {e.strerror}")
    if raw.startswith((b"PK\x03\x04", b"\xd0\xcf\x11\xe0")):
        fail("an Excel workbook (or another zip or OLE file), not a text table: save the sheet as CSV (Excel: "
             "File > Save As > CSV UTF-8) and give that file")
    if raw.startswith(b"\xef\xbb\xbf"):
        candidates = [("utf-8-sig", "UTF-8 with a byte-order mark")]
    elif raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        candidates = [("utf-16", "UTF-16 (with a byte-order mark)")]
    else:
        candidates = [("utf-8", "UTF-8"), ("cp1252", "Windows-1252 (not UTF-8)"),
                      ("latin-1", "Latin-1 (neither UTF-8 nor Windows-1252)")]
    for codec, what in candidates:
        try:
            text = raw.decode(codec)
        except UnicodeDecodeError:
            continue
        if any(ord(c) < 32 and c not in "\t\r\n" for c in text):
            break                                  # NUL and the like: binary
        return text, what
    fail("not a text file (expected a table: a header line, then rows of a time and a value, "
         "separated by commas, semicolons or tabs)")


def _lines(text):
    """[(line number, line)] and the line ends found (LF, CRLF, CR or mixed)."""
    ends = {e for e in re.findall(r"\r\n|\r|\n", text)}
    name = {"\n": "LF", "\r\n": "CRLF", "\r": "CR"}
    what = name[ends.pop()] if len(ends) == 1 else ("mixed" if ends else "no")
    return [(i + 1, ln) for i, ln in enumerate(re.split(r"\r\n|\r|\n", text))], what


def _cells(line, sep):
    """The cells of a line, stripped, quotes removed; the minus sign U+2212 (copied from a
    document) read as `-`."""
    if sep is None:
        cells = [line]
    else:
        try:
            cells = next(csv.reader([line], delimiter=sep, quotechar='"', skipinitialspace=True))
        except csv.Error:
            cells = line.split(sep)
    out = []
    for c in cells:
        c = c.strip()
        if len(c) >= 2 and c[0] == c[-1] == '"':
            c = c[1:-1].strip()
        out.append(c.replace("\u2212", "-"))
    return out


def _separator(header, rows, fail, hline):
    """The separator that splits the header and the rows alike: of those that split the header
    into two or more names and every row into as many cells (trailing empty ones aside), the
    one under which the most cells are numbers; None for a one-column header."""
    fits = []
    for sep in SEPARATORS:
        names = _cells(header, sep)
        while names and not names[-1]:
            names.pop()
        if len(names) < 2:
            continue
        counts, numeric = set(), 0
        for _, ln in rows:
            cells = _cells(ln, sep)
            while len(cells) > len(names) and not cells[-1]:
                cells.pop()
            if any(cells):
                counts.add(len(cells))
                numeric += sum(_looks_numeric(c) for c in cells)
        fits.append((counts <= {len(names)}, numeric, sep))
    if not fits:
        sample = next((ln for _, ln in rows if ln.strip()), "")
        if len(sample.split()) > 1:
            fail(f"one column `{header.strip()}`: the columns seem separated by spaces; separate them by commas, "
                 "semicolons or tabs (e.g. save from Excel as CSV)", hline)
        if "," in sample:
            fail(f"the header `{header.strip()}` names one column and the rows hold commas (`{sample.strip()}`): "
                 "the comma could be a separator or a decimal mark; write a header with a name per column, and "
                 "decimal points (or `;` as the separator)", hline)
        return None
    best = max(fits)
    if sum(1 for f in fits if f[:2] == best[:2]) > 1:
        both = " and ".join(SEPARATORS[s] for c, k, s in fits if (c, k) == best[:2])
        fail(f"the separator is ambiguous: the header and rows split alike on {both}; use one of them only", hline)
    return best[2]


def _has_time(line):
    return any(units.split(c)[0].lower() in TIME_NAMES for sep in SEPARATORS for c in _cells(line, sep))


def _no_preamble(rows, fail):
    """Refuses lines of text above the header (a title, an instrument's settings) that are not
    comments: the first line names no time column and a later one does."""
    if _has_time(rows[0][1]):
        return
    later = next(((n, ln) for n, ln in rows[1:30] if _has_time(ln)), None)
    if later:
        fail(f"`{rows[0][1].strip()}` is not a header of columns, but line {later[0]} (`{later[1].strip()}`) looks like "
             "one: make the lines above it comments (start them with #)", rows[0][0])


def _unit_row(row, names, sep):
    """The names with the units of a units line below the header (`time;force` then `s;µN`:
    `time [s]`, `force [µN]`), or None if `row` is not one: every cell empty, `-` or a unit, one
    at least a unit."""
    if row is None:
        return None
    cells = _cells(row[1], sep)
    bare = [c.strip("[](){} ") for c in cells]
    if len(cells) > len(names) or not any(units.unit(c) for c in bare) or not all(
            not c or c == "-" or units.unit(c) for c in bare):
        return None
    return [f"{h} [{c}]" if c and c != "-" and units.split(h)[1] is None else h
            for h, c in zip(names, bare + [""] * (len(names) - len(bare)))]


def _time_column(names, fail, hline):
    hits = [(k, units.split(h)) for k, h in enumerate(names) if units.split(h)[0].lower() in TIME_NAMES]
    if not hits:
        fail(f"no time column: expected one named time or t (in s, or with its unit: `time [min]`, `time_s`, "
             f"`t (h)`); the header has {names}{nearest('time', names)}", hline)
    if len(hits) > 1:
        fail(f"two time columns, {' and '.join(f'`{names[k]}`' for k, _ in hits)}: keep one", hline)
    [(k, (_, u, given))] = hits
    if u is None and given is not None:
        fail(f"the time column `{names[k]}`: unknown unit `{given}`: expected s, ms, min or h", hline)
    if u is not None and units.quantity(u) != "time":
        fail(f"the time column `{names[k]}` is in {units.shown(u)}, not a time: expected s, ms, min or h", hline)
    return k, u or "s"


def _value_column(names, column, unit, data_column, t_col, fail, hline):
    """(index, unit (None: none), the factor to the model's unit, how it was chosen and
    converted) of the value column."""
    model_unit = units.of_column(column)
    model_q = units.quantity(model_unit) if model_unit else None
    parsed = [units.split(h) for h in names]
    low = [h.lower() for h in names]
    others = [k for k in range(len(names)) if k != t_col and names[k]
              and parsed[k][0].lower() not in SIGMA_NAMES]
    stem = units.split(column)[0].lower()
    if data_column:
        if data_column.lower() not in low:
            fail(f"no column `{data_column}` (--data-column): the header has {names}"
                 f"{nearest(data_column, names)}", hline)
        k, why = low.index(data_column.lower()), "named by --data-column"
    else:
        def first(test):
            return next((k for k in others if test(k)), None)
        k, why = first(lambda k: low[k] == column.lower()), "the model's column"
        if k is None:
            k, why = first(lambda k: parsed[k][0].lower() == stem), "the model's column"
        if k is None and model_q in VALUE_NAMES:
            k, why = first(lambda k: parsed[k][0].lower() in VALUE_NAMES[model_q]), f"a {model_q}"
        if k is None:
            k, why = first(lambda k: parsed[k][0].lower() == "value"), "named value"
        if k is None and model_q:
            same = [j for j in others if parsed[j][1] and units.quantity(parsed[j][1]) == model_q]
            if len(same) > 1:
                fail(f"{len(same)} {model_q} columns ({', '.join(f'`{names[j]}`' for j in same)}): name the one to "
                     "fit (--data-column, or data_column in an experiments file)", hline)
            k, why = (same[0], f"the only {model_q} column") if same else (None, "")
        if k is None:
            want = f"`{column}`" + (f", a {model_q} with its unit (e.g. `{'force' if model_q == 'force' else model_q}"
                                    f" [{units.shown(model_unit)}]`)" if model_q else "") + " or `value`"
            known = [c for cs in units.MODEL_COLUMNS.values() for c in cs]
            model = closest(column, known) if model_unit is None and column not in known else None
            fail(f"no data column: expected {want}, or one named by --data-column; the header has {names}"
                 f"{nearest(column, [names[j] for j in others])}"
                 + (f"; and `{column}` is no column of the model's history: did you mean `{model}`?" if model else ""),
                 hline)
    _, u, given = parsed[k]
    if low[k] == column.lower():
        u, given = model_unit, None          # the model's own name: its unit
    if u is None and given is not None and low[k] != column.lower():
        fail(f"the column `{names[k]}`: unknown unit `{given}`" + (
            f": expected one of {', '.join(map(units.shown, units.UNITS[model_q]))}" if model_q else ""), hline)
    if unit:
        u_given = units.unit(unit)
        if u_given is None or (model_q and units.quantity(u_given) != model_q):
            fail(f"unknown unit `{unit}` (--data-unit)" + (
                f": expected one of {', '.join(map(units.shown, units.UNITS[model_q]))}" if model_q else ""))
        if u is not None and u != u_given:
            fail(f"the column `{names[k]}` is in {units.shown(u)}, but the unit given (--data-unit) is "
                 f"{units.shown(u_given)}: leave out --data-unit, or rename the column", hline)
        u = u_given
    if u is not None:
        q = units.quantity(u)
        if model_unit is None:
            fail(f"the column `{names[k]}` is in {units.shown(u)}, but the model's `{column}` has no unit this "
                 "reader converts to: give the values in the model's unit, without a unit in the name", hline)
        if q != model_q:
            fail(f"the column `{names[k]}` is a {q} ({units.shown(u)}), but the model's `{column}` is a {model_q} "
                 f"({units.shown(model_unit)})", hline)
        f = units.factor(u) / units.factor(model_unit)
        to = (f"1 {units.shown(model_unit)} = {1 / f:.6g} {units.shown(u)}" if q == "force" else
              f"x {f:.6g} to {units.shown(model_unit)}")
        return k, u, f, f"({why}) in {units.shown(u)}" + (f" ({to})" if f != 1 else "")
    if model_q and low[k] not in (column.lower(), "value"):
        fail(f"the column `{names[k]}` has no unit: name it with one (e.g. `{names[k]} [{units.shown(model_unit)}]`"
             f" or `{names[k]}_{model_unit}`) or give it (--data-unit, or unit in an experiments file)", hline)
    return k, model_unit, 1.0, f"({why}) in the model's unit" + (f" {units.shown(model_unit)}" if model_unit else "")


def _sigma_column(names, v_col, t_col, column, v_scale, fail, hline):
    """(index, the factor to the model's unit, its unit as said) of the sigma column, or Nones."""
    hits = [k for k, h in enumerate(names) if k not in (v_col, t_col) and units.split(h)[0].lower() in SIGMA_NAMES]
    if not hits:
        return None, None, None
    if len(hits) > 1:
        fail(f"two sigma columns, {' and '.join(f'`{names[k]}`' for k in hits)}: keep one", hline)
    k = hits[0]
    _, u, given = units.split(names[k])
    if u is None and given is not None:
        fail(f"the sigma column `{names[k]}`: unknown unit `{given}`", hline)
    if u is None:
        return k, v_scale, "in the value's unit"
    model_unit = units.of_column(column)
    if model_unit is None or units.quantity(u) != units.quantity(model_unit):
        fail(f"the sigma column `{names[k]}` is in {units.shown(u)}, but the model's `{column}` is in "
             f"{units.shown(model_unit) if model_unit else 'no unit'}", hline)
    return k, units.factor(u) / units.factor(model_unit), f"in {units.shown(u)}"


def _looks_numeric(cell):
    return bool(NUMBER.match(cell.replace(",", ".", 1))) if cell.count(",") <= 1 else False


def _decimal_comma(data, used, names, sep, fail):
    """Whether the used cells write decimals with a comma; refuses a mark that cannot be read
    for certain (see the module)."""
    point = comma = None
    for n, cells in data:
        for k in used:
            c = cells[k]
            if THOUSANDS.match(c) or ("," in c and "." in c and _looks_numeric(c.replace(",", "").replace(".", "", 1))):
                fail(f"`{c}` in column `{names[k]}`: a thousands separator? Numbers must be written without one "
                     "(e.g. 1234.5)", n)
            if "," in c and NUMBER.match(c.replace(",", ".")):
                if sep == ",":
                    fail(f"`{c}` in column `{names[k]}`: a comma inside a number in a comma-separated file could be "
                         "a decimal mark or a thousands separator: save the file with decimal points, or with `;` "
                         "as the separator", n)
                comma = comma or (n, c)
            elif "." in c and NUMBER.match(c):
                point = point or (n, c)
    if point and comma:
        fail(f"both decimal marks: `{comma[1]}` (line {comma[0]}) and `{point[1]}` (line {point[0]}): write every "
             "number with the same one")
    return comma is not None


def _number(cell, name, comma, fail, n):
    if not cell:
        fail(f"the cell of column `{name}` is empty: every row needs a time and a value (fill the cell or delete "
             "the row)", n)
    text = cell.replace(",", ".") if comma else cell
    if NUMBER.match(text):
        return float(text)
    if text.lower().lstrip("+-") in ("nan", "inf", "infinity"):
        fail(f"`{cell}` in column `{name}`: every value must be a finite number", n)
    if re.match(r"^\d+:\d\d(:\d\d([.,]\d+)?)?$", cell):
        fail(f"`{cell}` in column `{name}`: a clock time (h:mm:ss)? Give times as numbers with their unit in the "
             "header (e.g. `time [s]`: in Excel, format the column as a number of seconds)", n)
    fail(f"`{cell}` in column `{name}` is not a number", n)


def check_within(path, times, t_end):
    """DataError if a data time lies beyond the run's end `t_end` (s)."""
    late = [t for t in times if t > t_end * (1 + 1e-12)]
    if late:
        raise DataError(f"{path}: {len(late)} data times after the run's end (t_end = {t_end:g} s), "
                        f"the first {late[0]:g} s: lengthen time.t_end or leave them out (--t-max)")


def write_curve(path, times, values, sigmas=None, comment="", column="force_mg"):
    """A curve as a lab writes it, for `read_curve`: a comment line, then `time,COLUMN[,sigma]`."""
    with open(path, "w") as f:
        if comment:
            f.write(f"# {comment}\n")
        f.write(f"time,{column}" + (",sigma" if sigmas is not None else "") + "\n")
        for i, (t, v) in enumerate(zip(times, values)):
            f.write(f"{float(t)!r},{float(v)!r}" + (f",{float(sigmas[i])!r}" if sigmas is not None else "") + "\n")
