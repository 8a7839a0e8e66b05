"""The references reader: scripts/data/references.csv, the one source of converged values."""
import tempfile
import unittest
from pathlib import Path

from poroplast_tools.refs import SHIPPED, converged, references


class References(unittest.TestCase):
    def test_the_shipped_file(self):
        refs = references()
        value, bar = refs[("reference", "max:force_total_mg")]
        self.assertTrue(17.5 < value < 17.7 and 0 < bar < 0.01 * value, (value, bar))
        self.assertEqual(converged("reference", "max:force_total_mg"), value)
        self.assertTrue(SHIPPED.exists())

    def test_another_file_and_a_missing_value(self):
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "references.csv"
            p.write_text("case,observable,extrapolated,error_bar,relative_bar\nx,max:f,2.5,0.1,0.04\n")
            self.assertEqual(references(p), {("x", "max:f"): (2.5, 0.1)})
            self.assertEqual(converged("x", "max:f", p), 2.5)
            with self.assertRaises(SystemExit):
                converged("x", "min:f", p)


if __name__ == "__main__":
    unittest.main()
