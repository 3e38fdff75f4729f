#pragma once
// Semi-implicit marker update, Eqs. (56)-(60): trapezoidal rule solved by fixed-point iteration.
//   X^[0]   = X^n + dt U^{n+1}(X^n)                                   (Eq. 58, predictor "euler")
//   X^[0]   = X^n + dt (3/2 U^n(X^n) - 1/2 U^{n-1}(X^{n-1}))          (predictor "extrapolated")
//   X^[I+1] = X^n + dt/2 (U^n(X^n) + U^{n+1}(X^[I]))                   (root of g, Eq. 59)
// until max_k |g(X_k^[I])| <= eps; U^{n+1}(X) from the fluid velocity after the step, by either
// interpolation of coupling/interpolate.hpp. Both predictors lead to the same root within eps; the
// paper's costs one interpolation more and starts O(dt^2) from it, the Adams-Bashforth
// extrapolation (no interpolation: U^n and U^{n-1} are known) starts O(dt^3) from it, so that one
// iterate usually meets eps = 1e-12 (main job: 2 interpolations per step instead of 4).
#include <functional>

#include "fluid/types.hpp"

namespace sphib {

struct MarkerUpdateParams {
  double eps = 1e-12;  // tolerance on max_k |g_k| (a length)
  int max_iter = 50;
  double max_move = 0;  // > 0: a marker moving farther in one step is a blow-up (the Simulation sets dx)
  bool extrapolate = true;  // predictor: AB2 extrapolation when U^{n-1} is known, else Eq. (58)
};

struct MarkerUpdateResult {
  int iterations = 0;
  double residual = 0;  // max_k |g_k| at the accepted iterate
};

// The marker velocity U^{n+1} at points X (Nb x 2) into U (Nb x 2).
using MarkerVelocity = std::function<void(const Mat2& X, Mat2& U)>;

// X holds X^n on entry and X^{n+1} on exit; U_n = U^n(X^n); U_prev = U^{n-1}(X^{n-1}) or nullptr
// (the first step, or prm.extrapolate off: Eq. 58); U is workspace (Nb x 2) and holds
// U^{n+1}(X^{n+1}) on exit. Throws std::runtime_error naming `step` and the residual if the
// iteration does not reach eps in max_iter iterations.
MarkerUpdateResult advance_markers(const MarkerVelocity& U_new, const Mat2& U_n, const Mat2* U_prev, double dt,
                                   const MarkerUpdateParams& prm, long step, Mat2& X, Mat2& X_n, Mat2& U);

}  // namespace sphib
