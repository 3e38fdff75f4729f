"""The 2-D Keller-Skalak model of docs/vesicle_shear.md (scripts/vesicle_theory.py): its outer-flow
resistance against exact 2-D results, its limits, and the numbers the page quotes. Run by ctest with
the other Python tests (label unit)."""
import math
import os
import sys
import unittest

import numpy as np

SOURCE = os.environ.get("SPHIB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts"))

import vesicle_theory as vt  # noqa: E402


class VesicleTheory(unittest.TestCase):
    def test_circle_torque_and_stresslet(self):
        # 2-D Stokes, R = 1, mu = 1: torque 4 pi on a circle held in fluid rotating at rate 1; stresslet
        # 4 pi e in the strain e (intrinsic viscosity 2 of disks). Measured: 1e-14 relative with 200 sources.
        R = vt.Resistance(1.0, 1.0, 200)
        self.assertAlmostEqual(vt.torque(R.traction_moment(-vt.rotation(1.0))) / (4 * math.pi), 1.0, places=9)
        M = R.traction_moment(-vt.strain12(1.0)) + 2.0 * vt.strain12(1.0) * R.area
        self.assertAlmostEqual(0.5 * (M[0, 1] + M[1, 0]) / (4 * math.pi), 1.0, places=9)

    def test_free_rigid_ellipse_rotates_at_jefferys_rate(self):
        for a, b in [(2.0, 1.0), (1.5, 0.5)]:
            R = vt.Resistance(a, b, 400)
            k = vt.torque(R.traction_moment(vt.strain12(1.0))) / vt.torque(R.traction_moment(vt.rotation(1.0)))
            self.assertAlmostEqual(k, (a * a - b * b) / (a * a + b * b), places=8)

    def test_very_viscous_inside_tumbles_like_a_rigid_ellipse(self):
        # lambda -> infinity: the membrane cannot tank-tread, B -> Jeffery's k (B - k = O(1/lambda):
        # measured 1.4e-4 at lambda = 1e4)
        a, b = vt.axes_for_reduced_area(0.8)
        B = vt.ks_coefficients(a, b, 1e6)[0]
        self.assertAlmostEqual(B, (a * a - b * b) / (a * a + b * b), places=5)

    def test_reduced_area(self):
        a, b = vt.axes_for_reduced_area(0.8)
        self.assertAlmostEqual(a * b, 1.0, places=12)  # area pi (R0 = 1)
        self.assertAlmostEqual(4 * math.pi * math.pi * a * b / vt.perimeter(a, b) ** 2, 0.8, places=10)
        self.assertAlmostEqual(b / a, 0.45296, places=5)

    def test_the_numbers_the_page_quotes(self):
        # nu = 0.8: tank-treading angle 28.229 degrees at lambda = 1, 12.907 at 3; B(4.0507) = 1
        a, b = vt.axes_for_reduced_area(0.8)
        for lam, theta in [(1.0, 28.229), (3.0, 12.907)]:
            B = vt.ks_coefficients(a, b, lam)[0]
            self.assertAlmostEqual(0.5 * math.degrees(math.acos(1 / B)), theta, places=3)
        self.assertAlmostEqual(vt.ks_coefficients(a, b, 4.0507)[0], 1.0, places=4)
        # converged in the number of sources (200 against 800: 1e-13)
        self.assertAlmostEqual(vt.ks_coefficients(a, b, 1.0, 200)[0], vt.ks_coefficients(a, b, 1.0, 800)[0], places=10)


if __name__ == "__main__":
    unittest.main()
