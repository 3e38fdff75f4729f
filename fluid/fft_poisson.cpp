#include "fluid/fft_poisson.hpp"
#include "fluid/profile.hpp"
#include "fluid/products.hpp"  // kParallelRows

#include <fftw3.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <vector>

// LAPACK's banded Cholesky factorisation (the trailing argument is the hidden length of the Fortran
// character argument).
extern "C" {
void dpbtrf_(const char* uplo, const int* n, const int* kd, double* ab, const int* ldab, int* info, std::size_t);
}

namespace sphib {

namespace {

using Clock = std::chrono::steady_clock;

struct Work {  // one column's arrays: the right-hand side, its transform, the solution
  double* in = nullptr;
  double* out = nullptr;
  fftw_complex* hat = nullptr;
};

class FftPoissonSolver final : public LinearSolver {
 public:
  FftPoissonSolver(const std::string& system, const Lattice& L, bool singular)
      : nx_(L.nx), ny_(L.ny), nk_(L.nx / 2 + 1), singular_(singular) {
    info_.system = system;
    info_.n = nx_ * ny_;
    const int N = info_.n;
    for (Work& w : ws_) {  // a workspace per thread (two columns at once, see solve)
      w.in = fftw_alloc_real(N);
      w.out = fftw_alloc_real(N);
      w.hat = fftw_alloc_complex(static_cast<std::size_t>(nk_) * ny_);
    }
    double *in_ = ws_[0].in, *out_ = ws_[0].out;
    fftw_complex* hat_ = ws_[0].hat;
    // Rows of n_x along x (idist n_x); the transform of row i_y, wavenumber k goes to hat[i_y nk + k],
    // so that the banded solves run over all wavenumbers at once (contiguous, vectorised).
    // FFTW_ESTIMATE: the same plan, hence the same bits, in every run.
    const int n[1] = {nx_};
    fwd_ = fftw_plan_many_dft_r2c(1, n, ny_, in_, nullptr, 1, nx_, hat_, nullptr, 1, nk_, FFTW_ESTIMATE);
    inv_ = fftw_plan_many_dft_c2r(1, n, ny_, hat_, nullptr, 1, nk_, out_, nullptr, 1, nx_,
                                  FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
    if (!fwd_ || !inv_) {
      release();
      throw std::runtime_error("linear solver: system '" + system + "': FFTW could not plan the transforms");
    }
  }
  ~FftPoissonSolver() override { release(); }

  // Extracts the block-circulant model of A and factorises the banded systems; false (and `why`)
  // when A lacks the structure or a B_k is not positive definite.
  bool setup(const SpMat& A, std::string* why) {
    auto refuse = [&](const std::string& w) {
      if (why) *why = w;
      return false;
    };
    const int nx = nx_, ny = ny_, N = info_.n;
    if (A.rows() != N || A.cols() != N) return refuse("the matrix is not n_x n_y square");
    const auto t0 = Clock::now();
    const int* o = A.outerIndexPtr();
    const int* c = A.innerIndexPtr();
    const double* a = A.valuePtr();
    double amax = 0;
    int w = 0;
    for (int i = 0; i < N; ++i)
      for (int k = o[i]; k < o[i + 1]; ++k) {
        amax = std::max(amax, std::fabs(a[k]));
        w = std::max(w, std::abs(c[k] / nx - i / nx));
      }
    if (!(amax > 0)) return refuse("the matrix is zero");
    if (2 * w + 1 > ny) return refuse("the band in y is as wide as the lattice");
    const int nd = 2 * w + 1;
    const double tol = 1e-12 * amax;
    // The model C(i_y, d_y, d_x) from the rows i_x = 0: slot (d_y + w) n_x + d_x.
    std::vector<double> C(static_cast<std::size_t>(ny) * nd * nx, 0.0);
    std::vector<char> present(C.size(), 0);
    std::vector<std::vector<int>> slots(ny);
    auto slot = [&](int i, int j) {
      const int dy = j / nx - i / nx, dx = ((j % nx - i % nx) % nx + nx) % nx;
      return static_cast<std::size_t>(i / nx) * nd * nx + static_cast<std::size_t>(dy + w) * nx + dx;
    };
    for (int iy = 0; iy < ny; ++iy) {
      const int i = nx * iy;
      for (int k = o[i]; k < o[i + 1]; ++k) {
        const std::size_t s = slot(i, c[k]);
        C[s] = a[k];
        present[s] = 1;
        slots[iy].push_back(static_cast<int>(s - static_cast<std::size_t>(iy) * nd * nx));
      }
    }
    // Every row against the model: its entries, and no model entry missing from it.
    std::vector<int> seen(static_cast<std::size_t>(nd) * nx, -1);
    for (int i = 0; i < N; ++i) {
      const int iy = i / nx;
      const std::size_t base = static_cast<std::size_t>(iy) * nd * nx;
      for (int k = o[i]; k < o[i + 1]; ++k) {
        const std::size_t s = slot(i, c[k]);
        if (!present[s] ? std::fabs(a[k]) > tol : std::fabs(a[k] - C[s]) > tol) {
          std::ostringstream m;
          m << "row " << i << " is not a translate along x of row " << nx * iy << " (not block circulant)";
          return refuse(m.str());
        }
        seen[s - base] = i;
      }
      for (int s : slots[iy])
        if (seen[s] != i && std::fabs(C[base + s]) > tol) {
          std::ostringstream m;
          m << "row " << i << " lacks an entry of row " << nx * iy << " (not block circulant)";
          return refuse(m.str());
        }
    }
    // Even in d_x: B_k is real.
    for (int iy = 0; iy < ny; ++iy)
      for (int s : slots[iy]) {
        const int d = s / nx, dx = s % nx;
        const std::size_t base = static_cast<std::size_t>(iy) * nd * nx + static_cast<std::size_t>(d) * nx;
        if (std::fabs(C[base + dx] - C[base + (nx - dx) % nx]) > tol)
          return refuse("the coefficients are not even in the x offset");
      }
    // The bands of B_k in LAPACK's lower storage: ab[(i - j) + ldab j] = B_k(i, j), j <= i <= j + w.
    ldab_ = w + 1;
    w_ = w;
    std::vector<double> band(static_cast<std::size_t>(nk_) * ldab_ * ny, 0.0);  // B_k, then its factor
    std::vector<double> cosine(nx);
    for (int m = 0; m < nx; ++m) cosine[m] = std::cos(2.0 * M_PI * m / nx);
    double bmax = 0, asym = 0;
    std::vector<double> full(static_cast<std::size_t>(ny) * nd);  // B_k(i_y, i_y + d), all d, for the symmetry check
    for (int kk = 0; kk < nk_; ++kk) {
      std::fill(full.begin(), full.end(), 0.0);
      for (int iy = 0; iy < ny; ++iy)
        for (int s : slots[iy]) {
          const int d = s / nx, dx = s % nx;
          full[static_cast<std::size_t>(iy) * nd + d] +=
              C[static_cast<std::size_t>(iy) * nd * nx + s] * cosine[(static_cast<long>(kk) * dx) % nx];
        }
      double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny;
      for (int iy = 0; iy < ny; ++iy)
        for (int d = -w; d <= 0; ++d) {
          if (iy + d < 0) continue;
          const double v = full[static_cast<std::size_t>(iy) * nd + d + w];
          const double vt = full[static_cast<std::size_t>(iy + d) * nd + (-d) + w];  // B_k(i_y + d, i_y)
          bmax = std::max(bmax, std::fabs(v));
          asym = std::max(asym, std::fabs(v - vt));
          ab[(-d) + static_cast<std::size_t>(ldab_) * (iy + d)] = v;
        }
    }
    if (asym > 1e-10 * bmax) return refuse("the matrix is not symmetric");
    // Singular A: a wavenumber whose B_k annihilates the constants or the alternating vector in y
    // (to 1e-10 of max |B|) is a null direction of A (fluid/gauge.hpp): k = 0 for -lap phi; k = 0
    // and k = n_x/2 for the exact projection's G^T G (1 and (-1)^{i_x} in y); the same with (-1)^{i_y}
    // for a stream function's (odd images).
    drop_.assign(nk_, 0);
    if (singular_)
      for (int kk = 0; kk < nk_; ++kk) {
        const double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny;
        for (int alt = 0; alt < 2 && !drop_[kk]; ++alt) {
          std::vector<double> r(ny, 0.0);  // B_k z, from the lower band and its mirror
          auto z = [&](int j) { return alt && (j & 1) ? -1.0 : 1.0; };
          for (int j = 0; j < ny; ++j)
            for (int d = 0; d <= w && j + d < ny; ++d) {
              const double v = ab[d + static_cast<std::size_t>(ldab_) * j];  // B_k(j + d, j)
              r[j + d] += v * z(j);
              if (d) r[j] += v * z(j + d);
            }
          double rmax = 0;
          for (double v : r) rmax = std::max(rmax, std::fabs(v));
          drop_[kk] = rmax <= 1e-10 * bmax;
        }
      }
    if (singular_ && std::find(drop_.begin(), drop_.end(), 1) == drop_.end())
      return refuse("the matrix was said to be singular but no wavenumber block is");
    info_.analyse_seconds = seconds_since(t0);
    const auto t1 = Clock::now();
    for (int kk = 0; kk < nk_; ++kk) {
      // A singular B_k (constants in y, see above): i_y = 0 is dropped (x(k, 0) = 0), the rest is definite.
      const bool drop = drop_[kk];
      double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny + (drop ? ldab_ : 0);
      const int n = drop ? ny - 1 : ny;
      int info = 0;
      dpbtrf_("L", &n, &w_, ab, &ldab_, &info, 1);
      if (info != 0) {
        std::ostringstream m;
        m << "the banded system of wavenumber " << kk << " is not positive definite (LAPACK dpbtrf info " << info << ")";
        return refuse(m.str());
      }
    }
    // The factors rearranged wavenumber-fastest: lrow[(i ldab + d) nk + k] = L_k(i, i - d) (forward
    // substitution), lcol[(i ldab + d) nk + k] = L_k(i + d, i) (backward), rdiag = 1 / L_k(i, i).
    // Singular blocks: row and column 0 (dropped, x = 0 there) are zeros, so no wavenumber is special.
    lrow_.assign(static_cast<std::size_t>(ny) * ldab_ * nk_, 0.0);
    lcol_.assign(lrow_.size(), 0.0);
    rdiag_.assign(static_cast<std::size_t>(ny) * nk_, 0.0);
    for (int kk = 0; kk < nk_; ++kk) {
      const double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny;
      const int i0 = drop_[kk] ? 1 : 0;
      for (int i = i0; i < ny; ++i) {
        rdiag_[static_cast<std::size_t>(i) * nk_ + kk] = 1.0 / ab[static_cast<std::size_t>(ldab_) * i];
        for (int d = 1; d <= w; ++d) {
          if (i - d >= i0) lrow_[(static_cast<std::size_t>(i) * ldab_ + d) * nk_ + kk] = ab[d + static_cast<std::size_t>(ldab_) * (i - d)];
          if (i + d < ny) lcol_[(static_cast<std::size_t>(i) * ldab_ + d) * nk_ + kk] = ab[d + static_cast<std::size_t>(ldab_) * i];
        }
      }
    }
    info_.factor_seconds = seconds_since(t1);
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    info_.nnz_factor = static_cast<long>(nk_) * ldab_ * ny;
    std::ostringstream m;
    m << "FFT in x (FFTW) + banded Cholesky in y (LAPACK dpbtrf): " << nk_ << " systems of " << ny
      << ", half-bandwidth " << w;
    info_.method = m.str();
    return true;
  }

  // Columns are independent: with OpenMP and a large lattice two threads take one each (u and v of
  // the Crank-Nicolson system), each in its own workspace (FFTW's new-array execute is thread-safe).
  void solve(const double* B, double* X, int k) override {
    const int N = info_.n;
    const bool par = k >= 2 && N >= kParallelRows;
    (void)par;
#ifdef _OPENMP
    const int nt = std::min(2, omp_get_max_threads());  // OMP_NUM_THREADS = 1 keeps it serial
#else
    const int nt = 1;
#endif
    (void)nt;
#pragma omp parallel for num_threads(nt) schedule(static, 1) if (par)
    for (int col = 0; col < k; ++col) {
#ifdef _OPENMP
      Work& w = ws_[omp_get_thread_num() % 2];
#else
      Work& w = ws_[0];
#endif
      solve_column(B + static_cast<std::size_t>(col) * N, X + static_cast<std::size_t>(col) * N, w);
    }
  }

  void solve_column(const double* b, double* x, Work& ws) const {
    const int N = info_.n, ny = ny_;
    std::copy(b, b + N, ws.in);
    fftw_execute_dft_r2c(fwd_, ws.in, ws.hat);
    // B_k x = b for every wavenumber k, real and imaginary parts together (B_k is real): L y = b,
    // then L' x = y, in place, each row over all k at once. By hand rather than LAPACK dpbtrs,
    // whose Level-2 calls on bands of 2-5 cost 4x the rest of the solve (perf: 70 of 85 us per
    // step at 64 x 64).
    double* h = reinterpret_cast<double*>(ws.hat);  // (re, im) of row i, wavenumber k at 2 (i nk + k)
    for (int i = 0; i < ny; ++i) substitute_row(h, i, -1, lrow_, std::min(w_, i));                // L y = b
    for (int i = ny - 1; i >= 0; --i) substitute_row(h, i, +1, lcol_, std::min(w_, ny - 1 - i));  // L' x = y
    fftw_execute_dft_c2r(inv_, ws.hat, ws.out);  // unnormalised: n_x times the inverse transform
    const double s = 1.0 / nx_;
    for (int i = 0; i < N; ++i) x[i] = s * ws.out[i];
  }

  // Row i of a substitution, all wavenumbers at once: h_i -= sum_{d=1..dmax} l(i, d) h_{i + dir d},
  // then h_i *= 1/L(i, i) (dir -1: forward with lrow_, +1: backward with lcol_).
  void substitute_row(double* h, int i, int dir, const std::vector<double>& l, int dmax) const {
    const int nk = nk_;
    double* hi = h + 2 * static_cast<std::size_t>(i) * nk;
    for (int d = 1; d <= dmax; ++d) {
      const double* hj = h + 2 * static_cast<std::size_t>(i + dir * d) * nk;
      const double* c = l.data() + (static_cast<std::size_t>(i) * ldab_ + d) * nk;
      for (int k = 0; k < nk; ++k) {
        hi[2 * k] -= c[k] * hj[2 * k];
        hi[2 * k + 1] -= c[k] * hj[2 * k + 1];
      }
    }
    const double* r = rdiag_.data() + static_cast<std::size_t>(i) * nk;
    for (int k = 0; k < nk; ++k) {
      hi[2 * k] *= r[k];
      hi[2 * k + 1] *= r[k];
    }
  }

  bool refactorize(const SpMat& A) override {
    std::string why;
    if (!setup(A, &why)) throw std::runtime_error("linear solver: system '" + info_.system + "': " + why);
    return true;
  }

 private:
  void release() {
    if (fwd_) fftw_destroy_plan(fwd_);
    if (inv_) fftw_destroy_plan(inv_);
    for (Work& w : ws_) {
      if (w.in) fftw_free(w.in);
      if (w.out) fftw_free(w.out);
      if (w.hat) fftw_free(w.hat);
      w = Work{};
    }
    fwd_ = inv_ = nullptr;
  }

  int nx_, ny_, nk_, w_ = 0, ldab_ = 1;
  bool singular_;
  std::vector<char> drop_;  // per wavenumber: B_k singular, row 0 dropped
  std::vector<double> lrow_, lcol_, rdiag_;  // the factors, wavenumber fastest (see setup)
  Work ws_[2];
  fftw_plan fwd_ = nullptr, inv_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L,
                                              bool singular, std::string* why) {
  if (!L.domain.periodic_x || L.domain.periodic_y) {
    if (why) *why = "the domain is not periodic in x and walled in y";
    return nullptr;
  }
  auto s = std::make_unique<FftPoissonSolver>(system, L, singular);
  if (!s->setup(A, why)) return nullptr;
  return s;
}

}  // namespace sphib
