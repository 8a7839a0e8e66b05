"""The run observables of poroplast_tools.fields on a synthetic run with known answers: the
meridian's volume weights revolve each triangle exactly (Pappus: a rectangle r ≤ a, 0 ≤ z ≤ H in
two triangles gives the cylinder πa²H), a region mean and the positive-pressure share are the
weighted ones, fields between two outputs are interpolated linearly, the upper detachment is the
last row in contact, and the settle time of F = 1 + e^(−t/10) from t = 5 to 400 at 5% is
5 + 10 ln 20 s."""
import math
import tempfile
import unittest
from pathlib import Path

import numpy as np

from poroplast_tools import fields as o


class Fields(unittest.TestCase):
    def test_known_fields(self):
        import h5py
        with tempfile.TemporaryDirectory() as d:
            run = str(Path(d) / "run")
            Path(run).mkdir()
            a, H = 30.0, 200.0
            X = np.array([[0, 0, 0], [a, 0, 0], [a, 0, H], [0, 0, H]], float)
            mid = lambda i, j: (X[i] + X[j]) / 2
            X = np.vstack([X, mid(0, 1), mid(1, 2), mid(2, 0), mid(2, 3), mid(3, 0)])
            top = np.array([[0, 1, 2, 4, 5, 6], [0, 2, 3, 6, 7, 8]])
            with h5py.File(run + "/fields.h5", "w") as f:
                f["/mesh/coordinates"], f["/mesh/topology"], f["/time"] = X, top, np.array([0.0, 10.0])
                f["/fields/von_mises/000000"], f["/fields/von_mises/000001"] = np.array([1.0, 3.0]), np.array([3.0, 5.0])
                f["/fields/p/000000"], f["/fields/p/000001"] = np.array([1.0, 1, 1, -5, 0, 0, 0, 0, 0]), np.zeros(9)
            F = o.fields(run)
            self.assertLess(abs(F.w.sum() - math.pi * a * a * H), 1e-9 * F.w.sum())
            w = F.w / F.w.sum()
            self.assertLess(abs(F.mean(F.at("von_mises", 5.0), np.ones(2, bool)) - (2 * w[0] + 4 * w[1])), 1e-12)
            share, where, angle = o.bubble(run, 0.0)
            self.assertLess(abs(share - w[0]), 1e-12)
            self.assertLess(abs(w[0] - 2 / 3), 1e-12)
            with open(run + "/history.csv", "w") as h:
                h.write("time,force_total_mg,contact_nodes_upper,max_von_mises\n")
                for x in np.arange(0, 400.001, 0.01):
                    h.write(f"{x},{1 + math.exp(-x / 10)},{5 if x <= 37.2 else 0},{4 if x <= 37.2 else 3}\n")
            s = o.settle_time(run, "force_total_mg", 5.0, 400.0, 0.05)
            self.assertLess(abs(s - (5 + 10 * math.log(20))), 1e-3)
            det = o.detachment(run, 35.0)
            self.assertLess(abs(det[0] - 37.2), 1e-6)
            self.assertEqual(det[1:], (4.0, 3.0))
            o.fields.cache_clear()


if __name__ == "__main__":
    unittest.main()
