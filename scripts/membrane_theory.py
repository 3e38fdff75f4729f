#!/usr/bin/python3
"""Linear theory of a nearly circular elastic membrane in a viscous fluid (2-D, one viscosity).

The derivation is in docs/membrane_validation.md ("Linear theory"). A circle of radius R carries a
tension Tbar (prestress), a stretching modulus E (small-strain dT/d(strain), strain measured on the
current circle: E = lambda dT/dlambda of the law at the circle's stretch lambda) and a bending modulus
Eb. A mode-n perturbation, outward displacement rho e^{i n theta} and tangential eta e^{i n theta},
meets the force per unit length (outward, tangential) f = -K (rho, eta) with
    K = 1/R^2 [[E + Tbar (n^2 - 1) + Eb (n^2 - 1)^2 / R^2,  i n E],
               [-i n E,                                      n^2 E]]
and the fluid moves the membrane with u = M f:
    Stokes:  M = R / (4 mu (n^2 - 1)) [[n, -i], [i, n]]
    unsteady Stokes (time dependence e^{s t}, q^2 = s rho/mu, x = q R, I_n, K_n modified Bessel):
        M_rr = n (1 - 2 n I_n K_n) / (2 R mu q^2),   M_rt = -M_tr = i n (I_n K_n)'(x) / (2 mu q),
        M_tt = -(2 R q^2 I_n'(x) K_n'(x) + n / R) / (2 mu q^2)      (' = d/dx)
The membrane moves with the fluid, s (rho, eta) = u, so the modes are the roots of
det(s I + M(s) K) = 0.

Usage (prints the numbers the validation gallery quotes):
  membrane_theory.py oscillation [--R .. --r0 .. --T0 .. --mu .. --rho .. --n 2]
  membrane_theory.py relaxation  [--R .. --E .. --Eb .. --Tbar .. --mu .. --rho .. --n 2]
  membrane_theory.py capsule     [--cab 0.1,0.2,...]   (bending capillary number mu G R^3 / Eb)
"""
import argparse
import math
import sys

import mpmath as mp


def stiffness(n, R, E, Tbar, Eb):
    """K (force per unit length on (outward, tangential) displacements), 2x2 complex."""
    m2 = n * n - 1
    return [[(E + Tbar * m2 + Eb * m2 * m2 / R**2) / R**2, 1j * n * E / R**2],
            [-1j * n * E / R**2, n * n * E / R**2]]


def stokes_mobility(n, R, mu):
    c = R / (4 * mu * (n * n - 1))
    return [[c * n, -1j * c], [1j * c, c * n]]


def mobility(n, R, mu, rho, s):
    """Unsteady Stokes mobility of mode n on a circle of radius R, equal fluids inside and outside."""
    s = mp.mpc(s)
    q = mp.sqrt(s * rho / mu)  # principal branch: Re q > 0, K_n decays outside
    x = q * R
    In, Kn = mp.besseli(n, x), mp.besselk(n, x)
    Ip = mp.besseli(n - 1, x) - n / x * In  # I_n' and K_n' by their recurrences (mpmath's besselk
    Kp = -mp.besselk(n - 1, x) - n / x * Kn  # ignores derivative=)
    q2 = q * q
    Mrr = n * (1 - 2 * n * In * Kn) / (2 * R * mu * q2)
    Mrt = 1j * n * (In * Kp + Ip * Kn) / (2 * mu * q)
    Mtt = (-2 * R * q2 * Ip * Kp - n / R) / (2 * mu * q2)
    return [[Mrr, Mrt], [-Mrt, Mtt]]


def characteristic(n, R, mu, rho, E, Tbar, Eb):
    K = stiffness(n, R, E, Tbar, Eb)

    def det(s):
        M = mobility(n, R, mu, rho, s)
        A = [[s + sum(M[i][k] * K[k][j] for k in range(2)) if i == j else sum(M[i][k] * K[k][j] for k in range(2))
              for j in range(2)] for i in range(2)]
        return A[0][0] * A[1][1] - A[0][1] * A[1][0]
    return det


def root(n, R, mu, rho, E, Tbar, Eb, guess):
    mp.mp.dps = 30
    return complex(mp.findroot(characteristic(n, R, mu, rho, E, Tbar, Eb), mp.mpc(guess), solver="muller"))


def stokes_rates(n, R, mu, E, Tbar, Eb):
    """The two decay rates of mode n in Stokes flow: bending/prestress (the length-keeping mode
    rho + i n eta = 0) and stretching."""
    return n * ((n * n - 1) * Eb / R**2 + Tbar) / (4 * mu * R), n * E / (4 * mu * R)


def capsule(cab):
    """Small-deformation capsule with bending in simple shear (Stokes, one viscosity), circle
    reference at rest: D and the inclination (degrees) for the bending capillary number
    Ca_b = mu G R^3 / Eb. D = Ca_b / sqrt(9 + 4 Ca_b^2), theta = 45 - atan(2 Ca_b / 3)/2."""
    return cab / math.sqrt(9 + 4 * cab * cab), 45 - math.degrees(math.atan(2 * cab / 3)) / 2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", choices=["oscillation", "relaxation", "capsule"])
    ap.add_argument("--n", type=int, default=2)
    ap.add_argument("--R", type=float, help="radius of the circle (oscillation: sqrt(rx ry))")
    ap.add_argument("--r0", type=float, default=0.5, help="oscillation: rest radius (Hookean)")
    ap.add_argument("--rx", type=float, default=0.75)
    ap.add_argument("--ry", type=float, default=0.5)
    ap.add_argument("--T0", type=float, default=10.0)
    ap.add_argument("--E", type=float, default=0.0, help="relaxation: stretching modulus lambda dT/dlambda")
    ap.add_argument("--Tbar", type=float, default=0.0)
    ap.add_argument("--Eb", type=float, default=0.0)
    ap.add_argument("--mu", type=float, default=0.1)
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--cab", default="0.005,0.01,0.02,0.05,0.1,0.2,0.5,1")
    a = ap.parse_args()
    if a.case == "capsule":
        print("Ca_b        D         D/Ca_b    theta_deg")
        for c in (float(v) for v in a.cab.split(",")):
            D, th = capsule(c)
            print(f"{c:<10g}  {D:.6f}  {D / c:.6f}  {th:.4f}")
        return
    if a.case == "oscillation":
        R = a.R if a.R else math.sqrt(a.rx * a.ry)  # the circle of the ellipse's area
        lam = R / a.r0
        E, Tbar, Eb = a.T0 * lam, a.T0 * (lam - 1), a.Eb  # Hookean: T = T0 (lambda - 1), E = lambda dT/dlambda
        # inviscid guess: omega^2 = stiffness / added mass, refined by the root finder
        Kst = (E + Tbar * (a.n**2 - 1)) / R**2
        guess = complex(-0.1, math.sqrt(max(Kst * a.n / (2 * a.rho * R), 1e-6)))
        s = root(a.n, R, a.mu, a.rho, E, Tbar, Eb, guess)
        print(f"mode {a.n}: R = {R:.6f}, E = {E:.6f}, Tbar = {Tbar:.6f}, Eb = {Eb:g}, mu = {a.mu:g}, rho = {a.rho:g}")
        print(f"s = {s.real:.6f} {s.imag:+.6f} i: period {2 * math.pi / abs(s.imag):.6f}, "
              f"amplitude decay per period {math.exp(s.real * 2 * math.pi / abs(s.imag)):.6f}, "
              f"per half period {math.exp(s.real * math.pi / abs(s.imag)):.6f}")
        return
    R = a.R if a.R else 0.5
    sb, ss = stokes_rates(a.n, R, a.mu, a.E, a.Tbar, a.Eb)
    print(f"mode {a.n}: Stokes rates: bending/prestress {sb:.6f}, stretching {ss:.6f}")
    if a.rho > 0:  # the inertial correction of the slow (overdamped) rate: the root just off the real axis
        try:
            s = root(a.n, R, a.mu, a.rho, a.E, a.Tbar, a.Eb, complex(-sb, 1e-3 * sb))
            print(f"unsteady Stokes (rho = {a.rho:g}): s = {s.real:.6f} {s.imag:+.6f} i")
        except Exception as e:  # an overdamped mode sits on the branch cut of the unsteady problem
            print(f"unsteady Stokes (rho = {a.rho:g}): no root found near -{sb:.4f} ({str(e)[:60]})")


if __name__ == "__main__":
    sys.exit(main())
