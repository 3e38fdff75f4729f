"""The viscosity contrast from Python: the scene key membrane.viscosity_ratio and
Scene.add_membrane(viscosity_ratio=...), and their refusal by methods other than eulerian."""
import os
import unittest

import numpy as np

import sphib

SOURCE = os.environ.get("SPHIB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
OSCILLATION = os.path.join(SOURCE, "cases", "membrane_oscillation.toml")
LAGRANGIAN = os.path.join(SOURCE, "cases", "membrane_oscillation_lagrangian.toml")
SMALL = {"grid.nx": 24, "grid.ny": 24, "membrane.nb": 48, "time.dt": 1e-3}


class ViscosityContrast(unittest.TestCase):
    def test_scene_key_changes_the_flow(self):
        one = sphib.Simulation(sphib.load_scene(OSCILLATION, set=SMALL))
        four = sphib.Simulation(sphib.load_scene(OSCILLATION, set={**SMALL, "membrane.viscosity_ratio": 4}))
        for _ in range(10):
            one.step()
            four.step()
        self.assertGreater(np.abs(one.u - four.u).max(), 1e-4)
        with self.assertRaisesRegex(sphib.SceneError, "membrane.viscosity_ratio"):
            sphib.load_scene(OSCILLATION, set={"membrane.viscosity_ratio": 1000})
        with self.assertRaisesRegex(sphib.SceneError, r"membrane.viscosity_ratio.*eulerian"):
            sphib.load_scene(LAGRANGIAN, set={"membrane.viscosity_ratio": 2})

    def test_add_membrane_takes_the_ratio(self):
        keys = {"domain": {"x": [-1, 1], "y": [-0.5, 0.5]}, "grid": {"nx": 32, "ny": 16},
                "walls": {"top": [0.5, 0], "bottom": [-0.5, 0]},
                "fluid": {"rho": 1.0, "mu": 1.0}, "time": {"dt": 5e-4, "end": 0.005}}
        s = sphib.Scene(keys)
        s.add_membrane(sphib.circle(nb=64, r0=0.2, T0=1.0), viscosity_ratio=5.0)
        sim = sphib.Simulation(s)
        for _ in range(5):
            sim.step()
        self.assertTrue(np.isfinite(sim.u).all())
        with self.assertRaisesRegex(sphib.SceneError, r"membranes\[1\]\.viscosity_ratio"):
            s.add_membrane(sphib.circle(nb=64, r0=0.2, centre=(0.6, 0.0)), viscosity_ratio=0.0)
        lag = sphib.Scene({**keys, "method": "lagrangian"})
        with self.assertRaisesRegex(sphib.SceneError, r"viscosity_ratio.*eulerian"):  # checked as a file's key
            lag.add_membrane(sphib.circle(nb=64, r0=0.2, T0=1.0), viscosity_ratio=5.0)


if __name__ == "__main__":
    unittest.main()
