#pragma once
// What a membrane is made of: a tension law T(lambda) of the stretch, an optional bending
// stiffness, and the reference (stress-free) state both are measured from.
//
// The membrane is a closed curve X(s) with a Lagrangian label s in [0, L0) (markers at s_k = k L0/nb).
// Its reference state X_ref(s) has the metric a(s) = |X_ref,s| and curvature kappa0(s); the stretch
// is lambda = |X_s| / a. With the strain energy W(lambda) per unit reference length the elastic
// energy is E = int W(lambda) a ds + Eb/2 int (kappa - kappa0)^2 |X_s| ds, and its force density per
// unit label, f = -dE/dX, is (membrane/force.hpp)
//   f = d/ds [ (T(lambda) - Eb/2 (kappa^2 - kappa0^2)) tau - (1/|X_s|) d/ds (Eb (kappa - kappa0)) n ],
// T = dW/dlambda (Eqs. 47-50 of the paper for the Hookean law, with a = 1 and Eb = 0).
//
// A tension law is three functions of lambda. A new law is one file in membrane/laws/ with its
// LawInfo, one line in the registry (law.cpp) and its test.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "membrane/spline.hpp"  // Vec, Mat2

namespace sphib {

/// The contract of a tension law: W, T = dW/dlambda and dT/dlambda at the stretch lambda > 0.
class TensionLaw {
 public:
  virtual ~TensionLaw() = default;
  virtual double energy(double lambda) const = 0;      // W(lambda), per unit reference length
  virtual double tension(double lambda) const = 0;     // T(lambda) = W'(lambda), a force
  virtual double stiffness(double lambda) const = 0;   // dT/dlambda (the stable step, the stiff-force filter)
};

/// A parameter of a law beyond Es (e.g. Skalak's C): the scene key membrane.<name>.
struct LawParam {
  std::string name, help;
  double value = 0.0, min = 0.0, max = 1e300;
};

/// One entry of the registry: the law's name (the scene's membrane.law), what it is, its source, its
/// own parameters and how to make it from the modulus Es and those parameters.
struct LawInfo {
  std::string name, help;
  std::vector<LawParam> params;
  std::function<std::unique_ptr<TensionLaw>(double Es, const std::vector<double>& params)> make;
};

const std::vector<LawInfo>& tension_laws();          // the registry, in law.cpp
const LawInfo& tension_law_info(const std::string& name);  // throws std::invalid_argument listing the names

/// A membrane's material: the tension law (with its modulus Es and parameters) and the bending
/// modulus Eb (0: none) about the reference curvature, or about a uniform spontaneous curvature.
struct Material {
  std::string law = "hookean";
  double Es = 1.0;                 // Hookean: the paper's T0 (Eq. 47); others: the shear modulus
  std::vector<double> params;      // the law's LawParam values, in its order
  double Eb = 0.0;                 // bending modulus, energy Eb/2 int (kappa - kappa0)^2 dl
  bool spontaneous = false;        // true: kappa0 = spontaneous_curvature everywhere
  double spontaneous_curvature = 0.0;
  // > 0: the tension T(lambda) loses its modes along the membrane shorter than this length before it
  // makes the force (MembraneForce::compute), so stretching modes finer than the fluid's lattice carries
  // (wavelength < 2 dx) produce no force; 0: the tension as the law gives it.
  double tension_cutoff = 0.0;
};

/// The parameters of a material's law: its own, or the law's defaults when it gives none (a Material
/// built field by field, e.g. law = "skalak" without C). Throws std::invalid_argument for an unknown
/// law or a count of parameters the law does not take.
std::vector<double> law_params(const Material& mat);
/// The tension law of a material, made from law_params(mat).
std::unique_ptr<TensionLaw> make_tension_law(const Material& mat);

/// The paper's membrane: Hookean, T0 = Es, no bending.
inline Material hookean(double T0) {
  Material m;
  m.Es = T0;
  return m;
}

/// The reference (stress-free) state along the label s: its total label length L0, its metric
/// a_k = |X_ref,s| and its curvature kappa0_k at the markers. An empty stretch0 means a = 1 (markers
/// uniform in rest arclength, the paper's), an empty kappa0 a uniform curvature kappa0_uniform.
struct Reference {
  double L0 = 0.0;
  Vec stretch0;
  Vec kappa0;
  double kappa0_uniform = 0.0;
  bool uniform() const { return stretch0.size() == 0; }
  double a(int k) const { return stretch0.size() ? stretch0[k] : 1.0; }
  double kappa(int k) const { return kappa0.size() ? kappa0[k] : kappa0_uniform; }
};

/// The paper's reference: a circle of radius r0 (L0 = 2 pi r0, a = 1, kappa0 = 1/r0). Throws
/// std::invalid_argument unless r0 is positive and finite.
Reference circle_reference(double r0);

/// The curve X itself (nb x 2, anticlockwise, labelled uniformly in s) as the reference, shrunk by
/// 1/prestretch about its centroid: a capsule pre-inflated by `prestretch` (1: X is stress-free).
/// L0 is X's spline length over prestretch, a_k = |X_s| / prestretch, kappa0_k = prestretch kappa(X)_k.
Reference initial_reference(const Mat2& X, double prestretch = 1.0);

}  // namespace sphib
