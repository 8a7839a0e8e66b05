"""Every name of a calibration checked before any run is launched: the column to fit, the scene's
keys (--set, set entries, --param, synthetic values) through `poroplast columns`, the data
file's columns, the experiments file's keys. A fake POROPLAST_BIN stands in for the solver: its
`columns` prints a plate scene's history columns (or the solver's refusal of an unknown key),
and any other subcommand (a run, a sweep) leaves a mark, so a test can tell that nothing ran."""
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path
from unittest import mock

from poroplast_tools import cases
from poroplast_tools import experiments as exps
from poroplast_tools import runmodel
from poroplast_tools.fit import FitError

SCRIPTS = Path(__file__).resolve().parents[1]
COLUMNS = ["step", "time", "dt", "plate_disp", "force_total_mg", "force_constitutive_mg", "force_pressure_mg",
           "force_lower_mg", "height", "width", "newton_its", "ksp_its", "wall_s"]
# A stand-in for the solver: `columns SCENE [--set K=V ...]` as the real one answers (an unknown
# key refused on stderr, exit 1); anything else marks RAN and fails.
FAKE = f"""#!{sys.executable}
import os, sys
args = sys.argv[1:]
log = os.environ["FAKE_LOG"]
with open(log, "a") as f:
    f.write(" ".join(args) + "\\n")
if args[:1] != ["columns"]:
    open(log + ".ran", "w").write(" ".join(args))
    sys.exit("poroplast: error: the fake binary runs nothing")
sets = [args[i + 1] for i, a in enumerate(args) if a == "--set"]
for s in sets:
    key = s.split("=", 1)[0]
    if key.endswith("tensoin"):
        sys.exit(f"poroplast: error: --set {{s}}: unknown field `tensoin`, expected one of `tension`, `group`")
    if key == "material.mu" and float(s.split("=", 1)[1]) > 1e4:
        sys.exit(f"poroplast: error: material.mu = {{s.split('=', 1)[1]}} kPa is implausible (Pa meant?)")
print("\\n".join({COLUMNS!r}))
"""
OLD = f"""#!{sys.executable}
import sys
sys.stderr.write("error: unrecognized subcommand 'columns'\\n\\nUsage: poroplast <COMMAND>\\n")
sys.exit(2)
"""


class Fake:
    """A fake solver in a temporary directory: `bin`, the calls it got (`calls`), whether
    anything but `columns` was asked of it (`ran`)."""

    def __init__(self, text=FAKE):
        self.dir = Path(tempfile.mkdtemp())
        self.bin = self.dir / "poroplast"
        self.bin.write_text(text)
        self.bin.chmod(0o755)
        self.log = self.dir / "calls.log"
        self.log.write_text("")

    @property
    def calls(self):
        return self.log.read_text().splitlines()

    @property
    def ran(self):
        return Path(str(self.log) + ".ran").exists()

    def env(self):
        return {**os.environ, "POROPLAST_BIN": str(self.bin), "FAKE_LOG": str(self.log)}


class CheckNames(unittest.TestCase):
    def setUp(self):
        self.fake = Fake()
        patches = [mock.patch.object(cases, "BIN", self.fake.bin), mock.patch.dict(os.environ, FAKE_LOG=str(self.fake.log))]
        for p in patches:
            p.start()
            self.addCleanup(p.stop)

    def test_one_call_per_experiment_with_every_override_and_start(self):
        es = [exps.Experiment("a", "remodel_40", "force_total_mg", sets=[("mesh.params.R", "150")]),
              exps.Experiment("b", "remodel_40", "height", synthetic={"material.mu": 3.0})]
        ps = exps.params(["material.remodelling.lambda_p=0.002", "material.mu@a=2.5"], es)
        runmodel.check_names(es, ps, [("mesh.geometry", "axisymmetric")])
        self.assertEqual(self.fake.calls, [
            "columns remodel_40 --set mesh.geometry=axisymmetric --set mesh.params.R=150 "
            "--set material.remodelling.lambda_p=0.002 --set material.mu=2.5",
            "columns remodel_40 --set mesh.geometry=axisymmetric --set material.mu=3.0 "
            "--set material.remodelling.lambda_p=0.002"])
        self.assertFalse(self.fake.ran)

    def test_a_column_typo_is_refused_with_the_nearest(self):
        es = [exps.Experiment("my_aggregate", "my_aggregate.toml", "force_total")]
        with self.assertRaises(FitError) as e:
            runmodel.check_names(es, exps.params(["material.mu=2"], es))
        msg = str(e.exception)
        self.assertIn("`force_total` (the column to fit, --column) is not a column of the history of "
                      "my_aggregate.toml (did you mean `force_total_mg`?); its columns: time, plate_disp, "
                      "force_total_mg", msg)

    def test_the_solvers_refusal_of_a_key_or_value_is_passed_on(self):
        es = [exps.Experiment("a", "tst_hold", "force_total_mg")]
        with self.assertRaises(FitError) as e:
            runmodel.check_names(es, exps.params(["surface.tensoin=5"], es))
        self.assertIn("experiment `a` (tst_hold with surface.tensoin=5.0): --set surface.tensoin=5.0: unknown field "
                      "`tensoin`, expected one of `tension`", str(e.exception))
        with self.assertRaises(FitError) as e:
            runmodel.check_names(es, exps.params(["material.mu=28800"], es))
        self.assertIn("material.mu = 28800.0 kPa is implausible (Pa meant?)", str(e.exception))

    def test_a_binary_without_columns_is_said_and_the_first_run_checks(self):
        old = Fake(OLD)
        said = []
        with mock.patch.object(cases, "BIN", old.bin):
            runmodel.check_names([exps.Experiment("a", "s", "force_total")], [], say=said.append)
        self.assertEqual(len(said), 1)
        self.assertIn("has no `columns` subcommand", said[0])
        # Then the first run's history refuses the column (not 20 runs at NaN).
        runs = runmodel.Runs(tempfile.mkdtemp(), [exps.Experiment("a", "s", "force_total")], [])
        runs.data = [([1.0], None)]
        import numpy as np
        with self.assertRaises(FitError) as e:
            runs.check([{"time": np.array([0.0, 2.0]), "force_total_mg": np.array([0.0, 1.0])}])
        self.assertIn("(did you mean `force_total_mg`?)", str(e.exception))


class CalibrateRefuses(unittest.TestCase):
    """calibrate.py as a user runs it: each mistake refused in one line, exit 1, before anything
    runs, no traceback, and the study directory not created."""

    def calibrate(self, *args, fake=None):
        fake = fake or Fake()
        d = Path(tempfile.mkdtemp())
        data = d / "data.csv"
        data.write_text("time,force_uN\n1,9.81\n2,19.62\n3,29.43\n")
        argv = [a.replace("DATA", str(data)) for a in args]
        p = subprocess.run([sys.executable, str(SCRIPTS / "calibrate.py"), *argv, "--dir", str(d / "fit")],
                           capture_output=True, text=True, env=fake.env(), cwd=d)
        return p, fake, d

    def refused(self, part, *args):
        p, fake, d = self.calibrate(*args)
        out = p.stdout + p.stderr
        self.assertIn(p.returncode, (1, 2), out)          # 2: argparse's usage error
        self.assertNotIn("Traceback", out)
        self.assertIn(part, out)
        self.assertFalse(fake.ran, f"a run was launched:\n{out}")
        self.assertFalse((d / "fit").exists())
        return out

    def test_a_column_typo(self):
        out = self.refused("is not a column of the history of remodel_40 (did you mean `force_total_mg`?)",
                           "remodel_40", "--data", "DATA", "--column", "force_total", "--param", "material.mu=2")
        self.assertTrue(out.startswith("calibrate.py: `force_total` (the column to fit, --column)"), out)

    def test_a_key_typo_in_param_and_set(self):
        self.refused("unknown field `tensoin`", "tst_hold", "--data", "DATA", "--column", "force_total_mg",
                     "--param", "surface.tensoin=5")
        self.refused("unknown field `tensoin`", "tst_hold", "--data", "DATA", "--column", "force_total_mg",
                     "--param", "material.mu=2", "--set", "surface.tensoin=5")
        self.refused("`surface.tension` is not KEY=VALUE", "tst_hold", "--data", "DATA", "--column",
                     "force_total_mg", "--param", "material.mu=2", "--set", "surface.tension")

    def test_the_data_files_columns_and_units(self):
        p, fake, d = self.calibrate("remodel_40", "--data", "DATA", "--column", "force_total_mg", "--param",
                                    "material.mu=2", "--data-column", "forse_uN")
        self.assertIn("no column `forse_uN` (--data-column): the header has ['time', 'force_uN'] (did you mean "
                      "`force_uN`?)", p.stdout + p.stderr)
        self.assertFalse(fake.ran)
        self.refused("unknown unit `kg` (--data-unit)", "remodel_40", "--data", "DATA", "--column", "force_total_mg",
                     "--param", "material.mu=2", "--data-unit", "kg")
        self.refused("noise floor `0.05um`: `um` is not a force unit", "remodel_40", "--data", "DATA", "--column", "force_total_mg",
                     "--param", "material.mu=2", "--noise-floor", "0.05um")
        self.refused("--synthetic `material.mu=x`: `x` is not a number", "remodel_40", "--synthetic",
                     "material.mu=x", "--column", "force_total_mg", "--param", "material.mu=2")

    def test_an_experiments_file(self):
        fake = Fake()
        d = Path(tempfile.mkdtemp())
        (d / "a.csv").write_text("time;force (µN)\n1;9,81\n2;19,62\n3;29,43\n")
        (d / "e.toml").write_text('scene = "remodel_40"\ncolumn = "force_total_mg"\nset = "time.t_end=2"\n'
                                  '[[experiment]]\nname = "a"\ndata = "a.csv"\nset = "surface.tensoin=3"\n')
        p = subprocess.run([sys.executable, str(SCRIPTS / "calibrate.py"), "--experiments", str(d / "e.toml"),
                            "--param", "material.mu=2", "--dir", str(d / "fit")], capture_output=True, text=True,
                           env=fake.env())
        self.assertEqual(p.returncode, 1)
        self.assertIn("experiment `a` (remodel_40 with time.t_end=2 surface.tensoin=3 material.mu=2.0): --set "
                      "surface.tensoin=3: unknown field `tensoin`", p.stderr)
        self.assertFalse(fake.ran)
        self.assertEqual(len(fake.calls), 1)


if __name__ == "__main__":
    unittest.main()
