"""The claims table: its rule on numbers it must judge, every number it quotes read from the
converged references, and docs/reproduction.md holding the table as it is written now, with the
numbers of committed summaries (not converged) resolving. Pure Python, no solver."""

import math
import re
import unittest
from pathlib import Path

from poroplast_tools import claims, hypothesis
from poroplast_tools.refs import references

ROOT = Path(__file__).resolve().parents[2]


class Rule(unittest.TestCase):
    def test_within_the_papers_precision_widened_by_twice_the_error_bar(self):
        self.assertEqual(claims.rule(42.33, 0.19, 40, 5), "reproduced")
        self.assertEqual(claims.rule(42.33, 0.19, 40, 2), "reproduced")  # 2.33 ≤ 2 + 0.38
        self.assertEqual(claims.rule(42.33, 0.1, 40, 2), "partly")  # 2.33 > 2 + 0.2, ×1.06
        self.assertEqual(claims.rule(3.902, 0.066, 4.0, 0.05), "reproduced")

    def test_off_by_less_than_a_factor_two_with_the_same_sign_is_partly(self):
        self.assertEqual(claims.rule(1.2, 0.01, 2, 0.5), "partly")
        self.assertEqual(claims.rule(3.9, 0.01, 2, 0.5), "partly")
        self.assertEqual(claims.rule(0.565, 0.028, 2, 0.5), "no")  # ×0.28
        self.assertEqual(claims.rule(-2.8, 0.46, -12, 5.5), "no")  # ×0.23
        self.assertEqual(claims.rule(0.5, 0.01, -1, 0.1), "no")  # the opposite sign

    def test_a_factor_precision(self):
        self.assertEqual(claims.rule(4.0, 0.01, 10, "×3.1623"), "reproduced")
        self.assertEqual(claims.rule(1.489, 0.013, 10, "×3.1623"), "no")
        self.assertEqual(claims.rule(30.0, 0.5, 10, "×3.1623"), "reproduced")


class Table(unittest.TestCase):
    def setUp(self):
        self.rows = claims.load()
        self.refs = references()

    def test_ids_are_unique_and_verdicts_known(self):
        ids = [r["id"] for r in self.rows]
        self.assertEqual(len(ids), len(set(ids)))
        for r in self.rows:
            if r["measure"]:
                # A numeric claim's verdict is the rule's, never written by hand.
                self.assertEqual(r["verdict"], "", r["id"])
                self.assertTrue(r["paper_value"] and r["precision"] and r["precision_note"], r["id"])
            else:
                self.assertIn(r["verdict"], claims.VERDICTS, r["id"])

    def test_every_claim_of_the_paper_has_a_row(self):
        numbers = {int(re.match(r"P(\d+)", r["id"]).group(1)) for r in self.rows}
        self.assertLessEqual(set(range(1, 59)), numbers)   # the audit's 58, and those found since
        self.assertEqual(numbers, set(range(1, max(numbers) + 1)))

    def test_every_quoted_number_is_the_references(self):
        for r in self.rows:
            for case, observable in claims.PLACEHOLDER.findall(r["ours"]):
                if ":" in case:   # a committed summary's value (not converged): it must exist
                    self.assertTrue(math.isfinite(claims.source_value(*case.split(":", 1), observable)), r["id"])
                else:
                    self.assertIn((case, observable), self.refs, r["id"])
            ours, verdict = claims.resolved(self.refs, r)
            self.assertNotIn("{", ours, r["id"])
            if r["measure"]:
                value, bar = claims.measure(self.refs, r["measure"])
                self.assertIn(claims.fmt(value, bar), ours)

    def test_a_value_without_an_error_bar_prints_four_digits(self):
        self.assertEqual(claims.fmt(16.2248, math.nan), "16.22")
        self.assertEqual(claims.fmt(0.0123456, math.nan), "0.01235")
        self.assertEqual(claims.fmt(42.334, 0.19), "42.33 ± 0.19")

    def test_a_difference_and_a_ratio_carry_both_error_bars(self):
        refs = {("a", "x"): (3.0, 0.3), ("b", "x"): (1.0, 0.4)}
        # As references.py combines its values: the bars add, or the relative bars.
        value, bar = claims.measure(refs, "a|x - b|x")
        self.assertAlmostEqual(value, 2.0)
        self.assertAlmostEqual(bar, 0.7)
        value, bar = claims.measure(refs, "a|x / b|x")
        self.assertAlmostEqual(value, 3.0)
        self.assertAlmostEqual(bar, 3.0 * (0.1 + 0.4))

    def test_the_docs_hold_the_table_as_written_now(self):
        text = (ROOT / "docs" / "reproduction.md").read_text(encoding="utf-8")
        self.assertEqual(text, claims.replace_in(text, claims.table(self.rows, self.refs)),
                         "docs/reproduction.md: run python3 scripts/claims.py --write docs/reproduction.md")
        self.assertIn(claims.RULE, text)

class Hypothesis(unittest.TestCase):
    def test_the_share_of_the_gap_closed(self):
        self.assertAlmostEqual(hypothesis.closed(-12, -2, -4.5), 0.25)
        self.assertAlmostEqual(hypothesis.closed(40, 42.24, 40.12), 1 - 0.12 / 2.24)
        self.assertLess(hypothesis.closed(0.25, 0.79, 0.80), 0)
        self.assertLess(hypothesis.closed(2.0, 0.5, -3.5), 0)  # overshooting past the other side

    def test_rows_are_differences_and_ratios_of_one_models_runs(self):
        def run(cross, peak, con, p30):
            return {"zero:probe_p": cross, "max:force_total_mg": peak, "max:force_constitutive_mg": con,
                    "probe_p@30": p30, "changes": ""}
        rows = {v: run(40.0, 17.0, 7.0, 1.0) for v in hypothesis.HYPOTHESIS_VARIANTS}
        rows["c2_40a"] = run(30.0, 17.0, 7.0, 0.5)
        rows["lambda_01_40a"] = run(float("nan"), 18.0, 9.0, 4.0)
        got = hypothesis.values(rows)
        self.assertEqual(got["c = 2: its crossing minus the isotropic one (s)"][1]["(40a)"], -10.0)
        self.assertEqual(got["c = 2 over isotropic, p(X_U, 30 s)"][1]["(40a)"], 0.5)
        self.assertEqual(got["λp 1 → 0.1: constitutive-force peak change (mg)"][1]["(40a)"], 2.0)
        self.assertEqual(got["λp 1 → 0.1: total-force peak change (mg)"][1]["λp × 1.1"], 0.0)

    def test_the_docs_hold_the_table_of_the_shipped_runs(self):
        rows = hypothesis.load()
        self.assertTrue(all(rows[v]["status"] == "ok" for v in hypothesis.HYPOTHESIS_VARIANTS))
        text = (ROOT / "docs" / "reproduction.md").read_text(encoding="utf-8")
        self.assertEqual(text, claims.replace_in(text, hypothesis.table(rows), hypothesis.BEGIN, hypothesis.END),
                         "docs/reproduction.md: run python3 scripts/claims.py --write docs/reproduction.md")


if __name__ == "__main__":
    unittest.main()
