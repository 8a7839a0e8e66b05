"""Every number of docs/reproduction.md has a home in a committed CSV: the generated tables are
as their CSVs render them now, and every decimal number of the prose around them equals, to the
digits printed, a value of a committed CSV (scripts/data/*.csv, docs/figures/data/*.csv: the
references, the causes, the shipped scenes' summaries and figure data; its magnitude for a shift
said without its sign), a converged difference or ratio of the claims table, or one of the
model's parameters below. A number left from an older run fails. Pure Python, no solver."""

import csv
import math
import re
import unittest
from pathlib import Path

from poroplast_tools import claims, doc_tables
from poroplast_tools.refs import references

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "reproduction.md"

# Table 1 and the set-up's numbers (docs/model.md), which the page quotes as inputs.
PARAMETERS = [3.7729e-3, 2.5779e-3, 2.5779e-4, 3.7729e-7, 3.7729e-2, 0.2, 0.6, 0.0848, 4.638, 0.7, 0.3, 0.1, 0.5,
              0.45, 0.25, 1.1, 1.15, 1.2, 1.25, 0.4, 1.9, 0.125, 0.78, 0.11, 11.24, 11.8, 0.882, 1.254, 2.1, 0.03,
              0.003, 2.5]

NUMBER = re.compile(r"(?<![\w.])[−-]?\d+\.\d+(?:e[−-]?\d+)?(?![\w.])")


def pool():
    """Every numeric cell of the committed CSVs, the claims' paper numbers and PARAMETERS."""
    values = list(PARAMETERS)
    for path in sorted((ROOT / "scripts" / "data").glob("*.csv")) + sorted(
            (ROOT / "docs" / "figures" / "data").glob("*.csv")):
        with open(path, newline="", encoding="utf-8") as f:
            for row in csv.reader(f):
                for cell in row:
                    try:
                        x = float(cell)
                    except ValueError:
                        continue
                    if math.isfinite(x):
                        values.append(x)
    refs = references()
    for r in claims.load():   # the claims' differences and ratios of converged values
        if r["measure"]:
            values.append(claims.measure(refs, r["measure"])[0])
    # A shift is often said without its sign ("2.8 s earlier"): the magnitudes count too.
    return values + [abs(v) for v in values]


def prose(text):
    """The page without its generated tables, code blocks and image lines."""
    text = re.sub(r"<!-- (.+?) table: written by.*?<!-- end of the \1 table -->", "", text, flags=re.S)
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    return "\n".join(line for line in text.splitlines() if not line.startswith("!["))


def matches(token, values):
    """Whether a printed number equals some value to its printed digits."""
    x = float(token.replace("−", "-"))
    mantissa = token.split("e")[0]
    decimals = len(mantissa.split(".")[1])
    scale = 10 ** int(token.split("e")[1].replace("−", "-")) if "e" in token else 1.0
    tol = 0.5 * 10 ** -decimals * scale * (1 + 1e-9)
    return any(abs(v - x) <= tol for v in values)


class Numbers(unittest.TestCase):
    def test_the_generated_tables_are_as_their_csvs_render_them(self):
        text = DOC.read_text(encoding="utf-8")
        for name in doc_tables.TABLES:
            begin, _ = doc_tables.markers(name)
            self.assertTrue(begin in text, f"docs/reproduction.md has no {name} table")
        self.assertTrue(text == doc_tables.write_all(text, claims.replace_in),
                         "docs/reproduction.md is stale: python3 scripts/claims.py --write docs/reproduction.md")

    def test_every_number_of_the_prose_is_in_a_committed_csv(self):
        values = pool()
        text = prose(DOC.read_text(encoding="utf-8"))
        missing = sorted({t for t in NUMBER.findall(text) if not matches(t, values)}, key=lambda t: float(t.replace("−", "-")))
        self.assertEqual(missing, [], "numbers of docs/reproduction.md in no committed CSV")

    def test_the_check_finds_a_stale_number(self):
        values = [42.334, 0.786, 16.9619]
        self.assertTrue(matches("42.33", values))
        self.assertTrue(matches("0.79", values))
        self.assertFalse(matches("51.5", values))
        self.assertFalse(matches("42.3", [42.36]))
        self.assertTrue(matches("1.7e-3", [0.00171]))
        self.assertEqual(NUMBER.findall("at 42.33 s, ×1.49 and −0.54 kPa; v1.2.3 no"), ["42.33", "1.49", "−0.54"])


if __name__ == "__main__":
    unittest.main()
