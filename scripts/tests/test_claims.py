"""The claims table: its rule on numbers it must judge, every number it quotes read from the
converged references, and docs/reproduction.md holding the table as it is written now, with the
numbers of committed summaries (not converged) resolving. Pure Python, no solver."""

import csv
import importlib.util
import math
import re
import tempfile
import unittest
from pathlib import Path

from poroplast_tools import claims, hypothesis
from poroplast_tools.refs import references

ROOT = Path(__file__).resolve().parents[2]
# The labels a statement's parts carry in its row (claims.RULE).
HOLDS, FAILS, UNMEASURED, INCOMPARABLE = "holds:", "fails:", "not measured:", "not comparable:"


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

    def test_a_value_that_is_not_converged_has_no_bar_to_widen_by(self):
        self.assertEqual(claims.rule(4.04, math.nan, 4.0, 0.05), "reproduced")
        self.assertEqual(claims.rule(4.06, math.nan, 4.0, 0.05), "partly")
        self.assertEqual(claims.rule(1.08, math.nan, 4.0, 0.05), "no")  # ×0.27

    def test_the_crossing_at_40_s_is_as_precise_as_the_one_at_28_s(self):
        # 42.33 ± 0.19 s against "40 s": ±0.5 s, not ±5 s for the trailing zero.
        paper, precision = claims.printed("the pressure equals zero at t = 40 s")
        self.assertEqual(claims.rule(42.33, 0.19, paper, precision), "partly")
        self.assertEqual(claims.rule(40.3, 0.19, paper, precision), "reproduced")


class Precision(unittest.TestCase):
    """RULE's precision, read from the paper's words."""

    def test_every_printed_digit_counts_the_same_way(self):
        self.assertEqual(claims.printed("from 40 s onwards"), (40.0, 0.5))
        self.assertEqual(claims.printed("at the instant of time t = 28 s"), (28.0, 0.5))
        self.assertEqual(claims.printed("a change of 400 s"), (400.0, 0.5))
        self.assertEqual(claims.printed("0.25 mg"), (0.25, 0.005))

    def test_a_power_of_ten_and_the_papers_pa_in_the_tables_kpa(self):
        value, precision = claims.printed("a value close to 4.0 × 10³ Pa before the detachment")
        self.assertAlmostEqual(value, 4.0)
        self.assertAlmostEqual(precision, 0.05)
        value, precision = claims.printed("3 × 10⁻² s")
        self.assertAlmostEqual(value, 0.03)
        self.assertAlmostEqual(precision, 0.005)

    def test_a_fraction_is_a_count_of_its_parts(self):
        self.assertEqual(claims.printed("approximately 1/4"), (0.25, 0.125))
        self.assertEqual(claims.printed("3/8 of it"), (0.375, 0.0625))

    def test_words_of_approximation_add_nothing(self):
        self.assertEqual(claims.printed("is about 4 mg"), claims.printed("is 4 mg"))
        self.assertEqual(claims.printed("close to 4.0 × 10³ Pa"), claims.printed("4.0 × 10³ Pa"))

    def test_an_order_of_magnitude_is_a_factor(self):
        self.assertEqual(claims.printed("one order of magnitude lower"), (10.0, "×3.1623"))

    def test_a_difference_of_two_printed_numbers_carries_both_precisions(self):
        self.assertEqual(claims.paper_number('"zero at t = 28 s" minus "earlier than t = 40 s"'), (-12.0, 1.0))
        self.assertEqual(claims.paper_number('"about 4 mg"'), (4.0, 0.5))

    def test_a_quote_must_print_one_number(self):
        for quote in ("from 28 s to 40 s", "no number here"):
            with self.assertRaises(ValueError):
                claims.printed(quote)
        for note in ("from 40 s onwards", '"28 s" plus "40 s"', '"1 s" minus "2 s" minus "3 s"'):
            with self.assertRaises(ValueError):
                claims.paper_number(note)

    def test_the_paper_printed_to_its_own_digit(self):
        self.assertEqual(claims.precision_text(40.0, 0.5), "40 ± 0.5")
        self.assertEqual(claims.precision_text(4.0, 0.05), "4.0 ± 0.05")
        self.assertEqual(claims.precision_text(0.25, 0.125), "0.25 ± 0.125")
        self.assertEqual(claims.precision_text(-12.0, 1.0), "-12 ± 1")
        self.assertEqual(claims.precision_text(10.0, "×3.1623"), "10, within a factor 3.1623")


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
                self.assertTrue(r["paper_value"] and r["precision_note"], r["id"])
            else:
                self.assertIn(r["verdict"], claims.VERDICTS, r["id"])

    def test_each_numeric_row_quotes_the_words_of_its_number(self):
        # The number read from the quote is the row's number: its precision comes from the words.
        for r in (r for r in self.rows if r["measure"]):
            value, precision = claims.paper_number(r["precision_note"])
            self.assertAlmostEqual(value, float(r["paper_value"]), msg=r["id"])
            self.assertTrue(isinstance(precision, str) or 0 < precision < abs(value), r["id"])

    def test_each_numeric_verdict_is_the_rules_for_ours_against_the_papers(self):
        for r in (r for r in self.rows if r["measure"]):
            value, bar = claims.measure(self.refs, r["measure"])
            bar = 0.0 if math.isnan(bar) else bar
            paper, precision = claims.paper_number(r["precision_note"])
            verdict = claims.resolved(self.refs, r)[1]
            if isinstance(precision, str):
                low, high = paper / float(precision[1:]), paper * float(precision[1:])
                within = value + 2 * bar >= low and value - 2 * bar <= high
            else:
                within = abs(value - paper) <= precision + 2 * bar
            near = 0.5 <= value / paper <= 2
            self.assertEqual(verdict, "reproduced" if within else "partly" if near else "no", r["id"])

    def test_each_statement_says_which_of_its_parts_hold(self):
        for r in (r for r in self.rows if not r["measure"]):
            ours, verdict = r["ours"], r["verdict"]
            if verdict == "partly":
                self.assertIn(HOLDS, ours, r["id"])
                self.assertTrue(any(x in ours for x in (FAILS, UNMEASURED, INCOMPARABLE)), r["id"])
            if verdict == "reproduced":
                self.assertFalse(any(x in ours for x in (FAILS, UNMEASURED, INCOMPARABLE)), r["id"])
            if verdict == "no":
                self.assertIn(FAILS, ours, r["id"])
                self.assertNotIn(HOLDS, ours, r["id"])
            if verdict == "open":
                self.assertNotIn(HOLDS, ours, r["id"])
                self.assertNotIn(FAILS, ours, r["id"])
            if verdict == "not comparable":
                self.assertNotIn(HOLDS, ours, r["id"])
                self.assertIn("not comparable", ours, r["id"])

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

def _reproduce():
    """scripts/reproduce.py as a module (a script, not a package's)."""
    spec = importlib.util.spec_from_file_location("reproduce", ROOT / "scripts" / "reproduce.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Outflow(unittest.TestCase):
    """reproduce.flow, the outflow by phase that P7, P16, P20 and P65 read (flow_meridian.csv)."""

    def test_phases_of_a_known_outflow(self):
        # remodel_405: the hold ends at 400 s. 1-s steps, outflow 50 − t µm³/s: out until 50 s, then in.
        with tempfile.TemporaryDirectory() as d:
            with open(Path(d) / "history.csv", "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["step", "time", "dt", "outflow", "fluid_volume", "height", "width"])
                for t in range(0, 411):
                    w.writerow([t, float(t), 1.0, 50.0 - t, 1000.0, 100.0 + t, 200.0])
            s = _reproduce().flow("remodel_405", Path(d))
        self.assertEqual(s["t_hold_end_s"], 400.0)
        self.assertAlmostEqual(s["t_inflow_s"], 50.0)
        self.assertEqual(s["outflow_min_0_40"], 11.0)           # at 39 s, ]0, 40[ open
        self.assertEqual(s["outflow_40"], 10.0)
        self.assertEqual(s["out_0_40_um3"], sum(50 - t for t in range(1, 41)))
        self.assertEqual(s["in_hold_um3"], sum(t - 50 for t in range(51, 401)))
        self.assertEqual(s["out_hold_um3"], sum(50 - t for t in range(6, 50)))
        self.assertAlmostEqual(s["in_hold_share"], s["in_hold_um3"] / 1000.0)
        self.assertEqual(s["outflow_max_hold_after_inflow"], 0.0)  # at 50 s; inward after
        self.assertEqual(s["outflow_hold_end"], -350.0)
        self.assertAlmostEqual(s["hw_60"], 160.0 / 200.0)

    def test_an_outflow_that_never_turns(self):
        with tempfile.TemporaryDirectory() as d:
            with open(Path(d) / "history.csv", "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["step", "time", "dt", "outflow", "fluid_volume", "height", "width"])
                for t in range(0, 101):
                    w.writerow([t, float(t), 1.0, 5.0, 1000.0, 100.0, 200.0])
            s = _reproduce().flow("remodel_40", Path(d))
        self.assertIsNone(s["t_inflow_s"])
        self.assertIsNone(s["outflow_max_hold_after_inflow"])
        self.assertEqual(s["in_hold_um3"], 0.0)
        self.assertEqual(s["out_hold_um3"], 5.0 * 30)             # 6..35 s


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
