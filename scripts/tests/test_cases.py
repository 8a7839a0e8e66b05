"""What the scripts hand the sweep and read back: the study file, the summary rows, the levels;
and a case found again in its store by the binary's identity of it (a real run: POROPLAST_BIN)."""
import contextlib
import io
import math
import subprocess
import tempfile
import tomllib
import unittest
from pathlib import Path

from poroplast_tools import cases
from poroplast_tools.cases import _result, find_case, run_cases, study_text
from poroplast_tools.levels import grid_cases, parse_grid, refined_steps
from poroplast_tools.tables import pareto


class Cases(unittest.TestCase):
    def test_the_study_file_of_a_batch(self):
        text = study_text(["reference_axi", "cryer"], [[("material.mu", "10")], []], [("time.t_end", 3)],
                          ["-snes_rtol", "1e-9"], ["max:force_total_mg", "p_center@1"])
        s = tomllib.loads(text)
        self.assertEqual(s["set"], ["time.t_end=3"])
        self.assertEqual(s["petsc"], ["-snes_rtol", "1e-9"])
        self.assertEqual(s["observe"], ["max:force_total_mg", "p_center@1"])
        self.assertEqual(s["case"], [{"scene": "reference_axi", "set": ["material.mu=10"]},
                                     {"scene": "cryer", "set": []}])
        self.assertNotIn("observe", tomllib.loads(study_text(["x"], [[]], [])))   # the sweep's default list

    def test_a_summary_row_as_a_result(self):
        row = {"case": "0", "material.mu": "10", "status": "ok", "wall_s": "2.5", "steps": "12",
               "max:f": "", "f@1": "3.25", "error": "", "dir": "/s/cases/x-0123"}
        run, r = _result(row)
        self.assertEqual(run, Path("/s/cases/x-0123"))
        self.assertEqual((r["status"], r["wall_s"], r["steps"], r["f@1"]), ("ok", 2.5, 12.0, 3.25))
        self.assertTrue(math.isnan(r["max:f"]))
        self.assertNotIn("material.mu", r)

    def test_grids_and_step_levels(self):
        axes = [parse_grid("a=1,2"), parse_grid("b,c=3:4,5:6")]
        self.assertEqual(grid_cases(axes), [[("a", "1"), ("b", "3"), ("c", "4")], [("a", "1"), ("b", "5"), ("c", "6")],
                                            [("a", "2"), ("b", "3"), ("c", "4")], [("a", "2"), ("b", "5"), ("c", "6")]])
        steps = dict(refined_steps({"dt": 0.1, "growth": 1.21, "dt_max": 1.0}, {"time.dt_max": "2"}, 0.5))
        self.assertEqual(steps["time.dt"], 0.05)
        self.assertEqual(steps["time.dt_max"], 1.0)
        self.assertAlmostEqual(steps["time.growth"], 1.1, delta=1e-12)

    def test_pareto_front(self):
        pts = [dict(wall_s=w, error=e) for w, e in [(1, 0.1), (2, 0.2), (3, 0.01), (4, 0.05), (5, 0.001)]]
        self.assertEqual([(p["wall_s"], p["error"]) for p in pareto(pts)], [(1, 0.1), (3, 0.01), (5, 0.001)])


if __name__ == "__main__":
    unittest.main()


class FindCase(unittest.TestCase):
    def test_a_case_run_on_an_edited_scene_is_not_found(self):
        # A tiny Terzaghi case (4 steps) of a scene file, run as the scripts run cases.
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        d = Path(tmp.name)
        text = subprocess.run([str(cases.BIN), "show", "terzaghi"], check=True, capture_output=True,
                              text=True).stdout
        scene = d / "column.toml"
        scene.write_text(text)
        sets, case = [("time.t_end", "0.004")], [("material.mu", "12")]
        with contextlib.redirect_stdout(io.StringIO()):
            [(run, result)] = run_cases(str(scene), [case], sets, d, 1)
        self.assertEqual(result["status"], "ok")
        self.assertEqual(find_case(d, scene, case, sets), run)
        # Another override, the overrides in another order, other PETSc options: other cases.
        self.assertIsNone(find_case(d, scene, [("material.mu", "13")], sets))
        self.assertIsNone(find_case(d, scene, sets, case))
        self.assertIsNone(find_case(d, scene, case, sets, ["-ksp_rtol", "1e-9"]))
        # The same file with the same overrides, but edited (ν, which no override sets): another
        # case, whose results the store does not have.
        self.assertIn("nu = 0.2\n", text)
        scene.write_text(text.replace("nu = 0.2\n", "nu = 0.3\n"))
        self.assertIsNone(find_case(d, scene, case, sets))
        scene.write_text(text)
        self.assertEqual(find_case(d, scene, case, sets), run)
        # A store that does not exist holds no case; a key the scene has not is the solver's error.
        self.assertIsNone(find_case(d / "elsewhere", scene, case, sets))
        with self.assertRaises(cases.SceneError) as e:
            find_case(d, scene, [("material.muu", "12")], sets)
        self.assertIn("unknown field `muu`", str(e.exception))

