#include "coupling/marker_update.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {

// X^[I+1] is accepted by its linearised residual (marker_update.hpp) when the step |g| is below
// kLinearStep max_move and |dt/2 dU/dX g| below eps/2; then U <- U - dU/dX g.
constexpr double kLinearStep = 1e-6;

bool accept_linearised(const MarkerUpdateParams& prm, double dt, double g_max, MarkerWork& w, Mat2& U,
                       MarkerUpdateResult& res) {
  if (!(g_max <= kLinearStep * prm.max_move)) return false;
  double r_max = 0.0;
  for (int k = 0; k < U.rows(); ++k) {
    const double gx = w.g(k, 0), gy = w.g(k, 1);
    const double ex = w.dU(k, 0) * gx + w.dU(k, 1) * gy, ey = w.dU(k, 2) * gx + w.dU(k, 3) * gy;  // dU/dX g
    r_max = std::max(r_max, 0.5 * dt * std::sqrt(ex * ex + ey * ey));
  }
  if (!(r_max <= 0.5 * prm.eps)) return false;
  for (int k = 0; k < U.rows(); ++k) {  // U^{n+1}(X^[I+1]) = U^{n+1}(X^[I]) + dU/dX (X^[I+1] - X^[I])
    const double gx = w.g(k, 0), gy = w.g(k, 1);
    U(k, 0) -= w.dU(k, 0) * gx + w.dU(k, 1) * gy;
    U(k, 1) -= w.dU(k, 2) * gx + w.dU(k, 3) * gy;
  }
  ++res.iterations;
  res.residual = r_max;
  res.linearised = true;
  return true;
}

}  // namespace

MarkerUpdateResult advance_markers(const MarkerVelocity& U_new, const Mat2& U_n, const Mat2* U_prev, double dt,
                                   const MarkerUpdateParams& prm, long step, Mat2& X, Mat2& X_n, Mat2& U,
                                   MarkerWork& work) {
  X_n = X;
  MarkerUpdateResult res;
  if (prm.extrapolate && U_prev) {
    X = X_n + dt * (1.5 * U_n - 0.5 * *U_prev);  // Adams-Bashforth: O(dt^3) from the root of Eq. (59)
  } else {
    U_new(X_n, U, nullptr);  // U^{n+1}(X^n), Eq. (62)
    X = X_n + dt * U;        // Eq. (58)
    res.interpolations = 1;
  }
  auto check_moves = [&]() {
    if (prm.max_move <= 0) return;
    for (int k = 0; k < X.rows(); ++k) {
      const double dx = X(k, 0) - X_n(k, 0), dy = X(k, 1) - X_n(k, 1);
      const double d = std::sqrt(dx * dx + dy * dy);  // (not hypot: a libm call per marker, no overflow here)
      if (!(d <= prm.max_move)) {
        std::ostringstream m;
        m << "blow-up at step " << step << ": marker " << k << " would move by " << d << " in one step (limit "
          << prm.max_move << ", one lattice spacing)";
        throw std::runtime_error(m.str());
      }
    }
  };
  check_moves();
  work.g.resize(X.rows(), 2);
  for (int I = 0; I <= prm.max_iter; ++I) {
    const bool gradient = U_new(X, U, prm.linearise ? &work.dU : nullptr);  // U^{n+1}(X^[I]), Eq. (63)
    ++res.interpolations;
    // g(X) = X - X^n - dt/2 (U^n(X^n) + U^{n+1}(X)), Eq. (59)
    double g_max = 0.0;
    for (int k = 0; k < X.rows(); ++k) {
      const double gx = X(k, 0) - X_n(k, 0) - 0.5 * dt * (U_n(k, 0) + U(k, 0));
      const double gy = X(k, 1) - X_n(k, 1) - 0.5 * dt * (U_n(k, 1) + U(k, 1));
      work.g(k, 0) = gx;
      work.g(k, 1) = gy;
      g_max = std::max(g_max, std::sqrt(gx * gx + gy * gy));
    }
    res.iterations = I;
    res.residual = g_max;
    if (!std::isfinite(g_max)) break;
    if (g_max <= prm.eps) return res;
    X = X_n + 0.5 * dt * (U_n + U);  // fixed-point iteration X^[I+1] = X^[I] - g(X^[I])
    check_moves();
    if (gradient && accept_linearised(prm, dt, g_max, work, U, res)) return res;
  }
  std::ostringstream m;
  m << "marker update did not converge at step " << step << ": max |g| = " << res.residual << " after "
    << res.iterations << " iterations (tolerance " << prm.eps << ")";
  throw std::runtime_error(m.str());
}

}  // namespace sphib
