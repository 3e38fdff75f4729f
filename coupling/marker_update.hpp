#pragma once
// Semi-implicit marker update, Eqs. (56)-(60): trapezoidal rule solved by fixed-point iteration.
//   X^[0]   = X^n + dt U^{n+1}(X^n)                                   (Eq. 58, predictor "euler")
//   X^[0]   = X^n + dt (3/2 U^n(X^n) - 1/2 U^{n-1}(X^{n-1}))          (predictor "extrapolated")
//   X^[I+1] = X^n + dt/2 (U^n(X^n) + U^{n+1}(X^[I]))                   (root of g, Eq. 59)
// until max_k |g(X_k^[I])| <= eps; U^{n+1}(X) from the fluid velocity after the step, by either
// interpolation of coupling/interpolate.hpp. Both predictors lead to the same root within eps; the
// paper's costs one interpolation more and starts O(dt^2) from it, the Adams-Bashforth
// extrapolation (no interpolation: U^n and U^{n-1} are known) starts O(dt^3) from it, so that one
// iterate usually meets eps = 1e-12.
//
// Linearised acceptance (when the interpolation also gives dU/dX, the divergence-free one): the
// iterate X^[I+1] = X^[I] - g(X^[I]) is a step of |g| (~1e-11 on the main job) from the point
// where U and dU/dX were interpolated, so there
//   U^{n+1}(X^[I+1]) = U^{n+1}(X^[I]) - dU/dX g + O(|g|^2),   g(X^[I+1]) = dt/2 dU/dX g + O(dt |g|^2).
// X^[I+1] is accepted without interpolating there when the step is below linear_step = 1e-6 of
// max_move (one lattice spacing: U varies on the kernel's scale h, so the neglected terms are ~1e-6
// of the linear ones) and the linear residual |dt/2 dU/dX g| is below eps/2; U^{n+1}(X^{n+1}) is then
// the linearised value (the next step's U^n(X^n)), exact to O(|g|^2) ~ 1e-22. One interpolation
// (with its gradient) per step instead of two, the same root within eps.
//
// Newton step (prm.newton): where the first iterate is too far from the root for the above (beyond
// linear_step at nearly every step of the suspension case, docs/suspensions.md), the step from X^[I]
// is the root of g linearised there, X^[I+1] = X^[I] + d with (I - dt/2 dU/dX) d = -g(X^[I]), whose
// linear residual is zero:
//   g(X^[I+1]) = -dt/2 (U^{n+1}(X^[I+1]) - U^{n+1}(X^[I]) - dU/dX d) = O(dt/4 |grad grad U| |d|^2).
// It is accepted without interpolating when max |d| <= linear_step max_move, U^{n+1}(X^{n+1}) the
// linearised U^{n+1}(X^[I]) + dU/dX d; otherwise the iteration interpolates at X^[I+1] and takes
// Newton steps on (quadratic convergence). linear_step then bounds only the quadratic term.
//
// Area constraint (prm.keep_area; the caller's `constrain`): every evaluation of U^{n+1} at an
// iterate X, and the linearised one that is accepted, is changed so that grad A(X_mid) . (U^n +
// U^{n+1}) = 0, X_mid = (X^n + X) / 2, A the group's enclosed area (quadratic in X:
// membrane/geometry.hpp). At the root X^{n+1} - X^n = dt/2 (U^n + U^{n+1}), and for a quadratic A
//   A(X^{n+1}) - A(X^n) = grad A(X_mid) . (X^{n+1} - X^n) = 0
// exactly: the step keeps the area to the residual (|grad A| eps). The Jacobian dU/dX of the Newton
// step leaves the constraint out: the iteration still converges to the root of g with the
// constrained U.
//
// Every marker's equation g(X_k) = 0 is its own (U^{n+1}(X_k) depends on X_k alone), so several
// membranes advance as one set of markers, each membrane a group with its own decisions: a group
// stops when its largest |g| is below eps or when the linearised acceptance holds for all its
// markers, and the groups still iterating are interpolated again together, in one call. Each group
// goes through exactly the steps it would alone (bit for bit: the interpolations are pointwise).
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling/params.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

// The marker velocity U^{n+1} at points X (Nb x 2) into U (Nb x 2); with dU non-null also its
// gradient at X if the interpolation has one. Returns whether dU was filled.
using MarkerVelocity = std::function<bool(const Mat2& X, Mat2& U, Jacobians* dU)>;
// The area constraint on group g's U^{n+1} at its iterate X, given the step's start X^n and U^n
// (rows of one group).
using MarkerConstraint = std::function<void(int g, Eigen::Ref<const Mat2> X_n, Eigen::Ref<const Mat2> U_n,
                                            Eigen::Ref<const Mat2> X, Eigen::Ref<Mat2> U)>;

struct MarkerWork {  // advance_markers' workspace (sized on first use) and its results by group
  Mat2 g;            // g(X^[I]) per marker
  Jacobians dU;      // dU/dX at X^[I]
  std::vector<int> active;  // the groups still iterating
  Mat2 Xa, Ua;       // their markers' positions and velocities, gathered
  Jacobians dUa;
  std::vector<MarkerUpdateResult> results;  // of the last update, by group
};

// A marker update that failed: a marker moving more than max_move in a step (a blow-up), a group's
// iteration not converging (its worst marker), a marker with no fluid around it (interpolate.hpp).
// Names the marker by its row of X: what() is head + marker + tail.
struct MarkerError : std::runtime_error {
  MarkerError(std::string head_, int marker_, std::string tail_)
      : std::runtime_error(head_ + std::to_string(marker_) + tail_), head(std::move(head_)), tail(std::move(tail_)),
        marker(marker_) {}
  std::string head, tail;
  int marker;
};

// X holds X^n on entry and X^{n+1} on exit; U_n = U^n(X^n); U_prev = U^{n-1}(X^{n-1}) or nullptr
// (the first step, or prm.extrapolate off: Eq. 58); U is workspace (Nb x 2) and holds
// U^{n+1}(X^{n+1}) on exit (interpolated, or linearised as above). `groups`: the markers of group g
// are the rows [groups[g], groups[g+1]) (nullptr: one group of all); work.results holds each group's
// result, and the return value their worst (most iterations and interpolations, largest residual).
// `constrain` (or nullptr) is applied to each group's U^{n+1} wherever it is evaluated (above).
// Throws MarkerError naming `step`, the marker and its move (a blow-up) or its residual (a
// group not converging in max_iter iterations).
MarkerUpdateResult advance_markers(const MarkerVelocity& U_new, const Mat2& U_n, const Mat2* U_prev, double dt,
                                   const MarkerUpdateParams& prm, long step, Mat2& X, Mat2& X_n, Mat2& U,
                                   MarkerWork& work, const std::vector<int>* groups = nullptr,
                                   const MarkerConstraint* constrain = nullptr);

}  // namespace sphib
