#include "coupling/marker_update.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

MarkerUpdateResult advance_markers(const MarkerVelocity& U_new, const Mat2& U_n, const Mat2* U_prev, double dt,
                                   const MarkerUpdateParams& prm, long step, Mat2& X, Mat2& X_n, Mat2& U,
                                   MarkerWork& w, const std::vector<int>* groups, const MarkerConstraint* constrain) {
  const int n = static_cast<int>(X.rows());
  const std::vector<int> all{0, n};
  const std::vector<int>& G = groups ? *groups : all;
  const int ng = static_cast<int>(G.size()) - 1;
  auto constrain_group = [&](int g, const Mat2& Xg) {  // the area constraint on group g's U at Xg
    if (!constrain) return;
    const int a = G[g], m = G[g + 1] - G[g];
    (*constrain)(g, X_n.middleRows(a, m), U_n.middleRows(a, m), Xg.middleRows(a, m), U.middleRows(a, m));
  };
  X_n = X;
  int predictor = 0;  // interpolations of the predictor
  if (prm.extrapolate && U_prev) {
    X = X_n + dt * (1.5 * U_n - 0.5 * *U_prev);  // Adams-Bashforth: O(dt^3) from the root of Eq. (59)
  } else {
    U_new(X_n, U, nullptr);  // U^{n+1}(X^n), Eq. (62)
    for (int g = 0; g < ng; ++g) constrain_group(g, X_n);
    X = X_n + dt * U;        // Eq. (58)
    predictor = 1;
  }
  auto check_moves = [&](int begin, int end) {
    if (prm.max_move <= 0) return;
    for (int k = begin; k < end; ++k) {
      const double dx = X(k, 0) - X_n(k, 0), dy = X(k, 1) - X_n(k, 1);
      const double d = std::sqrt(dx * dx + dy * dy);  // (not hypot: a libm call per marker, no overflow here)
      if (!(d <= prm.max_move)) {
        std::ostringstream tail;
        tail << " would move by " << d << " in one step (limit " << prm.max_move << ", one lattice spacing)";
        throw MarkerError("blow-up at step " + std::to_string(step) + ": marker ", k, tail.str());
      }
    }
  };
  check_moves(0, n);
  w.g.resize(n, 2);
  w.results.assign(ng, MarkerUpdateResult{});
  w.active.resize(ng);
  for (int g = 0; g < ng; ++g) w.active[g] = g;
  const double lim = prm.linear_step * prm.max_move;
  for (int I = 0; I <= prm.max_iter; ++I) {
    // U^{n+1}(X^[I]) of the groups still iterating, Eq. (63): in one call (gathered unless all are)
    bool gradient;
    Jacobians* dU = prm.linearise ? &w.dU : nullptr;
    if (static_cast<int>(w.active.size()) == ng) {
      gradient = U_new(X, U, dU);
    } else {
      int m = 0;
      for (int g : w.active) m += G[g + 1] - G[g];
      w.Xa.resize(m, 2);
      w.Ua.resize(m, 2);
      m = 0;
      for (int g : w.active)
        for (int k = G[g]; k < G[g + 1]; ++k) w.Xa.row(m++) = X.row(k);
      try {
        gradient = U_new(w.Xa, w.Ua, dU ? &w.dUa : nullptr);
      } catch (const MarkerError& e) {  // its marker as a row of X
        int r = e.marker;
        for (int g : w.active) {
          if (r < G[g + 1] - G[g]) throw MarkerError(e.head, G[g] + r, e.tail);
          r -= G[g + 1] - G[g];
        }
        throw;
      }
      m = 0;
      for (int g : w.active)
        for (int k = G[g]; k < G[g + 1]; ++k, ++m) {
          U.row(k) = w.Ua.row(m);
          if (gradient) w.dU.row(k) = w.dUa.row(m);
        }
    }
    for (int g : w.active) constrain_group(g, X);
    size_t kept = 0;
    for (int g : w.active) {
      MarkerUpdateResult& res = w.results[g];
      res.interpolations = predictor + I + 1;
      res.iterations = I;
      // g(X) = X - X^n - dt/2 (U^n(X^n) + U^{n+1}(X)), Eq. (59)
      double g_max = 0.0;
      int worst = G[g];
      for (int k = G[g]; k < G[g + 1]; ++k) {
        const double gx = X(k, 0) - X_n(k, 0) - 0.5 * dt * (U_n(k, 0) + U(k, 0));
        const double gy = X(k, 1) - X_n(k, 1) - 0.5 * dt * (U_n(k, 1) + U(k, 1));
        w.g(k, 0) = gx;
        w.g(k, 1) = gy;
        const double r = std::sqrt(gx * gx + gy * gy);
        if (!(r <= g_max)) g_max = r, worst = k;  // (a NaN is the worst)
      }
      res.residual = g_max;
      auto no_convergence = [&] {
        std::ostringstream tail;
        tail << ": |g| = " << g_max << " after " << I << " iterations (tolerance " << prm.eps << ")";
        return MarkerError("marker update did not converge at step " + std::to_string(step) + ": marker ", worst,
                                 tail.str());
      };
      if (!std::isfinite(g_max)) throw no_convergence();
      if (g_max <= prm.eps) continue;  // converged
      if (gradient && prm.newton) {
        // Newton step X^[I+1] = X^[I] + d, (I - dt/2 dU/dX) d = -g(X^[I]) (dU/dX at X^[I]): the root of g
        // linearised at X^[I]; accepted when max |d| <= lim, U^{n+1}(X^[I+1]) = U^{n+1}(X^[I]) + dU/dX d
        const double c = 0.5 * dt;
        double d_max = 0.0;
        for (int k = G[g]; k < G[g + 1]; ++k) {
          const double J00 = w.dU(k, 0), J01 = w.dU(k, 1), J10 = w.dU(k, 2), J11 = w.dU(k, 3);
          const double a00 = 1.0 - c * J00, a01 = -c * J01, a10 = -c * J10, a11 = 1.0 - c * J11;
          const double det = a00 * a11 - a01 * a10;
          const double gx = w.g(k, 0), gy = w.g(k, 1);
          const double dx = -(a11 * gx - a01 * gy) / det, dy = -(a00 * gy - a10 * gx) / det;
          w.g(k, 0) = dx;  // (g no longer needed: the step in its place)
          w.g(k, 1) = dy;
          X(k, 0) += dx;
          X(k, 1) += dy;
          const double d = std::sqrt(dx * dx + dy * dy);
          if (!(d <= d_max)) d_max = d;  // (a NaN is the largest)
        }
        check_moves(G[g], G[g + 1]);
        if (d_max <= lim) {
          for (int k = G[g]; k < G[g + 1]; ++k) {
            const double dx = w.g(k, 0), dy = w.g(k, 1);
            U(k, 0) += w.dU(k, 0) * dx + w.dU(k, 1) * dy;
            U(k, 1) += w.dU(k, 2) * dx + w.dU(k, 3) * dy;
          }
          constrain_group(g, X);
          res.iterations = I + 1;
          res.residual = 0.0;  // its first-order value (the quadratic term is below dt/4 |grad grad U| lim^2)
          res.linearised = true;
          continue;
        }
        if (I == prm.max_iter) throw no_convergence();
        w.active[kept++] = g;  // iterates on from the Newton iterate
        continue;
      }
      X.middleRows(G[g], G[g + 1] - G[g]) =  // fixed-point iteration X^[I+1] = X^[I] - g(X^[I])
          X_n.middleRows(G[g], G[g + 1] - G[g]) +
          0.5 * dt * (U_n.middleRows(G[g], G[g + 1] - G[g]) + U.middleRows(G[g], G[g + 1] - G[g]));
      check_moves(G[g], G[g + 1]);
      if (gradient && g_max <= lim) {
        // linearised acceptance: U^{n+1}(X^[I+1]) = U^{n+1}(X^[I]) + dU/dX (X^[I+1] - X^[I]) when the
        // linear residual |dt/2 dU/dX g| is below eps/2 at every marker of the group
        double r_max = 0.0;
        for (int k = G[g]; k < G[g + 1]; ++k) {
          const double gx = w.g(k, 0), gy = w.g(k, 1);
          const double ex = w.dU(k, 0) * gx + w.dU(k, 1) * gy, ey = w.dU(k, 2) * gx + w.dU(k, 3) * gy;  // dU/dX g
          r_max = std::max(r_max, 0.5 * dt * std::sqrt(ex * ex + ey * ey));
        }
        if (r_max <= 0.5 * prm.eps) {
          for (int k = G[g]; k < G[g + 1]; ++k) {
            const double gx = w.g(k, 0), gy = w.g(k, 1);
            U(k, 0) -= w.dU(k, 0) * gx + w.dU(k, 1) * gy;
            U(k, 1) -= w.dU(k, 2) * gx + w.dU(k, 3) * gy;
          }
          constrain_group(g, X);
          res.iterations = I + 1;
          res.residual = r_max;
          res.linearised = true;
          continue;
        }
      }
      if (I == prm.max_iter) throw no_convergence();
      w.active[kept++] = g;  // iterates on
    }
    w.active.resize(kept);
    if (kept == 0) break;
  }
  MarkerUpdateResult worst;
  for (const MarkerUpdateResult& r : w.results) {
    worst.iterations = std::max(worst.iterations, r.iterations);
    worst.interpolations = std::max(worst.interpolations, r.interpolations);
    worst.residual = std::max(worst.residual, r.residual);
    worst.linearised |= r.linearised;
  }
  return worst;
}

}  // namespace sphib
