"""A run's accepted steps as the `time.steps` that replays them, each time exactly as written."""
import unittest

import numpy as np

from poroplast_tools.history import given_steps


class History(unittest.TestCase):
    def test_given_steps_are_the_times_after_the_first_row(self):
        h = {"time": np.array([0.0, 0.1, 0.30000000000000004, 2.0])}
        self.assertEqual(given_steps(h), "[0.1,0.30000000000000004,2.0]")


if __name__ == "__main__":
    unittest.main()
