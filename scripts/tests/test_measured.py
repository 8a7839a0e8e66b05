"""A lab's data file: read in its units whatever program wrote it (Excel's exports in a European
or US locale, an instrument's Windows software, a script), every detected convention said in
one line, and every malformed or ambiguous file refused with a message that names the problem,
its line and the fix. The numbers expected are the file's, converted by hand: 1 mg = 9.81 µN
(the solver's g), 1 min = 60 s."""
import tempfile
import unittest
from pathlib import Path

from poroplast_tools import units
from poroplast_tools.measured import DataError, check_within, read_curve

DATA = Path(__file__).resolve().parent / "data"
G = 9.81


class Measured(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def file(self, text, encoding="utf-8", name="data.csv"):
        p = Path(self.dir.name) / name
        p.write_bytes(text if isinstance(text, bytes) else text.encode(encoding))
        return p

    def read(self, text, column="force_total_mg", encoding="utf-8", **kw):
        return read_curve(self.file(text, encoding), column, **kw)

    def refused(self, text, part, column="force_total_mg", encoding="utf-8", **kw):
        with self.assertRaises(DataError) as e:
            self.read(text, column, encoding, **kw)
        self.assertIn(part, str(e.exception))
        return str(e.exception)

    def assertCurve(self, curve, times, values, sigmas=None):
        t, v, s = curve
        self.assertEqual(len(t), len(times))
        for got, want in zip(t + v + (s or []), times + values + (sigmas or [])):
            self.assertAlmostEqual(got, want, delta=1e-12 * max(1.0, abs(want)))
        self.assertEqual(s is None, sigmas is None)

    def test_one_value_of_g(self):
        # The solver's 9.81 m/s² (src/observe/experiment.rs), not the standard 9.80665.
        self.assertEqual(units.G, 9.81)
        self.assertAlmostEqual(units.factor("uN"), 1 / 9.81, places=15)
        self.assertAlmostEqual(units.force("0.05uN"), 0.05 / 9.81, places=15)
        self.assertAlmostEqual(units.force("0.5 nN"), 0.5e-3 / 9.81, places=15)
        self.assertEqual(units.force("0.01"), 0.01)
        with self.assertRaises(ValueError):
            units.force("0.05um")

    def test_units_are_converted_to_the_models(self):
        c = self.read("# comment\ntime,force_uN,sigma_uN\n1,9.81,0.981\n2,19.62,0.981\n")
        self.assertCurve(c, [1.0, 2.0], [1.0, 2.0], [0.1, 0.1])
        self.assertCurve(self.read("time,force_nN\n0.5,9810\n"), [0.5], [1.0])
        self.assertCurve(self.read("time_s,value\n0.5,3.0\n", unit="uN"), [0.5], [3.0 / G])
        # The model's own column name, or `value`, in the model's unit (mg).
        self.assertCurve(self.read("t,force_total_mg\n0.5,3.0\n"), [0.5], [3.0])
        self.assertCurve(self.read("time,value\n0.5,3.0\n"), [0.5], [3.0])
        # Lengths to µm, stresses to kPa.
        self.assertCurve(self.read("time,height_mm\n1,0.2\n", "height"), [1.0], [200.0])
        self.assertCurve(self.read("time,stress_zz [Pa]\n1,-250\n", "stress_zz"), [1.0], [-0.25])

    def test_header_units_in_common_spellings(self):
        for name, value in [("force [uN]", 9.81), ("force (µN)", 9.81), ("force (μN)", 9.81), ("Force_uN", 9.81),
                            ("F/mN", 0.00981), ("force_nN", 9810.0), ("force [mg]", 1.0), ("Force (N)", 9.81e-6),
                            ("FORCE [UN]", 9.81), ("force {µN}", 9.81), ("force_total [uN]", 9.81),
                            ("Kraft [µN]", 9.81)]:
            c = self.read(f"time,{name}\n1,{value!r}\n")
            self.assertAlmostEqual(c[1][0], 1.0, delta=1e-12, msg=name)
            self.assertIn(f"value `{name}`", c.detected)
        for name, scale in [("time", 1), ("Time", 1), ("TIME [s]", 1), ("time_s", 1), ("t", 1), ("time_min", 60),
                            ("time [min]", 60), ("t (h)", 3600), ("Time (ms)", 1e-3), ("time_sec", 1),
                            ("time [minutes]", 60)]:
            c = self.read(f"{name},force_mg\n1.5,2\n")
            self.assertAlmostEqual(c[0][0], 1.5 * scale, delta=1e-12, msg=name)

    def test_excel_exports(self):
        # "CSV UTF-8": a byte-order mark and CRLF.
        c = self.read("\ufefftime,force_uN\r\n1,9.81\r\n2,19.62\r\n")
        self.assertCurve(c, [1.0, 2.0], [1.0, 2.0])
        self.assertIn("UTF-8 with a byte-order mark, CRLF line ends, separator comma, decimal point", c.detected)
        self.assertIn("value `force_uN` (a force) in µN (1 mg = 9.81 µN)", c.detected)
        # A European locale: semicolons and decimal commas, trailing separators, a blank row.
        c = self.read("time;force_uN;;\r\n0,5;9,81;;\r\n;;;\r\n1,5;19,62;;\r\n")
        self.assertCurve(c, [0.5, 1.5], [1.0, 2.0])
        self.assertIn("separator semicolon, decimal comma", c.detected)
        # An instrument's second header line of units.
        c = self.read("Time;Force;Phase\ns;µN;-\n0,5;9,81;ramp\n")
        self.assertCurve(c, [0.5], [1.0])
        self.assertIn("units from the line below the header", c.detected)
        self.assertIn("value `Force [µN]`", c.detected)
        # Excel's line naming the separator.
        self.assertCurve(self.read("sep=;\r\ntime;force_uN\r\n0,5;9,81\r\n"), [0.5], [1.0])
        # Semicolons with decimal points (also written by Excel in some locales).
        self.assertCurve(self.read("time;force_uN\n0.5;9.81\n"), [0.5], [1.0])
        # Tab-separated text with decimal commas, time in minutes, a column of words not read.
        c = self.read("Time [min]\tForce (µN)\tphase\n0,5\t9,81\tramp\n1\t19,62\thold\n")
        self.assertCurve(c, [30.0, 60.0], [1.0, 2.0])
        self.assertIn("separator tab, decimal comma", c.detected)
        self.assertIn("not read: `phase`", c.detected)
        # Quoted cells, spaces after the separator.
        self.assertCurve(self.read('"time", "force_uN"\n"1.5", "9.81"\n'), [1.5], [1.0])
        # The minus sign U+2212, as a document writes it.
        self.assertCurve(self.read("time,force_uN\n1,\u22129.81\n"), [1.0], [-1.0])
        # Old Mac line ends (CR only).
        c = self.read("time,force_uN\r1,9.81\r2,19.62\r")
        self.assertCurve(c, [1.0, 2.0], [1.0, 2.0])
        self.assertIn("CR line ends", c.detected)
        # UTF-16 with its byte-order mark ("Unicode text").
        c = self.read("time\tforce_uN\r\n1\t9.81\r\n".encode("utf-16"))
        self.assertCurve(c, [1.0], [1.0])
        self.assertIn("UTF-16", c.detected)

    def test_windows_1252_and_latin_1(self):
        # Excel on Windows writes µ as the single byte 0xB5: not UTF-8.
        c = self.read("time;force_µN\n1;9,81\n", encoding="cp1252")
        self.assertCurve(c, [1.0], [1.0])
        self.assertIn("Windows-1252 (not UTF-8)", c.detected)
        # A byte Windows-1252 leaves undefined (0x81): Latin-1.
        c = self.read(b"# \x81 instrument\ntime,force_\xb5N\n1,9.81\n")
        self.assertCurve(c, [1.0], [1.0])
        self.assertIn("Latin-1", c.detected)

    def test_a_published_file(self):
        # Guevorkian et al. 2010 (its header names the source): time in minutes, the tongue's
        # length in µm, a column of words.
        c = read_curve(DATA / "guevorkian2010_aspiration.csv", "height")
        t, v, s = c
        self.assertEqual(len(t), 43)
        self.assertAlmostEqual(t[0], 120.0, delta=1e-9)
        self.assertAlmostEqual(v[0], 29.0827, delta=1e-12)
        self.assertAlmostEqual(t[-1], 278.5833 * 60, delta=1e-9)
        self.assertAlmostEqual(v[-1], 59.9998, delta=1e-12)
        self.assertIsNone(s)
        self.assertIn("time `time_min` in min (x 60 to s); value `L_um`", c.detected)
        self.assertIn("not read: `phase`", c.detected)
        # Named explicitly; in mm it is converted.
        _, v, _ = read_curve(DATA / "guevorkian2010_aspiration.csv", "height", data_column="L_um")
        self.assertAlmostEqual(v[1], 37.61, delta=1e-12)
        self.assertCurve(self.read("time_min,L_mm\n2,0.029\n", "height"), [120.0], [29.0])

    def test_ambiguous_numbers_are_refused_with_the_fix(self):
        fix = "save the file with decimal points, or with `;` as the separator"
        self.refused('time,force_uN\n1,"1,5"\n', fix)
        self.refused("time,force_uN\n1,1,5\n", "a decimal comma? In a comma-separated file")
        self.refused("force_uN\n0,5\n", "the comma could be a separator or a decimal mark")
        self.refused("time;force_uN\n1;1.234,5\n", "a thousands separator? Numbers must be written without one")
        self.refused('time,force_uN\n1,"1,234.5"\n', "a thousands separator?")
        self.refused("time;force_uN\n1;1 234\n", "a thousands separator?")
        self.refused("time\tforce_uN\n1\t1,234,567\n", "a thousands separator?")
        self.refused("time;force_uN\n1;1,5\n2;2.5\n", "both decimal marks: `1,5` (line 2) and `2.5` (line 3)")
        self.refused("time force_uN\n1 2\n", "separated by spaces")
        self.refused("Aggregate 3, 2026-11-02\ntime;force_uN\n1;2\n", "`Aggregate 3, 2026-11-02` is not a header of "
                     "columns, but line 2 (`time;force_uN`) looks like one: make the lines above it comments")

    def test_units_that_do_not_fit_are_refused(self):
        self.refused("time,force\n1,2\n", "the column `force` has no unit: name it with one")
        self.refused("time,force [kg]\n1,2\n", "unknown unit `kg`")
        self.refused("time [uN],force_uN\n1,2\n", "is in µN, not a time")
        self.refused("time (days),force_uN\n1,2\n", "unknown unit `days`")
        self.refused("time,height_um\n1,2\n", "no data column")
        self.refused("time,force_uN\n1,2\n", "is a force (µN), but the model's `height` is a length", column="height",
                     data_column="force_uN")
        self.refused("time,force_uN\n1,2\n", "in µN, but the unit given (--data-unit) is mg", unit="mg")
        self.refused("time,value\n1,2\n", "unknown unit `um` (--data-unit)", unit="um")
        self.refused("time,force_upper_uN,force_lower_uN\n1,2,3\n", "2 force columns")
        self.refused("time,force_uN,sigma,sd\n1,2,3,4\n", "two sigma columns")
        self.refused("time,time_min,force_uN\n1,2,3\n", "two time columns")
        self.refused("time,force_total\n1,2\n", "no column `force_totl` (--data-column): the header has "
                     "['time', 'force_total'] (did you mean `force_total`?)", data_column="force_totl")

    def test_every_malformed_file_is_named_with_its_problem(self):
        self.refused("", "empty")
        self.refused("# only a comment\n\n", "empty")
        self.refused("1,2\n3,4\n", "no header line")
        self.refused("force_uN\n1\n", "no time column")
        self.refused("Tiem,force_uN\n1,2\n", "no time column: expected one named time or t (in s, or with its unit: "
                     "`time [min]`, `time_s`, `t (h)`); the header has ['Tiem', 'force_uN'] (did you mean `Tiem`?)")
        self.refused("time,height\n1,2\n", "no data column: expected `force_total_mg`, a force with its unit")
        # A model column typed wrong (a solver without `poroplast columns` leaves it to the reader).
        self.refused("time,force_uN\n1,2\n", "no data column: expected `force_total` or `value`, or one named by "
                     "--data-column; the header has ['time', 'force_uN'] (did you mean `force_uN`?); and `force_total` "
                     "is no column of the model's history: did you mean `force_total_mg`?", column="force_total")
        self.refused("time,force_uN\n1,abc\n", "line 2: `abc` in column `force_uN` is not a number")
        self.refused("time,force_uN\n1,#DIV/0!\n", "line 2: `#DIV/0!` in column `force_uN` is not a number")
        self.refused("time,force_uN\n1,1_000\n", "`1_000` in column `force_uN` is not a number")
        self.refused("time,force_uN,note\n1,,x\n", "line 2: the cell of column `force_uN` is empty")
        self.refused("time,force_uN\n1,nan\n", "finite number")
        self.refused("time,force_uN\n1,inf\n", "finite number")
        self.refused("time,force_uN\n2,1\n1,1\n", "line 3: time 1 s comes before")
        self.refused("time,force_uN\n1,1\n1,2\n", "line 3: time 1 s repeats")
        self.refused("time_min,force_uN\n2,1\n1,1\n", "line 3: time 1 min comes before the previous row's 2 min")
        self.refused("time,force_uN\n0,1\n", "t > 0")
        self.refused("time,force_uN\n1,1,3\n", "3 fields, the header has 2")
        self.refused("time;force_uN;note\n1;1\n", "2 fields, the header has 3")
        self.refused("time,force_uN\n", "no rows")
        self.refused("time,force_uN,sigma\n1,1,0\n", "sigma 0")
        self.refused("time,time,force_uN\n1,1,1\n", "appears twice")
        with self.assertRaises(DataError) as e:
            read_curve(Path(self.dir.name) / "missing.csv", "force_total_mg")
        self.assertIn("no such file", str(e.exception))
        with self.assertRaises(DataError) as e:
            read_curve(Path(self.dir.name), "force_total_mg")
        self.assertIn("a directory", str(e.exception))
        self.refused(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "not a text file")
        self.refused(b"PK\x03\x04\x14\x00\x06\x00", "an Excel workbook (or another zip or OLE file), not a text "
                     "table: save the sheet as CSV")
        self.refused("time,force_uN\n00:01:30,2\n", "line 2: `00:01:30` in column `time`: a clock time (h:mm:ss)?")

    def test_times_beyond_the_run_are_refused(self):
        check_within("d.csv", [1.0, 90.0], 90.0)
        with self.assertRaises(DataError) as e:
            check_within("d.csv", [1.0, 95.0, 99.0], 90.0)
        self.assertIn("2 data times after the run's end (t_end = 90 s), the first 95 s", str(e.exception))


if __name__ == "__main__":
    unittest.main()
