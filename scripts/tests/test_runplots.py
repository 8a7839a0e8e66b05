"""plot_run.py's figures on tiny run and sweep directories written here in the solver's formats
(history.csv, scene.toml, summary.toml, fields.h5 of a meridian or a 3-D mesh, summary.csv)."""
import tempfile
import unittest
from pathlib import Path

import h5py
import numpy as np

from poroplast_tools import runplots

PNG = b"\x89PNG\r\n\x1a\n"


def write_run(d, mu=20.0, cells=6, times=(0.0, 1.0, 2.0, 5.0, 7.0, 9.0, 12.0, 15.0)):
    """A run of the protocol ramp to 2 s, hold to 6 s, release by 8 s; fields at `times` on a
    meridian of two tri6 cells (`cells` = 6) or one tet10 (10)."""
    d.mkdir(parents=True)
    t = np.array([0.0, 1.0, 2.0, 4.0, 6.0, 7.0, 8.0, 9.0])
    f = mu / 20 * np.array([0.0, 2.0, 4.0, 3.0, 2.5, 1.0, 0.0, 0.0])
    rows = ["step,time,dt,force_total_mg,probe_p,height,width,contact_nodes_upper,newton_its,ksp_its,wall_s"]
    for i, (ti, fi) in enumerate(zip(t, f)):
        rows.append(f"{i},{ti},1,{fi},{fi / 2},{200 - 10 * fi},{200 + 5 * fi},{int(fi > 0)},3,3,0.1")
    (d / "history.csv").write_text("\n".join(rows) + "\n")
    (d / "scene.toml").write_text(f'name = "x"\n[material]\nmu = {mu}\n[plates]\nradius = 100.0\nt_ramp = 2.0\nt_end = 8.0\n')
    (d / "summary.toml").write_text("[plates]\npeak_force_mg = 4.0\npeak_force_uN = 39.24\npeak_force_time_s = 2.0\n"
                                    "contact_opening_time_s = 8.0\n")
    with h5py.File(d / "fields.h5", "w") as h:
        if cells == 6:
            X = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1],
                          [0.5, 0, 0], [0.5, 0, 0.5], [0, 0, 0.5], [1, 0, 0.5], [0.5, 0, 1]], float)
            top = np.array([[0, 1, 2, 4, 5, 6], [1, 3, 2, 7, 8, 5]])
        else:
            X = np.vstack([np.eye(3), [[0, 0, 0]], np.random.default_rng(0).random((6, 3))])
            top = np.arange(10)[None, :]
        h["mesh/coordinates"], h["mesh/topology"], h["time"] = X, top, np.array(times)
        h["step_mesh"] = np.zeros(len(times), int)
        for k in range(len(times)):
            h[f"fields/p/{k:06d}"] = np.full(len(X), float(k))
            h[f"fields/u/{k:06d}"] = np.zeros((len(X), 3))
            h[f"fields/von_mises/{k:06d}"] = np.full(len(top), 2.0 * k)
    return d


class RunPlots(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def test_the_phases_of_the_protocol(self):
        run = write_run(self.root / "run")
        self.assertEqual(runplots.phases(run), [("ramp", 0.0, 2.0), ("hold", 2.0, 6.0), ("release", 6.0, 8.0)])
        # Today's resolved scene names the phases (a release of its own length).
        (run / "scene.toml").write_text('[plates]\nramp = 2.0\nhold = 4.0\nrelease = 3.0\n')
        self.assertEqual(runplots.phases(run), [("ramp", 0.0, 2.0), ("hold", 2.0, 6.0), ("release", 6.0, 9.0)])
        (run / "scene.toml").write_text('name = "cryer"\n')
        self.assertEqual(runplots.phases(run), [])

    def test_output_times_drawn(self):
        self.assertEqual(runplots.output_times(range(4)), [0, 1, 2, 3])
        self.assertEqual(runplots.output_times(np.arange(10.0)), [0, 2, 4, 5, 7, 9])
        self.assertEqual(runplots.output_times([0.0, 1.0, 2.0, 5.0], wanted=[1.9, 4.0, 100.0]), [2, 3])

    def test_a_meridian_run_gets_both_figures(self):
        run = write_run(self.root / "run")
        written, note = runplots.plot(run)
        self.assertEqual(written, [run / "plot_history.png", run / "plot_fields.png"])
        self.assertIsNone(note)
        for p in written:
            self.assertEqual(p.read_bytes()[:8], PNG)
        # Eight output times: six drawn, the first and the last among them.
        self.assertEqual(runplots.fields_figure(run, self.root / "f.png"), [0, 1, 3, 4, 6, 7])
        fig = runplots.history_figure([("run", run)], self.root / "h.png")
        force = fig.axes[0]
        self.assertEqual(force.get_ylabel(), "total force (mg)")
        self.assertEqual([a.get_ylabel() for a in fig.axes[1:]], ["p(X_U) (kPa)", "H/W"])
        # The phases shaded, and the summary's peak marked.
        self.assertEqual(len(force.patches), 3)
        peak = [l for l in force.lines if l.get_label().startswith("peak")]
        self.assertEqual(list(peak[0].get_xdata()), [2.0])

    def test_a_3d_run_has_no_fields_figure(self):
        run = write_run(self.root / "run3d", cells=10, times=(0.0, 1.0))
        written, note = runplots.plot(run)
        self.assertEqual(written, [run / "plot_history.png"])
        self.assertIn("3-D", note)

    def test_a_sweep_overlays_the_cases_that_ended_ok(self):
        sweep = self.root / "sweep"
        for name, mu in [("a", 15), ("b", 25)]:
            write_run(sweep / "cases" / name, mu=mu)
        (sweep / "summary.csv").write_text(
            "case,material.mu,status,wall_s,max:force_total_mg,error,dir\n"
            "0,15,ok,1,3,,cases/a\n1,25,ok,1,5,,cases/b\n2,-3,failed,,,bad mu,cases/c\n")
        cases = runplots.sweep_cases(sweep)
        self.assertEqual([c[0] for c in cases], ["µ = 15 kPa", "µ = 25 kPa"])
        written, _ = runplots.plot(sweep)
        self.assertEqual(written, [sweep / "plot_history.png"])
        fig = runplots.history_figure(cases, self.root / "s.png")
        self.assertEqual([l.get_label() for l in fig.axes[0].lines], ["µ = 15 kPa", "µ = 25 kPa"])
        self.assertEqual(max(fig.axes[0].lines[1].get_ydata()), 5.0)


if __name__ == "__main__":
    unittest.main()
