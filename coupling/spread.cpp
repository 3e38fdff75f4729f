#include "coupling/spread.hpp"

#include "coupling/neighbourhood.hpp"
#include "fluid/algebra/row_stencil.hpp"  // kParallelRows

#include <exception>

#ifdef _OPENMP
#include <omp.h>
#endif

// Four-lane values (Lanes4) live only inside the inlined kernel of the AVX2 and default clones.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace sphib {

namespace {

// One marker's force f_k ds spread over its lattice box (the fixed lattice), row by row: W at every
// point of a row, four lanes at a time, then added along the row (Eq. 53). Points of the box beyond
// 2h* get W = 0 and add f ds * 0 = +-0, which leaves every value of F as it was (except that a -0
// would become +0; sums of +0 and non-zero terms never make -0), so F is bit for bit that of the
// loop over the points within 2h* (the points are distinct: the order among them is immaterial).
[[gnu::target_clones("avx2", "default")]] void spread_box(const CellGrid::LatticeBox& box, const CubicSplineKernel& W,
                                                          double fx, double fy, double* __restrict Fx,
                                                          double* __restrict Fy) {
  const int ncol = box.ncol, nlanes = (ncol + 3) / 4 * 4;
  const double beyond = 4.0 * W.support() * W.support();  // the padding lanes: W = 0
  alignas(32) double cdx2[CellGrid::LatticeBox::kMax + 4], w[CellGrid::LatticeBox::kMax + 4];
  for (int c = 0; c < nlanes; ++c) cdx2[c] = c < ncol ? box.cdx[c] * box.cdx[c] : beyond;
  const bool contiguous = ncol > 0 && box.col[ncol - 1] - box.col[0] == ncol - 1;  // no periodic wrap
  for (int r = 0; r < box.nrow; ++r) {
    const double ry2 = box.ry[r] * box.ry[r];
    for (int c = 0; c < nlanes; c += 4) {
#if defined(__clang__)
      // clang refuses a 256-bit vector argument in the default clone (no AVX there, a different
      // ABI): two two-lane halves instead, each lane by the same expressions, so the same values.
      for (int half = c; half < c + 4; half += 2) {
        const Lanes2 wc = W.W2(Lanes2{cdx2[half], cdx2[half + 1]} + lanes2(ry2));  // W(x_i - X_k, h*)
        w[half] = wc[0];
        w[half + 1] = wc[1];
      }
#else
      Lanes4 d2;
      __builtin_memcpy(&d2, cdx2 + c, sizeof d2);
      const Lanes4 wc = W.W2(d2 + lanes(Lanes4{}, ry2));  // W(x_i - X_k, h*), 0 beyond 2h*
      __builtin_memcpy(w + c, &wc, sizeof wc);
#endif
    }
    double* __restrict fxr = Fx + box.base[r];
    double* __restrict fyr = Fy + box.base[r];
    if (contiguous) {
      fxr += box.col[0];
      fyr += box.col[0];
      for (int c = 0; c < ncol; ++c) {
        fxr[c] += fx * w[c];  // Eq. (53)
        fyr[c] += fy * w[c];
      }
    } else {
      for (int c = 0; c < ncol; ++c) {
        fxr[box.col[c]] += fx * w[c];
        fyr[box.col[c]] += fy * w[c];
      }
    }
  }
}

}  // namespace

namespace {

// F += sum_k W(x_i - X_k, h*) (fx_k, fy_k), with fx_k = fx(k) (Eq. 53): the markers one after the other.
// On the fixed lattice from kParallelMarkers markers and kParallelRows points, by the threads: each
// owns a fixed range of the points and walks every marker in order, adding only into the lattice rows
// that start in its range (a row whole to one thread), so every point receives its markers' terms
// in the serial order: the same bits for any thread count.
constexpr int kParallelMarkers = 256;

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
        grid.lattice_box(X(k, 0), X(k, 1), radius, box);
        if (T > 1) {  // this thread's rows of the box, in their order
          int kept = 0;
          for (int r = 0; r < box.nrow; ++r)
            if (box.base[r] >= lo && box.base[r] < hi) {
              box.base[kept] = box.base[r];
              box.ry[kept++] = box.ry[r];
            }
          box.nrow = kept;
          if (kept == 0) continue;
        }
        spread_box(box, W_star, fx_of(k), fy_of(k), F.col(0).data(), F.col(1).data());
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
    const double fx = fx_of(k), fy = fy_of(k);
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

}  // namespace

void spread_force(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& f,
                  double ds, Mat2& F) {
  spread(grid, W_star, X, [&](int k) { return f(k, 0) * ds; }, [&](int k) { return f(k, 1) * ds; }, F);  // f_k ds
}

void spread_point_forces(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& P, Mat2& F) {
  spread(grid, W_star, X, [&](int k) { return P(k, 0); }, [&](int k) { return P(k, 1); }, F);
}

}  // namespace sphib
