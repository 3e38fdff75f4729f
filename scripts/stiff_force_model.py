#!/usr/bin/python3
"""The stiff-force filter (coupling/stiff_force.hpp) on one membrane mode, a model of its stability.

One Fourier mode of the membrane: displacement X, stiffness K (force -K X), and the fluid's response
over one step, u^{n+1} = a u^n + b f, with a = 1/(1 + dt c/rho_a) and b = dt/(rho_a + dt c) (added
mass rho_a, Stokes drag c: an unsteady Stokes mode). The filter spreads
    f~ = (f^n - theta dt K~ A u^n) / (1 + theta dt K~ B),   theta = min(1, dt K~ B / 0.1),
with estimates K~ = fk K, B = fb b, A = fa a of the true stiffness and response. The explicit force is
f~ = f^n. Each combination runs 3000 steps from X = 1; 'unstable' means |X| > 1e6.

Prints, for the explicit force and for the filter, how many of the (rho_a, c, K) regimes blow up, for
estimates that overestimate (fk, fb >= 1) and that underestimate. Usage: scripts/stiff_force_model.py
"""
import itertools


def run(rho_a, c, K, dt, fa, fb, fk, explicit=False, nsteps=3000):
    X, u = 1.0, 0.0
    a, b = 1 / (1 + dt * c / rho_a), dt / (rho_a + dt * c)
    A, B, Kt = a * fa, b * fb, K * fk
    th = min(1.0, dt * Kt * B / 0.1)
    for _ in range(nsteps):
        f = -K * X
        ft = f if explicit else (f - th * dt * Kt * A * u) / (1 + th * dt * Kt * B)
        u = a * u + b * ft
        X += dt * u
        if abs(X) > 1e6:
            return False
    return True


regimes = list(itertools.product([1e-4, 1e-2, 1, 100], [1e-3, 1, 10], [1, 10, 1e2, 1e3, 1e4, 1e6, 1e9]))
dt = 1e-2
print(f"{len(regimes)} regimes (added mass x drag x stiffness), dt = {dt}")
bad = sum(not run(*r, dt, 1, 1, 1, explicit=True) for r in regimes)
print(f"explicit force: {bad} unstable")
for name, fas, fbs, fks in [("overestimated K and B (fk, fb in {1, 1.5, 3, 10}, fa in {0, .5, 1, 1.5})",
                             [0, 0.5, 1, 1.5], [1, 1.5, 3, 10], [1, 1.5, 3, 10]),
                            ("underestimated B (fb = 0.5), K exact", [1], [0.5], [1]),
                            ("underestimated K (fk = 0.3), B exact", [1], [1], [0.3])]:
    tot = bad = 0
    for r in regimes:
        for fa, fb, fk in itertools.product(fas, fbs, fks):
            tot += 1
            bad += not run(*r, dt, fa, fb, fk)
    print(f"filter, {name}: {bad} unstable of {tot}")
