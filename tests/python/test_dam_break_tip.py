"""scripts/dam_break_tip.py (docs/free_surfaces.md, "Dam break: the surge front"): the front measures
on a block of water with a one-particle film ahead of it. Run by ctest with the other Python tests
(label unit)."""
import math
import os
import sys
import unittest

import numpy as np

SOURCE = os.environ.get("SPHIB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts"))

import dam_break_tip as tip  # noqa: E402


class FrontMeasures(unittest.TestCase):
    # A block of 10 x 6 particles at spacing dx = 1 mm (centres 0.5 ... 9.5 mm, first row dx/2 above the
    # floor y = 0): its edge is x = 10 mm, and it is 6 mm deep.
    dx = 1e-3
    reach = 2.6e-3  # 2h at h = 1.3 dx

    def block(self, extra=()):
        pts = [((i + 0.5) * self.dx, (j + 0.5) * self.dx) for i in range(10) for j in range(6)] + list(extra)
        return np.array([p[0] for p in pts]), np.array([p[1] for p in pts])

    def measure(self, x, y):
        return tip.measures(x, y, self.dx, self.dx, self.reach, 0.0, 0.0)[0]

    def test_the_block_alone_has_its_edge_by_every_measure(self):
        m = self.measure(*self.block())
        for name in ("support1", "support4", "support8", "depth 2dx", "depth 2mm", "depth 5mm"):
            self.assertAlmostEqual(m[name], 10e-3, places=12, msg=name)

    def test_a_film_two_spacings_ahead_is_the_front_by_one_neighbour_only(self):
        # (11.5, 0.5) mm: the block's corner particles (9.5, 0.5) and (9.5, 1.5) are within 2h, no other
        m = self.measure(*self.block([(11.5e-3, 0.5e-3)]))
        self.assertAlmostEqual(m["support1"], 12e-3, places=12)
        self.assertAlmostEqual(m["support4"], 10e-3, places=12)
        self.assertAlmostEqual(m["depth 2mm"], 10e-3, places=12)  # its strip holds 1 mm of water
        self.assertAlmostEqual(m["depth 5mm"], 10e-3, places=12)

    def test_a_layer_thinner_than_the_depth_is_not_the_front(self):
        # three rows (3 mm) from 10 to 14 mm: within 2 mm and not 5 mm
        layer = [((i + 0.5) * self.dx, (j + 0.5) * self.dx) for i in range(10, 14) for j in range(3)]
        m = self.measure(*self.block(layer))
        self.assertAlmostEqual(m["depth 2mm"], 14e-3, places=12)
        self.assertAlmostEqual(m["depth 5mm"], 10e-3, places=12)
        self.assertAlmostEqual(m["support8"], 14e-3, places=12)

    def test_no_strip_deep_enough(self):
        x, y = self.block()
        self.assertTrue(math.isnan(tip.depth_front(x[y < 1e-3], self.dx, self.dx, 5e-3, 0.0)))


class InitialField(unittest.TestCase):
    # The column of the dam-break cases: a = 0.146 m, H = 2a.
    a, H, g, rho = 0.146, 0.292, 9.81, 1000.0

    def field(self, x, y, a=None):
        return tip.initial_field(np.array(x, float), np.array(y, float), a or self.a, self.H, self.g, self.rho)

    def test_boundary_conditions(self):
        y = np.linspace(0.01, 0.28, 7)
        p_face, _ = self.field(np.full(7, self.a), y)
        p_top, _ = self.field(np.linspace(0.0, 0.14, 7), np.full(7, self.H))
        _, ax_wall = self.field(np.zeros(7), y)
        # the series' truncation (4000 terms): measured 6e-5 Pa at most on the face against rho g H = 2865 Pa
        self.assertLess(np.abs(p_face).max(), 1e-2)
        self.assertLess(np.abs(p_top).max(), 1e-9)
        self.assertLess(np.abs(ax_wall).max(), 1e-12)
        # the floor: dp/dy = -rho g (a_y = 0), by central differences (measured 2.5e-5 relative here)
        x, e = np.array([0.02, 0.07, 0.12]), 1e-6
        dp = (self.field(x, np.full(3, 2 * e))[0] - self.field(x, np.zeros(3))[0]) / (2 * e)
        np.testing.assert_allclose(dp, -self.rho * self.g * np.ones(3), rtol=1e-4)

    def test_a_long_column_has_the_logarithmic_face_acceleration(self):
        y = np.array([0.005, 0.05, 0.15]) * self.H
        _, ax = self.field(np.full(3, 20.0), y, a=20.0)
        exact = 2 * self.g / np.pi * np.log(1 / np.tan(np.pi * y / (4 * self.H)))
        np.testing.assert_allclose(ax, exact, rtol=1e-3)  # the truncated series: measured 4.6e-5 at y = 0.005 H

    def test_a_long_column_is_hydrostatic_far_from_its_face(self):
        p, ax = self.field([1.0], [0.1], a=20.0)
        self.assertAlmostEqual(p[0], self.rho * self.g * (self.H - 0.1), delta=1e-6)
        self.assertLess(abs(ax[0]), 1e-9)


if __name__ == "__main__":
    unittest.main()
