"""A lab's data file: read in its units, and every malformed file refused with a message that
names the problem and the line."""
import tempfile
import unittest
from pathlib import Path

from poroplast_tools.measured import DataError, check_within, read_curve


class Measured(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def file(self, text, name="data.csv"):
        p = Path(self.dir.name) / name
        p.write_text(text, encoding="utf-8")
        return p

    def refused(self, text, part, column="force_total_mg"):
        with self.assertRaises(DataError) as e:
            read_curve(self.file(text), column)
        self.assertIn(part, str(e.exception))
        return str(e.exception)

    def test_units_are_converted_to_mg(self):
        # 9.80665 uN = 1 mg (milligram-force); nN a thousandth of a uN.
        t, v, s = read_curve(self.file("# comment\ntime,force_uN,sigma_uN\n1,9.80665,0.980665\n2,19.6133,0.980665\n"),
                             "force_total_mg")
        self.assertEqual(t, [1.0, 2.0])
        self.assertAlmostEqual(v[0], 1.0, places=12)
        self.assertAlmostEqual(v[1], 2.0, places=12)
        self.assertAlmostEqual(s[0], 0.1, places=12)
        _, v, s = read_curve(self.file("time,force_nN\n0.5,9806.65\n"), "force_total_mg")
        self.assertAlmostEqual(v[0], 1.0, places=12)
        self.assertIsNone(s)
        _, v, _ = read_curve(self.file("time_s,value\n0.5,3.0\n"), "force_total_mg", unit="uN")
        self.assertAlmostEqual(v[0], 3.0 / 9.80665, places=12)
        # The model's own column name, or `value`, in mg.
        _, v, _ = read_curve(self.file("t,force_total_mg\n0.5,3.0\n"), "force_total_mg")
        self.assertEqual(v, [3.0])

    def test_every_malformed_file_is_named_with_its_problem(self):
        self.refused("", "empty")
        self.refused("# only a comment\n\n", "empty")
        self.refused("1,2\n3,4\n", "no header line")
        self.refused("force_uN\n1\n", "no time column")
        self.refused("time,height\n1,2\n", "no data column: expected `force_total_mg`, `force_uN`")
        self.refused("time,force_uN\n1,abc\n", "line 2: `abc` in column `force_uN` is not a number")
        self.refused("time,force_uN\n1,nan\n", "finite number")
        self.refused("time,force_uN\n1,inf\n", "finite number")
        self.refused("time,force_uN\n2,1\n1,1\n", "line 3: time 1 s comes before")
        self.refused("time,force_uN\n1,1\n1,2\n", "line 3: time 1 s repeats")
        self.refused("time,force_uN\n0,1\n", "t > 0")
        self.refused("time,force_uN\n1,1,3\n", "3 fields, the header has 2")
        self.refused("time,force_uN\n", "no rows")
        self.refused("time,force_uN,sigma\n1,1,0\n", "sigma 0")
        self.refused("time,time,force_uN\n1,1,1\n", "appears twice")
        with self.assertRaises(DataError) as e:
            read_curve(Path(self.dir.name) / "missing.csv", "force_total_mg")
        self.assertIn("no such file", str(e.exception))
        p = Path(self.dir.name) / "binary.csv"
        p.write_bytes(bytes([0xff, 0xfe, 0x00, 0x81]))
        with self.assertRaises(DataError) as e:
            read_curve(p, "force_total_mg")
        self.assertIn("not a text file", str(e.exception))

    def test_times_beyond_the_run_are_refused(self):
        check_within("d.csv", [1.0, 90.0], 90.0)
        with self.assertRaises(DataError) as e:
            check_within("d.csv", [1.0, 95.0, 99.0], 90.0)
        self.assertIn("2 data times after the run's end (t_end = 90 s), the first 95 s", str(e.exception))


if __name__ == "__main__":
    unittest.main()
