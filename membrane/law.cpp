// The registry of tension laws, and the reference states.
#include "membrane/law.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "membrane/force.hpp"

namespace sphib {

// One line per law (its file in membrane/laws/).
LawInfo hookean_law();
LawInfo neo_hookean_law();
LawInfo skalak_law();
LawInfo inextensible_law();

const std::vector<LawInfo>& tension_laws() {
  static const std::vector<LawInfo> laws{hookean_law(), neo_hookean_law(), skalak_law(), inextensible_law()};
  return laws;
}

const LawInfo& tension_law_info(const std::string& name) {
  std::string names;
  for (const LawInfo& l : tension_laws()) {
    if (l.name == name) return l;
    names += (names.empty() ? "" : ", ") + l.name;
  }
  throw std::invalid_argument("unknown membrane law \"" + name + "\" (known: " + names + ")");
}

std::vector<double> law_params(const Material& mat) {
  const LawInfo& info = tension_law_info(mat.law);
  if (mat.params.empty()) {
    std::vector<double> defaults;
    for (const LawParam& p : info.params) defaults.push_back(p.value);
    return defaults;
  }
  if (mat.params.size() != info.params.size())
    throw std::invalid_argument("membrane: law \"" + mat.law + "\" takes " + std::to_string(info.params.size()) +
                                " parameters, got " + std::to_string(mat.params.size()));
  return mat.params;
}

std::unique_ptr<TensionLaw> make_tension_law(const Material& mat) {
  return tension_law_info(mat.law).make(mat.Es, law_params(mat));
}

Reference circle_reference(double r0) {
  if (!(r0 > 0.0) || !std::isfinite(r0))
    throw std::invalid_argument("membrane: rest radius r0 = " + std::to_string(r0) + " must be positive and finite");
  constexpr double kPi = 3.14159265358979323846;
  Reference r;
  r.L0 = 2.0 * kPi * r0;
  r.kappa0_uniform = 1.0 / r0;
  return r;
}

Reference initial_reference(const Mat2& X, double prestretch) {
  const int n = static_cast<int>(X.rows());
  if (n < 4) throw std::invalid_argument("membrane: nb = " + std::to_string(n) + " markers, need nb >= 4");
  if (!(prestretch > 0.0) || !std::isfinite(prestretch))
    throw std::invalid_argument("membrane: prestretch = " + std::to_string(prestretch) + " must be positive and finite");
  // The spline's curve does not depend on the period of its uniform knots: its length from any period.
  PeriodicSpline sx(n, 1.0), sy(n, 1.0);
  PeriodicSpline::fit_pair(sx, X.data(), sy, X.data() + n);
  double length = 0.0;
  for (int k = 0; k < n; ++k) {
    double cx[4], cy[4];
    sx.segment(k, cx);
    sy.segment(k, cy);
    for (int q = 0; q < 5; ++q) {
      const double t = 0.5 * sx.h() * (1.0 + gauss5::x[q]);
      const double xs = cx[1] + t * (2.0 * cx[2] + 3.0 * t * cx[3]), ys = cy[1] + t * (2.0 * cy[2] + 3.0 * t * cy[3]);
      length += 0.5 * sx.h() * gauss5::w[q] * std::sqrt(xs * xs + ys * ys);
    }
  }
  Reference r;
  r.L0 = length / prestretch;  // the label: reference arclength on average
  // a and kappa0 as the force (force.cpp, bending.hpp) measures them, so that prestretch = 1 leaves
  // lambda = 1 and kappa = kappa0 at every marker to the last bit: X is stress-free.
  KnotGeometry g(n, r.L0);
  g.fit(X, true);
  r.stretch0 = g.norm / prestretch;
  r.kappa0 = prestretch * g.kappa;
  return r;
}

}  // namespace sphib
