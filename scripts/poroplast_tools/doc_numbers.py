"""The numbers of the docs' prose, each tied to where it comes from.

A number is either **bound** or **listed**:

* bound: an invisible comment right after it names its source and rounding rule,

      crosses zero at 42.33<!-- = remodel_155|zero:probe_p ; .2f --> s

  The source is an expression of `claims.measure` (the claims table's `measure` column):
  `CASE|OBSERVABLE` (a converged value of references.csv), `SOURCE:ROW|COLUMN` (a cell of one of
  `claims.SOURCES`), or two of them joined by " - " or " / "; `value` names the other forms
  (aggregates, references.csv's levels and orders, a plain number as one operand). In a table row
  each "|" is written "\\|", or GitHub splits the cell there. The rule is a Python format spec
  (`.2f`, `+.3g`, `.1%`), after any of: `bar` (the error bar, not the value), `abs` (the
  magnitude: a shift said without its sign), `rel` (minus 1: a ratio as a relative difference,
  "−0.54%" of `17.4912 / reference|max:force_total_mg`), `*F` (times F). `write` renders every bound number
  from its source; `stale` names those that differ.
* listed: scripts/data/doc_numbers.toml gives, per line of a page, the numbers it prints that no
  CSV holds (the paper's, Table 1's, inputs, counts, measurements kept nowhere else) with their
  source. `unlisted` names what is neither bound nor listed, and `unmatched` the list's entries
  that no longer match a line.

Not numbers here (not a quantity): code blocks, inline code, HTML comments, link targets, image
lines, the generated tables (checked as a whole against their generator; the words of ours they
quote from claims.csv are a page of their own, CLAIMS), claims.csv's placeholders, section,
figure, table, equation, citation, claim, decision and commit numbers, dates and times,
versions, and "3-D"/"2-D"."""

import math
import re
import tomllib
from decimal import Decimal
from functools import lru_cache
from pathlib import Path

from . import claims
from .refs import SHIPPED as REFERENCES, references
from .tables import write_rows

ROOT = Path(__file__).resolve().parents[2]
LIST = ROOT / "scripts" / "data" / "doc_numbers.toml"
# The pages whose every number is bound or listed; claims.csv is read as a page of its own: the
# claims table's words that are ours (its `ours` and `cause` columns; the others are the paper's).
CLAIMS = "scripts/data/claims.csv"
PAGES = ["docs/reproduction.md", "docs/studies.md", "docs/performance.md", "docs/numerics.md", "README.md", "scripts/README.md", CLAIMS]
_CELLS = " ¦ "


def read_page(name):
    """A page's text; claims.csv's as one line per row: `ID: ours ¦ cause`."""
    path = ROOT / name
    if name != CLAIMS:
        return path.read_text(encoding="utf-8")
    return "\n".join(f"{r['id']}: {r['ours']}{_CELLS}{r['cause']}" for r in claims.load(path))


def write_page(name, text):
    """Write a page's text back (claims.csv: its rows' `ours` and `cause` cells)."""
    path = ROOT / name
    if name != CLAIMS:
        path.write_text(text, encoding="utf-8")
        return
    rows = claims.load(path)
    for r, line in zip(rows, text.split("\n"), strict=True):
        r["ours"], r["cause"] = line.split(": ", 1)[1].split(_CELLS)
    write_rows(path, rows)

MINUS = "−"
_NUM = r"[+−-]?\d+(?:\.\d+)?(?:e[+−-]?\d+)?%?"
# A bound number: NUMBER<!-- = EXPR ; RULE --> (found from its comment backwards: a regex that
# starts at the number is slow on a page of hundreds).
_BINDING = re.compile(r"<!-- = (?P<expr>[^;>]+?) ; (?P<rule>[^>]+?) -->")
_NUM_END = re.compile(rf"{_NUM}\Z")


class _Site(dict):
    """A bound number: num, expr, rule, and the spans of the number and of the whole binding."""
    def start(self, group=None):
        return self["_a"]

    def end(self, group=None):
        return self["_n"] if group == "num" else self["_b"]

    def group(self, _=0):
        return self["_text"][self["_a"]:self["_b"]]


def _sites(text):
    """The bound numbers of `text`, in order."""
    for c in _BINDING.finditer(text):
        n = _NUM_END.search(text, max(0, c.start() - 40), c.start())
        if n:
            yield _Site(num=n.group(0), expr=c["expr"], rule=c["rule"], _a=n.start(), _n=n.end(), _b=c.end(), _text=text)
# A number of the prose: thousands grouped by spaces ("6 276"), a fraction ("1/16"), a power of
# ten ("10⁴", "10⁻⁶"), a decimal with an exponent ("3.7729e-3"), a percentage.
TOKEN = re.compile(r"(?<![\w.^])(?:\d{1,3}(?: \d{3})+(?![\d.])|\d+/\d+(?![\d.])|10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+|"
                   r"\d+(?:\.\d+)?(?:e[+−-]?\d+)?%?)(?![\w.]\w|[\w]|-D)")
# What is not a quantity (see the module's docstring); each match is blanked before TOKEN runs.
_ID = r"\d+[a-z]?(?:\.\d+)*"
NOT_QUANTITIES = [
    r"^```.*?^```",                                   # code blocks
    r"<!--.*?-->",                                    # comments (and the bindings' own text)
    r"`[^`\n]*`",                                     # inline code
    r"\]\([^)\s]*\)",                                 # link targets
    r"^!\[[^\n]*",                                       # image lines
    rf"(?:§§?|\bFigs?\.?|\bFigures?|\bTables?|\bdecisions?|\bcommits?|\bissues?|\bsections?|\bPR)"
    rf"\s*{_ID}(?:(?:\s*[–-]\s*|,\s*|\s+and\s+){_ID})*",   # section, figure, table, ... numbers
    r"\((?:\d+[a-z]?)\)(?:/\(\d+[a-z]?\))*",             # equation numbers: (40a), (54c)/(40b)
    r"\[\d+\]",                                       # citations
    r"\{[^{}\n]*\|[^{}\n]*\}",                           # claims.csv's placeholders (claims.py renders them)
    r"\d{4}-\d{2}-\d{2}(?:/\d{2})?|\b\d{1,2}:\d{2}\b",  # dates and times
    r"\b(?:PETSc|Rust|FEBio|Debian|Python|ParaView|ZAMP|Open MPI)\s+\d+(?:\.\d+)*",  # versions
    r"\(\d{4}\)",                                     # years of a citation
    r"\bP\d+[a-z]?(?:\s*[–-]\s*P\d+[a-z]?)?",          # claim ids
]
_BLANK = re.compile("|".join(f"(?:{p})" for p in NOT_QUANTITIES), re.S | re.M)


# ---------------------------------------------------------------------------------------------
# Bound numbers


@lru_cache(maxsize=None)
def _refs():
    return references()


# A column of references.csv besides the value and its bar: `p_h CASE|OBS`, `p_t ...`,
# `relative_bar ...`, or `level N CASE|OBS`, the N-th of its `levels` (the mesh levels, then the
# step levels, counted from 0).
REFERENCE_FIELD = re.compile(r"(p_h|p_t|relative_bar|level (\d+)) (\S+\|.+)")
AGGREGATE = re.compile(r"(min|max|count) (\w+)(?:\|([^ ]+))?(?: where (\w+) (at least|at most) ([+-]?\d+(?:\.\d+)?))?")


def _own(expr):
    """Whether an operand is one of this module's forms (a reference column, an aggregate, a
    number: the paper's, say) rather than claims.measure's."""
    return bool(REFERENCE_FIELD.fullmatch(expr) or AGGREGATE.fullmatch(expr)
                or re.fullmatch(r"[+-]?\d+(?:\.\d+)?", expr))


@lru_cache(maxsize=None)
def _reference_rows():
    return {f"{r['case']}|{r['observable']}": r for r in claims._rows(REFERENCES)}


@lru_cache(maxsize=None)
def value(expr):
    """(value, error bar) of a binding's source expression: claims.measure's; or `min SOURCE|COLUMN`,
    `max SOURCE|COLUMN`, `count SOURCE` over the rows of one of claims.SOURCES, or over those of
    its rows with `where COLUMN at least X` (or `at most X`); or a column of
    references.csv (REFERENCE_FIELD); or a difference or ratio of two operands one of which is
    such a form or a plain number ("remodel_155|zero:probe_p - 40": the gap to the paper's 40 s).
    Only claims.measure's forms have an error bar."""
    for op in (" - ", " / "):
        parts = expr.split(op)
        if len(parts) == 2 and any(_own(x.strip()) for x in parts):
            (a, _), (b, _) = (value(x.strip()) for x in parts)
            return (a - b if op == " - " else a / b), math.nan
    if re.fullmatch(r"[+-]?\d+(?:\.\d+)?", expr):
        return float(expr), math.nan
    m = REFERENCE_FIELD.fullmatch(expr)
    if m:
        field, level, key = m.groups()
        row = _reference_rows().get(key)
        if row is None:
            raise KeyError(f"no converged value {key} in references.csv")
        if level is not None:
            levels = row["levels"].replace("|", " ").split()
            return float(levels[int(level)]), math.nan
        return float(row[field]), math.nan
    m = AGGREGATE.fullmatch(expr)
    if not m:
        return claims.measure(_refs(), expr)
    how, source, column, where, cmp, bound = m.groups()
    if source not in claims.SOURCES:
        raise KeyError(f"no source {source!r}")
    rows = claims._rows(claims.SOURCES[source][0])
    if where:   # the rows whose column `where` is at least or at most the bound ("nan": neither)
        keep = (lambda x: x >= float(bound)) if cmp == "at least" else (lambda x: x <= float(bound))
        rows = [r for r in rows if r.get(where, "") not in ("", "nan") and keep(float(r[where]))]
    if how == "count":
        return float(len(rows)), math.nan
    # a row without the value (a run that did not reach it: "nan") has no say in the extreme
    xs = [x for x in (float(r[column]) for r in rows) if not math.isnan(x)]
    return (min(xs) if how == "min" else max(xs)), math.nan


@lru_cache(maxsize=None)
def render(expr, rule):
    """A bound number as its rule prints its source (U+2212 for a minus sign)."""
    *mods, spec = rule.split()
    x, bar = value(expr.strip())
    for m in mods:
        if m == "bar":
            x = bar
        elif m == "abs":
            x = abs(x)
        elif m == "rel":
            x -= 1   # a ratio as a relative difference: "17.4912 / reference|max:force_total_mg"
        elif m.startswith("*"):
            x *= float(m[1:])
        else:
            raise ValueError(f"unknown rule {m!r} in {rule!r} (bar, abs, rel, *F, then a format spec)")
    if not math.isfinite(x):
        raise ValueError(f"{expr}: no value ({x})")
    s = format(x, spec)
    s = re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("" if m.group(1) == "+" else "-") + m.group(2), s)
    return MINUS + s[1:] if s.startswith("-") else s   # an exponent keeps its "-" ("3.7729e-3")


def _expr(m):
    """A binding's source expression, a table row's "\\|" read as "|"."""
    return m["expr"].replace("\\|", "|")


def bound(text):
    """The bound numbers of a text: (line number, printed, expression, rule, match)."""
    out, line, at = [], 1, 0
    for m in _sites(text):
        line += text.count("\n", at, m.start())
        at = m.start()
        out.append((line, m["num"], _expr(m), m["rule"], m))
    return out


def bare_pipes(text):
    """The lines of a table whose bindings hold a bare "|": GitHub would split the cell there, so a
    binding in a table row writes "\\|"."""
    return [i for i, line in enumerate(text.split("\n"), 1) if line.lstrip().startswith("|")
            and any(re.search(r"(?<!\\)\|", m["expr"]) for m in _sites(line))]


def _same(printed, rendered):
    return (MINUS + printed[1:] if printed.startswith("-") else printed) == rendered


def stale(text):
    """The bound numbers that differ from their source: (line, printed, as the source renders it,
    expression)."""
    out = []
    for line, printed, expr, rule, _ in bound(text):
        try:
            r = render(expr, rule)
        except (KeyError, ValueError, ZeroDivisionError) as e:
            r = f"no value: {e}"
        if not _same(printed, r):
            out.append((line, printed, r, expr))
    return out


def write(text):
    """`text` with every bound number rendered from its source (keeping its minus sign style)."""
    def one(m):
        r = render(_expr(m), m["rule"])
        if m["num"].startswith("-"):
            r = "-" + r[1:]
        return r + m.group(0)[len(m["num"]):]
    out, at = [], 0
    for m in _sites(text):
        out += [text[at:m.start()], one(m)]
        at = m.end()
    return "".join(out + [text[at:]])


# ---------------------------------------------------------------------------------------------
# The prose's other numbers


def _generated(text):
    """The spans of the generated tables (between their markers)."""
    return [(m.start(), m.end()) for m in
            re.finditer(r"<!-- ([^\n>]+?) table: written by.*?<!-- end of the \1 table -->", text, re.S)]


def blank(text):
    """`text` with everything that is not a quantity (and the bound numbers) replaced by spaces,
    line breaks kept, so that positions and line numbers stay."""
    spans = _generated(text) + [(m.start(), m.end()) for m in _sites(text)]
    spans += [(m.start(), m.end()) for m in _BLANK.finditer(text)]
    out, at = [], 0
    for a, b in sorted(spans):
        if b <= at:
            continue
        a = max(a, at)
        out += [text[at:a], re.sub(r"[^\n]", " ", text[a:b])]
        at = b
    return "".join(out + [text[at:]])


def free(text):
    """The numbers of the prose that are not bound, per line: {line number: [printed, ...]}."""
    out = {}
    for i, line in enumerate(blank(text).split("\n"), 1):
        found = TOKEN.findall(line)
        if found:
            out[i] = found
    return out


def load_list(path=LIST):
    """The listed numbers: ({page: [entry]}, {source name: text}); an entry is a dict with `at`
    (text of its line, unique on the page), `numbers` (as printed, in order) and `source` (a
    name of [sources]; `n` picks the n-th line holding `at` where identical lines repeat)."""
    with open(path, "rb") as f:
        data = tomllib.load(f)
    pages = {}
    for e in data.get("line", []):
        pages.setdefault(e["page"], []).append(e)
    return pages, data.get("sources", {})


COMMENT = re.compile(r"<!--.*?-->")


def plain(line):
    """A line as a list entry's `at` reads it: each bound number and its comment as "#" (so that
    rendering it again does not move the entry), other comments left out."""
    out, at = [], 0
    for m in _sites(line):
        out += [line[at:m.start()], "#"]
        at = m.end()
    return COMMENT.sub("", "".join(out + [line[at:]]))


def _match(lines, entries):
    """{line number: [entry]} for the entries whose `at` is in exactly one line (read by `plain`),
    and the entries that match no line or several."""
    lines = {i: plain(line) for i, line in lines.items()}
    hits, bad = {}, []
    for e in entries:
        where = [i for i, line in lines.items() if e["at"] in line]
        if "n" in e:   # the n-th of several identical lines (a table header repeated)
            where = where[e["n"] - 1:e["n"]] if len(where) >= e["n"] >= 1 else []
        if len(where) != 1:
            bad.append((e, len(where)))
        else:
            hits.setdefault(where[0], []).append(e)
    return hits, bad


def listed(text, entries):
    """{line number: the numbers the list gives for that line, in order}."""
    hits, _ = _match(dict(enumerate(text.split("\n"), 1)), entries)
    return {i: [n for e in es for n in e["numbers"]] for i, es in hits.items()}


def unlisted(text, entries):
    """The lines whose free numbers are not the list's for that line: (line, printed numbers,
    the list's numbers or None)."""
    have = listed(text, entries)
    out = []
    for i, nums in free(text).items():
        if nums != have.get(i, []):
            out.append((i, nums, have.get(i)))
    return out


def unmatched(text, entries, sources):
    """The list's entries that match no line, several lines, or a line without free numbers, or
    name an unknown source: (at, why)."""
    lines = dict(enumerate(text.split("\n"), 1))
    hits, bad = _match(lines, entries)
    out = [(e["at"], f"matches {n} lines") for e, n in bad]
    have = free(text)
    out += [(e["at"], "its line has no free numbers") for i, es in hits.items() if i not in have for e in es]
    out += [(e["at"], f"unknown source {e['source']!r}") for e in entries if e["source"] not in sources]
    out += [(e["at"], "no numbers") for e in entries if not e["numbers"]]
    return out


def problems(text, entries, sources):
    """Every reason the page's numbers are not as their sources say (empty when they are)."""
    out = [f"line {l}: {p} is bound to {x}, which gives {r}" for l, p, r, x in stale(text)]
    out += [f"line {l}: a binding in a table row writes \\| for |" for l in bare_pipes(text)]
    for i, nums, listed in unlisted(text, entries):
        out.append(f"line {i}: numbers {nums} neither bound nor listed" if listed is None else
                   f"line {i}: numbers {nums}, the list has {listed}")
    out += [f"list entry {at!r}: {why}" for at, why in unmatched(text, entries, sources)]
    return out


# ---------------------------------------------------------------------------------------------
# The test of the test


def nudge(printed):
    """`printed` changed by one unit in its last printed digit ("0.79" -> "0.80", "9" -> "10",
    "3e-5" -> "4e-5", "−0.54%" -> "−0.53%": towards zero or away, always a different number)."""
    s = "-" + printed[1:] if printed.startswith(MINUS) else printed
    pct = s.endswith("%")
    s = s.rstrip("%")
    mant, _, exp = s.partition("e")
    d = Decimal(mant)
    unit = Decimal(1).scaleb(d.as_tuple().exponent)
    new = str((d + unit).quantize(unit))
    if mant.startswith("+") and not new.startswith("-"):
        new = "+" + new
    out = new + ("e" + exp if exp else "") + ("%" if pct else "")
    return MINUS + out[1:] if printed.startswith(MINUS) and out.startswith("-") else out


def mutants(text):
    """For every bound number, the text with that number (alone) nudged: (line, printed, text)."""
    for line, printed, _, _, m in bound(text):
        a = m.start("num")
        yield line, printed, text[:a] + nudge(printed) + text[m.end("num"):]


def table_mutants(text):
    """For every number of the generated tables, the text with it (alone) nudged: (printed,
    text)."""
    for a, b in _generated(text):
        body = COMMENT.sub(lambda m: " " * len(m.group(0)), text[a:b])
        for m in TOKEN.finditer(body):
            printed = m.group(0)
            if re.fullmatch(r"\d+(?:\.\d+)?(?:e[+−-]?\d+)?%?", printed):
                i = a + m.start()
                yield printed, text[:i] + nudge(printed) + text[i + len(printed):]


def free_mutants(text):
    """For every number that is not bound, its line's free numbers with that number (alone)
    nudged: (line, printed, the line's numbers as `free` reads them then). Only the line changes,
    so only its numbers are read again. Grouped ("6 276"), fractions and powers of ten are left
    out: their one unit is not well defined."""
    for i, line in enumerate(blank(text).split("\n"), 1):
        for m in TOKEN.finditer(line):
            printed = m.group(0)
            if re.fullmatch(r"\d+(?:\.\d+)?(?:e[+−-]?\d+)?%?", printed):
                mutated = line[:m.start()] + nudge(printed) + line[m.end():]
                yield i, printed, TOKEN.findall(mutated)


# ---------------------------------------------------------------------------------------------
# The helper: candidate sources of a free number


def _cells():
    """Every numeric cell of claims.SOURCES as (expression, value), and the converged values."""
    out = [(f"{c}|{o}", v) for (c, o), (v, _) in _refs().items()]
    out += [(f"{c}|{o} (bar)", b) for (c, o), (_, b) in _refs().items()]
    for name in claims.SOURCES:
        path, key = claims.SOURCES[name]
        for r in claims._rows(path):
            k = claims.row_key(r, key)
            for col, cell in r.items():
                try:
                    x = float(cell)
                except (TypeError, ValueError):
                    continue
                if math.isfinite(x) and col not in (key if isinstance(key, tuple) else (key,)):
                    out.append((f"{name}:{k}|{col}", x))
    return out


def candidates(printed, cells=None):
    """The cells that equal `printed` (with its sign, if any) to its printed digits, or whose
    magnitude does, with a rule that prints them so."""
    cells = _cells() if cells is None else cells
    s = printed.replace(MINUS, "-").replace(" ", "")
    pct = "%" if s.endswith("%") else ""
    s = s.rstrip("%")
    if not re.fullmatch(r"[+-]?[\d.]+(e[+-]?\d+)?", s):
        return []
    mant = s.split("e")[0]
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    spec = ("+" if s.startswith("+") else "") + f".{decimals}{'e' if 'e' in s else pct or 'f'}"
    out = []
    for expr, x in cells:
        for mods in ("", "abs "):
            if mods and s[0] in "+-":
                continue
            try:
                rendered = format(abs(x) if mods else x, spec)
            except ValueError:
                continue
            rendered = re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("" if m.group(1) == "+" else "-") + m.group(2), rendered)
            if rendered == s + pct:
                bar = "bar " if expr.endswith("(bar)") else ""
                out.append(f"{expr.removesuffix(' (bar)')} ; {bar}{mods}{spec}")
                break
    return out
