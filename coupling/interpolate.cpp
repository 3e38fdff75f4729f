#include "coupling/interpolate.hpp"

#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
struct Uniform {
  double v;
  double operator[](int) const { return v; }
};

template <class Volumes>
void interpolate(const CellGrid& grid, const CubicSplineKernel& W, const Volumes& V, const Mat2& u, const Mat2& X,
                 Mat2& U, bool normalised) {
  const double radius = W.support();
  for (int k = 0; k < X.rows(); ++k) {
    double sx = 0, sy = 0, sw = 0;
    grid.for_each_near(X(k, 0), X(k, 1), radius, [&](int j, double, double, double r) {
      const double w = W.W(r) * V[j];  // W(X_k - x_j, h) m_j / rho_j
      sx += u(j, 0) * w;             // numerator of Eq. (63)
      sy += u(j, 1) * w;
      sw += w;                       // denominator of Eq. (63)
    });
    if (!(sw > 0)) {
      std::ostringstream m;
      m << "interpolation: marker " << k << " at (" << X(k, 0) << ", " << X(k, 1)
        << ") has no fluid particle within 2h";
      throw std::runtime_error(m.str());
    }
    const double d = normalised ? sw : 1.0;
    U(k, 0) = sx / d;
    U(k, 1) = sy / d;
  }
}

}  // namespace

void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, double V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised) {
  interpolate(grid, W, Uniform{V}, u, X, U, normalised);
}

void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, const Vec& V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised) {
  interpolate(grid, W, V, u, X, U, normalised);
}

}  // namespace sphib
