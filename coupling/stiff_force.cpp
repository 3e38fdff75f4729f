#include "coupling/stiff_force.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace sphib {

namespace {
constexpr double kPi = 3.14159265358979323846;
// dt K B below which a mode leans towards the explicit force: theta = min(1, dt K B / kStiff).
constexpr double kStiff = 0.1;
// The model's residual G (the velocity it missed last step) is smoothed over steps with weight kRelax
// and used only on modes the kernels resolve well (the bound of their attenuation above kResolved),
// where B is close to the fluid's response rather than a loose bound. Both chosen by measurement
// (docs/membranes.md, "Accuracy"): larger weights or a lower threshold diverge on some of the scenes
// measured there.
constexpr double kRelax = 0.2, kResolved = 0.9;
// The residual's gain. A component j (normal, tangential) of G moves the force of every component i
// by dt K_ij and that force the membrane by B_i: its gain on the mode is s_j = dt max_i |K_ij| B_i
// (a column of dt B K). G_j's weight falls as kRelax min(1, kLag / s_j) where s_j > kLag, so that
// the loop residual -> G -> f~ -> U, of gain about 1 - w b/B on a stiff mode (b the fluid's true
// response), stays below 1 when B is off by a large factor; a normal component keeps the full
// weight while the mode keeps its velocity over a step (A >= kViscous: a tank-treading capsule's
// bending modes, whose residual must follow the tank-treading). Any weight
// gives the same fixed point (a steady state still receives f^n). |G_j| is capped at kCap B_j |f^n_j|
// (a steady state has |G_j| = B_j |f^n_j|). And with G the tangential layer is at least the
// interpolation's smoothing length h (the lattice carries no thinner layer; sqrt(pi nu dt) < h
// overestimates Bt, 20 times at mu = 0.1, dt = 1e-4 on the stability map's lattice, h = 0.1125).
// Each of the three chosen by measurement (docs/membranes.md, "The residual's gain"): without any
// one of them a row of the stability map fails where the default is stable.
constexpr double kLag = 1.0, kViscous = 0.2, kCap = 1.5;
using C = std::complex<double>;

// An upper bound of the cubic-spline kernel's 2-D Fourier transform at q = k h: within 1.25x of
// sinc^4(q/2) over its first lobe (q < 6), then side lobes below 1e-3 (numerical Hankel transform,
// docs/membranes.md), so that B is overestimated, never under.
double smoothing(double q) {
  const double x = 0.5 * q, sinc = x == 0.0 ? 1.0 : std::sin(x) / x;
  return std::min(1.0, 1.5 * sinc * sinc * sinc * sinc + 1e-3);
}
}  // namespace

StiffForceFilter::StiffForceFilter(int nb, bool residual) : nb_(nb), nm_(nb / 2 + 1), residual_(residual) {
  hist_.assign(6 * static_cast<size_t>(nm_), std::complex<double>(0.0));
  in_ = fftw_alloc_real(4 * static_cast<size_t>(nb_));
  hat_ = fftw_alloc_complex(4 * static_cast<size_t>(nm_));
  if (!in_ || !hat_) throw std::bad_alloc();
  int n[1] = {nb_};
  fwd_ = fftw_plan_many_dft_r2c(1, n, 4, in_, nullptr, 1, nb_, hat_, nullptr, 1, nm_, FFTW_ESTIMATE);
  inv_ = fftw_plan_many_dft_c2r(1, n, 2, hat_, nullptr, 1, nm_, in_, nullptr, 1, nb_, FFTW_ESTIMATE);
  if (!fwd_ || !inv_) throw std::runtime_error("StiffForceFilter: no FFTW plan for " + std::to_string(nb) + " markers");
}

StiffForceFilter::~StiffForceFilter() {
  if (fwd_) fftw_destroy_plan(fwd_);
  if (inv_) fftw_destroy_plan(inv_);
  fftw_free(in_);
  fftw_free(hat_);
}

void StiffForceFilter::apply(const MembraneForce& force, const Mat2& f, const Mat2& U, const StiffFluid& fl,
                             Mat2& f_tilde, bool record) {
  const KnotGeometry& g = force.geometry();
  const MembraneStiffness st = force.stiffness();
  const int n = nb_;
  // Inward normal and tangential components; the force per unit current length (f is per unit label).
  double* fn = in_;
  double* ft = in_ + n;
  double* un = in_ + 2 * n;
  double* ut = in_ + 3 * n;
  for (int k = 0; k < n; ++k) {
    const double tx = g.X_s(k, 0) / g.norm[k], ty = g.X_s(k, 1) / g.norm[k];  // tau; n = (-ty, tx)
    fn[k] = (-ty * f(k, 0) + tx * f(k, 1)) / g.norm[k];
    ft[k] = (tx * f(k, 0) + ty * f(k, 1)) / g.norm[k];
    un[k] = -ty * U(k, 0) + tx * U(k, 1);
    ut[k] = tx * U(k, 0) + ty * U(k, 1);
  }
  fftw_execute(fwd_);
  C* Fn = reinterpret_cast<C*>(hat_);
  C* Ft = Fn + nm_;
  const C* Un = Fn + 2 * nm_;
  const C* Ut = Fn + 3 * nm_;

  const double R = st.length / (2.0 * kPi), dt = fl.dt, nu = fl.mu / fl.rho;
  const double Et = st.Et / (R * R), Tp = std::max(st.T_mean, 0.0) / (R * R), Eb = st.Eb / (R * R * R * R);
  const double layer = residual_ ? std::max(std::sqrt(kPi * nu * dt), fl.h) : std::sqrt(kPi * nu * dt);
  const C i(0.0, 1.0);
  C* Up = hist_.data();  // U^{n-1} (normal modes, then tangential), f~^{n-1}, G
  C* Fp = Up + 2 * nm_;
  C* G = Up + 4 * nm_;
  for (int m = 0; m < nm_; ++m) {
    const double mm = static_cast<double>(m), k = mm / R, m2 = mm * mm;
    // K (per unit length, on (a, b) = inward normal, tangential); no coupling at the Nyquist mode
    const bool nyquist = 2 * m == n;
    const double Kaa = Et + Eb * (m2 - 1.0) * (m2 - 1.0) + Tp * std::max(m2 - 1.0, 0.0), Kbb = m2 * Et;
    const C Kab = nyquist ? C(0.0) : -i * mm * Et, Kba = std::conj(Kab);
    // the fluid's one-step response B and the velocity a mode keeps, A
    const double stokes = m == 0 ? INFINITY : 1.0 / (4.0 * fl.mu * k);
    const double s = smoothing(k * fl.h_star) * smoothing(k * fl.h);  // spreading and interpolation
    const double Bn = s * std::min(dt * k / (2.0 * fl.rho), stokes);
    const double Bt = s * std::min(dt / (2.0 * fl.rho * (m == 0 ? layer : std::min(1.0 / k, layer))), stokes);
    const double A = 1.0 / (1.0 + 2.0 * nu * k * k * dt);
    // theta: implicit where the mode is stiff, fading to the explicit f^n where dt K B << kStiff
    const double th = dt * std::min(1.0, dt * std::max(Kaa, Kbb) * std::max(Bn, Bt) / kStiff);
    // G: what the model U^{n+1} = A U^n + B f~ missed last step (the flow's own driving, model
    // error), smoothed; zero on modes the kernels do not resolve
    if (!residual_ || s <= kResolved) {
      G[m] = G[nm_ + m] = 0.0;
    } else if (record && have_prev_) {
      const double sa = dt * std::max(Kaa * Bn, std::abs(Kba) * Bt), sb = dt * std::max(Kbb * Bt, std::abs(Kab) * Bn);
      const double wn = kRelax * std::min(1.0, std::max(kLag / sa, A / kViscous));
      const double wt = kRelax * std::min(1.0, kLag / sb);
      G[m] += wn * (Un[m] - A * Up[m] - Bn * Fp[m] - G[m]);
      G[nm_ + m] += wt * (Ut[m] - A * Up[nm_ + m] - Bt * Fp[nm_ + m] - G[nm_ + m]);
      const double cap_n = kCap * Bn * std::abs(Fn[m]), cap_t = kCap * Bt * std::abs(Ft[m]);  // Fn, Ft: f^n
      if (std::abs(G[m]) > cap_n) G[m] *= cap_n / std::abs(G[m]);
      if (std::abs(G[nm_ + m]) > cap_t) G[nm_ + m] *= cap_t / std::abs(G[nm_ + m]);
    }
    // r = f - theta dt K (A U + G);  M = I + theta dt K B;  f~ = M^{-1} r
    const C pa = A * Un[m] + G[m], pb = A * Ut[m] + G[nm_ + m];
    const C ra = Fn[m] - th * (Kaa * pa + Kab * pb);
    const C rb = Ft[m] - th * (Kba * pa + Kbb * pb);
    const C Maa = 1.0 + th * Kaa * Bn, Mab = th * Kab * Bt, Mba = th * Kba * Bn, Mbb = 1.0 + th * Kbb * Bt;
    const C det = Maa * Mbb - Mab * Mba;
    Fn[m] = (Mbb * ra - Mab * rb) / det;
    Ft[m] = (Maa * rb - Mba * ra) / det;
    if (record && residual_) {  // the history only the residual reads
      Up[m] = Un[m];
      Up[nm_ + m] = Ut[m];
      Fp[m] = Fn[m];
      Fp[nm_ + m] = Ft[m];
    }
  }
  if (record && residual_) have_prev_ = true;
  fftw_execute(inv_);  // f~_n, f~_t into in_[0, 2n), times n (FFTW's unnormalised transforms)
  f_tilde.resize(n, 2);
  const double inv_n = 1.0 / n;
  double mx = 0.0, my = 0.0;  // the change's net force, removed: the filter must not push the membrane
  for (int k = 0; k < n; ++k) {
    const double tx = g.X_s(k, 0) / g.norm[k], ty = g.X_s(k, 1) / g.norm[k];
    const double a = fn[k] * inv_n * g.norm[k], b = ft[k] * inv_n * g.norm[k];  // per unit label again
    f_tilde(k, 0) = -ty * a + tx * b;
    f_tilde(k, 1) = tx * a + ty * b;
    mx += f_tilde(k, 0) - f(k, 0);
    my += f_tilde(k, 1) - f(k, 1);
  }
  mx *= inv_n;
  my *= inv_n;
  for (int k = 0; k < n; ++k) {
    f_tilde(k, 0) -= mx;
    f_tilde(k, 1) -= my;
  }
}

Eigen::MatrixXd StiffForceFilter::state() const {
  if (!have_prev_) return {};
  Eigen::MatrixXd s(nm_, 12);
  for (int m = 0; m < nm_; ++m)
    for (int j = 0; j < 6; ++j) {
      s(m, 2 * j) = hist_[j * nm_ + m].real();
      s(m, 2 * j + 1) = hist_[j * nm_ + m].imag();
    }
  return s;
}

void StiffForceFilter::set_state(const Eigen::MatrixXd& s) {
  if (s.size() == 0) {
    have_prev_ = false;
    std::fill(hist_.begin(), hist_.end(), C(0.0));
    return;
  }
  if (s.rows() != nm_ || s.cols() != 12)
    throw std::invalid_argument("stiff-force filter state: " + std::to_string(s.rows()) + " x " +
                                std::to_string(s.cols()) + ", expected " + std::to_string(nm_) + " x 12");
  for (int m = 0; m < nm_; ++m)
    for (int j = 0; j < 6; ++j) hist_[j * nm_ + m] = C(s(m, 2 * j), s(m, 2 * j + 1));
  have_prev_ = true;
}

}  // namespace sphib
