#include "membrane/spline.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sphib {

PeriodicSpline::PeriodicSpline(int n, double L) : n_(n), L_(L) {
  if (n < 4)
    throw std::invalid_argument("PeriodicSpline: n = " + std::to_string(n) +
                                " knots, a periodic cubic spline needs n >= 4");
  if (!(L > 0.0) || !std::isfinite(L))
    throw std::invalid_argument("PeriodicSpline: period L = " + std::to_string(L) +
                                " must be positive and finite");
  h_ = L / n;
  rho_ = 2.0 - std::sqrt(3.0);
  // Periodic inverse of (I + rho S): sum_j (-rho)^j b_{k+j} / (1 - (-rho)^n). The terms
  // fall as 0.268^j, so ~32 of them reach round-off whatever n is.
  const double denom = 1.0 - std::pow(-rho_, n);
  int m = 0;
  for (double p = 1.0; m < n && std::abs(p) > 1e-18; p *= -rho_) ++m;
  pw_.resize(m);
  double p = 1.0;
  for (int j = 0; j < m; ++j, p *= -rho_) pw_[j] = p / denom;
  y_ = Vec::Zero(n);
  M_ = Vec::Zero(n);
  w_ = Vec::Zero(n);
}

// The sweeps of C splines of the same n and h, interleaved value by value (each spline's arithmetic
// is that of a fit on its own).
template <int C>
void PeriodicSpline::fit_splines(PeriodicSpline* const* sp, const double* const* y, int stride) {
  const PeriodicSpline& P = *sp[0];
  const int n = P.n_;
  double *Y[C], *M[C], *w[C];
  for (int c = 0; c < C; ++c) {
    Y[c] = sp[c]->y_.data();
    M[c] = sp[c]->M_.data();
    w[c] = sp[c]->w_.data();
    for (int k = 0; k < n; ++k) Y[c][k] = y[c][static_cast<std::ptrdiff_t>(k) * stride];
  }

  // r_k = 6 (y_{k+1} - 2 y_k + y_{k-1}) / h^2, stored in M for now.
  const double r = 6.0 / (P.h_ * P.h_);
  for (int c = 0; c < C; ++c) {
    const double* y_ = Y[c];
    double* M_ = M[c];
    M_[0] = r * (y_[1] - 2.0 * y_[0] + y_[n - 1]);
    for (int k = 1; k < n - 1; ++k) M_[k] = r * (y_[k + 1] - 2.0 * y_[k] + y_[k - 1]);
    M_[n - 1] = r * (y_[0] - 2.0 * y_[n - 1] + y_[n - 2]);
  }

  solve_cyclic<C>(P, M, w);
}

// circ(1, 4, 1) M = r for C right-hand sides (in M, replaced by the solutions; w workspace), as
// (1/rho) (I + rho S)(I + rho S^T): two sweeps, each started from its periodic closed form.
template <int C>
void PeriodicSpline::solve_cyclic(const PeriodicSpline& P, double* const* M, double* const* w) {
  const int n = P.n_;
  const int m = static_cast<int>(P.pw_.size());
  const double rho = P.rho_;
  const double* pw = P.pw_.data();
  // (I + rho S) w = rho r:  w_k = rho (r_k - w_{k+1}), closed periodically.
  double acc[C] = {};
  for (int j = 0; j < m; ++j)
    for (int c = 0; c < C; ++c) acc[c] += pw[j] * M[c][(n - 1 + j) % n];
  for (int c = 0; c < C; ++c) w[c][n - 1] = rho * acc[c];
  for (int k = n - 2; k >= 0; --k)
    for (int c = 0; c < C; ++c) w[c][k] = rho * (M[c][k] - w[c][k + 1]);

  // (I + rho S^T) M = w:  M_k = w_k - rho M_{k-1}, closed periodically.
  for (int c = 0; c < C; ++c) acc[c] = 0.0;
  for (int j = 0; j < m; ++j)
    for (int c = 0; c < C; ++c) acc[c] += pw[j] * w[c][(n - j) % n];
  for (int c = 0; c < C; ++c) M[c][0] = acc[c];
  for (int k = 1; k < n; ++k)
    for (int c = 0; c < C; ++c) M[c][k] = w[c][k] - rho * M[c][k - 1];
}

void PeriodicSpline::solve_141(double* r, double* work) const {
  double* M[1] = {r};
  double* w[1] = {work};
  solve_cyclic<1>(*this, M, w);
}

void PeriodicSpline::fit(const double* y, int stride) {
  PeriodicSpline* sp[1] = {this};
  fit_splines<1>(sp, &y, stride);
}

void PeriodicSpline::fit_pair(PeriodicSpline& a, const double* ya, PeriodicSpline& b, const double* yb) {
  if (a.n_ != b.n_ || a.h_ != b.h_)
    throw std::invalid_argument("PeriodicSpline::fit_pair: the splines differ in n or period");
  PeriodicSpline* sp[2] = {&a, &b};
  const double* y[2] = {ya, yb};
  fit_splines<2>(sp, y, 1);
}

bool PeriodicSpline::fitted_to(const double* y) const {
  return std::memcmp(y_.data(), y, sizeof(double) * static_cast<size_t>(n_)) == 0;
}

void PeriodicSpline::locate(double s, int& k, double& t) const {
  double u = s / h_;
  double fk = std::floor(u);
  t = (u - fk) * h_;
  double kk = std::fmod(fk, static_cast<double>(n_));
  if (kk < 0) kk += n_;
  k = static_cast<int>(kk);
  if (k >= n_) k = 0;  // guard fmod round-off
}

void PeriodicSpline::segment(int k, double c[4]) const {
  k = wrap(k);
  const int k1 = (k + 1 == n_) ? 0 : k + 1;
  c[0] = y_[k];
  c[1] = (y_[k1] - y_[k]) / h_ - h_ * (2.0 * M_[k] + M_[k1]) / 6.0;
  c[2] = 0.5 * M_[k];
  c[3] = (M_[k1] - M_[k]) / (6.0 * h_);
}

void PeriodicSpline::eval(double s, double& v, double& v_s, double& v_ss) const {
  int k;
  double t, c[4];
  locate(s, k, t);
  segment(k, c);
  v = c[0] + t * (c[1] + t * (c[2] + t * c[3]));
  v_s = c[1] + t * (2.0 * c[2] + 3.0 * t * c[3]);
  v_ss = 2.0 * c[2] + 6.0 * t * c[3];
}

double PeriodicSpline::value(double s) const {
  double v, v_s, v_ss;
  eval(s, v, v_s, v_ss);
  return v;
}

double PeriodicSpline::d1(double s) const {
  double v, v_s, v_ss;
  eval(s, v, v_s, v_ss);
  return v_s;
}

double PeriodicSpline::d2(double s) const {
  double v, v_s, v_ss;
  eval(s, v, v_s, v_ss);
  return v_ss;
}

void PeriodicSpline::d1_at_knots(double* out, int stride) const {
  const double inv_h = 1.0 / h_, h6 = h_ / 6.0;
  for (int k = 0; k < n_; ++k) {
    const int k1 = (k + 1 == n_) ? 0 : k + 1;
    out[static_cast<std::ptrdiff_t>(k) * stride] =
        (y_[k1] - y_[k]) * inv_h - h6 * (2.0 * M_[k] + M_[k1]);
  }
}

void PeriodicSpline::d2_at_knots(double* out, int stride) const {
  for (int k = 0; k < n_; ++k) out[static_cast<std::ptrdiff_t>(k) * stride] = M_[k];
}

}  // namespace sphib
