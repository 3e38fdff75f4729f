#include "fluid/algebra/gauge.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "fluid/algebra/row_stencil.hpp"  // kParallelRows
#include "kernels/alternating.hpp"

namespace sphib {

Gauge::Gauge(const Lattice& L, NullSpace ns) : nx_(L.nx), ny_(L.ny) {
  if (ns == NullSpace::None) return;
  if (ns == NullSpace::Constants)  // the constant continues only through even images of phi
    for (Side s : {Left, Right, Bottom, Top})
      if (L.domain.parity(s, Field::Scalar) < 0) return;
  // The factors along one axis: 0 = constant, 1 = alternating. Across a wall the constant continues
  // through even images, the alternating mode through odd ones (the rule's parity of the field).
  const Field field = ns == NullSpace::GradientScalar ? Field::Scalar : Field::Stream;
  auto factors = [&](Side lo, Side hi, int n) -> std::vector<int> {
    if (ns == NullSpace::Constants) return {0};
    if (L.domain.is_periodic(lo)) return n % 2 == 0 ? std::vector<int>{0, 1} : std::vector<int>{0};
    const int p = L.domain.parity(lo, field), q = L.domain.parity(hi, field);
    if (p == 0 || q == 0)
      throw std::invalid_argument(std::string("gauge: the ") + side_name(lo) + " and " + side_name(hi) +
                                  " sides give no common image parity (walls on both needed)");
    if (p != q) return {};  // even on one side, odd on the other (an inflow facing an outflow): no mode continues
    return {p > 0 ? 0 : 1};
  };
  const std::vector<int> fx = factors(Left, Right, L.nx), fy = factors(Bottom, Top, L.ny);
  for (size_t b = 0; b < fy.size(); ++b)
    for (size_t a = 0; a < fx.size(); ++a) {
      modes_.push_back({fx[a], fy[b]});
      pins_.push_back(static_cast<int>(a) + L.nx * static_cast<int>(b));
    }
}

namespace {

// c[sy][sx] = <f, (-1)^{sx i_x + sy i_y}> / N from the even- and odd-column sums of each row, the
// rows' sums added in row order. On a large lattice the rows' sums are shared among the threads
// (blocks of four rows, kChunk rows at a time on the stack); each is summed alone, and the sums are
// added in row order by one thread: the bits do not depend on the thread count.
void mode_coefficients(const double* f, int nx, int ny, double c[2][2]) {
  c[0][0] = c[0][1] = c[1][0] = c[1][1] = 0.0;
  auto add_row = [&](int iy, double e, double o) {
    const double s = (iy & 1) ? -1.0 : 1.0;
    c[0][0] += e + o;
    c[0][1] += e - o;
    c[1][0] += s * (e + o);
    c[1][1] += s * (e - o);
  };
  constexpr int kChunk = 512;
  double e[kChunk], o[kChunk];
  const bool par = static_cast<long>(nx) * ny >= kParallelRows;
  (void)par;
  for (int y0 = 0; y0 < ny; y0 += kChunk) {
    const int m = std::min(kChunk, ny - y0), quads = (m + 3) / 4;
#pragma omp parallel for schedule(static) if (par)
    for (int q = 0; q < quads; ++q) row_sums(f, nx, y0 + 4 * q, std::min(4, m - 4 * q), e + 4 * q, o + 4 * q);
    for (int l = 0; l < m; ++l) add_row(y0 + l, e[l], o[l]);
  }
  const double N = static_cast<double>(nx) * ny;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) c[a][b] /= N;
}

// The values w * sum over `modes` of c[sy][sx] (-1)^{sx i_x + sy i_y} at even and odd i_x of row iy
template <class Modes>
void row_values(const Modes& modes, const double c[2][2], double w, int iy, double& even, double& odd) {
  even = 0;
  odd = 0;
  for (const auto& m : modes) {
    const double v = w * c[m.sy][m.sx] * ((m.sy && (iy & 1)) ? -1.0 : 1.0);
    even += v;
    odd += m.sx ? -v : v;
  }
}

// f += v[i_y mod 2][i_x mod 2] (v: the values added at even and odd i_x of even and odd rows)
// (rows shared among the threads on a large lattice: each value is computed alone)
void add_alternating(double* f, int nx, int ny, const double (*v)[2]) {
  const bool par = static_cast<long>(nx) * ny >= kParallelRows;
  (void)par;
#pragma omp parallel for schedule(static) if (par)
  for (int iy = 0; iy < ny; ++iy) add_alternating_row(f + static_cast<std::size_t>(nx) * iy, nx, v[iy & 1][0], v[iy & 1][1]);
}

// f += w * sum over `modes` of c[sy][sx] (-1)^{sx i_x + sy i_y} (row_values depends on i_y only by
// its parity)
template <class Modes>
void add_modes(double* f, int nx, int ny, const Modes& modes, const double c[2][2], double w) {
  double v[2][2];
  for (int p = 0; p < 2; ++p) row_values(modes, c, w, p, v[p][0], v[p][1]);
  add_alternating(f, nx, ny, v);
}

}  // namespace

void Gauge::project(Vec& f) const {
  if (modes_.empty()) return;
  if (modes_.size() == 1 && modes_[0].sx == 0 && modes_[0].sy == 0) {  // the constants: the mean, in order
    double s = 0;
    for (int i = 0; i < f.size(); ++i) s += f[i];
    s /= f.size();
    for (int i = 0; i < f.size(); ++i) f[i] -= s;
    return;
  }
  double c[2][2];
  mode_coefficients(f.data(), nx_, ny_, c);  // every null vector has |z|^2 = N
  add_modes(f.data(), nx_, ny_, modes_, c, -1.0);
}

VelocityModes::VelocityModes(const Lattice& L) {
  for (int comp = 0; comp < 2; ++comp) {
    Gauge& g = comp_[comp];
    g.nx_ = L.nx;
    g.ny_ = L.ny;
    // The velocity of a stream function psi: across a wall its normal component (the tangential
    // derivative of psi) has psi's parity, its tangential one (the normal derivative) the opposite;
    // a mode continues through even images as the constant, through odd ones alternating.
    // A mode continues only where both sides give it (not between an inflow and an outflow).
    auto factors = [&](Side lo, Side hi, int n, bool normal) -> std::vector<int> {
      if (L.domain.is_periodic(lo)) return n % 2 == 0 ? std::vector<int>{0, 1} : std::vector<int>{0};
      const int psi = L.domain.parity(lo, Field::Stream), p = normal ? psi : -psi;
      if (L.domain.parity(hi, Field::Stream) != psi) return {};
      return {p > 0 ? 0 : 1};
    };
    const std::vector<int> fx = factors(Left, Right, L.nx, comp == 0);
    const std::vector<int> fy = factors(Bottom, Top, L.ny, comp == 1);
    const bool channel = L.domain.periodic_x != L.domain.periodic_y;
    for (int sy : fy)
      for (int sx : fx) {
        if (sx == 0 && sy == 0 && channel) continue;  // the flux: the stream function's
        g.modes_.push_back({sx, sy});
      }
  }
}

void VelocityModes::add_components(const Mat2& from, Mat2& to) const {
  for (int comp = 0; comp < 2; ++comp) {
    const Gauge& g = comp_[comp];
    if (g.modes_.empty()) continue;
    double c[2][2];
    mode_coefficients(from.col(comp).data(), g.nx_, g.ny_, c);
    add_modes(to.col(comp).data(), g.nx_, g.ny_, g.modes_, c, 1.0);
  }
}

VelocityModes::Addends VelocityModes::addends(const Mat2& from) const {
  Addends a;
  for (int comp = 0; comp < 2; ++comp) {
    const Gauge& g = comp_[comp];
    if (g.modes_.empty()) continue;
    a.has[comp] = true;
    double c[2][2];
    mode_coefficients(from.col(comp).data(), g.nx_, g.ny_, c);
    for (int py = 0; py < 2; ++py) row_values(g.modes_, c, 1.0, py, a.value[comp][py][0], a.value[comp][py][1]);
  }
  return a;
}

SpMat Gauge::pinned(const SpMat& A, bool prune) const {
  SpMat P = A;
  std::vector<char> pin(P.rows(), 0);
  for (int p : pins_) pin[p] = 1;
  for (int i = 0; i < P.outerSize(); ++i)
    for (SpMat::InnerIterator it(P, i); it; ++it)
      if (pin[i] || pin[it.col()]) it.valueRef() = (i == it.col()) ? 1.0 : 0.0;
  if (prune) P.prune(0.0);
  return P;
}

void Gauge::pin_rhs(Vec& b) const {
  for (int p : pins_) b[p] = 0.0;
}

}  // namespace sphib
