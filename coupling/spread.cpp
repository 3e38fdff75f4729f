#include "coupling/spread.hpp"

#include "coupling/neighbourhood.hpp"
#include "fluid/algebra/row_stencil.hpp"  // kParallelRows
#include "kernels/spread.hpp"

#include <exception>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphib {

namespace {

// F += sum_k W(x_i - X_k, h*) (fx_k, fy_k), with fx_k = fx(k) (Eq. 53): the markers one after the other.
// On the fixed lattice from kParallelMarkers markers and kParallelRows points, by the threads: each
// owns a fixed range of the points and walks every marker in order, adding only into the lattice rows
// that start in its range (a row whole to one thread), so every point receives its markers' terms
// in the serial order: the same bits for any thread count.
constexpr int kParallelMarkers = 256;
static_assert(CellGrid::LatticeBox::kMax <= LatticeRows::kMaxCols, "a lattice box fits the spreading kernel");

template <class Fx, class Fy>
void spread(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, Fx&& fx_of, Fy&& fy_of, Mat2& F) {
  const double radius = W_star.support();
  if (grid.lattice_mode()) {
    const long N = F.rows();
    const bool par = X.rows() >= kParallelMarkers && N >= kParallelRows;
    (void)par;
    std::exception_ptr fault;  // lattice_box's refusal (every thread meets it at the same marker)
#pragma omp parallel if (par)
    try {
#ifdef _OPENMP
      const long t = omp_get_thread_num(), T = omp_get_num_threads();
#else
      const long t = 0, T = 1;
#endif
      const long lo = N * t / T, hi = N * (t + 1) / T;  // the rows starting in [lo, hi)
      CellGrid::LatticeBox box;
      for (int k = 0; k < X.rows(); ++k) {
        if (T == 1) grid.lattice_box(X(k, 0), X(k, 1), radius, box);
        else grid.lattice_box(X(k, 0), X(k, 1), radius, lo, hi, box);  // this thread's rows of the box, in their order
        if (box.nrow == 0) continue;
        const LatticeRows rows{box.ncol, box.nrow, box.col, box.cdx, box.base, box.ry};
        spread_rows(rows, W_star.scale(), fx_of(k), fy_of(k), F.col(0).data(), F.col(1).data());  // Eq. (53)
      }
    } catch (...) {
#pragma omp critical(sphib_spread_fault)
      if (!fault) fault = std::current_exception();
    }
    if (fault) std::rethrow_exception(fault);
    return;
  }
  Neighbourhood nb;
  for (int k = 0; k < X.rows(); ++k) {
    nb.gather(grid, X(k, 0), X(k, 1), radius, /*offsets=*/false);
    spread_pairs(nb.points(), W_star.scale(), fx_of(k), fy_of(k), F.col(0).data(), F.col(1).data());  // Eq. (53)
  }
}

}  // namespace

void spread_force(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& f,
                  double ds, Mat2& F) {
  spread(grid, W_star, X, [&](int k) { return f(k, 0) * ds; }, [&](int k) { return f(k, 1) * ds; }, F);  // f_k ds
}

void spread_point_forces(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& P, Mat2& F) {
  spread(grid, W_star, X, [&](int k) { return P(k, 0); }, [&](int k) { return P(k, 1); }, F);
}

}  // namespace sphib
