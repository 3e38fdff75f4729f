// The membrane force density (force.hpp): any tension law, with or without bending, by splines in the
// label s. The Hookean law on the paper's reference without bending keeps its own two schemes
// (Eqs. 47-50); the measured errors and orders of both are in tests/test_membrane.cpp.
#include "membrane/force.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "membrane/geometry.hpp"  // elastic_energy: the paper's Hookean energy
#include "membrane/laws/bending.hpp"

namespace sphib {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

KnotGeometry::KnotGeometry(int nb, double L0)
    : sx(nb, L0), sy(nb, L0), bx(nb, L0), by(nb, L0), X_s(nb, 2), X_ss(nb, 2), norm(nb), kappa(nb) {}

void KnotGeometry::fit(const Mat2& X, bool curvature) {
  const int n = static_cast<int>(X.rows());
  PeriodicSpline::fit_pair(sx, X.data(), sy, X.data() + n);
  sx.d1_at_knots(X_s.data());
  sy.d1_at_knots(X_s.data() + n);
  for (int k = 0; k < n; ++k) norm[k] = std::sqrt(X_s(k, 0) * X_s(k, 0) + X_s(k, 1) * X_s(k, 1));
  if (!curvature) return;
  PeriodicSpline::fit_pair(bx, X_s.data(), by, X_s.data() + n);  // X_ss = d/ds of the spline of X_s
  bx.d1_at_knots(X_ss.data());
  by.d1_at_knots(X_ss.data() + n);
  for (int k = 0; k < n; ++k) {
    const double g = norm[k];
    kappa[k] = (X_s(k, 0) * X_ss(k, 1) - X_s(k, 1) * X_ss(k, 0)) / (g * g * g);  // (X_s x X_ss)/|X_s|^3
  }
}

std::string describe(const Material& mat) {
  std::ostringstream o;
  o << mat.law << (mat.law == "hookean" ? " T0 = " : " Es = ") << mat.Es;
  const LawInfo& info = tension_law_info(mat.law);
  for (size_t i = 0; i < info.params.size() && i < mat.params.size(); ++i) o << ", " << info.params[i].name << " = " << mat.params[i];
  if (mat.Eb > 0) o << ", Eb = " << mat.Eb;
  if (mat.spontaneous) o << ", kappa0 = " << mat.spontaneous_curvature;
  return o.str();
}

Membrane make_membrane(Mat2 X, double r0, double T0) {
  return make_membrane(std::move(X), circle_reference(r0), hookean(T0));
}

Membrane make_membrane(Mat2 X, Reference ref, Material mat) {
  const int n = static_cast<int>(X.rows());
  if (n < 4) throw std::invalid_argument("membrane: nb = " + std::to_string(n) + " markers, need nb >= 4");
  if (!(ref.L0 > 0.0) || !std::isfinite(ref.L0))
    throw std::invalid_argument("membrane: reference length L0 = " + std::to_string(ref.L0) + " must be positive and finite");
  if ((ref.stretch0.size() && ref.stretch0.size() != n) || (ref.kappa0.size() && ref.kappa0.size() != n))
    throw std::invalid_argument("membrane: the reference has another number of markers than X (" + std::to_string(n) + ")");
  if (ref.stretch0.size() && !(ref.stretch0.minCoeff() > 0.0 && ref.stretch0.allFinite()))
    throw std::invalid_argument("membrane: the reference's stretch must be positive and finite at every marker");
  const LawInfo& info = tension_law_info(mat.law);
  if (!(mat.Es >= 0.0) || !std::isfinite(mat.Es))
    throw std::invalid_argument("membrane: modulus Es = " + std::to_string(mat.Es) + " must be >= 0 and finite");
  if (!(mat.Eb >= 0.0) || !std::isfinite(mat.Eb))
    throw std::invalid_argument("membrane: bending modulus Eb = " + std::to_string(mat.Eb) + " must be >= 0 and finite");
  mat.params = law_params(mat);
  for (size_t i = 0; i < info.params.size(); ++i)
    if (!(mat.params[i] >= info.params[i].min && mat.params[i] <= info.params[i].max))
      throw std::invalid_argument("membrane: " + info.params[i].name + " = " + std::to_string(mat.params[i]) +
                                  " is out of range [" + std::to_string(info.params[i].min) + ", " +
                                  std::to_string(info.params[i].max) + "]");
  if (!std::isfinite(mat.spontaneous_curvature))
    throw std::invalid_argument("membrane: the spontaneous curvature must be finite");
  if (!(mat.tension_cutoff >= 0.0) || !std::isfinite(mat.tension_cutoff))
    throw std::invalid_argument("membrane: tension_cutoff = " + std::to_string(mat.tension_cutoff) +
                                " must be >= 0 and finite");
  return {std::move(X), std::move(ref), std::move(mat)};
}

MembraneForce::MembraneForce(const Membrane& m, HookeanScheme scheme)
    : nb_(m.nb()), ref_(m.ref), mat_(m.mat), scheme_(scheme),
      law_(make_tension_law(m.mat)), geo_(m.nb(), m.L0()),
      mspline_(m.nb(), m.L0()), wx_(m.nb(), m.L0()), wy_(m.nb(), m.L0()), ax_(m.nb(), m.L0()), kx_(m.nb(), m.L0()),
      W_(m.nb(), 2), m_(m.nb()), m_s_(m.nb()), lambda_(m.nb()) {
  if (scheme_ == HookeanScheme::Analytic && !paper_hookean())
    throw std::invalid_argument("MembraneForce: the Analytic scheme is the paper's Hookean law's only");
  if (!ref_.uniform()) ax_.fit(ref_.stretch0.data());
  if (ref_.kappa0.size()) kx_.fit(ref_.kappa0.data());
  if (mat_.tension_cutoff > 0.0) {
    cos_.resize(nb_);
    sin_.resize(nb_);
    for (int j = 0; j < nb_; ++j) {
      const double th = 2.0 * kPi * j / nb_;
      cos_[j] = std::cos(th);
      sin_[j] = std::sin(th);
    }
    tc_.resize(nb_ / 2 + 1);
    ts_.resize(nb_ / 2 + 1);
  }
}

bool MembraneForce::paper_hookean() const {
  return mat_.law == "hookean" && ref_.uniform() && mat_.Eb == 0.0 && mat_.tension_cutoff == 0.0;
}

// The tension's Fourier modes in the label s (markers uniform in s) whose wavelength along the current
// length L is below the cutoff, m > L / tension_cutoff, removed: T_k = sum_{|m| <= mc} T^_m e^{2 pi i m k/nb}.
// Cost O(nb mc) with the tabulated cos, sin (mc < nb/2).
void MembraneForce::cut_tension(Vec& T) {
  double L = 0.0;
  for (int k = 0; k < nb_; ++k) L += geo_.norm[k];
  L *= ds();
  const double mcd = std::floor(L / mat_.tension_cutoff);
  if (2.0 * mcd >= nb_) return;  // the markers carry no mode that short
  const int mc = static_cast<int>(mcd);
  for (int m = 0; m <= mc; ++m) {
    double a = 0.0, b = 0.0;
    for (int k = 0, j = 0; k < nb_; ++k) {  // j = m k mod nb
      a += T[k] * cos_[j];
      b += T[k] * sin_[j];
      j += m;
      if (j >= nb_) j -= nb_;
    }
    tc_[m] = a;
    ts_[m] = b;
  }
  const double inv = 1.0 / nb_;
  for (int k = 0; k < nb_; ++k) {
    double t = 0.5 * tc_[0];
    for (int m = 1, j = k; m <= mc; ++m) {  // j = m k mod nb
      t += tc_[m] * cos_[j] + ts_[m] * sin_[j];
      j += k;
      if (j >= nb_) j -= nb_;
    }
    T[k] = 2.0 * t * inv;
  }
}

void MembraneForce::compute(const Mat2& X, Mat2& f, Vec& T) {
  if (X.rows() != nb_)
    throw std::invalid_argument("MembraneForce: X has " + std::to_string(X.rows()) + " markers, expected nb = " +
                                std::to_string(nb_));
  f.resize(nb_, 2);  // no-op (no allocation) when already nb x 2
  T.resize(nb_);
  const int n = nb_;
  const double T0 = mat_.Es;
  const bool bending = mat_.Eb > 0.0;

  if (paper_hookean() && scheme_ == HookeanScheme::Analytic) {
    // d(T tau)/ds = T0 (X_ss - X_ss/|X_s| + X_s (X_s . X_ss)/|X_s|^3), Eqs. (47, 48, 50).
    PeriodicSpline::fit_pair(geo_.sx, X.data(), geo_.sy, X.data() + n);
    for (int d = 0; d < 2; ++d) {
      spline(d).d1_at_knots(geo_.X_s.data() + d * n);
      spline(d).d2_at_knots(W_.data() + d * n);
    }
    for (int k = 0; k < n; ++k) {
      const double xs = geo_.X_s(k, 0), ys = geo_.X_s(k, 1);
      const double xss = W_(k, 0), yss = W_(k, 1);
      const double norm = std::sqrt(xs * xs + ys * ys);    // |X_s|
      geo_.norm[k] = norm;
      T[k] = T0 * (norm - 1.0);                              // Eq. (47)
      const double inv = 1.0 / norm;
      const double a = T0 * (1.0 - inv);                     // T0 (1 - 1/|X_s|) X_ss
      const double b = T0 * (xs * xss + ys * yss) * inv * inv * inv;  // T0 (X_s.X_ss)/|X_s|^3 X_s
      f(k, 0) = a * xss + b * xs;                            // Eq. (50)
      f(k, 1) = a * yss + b * ys;
    }
    return;
  }

  geo_.fit(X, bending);
  if (paper_hookean()) {
    for (int k = 0; k < n; ++k) {
      const double xs = geo_.X_s(k, 0), ys = geo_.X_s(k, 1), norm = geo_.norm[k];
      T[k] = T0 * (norm - 1.0);                          // Eq. (47)
      const double T_over_norm = T[k] / norm;            // T tau = T X_s/|X_s|, Eq. (48)
      W_(k, 0) = T_over_norm * xs;
      W_(k, 1) = T_over_norm * ys;
    }
  } else {
    for (int k = 0; k < n; ++k) {
      lambda_[k] = geo_.norm[k] / ref_.a(k);  // stretch against the reference
      T[k] = law_->tension(lambda_[k]);
    }
    if (mat_.tension_cutoff > 0.0) cut_tension(T);
    if (bending) {
      for (int k = 0; k < n; ++k) m_[k] = bending_moment(mat_.Eb, geo_.kappa[k], kappa0(k));
      mspline_.fit(m_.data());
      mspline_.d1_at_knots(m_s_.data());  // dm/ds
    }
    for (int k = 0; k < n; ++k) {
      const double xs = geo_.X_s(k, 0), ys = geo_.X_s(k, 1), g = geo_.norm[k];
      double Ttot = T[k], Q = 0.0;
      if (bending) {
        Ttot += bending_tension(m_[k], geo_.kappa[k], kappa0(k));  // T_b
        Q = -m_s_[k] / g;                                          // -dm/dl
      }
      // (T + T_b) tau + Q n, tau = X_s/g, n = (-tau_y, tau_x)
      W_(k, 0) = (Ttot * xs - Q * ys) / g;
      W_(k, 1) = (Ttot * ys + Q * xs) / g;
    }
  }
  PeriodicSpline::fit_pair(wx_, W_.data(), wy_, W_.data() + n);  // f = dW/ds, Eq. (50)
  wx_.d1_at_knots(f.data());
  wy_.d1_at_knots(f.data() + n);
}

void MembraneForce::fit_energy(const Mat2& X) {
  if (fitted_to(X)) return;
  if (mat_.Eb > 0.0) geo_.fit(X, true);  // the bending energy's curvature: the force's splines of X_s
  else PeriodicSpline::fit_pair(geo_.sx, X.data(), geo_.sy, X.data() + nb_);
}

MembraneEnergy MembraneForce::energy() const {
  MembraneEnergy e;
  if (paper_hookean()) {
    e.stretching = elastic_energy(geo_.sx, geo_.sy, mat_.Es);  // T0/2 int (|X_s| - 1)^2 ds, bit for bit the guard's
    return e;
  }
  const double h = geo_.sx.h();
  const bool bending = mat_.Eb > 0.0;
  double cx[4], cy[4], ca[4], ck[4], bx[4], by[4];
  for (int k = 0; k < nb_; ++k) {
    geo_.sx.segment(k, cx);
    geo_.sy.segment(k, cy);
    if (bending) {
      geo_.bx.segment(k, bx);
      geo_.by.segment(k, by);
    }
    if (!ref_.uniform()) ax_.segment(k, ca);
    if (ref_.kappa0.size()) kx_.segment(k, ck);
    for (int q = 0; q < 5; ++q) {
      const double t = 0.5 * h * (1.0 + gauss5::x[q]), w = 0.5 * h * gauss5::w[q];
      const double xs = cx[1] + t * (2.0 * cx[2] + 3.0 * t * cx[3]), ys = cy[1] + t * (2.0 * cy[2] + 3.0 * t * cy[3]);
      const double g = std::sqrt(xs * xs + ys * ys);
      const double a = ref_.uniform() ? 1.0 : ca[0] + t * (ca[1] + t * (ca[2] + t * ca[3]));
      e.stretching += w * law_->energy(g / a) * a;  // int W(lambda) a ds
      if (!bending) continue;
      // X_ss as the force takes it: the derivative of the spline of X_s (O(h^4); the spline of X's own
      // second derivative is piecewise linear, O(h^2))
      const double xss = bx[1] + t * (2.0 * bx[2] + 3.0 * t * bx[3]), yss = by[1] + t * (2.0 * by[2] + 3.0 * t * by[3]);
      const double kappa = (xs * yss - ys * xss) / (g * g * g);
      const double k0 = mat_.spontaneous              ? mat_.spontaneous_curvature
                        : ref_.kappa0.size() ? ck[0] + t * (ck[1] + t * (ck[2] + t * ck[3]))
                                             : ref_.kappa0_uniform;
      e.bending += w * bending_energy_density(mat_.Eb, kappa, k0) * g;  // Eb/2 int (kappa - kappa0)^2 dl
    }
  }
  return e;
}

MembraneStiffness MembraneForce::stiffness() const {
  MembraneStiffness s;
  s.Eb = mat_.Eb;
  double T = 0.0;
  for (int k = 0; k < nb_; ++k) {
    const double lambda = geo_.norm[k] / ref_.a(k);
    s.Et = std::max(s.Et, law_->stiffness(lambda));
    T += law_->tension(lambda);
    s.length += geo_.norm[k];
  }
  s.T_mean = T / nb_;
  s.length *= ds();
  return s;
}

}  // namespace sphib
