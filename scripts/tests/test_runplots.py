"""plot_run.py's figures on tiny run and sweep directories written here in the solver's formats
(history.csv, scene.toml, summary.toml, status.txt, fields.h5 of a meridian or a 3-D mesh,
summary.csv): the protocol's phases from a table (two holds) or from phases, forces in µN, runs
in progress, damaged files, the field pictures' values (a 3-D section of a linear field is that
field on the plane), and the command line's answers to good and bad arguments."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import h5py
import numpy as np

from poroplast_tools import fieldplots, labels, runplots
from tests.test_slices import cube, linear

PNG = b"\x89PNG\r\n\x1a\n"
SCRIPT = Path(__file__).resolve().parents[1] / "plot_run.py"
TWO_HOLDS = [[0.0, 0.0], [5.0, 0.15], [1005.0, 0.15], [1010.0, 0.0], [1300.0, 0.0], [1305.0, 0.3],
             [2305.0, 0.3], [2310.0, 0.0]]   # tst_two_compressions' table


def write_history(d, t, f, extra=None, end="\n"):
    """history.csv with the plate columns (force f in mg) at times t; `extra` {column: values}."""
    extra = extra or {}
    head = ["step", "time", "dt", "force_total_mg", "probe_p", "height", "width", "contact_nodes_upper",
            *extra, "newton_its", "ksp_its", "wall_s"]
    rows = [",".join(head)]
    for i, (ti, fi) in enumerate(zip(t, f)):
        more = [str(v[i]) for v in extra.values()]
        cols = [i, ti, 1, fi, fi / 2, 200 - 10 * fi, 200 + 5 * fi, int(fi > 0), *more, 3, 3, 0.1]
        rows.append(",".join(map(str, cols)))
    (d / "history.csv").write_text("\n".join(rows) + end)


def meridian_fields(path, times):
    """fields.h5 of a meridian of two tri6 cells: p = k (node), von_mises = 2k and porosity
    0.4 − 0.01 k − 0.001 cell (cells) at output k."""
    X = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1],
                  [0.5, 0, 0], [0.5, 0, 0.5], [0, 0, 0.5], [1, 0, 0.5], [0.5, 0, 1]], float)
    top = np.array([[0, 1, 2, 4, 5, 6], [1, 3, 2, 7, 8, 5]])
    with h5py.File(path, "w") as h:
        h["mesh/coordinates"], h["mesh/topology"], h["time"] = X, top, np.array(times)
        h["step_mesh"] = np.zeros(len(times), int)
        for k in range(len(times)):
            h[f"fields/p/{k:06d}"] = np.full(len(X), float(k))
            h[f"fields/u/{k:06d}"] = np.zeros((len(X), 3))
            h[f"fields/von_mises/{k:06d}"] = np.full(len(top), 2.0 * k)
            h[f"fields/porosity/{k:06d}"] = 0.4 - 0.01 * k - 0.001 * np.arange(len(top))


def tet10(X, tets):
    """10-node tetrahedra on the 4-node ones: a mid-edge node per edge (XDMF's order)."""
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    mids, index, top = [], {}, []
    for t in tets:
        row = list(t)
        for a, b in edges:
            key = tuple(sorted((t[a], t[b])))
            if key not in index:
                index[key] = len(X) + len(mids)
                mids.append(0.5 * (X[t[a]] + X[t[b]]))
            row.append(index[key])
        top.append(row)
    return np.vstack([X, mids]), np.array(top)


STRETCH = 0.1   # the 3-D run's u = (0, 0, STRETCH z)


def solid_fields(path, times):
    """fields.h5 of a 3-D run: the cube [0, 100]³ in tet10, p = linear(X) + k, von_mises = the
    cell's index, u = (0, 0, STRETCH z) at every output k."""
    X, top = tet10(*cube(3, 100.0))
    with h5py.File(path, "w") as h:
        h["mesh/coordinates"], h["mesh/topology"], h["time"] = X, top, np.array(times)
        h["step_mesh"] = np.zeros(len(times), int)
        for k in range(len(times)):
            h[f"fields/p/{k:06d}"] = linear(X) + k
            h[f"fields/u/{k:06d}"] = np.stack([0 * X[:, 0], 0 * X[:, 0], STRETCH * X[:, 2]], 1)
            h[f"fields/von_mises/{k:06d}"] = np.arange(len(top), dtype=float)
    return X, top


def write_run(d, mu=20.0, fields="meridian", times=(0.0, 5.0), plates=None,
              status="completed: 7 steps, t = 9"):
    """A completed run of the protocol ramp to 2 s, hold to 6 s, release by 8 s (earlier
    versions' t_ramp and t_end, or `plates`), with fields on a meridian, a 3-D mesh or none."""
    d.mkdir(parents=True)
    t = np.array([0.0, 1.0, 2.0, 4.0, 6.0, 7.0, 8.0, 9.0])
    write_history(d, t, mu / 20 * np.array([0.0, 2.0, 4.0, 3.0, 2.5, 1.0, 0.0, 0.0]))
    plates = plates or "t_ramp = 2.0\nt_end = 8.0\n"
    (d / "scene.toml").write_text(f'name = "x"\n[material]\nmu = {mu}\n[plates]\nradius = 100.0\n{plates}')
    (d / "summary.toml").write_text("[plates]\npeak_force_mg = 4.0\npeak_force_uN = 39.24\npeak_force_time_s = 2.0\n"
                                    "contact_opening_time_s = 8.0\n")
    if status:
        (d / "status.txt").write_text(status + "\n")
    if fields == "meridian":
        meridian_fields(d / "fields.h5", times)
    elif fields == "3d":
        solid_fields(d / "fields.h5", times)
    return d


def force_line(fig):
    return [l for l in fig.axes[0].lines if not l.get_label().startswith(("peak", "contact"))
            and len(l.get_xdata()) > 2][0]


class Protocol(unittest.TestCase):
    def test_phases_from_a_table_of_two_holds(self):
        self.assertEqual(runplots.segments(runplots.plate_path({"table": TWO_HOLDS})),
                         [("ramp", 0.0, 5.0), ("hold", 5.0, 1005.0), ("release", 1005.0, 1010.0),
                          ("ramp", 1300.0, 1305.0), ("hold", 1305.0, 2305.0), ("release", 2305.0, 2310.0)])

    def test_phases_from_rows_that_merge_step_or_stay_compressed(self):
        # Two rising rows are one ramp; a step up from a hold is a ramp between two holds; a table
        # that ends compressed holds to the end of the run.
        path = runplots.plate_path({"table": [[0, 0], [1, 0.1], [3, 0.2], [4, 0.2], [5, 0.3], [9, 0.3]]})
        self.assertEqual(runplots.segments(path), [("ramp", 0.0, 3.0), ("hold", 3.0, 4.0), ("ramp", 4.0, 5.0),
                                                   ("hold", 5.0, float("inf"))])

    def test_phases_from_the_phase_keys_and_the_deprecated_ones(self):
        self.assertEqual(runplots.segments(runplots.plate_path({"compression": 0.3, "ramp": 5.0, "hold": 30.0,
                                                                "release": 5.0})),
                         [("ramp", 0.0, 5.0), ("hold", 5.0, 35.0), ("release", 35.0, 40.0)])
        self.assertEqual(runplots.segments(runplots.plate_path({"t_ramp": 2.0, "t_end": 8.0})),
                         [("ramp", 0.0, 2.0), ("hold", 2.0, 6.0), ("release", 6.0, 8.0)])
        self.assertIsNone(runplots.plate_path(None))

    def test_phases_of_a_run_directory(self):
        with tempfile.TemporaryDirectory() as tmp:
            run = write_run(Path(tmp) / "run", fields=None)
            self.assertEqual(runplots.phases(run), [("ramp", 0.0, 2.0), ("hold", 2.0, 6.0), ("release", 6.0, 8.0)])
            (run / "scene.toml").write_text('name = "cryer"\n')
            self.assertEqual(runplots.phases(run), [])
            notes = []
            (run / "scene.toml").write_text('[plates]\nramp = 2.0\n')
            self.assertEqual(runplots.phases(run, notes), [])
            self.assertIn("protocol is incomplete", notes[0])


class RunPlots(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def test_a_meridian_run_gets_both_figures(self):
        run = write_run(self.root / "run")
        written, notes = runplots.plot(run)
        self.assertEqual([p for p, _ in written], [run / "plot_history.png", run / "plot_fields.png"])
        self.assertEqual(notes, [])
        for p, _ in written:
            self.assertEqual(p.read_bytes()[:8], PNG)
        fig = runplots.history_figure([("run", run)], self.root / "h.png")
        force = fig.axes[0]
        self.assertEqual(force.get_ylabel(), "total force (µN)")
        self.assertEqual([a.get_ylabel() for a in fig.axes[1:3]], ["p(X_U) (kPa)", "H/W"])
        # The force in µN: the mg column × 9.81 (no µN column in this history); mg on the right.
        self.assertEqual(list(force_line(fig).get_ydata()), [f * 9.81 for f in [0.0, 2.0, 4.0, 3.0, 2.5, 1.0, 0, 0]])
        self.assertEqual(force.child_axes[0].get_ylabel(), "mg")
        # The phases shaded, the hold's end dashed, the summary's peak marked (µN).
        self.assertEqual(len(force.patches), 3)
        self.assertEqual([list(l.get_xdata()) for l in force.lines if l.get_linestyle() == "--"], [[6.0, 6.0]])
        peak = [l for l in force.lines if l.get_label().startswith("peak")]
        self.assertEqual(list(peak[0].get_xdata()), [2.0])
        self.assertEqual(list(peak[0].get_ydata()), [39.24])
        self.assertEqual(peak[0].get_label(), "peak 39.24 µN = 4 mg")

    def test_forces_from_the_uN_columns_where_the_history_has_them(self):
        run = write_run(self.root / "run", fields=None)
        t = [0.0, 1.0, 2.0]
        write_history(run, t, [0.0, 1.0, 2.0], {"force_total_uN": [0.0, 10.0, 20.5]})
        fig = runplots.history_figure([("run", run)], self.root / "h.png")
        self.assertEqual(list(force_line(fig).get_ydata()), [0.0, 10.0, 20.5])
        self.assertEqual(labels.G, 9.81)

    def test_a_table_of_two_holds(self):
        run = write_run(self.root / "tst", fields=None, plates=f"table = {TWO_HOLDS}\n")
        t = np.linspace(0, 2400, 49)
        f = np.interp(t, [r[0] for r in TWO_HOLDS], [r[1] for r in TWO_HOLDS])
        write_history(run, t, f, {"sigma_app": np.where(f > 0, 5.0, np.nan)})
        fig = runplots.history_figure([("tst", run)], self.root / "h.png")
        force = fig.axes[0]
        self.assertEqual(len(force.patches), 6)
        self.assertEqual([l.get_xdata()[0] for l in force.lines if l.get_linestyle() == "--"], [1005.0, 2305.0])
        self.assertEqual([x.get_text() for x in force.texts], ["hold 1", "hold 2"])  # the 5-s ramps: no room
        # No surface tension in the scene: σ_app means nothing, no panel.
        self.assertEqual([a.get_ylabel() for a in fig.axes if a.get_ylabel() != "mg"][-1], "H/W")
        (run / "scene.toml").write_text(f'[surface]\ntension = 5.0\n[plates]\ntable = {TWO_HOLDS}\n')
        fig = runplots.history_figure([("tst", run)], self.root / "h.png")
        sigma = [a for a in fig.axes if a.get_ylabel() == "σ_app (mN/m)"]
        self.assertEqual(np.nanmax(sigma[0].lines[-1].get_ydata()), 5.0)
        # A run that stopped in the first hold: the second is not shaded, the first hold not ended.
        write_history(run, t[:10], f[:10])
        fig = runplots.history_figure([("tst", run)], self.root / "h.png")
        self.assertEqual(len(fig.axes[0].patches), 2)
        self.assertEqual([l for l in fig.axes[0].lines if l.get_linestyle() == "--"], [])

    def test_a_run_in_progress_or_stopped_says_so(self):
        run = write_run(self.root / "run", fields=None, status=None)
        (run / "summary.toml").unlink()
        written, notes = runplots.plot(run)
        self.assertEqual(notes, ["the run is in progress (no status.txt yet): drawn as far as it got",
                                 "no summary.toml: the peak and the contact opening are not marked (the run has "
                                 "not completed)", "no fields.h5 (output.fields = false): no field pictures"])
        fig = runplots.history_figure([("run", run)], self.root / "h.png", runplots.status(run))
        self.assertIn("in progress", fig.get_suptitle())
        self.assertEqual(runplots.status(run), "in progress (no status.txt yet)")
        (run / "status.txt").write_text("stopped by a signal after step 3 (t = 2): continue with ...\n")
        self.assertTrue(runplots.status(run).startswith("stopped"))
        (run / "status.txt").write_text("failed after step 3 (t = 2): Newton diverged\n")
        self.assertEqual(runplots.status(run), "failed: Newton diverged")
        (run / "status.txt").write_text("completed: 3 steps, t = 2\n")
        self.assertIsNone(runplots.status(run))

    def test_a_cut_last_line_and_bad_rows_are_dropped_and_named(self):
        run = write_run(self.root / "run", fields=None)
        text = (run / "history.csv").read_text()
        lines = text.splitlines()
        lines.insert(3, "2,1.5,1,oops,0,0,0,0,3,3,0.1")
        (run / "history.csv").write_text("\n".join(lines)[:-3])      # the last line cut
        written, notes = runplots.plot(run)
        self.assertEqual([p.name for p, _ in written], ["plot_history.png"])
        self.assertTrue(any("last line is cut" in n for n in notes), notes)
        self.assertTrue(any("1 line(s) not 11 numbers" in n and "line 4" in n for n in notes), notes)
        fig = runplots.history_figure([("run", run)], self.root / "h.png")
        self.assertEqual(list(force_line(fig).get_xdata()), [0.0, 1.0, 2.0, 4.0, 6.0, 7.0, 8.0])

    def test_no_fields_no_scene_no_summary(self):
        run = write_run(self.root / "run", fields=None)
        (run / "scene.toml").unlink()
        (run / "summary.toml").write_text("[plates\npeak")
        written, notes = runplots.plot(run)
        self.assertEqual([p.name for p, _ in written], ["plot_history.png"])
        self.assertIn("no fields.h5 (output.fields = false): no field pictures", notes)
        self.assertIn("no scene.toml: the protocol's phases are not shaded", notes)
        self.assertTrue(any(n.startswith("summary.toml is not readable TOML") for n in notes), notes)

    def test_a_truncated_fields_file_and_its_checkpoint_copy(self):
        run = write_run(self.root / "run")
        data = (run / "fields.h5").read_bytes()
        (run / "checkpoints").mkdir()
        (run / "checkpoints" / "fields.h5").write_bytes(data)
        (run / "fields.h5").write_bytes(data[:len(data) // 2])
        written, notes = runplots.plot(run)
        self.assertEqual([p.name for p, _ in written], ["plot_history.png", "plot_fields.png"])
        self.assertIn("fields.h5 cannot be read", notes[0])
        self.assertIn("drawn from the copy at the last checkpoint", notes[0])
        (run / "checkpoints" / "fields.h5").unlink()
        (run / "plot_fields.png").unlink()
        written, notes = runplots.plot(run)
        self.assertEqual([p.name for p, _ in written], ["plot_history.png"])
        self.assertTrue(notes[0].startswith("fields.h5 cannot be read") and notes[0].endswith("no field pictures"))

    def test_what_is_neither_a_run_nor_a_sweep_or_has_nothing_to_draw(self):
        with self.assertRaisesRegex(runplots.Nothing, "neither a run directory"):
            runplots.plot(self.root)
        with self.assertRaisesRegex(runplots.Nothing, "no such directory"):
            runplots.plot(self.root / "nowhere")
        (self.root / "history.csv").write_text("time\n0\n")
        with self.assertRaisesRegex(runplots.Nothing, "a file, not a directory: give the run or sweep directory"):
            runplots.plot(self.root / "history.csv")
        run = write_run(self.root / "run", fields=None)
        (run / "history.csv").write_text("step,time,force_total_mg\n")
        with self.assertRaisesRegex(runplots.Nothing, "history.csv has no rows.*output.fields = false"):
            runplots.plot(run)
        (run / "history.csv").write_text("step,force_total_mg\n0,1.0\n")
        with self.assertRaisesRegex(runplots.Nothing, "history.csv has no time column"):
            runplots.plot(run)
        (self.root / "sweep" / "cases").mkdir(parents=True)
        with self.assertRaisesRegex(runplots.Nothing, "a sweep directory without its summary.csv yet"):
            runplots.plot(self.root / "sweep")

    def test_a_sweep_overlays_its_cases(self):
        sweep = self.root / "sweep"
        for name, mu in [("a", 15), ("b", 25), ("r", 35)]:
            write_run(sweep / "cases" / name, mu=mu, fields=None, plates=f"table = {TWO_HOLDS}\n")
        (sweep / "summary.csv").write_text(
            "case,material.mu,status,wall_s,max:force_total_mg,error,dir\n"
            "0,15,ok,1,3,,cases/a\n1,25,ok,1,5,,cases/b\n2,-3,failed,,,bad mu,cases/c\n3,35,running,,,,cases/r\n"
            "4,45,pen")   # a row cut while written
        notes = []
        cases = runplots.sweep_cases(sweep, notes)
        self.assertEqual([c[0] for c in cases], ["µ = 15 kPa", "µ = 25 kPa", "µ = 35 kPa (running)"])
        self.assertEqual(notes, ["case 2 (failed: bad mu) not drawn", "case 4 (pen) not drawn"])
        written, notes = runplots.plot(sweep)
        self.assertEqual([p for p, _ in written], [sweep / "plot_history.png"])
        fig = runplots.history_figure(cases, self.root / "s.png")
        lines = [l for l in fig.axes[0].lines if not l.get_label().startswith("_")]
        self.assertEqual([l.get_label() for l in lines], [c[0] for c in cases])
        self.assertEqual(max(lines[1].get_ydata()), 5.0 * 9.81)
        self.assertEqual(len(fig.axes[0].patches), 2)   # the shared table's first ramp and hold: t ≤ 9 s


class FieldPictures(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def draw(self, run, **kw):
        """fieldplots.figure on the run's file, as draw() calls it: (panels, notes)."""
        with h5py.File(run / "fields.h5", "r") as f:
            rows = fieldplots.output_times(f["time"][:], kw.pop("wanted", None))
            return fieldplots.figure(f, rows, kw.pop("names", ["p", "von_mises"]), self.root / "f.png",
                                     kw.pop("where", "axis"), kw.pop("asked", {}), "run")

    def test_output_times_drawn(self):
        self.assertEqual(fieldplots.output_times(range(4)), [0, 1, 2, 3])
        self.assertEqual(fieldplots.output_times(np.arange(10.0)), [0, 2, 4, 5, 7, 9])
        self.assertEqual(fieldplots.output_times([0.0, 1.0, 2.0, 5.0], wanted=[1.9, 4.0, 100.0]), [2, 3])

    def test_a_meridian_run_draws_porosity_and_says_which_time(self):
        run = write_run(self.root / "run", times=(0.0, 5.0, 15.0))
        names = ["p", "porosity", "sigma_vm", "q", "u"]
        written, notes = runplots.plot(run, wanted=[5.0, 4.0, 100.0], fields=names)
        self.assertEqual(notes, ["u: a vector field, not drawn (the scalar fields: p, porosity, von_mises)",
                                 "fields.h5 has no q (it has p, porosity, von_mises)",
                                 "t = 4 s is not an output time: drawn at the nearest written, 5 s",
                                 "t = 100 s is after the last output (15 s): drawn at the nearest written, 15 s"])
        self.assertEqual(written[1][1], "p, porosity, von_mises at t = 5, 15 s on the deformed meridian")
        panels, _ = self.draw(run, wanted=[5.0], names=["porosity", "p"], where="meridian")
        tri, v = panels[(1, "porosity")]
        self.assertEqual(list(v), [0.39, 0.389])
        self.assertEqual(list(tri.triangles[1]), [1, 3, 2])
        self.assertEqual(list(panels[(1, "p")][1]), [1.0] * 9)

    def test_a_3d_section_through_the_axis_is_the_field_on_the_plane(self):
        run = write_run(self.root / "run3d", fields="3d", times=(0.0, 1.0))
        X, top = tet10(*cube(3, 100.0))
        written, notes = runplots.plot(run, wanted=[1.0], fields=["p"], mid_plane=True)
        self.assertEqual([p.name for p, _ in written], ["plot_history.png", "plot_fields.png", "plot_fields_mid.png"])
        self.assertEqual(notes, [])
        panels, notes = self.draw(run)
        for k in (0, 1):
            tri, p = panels[(k, "p")]
            # drawn in (x, z) of the deformed body, z = 1.1 Z: p is the linear field of X = (x, 0, z/1.1), + k
            ref = np.stack([tri.x, 0 * tri.x, tri.y / (1 + STRETCH)], 1)
            self.assertLess(np.abs(p - (linear(ref) + k)).max(), 1e-12)
            self.assertAlmostEqual(tri.x.max() - tri.x.min(), 100.0, places=12)
            self.assertAlmostEqual(tri.y.max(), 110.0, places=12)
            # The face y = 0 of the cube: each triangle is a face of the cell whose value it shows.
            tri, vm = panels[(k, "von_mises")]
            corners = np.stack([tri.x[tri.triangles], tri.y[tri.triangles] / (1 + STRETCH)], -1)
            cells = X[top[vm.astype(int), :4]][:, :, [0, 2]]
            for c, cell in zip(corners, cells):
                self.assertTrue(all(np.abs(cell - q).sum(1).min() < 1e-9 for q in c))
            e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
            area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
            self.assertAlmostEqual(area, 100.0 * 100.0, places=6)
        # The mid-height section: z = 55 in the deformed body, Z = 50: p = linear(x, y, 50) + k.
        panels, _ = self.draw(run, where="mid", names=["p"])
        tri, p = panels[(1, "p")]
        ref = np.stack([tri.x, tri.y, 0 * tri.x + 50.0], 1)
        self.assertLess(np.abs(p - (linear(ref) + 1)).max(), 1e-12)

    def test_values_that_are_not_finite_are_left_blank(self):
        import matplotlib.pyplot as plt
        from matplotlib.tri import Triangulation
        tri = Triangulation([0, 1, 0, 1], [0, 0, 1, 1], [[0, 1, 2], [1, 3, 2]])
        fig, ax = plt.subplots()
        # A node value NaN: its triangle blank, the other's values (0, 1, 2) coloured.
        levels = fieldplots.panel(ax, tri, np.array([0.0, 1.0, 2.0, np.nan]), True).levels
        self.assertTrue(levels[0] <= 0.0 and 2.0 <= levels[-1] < 2.1, levels)
        self.assertEqual(list(fieldplots.panel(ax, tri, np.array([1.0, np.nan]), False).get_array()), [1.0])
        plt.close(fig)

    def test_colour_bars_carry_no_offset_label(self):
        f = fieldplots.TickLabels()
        ticks = [0.3999995, 0.4, 0.4000005]
        f.set_locs(ticks)
        self.assertEqual([f(v) for v in ticks], ["0.3999995", "0.4", "0.4000005"])
        ticks = [-1e-22, 2e-8, 4e-8]   # a 0 with round-off
        f.set_locs(ticks)
        self.assertEqual([f(v) for v in ticks], ["0", "2e-08", "4e-08"])
        f.set_locs([0.0, 5.0, 10.0, 15.0])
        self.assertEqual(f(15.0), "15")


class CommandLine(unittest.TestCase):
    def run_script(self, *args):
        env = dict(os.environ, MPLBACKEND="Agg")
        r = subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, env=env)
        self.assertNotIn("Traceback", r.stderr)
        return r

    def test_times_as_labs_write_them(self):
        sys.path.insert(0, str(SCRIPT.parent))
        import plot_run
        for text, want in [("5,35", [5, 35]), ("5s,35s", [5, 35]), ("5 s, 35 s", [5, 35]), ("1min", [60]),
                           ("1min 90s", [60, 90]), ("0.5h;1e1", [1800, 10]), (" 5 , 35 ", [5, 35])]:
            self.assertEqual(plot_run.times(text), want, text)
        for bad in ["abc", "5 parsecs", "", "5,,x", "-3"]:
            with self.assertRaises(Exception, msg=bad):
                plot_run.times(bad)

    def test_bad_arguments_and_directories_get_one_line(self):
        with tempfile.TemporaryDirectory() as tmp:
            run = write_run(Path(tmp) / "run")
            r = self.run_script(run, "--times", "5 parsecs")
            self.assertEqual(r.returncode, 2)
            self.assertIn("'5 parsecs' is not a time", r.stderr)
            r = self.run_script(tmp)
            self.assertEqual(r.returncode, 1)
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
            self.assertIn("neither a run directory", r.stderr)
            data = (run / "fields.h5").read_bytes()
            (run / "fields.h5").write_bytes(data[:1000])
            r = self.run_script(run, "--times", "1s,2s")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("plot_history.png: 1 run(s), 8 rows to t = 9 s", r.stdout)
            self.assertIn("note: fields.h5 cannot be read", r.stdout)


if __name__ == "__main__":
    unittest.main()
