"""Mesh levels of a convergence study scale the sizes a run with the study's overrides would
mesh with, as the binary resolves them (`poroplast show --explain`: these tests ask the real one,
POROPLAST_BIN): a size in µm (the scene's mesh.params or a --set one) wins over the scene's
mesh.relative_sizes, and the sizes are scaled from the h the same overrides give. A failed level
is named with its mesh when the mesh is the likely cause."""

import functools
import subprocess
import tempfile
import unittest
from pathlib import Path

from poroplast_tools import cases
from poroplast_tools.convergence import cross, failure_cause, failure_stage
from poroplast_tools.levels import base_sizes, describe_sizes, h_levels


@functools.lru_cache(maxsize=None)
def shipped(name, edits):
    """A shipped scene's text with lines replaced (each `from` must be there)."""
    text = subprocess.run([str(cases.BIN), "show", name], check=True, capture_output=True, text=True).stdout
    for old, new in edits:
        assert old in text, f"{name} has no `{old}`"
        text = text.replace(old, new, 1)
    return text


# The tensiometry hold on its meridian with R = 220 µm and every size relative to R.
TST_SIZES = "relative_sizes = { h = 0.15, h_pole = 0.025, r_pole = 0.5, h_surf = 0.025, w_surf = 0.2 }"
RELATIVE_SIZES = "relative_sizes = { h = 0.2, h_pole = 0.03, r_pole = 0.5, h_surf = 0.025, w_surf = 0.2 }"


def relative():
    return shipped("tst_hold", (("params = { R = 100.0 }", "params = { R = 220.0 }"), (TST_SIZES, RELATIVE_SIZES)))


def absolute():
    return shipped("tst_hold", (("params = { R = 100.0 }", "params = { R = 220.0, h = 30.0, h_pole = 6.0 }"),
                                (TST_SIZES, "")))


class Levels(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def scene(self, text):
        p = Path(self.dir.name) / "scene.toml"
        p.write_text(text)
        return str(p)

    def level(self, text, h, sets=()):
        return {k: float(v) for k, v in h_levels(self.scene(text), [h], sets)[0]}

    def test_absolute_sets_win_over_relative_sizes_and_scale_from_the_set_h(self):
        # The new-user trial's T6: h = 10, h_pole = h_surf = 2 µm by --set on a scene whose
        # relative h is 0.2 × 220 = 44 µm. At h = 14.1 the poles are 2 × 14.1/10 = 2.82 µm (not
        # 2 × 14.1/44 = 0.641 µm).
        sets = ["mesh.params.h=10", "mesh.params.h_pole=2", "mesh.params.h_surf=2", "mesh.params.w_surf=30"]
        lv = self.level(relative(), 14.1, sets)
        self.assertEqual(lv["mesh.params.h"], 14.1)
        self.assertAlmostEqual(lv["mesh.params.h_pole"], 2.82, places=6)
        self.assertAlmostEqual(lv["mesh.params.h_surf"], 2.82, places=6)
        self.assertNotIn("mesh.params.w_surf", lv)   # a depth, not a size: the run's as given
        sizes = base_sizes(self.scene(relative()), sets)
        self.assertEqual(sizes["h"], (10.0, "--set mesh.params.h"))
        self.assertEqual(sizes["h_pole"], (2.0, "--set mesh.params.h_pole"))

    def test_an_absolute_set_size_without_h_scales_from_the_scenes_relative_h(self):
        # h_pole = 4.4 µm set at the scene's h = 44 µm: a tenth of h on every level.
        lv = self.level(relative(), 22, ["mesh.params.h_pole=4.4"])
        self.assertAlmostEqual(lv["mesh.params.h_pole"], 2.2, places=9)
        self.assertAlmostEqual(lv["mesh.params.h_surf"], 0.025 * 220 * 22 / 44, places=9)

    def test_relative_only_sizes_are_scaled_in_micrometres(self):
        lv = self.level(relative(), 22)
        self.assertAlmostEqual(lv["mesh.params.h_pole"], 0.03 * 220 / 2, places=9)
        self.assertAlmostEqual(lv["mesh.params.h_surf"], 0.025 * 220 / 2, places=9)
        sizes = base_sizes(self.scene(relative()))
        self.assertAlmostEqual(sizes["h"][0], 44.0, places=9)
        self.assertEqual(sizes["h"][1], "resolved from the scene")

    def test_relative_sizes_set_on_the_command_line_are_used(self):
        # A whole relative_sizes table by --set replaces the scene's (as a run does).
        lv = self.level(relative(), 15, ["mesh.relative_sizes={ h = 0.15, h_pole = 0.02, r_pole = 0.5 }"])
        self.assertAlmostEqual(lv["mesh.params.h_pole"], 0.02 * 220 * 15 / 33, places=9)
        self.assertNotIn("mesh.params.h_surf", lv)
        # A set radius moves the relative sizes.
        lv = self.level(relative(), 20, ["mesh.params.R=100"])
        self.assertAlmostEqual(lv["mesh.params.h_pole"], 3.0, places=9)

    def test_absolute_only_sizes(self):
        lv = self.level(absolute(), 15)
        self.assertEqual((lv["mesh.params.h"], lv["mesh.params.h_pole"]), (15.0, 3.0))
        self.assertEqual(self.level(absolute(), 15, ["mesh.params.h=60"])["mesh.params.h_pole"], 1.5)
        self.assertEqual(base_sizes(self.scene(absolute()))["h_pole"], (6.0, "resolved from the scene"))

    def test_the_log_names_each_levels_sizes(self):
        lines = describe_sizes(self.scene(relative()), [14.1, 10], ["mesh.params.h=10", "mesh.params.h_pole=2"])
        text = "\n".join(lines)
        self.assertIn("h_pole = 2 µm (--set mesh.params.h_pole)", text)
        self.assertIn("h_surf = 5.5 µm (resolved from the scene and the --set values)", text)
        self.assertIn("level h = 14.1: h = 14.1, h_pole = 2.82, h_surf = 7.755", text)

    def test_the_level_sizes_replace_the_set_ones_in_every_case(self):
        sets = ["mesh.params.h=10", "mesh.params.h_pole=2", "fem.stabilisation=0"]
        cases, fixed = cross(self.scene(relative()), [14.1, 10, 7.07], [1, 0.5, 0.25], sets, 10, 0.25)
        self.assertEqual(fixed, [("fem.stabilisation", "0")])
        self.assertEqual(len(cases), 5)
        self.assertIn(("mesh.params.h_pole", "2.82"), cases[0][2])

    def test_a_scene_without_h_is_refused_with_the_fix(self):
        with self.assertRaises(SystemExit) as e:
            h_levels(self.scene(relative().replace(RELATIVE_SIZES, RELATIVE_SIZES.replace("h = 0.2, ", ""))), [10])
        self.assertIn("give one, e.g. --set mesh.params.h=20", str(e.exception))

    def test_shipped_scenes(self):
        # The shipped reference: R = 100 µm, h = 0.2 R, h_pole = 0.03 R; and a scene in µm.
        self.assertAlmostEqual(float(dict(h_levels("reference", [10.0])[0])["mesh.params.h_pole"]), 1.5)
        self.assertEqual(dict(h_levels("terzaghi", [10.0])[0]), {"mesh.params.h": "10"})
        # mesh.grading = "auto": the chart's sizes (h = 0.2 R, h_pole = 0.03 R), scaled as given ones.
        self.assertEqual(dict(h_levels("reference", [10.0], ["mesh.grading=auto"])[0]),
                         {"mesh.params.h": "10", "mesh.params.h_pole": "1.5"})

    def test_the_levels_are_the_sizes_the_binary_meshes_with(self):
        # tst_hold's file: R = 100 µm, h = 0.15 R, h_pole = h_surf = 0.025 R (r_pole = 0.5 R and
        # w_surf = 0.2 R are distances, not sizes). At h = 10 and 5 µm the poles and the surface
        # are h/6: 1.66667 and 0.833333 µm. Each level's overrides, given to the binary, resolve to
        # exactly those sizes with the rest of the scene's mesh as it was.
        self.assertEqual(base_sizes("tst_hold"), {k: (v, "resolved from the scene")
                                                  for k, v in [("h", 15.0), ("h_pole", 2.5), ("h_surf", 2.5)]})
        for h, pole, level in zip([10, 5], [1.66667, 0.833333], h_levels("tst_hold", [10, 5])):
            self.assertEqual(level, [("mesh.params.h", f"{h}"), ("mesh.params.h_pole", f"{pole}"),
                                     ("mesh.params.h_surf", f"{pole}")])
            params = cases.resolved_scene("tst_hold", level)["mesh"]["params"]
            self.assertEqual(params, {"R": 100.0, "h": h, "h_pole": pole, "h_surf": pole, "r_pole": 50.0,
                                      "w_surf": 20.0})

    def test_a_value_the_binary_refuses_is_its_message(self):
        with self.assertRaises(SystemExit) as e:
            h_levels("tst_hold", [10], ["mesh.params.h=-3"])
        self.assertIn("mesh levels of tst_hold: ", str(e.exception))
        self.assertIn("a length must be positive", str(e.exception))


SETTLING = ("no convergence: settling under gravity (the static equilibrium on the lower plate, before t = 0; 1 of "
            "the weight) failed: J <= phi_s. Can the solid carry its weight (material.mu, material.gravity)?")


class FailedLevels(unittest.TestCase):
    def case(self, h, pole):
        return (h, 0.25, [("mesh.params.h", f"{h:g}"), ("mesh.params.h_pole", f"{pole:g}")])

    def test_a_level_failing_while_settling_is_blamed_on_its_mesh(self):
        completed = [self.case(10, 2)[2], self.case(7.07, 1.414)[2]]
        m = failure_cause(self.case(14.1, 0.640909), SETTLING, completed)
        self.assertTrue(m.startswith("level h = 14.1, steps × 0.25 failed while settling under gravity "
                                     "(before t = 0). Likely cause: its mesh, not the material"), m)
        self.assertIn("h = 14.1, h_pole = 0.640909 µm", m)
        self.assertIn("0.640909 µm, is 2.2× finer than that of any level that completed (1.414 µm)", m)
        self.assertIn("crushed by the weight", m)
        self.assertIn("The run said: " + SETTLING, m)

    def test_a_much_finer_level_failing_later_is_blamed_on_its_mesh(self):
        err = "no convergence: failed solves cut the step from t = 3.2 to 1.0e-09 s, below time.dt_min"
        m = failure_cause(self.case(5, 0.3), err, [self.case(20, 4)[2], self.case(10, 2)[2]])
        self.assertIn("failed at t = 3.2 s. Likely cause: its mesh", m)
        self.assertIn("6.7× finer", m)

    def test_a_level_like_the_others_failing_later_passes_the_error_on(self):
        err = "no convergence: time step from t = 12.5 failed after all retries (TS reason DIVERGED)"
        m = failure_cause(self.case(10, 2), err, [self.case(20, 4)[2], self.case(14.1, 2.82)[2]])
        self.assertEqual(m, f"level h = 10, steps × 0.25 failed at t = 12.5 s: {err}")

    def test_no_completed_level_says_to_try_one_alone(self):
        m = failure_cause(self.case(10, 2), "no convergence: time step from t = 0 failed after all retries", [])
        # Nothing ran at other sizes either: the mesh is named, the material not cleared.
        self.assertIn("failed in its first step. Likely cause: its mesh: the level's sizes are h = 10, h_pole = 2 µm", m)
        self.assertNotIn("not the material", m)
        self.assertIn("No level completed", m)

    def test_stages(self):
        self.assertEqual(failure_stage(SETTLING), "settling")
        self.assertEqual(failure_stage("time step from t = 0 failed"), "first step")
        self.assertEqual(failure_stage("cut the step from t = 0.0 to 1e-9"), "first step")
        self.assertEqual(failure_stage("cut the step from t = 130.07980000000003 to 1e-9"), "at t = 130.08 s")
        self.assertEqual(failure_stage("cannot read the mesh"), "unknown")


if __name__ == "__main__":
    unittest.main()
