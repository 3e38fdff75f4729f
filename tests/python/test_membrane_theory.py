"""The linear theory of the membrane validations (scripts/membrane_theory.py): its limits and the numbers
docs/membrane_validation.md quotes. Run by ctest with the other Python tests (label unit)."""
import math
import os
import sys
import unittest

SOURCE = os.environ.get("SPHIB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts"))

import membrane_theory as mt  # noqa: E402


class MembraneTheory(unittest.TestCase):
    def test_unsteady_mobility_tends_to_the_stokes_mobility(self):
        # rho -> 0 at fixed s: q R -> 0 (measured: 3.4e-6 relative at rho = 1e-6, 1.6e-2 at rho = 1e-3)
        for n in (2, 3, 5):
            M = mt.mobility(n, 0.6, 0.1, 1e-8, complex(-1, 4))
            S = mt.stokes_mobility(n, 0.6, 0.1)
            for i in range(2):
                for j in range(2):
                    self.assertAlmostEqual(complex(M[i][j]), S[i][j], delta=1e-5 * abs(S[0][0]))

    def test_stokes_rates_are_the_eigenvalues_of_M_K(self):
        n, R, mu, E, Tbar, Eb = 3, 0.5, 1.0, 4.0, 0.3, 0.1
        M, K = mt.stokes_mobility(n, R, mu), mt.stiffness(n, R, E, Tbar, Eb)
        MK = [[sum(M[i][k] * K[k][j] for k in range(2)) for j in range(2)] for i in range(2)]
        tr, det = MK[0][0] + MK[1][1], MK[0][0] * MK[1][1] - MK[0][1] * MK[1][0]
        a, b = mt.stokes_rates(n, R, mu, E, Tbar, Eb)
        self.assertAlmostEqual(tr.real, a + b, places=12)
        self.assertAlmostEqual(det.real, a * b, places=10)

    def test_the_oscillating_membrane_period(self):
        # the paper's scene: R = sqrt(0.375), Hookean T0 = 10 on r0 = 0.5, mu = 0.1, rho = 1
        R = math.sqrt(0.375)
        lam = R / 0.5
        s = mt.root(2, R, 0.1, 1.0, 10 * lam, 10 * (lam - 1), 0.0, complex(-1, 4))
        self.assertAlmostEqual(2 * math.pi / s.imag, 1.460355, places=5)
        self.assertAlmostEqual(s.real, -1.150917, places=5)

    def test_capsule_small_deformation(self):
        D, theta = mt.capsule(0.1)
        self.assertAlmostEqual(D, 0.1 / math.sqrt(9.04), places=14)
        self.assertAlmostEqual(theta, 45 - math.degrees(math.atan(0.2 / 3)) / 2, places=12)
        self.assertAlmostEqual(mt.capsule(1e-6)[0] / 1e-6, 1 / 3, places=9)  # D -> Ca_b / 3


if __name__ == "__main__":
    unittest.main()
