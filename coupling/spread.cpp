#include "coupling/spread.hpp"

#include "coupling/neighbourhood.hpp"

namespace sphib {

void spread_force(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& f,
                  double ds, Mat2& F) {
  const double radius = W_star.support();
  Neighbourhood nb;
  for (int k = 0; k < X.rows(); ++k) {
    const double fx = f(k, 0) * ds, fy = f(k, 1) * ds;  // f_k ds
    nb.gather(grid, X(k, 0), X(k, 1), radius, /*offsets=*/false);
    for (int m = 0; m < nb.pairs; ++m) {
      const Lanes2 w = W_star.W2(nb.r2(m));  // W(x_i - X_k, h*), 0 beyond 2h*
      const int i0 = nb.j0(m), i1 = nb.j1(m);
      F(i0, 0) += fx * w[0];  // Eq. (53)
      F(i0, 1) += fy * w[0];
      F(i1, 0) += fx * w[1];
      F(i1, 1) += fy * w[1];
    }
  }
}

}  // namespace sphib
