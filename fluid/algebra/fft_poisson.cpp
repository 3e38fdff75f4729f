#include "fluid/algebra/fft_poisson.hpp"
#include "fluid/common/profile.hpp"
#include "fluid/algebra/products.hpp"  // kParallelRows
#include "fluid/common/threads.hpp"
#include "kernels/banded.hpp"

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
#include <type_traits>
#include <utility>
#include <vector>

// LAPACK's banded Cholesky factorisation (the trailing argument is the hidden length of the Fortran
// character argument).
extern "C" {
void dpbtrf_(const char* uplo, const int* n, const int* kd, double* ab, const int* ldab, int* info, std::size_t);
}

namespace sphib {

namespace {

using Clock = std::chrono::steady_clock;

bool refuse(std::string& why, std::string reason) {
  why = std::move(reason);
  return false;
}

// A compressed matrix as one block of rows
MatrixRows whole(const SpMat& A) {
  return [&A](const std::function<void(const SpMat&, int)>& f) { f(A, 0); };
}

// ================================================================================================
// The structure of A (see the header): a model of its rows, checked against every row
// ================================================================================================

// The transform along x, by the x boundary and, between walls, the parity of the images.
// Along x: periodic, or walls whose images are even at both (DCT-II), odd at both (DST-II), even at
// the left and odd at the right (DCT-IV) or the reverse (DST-IV).
enum class XKind { Periodic, Even, Odd, EvenOdd, OddEven };
bool quarter_wave(XKind x) { return x == XKind::EvenOdd || x == XKind::OddEven; }

// One coefficient of a reference row: its offset slots along x and y (Model) and its value.
struct Entry {
  int sx, sy;
  double v;
};

// The entries of A's reference rows, one per row class, and how every other row follows from them.
// Row classes: lattice row i_y when y is walled (the y folds differ from row to row, so B_k is any
// banded matrix), a single class when y is periodic. Reference column ix0: 0 along a periodic x, the
// middle n_x / 2 between walls (its row must reach no image). Offset slots: along a periodic axis the
// offset mod n (n slots), along a walled one the offset plus the half-width w (2 w + 1 slots).
struct Model {
  int nx = 0, ny = 0;
  bool x_periodic = true, y_periodic = false;
  XKind x = XKind::Periodic;  // the parity of the x images, once the rows have been matched
  int ix0 = 0, wx = 0, wy = 0;
  double tol = 0;                       // 1e-12 max |A|
  long nnz = 0;                         // A's non-zeros (for info())
  std::vector<std::vector<Entry>> cls;  // per class, in the reference row's storage order

  int classes() const { return y_periodic ? 1 : ny; }
  int class_of(int iy) const { return y_periodic ? 0 : iy; }
  int nsx() const { return x_periodic ? nx : 2 * wx + 1; }
  int nsy() const { return y_periodic ? ny : 2 * wy + 1; }
  int slot_x(int ix, int jx) const { return x_periodic ? ((jx - ix) % nx + nx) % nx : jx - ix + wx; }
  int slot_y(int iy, int jy) const { return y_periodic ? ((jy - iy) % ny + ny) % ny : jy - iy + wy; }
  int mirror_x(int sx) const { return x_periodic ? (nx - sx) % nx : 2 * wx - sx; }  // offset -d_x
  int mirror_y(int sy) const { return y_periodic ? (ny - sy) % ny : 2 * wy - sy; }
  // |d| for a cosine: along a periodic axis the slot itself (cos(2 pi k s / n) has period n in s)
  int cos_dx(int sx) const { return x_periodic ? sx : std::abs(sx - wx); }
  int cos_dy(int sy) const { return y_periodic ? sy : std::abs(sy - wy); }
  // Whether row i is its class's reference row (column ix0; lattice row 0 when y is periodic).
  bool is_reference(int i, int ix0) const { return i % nx == ix0 && (!y_periodic || i / nx == 0); }
  // Row i's entries (columns c, values a, n of them) into max |A| and the half-width in y.
  void note_extent(int i, const int* c, const double* a, int n, double& amax) {
    for (int k = 0; k < n; ++k) {
      amax = std::max(amax, std::fabs(a[k]));
      if (!y_periodic) wy = std::max(wy, std::abs(c[k] / nx - i / nx));
    }
  }
};

// f(i, columns, values, count) for every row i of A in order, A's non-zeros counted and its extent
// (max |A|, the half-width in y) noted into m and amax on the way.
template <class F>
void each_row(const MatrixRows& A, Model& m, double& amax, F&& f) {
  A([&](const SpMat& B, int r0) {
    const int* o = B.outerIndexPtr();
    const int* c = B.innerIndexPtr();
    const double* a = B.valuePtr();
    m.nnz += B.nonZeros();
    for (int t = 0; t < B.rows(); ++t) {
      m.note_extent(r0 + t, c + o[t], a + o[t], o[t + 1] - o[t], amax);
      f(r0 + t, c + o[t], a + o[t], o[t + 1] - o[t]);
    }
  });
}

// (column, value) of each class's reference row, as read from A
using ReferenceRows = std::vector<std::vector<std::pair<int, double>>>;

// The model from the reference rows, max |A| and the half-width in y: the tolerance, the half-width
// in x between walls and the classes' entries; false (and why, when asked) when the lattice cannot
// hold them.
bool finish_model(Model& m, int ix0, double amax, const ReferenceRows& ref, std::string* why) {
  const auto no = [&](std::string reason) { return why ? refuse(*why, std::move(reason)) : false; };
  if (!(amax > 0)) return no("the matrix is zero");
  if (!m.y_periodic && 2 * m.wy + 1 > m.ny) return no("the band in y is as wide as the lattice");
  m.tol = 1e-12 * amax;
  m.ix0 = ix0;
  if (!m.x_periodic) {
    for (int cl = 0; cl < m.classes(); ++cl)
      for (const auto& [col, v] : ref[cl]) m.wx = std::max(m.wx, std::abs(col % m.nx - m.ix0));
    if (m.ix0 - m.wx < 1 || m.ix0 + m.wx > m.nx - 2) {
      std::ostringstream s;
      s << "the stencil (half-width " << m.wx << " in x) reaches a wall from the middle of the lattice (n_x = " << m.nx
        << "): no row free of images to take the model from";
      return no(s.str());
    }
  }
  m.cls.assign(m.classes(), {});
  for (int cl = 0; cl < m.classes(); ++cl)
    for (const auto& [col, v] : ref[cl]) m.cls[cl].push_back({m.slot_x(m.ix0, col % m.nx), m.slot_y(cl, col / m.nx), v});
  return true;
}

// Half-widths, reference rows and their entries; false (and why) when the lattice cannot hold them.
// One pass over A's rows: max |A|, the half-width in y and the rows the model may take its entries
// from (every row of column ix0 candidates: the half-width in x between walls comes from them).
bool extract_model(const MatrixRows& A, Model& m, std::string& why) {
  const int nx = m.nx;
  double amax = 0;
  ReferenceRows ref(m.classes());
  const int ix0 = m.x_periodic ? 0 : nx / 2;
  each_row(A, m, amax, [&](int i, const int* c, const double* a, int n) {
    if (m.is_reference(i, ix0))
      for (int k = 0; k < n; ++k) ref[m.class_of(i / nx)].emplace_back(c[k], a[k]);
  });
  return finish_model(m, ix0, amax, ref, &why);
}

const char* parity_name(int p) { return p > 0 ? "even" : "odd"; }

std::string mismatch(const Model& m, int i, int left, int right, const char* what) {
  std::ostringstream s;
  s << "row " << i << (*what ? " lacks an entry of" : " is not") << " row " << m.ix0 + m.nx * m.class_of(i / m.nx);
  if (m.x_periodic)
    s << (m.y_periodic ? " translated along x and y (not doubly circulant)" : " translated along x (not block circulant)");
  else
    s << " translated along x with the walls' "
      << (left == right ? std::string(parity_name(left)) : std::string(parity_name(left)) + " (left) and " + parity_name(right) + " (right)")
      << " images folded in"
      << (m.y_periodic ? " and translated along y" : "");
  return s.str();
}

// Whether every row equals its class's model translated along the periodic axes and folded at the x
// walls with images of sign `left` and `right` at the two walls (+1 even, -1 odd): each entry to m.tol, and no model entry
// missing. O(nnz): the predicted row is accumulated in `acc`, stamped by row. (Measured on every
// operator of tests/test_fft_solver.cpp, wall and corner rows included: the rows match their
// folded model to 5.9e-15 of max |A|, round-off of the different summation orders.)
bool rows_match(const MatrixRows& A, const Model& m, int left, int right, std::string& why) {
  const int nx = m.nx, ny = m.ny, N = nx * ny;
  std::vector<double> acc(N, 0.0);
  std::vector<int> stamp(N, -1), seen(N, -1), touched;
  bool ok = true;
  A([&](const SpMat& B, int r0) {
    const int* o = B.outerIndexPtr();
    const int* c = B.innerIndexPtr();
    const double* a = B.valuePtr();
    for (int t = 0; ok && t < B.rows(); ++t) {
      const int i = r0 + t;
      const int ix = i % nx, iy = i / nx;
      touched.clear();
      for (const Entry& e : m.cls[m.class_of(iy)]) {
        int jx = m.x_periodic ? (ix + e.sx) % nx : ix + e.sx - m.wx;
        double sign = 1.0;
        if (jx < 0 || jx >= nx) {  // an image: column -1 - jx or 2 n_x - 1 - jx carries its parent's value times parity
          sign = jx < 0 ? left : right;
          jx = jx < 0 ? -1 - jx : 2 * nx - 1 - jx;
        }
        const int jy = m.y_periodic ? (iy + e.sy) % ny : iy + e.sy - m.wy;
        const int j = jx + nx * jy;
        if (stamp[j] != i) {
          stamp[j] = i;
          acc[j] = 0.0;
          touched.push_back(j);
        }
        acc[j] += sign * e.v;
      }
      for (int k = o[t]; k < o[t + 1]; ++k) {
        const int j = c[k];
        if (std::fabs(a[k] - (stamp[j] == i ? acc[j] : 0.0)) > m.tol) {
          ok = refuse(why, mismatch(m, i, left, right, ""));
          break;
        }
        seen[j] = i;
      }
      if (!ok) break;
      for (int j : touched)
        if (seen[j] != i && std::fabs(acc[j]) > m.tol) {
          ok = refuse(why, mismatch(m, i, left, right, "lacks"));
          break;
        }
    }
  });
  return ok;
}

// Whether every class's stencil is even in d_x (B_k real) and, when y is periodic, in d_y (the
// eigenvalues sums of cosines).
bool model_even(const Model& m, std::string& why) {
  const int nsx = m.nsx();
  std::vector<double> dense(static_cast<std::size_t>(nsx) * m.nsy(), 0.0);
  auto at = [&](int sx, int sy) -> double& { return dense[static_cast<std::size_t>(sy) * nsx + sx]; };
  for (const auto& cl : m.cls) {
    for (const Entry& e : cl) at(e.sx, e.sy) = e.v;
    for (const Entry& e : cl) {
      if (std::fabs(e.v - at(m.mirror_x(e.sx), e.sy)) > m.tol) return refuse(why, "the coefficients are not even in the x offset");
      if (m.y_periodic && std::fabs(e.v - at(e.sx, m.mirror_y(e.sy))) > m.tol)
        return refuse(why, "the coefficients are not even in the y offset");
    }
    for (const Entry& e : cl) at(e.sx, e.sy) = 0.0;
  }
  return true;
}

// extract_model and rows_match in one pass over A's rows (A's rows are made once, not twice: the
// setup's G^T G is a product per row): each row is compared with its class's reference row as soon as
// that row has passed (the rows of a lattice row before it, between x walls the first n_x / 2, wait
// for it), and the largest deviation from the model and max |A| are kept, to be compared at the end
// (a deviation <= 1e-12 max |A| everywhere is rows_match's test with extract_model's tolerance). The
// reference rows are extract_model's and every prediction is rows_match's, summed in the same order,
// so the model and the verdict are theirs; true with m made as extract_model makes it when A passes
// every check of both, false otherwise (the caller then runs them, for the reason).
bool analyse_in_one_pass(const MatrixRows& A, Model& m, int left, int right) {
  const int nx = m.nx, ny = m.ny, N = nx * ny;
  const int ix0 = m.x_periodic ? 0 : nx / 2;
  double amax = 0, dev = 0;  // max |A|, the largest deviation from the model
  bool bad = false;          // a prediction off the lattice (a stencil reaching across a wall)
  ReferenceRows ref(m.classes());
  std::vector<char> have(m.classes(), 0);
  std::vector<double> acc(N, 0.0);
  std::vector<int> stamp(N, -1), seen(N, -1), touched;
  struct Pending {  // a row waiting for its class's reference row
    int i;
    std::vector<int> col;
    std::vector<double> val;
  };
  std::vector<Pending> pending;
  // row i (entries c[0 .. n - 1], a[...]) against its class's reference row, as rows_match
  const auto match = [&](int i, const int* c, const double* a, int n) {
    const int ix = i % nx, iy = i / nx, cl = m.class_of(iy);
    touched.clear();
    for (const auto& [col, v] : ref[cl]) {
      int jx;
      double sign = 1.0;
      if (m.x_periodic) {
        jx = (ix + col % nx) % nx;  // (ix0 = 0)
      } else {
        jx = ix + col % nx - ix0;
        if (jx < 0 || jx >= nx) {
          sign = jx < 0 ? left : right;
          jx = jx < 0 ? -1 - jx : 2 * nx - 1 - jx;
          if (jx < 0 || jx >= nx) {
            bad = true;
            return;
          }
        }
      }
      const int jy = m.y_periodic ? (iy + col / nx) % ny : col / nx;  // (the reference row's lattice row: iy, or 0)
      const int j = jx + nx * jy;
      if (stamp[j] != i) {
        stamp[j] = i;
        acc[j] = 0.0;
        touched.push_back(j);
      }
      acc[j] += sign * v;
    }
    for (int k = 0; k < n; ++k) {
      const int j = c[k];
      dev = std::max(dev, std::fabs(a[k] - (stamp[j] == i ? acc[j] : 0.0)));
      seen[j] = i;
    }
    for (int j : touched)
      if (seen[j] != i) dev = std::max(dev, std::fabs(acc[j]));
  };
  each_row(A, m, amax, [&](int i, const int* c, const double* a, int n) {
    const int cl = m.class_of(i / nx);
    if (m.is_reference(i, ix0)) {
      for (int k = 0; k < n; ++k) ref[cl].emplace_back(c[k], a[k]);
      have[cl] = 1;
      for (const Pending& p : pending) match(p.i, p.col.data(), p.val.data(), static_cast<int>(p.col.size()));
      pending.clear();
    }
    if (have[cl]) match(i, c, a, n);
    else pending.push_back({i, std::vector<int>(c, c + n), std::vector<double>(a, a + n)});
  });
  // extract_model's checks and model, then rows_match's verdict
  if (bad || !pending.empty()) return false;
  return finish_model(m, ix0, amax, ref, nullptr) && dev <= m.tol;
}

// The model of A on an n_x x n_y lattice with the given periodic axes, its x images' parities at the
// two walls given by the boundary rule (+1 even, -1 odd; unused along a periodic x); false (and why)
// when A does not have that structure.
bool analyse(const MatrixRows& A, long rows, long cols, int nx, int ny, bool px, bool py, XParities xp, Model& m,
             std::string& why) {
  if (rows != static_cast<long>(nx) * ny || cols != static_cast<long>(nx) * ny) return refuse(why, "the matrix is not n_x n_y square");
  m.nx = nx;
  m.ny = ny;
  m.x_periodic = px;
  m.y_periodic = py;
  const bool given = (xp.left == 1 || xp.left == -1) && (xp.right == 1 || xp.right == -1);
  if (px || given) {  // A's rows made once; should A fail a check, the two passes below say which
    Model one = m;
    if (analyse_in_one_pass(A, one, px ? 1 : xp.left, px ? 1 : xp.right)) {
      m = std::move(one);
      m.x = px ? XKind::Periodic
               : xp.left == xp.right ? (xp.left > 0 ? XKind::Even : XKind::Odd) : (xp.left > 0 ? XKind::EvenOdd : XKind::OddEven);
      return model_even(m, why);
    }
  }
  if (!extract_model(A, m, why)) return false;
  if (px) {
    m.x = XKind::Periodic;
    if (!rows_match(A, m, 1, 1, why)) return false;
  } else {
    if (!given) return refuse(why, "the boundary rule gives the x walls no image parity (no transform for them)");
    if (!rows_match(A, m, xp.left, xp.right, why)) return false;
    m.x = xp.left == xp.right ? (xp.left > 0 ? XKind::Even : XKind::Odd) : (xp.left > 0 ? XKind::EvenOdd : XKind::OddEven);
  }
  return model_even(m, why);
}

// The wavenumbers along x: count, and the table of cos(theta_k d) = cosine[(q_k |d|) mod M] for the
// transform's slot k: theta_k = 2 pi q_k / M with M = n_x along a periodic x (q_k = k, k <= n_x / 2)
// and M = 2 n_x between walls (DCT-II: q_k = k; DST-II: q_k = k + 1 in FFTW's order, n_x - k in the
// reversed order of RowDct below); between walls of different parities the quarter-wave forms
// (DCT-IV, DST-IV: eigenvectors cos or sin of theta_k (j + 1/2), theta_k = pi (k + 1/2) / n_x, the
// extension even about one wall and odd about the other, period 4 n_x): M = 4 n_x, q_k = 2 k + 1.
struct XWaves {
  int nk, M;
  bool dst, quarter, reversed;
  std::vector<double> cosine;
  XWaves(const Model& m, bool dst_reversed)
      : nk(m.x == XKind::Periodic ? m.nx / 2 + 1 : m.nx),
        M(m.x == XKind::Periodic ? m.nx : quarter_wave(m.x) ? 4 * m.nx : 2 * m.nx), dst(m.x == XKind::Odd),
        quarter(quarter_wave(m.x)), reversed(dst_reversed), cosine(M) {
    for (int j = 0; j < M; ++j) cosine[j] = std::cos(2.0 * M_PI * j / M);
  }
  int q(int k) const { return quarter ? 2 * k + 1 : !dst ? k : reversed ? M / 2 - k : k + 1; }
  double cos_k(int k, int d) const { return cosine[(static_cast<long>(q(k)) * d) % M]; }
};

// DCT-II and DST-II of rows of n by a real FFT of the same length (J. Makhoul, "A fast cosine
// transform in one and two dimensions", IEEE Trans. Acoust. Speech Signal Process. 28:27, 1980):
// v = (x_0, x_2, x_4, ..., x_5, x_3, x_1) (the even samples, then the odd ones reversed), V = FFT(v),
// Y_k = 2 Re(e^{-i pi k / 2n} V_k) and Y_{n-k} = -2 Im(e^{-i pi k / 2n} V_k), which is FFTW's REDFT10,
// Y_k = 2 sum_j x_j cos(pi (j + 1/2) k / n). The DST-II is the DCT-II of (-1)^j x_j read backwards
// (RODFT10_k = REDFT10((-1)^j x)_{n-1-k}): slot k then holds wavenumber n - k. The inverse runs the
// steps backwards (c2r): REDFT01 (DCT-III), 2 n x from Y. FFTW's own REDFT10/RODFT10 and their
// inverses under FFTW_ESTIMATE take 2.2-2.3 times the r2c and c2r FFTs of the same rows (64 rows of
// 64: bench/domains, part T), and the reordering and the twiddles here replace the copy in and
// the scaled copy out that a solve makes anyway.
class RowDct {
 public:
  RowDct(int n, bool odd) : n_(n), nk_(n / 2 + 1), sigma_(odd ? -1.0 : 1.0), c_(nk_), s_(nk_) {
    for (int k = 0; k < nk_; ++k) {
      c_[k] = std::cos(M_PI * k / (2.0 * n));
      s_[k] = std::sin(M_PI * k / (2.0 * n));
    }
  }
  int nk() const { return nk_; }  // complex values per row of the FFT

  // Each on rows r0 <= r < r1 (of the whole arrays x, v, V, y).
  void permute(const double* x, double* v, int r0, int r1) const {  // v = the reordered rows (DST: times (-1)^j)
    x += static_cast<std::size_t>(r0) * n_;
    v += static_cast<std::size_t>(r0) * n_;
    for (int r = r0; r < r1; ++r, x += n_, v += n_) {
      for (int j = 0; 2 * j < n_; ++j) v[j] = x[2 * j];
      for (int j = 0; 2 * j + 1 < n_; ++j) v[n_ - 1 - j] = sigma_ * x[2 * j + 1];
    }
  }
  void unpermute(const double* v, double* x, double scale, int r0, int r1) const {  // x = scale times the inverse reordering
    x += static_cast<std::size_t>(r0) * n_;
    v += static_cast<std::size_t>(r0) * n_;
    for (int r = r0; r < r1; ++r, x += n_, v += n_) {
      for (int j = 0; 2 * j < n_; ++j) x[2 * j] = scale * v[j];
      for (int j = 0; 2 * j + 1 < n_; ++j) x[2 * j + 1] = (sigma_ * scale) * v[n_ - 1 - j];
    }
  }
  void to_real(const double* V, double* y, int r0, int r1) const {  // V = FFT(v) (re, im), y = the DCT-II
    V += static_cast<std::size_t>(r0) * 2 * nk_;
    y += static_cast<std::size_t>(r0) * n_;
    for (int r = r0; r < r1; ++r, V += 2 * nk_, y += n_) {
      y[0] = 2.0 * V[0];
      for (int k = 1; k < nk_; ++k) {
        const double re = V[2 * k], im = V[2 * k + 1];
        y[k] = 2.0 * (c_[k] * re + s_[k] * im);
        if (n_ - k != k) y[n_ - k] = 2.0 * (s_[k] * re - c_[k] * im);
      }
    }
  }
  void from_real(const double* y, double* V, int r0, int r1) const {  // V = e^{i pi k / 2n} (Y_k - i Y_{n-k}), for the c2r
    V += static_cast<std::size_t>(r0) * 2 * nk_;
    y += static_cast<std::size_t>(r0) * n_;
    for (int r = r0; r < r1; ++r, V += 2 * nk_, y += n_) {
      V[0] = y[0];
      V[1] = 0.0;
      for (int k = 1; k < nk_; ++k) {
        const double a = y[k], b = y[n_ - k];
        V[2 * k] = c_[k] * a + s_[k] * b;
        V[2 * k + 1] = s_[k] * a - c_[k] * b;
      }
    }
  }

 private:
  int n_, nk_;
  double sigma_;
  std::vector<double> c_, s_;
};

const char* x_transform_name(XKind x) {
  switch (x) {
    case XKind::Periodic: return "FFT in x (FFTW r2c; periodic)";
    case XKind::Even: return "DCT-II in x (walls, even images)";
    case XKind::Odd: return "DST-II in x (walls, odd images)";
    case XKind::EvenOdd: return "DCT-IV in x (walls, even images left, odd right)";
    default: return "DST-IV in x (walls, odd images left, even right)";
  }
}
// FFTW's kinds: DCT-II/DST-II forward, DCT-III/DST-III inverse; DCT-IV/DST-IV (REDFT11/RODFT11) are
// their own inverses. Each pair scales by 2 n_x.
fftw_r2r_kind forward_kind(XKind x) {
  switch (x) {
    case XKind::Even: return FFTW_REDFT10;
    case XKind::Odd: return FFTW_RODFT10;
    case XKind::EvenOdd: return FFTW_REDFT11;
    default: return FFTW_RODFT11;
  }
}
fftw_r2r_kind inverse_kind(XKind x) {
  switch (x) {
    case XKind::Even: return FFTW_REDFT01;
    case XKind::Odd: return FFTW_RODFT01;
    case XKind::EvenOdd: return FFTW_REDFT11;
    default: return FFTW_RODFT11;
  }
}
const char* fftw_kind_name(XKind x) {
  switch (x) {
    case XKind::Even: return "REDFT10";
    case XKind::Odd: return "RODFT10";
    case XKind::EvenOdd: return "REDFT11";
    default: return "RODFT11";
  }
}

// ================================================================================================
// The solvers
// ================================================================================================

struct Work {  // one column's arrays: the right-hand side, its transform, the solution
  double* in = nullptr;
  double* out = nullptr;
  double* hat = nullptr;  // complex (re, im) pairs for the r2c transforms
  double* tmp = nullptr;  // RowDct's FFT of the reordered rows (re, im)
};

// What both solvers share: the workspaces, the FFTW plans (in -> hat, hat -> out), the columns
// shared among threads.
class LatticeSolver : public LinearSolver {
 public:
  bool exact() const override { return true; }
  ~LatticeSolver() override { release(); }

  // The systems from A (whose model is m); false (and why) when one is not (semi-)definite.
  virtual bool factor(long nnz, const Model& m, std::string& why) = 0;  // (nnz: A's, for info())

  // Columns are independent: with OpenMP and a large lattice two threads take one each (u and v of
  // the Crank-Nicolson system), each in its own workspace (FFTW's new-array execute is thread-safe);
  // a single column shares its row blocks and wavenumbers among the threads (solve_shared). Every
  // row and wavenumber is computed by the same arithmetic either way: the bits do not depend on the
  // thread count.
  void solve(const double* B, double* X, int k) override {
    const int N = info_.n;
    const int nt = N >= kParallelRows ? thread_count() : 1;
    if (k >= 2 && nt >= 2) {
#pragma omp parallel for num_threads(2) schedule(static, 1)
      for (int col = 0; col < k; ++col) {
#ifdef _OPENMP
        Work& w = ws_[omp_get_thread_num() % 2];
#else
        Work& w = ws_[0];
#endif
        solve_column(B + static_cast<std::size_t>(col) * N, X + static_cast<std::size_t>(col) * N, w);
      }
      return;
    }
    for (int col = 0; col < k; ++col)
      solve_shared(B + static_cast<std::size_t>(col) * N, X + static_cast<std::size_t>(col) * N, ws_[0], nt);
  }

  bool refactorize(const SpMat& A) override {
    std::string why;
    Model m;
    const XParities xp{x_ == XKind::Odd || x_ == XKind::OddEven ? -1 : 1, x_ == XKind::Odd || x_ == XKind::EvenOdd ? -1 : 1};
    bool ok = analyse(whole(A), A.rows(), A.cols(), nx_, ny_, x_ == XKind::Periodic, y_periodic_, xp, m, why);  // as planned
    if (!ok || !factor(m.nnz, m, why)) throw std::runtime_error("linear solver: system '" + info_.system + "': " + why);
    return true;
  }

  void set_seconds(double analyse, double factor) {
    info_.analyse_seconds = analyse;
    info_.factor_seconds = factor;
  }

 protected:
  LatticeSolver(const std::string& system, const Model& m, bool singular)
      : nx_(m.nx), ny_(m.ny), y_periodic_(m.y_periodic), x_(m.x), singular_(singular) {
    info_.system = system;
    info_.n = nx_ * ny_;
  }
  // The workspaces (hat: `hat_doubles`, tmp: `tmp_doubles`), then the plans made on the first; throws
  // when FFTW cannot plan.
  template <class Plan>
  void make_plans(std::size_t hat_doubles, std::size_t tmp_doubles, Plan plan) {
    for (Work& w : ws_) {  // a workspace per thread (two columns at once, see solve)
      w.in = fftw_alloc_real(info_.n);
      w.out = fftw_alloc_real(info_.n);
      w.hat = fftw_alloc_real(hat_doubles);
      if (tmp_doubles) w.tmp = fftw_alloc_real(tmp_doubles);
    }
    plan(ws_[0]);  // FFTW_ESTIMATE: the same plan, hence the same bits, in every run
    if (!fwd_ || !inv_ || (rest_rows_ && (!fwd_rest_ || !inv_rest_))) {
      release();
      throw std::runtime_error("linear solver: system '" + info_.system + "': FFTW could not plan the transforms");
    }
  }
  // The forward transform of b into w.hat, from b itself when FFTW may read it there (the
  // plans' alignment; the forward transforms preserve their input), else from a copy in w.in.
  void forward(const double* b, Work& w) const {
    double* in = w.in;
    if (fftw_alignment_of(const_cast<double*>(b)) == fftw_alignment_of(w.in)) in = const_cast<double*>(b);
    else std::copy(b, b + info_.n, w.in);
    if (complex_) fftw_execute_dft_r2c(fwd_, in, reinterpret_cast<fftw_complex*>(w.hat));
    else fftw_execute_r2r(fwd_, in, w.hat);
  }
  // The inverse transform of w.hat (destroyed), into x itself where FFTW may write it, else into
  // w.out; returns where the result is.
  const double* inverse(Work& w, double* x) const {
    double* out = fftw_alignment_of(x) == fftw_alignment_of(w.out) ? x : w.out;
    if (complex_) fftw_execute_dft_c2r(inv_, reinterpret_cast<fftw_complex*>(w.hat), out);
    else fftw_execute_r2r(inv_, w.hat, out);
    return out;
  }
  virtual void solve_column(const double* b, double* x, Work& w) const = 0;
  // One column on nt threads (the same bits as solve_column); by default on one.
  virtual void solve_shared(const double* b, double* x, Work& w, int /*nt*/) const { solve_column(b, x, w); }

  int nx_, ny_;
  bool y_periodic_;
  XKind x_;
  bool singular_;
  bool complex_ = false;  // the transforms are r2c / c2r (else r2r)
  int rest_rows_ = 0;     // the rows of BandedSolver's last row block when shorter than the others
  fftw_plan fwd_ = nullptr, inv_ = nullptr;
  fftw_plan fwd_rest_ = nullptr, inv_rest_ = nullptr;  // BandedSolver's last, shorter row block (when any)

 private:
  void release() {
    for (fftw_plan* p : {&fwd_, &inv_, &fwd_rest_, &inv_rest_})
      if (*p) fftw_destroy_plan(*p);
    for (Work& w : ws_) {
      if (w.in) fftw_free(w.in);
      if (w.out) fftw_free(w.out);
      if (w.hat) fftw_free(w.hat);
      if (w.tmp) fftw_free(w.tmp);
      w = Work{};
    }
    fwd_ = inv_ = fwd_rest_ = inv_rest_ = nullptr;
  }
  Work ws_[2];
};

// y walled: the transform along x, one banded system in y per wavenumber (banded Cholesky).
class BandedSolver final : public LatticeSolver {
 public:
  BandedSolver(const std::string& system, const Model& m, bool singular)
      : LatticeSolver(system, m, singular), waves_(m, true), nk_(waves_.nk), dct_(m.nx, m.x == XKind::Odd) {
    complex_ = m.x == XKind::Periodic;
    quarter_ = quarter_wave(m.x);
    const int n[1] = {nx_}, nc = dct_.nk();
    // Rows of n_x along x (idist n_x); the transform of row i_y, wavenumber k goes to hat[i_y nk + k],
    // so that the banded solves run over all wavenumbers at once (contiguous, vectorised). Between
    // walls the r2c FFT of the reordered rows goes to tmp (RowDct). The rows are transformed in
    // blocks of rb_ (one block below kParallelRows; else about an eighth of the rows, a multiple of 4
    // so that every block starts at the plans' alignment): threads take whole blocks, and the plans
    // are the same whatever their number.
    rb_ = row_block(nx_, ny_);
    blocks_ = (ny_ + rb_ - 1) / rb_;
    rest_rows_ = ny_ % rb_;
    make_plans(static_cast<std::size_t>(complex_ ? 2 : 1) * nk_ * ny_,
               complex_ || quarter_ ? 0 : static_cast<std::size_t>(2) * nc * ny_, [&](Work& w) {
                 auto* c = reinterpret_cast<fftw_complex*>(complex_ ? w.hat : w.tmp);
                 const int nkc = complex_ ? nk_ : nc;
                 auto plan = [&](int rows, fftw_plan& fwd, fftw_plan& inv) {
                   if (quarter_) {  // FFTW's own DCT-IV / DST-IV of the rows, straight into hat
                     const fftw_r2r_kind kind[1] = {forward_kind(x_)};
                     fwd = fftw_plan_many_r2r(1, n, rows, w.in, nullptr, 1, nx_, w.hat, nullptr, 1, nk_, kind, FFTW_ESTIMATE);
                     inv = fftw_plan_many_r2r(1, n, rows, w.hat, nullptr, 1, nk_, w.out, nullptr, 1, nx_, kind,
                                              FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
                     return;
                   }
                   fwd = fftw_plan_many_dft_r2c(1, n, rows, w.in, nullptr, 1, nx_, c, nullptr, 1, nkc, FFTW_ESTIMATE);
                   inv = fftw_plan_many_dft_c2r(1, n, rows, c, nullptr, 1, nkc, w.out, nullptr, 1, nx_,
                                                FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
                 };
                 plan(rb_, fwd_, inv_);
                 if (rest_rows_) plan(rest_rows_, fwd_rest_, inv_rest_);
               });
  }

  bool factor(long nnz, const Model& m, std::string& why) override {
    w_ = m.wy;
    ldab_ = w_ + 1;
    std::vector<double> band;  // B_k, then its factor, in LAPACK's lower band storage
    double bmax = 0;
    if (!assemble_bands(m, band, bmax, why)) return false;
    find_singular_blocks(band, bmax);
    const auto first = std::find(drop_.begin(), drop_.end(), 1);
    if (singular_ && first == drop_.end()) return refuse(why, "the matrix was said to be singular but no wavenumber block is");
    if (!singular_ && first != drop_.end())
      return refuse(why, "the matrix is singular, not positive definite (the block of wavenumber " +
                             std::to_string(first - drop_.begin()) + " annihilates the constant or alternating vector in y)");
    if (!factor_bands(band, why)) return false;
    arrange_factors(band);
    info_.nnz_A = info_.nnz_used = nnz;
    info_.nnz_factor = static_cast<long>(nk_) * ldab_ * ny_;
    std::ostringstream s;
    s << x_transform_name(x_) << " + banded Cholesky in y (LAPACK dpbtrf; walls): " << nk_ << " systems of " << ny_
      << ", half-bandwidth " << w_;
    const long nsing = std::count(drop_.begin(), drop_.end(), 1);
    if (nsing) s << ", " << nsing << " singular (null space)";
    info_.method = s.str();
    return true;
  }

 private:
  // The bands of B_k = sum_{d_x} C(i_y, d_y, d_x) cos(theta_k d_x) in LAPACK's lower storage,
  // ab[(i - j) + ldab j] = B_k(i, j), j <= i <= j + w, wavenumber after wavenumber; false when not
  // symmetric (to 1e-10 of max |B|).
  bool assemble_bands(const Model& m, std::vector<double>& band, double& bmax, std::string& why) const {
    const int w = w_, nd = 2 * w + 1, ny = ny_;
    band.assign(static_cast<std::size_t>(nk_) * ldab_ * ny, 0.0);
    double asym = 0;
    std::vector<double> full(static_cast<std::size_t>(ny) * nd);  // B_k(i_y, i_y + d), all d, for the symmetry check
    for (int kk = 0; kk < nk_; ++kk) {
      std::fill(full.begin(), full.end(), 0.0);
      for (int iy = 0; iy < ny; ++iy)
        for (const Entry& e : m.cls[iy]) full[static_cast<std::size_t>(iy) * nd + e.sy] += e.v * waves_.cos_k(kk, m.cos_dx(e.sx));
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
    if (asym > 1e-10 * bmax) return refuse(why, "the matrix is not symmetric");
    return true;
  }

  // A wavenumber whose B_k annihilates the constants or the alternating vector in y
  // (to 1e-10 of max |B|) is a null direction of A (fluid/algebra/gauge.hpp): on a channel k = 0 for -lap phi,
  // k = 0 and k = n_x/2 for the exact projection's G^T G (1 and (-1)^{i_x} in x), the same with
  // (-1)^{i_y} for a stream function's (odd images); on a closed box the DCT's k = 0 for -lap phi,
  // the DST's k = n_x ((-1)^{i_x}) with (-1)^{i_y} for G^T G with odd images.
  void find_singular_blocks(const std::vector<double>& band, double bmax) {
    const int ny = ny_, w = w_;
    drop_.assign(nk_, 0);
    std::vector<double> r(ny);  // B_k z, from the lower band and its mirror
    for (int kk = 0; kk < nk_; ++kk) {
      const double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny;
      for (int alt = 0; alt < 2 && !drop_[kk]; ++alt) {
        std::fill(r.begin(), r.end(), 0.0);
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
  }

  // Banded Cholesky of every B_k; a singular one (see above) without its row and column i_y = 0
  // (x(k, 0) = 0), the rest definite.
  bool factor_bands(std::vector<double>& band, std::string& why) {
    for (int kk = 0; kk < nk_; ++kk) {
      const bool drop = drop_[kk];
      double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny_ + (drop ? ldab_ : 0);
      const int n = drop ? ny_ - 1 : ny_;
      int info = 0;
      dpbtrf_("L", &n, &w_, ab, &ldab_, &info, 1);
      if (info != 0) {
        std::ostringstream m;
        m << "the banded system of wavenumber " << kk << " is not positive definite (LAPACK dpbtrf info " << info << ")";
        return refuse(why, m.str());
      }
    }
    return true;
  }

  // The factors rearranged wavenumber-fastest, once per wavenumber (substitute_bands reads a
  // wavenumber's factor for both the real and the imaginary part of h after the r2c FFT):
  // lrow[(i ldab + d) nk + k] = L_k(i, i - d) (forward substitution), lcol[...] = L_k(i + d, i)
  // (backward), rdiag[i nk + k] = 1 / L_k(i, i). Singular blocks: row and column 0 (dropped, x = 0
  // there) are zeros, so no wavenumber is special.
  void arrange_factors(const std::vector<double>& band) {
    const int ny = ny_, w = w_;
    const std::size_t nk = nk_;
    lrow_.assign(static_cast<std::size_t>(ny) * ldab_ * nk, 0.0);
    lcol_.assign(lrow_.size(), 0.0);
    rdiag_.assign(static_cast<std::size_t>(ny) * nk, 0.0);
    for (int kk = 0; kk < nk_; ++kk) {
      const double* ab = band.data() + static_cast<std::size_t>(kk) * ldab_ * ny;
      const int i0 = drop_[kk] ? 1 : 0;
      for (int i = i0; i < ny; ++i) {
        rdiag_[static_cast<std::size_t>(i) * nk + kk] = 1.0 / ab[static_cast<std::size_t>(ldab_) * i];
        for (int d = 1; d <= w; ++d) {
          const std::size_t at = (static_cast<std::size_t>(i) * ldab_ + d) * nk + kk;
          if (i - d >= i0) lrow_[at] = ab[d + static_cast<std::size_t>(ldab_) * (i - d)];
          if (i + d < ny) lcol_[at] = ab[d + static_cast<std::size_t>(ldab_) * i];
        }
      }
    }
  }

  static int row_block(int nx, int ny) {
    if (static_cast<long>(nx) * ny < kParallelRows) return ny;
    return std::min(ny, ((ny + 7) / 8 + 3) / 4 * 4);
  }

  void solve_column(const double* b, double* x, Work& ws) const override { solve_shared(b, x, ws, 1); }

  // The forward transforms by row blocks, the banded substitutions by ranges of wavenumbers (one per
  // thread, each an even count: substitute_bands), the inverse transforms by row blocks: one parallel
  // region, a barrier between the phases.
  void solve_shared(const double* b, double* x, Work& ws, int nt) const override {
    const bool b_direct = complex_ && fftw_alignment_of(const_cast<double*>(b)) == fftw_alignment_of(ws.in);
    const bool x_direct = complex_ && fftw_alignment_of(x) == fftw_alignment_of(ws.out);
    (void)nt;
#pragma omp parallel num_threads(nt) if (nt > 1)
    {
#pragma omp for schedule(static)
      for (int blk = 0; blk < blocks_; ++blk) forward_rows(b, ws, blk, b_direct);
#ifdef _OPENMP
      const int t = omp_get_thread_num(), T = omp_get_num_threads();
#else
      const int t = 0, T = 1;
#endif
      const int chunk = ((nk_ + T - 1) / T + 1) / 2 * 2;
      const int k0 = std::min(nk_, t * chunk), k1 = std::min(nk_, k0 + chunk);
      // B_k x = b for wavenumbers k0 .. k1 - 1 (B_k is real: real and imaginary parts alike): L y = b,
      // then L' x = y, in place. By hand rather than LAPACK dpbtrs, whose Level-2 calls on bands of
      // 2-5 cost 4x the rest of the solve (perf: 70 of 85 us per step at 64 x 64).
      if (k1 > k0) substitute_bands(ws.hat, {ny_, w_, ldab_, nk_, complex_, lrow_.data(), lcol_.data(), rdiag_.data()}, k0, k1);
#pragma omp barrier
#pragma omp for schedule(static)
      for (int blk = 0; blk < blocks_; ++blk) inverse_rows(ws, x, blk, x_direct);
    }
  }

  // Row block blk of b into ws.hat: the r2c FFT (from b itself when `direct`, else from a copy in
  // ws.in), or between walls the DCT-II or DST-II by RowDct.
  void forward_rows(const double* b, Work& ws, int blk, bool direct) const {
    const int r0 = blk * rb_, r1 = std::min(ny_, r0 + rb_);
    const fftw_plan fwd = r1 - r0 == rb_ ? fwd_ : fwd_rest_;
    const std::size_t at = static_cast<std::size_t>(r0) * nx_, end = static_cast<std::size_t>(r1) * nx_;
    if (complex_) {
      double* in = const_cast<double*>(b) + at;  // (the forward transforms preserve their input)
      if (!direct) {
        std::copy(b + at, b + end, ws.in + at);
        in = ws.in + at;
      }
      fftw_execute_dft_r2c(fwd, in, reinterpret_cast<fftw_complex*>(ws.hat) + static_cast<std::size_t>(r0) * nk_);
    } else if (quarter_) {
      std::copy(b + at, b + end, ws.in + at);
      fftw_execute_r2r(fwd, ws.in + at, ws.hat + static_cast<std::size_t>(r0) * nk_);
    } else {
      dct_.permute(b, ws.in, r0, r1);
      fftw_execute_dft_r2c(fwd, ws.in + at, reinterpret_cast<fftw_complex*>(ws.tmp) + static_cast<std::size_t>(r0) * dct_.nk());
      dct_.to_real(ws.tmp, ws.hat, r0, r1);
    }
  }

  // Row block blk of x from ws.hat (destroyed): the c2r FFT (into x itself when `direct`, else into
  // ws.out) scaled by 1 / n_x, or between walls the inverse by RowDct, its scale 1 / (2 n_x).
  void inverse_rows(Work& ws, double* x, int blk, bool direct) const {
    const int r0 = blk * rb_, r1 = std::min(ny_, r0 + rb_);
    const fftw_plan inv = r1 - r0 == rb_ ? inv_ : inv_rest_;
    const std::size_t at = static_cast<std::size_t>(r0) * nx_, end = static_cast<std::size_t>(r1) * nx_;
    if (complex_) {
      double* out = direct ? x : ws.out;  // unnormalised: n_x times the inverse transform
      fftw_execute_dft_c2r(inv, reinterpret_cast<fftw_complex*>(ws.hat) + static_cast<std::size_t>(r0) * nk_, out + at);
      const double s = 1.0 / nx_;
      for (std::size_t i = at; i < end; ++i) x[i] = s * out[i];
    } else if (quarter_) {
      fftw_execute_r2r(inv, ws.hat + static_cast<std::size_t>(r0) * nk_, ws.out + at);
      const double s = 0.5 / nx_;  // the pair scales by 2 n_x
      for (std::size_t i = at; i < end; ++i) x[i] = s * ws.out[i];
    } else {
      auto* tmp = reinterpret_cast<fftw_complex*>(ws.tmp) + static_cast<std::size_t>(r0) * dct_.nk();
      dct_.from_real(ws.hat, ws.tmp, r0, r1);
      fftw_execute_dft_c2r(inv, tmp, ws.out + at);
      dct_.unpermute(ws.out, x, 0.5 / nx_, r0, r1);
    }
  }

  XWaves waves_;
  int nk_, w_ = 0, ldab_ = 1;
  int rb_ = 1, blocks_ = 1;  // rows per block of the row transforms, and blocks
  bool quarter_ = false;     // DCT-IV / DST-IV by FFTW (walls of different parities)
  RowDct dct_;
  std::vector<char> drop_;                   // per wavenumber: B_k singular, row 0 dropped
  std::vector<double> lrow_, lcol_, rdiag_;  // the factors, wavenumber fastest (see arrange_factors)
};

// y periodic: the transform along y too (FFT, with the x transform a 2-D one), A diagonal.
class DiagonalSolver final : public LatticeSolver {
 public:
  DiagonalSolver(const std::string& system, const Model& m, bool singular)
      : LatticeSolver(system, m, singular), waves_(m, false) {
    complex_ = m.x == XKind::Periodic;
    // Row-major n_y x n_x. Periodic x: the 2-D r2c FFT, hat[k_y][k_x] for k_x <= n_x / 2. Walls in x:
    // the separable r2r transform, halfcomplex in y (FFTW R2HC: slot m holds the real part of
    // wavenumber m for m <= n_y/2, the imaginary part of wavenumber n_y - m above; both have the
    // eigenvalue of wavenumber m, a cosine sum) and DCT-II or DST-II in x.
    make_plans(static_cast<std::size_t>(complex_ ? 2 : 1) * waves_.nk * ny_, 0, [&](Work& w) {
      if (complex_) {
        auto* hat = reinterpret_cast<fftw_complex*>(w.hat);
        fwd_ = fftw_plan_dft_r2c_2d(ny_, nx_, w.in, hat, FFTW_ESTIMATE);
        inv_ = fftw_plan_dft_c2r_2d(ny_, nx_, hat, w.out, FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
      } else {
        fwd_ = fftw_plan_r2r_2d(ny_, nx_, w.in, w.hat, FFTW_R2HC, forward_kind(x_), FFTW_ESTIMATE);
        inv_ = fftw_plan_r2r_2d(ny_, nx_, w.hat, w.out, FFTW_HC2R, inverse_kind(x_), FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
      }
    });
  }

  // The eigenvalues lambda(k_y, k_x) = sum_{d_y} cos(2 pi k_y d_y / n_y) g(d_y, k_x),
  // g(d_y, k_x) = sum_{d_x} s(d_x, d_y) cos(theta_{k_x} d_x); stored as 1 / (lambda times the
  // transforms' scale), 0 for a zero eigenvalue (|lambda| <= 1e-10 max |lambda|: the null space).
  bool factor(long nnz, const Model& m, std::string& why) override {
    const int nk = waves_.nk, ny = ny_;
    std::vector<int> row_of(ny, -1), dys;  // the d_y slots present
    for (const Entry& e : m.cls[0])
      if (row_of[e.sy] < 0) {
        row_of[e.sy] = static_cast<int>(dys.size());
        dys.push_back(e.sy);
      }
    std::vector<double> g(dys.size() * nk, 0.0), cy(ny);
    for (const Entry& e : m.cls[0])
      for (int k = 0; k < nk; ++k) g[row_of[e.sy] * nk + k] += e.v * waves_.cos_k(k, m.cos_dx(e.sx));
    for (int j = 0; j < ny; ++j) cy[j] = std::cos(2.0 * M_PI * j / ny);
    std::vector<double> lambda(static_cast<std::size_t>(nk) * ny, 0.0);
    double lmax = 0;
    for (int ky = 0; ky < ny; ++ky)
      for (std::size_t p = 0; p < dys.size(); ++p) {
        const double c = cy[(static_cast<long>(ky) * m.cos_dy(dys[p])) % ny];
        for (int k = 0; k < nk; ++k) lambda[static_cast<std::size_t>(ky) * nk + k] += g[p * nk + k] * c;
      }
    for (double l : lambda) lmax = std::max(lmax, std::fabs(l));
    const double scale = complex_ ? static_cast<double>(nx_) * ny : 2.0 * nx_ * ny;  // forward then inverse
    inv_lambda_.assign(lambda.size(), 0.0);
    long nnull = 0;
    for (std::size_t q = 0; q < lambda.size(); ++q) {
      if (std::fabs(lambda[q]) <= 1e-10 * lmax) {
        ++nnull;
      } else if (lambda[q] < 0) {
        std::ostringstream s;
        s << "the matrix is not positive " << (singular_ ? "semi-" : "") << "definite (eigenvalue " << lambda[q]
          << " at k_x = " << q % nk << ", k_y = " << q / nk << ")";
        return refuse(why, s.str());
      } else {
        inv_lambda_[q] = 1.0 / (lambda[q] * scale);
      }
    }
    if (singular_ && nnull == 0) return refuse(why, "the matrix was said to be singular but no eigenvalue is zero");
    if (!singular_ && nnull > 0) return refuse(why, "the matrix is singular, not positive definite (" + std::to_string(nnull) + " zero eigenvalues)");
    info_.nnz_A = info_.nnz_used = nnz;
    info_.nnz_factor = static_cast<long>(lambda.size());
    std::ostringstream s;
    if (complex_) s << "2-D FFT (FFTW r2c; periodic in x and y)";
    else s << x_transform_name(x_) << " x FFT in y (periodic; FFTW " << fftw_kind_name(x_) << " x R2HC)";
    s << ", A diagonal: " << lambda.size() << " eigenvalues";
    if (nnull) s << ", " << nnull << " zero (null space)";
    info_.method = s.str();
    return true;
  }

 private:
  void solve_column(const double* b, double* x, Work& ws) const override {
    const int N = info_.n;
    forward(b, ws);
    const std::size_t n = inv_lambda_.size();
    const double* r = inv_lambda_.data();
    double* h = ws.hat;
    if (complex_) {
      for (std::size_t q = 0; q < n; ++q) {
        h[2 * q] *= r[q];
        h[2 * q + 1] *= r[q];
      }
    } else {
      for (std::size_t q = 0; q < n; ++q) h[q] *= r[q];
    }
    const double* out = inverse(ws, x);
    if (out != x) std::copy(out, out + N, x);
  }

  XWaves waves_;
  std::vector<double> inv_lambda_;  // 1 / (lambda scale) per transform slot, 0 on the null space
};

}  // namespace

namespace {
// A compressed A (a copy when it is not).
template <class F>
auto with_compressed(const SpMat& A, F f) {
  if (A.isCompressed()) return f(A);
  SpMat c = A;
  c.makeCompressed();
  return f(c);
}
}  // namespace

std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L, XParities xp,
                                              bool singular, std::string* why) {
  return with_compressed(A, [&](const SpMat& a) { return make_fft_solver(system, whole(a), a.rows(), L, xp, singular, why); });
}

std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L, Field field,
                                              bool singular, std::string* why) {
  SpMat compressed;
  const SpMat* a = &A;
  if (!A.isCompressed()) {
    compressed = A;
    compressed.makeCompressed();
    a = &compressed;
  }
  return make_fft_solver(system, whole(*a), a->rows(), L, field, singular, why);
}

XParities x_parities(const Domain& d, Field field) { return {d.parity(Left, field), d.parity(Right, field)}; }

std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const MatrixRows& A, long n, const Lattice& L,
                                              Field field, bool singular, std::string* why) {
  // The transform along x from the boundary rule: the field's image parities at the x walls; along y
  // the banded systems take any folds.
  return make_fft_solver(system, A, n, L, x_parities(L.domain, field), singular, why);
}

std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const MatrixRows& A, long n, const Lattice& L,
                                              XParities xp, bool singular, std::string* why) {
  const auto t0 = Clock::now();
  std::string w;
  Model m;
  if (analyse(A, n, n, L.nx, L.ny, L.domain.periodic_x, L.domain.periodic_y, xp, m, w)) {
    const double t_analyse = seconds_since(t0);
    const auto t1 = Clock::now();
    std::unique_ptr<LatticeSolver> s;
    if (m.y_periodic) s = std::make_unique<DiagonalSolver>(system, m, singular);
    else s = std::make_unique<BandedSolver>(system, m, singular);
    if (s->factor(m.nnz, m, w)) {
      s->set_seconds(t_analyse, seconds_since(t1));
      return s;
    }
  }
  if (why) *why = w;
  return nullptr;
}

}  // namespace sphib
