#!/usr/bin/python3
"""The stiff-force filter (coupling/stiff_force.hpp) on one membrane mode, a model of its stability.

One Fourier mode of the membrane: displacement X, stiffness K (force -K X), and the fluid's response
over one step, u^{n+1} = a u^n + b (f + g), with a = 1/(1 + dt c/rho_a) and b = dt/(rho_a + dt c)
(added mass rho_a, Stokes drag c: an unsteady Stokes mode; g a steady force of the rest of the flow).
The markers move by the trapezoidal rule, X^{n+1} = X^n + dt/2 (u^n + u^{n+1}) (Eqs. 56-60). The
filter spreads
    f~ = (f^n - theta dt K~ (A u^n + G)) / (1 + theta dt K~ B),   theta = min(1, dt K~ B / 0.1),
with estimates K~ = fk K, B = fb b, A = fa a of the true stiffness and response, and G the model's
residual, G <- G + w (u^n - A u^{n-1} - B f~^{n-1} - G) (w = 0: no residual, G = 0); with the
lagged gain (coupling/stiff_force.cpp) the weight is w min(1, 1 / (theta dt K~ B)) instead. The explicit
force is f~ = f^n. Each combination runs 3000 steps from X = 1; 'unstable' means |X| > 1e6.

Prints, for the explicit force and for the filter with w = 0, 0.2 and 1, and w = 0.2 lagged: how many of the
(rho_a, c, K) regimes blow up, for estimates that overestimate (fk, fb >= 1) and that underestimate;
and the steady displacement under a steady force g = 1 against the exact 1/K.
Usage: scripts/stiff_force_model.py
"""
import itertools


def run(rho_a, c, K, dt, fa, fb, fk, w=0.0, explicit=False, g=0.0, nsteps=3000, lag=False):
    X, u = 1.0, 0.0
    a, b = 1 / (1 + dt * c / rho_a), dt / (rho_a + dt * c)
    A, B, Kt = a * fa, b * fb, K * fk
    th = min(1.0, dt * Kt * B / 0.1)
    if lag and th * dt * Kt * B > 1:
        w = w / (th * dt * Kt * B)
    G, prev = 0.0, None
    for _ in range(nsteps):
        f = -K * X
        if prev is not None:
            G += w * (u - A * prev[0] - B * prev[1] - G)
        ft = f if explicit else (f - th * dt * Kt * (A * u + G)) / (1 + th * dt * Kt * B)
        prev = (u, ft)
        un = a * u + b * (ft + g)
        X += 0.5 * dt * (u + un)
        u = un
        if not abs(X) < 1e6:
            return None
    return X


regimes = list(itertools.product([1e-4, 1e-2, 1, 100], [1e-3, 1, 10], [1, 10, 1e2, 1e3, 1e4, 1e6, 1e9]))
dt = 1e-2
print(f"{len(regimes)} regimes (added mass x drag x stiffness), dt = {dt}, trapezoidal marker update")
bad = sum(run(*r, dt, 1, 1, 1, explicit=True) is None for r in regimes)
print(f"explicit force: {bad} unstable")
cases = [("exact estimates", [1], [1], [1]),
         ("overestimated K and B (fk, fb in {1, 1.5, 3, 10}, fa in {.5, 1, 1.5})",
          [0.5, 1, 1.5], [1, 1.5, 3, 10], [1, 1.5, 3, 10]),
         ("B at most 1.5x (fb in {1, 1.5}, fk in {1, 1.5, 3, 10}, fa in {.5, 1, 1.5})",
          [0.5, 1, 1.5], [1, 1.5], [1, 1.5, 3, 10]),
         ("underestimated B (fb = 0.5), K exact", [1], [0.5], [1]),
         ("underestimated K (fk = 0.3), B exact", [1], [1], [0.3])]
steady = [(1e-2, 1, 1e4), (1, 10, 1e6), (1e-4, 1e-3, 1e3)]
for w, lag in [(0.0, False), (0.2, False), (1.0, False), (0.2, True)]:
    print(f"filter, residual weight w = {w}{' lagged' if lag else ''}:")
    for name, fas, fbs, fks in cases:
        tot = bad = 0
        for r in regimes:
            for fa, fb, fk in itertools.product(fas, fbs, fks):
                tot += 1
                bad += run(*r, dt, fa, fb, fk, w, lag=lag) is None
        print(f"  {name}: {bad} unstable of {tot}")
    xs = [run(*r, dt, 1, 1, 1, w, g=1.0, nsteps=200000 if lag else 20000, lag=lag) * r[2] for r in steady]
    print("  steady K X under g = 1 (exact 1) at (rho_a, c, K) = " +
          ", ".join(f"{r}: {x:.6g}" for r, x in zip(steady, xs)))
