#!/usr/bin/env python3
"""The 2-D Keller-Skalak model of a vesicle in simple shear (docs/vesicle_shear.md).

A fixed ellipse (half-axes a >= b, inclination theta to the flow) whose membrane tank-treads with
the shape-keeping field w = omega_t (-(a/b) y', (b/a) x') (body axes x', y'), enclosing fluid of
viscosity lambda mu, in the unbounded shear u = (G y, 0) of viscosity mu, Stokes flow. This is
Keller & Skalak's (J. Fluid Mech. 120, 27, 1982) fixed-shape model written in two dimensions, the
model that Messlinger, Schmidt, Noguchi & Gompper (Phys. Rev. E 80, 011901, 2009) extend to
deformable 2-D vesicles. The inside flow is the linear field L x (rotation and tank-treading),
exactly Stokes; the outside flow is that of a rigid ellipse held in the linear flow (G - L) x.
Two conditions fix d theta/dt and omega_t: no torque on the membrane, and the power the outer
fluid gives the membrane equal to the inner fluid's dissipation (the membrane stores none at a
fixed shape). Both are linear, so

    d theta / dt = G/2 (-1 + B cos 2 theta),

tank-treading at cos 2 theta = 1/B when B >= 1, tumbling when B < 1. The outer problem's
resistance (torque and first traction moment of a rigid ellipse in rotation and strain) is
computed here by the method of fundamental solutions (2-D Stokeslets on a shrunken ellipse),
checked against the circle's exact torque 4 pi mu R^2 omega and stresslet 4 pi mu R^2 e and against
Jeffery's rotation rate of a free rigid ellipse, k = (a^2 - b^2)/(a^2 + b^2).

  vesicle_theory.py check                     # the checks above
  vesicle_theory.py angle --nu 0.8 --lam 1,2,3   # B, the tank-treading angle, lambda_c
"""
import argparse
import math
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

    def residuals(W, wt, e):
        Om = -0.5 - (W + wt * c_rot)          # ambient minus membrane rotation
        Es = e - wt * c_str                    # ambient minus membrane 12-strain
        M = -(Om * Mw + Es * Me) + 2.0 * strain12(e) * R.area  # disturbance (data (L - G) x) + ambient stress
        T = torque(M)
        EL = strain12(wt * c_str)
        WL = rotation(W + wt * c_rot)
        P_out = np.sum((EL + WL) * M)          # int f . (L x) ds = L_ij M_ij
        P_in = 2.0 * lam * np.sum(EL * EL) * R.area
        return T, P_out - P_in

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
    print("checks", "pass" if ok else "FAIL")
    return ok


def marker_mean_angular_velocity(a, b, wt, n=4096):
    """The mean over markers uniform in arclength of (X x U)/|X|^2 (sphib's m0_omega) for the
    tank-treading field U = wt (-a sin phi, b cos phi) at X = (a cos phi, b sin phi), body at rest."""
    phi = 2 * np.pi * (np.arange(n) + 0.5) / n
    w = np.sqrt((a * np.sin(phi)) ** 2 + (b * np.cos(phi)) ** 2)   # ds/dphi
    ang = wt * a * b / ((a * np.cos(phi)) ** 2 + (b * np.sin(phi)) ** 2)
    return float((ang * w).sum() / w.sum())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["check", "angle", "points"])
    ap.add_argument("--r0", type=float, default=0.4, help="points: effective radius sqrt(A/pi)")
    ap.add_argument("--n", type=int, default=128, help="points: how many (uniform in the ellipse's parameter)")
    ap.add_argument("--nu", type=float, default=0.8, help="reduced area 4 pi A / L^2")
    ap.add_argument("--lam", default="1,2,3,5,8", help="viscosity ratios (comma-separated)")
    a = ap.parse_args()
    if a.what == "check":
        sys.exit(0 if check() else 1)
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
    # lambda_c: B(lambda) = 1; B falls with lambda
    lc = bisect(lambda l: ks_coefficients(ax, bx, l, 200)[0] - 1.0, 0.01, 1e3, 1e-6)
    print(f"lambda_c = {lc:.4f} (B = 1: tank-treading below, tumbling above)")
    print(f"{'lambda':>7} {'B':>8} {'theta_deg':>9} {'omega_t/G':>10} {'omega_markers/G':>15} {'TT period G T':>13}")
    for lam in [float(x) for x in a.lam.split(",")]:
        B, W0, dwt, res = ks_coefficients(ax, bx, lam)
        th = 0.5 * math.degrees(math.acos(1.0 / B)) if B >= 1 else float("nan")
        if B >= 1:
            wt = dwt * math.cos(math.radians(2 * th))
            wm = marker_mean_angular_velocity(ax, bx, wt)
            print(f"{lam:7g} {B:8.5f} {th:9.3f} {wt:10.5f} {wm:15.5f} {2 * math.pi / abs(wt):13.3f}")
        else:  # tumbling: d theta/dt = (-1 + B cos 2 theta)/2, period 2 pi / sqrt(1 - B^2) per half-turn pi
            print(f"{lam:7g} {B:8.5f} {'tumbling':>9}   period of a half turn G T = {2 * math.pi / math.sqrt(1 - B * B):.3f}")


if __name__ == "__main__":
    main()
