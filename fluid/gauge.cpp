#include "fluid/gauge.hpp"

namespace sphib {

Gauge::Gauge(const Lattice& L, NullSpace ns) : nx_(L.nx), ny_(L.ny) {
  if (ns == NullSpace::None) return;
  // The factors along one axis: 0 = constant, 1 = alternating.
  auto factors = [&](bool periodic, int n) -> std::vector<int> {
    if (ns == NullSpace::Constants) return {0};
    if (periodic) return n % 2 == 0 ? std::vector<int>{0, 1} : std::vector<int>{0};
    return {ns == NullSpace::GradientEvenImages ? 0 : 1};
  };
  const std::vector<int> fx = factors(L.domain.periodic_x, L.nx), fy = factors(L.domain.periodic_y, L.ny);
  for (size_t b = 0; b < fy.size(); ++b)
    for (size_t a = 0; a < fx.size(); ++a) {
      modes_.push_back({fx[a], fy[b]});
      pins_.push_back(static_cast<int>(a) + L.nx * static_cast<int>(b));
    }
}

void Gauge::project(Vec& f) const {
  const int N = nx_ * ny_;
  for (const Mode& m : modes_) {
    double s = 0;
    for (int iy = 0; iy < ny_; ++iy)
      for (int ix = 0; ix < nx_; ++ix) s += ((m.sx * ix + m.sy * iy) & 1 ? -f[ix + nx_ * iy] : f[ix + nx_ * iy]);
    s /= N;  // every null vector has |z|^2 = N
    for (int iy = 0; iy < ny_; ++iy)
      for (int ix = 0; ix < nx_; ++ix) f[ix + nx_ * iy] -= ((m.sx * ix + m.sy * iy) & 1 ? -s : s);
  }
}

SpMat Gauge::pinned(const SpMat& A) const {
  SpMat P = A;
  std::vector<char> pin(P.rows(), 0);
  for (int p : pins_) pin[p] = 1;
  for (int i = 0; i < P.outerSize(); ++i)
    for (SpMat::InnerIterator it(P, i); it; ++it)
      if (pin[i] || pin[it.col()]) it.valueRef() = (i == it.col()) ? 1.0 : 0.0;
  P.prune(0.0);
  return P;
}

void Gauge::pin_rhs(Vec& b) const {
  for (int p : pins_) b[p] = 0.0;
}

}  // namespace sphib
