"""scripts/probe_windows.py (docs/free_surfaces.md, Lobovsky et al.): a probe's single-step readings
from its windowed means, and the means over another window. Run by ctest with the other Python tests
(label unit)."""
import os
import sys
import unittest

import numpy as np

SOURCE = os.environ.get("SPHIB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts"))

import probe_windows as pw  # noqa: E402


def brute_means(t, p, window):
    # observe/probes.cpp's rule written out: the steps j <= k with t_j >= t_k - window (1 + 1e-9)
    return np.array([np.mean([p[j] for j in range(k + 1) if t[j] >= t[k] - window * (1 + 1e-9)])
                     for k in range(len(t))])


class ProbeWindows(unittest.TestCase):
    def setUp(self):
        dt = 1.25e-4
        self.t = np.cumsum(np.full(400, dt)) - dt  # t = k dt, summed as a run's clock is
        rng = np.random.default_rng(3)
        self.p = np.where(np.arange(400) < 120, 0.0, rng.uniform(0, 5e4, 400))  # dry, then an impact

    def test_window_means_follow_the_probes_rule(self):
        for w in (1e-3, 5e-3):
            np.testing.assert_allclose(pw.window_means(self.t, self.p, w), brute_means(self.t, self.p, w), rtol=1e-12)
        np.testing.assert_array_equal(pw.window_means(self.t, self.p, 0.0), self.p)

    def test_single_steps_from_the_means_of_a_dry_start(self):
        # measured: 3.6e-10 / 7.1e-10 Pa at most (1 / 5 ms) against readings up to 5e4 Pa (round-off)
        for w in (1e-3, 5e-3):
            m = brute_means(self.t, self.p, w)
            np.testing.assert_allclose(pw.single_steps(self.t, m, w), self.p, atol=1e-8)

    def test_a_wet_start_is_not_recovered(self):
        # the recursion needs p = 0 before the first window fills: a sensor wet from t = 0 is not
        p = self.p + 1e3 * (1 + np.sin(np.arange(400)))
        m = brute_means(self.t, p, 1e-3)
        self.assertGreater(np.abs(pw.single_steps(self.t[5:], m[5:], 1e-3) - p[5:]).max(), 1.0)


if __name__ == "__main__":
    unittest.main()
