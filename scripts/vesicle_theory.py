#!/usr/bin/env python3
"""Fixed-shape models of a 2-D vesicle in simple shear (docs/vesicle_shear.md).

A fixed shape (an ellipse of half-axes a >= b at inclination theta, or any smooth closed curve) in the
unbounded Stokes shear u = (G y, 0) of viscosity mu, enclosing fluid of viscosity lambda mu. Its
membrane moves with a rigid rotation W and a tank-treading field of rate w that keeps the shape:

  ks            Keller & Skalak's field (J. Fluid Mech. 120, 27, 1982) written in two dimensions,
                w (-(a/b) y', (b/a) x') in body axes: a marker goes round in 2 pi / |w|, but its speed
                follows the parameter angle, so the membrane stretches and shrinks locally;
  inextensible  the field of a locally inextensible membrane on a steady shape: a uniform tangential
                speed v along the membrane, w = 2 pi v / L (L the perimeter). w is then exactly the
                markers' mean angular velocity about the centroid (sphib's m0_omega), at every instant.

Two conditions fix W and w (Keller & Skalak's): no torque on the membrane, and no generalised force
on the tank-treading mode, int f . u_tt ds = 0 (f the outer traction minus lambda times the inner
one): the membrane's tension does no work on an inextensible mode and its bending none on a fixed
shape. Both are linear in (W, w), so for an ellipse

    d theta / dt = W = G/2 (-1 + B(lambda, b/a) cos 2 theta),

tank-treading at cos 2 theta = 1/B when B >= 1, tumbling when B < 1. (The membrane's power balance,
outer work = inner dissipation, is quadratic in (W, w); its non-zero root is this one.) The
Keller-Skalak field's inside flow is linear and exact, so its resistance needs only the traction
moments of a rigid ellipse (class Resistance: 2-D Stokeslets on a shrunken confocal ellipse), checked
against the circle's exact torque 4 pi mu R^2 omega and stresslet 4 pi mu R^2 e and Jeffery's rotation
rate of a free rigid ellipse, k = (a^2 - b^2)/(a^2 + b^2). Any other field (the inextensible one) or
shape is solved by the method of fundamental solutions on both sides (class Shape: Stokeslets offset
along the normal inside for the outer flow, outside for the inner flow), checked against the moment
method on the Keller-Skalak field.

  vesicle_theory.py check                        # the checks above
  vesicle_theory.py angle --nu 0.8 --lam 1,2,3   # B, the tank-treading angle, w, lambda_c, both fields
  vesicle_theory.py shape RUN_DIR --lam 1        # the inextensible model on a run's last shape (G = mu = 1)
"""
import argparse
import functools
import math
import os
import sys

import numpy as np


def bisect(f, lo, hi, tol=1e-13):
    """The root of f in [lo, hi] (f(lo), f(hi) of opposite signs)."""
    flo = f(lo)
    while hi - lo > tol * max(1.0, abs(lo)):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


def perimeter(a, b, n=4096):
    """The ellipse's perimeter: the trapezoidal rule on the periodic integrand (spectrally accurate)."""
    t = 2 * np.pi * np.arange(n) / n
    return float(np.sqrt((a * np.sin(t)) ** 2 + (b * np.cos(t)) ** 2).sum() * 2 * np.pi / n)


def axes_for_reduced_area(nu):
    """Half-axes (a, b) of the ellipse of area pi (R0 = 1) and reduced area nu = 4 pi A / L^2."""
    def nu_of(r):  # r = b/a, a = 1
        L = perimeter(1.0, r)
        return 4.0 * math.pi * (math.pi * r) / (L * L)

    r = bisect(lambda r: nu_of(r) - nu, 1e-3, 1.0)
    a = 1.0 / math.sqrt(r)
    return a, a * r


class Resistance:
    """Outer flow of a rigid ellipse (axes along x, y) whose surface moves with boundary data U(x):
    Stokeslets F_k (forces on the fluid) at points inside; returns their sum and first moment."""

    def __init__(self, a, b, n=400, shrink=0.7):
        t = 2 * np.pi * (np.arange(n) + 0.5) / n
        self.xb = np.stack([a * np.cos(t), b * np.sin(t)], 1)            # collocation points
        # sources on a confocal-like inner curve
        c = math.sqrt(max(a * a - b * b, 0.0))
        s = np.arange(n) * 2 * np.pi / n
        if c > 0:
            mu0 = math.atanh(b / a) * shrink
            self.xs = np.stack([c * math.cosh(mu0) * np.cos(s), c * math.sinh(mu0) * np.sin(s)], 1)
        else:
            self.xs = np.stack([shrink * a * np.cos(s), shrink * a * np.sin(s)], 1)
        m = len(self.xb)
        A = np.zeros((2 * m, 2 * n))
        for i in range(2):
            for j in range(2):
                d = self.xb[:, None, :] - self.xs[None, :, :]
                r2 = (d ** 2).sum(-1)
                G = -0.5 * np.log(r2) * (i == j) + d[..., i] * d[..., j] / r2
                A[i::2, j::2] = G / (4 * np.pi)     # mu = 1
        # no net force
        C = np.zeros((2, 2 * n))
        C[0, 0::2] = 1.0
        C[1, 1::2] = 1.0
        self.A = np.vstack([A, 1e3 * C])
        self.area = np.pi * a * b

    def moments(self, Lgrad):
        """Boundary data (Lgrad) x; returns the first moment sum_k F_k,i x_k,j."""
        u = self.xb @ Lgrad.T
        rhs = np.concatenate([u.reshape(-1), np.zeros(2)])
        F, *_ = np.linalg.lstsq(self.A, rhs, rcond=None)
        F = F.reshape(-1, 2)
        self.residual = np.abs(self.A @ F.reshape(-1) - rhs).max()
        return F.T @ self.xs  # (i, j): sum F_i x_j

    def traction_moment(self, Lgrad):
        """M_ij = int f_i x_j ds on the body, f the traction of the outer fluid, for the outer flow whose
        disturbance has boundary data Lgrad x (far field 0): M = int_V sigma dV - sum F x, with the
        deviatoric part of int_V sigma dV = mu int (u n + n u) ds = 2 mu sym(Lgrad) area (mu = 1)."""
        P = self.moments(Lgrad)
        E = 0.5 * (Lgrad + Lgrad.T)
        return 2.0 * E * self.area - P


def rotation(w):
    return np.array([[0.0, -w], [w, 0.0]])


def strain12(e):
    return np.array([[0.0, e], [e, 0.0]])


def torque(M):
    return M[1, 0] - M[0, 1]  # int (x f_y - y f_x) ds


def ks_coefficients(a, b, lam, n=400):
    """B of d theta/dt = G/2 (-1 + B cos 2 theta) (G = 1), and the tank-treading rate per cos 2 theta."""
    R = Resistance(a, b, n)
    # Outer disturbance for the unit basis of the body-frame gradient (G - L): rotation, 12-strain.
    Mw = R.traction_moment(rotation(1.0))     # (G-L) = rotation rate 1: the body lags the fluid
    Me = R.traction_moment(strain12(1.0))
    # The ambient flow's own traction moment on the body: uniform stress 2 mu E_G, int sigma n x = sigma A.
    # Unknowns: body rotation W (= d theta/dt) and tank-treading rate wt; body-frame data at theta with
    # G = 1: ambient rotation -1/2, ambient 12-strain e = cos(2 theta)/2 (the 11-strain does no work on
    # the tank-treading mode and gives no torque, by symmetry). L = rotation(W + wt (a/b + b/a)/2)
    # + strain12(-wt (a^2 - b^2)/(2 a b)).
    c_rot = (a / b + b / a) / 2
    c_str = -(a * a - b * b) / (2 * a * b)

    Ltt = rotation(c_rot) + strain12(c_str)   # the tank-treading mode at rate 1: u_tt = Ltt x

    def residuals(W, wt, e):
        Om = -0.5 - (W + wt * c_rot)          # ambient minus membrane rotation
        Es = e - wt * c_str                    # ambient minus membrane 12-strain
        M = -(Om * Mw + Es * Me) + 2.0 * strain12(e) * R.area  # disturbance (data (L - G) x) + ambient stress
        T = torque(M)
        EL = strain12(wt * c_str)
        # generalised force on the mode: int u_tt . (f_out - lambda f_in) ds, f_in = 2 mu E_L n (the inner
        # flow L x is linear): int (Ltt x) . f ds = Ltt_ij M_ij, and int (Ltt x) . 2 EL n ds = 2 Ltt:EL area
        Q = np.sum(Ltt * M) - 2.0 * lam * np.sum(Ltt * EL) * R.area
        return T, Q

    # Linear in (W, wt) for a given e: solve from three evaluations.
    def solve(e):
        r0 = np.array(residuals(0.0, 0.0, e))
        r1 = np.array(residuals(1.0, 0.0, e)) - r0
        r2 = np.array(residuals(0.0, 1.0, e)) - r0
        return np.linalg.solve(np.stack([r1, r2], 1), -r0)

    W0, wt0 = solve(0.0)   # theta = 45 degrees
    W1, wt1 = solve(0.5)   # theta = 0
    # d theta/dt = W = -1/2 + (B/2) cos 2 theta  ->  B = 2 (W1 - W0)
    return 2.0 * (W1 - W0), W0, wt1 - wt0, R.residual


def ks_power_residual(a, b, lam, W, wt, e, n=400):
    """The membrane's power balance, outer work minus lambda times the inner dissipation, for the
    Keller-Skalak field at (W, wt) and body-frame 12-strain e: zero at a solution of ks_coefficients."""
    R = Resistance(a, b, n)
    Mw, Me = R.traction_moment(rotation(1.0)), R.traction_moment(strain12(1.0))
    c_rot, c_str = (a / b + b / a) / 2, -(a * a - b * b) / (2 * a * b)
    M = -((-0.5 - (W + wt * c_rot)) * Mw + (e - wt * c_str) * Me) + 2.0 * strain12(e) * R.area
    EL, WL = strain12(wt * c_str), rotation(W + wt * c_rot)
    return float(np.sum((EL + WL) * M) - 2.0 * lam * np.sum(EL * EL) * R.area)


# ---- Any field, any shape: the method of fundamental solutions on both sides of the membrane ----

def _stokeslets(d, nrm):
    """Velocity G (u_i = G_ij F_j) and traction K (t_i = K_ij F_j on normal nrm) at offsets d from 2-D
    Stokeslets of force F on the fluid, mu = 1: G = (-delta ln r + r r / r^2) / (4 pi),
    sigma_ik = -(1/pi) r_i r_j r_k F_j / r^4 (Pozrikidis 1992, Eq. 2.6.8 and 2.6.10 in 2-D)."""
    r2 = (d ** 2).sum(-1)
    G = d[..., :, None] * d[..., None, :] / r2[..., None, None]
    G[..., 0, 0] -= 0.5 * np.log(r2)
    G[..., 1, 1] -= 0.5 * np.log(r2)
    K = -(1 / np.pi) * d[..., :, None] * d[..., None, :] * ((d * nrm).sum(-1) / r2 ** 2)[..., None, None]
    m, k = d.shape[0], d.shape[1]
    flat = lambda A: A.transpose(0, 2, 1, 3).reshape(2 * m, 2 * k)  # (x0, y0, x1, y1, ...) ordering
    return flat(G / (4 * np.pi)), flat(K)


class Shape:
    """A smooth closed curve (anticlockwise): n points x, their tangent derivative dx (any parameter,
    uniform steps), and the offset of the sources along the normal. Gives the outer traction of the
    decaying outer flow with given boundary data and the inner traction of the inner flow with given
    boundary data (both on the outward normal; mu = 1)."""

    def __init__(self, x, dx, offset):
        n = len(x)
        sp = np.sqrt((dx ** 2).sum(1))
        self.x, self.t = x, dx / sp[:, None]
        self.n = np.stack([self.t[:, 1], -self.t[:, 0]], 1)  # outward
        self.ds = sp * 2 * np.pi / n                          # trapezoidal weights (periodic: spectral)
        self.length = float(self.ds.sum())
        G, K = _stokeslets(x[:, None] - (x - offset[:, None] * self.n)[None], self.n[:, None])
        C = np.zeros((2, 2 * n))
        C[0, 0::2] = C[1, 1::2] = 1.0   # no net force: the outer disturbance decays
        self._out = K @ np.linalg.pinv(np.vstack([G, 1e3 * C]), rcond=1e-13)
        G, K = _stokeslets(x[:, None] - (x + offset[:, None] * self.n)[None], self.n[:, None])
        self._in = K @ np.linalg.pinv(G, rcond=1e-13)

    def traction_out(self, data):
        return (self._out @ np.concatenate([data.reshape(-1), [0.0, 0.0]])).reshape(-1, 2)

    def traction_in(self, data):
        return (self._in @ data.reshape(-1)).reshape(-1, 2)


def ellipse_shape(a, b, n=300, theta=0.0, offset=0.3):
    """The ellipse x = (a cos t, b sin t) turned by theta, n points uniform in t; sources offset by
    offset times the local radius of curvature (at most offset b)."""
    t = 2 * np.pi * (np.arange(n) + 0.5) / n
    c, s = math.cos(theta), math.sin(theta)
    Rm = np.array([[c, -s], [s, c]])
    x = np.stack([a * np.cos(t), b * np.sin(t)], 1) @ Rm.T
    dx = np.stack([-a * np.sin(t), b * np.cos(t)], 1) @ Rm.T
    rc = np.sqrt((dx ** 2).sum(1)) ** 3 / (a * b)
    return Shape(x, dx, offset * np.minimum(rc, b))


def markers_shape(X, n=400, modes=24, offset=0.3):
    """A smooth curve through markers X (anticlockwise): their Fourier series in the marker index up to
    `modes`, n points, about the centroid of its enclosed area. Returns the Shape and that area."""
    m = len(X)
    c = np.fft.fft(X[:, 0] + 1j * X[:, 1]) / m
    k = np.fft.fftfreq(m, 1.0 / m)
    keep = np.abs(k) <= modes
    E = np.exp(1j * np.outer(2 * np.pi * (np.arange(n) + 0.5) / n, k[keep]))
    z, dz, ddz = E @ c[keep], E @ (1j * k[keep] * c[keep]), E @ (-(k[keep] ** 2) * c[keep])
    w = 2 * np.pi / n
    area = 0.5 * float(np.sum(z.real * dz.imag - z.imag * dz.real)) * w
    z = z - complex(0.5 * np.sum(z.real ** 2 * dz.imag) * w / area, -0.5 * np.sum(z.imag ** 2 * dz.real) * w / area)
    curv = np.abs((np.conj(dz) * ddz).imag) / np.abs(dz) ** 3
    off = offset * np.minimum(1.0 / np.maximum(curv, 1e-12), 1.0)
    return Shape(np.stack([z.real, z.imag], 1), np.stack([dz.real, dz.imag], 1), off), area


def tank_treading_field(S, field, ab=None, theta=0.0):
    """The tank-treading mode at rate 1 on shape S: 'inextensible' (uniform tangential speed
    L / (2 pi): the markers' mean angular velocity 1) or 'ks' (the ellipse (a, b) = ab turned by theta)."""
    if field == "inextensible":
        return S.t * (S.length / (2 * np.pi))
    a, b = ab
    c, s = math.cos(theta), math.sin(theta)
    xb = S.x @ np.array([[c, -s], [s, c]])   # body axes
    u = np.stack([-(a / b) * xb[:, 1], (b / a) * xb[:, 0]], 1)
    return u @ np.array([[c, -s], [s, c]]).T


def fixed_shape_motion(S, lam, tt, grad):
    """(W, w): the rotation rate and tank-treading rate of the fixed shape S whose membrane moves with
    W z x x + w tt, in the ambient flow u = grad x (mu = 1, inside lambda): no torque, no force on tt."""
    x = S.x
    rot = np.stack([-x[:, 1], x[:, 0]], 1)
    E = 0.5 * (grad + grad.T)

    def res(W, w):
        ub = W * rot + w * tt
        f = S.traction_out(ub - x @ grad.T) + S.n @ (2.0 * E).T - lam * S.traction_in(ub)
        return np.array([((x[:, 0] * f[:, 1] - x[:, 1] * f[:, 0]) * S.ds).sum(), ((tt * f).sum(1) * S.ds).sum()])

    r0 = res(0.0, 0.0)
    W, w = np.linalg.solve(np.stack([res(1.0, 0.0) - r0, res(0.0, 1.0) - r0], 1), -r0)
    return float(W), float(w)


@functools.lru_cache(maxsize=8)
def _ellipse_and_fields(a, b, n):
    S = ellipse_shape(a, b, n)
    return S, {f: tank_treading_field(S, f, (a, b)) for f in ("inextensible", "ks")}


def coefficients(a, b, lam, field="inextensible", n=300):
    """B of d theta/dt = G/2 (-1 + B cos 2 theta) (G = 1), W at 45 degrees, and the tank-treading rate w
    per cos 2 theta, for the ellipse (a, b) with the given field, by the method of fundamental solutions
    (body frame: ambient rotation -1/2 and 12-strain cos(2 theta)/2; the 11-strain gives neither torque
    nor force on the mode, by symmetry)."""
    S, tt = _ellipse_and_fields(a, b, n)
    W0, w0 = fixed_shape_motion(S, lam, tt[field], rotation(-0.5) + strain12(0.0))
    W1, w1 = fixed_shape_motion(S, lam, tt[field], rotation(-0.5) + strain12(0.5))
    return 2.0 * (W1 - W0), W0, w1 - w0


def lambda_c(a, b, field="inextensible"):
    """The viscosity ratio at which B = 1 (B falls with lambda)."""
    if field == "ks_moments":
        return bisect(lambda l: ks_coefficients(a, b, l, 200)[0] - 1.0, 0.01, 1e3, 1e-6)
    return bisect(lambda l: coefficients(a, b, l, field)[0] - 1.0, 0.01, 1e3, 1e-6)


def check():
    ok = True
    R = Resistance(1.0, 1.0, 200)
    M = R.traction_moment(-rotation(1.0))   # disturbance data (L - G) x, L = 0, G = rotation
    t = torque(M)
    print(f"circle R=1, fluid rotating at 1 about a fixed circle: torque {t:.6f} (exact 4 pi = {4*np.pi:.6f})")
    ok &= abs(t / (4 * np.pi) - 1) < 1e-6
    M = R.traction_moment(-strain12(1.0)) + 2.0 * strain12(1.0) * R.area   # plus the ambient stress
    S = 0.5 * (M + M.T)[0, 1]   # Batchelor's stresslet of a rigid body: u = 0 on it (2-D disks: [eta] = 2)
    print(f"circle R=1 in the strain e12=1: stresslet {S:.6f} (exact 4 pi = {4*np.pi:.6f})")
    ok &= abs(S / (4 * np.pi) - 1) < 1e-6
    for a, b in [(2.0, 1.0), (1.5, 0.5)]:
        R = Resistance(a, b, 400)
        Mw, Me = R.traction_moment(rotation(1.0)), R.traction_moment(strain12(1.0))
        # free rigid ellipse: torque(Om Mw + e Me) = 0 with Om = -1/2 - W, e = cos 2theta/2
        k_num = torque(Me) / torque(Mw)
        k = (a * a - b * b) / (a * a + b * b)
        print(f"ellipse {a}x{b}: Jeffery k {k_num:.6f} (exact {k:.6f})")
        ok &= abs(k_num - k) < 1e-6
    # the solution makes the membrane's power balance vanish (its non-zero root)
    a, b = axes_for_reduced_area(0.8)
    B, W0, dwt, _ = ks_coefficients(a, b, 1.0)
    c2 = 1.0 / B
    P = ks_power_residual(a, b, 1.0, 0.0, dwt * c2, c2 / 2)
    print(f"nu 0.8, lambda 1, Keller-Skalak field: power balance at the tank-treading solution {P:.2e} (exact 0)")
    ok &= abs(P) < 1e-8
    # both methods on the Keller-Skalak field
    Bm = coefficients(a, b, 1.0, "ks")[0]
    print(f"nu 0.8, lambda 1, Keller-Skalak field: B {B:.6f} (traction moments), {Bm:.6f} (fundamental solutions)")
    ok &= abs(Bm - B) < 1e-6
    # a free rigid ellipse with the fundamental solutions: its torque-free rotation at theta = 0
    S = ellipse_shape(2.0, 1.0, 300)
    x = S.x
    rot, grad = np.stack([-x[:, 1], x[:, 0]], 1), rotation(-0.5) + strain12(0.5)

    def tq(W):
        f = S.traction_out(W * rot - x @ grad.T) + S.n @ (grad + grad.T).T
        return ((x[:, 0] * f[:, 1] - x[:, 1] * f[:, 0]) * S.ds).sum()

    W = -tq(0.0) / (tq(1.0) - tq(0.0))
    print(f"ellipse 2x1, rigid, fundamental solutions: d theta/dt at theta = 0 {W:.6f} (Jeffery {-(1 - 0.6) / 2:.6f})")
    ok &= abs(W + 0.2) < 1e-6
    print("checks", "pass" if ok else "FAIL")
    return ok


def shape_of_run(run, lam, modes=24, n=400):
    """The inextensible model (W, w) on the last membrane shape of a run's output.h5, in the unbounded
    shear u = (y, 0) (G = mu = 1), and that shape's inclination (second moments of its area)."""
    import h5py
    with h5py.File(os.path.join(run, "output.h5"), "r") as f:
        last = sorted(f["snapshots"].keys())[-1]
        X = f["snapshots"][last]["membrane_0"]["X"][()]
    S, area = markers_shape(X, n, modes)
    w = 2 * np.pi / n
    x, dx = S.x, S.t * (S.ds / w)[:, None]
    Jxx = np.sum(x[:, 1] ** 3 * (-dx[:, 0])) * w / 3   # int y^2 dA by Green's theorem
    Jyy = np.sum(x[:, 0] ** 3 * dx[:, 1]) * w / 3      # int x^2 dA
    Jxy = np.sum(x[:, 0] ** 2 * x[:, 1] * dx[:, 1]) * w / 2   # int x y dA
    theta = 0.5 * math.atan2(2 * Jxy, Jyy - Jxx)
    W, om = fixed_shape_motion(S, lam, tank_treading_field(S, "inextensible"), rotation(-0.5) + strain12(0.5))
    return W, om, math.degrees(theta), area


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["check", "angle", "points", "shape"])
    ap.add_argument("runs", nargs="*", help="shape: run directories (their output.h5's last snapshot)")
    ap.add_argument("--r0", type=float, default=0.4, help="points: effective radius sqrt(A/pi)")
    ap.add_argument("--n", type=int, default=128, help="points: how many (uniform in the ellipse's parameter)")
    ap.add_argument("--nu", type=float, default=0.8, help="reduced area 4 pi A / L^2")
    ap.add_argument("--lam", default="1,2,3,5,8", help="viscosity ratios (comma-separated; shape: one)")
    a = ap.parse_args()
    if a.what == "check":
        sys.exit(0 if check() else 1)
    if a.what == "shape":
        lam = float(a.lam.split(",")[0])
        missing = [r for r in a.runs if not os.path.exists(os.path.join(r, "output.h5"))]
        if missing or not a.runs:
            sys.exit(f"vesicle_theory.py shape: no output.h5 in {', '.join(missing) or '(no run given)'}")
        for run in a.runs:
            W, om, th, area = shape_of_run(run, lam)
            print(f"{run}: shape at {th:.3f} degrees, area {area:.6f}; unbounded, lambda {lam:g}: "
                  f"d theta/dt {W:.5f}, markers' mean angular velocity {om:.5f}")
        return
    ax, bx = axes_for_reduced_area(a.nu)
    if a.what == "points":  # the membrane.points of cases/vesicle_shear.toml (anticlockwise, long axis along x)
        t = 2 * np.pi * np.arange(a.n) / a.n
        print(f"# ellipse of reduced area {a.nu}, R0 = {a.r0}: half-axes {a.r0 * ax:.7f} x {a.r0 * bx:.7f}, "
              f"{a.n} points uniform in its parameter")
        print("points = [")
        for x, y in zip(a.r0 * ax * np.cos(t), a.r0 * bx * np.sin(t)):
            print(f"  [{x:.10f}, {y:.10f}],")
        print("]")
        return
    print(f"nu = {a.nu}: b/a = {bx/ax:.5f} (R0 = 1: a = {ax:.5f}, b = {bx:.5f}, L = {perimeter(ax, bx):.5f})")
    for field in ("inextensible", "ks"):
        print(f"{field} field: lambda_c = {lambda_c(ax, bx, field):.4f} (B = 1: tank-treading below, tumbling above)")
        print(f"{'lambda':>7} {'B':>8} {'theta_deg':>9} {'omega/G':>8} {'TT period G T':>13}")
        for lam in [float(x) for x in a.lam.split(",")]:
            B, W0, dw = coefficients(ax, bx, lam, field)
            if B >= 1:
                th = 0.5 * math.degrees(math.acos(1.0 / B))
                w = dw / B   # at cos 2 theta = 1/B: the markers' (time-)mean angular velocity
                print(f"{lam:7g} {B:8.5f} {th:9.3f} {w:8.5f} {2 * math.pi / abs(w):13.3f}")
            else:  # tumbling: d theta/dt = (-1 + B cos 2 theta)/2, period 2 pi / sqrt(1 - B^2) per half-turn pi
                print(f"{lam:7g} {B:8.5f} {'tumbling':>9}   period of a half turn G T = {2 * math.pi / math.sqrt(1 - B * B):.3f}")

if __name__ == "__main__":
    main()
