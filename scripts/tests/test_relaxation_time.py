"""The relaxation time reproduce.py reports for "relaxes in 400-1000 s": for an exponential decay
to the plateau, 95% of the way is reached after τ ln 20; a decay that stays above that by t_max
has none. Pure Python."""

import unittest

import numpy as np

from poroplast_tools.history import relaxation_time


class RelaxationTime(unittest.TestCase):
    def test_an_exponential_decay_reaches_95_percent_after_tau_ln_20(self):
        t = np.r_[np.linspace(0, 5, 20), np.linspace(5.1, 405, 4000)]
        for tau, plateau in ((30.0, 3.7), (123.0, 0.0)):
            f = np.where(t < 5, 13.0 * t / 5, plateau + (13.0 - plateau) * np.exp(-(t - 5) / tau))
            got = relaxation_time(t, f, plateau, 400.0)
            self.assertLess(abs(got - (5 + tau * np.log(20))), 0.01, (tau, got))

    def test_none_where_the_decay_is_slower(self):
        t = np.linspace(0, 400, 200)
        f = 3.7 + 10 * np.exp(-t / 300)          # 95% would take 899 s
        self.assertIsNone(relaxation_time(t, f, 3.7, 400.0))
        self.assertAlmostEqual(relaxation_time(t, f, 3.7, 400.0, 0.5), 300 * np.log(2), delta=0.05)


if __name__ == "__main__":
    unittest.main()
