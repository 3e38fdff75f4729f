#include "coupling/spread.hpp"

namespace sphib {

void spread_force(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& f,
                  double ds, Mat2& F) {
  const double radius = W_star.support();
  for (int k = 0; k < X.rows(); ++k) {
    const double fx = f(k, 0) * ds, fy = f(k, 1) * ds;  // f_k ds
    grid.for_each_near(X(k, 0), X(k, 1), radius, [&](int i, double, double, double r) {
      const double w = W_star.W(r);  // W(x_i - X_k, h*)
      F(i, 0) += fx * w;               // Eq. (53)
      F(i, 1) += fy * w;
    });
  }
}

}  // namespace sphib
