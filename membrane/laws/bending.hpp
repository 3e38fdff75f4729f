#pragma once
// Helfrich-Canham bending of a closed curve in 2-D: E_b = Eb/2 int (kappa - kappa0)^2 dl (Canham 1970,
// J. Theor. Biol. 26, 61; Helfrich 1973, Z. Naturforsch. 28c, 693, reduced to a curve), kappa0 the
// reference's curvature at each material point or a uniform spontaneous curvature. Combined with any
// tension law by membrane/force.cpp.
//
// Its force per unit label s, f_b = -dE_b/dX, in the divergence form of the tension's (Eq. 50):
// with |X_s| = g, kappa = (X_s x X_ss)/g^3, tau = X_s/g, n = tau rotated by +90 degrees (inward on an
// anticlockwise curve) and the bending moment m = Eb (kappa - kappa0),
//   dE_b = int [m dkappa g + Eb/2 (kappa - kappa0)^2 dg] ds
// with dkappa = (dX_s x X_ss + X_s x dX_ss)/g^3 - 3 kappa dg/g and dg = tau . dX_s; integrating
// dX_ss by parts and splitting X_ss = g_s tau + kappa g^2 n leaves
//   f_b = d/ds [ T_b tau + Q n ],   T_b = -(m/2)(kappa + kappa0) = -Eb/2 (kappa^2 - kappa0^2),
//                                   Q = -(1/g) dm/ds   (the transverse shear, -dm/dl).
// Check: a circle of radius R with kappa0 = 0 has Q = 0, T_b = -Eb/(2R^2), so f_b = -Eb/(2R^3) n per
// unit length, outward, = -(dE_b/dR)/(2 pi R) with E_b = pi Eb/R.

namespace sphib {

inline double bending_moment(double Eb, double kappa, double kappa0) { return Eb * (kappa - kappa0); }
inline double bending_tension(double m, double kappa, double kappa0) { return -0.5 * m * (kappa + kappa0); }
inline double bending_energy_density(double Eb, double kappa, double kappa0) {
  return 0.5 * Eb * (kappa - kappa0) * (kappa - kappa0);  // per unit current length
}

}  // namespace sphib
