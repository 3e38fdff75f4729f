#pragma once
// Normalised SPH interpolation (Eq. 61; for the markers Eq. 63) of K particle fields at points X:
//   out(k) = sum_j f_j W(X_k - x_j, h) V_j / sum_j W(X_k - x_j, h) V_j,
// exact for constant fields (the unnormalised form, Eq. 60, divides by 1 instead). The particles are
// those of `grid` (a CellGrid over the particles, or over the fixed lattice by index arithmetic); V
// is a vector of volumes or UniformVolume. One function for the coupling's marker velocities and for
// LPSPH's reinitialisation onto the lattice.
#include <array>
#include <sstream>
#include <stdexcept>
#include <string>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/neighbours.hpp"

namespace sphib {

struct UniformVolume {
  double v;
  double operator[](int) const { return v; }
};

// K columns of f (anything with f(j, c)) at the rows of X into out(k, c). A point with no particle
// within 2h throws std::runtime_error: "<what> k at (x, y) has no fluid particle within 2h".
template <int K, class Volumes, class Field, class Out>
void interpolate_normalised(const CellGrid& grid, const CubicSplineKernel& W, const Volumes& V, const Field& f,
                            const Mat2& X, Out& out, bool normalised, const char* what) {
  const double radius = W.support();
  for (int k = 0; k < X.rows(); ++k) {
    std::array<double, K> s{};
    double sw = 0;
    grid.for_each_near(X(k, 0), X(k, 1), radius, [&](int j, double, double, double r) {
      const double w = W.W(r) * V[j];                   // W(X_k - x_j, h) m_j / rho_j
      for (int c = 0; c < K; ++c) s[c] += f(j, c) * w;  // numerator
      sw += w;                                          // denominator
    });
    if (!(sw > 0)) {
      std::ostringstream m;
      m << what << " " << k << " at (" << X(k, 0) << ", " << X(k, 1) << ") has no fluid particle within 2h";
      throw std::runtime_error(m.str());
    }
    const double d = normalised ? sw : 1.0;
    for (int c = 0; c < K; ++c) out(k, c) = s[c] / d;
  }
}

}  // namespace sphib
