"""The experiments file and the parameters (shared, KEY@NAME), and the calibration's model of
several experiments: every experiment at every point one batch, each replaying its own steps,
the parameters applied where they belong (run_cases stubbed: no solver)."""
import math
import tempfile
import types
import unittest
from pathlib import Path
from unittest import mock

import numpy as np

from poroplast_tools import experiments as exps
from poroplast_tools import runmodel
from poroplast_tools.measured import read_curve

FILE = """
scene = "remodel_40"
column = "force_total_mg"
set = ["mesh.geometry=axisymmetric"]
noise = "relative+floor"
noise_floor = "0.098uN"

[[experiment]]
name = "a"
data = "a.csv"
set = ["mesh.params.R=150"]
t_max = 70

[[experiment]]
name = "b"
scene = "reference_axi"
noise = "absolute"
synthetic = { "material.mu" = 3 }
synthetic_noise = 0.02
"""


class ExperimentsFile(unittest.TestCase):
    def write(self, text):
        d = Path(tempfile.mkdtemp())
        (d / "e.toml").write_text(text)
        return d / "e.toml"

    def test_defaults_and_overrides(self):
        path = self.write(FILE)
        a, b = exps.read(path, {"set": ["time.dt=0.1"], "column": "stress_zz"})
        self.assertEqual((a.name, a.scene, a.column), ("a", "remodel_40", "force_total_mg"))
        self.assertEqual(a.sets, [("time.dt", "0.1"), ("mesh.geometry", "axisymmetric"), ("mesh.params.R", "150")])
        self.assertEqual(a.data, str(path.parent / "a.csv"))
        self.assertEqual((a.t_max, a.noise), (70.0, "relative+floor"))
        self.assertAlmostEqual(a.noise_floor, 0.098 / 9.81, delta=1e-15)      # in mg: 1 mg = 9.81 µN
        self.assertEqual((b.scene, b.noise, b.data, b.synthetic, b.synthetic_noise),
                         ("reference_axi", "absolute", None, {"material.mu": 3.0}, 0.02))
        # A floor without a noise model means relative+floor.
        [c] = exps.read(self.write("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'c'\ndata = 'x'\n"
                                   "noise_floor = 0.01"), {})
        self.assertEqual((c.noise, c.noise_floor), ("relative+floor", 0.01))

    def test_malformed_files_are_refused_with_the_reason(self):
        for text, part in [
            ("scene = 'x'", "no [[experiment]] table"),
            ("colour = 1\n[[experiment]]\nname = 'a'\ndata = 'a.csv'", "unknown key `colour` (did you mean `column`?)"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nt_mx = 3",
             "experiment 1: unknown key `t_mx` (did you mean `t_max`?)"),
            ("data = 'x'\n[[experiment]]\nname = 'a'", "`data` belongs in an [[experiment]]"),
            ("scene = 's'\n[[experiments]]\nname = 'a'", "no [[experiment]] table (did you mean `experiments`?)"),
            ("scene = 's'\n[experiment]\nname = 'a'", "`[experiment]` is one table: write each experiment as"),
            ("scene = 's'\ncolumn = 'c'\nset = 3\n[[experiment]]\nname = 'a'\ndata = 'x'",
             "`set = 3` is an integer: expected a string or a list of strings"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nset = ['a=1', 2]",
             "`set` entry 2 is an integer"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nset = 'time.t_end'",
             "`time.t_end` is not KEY=VALUE"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nt_max = '70'",
             "`t_max = '70'` is a string: expected a number"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nseed = 1.5",
             "`seed = 1.5` is a number: expected an integer"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\nsynthetic = { 'material.mu' = 'x' }",
             "synthetic `material.mu = 'x'` is a string: expected a number"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nnoise_floor = '0.05um'",
             "`um` is not a force unit"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\nt_min = 5\nt_max = 2",
             "t_min = 5 is not below t_max = 2"),
            ("scene = 's'\ncolumn = 'c'\nnoise = 'relativ'\n[[experiment]]\nname = 'a'\ndata = 'x'",
             "(did you mean `relative`?)"),
            ("[[experiment]]\nname = 'a'\ndata = 'a.csv'\ncolumn = 'c'", "no `scene`"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a b'\ndata = 'a.csv'", "a `name` of letters"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'", "either `data`"),
            ("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\n[[experiment]]\nname = 'a'\n"
             "data = 'y'", "the name `a` is taken"),
            ("scene = 's'\ncolumn = 'c'\nnoise = 'poisson'\n[[experiment]]\nname = 'a'\ndata = 'x'", "poisson"),
            ("scene = [", "not TOML"),
        ]:
            with self.assertRaises(exps.ExperimentError) as e:
                exps.read(self.write(text), {})
            self.assertIn(part, str(e.exception))

    def test_set_is_one_override_or_a_list(self):
        # `set = "time.t_end=2"` is one override (not read character by character); a list too;
        # the command line's --set first, then the file's, then the experiment's.
        [a] = exps.read(self.write("scene = 's'\ncolumn = 'c'\nset = 'mesh.params.R=150'\n[[experiment]]\n"
                                   "name = 'a'\ndata = 'x'\nset = \"time.t_end=2\"\n"), {"set": ["time.dt=0.1"]})
        self.assertEqual(a.sets, [("time.dt", "0.1"), ("mesh.params.R", "150"), ("time.t_end", "2")])
        [a] = exps.read(self.write("scene = 's'\ncolumn = 'c'\n[[experiment]]\nname = 'a'\ndata = 'x'\n"
                                   "set = ['time.t_end = 2', \"plates.table=[[0.0, 0.0], [5.0, 0.15]]\"]\n"), {})
        self.assertEqual(a.sets, [("time.t_end", "2"), ("plates.table", "[[0.0, 0.0], [5.0, 0.15]]")])

    def test_parameters_shared_and_per_experiment(self):
        es = exps.read(self.write(FILE), {})
        ps = exps.params(["material.remodelling.lambda_p=0.001", "material.mu@a=2.5"], es)
        self.assertEqual([p.label for p in ps], ["material.remodelling.lambda_p", "material.mu@a"])
        self.assertEqual([[p.applies(e) for e in es] for p in ps], [[True, True], [True, False]])
        for items, part in [(["material.mu@c=1"], "no experiment `c`"), (["material.mu=-1"], "positive"),
                            (["material.mu=1", "material.mu@a=2"], "given twice"), (["material.mu"], "KEY=START"),
                            (["material.mu=x"], "not a number")]:
            with self.assertRaises(exps.ExperimentError) as e:
                exps.params(items, es)
            self.assertIn(part, str(e.exception))

    def test_a_start_at_zero_or_outside_the_scenes_range_is_refused_with_the_reason(self):
        es = exps.read(self.write(FILE), {})
        for item, part in [("surface.tension=0", "builds no surface term"),
                           ("material.remodelling.sigma_y=0", "liquid limit"),
                           ("surface.tension=0.005", "below 0.01 mN/m"),
                           ("surface.tension=5000", "above 1000 mN/m"),
                           ("surface.tension@a=0.001", "below 0.01 mN/m")]:
            with self.assertRaises(exps.ExperimentError) as e:
                exps.params([item], es)
            self.assertIn(part, str(e.exception))
        self.assertEqual(exps.params(["surface.tension=0.01"], es)[0].start, 0.01)
        self.assertIsNone(exps.outside("material.mu", 1e-9))


class OneBatch(unittest.TestCase):
    """runmodel.Runs over two experiments: one run_cases call per evaluate()."""

    def test_every_experiment_at_every_point_is_one_batch(self):
        es = [exps.Experiment("a", "s1", "f", sets=[("R", "150")]), exps.Experiment("b", "s2", "f")]
        ps = exps.params(["lp=0.002", "mu@b=3"], es)
        runs = runmodel.Runs(tempfile.mkdtemp(), es, ps, [("time.dt", "0.1")], ranks=2, sweep=True)
        runs.data = [([1.0, 2.0], np.array([0.0, 0.0])), ([1.5], np.array([1.0]))]
        runs.checked = True
        calls = []

        def run_cases(scenes, cases, sets, root, ranks, counts=None):
            calls.append((scenes, cases, sets))
            return [(Path(f"/run{i}"), {"status": "ok"}) for i in range(len(cases))]

        # Each run's history: the value equals the run's index + time (so the differences tell
        # which run and which data time they come from).
        def history(d):
            i = int(str(d)[4:])
            return {"time": np.array([0.0, 1.0, 2.0]), "f": np.array([i, i + 1.0, i + 2.0])}

        replay = {"x": np.log([0.001, 3.0]),
                  "histories": [{"time": np.array([0.0, 0.5, 2.0])}, {"time": np.array([0.0, 1.5, 2.0])}]}
        x = [np.log([0.002, 3.0]), np.log([0.004, 6.0])]
        with mock.patch.object(runmodel, "run_cases", run_cases), mock.patch.object(runmodel, "history", history), \
                mock.patch("builtins.print"):
            out = runs.evaluate(x, ["p", "q"], replay)
        [(scenes, cases, sets)] = calls
        self.assertEqual(scenes, ["s1", "s2", "s1", "s2"])
        self.assertEqual(sets, [("time.dt", "0.1")])
        self.assertEqual(cases[0], [("R", "150"), ("lp", repr(math.exp(math.log(0.002)))), ("time.steps", "[0.5,2.0]")])
        self.assertEqual(cases[1], [("lp", repr(math.exp(math.log(0.002)))), ("mu", repr(math.exp(math.log(3.0)))),
                                    ("time.steps", "[1.5,2.0]")])
        self.assertEqual(cases[2][1], ("lp", repr(math.exp(math.log(0.004)))))
        # Point p: runs 0 (a: values 1, 2 at t = 1, 2) and 1 (b: 1 + 1.5 − 1 at t = 1.5); q: 2, 3.
        np.testing.assert_allclose(out[0][0], [1.0, 2.0, 1.5])
        np.testing.assert_allclose(out[1][0], [3.0, 4.0, 3.5])
        self.assertEqual(len(out[1][1]["histories"]), 2)
        np.testing.assert_array_equal(out[1][1]["x"], x[1])

        # A neighbour that moves only b's own µ: a is not run again, its history is replay's.
        calls.clear()
        replay = {"x": x[0], "histories": [history(Path("/run7")), history(Path("/run8"))]}
        with mock.patch.object(runmodel, "run_cases", run_cases), mock.patch.object(runmodel, "history", history), \
                mock.patch("builtins.print"):
            [(d, state)] = runs.evaluate([x[0] + [0.0, 1e-3]], ["d mu@b"], replay)
        [(scenes, cases, _)] = calls
        self.assertEqual(scenes, ["s2"])
        self.assertIs(state["histories"][0], replay["histories"][0])
        np.testing.assert_allclose(d, [8.0, 9.0, 0.5])      # a: run 7 at t = 1, 2; b: the new run 0

    def test_a_point_outside_the_scenes_range_is_not_run(self):
        # γ below 0.01 mN/m (the scene would refuse it as a unit mistake): that point is None, a
        # failed step, and only the other point's runs are in the batch.
        es = [exps.Experiment("a", "s1", "f")]
        ps = exps.params(["surface.tension=5", "lp=0.002"], es)
        runs = runmodel.Runs(tempfile.mkdtemp(), es, ps, [], ranks=1, sweep=True)
        runs.data = [([1.0], np.array([0.0]))]
        runs.checked = True
        calls, said = [], []

        def run_cases(scenes, cases, sets, root, ranks, counts=None):
            calls.append(cases)
            return [(Path(f"/run{i}"), {"status": "ok"}) for i in range(len(cases))]

        def history(d):
            return {"time": np.array([0.0, 2.0]), "f": np.array([0.0, 2.0])}

        with mock.patch.object(runmodel, "run_cases", run_cases), mock.patch.object(runmodel, "history", history), \
                mock.patch("builtins.print", lambda *a, **k: said.append(" ".join(map(str, a)))):
            out = runs.evaluate([np.log([0.004, 0.002]), np.log([4.0, 0.002])], ["low", "fine"])
        self.assertIsNone(out[0])
        np.testing.assert_allclose(out[1][0], [1.0])
        [cases] = calls
        self.assertEqual(len(cases), 1)
        self.assertEqual(cases[0][0], ("surface.tension", repr(math.exp(math.log(4.0)))))
        self.assertTrue(any(line.startswith("low: ") and "not run, surface.tension = 0.004 is below 0.01 mN/m" in line
                            for line in said), said)


class Synthetic(unittest.TestCase):
    """runmodel.synthesise: the noisy curve it fits to is the file it writes, in the lab format."""

    def test_the_written_curve_reads_back_as_data(self):
        study = Path(tempfile.mkdtemp())
        e = exps.Experiment("s", "scene", "force_total_mg", synthetic={"material.mu": 2.5}, synthetic_noise=0.02,
                            synthetic_floor=0.005, synthetic_every=1.0, seed=4)
        h = {"time": np.array([0.0, 0.5, 1.5, 3.0]), "force_total_mg": np.array([0.0, 1.0, 3.0, 6.0])}
        runs = types.SimpleNamespace(study=study, histories=lambda cases, what: [h])
        with mock.patch("builtins.print"):
            [(ts, ys)] = runmodel.synthesise(runs, [e]).values()
        self.assertEqual(list(ts), [1.0, 2.0, 3.0])
        # Noise of 2% of 2, 4, 6 mg: within 5 sigma of the model's values.
        for y, exact in zip(ys, [2.0, 4.0, 6.0]):
            self.assertLess(abs(y - exact), 5 * math.hypot(0.02 * exact, 0.005))
        self.assertNotEqual(list(ys), [2.0, 4.0, 6.0])
        t, v, s = read_curve(study / "synthetic_s.csv", "force_total_mg")
        self.assertEqual((list(t), list(v), s), (list(ts), list(ys), None))


if __name__ == "__main__":
    unittest.main()
