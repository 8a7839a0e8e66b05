"""Every number of the pages in doc_numbers.PAGES (docs/reproduction.md, docs/studies.md,
docs/performance.md, docs/numerics.md, README.md, scripts/README.md, and the claims table's own words
in scripts/data/claims.csv) has its source, and a wrong one fails:

* a bound number (`42.33<!-- = remodel_155|zero:probe_p ; .2f -->`) must be what its rule prints
  of its source, a committed CSV (scripts/data, docs/figures/data);
* every other number of the prose must be listed, line by line, with its source in
  scripts/data/doc_numbers.toml, and every entry there must still match its line;
* the generated tables of docs/reproduction.md must be as their CSVs render them;
* the test of the test: each bound number changed by one unit in its last printed digit fails the
  check (the count is printed), and so does each listed number.

Pure Python, no solver; a few seconds (poroplast_tools/doc_numbers.py says what is not a number:
section, figure, equation and commit numbers, dates, versions, code, links)."""

import contextlib
import sys
import tempfile
import unittest
from unittest import mock
from pathlib import Path

from poroplast_tools import claims, doc_numbers as dn, doc_tables, hypothesis

ROOT = Path(__file__).resolve().parents[2]


class Pages(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.listed, cls.sources = dn.load_list()
        cls.texts = {name: dn.read_page(name) for name in dn.PAGES}

    def test_every_bound_number_is_its_source_by_its_rule(self):
        for name, text in self.texts.items():
            with self.subTest(page=name):
                self.assertEqual(dn.stale(text), [], f"{name} is stale: python3 scripts/doc_numbers.py --write {name}")
                self.assertEqual(dn.bare_pipes(text), [], f"{name}: a binding in a table row writes \\| for |")

    def test_every_other_number_is_listed_with_its_source(self):
        for name, text in self.texts.items():
            with self.subTest(page=name):
                self.assertEqual(dn.unlisted(text, self.listed.get(name, [])), [],
                                 f"numbers of {name} neither bound nor listed: python3 scripts/doc_numbers.py --free {name}")
                self.assertEqual(dn.unmatched(text, self.listed.get(name, []), self.sources), [],
                                 f"entries of scripts/data/doc_numbers.toml that no longer match {name}")

    def test_the_list_names_only_the_pages_checked(self):
        self.assertEqual(sorted(set(self.listed) - set(dn.PAGES)), [])

    @staticmethod
    def generated(text):
        """docs/reproduction.md as claims.py --write renders its tables from the CSVs."""
        text = claims.replace_in(text, claims.table())
        text = claims.replace_in(text, hypothesis.table(), hypothesis.BEGIN, hypothesis.END)
        return doc_tables.write_all(text, claims.replace_in)

    def test_the_generated_tables_are_as_their_csvs_render_them(self):
        text = self.texts["docs/reproduction.md"]
        for name in doc_tables.TABLES:
            self.assertIn(doc_tables.markers(name)[0], text, f"docs/reproduction.md has no {name} table")
        self.assertTrue(text == self.generated(text),
                        "docs/reproduction.md is stale: python3 scripts/claims.py --write docs/reproduction.md")

    def test_changing_any_number_of_a_generated_table_fails(self):
        text = self.texts["docs/reproduction.md"]
        expected = self.generated(text)   # the tables come from the CSVs alone: a mutant's rendering too
        outcomes = [mutant != expected for _, mutant in dn.table_mutants(text)]
        print(f"\n{sum(outcomes)} of {len(outcomes)} numbers of the generated tables fail when changed by one unit "
              "in the last digit", file=sys.stderr)
        self.assertTrue(all(outcomes))
        self.assertGreater(len(outcomes), 500)

    def test_changing_any_bound_number_by_one_unit_in_its_last_digit_fails(self):
        total, caught, missed = 0, 0, []
        for name, text in self.texts.items():
            for line, printed, mutant in dn.mutants(text):
                total += 1
                if dn.stale(mutant):
                    caught += 1
                else:
                    missed.append(f"{name}:{line}: {printed}")
        print(f"\n{caught} of {total} bound numbers fail when changed by one unit in the last digit", file=sys.stderr)
        self.assertEqual(missed, [])
        self.assertGreater(total, 100)

    def test_changing_any_listed_number_fails(self):
        total, missed = 0, []
        for name, text in self.texts.items():
            have = dn.listed(text, self.listed.get(name, []))
            for line, printed, numbers in dn.free_mutants(text):
                total += 1
                if numbers == have.get(line, []):
                    missed.append(f"{name}:{line}: {printed}")
        print(f"\n{total - len(missed)} of {total} listed numbers fail when changed by one unit in the last digit",
              file=sys.stderr)
        self.assertEqual(missed, [])


class Machinery(unittest.TestCase):
    def test_a_stale_bound_number_is_found(self):
        good = "crosses at 42.33<!-- = remodel_155|zero:probe_p ; .2f --> s"
        self.assertEqual(dn.stale(good), [])
        self.assertEqual(len(dn.stale(good.replace("42.33", "42.34"))), 1)
        self.assertEqual(len(dn.stale(good.replace("42.33", "42.3"))), 1, "fewer digits than the rule prints")
        self.assertEqual(dn.write(good.replace("42.33", "17")), good)

    def test_a_binding_in_a_table_row_escapes_its_pipes(self):
        row = "| x | 42.33<!-- = remodel_155|zero:probe_p ; .2f --> |"
        self.assertEqual(dn.bare_pipes(row), [1])
        self.assertEqual(dn.bare_pipes(row.replace("155|", "155\\|")), [])
        self.assertEqual(dn.stale(row.replace("155|", "155\\|")), [])
        self.assertEqual(dn.bare_pipes(row[2:]), [], "a prose line may hold a bare |")

    def test_a_list_entry_does_not_move_when_its_line_is_rendered_again(self):
        line = "at 42.33<!-- = remodel_155|zero:probe_p ; .2f --> s and 40 s<!-- a remark -->"
        self.assertEqual(dn.plain(line), "at # s and 40 s")
        entry = {"page": "p", "at": "at # s and", "numbers": ["40"], "source": "paper"}
        self.assertEqual(dn.unlisted(line, [entry]), [])
        self.assertEqual(dn.unlisted(line.replace("42.33", "42.3"), [entry]), [])
        self.assertEqual(len(dn.unlisted(line.replace("40 s", "41 s"), [entry])), 1)

    def test_the_rules(self):
        x, bar = dn.value("remodel_155|zero:probe_p")
        self.assertEqual(dn.render("remodel_155|zero:probe_p", "bar .2f"), f"{bar:.2f}")
        shift = "hypothesis:form_40a|shift zero:probe_p"
        self.assertTrue(dn.render(shift, ".2f").startswith("−"), "a minus sign is U+2212")
        self.assertEqual(dn.render(shift, "abs .2f"), dn.render(shift, ".2f")[1:])
        self.assertTrue(dn.render("meridian:remodel_405|p_share_peak", ".1%").endswith("%"))
        self.assertEqual(dn.render("meridian:remodel_405|p_share_peak", "*100 .1f"),
                         dn.render("meridian:remodel_405|p_share_peak", ".1%")[:-1])
        self.assertEqual(dn.render("count meridian", ".0f"), "72")
        with self.assertRaises(KeyError):
            dn.render("nosuch:row|col", ".2f")

    @contextlib.contextmanager
    def source(self, name, key, text):
        """A CSV `text` as the source `name` (rows keyed by column `key`) while the block runs."""
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / f"{name}.csv"
            path.write_text(text, encoding="utf-8")
            with mock.patch.dict(claims.SOURCES, {name: (path, key)}):
                yield
        dn.value.cache_clear()
        dn.render.cache_clear()

    def test_an_extreme_skips_the_rows_without_a_value(self):
        # a run that did not reach the value writes "nan"; first or not, it has no say in min/max
        with self.source("test_runs_nan", "run", "run,t\na,nan\nb,29.5\nc,nan\nd,41.25\n"):
            self.assertEqual(dn.render("min test_runs_nan|t", ".2f"), "29.50")
            self.assertEqual(dn.render("max test_runs_nan|t", ".2f"), "41.25")
            self.assertEqual(dn.render("count test_runs_nan", ".0f"), "4", "count: every row")

    def test_an_aggregate_over_the_rows_a_condition_keeps(self):
        with self.source("test_points", "p", "p,share,peak\na,0.3,17\nb,0.5,15\nc,nan,20\nd,0.7,13\n"):
            self.assertEqual(dn.render("count test_points where share at least 0.5", ".0f"), "2")
            self.assertEqual(dn.render("max test_points|peak where share at least 0.5", ".0f"), "15")
            self.assertEqual(dn.render("min test_points|peak where share at most 0.5", ".0f"), "15")
            self.assertEqual(dn.render("count test_points where share at most 0.4", ".0f"), "1", "nan is kept by neither")

    def test_one_unit_in_the_last_digit(self):
        for printed, nudged in [("0.79", "0.80"), ("9", "10"), ("3e-5", "4e-5"), ("−0.54%", "−0.53%"),
                                ("+0.13", "+0.14"), ("0.000338", "0.000339"), ("1.2e-3", "1.3e-3")]:
            self.assertEqual(dn.nudge(printed), nudged)

    def test_what_is_a_number(self):
        text = ("Table 1 (µ = 20 kPa), §§3.2–7.4, Figs 3–11 and Fig 7c, 8c, (40a)/(40b), eq. (56), [42], "
                "P24a, P59–P66, 2026-12-02, 06:07, PETSc 3.18, commit 2067464, 3-D, `remodel_155`, "
                "[a](studies.md#x), 6 276 dofs, 1/16 of the steps, 10⁴ s, 11.8% and ×1.49\n"
                "```\nrun 42 s\n```\n<!-- 17 -->")
        self.assertEqual(dn.free(text), {1: ["20", "6 276", "1/16", "10⁴", "11.8%", "1.49"]})

    def test_candidates_are_the_cells_equal_to_the_printed_digits(self):
        self.assertIn("remodel_155|zero:probe_p ; .2f", dn.candidates("42.33"))
        self.assertIn("remodel_155|zero:probe_p ; bar .2f", dn.candidates("0.19"))
        self.assertNotIn("remodel_155|zero:probe_p ; .2f", dn.candidates("42.34"))


if __name__ == "__main__":
    unittest.main()
