#include "kernels/curl_sums.hpp"
#include "kernels/cubic_spline_lanes.hpp"

namespace sphib {

namespace {

// Each sum in two lanes (the even and the odd points), added at the end.
struct LaneSums {
  Lanes2 s{}, sp{}, gx{}, gy{}, gpx{}, gpy{};
  Lanes2 hxx{}, hxy{}, hyy{}, phxx{}, phxy{}, phyy{};
};

template <bool kHessian>
[[gnu::always_inline]] inline void add_pairs(const MarkerPoints& nb, const CubicSpline& K, const double* psi, LaneSums& c) {
  for (int i = 0; i < nb.pairs; ++i) {
    const CubicSplineLanes<Lanes2> k(K, Lanes2{nb.r2[2 * i], nb.r2[2 * i + 1]});
    const Lanes2 w = k.W(), F = k.F();  // W(X - x_j), (1/r) dW/dr
    Lanes2 G{};
    if constexpr (kHessian) G = k.G();  // (1/r) dF/dr (here, while k's values are in registers)
    const Lanes2 p{psi[nb.j[2 * i]], psi[nb.j[2 * i + 1]]};
    const Lanes2 dx{nb.dx[2 * i], nb.dx[2 * i + 1]}, dy{nb.dy[2 * i], nb.dy[2 * i + 1]};
    c.s += w;
    c.sp += p * w;
    const Lanes2 wx = F * dx, wy = F * dy;  // grad_X W(X - x_j) = F (X - x_j)
    c.gx += wx;
    c.gy += wy;
    c.gpx += p * wx;
    c.gpy += p * wy;
    if constexpr (kHessian) {  // Hess W(X - x_j) = F I + G d d^T
      const Lanes2 Gx = G * dx, Gy = G * dy, Hxx = F + Gx * dx, Hxy = Gx * dy, Hyy = F + Gy * dy;
      c.hxx += Hxx;
      c.hxy += Hxy;
      c.hyy += Hyy;
      c.phxx += p * Hxx;
      c.phxy += p * Hxy;
      c.phyy += p * Hyy;
    }
  }
}

double sum(Lanes2 a) { return a[0] + a[1]; }

}  // namespace

// Compiled twice (SSE2 and AVX2, chosen at load time): the same two-lane arithmetic (no FMA, so the
// same bits), fewer register copies with AVX's three-operand instructions.
[[gnu::target_clones("avx2", "default")]] CurlSums curl_sums(const MarkerPoints& nb, const CubicSpline& W,
                                                             const double* psi, bool hessian) {
  LaneSums c;
  if (hessian) add_pairs<true>(nb, W, psi, c);
  else add_pairs<false>(nb, W, psi, c);
  return {sum(c.s),   sum(c.sp),  sum(c.gx),   sum(c.gy),   sum(c.gpx),  sum(c.gpy),
          sum(c.hxx), sum(c.hxy), sum(c.hyy), sum(c.phxx), sum(c.phxy), sum(c.phyy)};
}

CurlSums curl_sums_plain(const MarkerPoints& nb, const CubicSpline& W, const double* psi, bool hessian) {
  CurlSums c;
  for (int m = 0; m < 2 * nb.pairs; ++m) {
    const double r = std::sqrt(nb.r2[m]), p = psi[nb.j[m]], dx = nb.dx[m], dy = nb.dy[m];
    const double w = cubic_W(W, r), F = cubic_F(W, r);  // Eq. (19) and (1/r) dW/dr
    c.s += w;
    c.sp += p * w;
    c.gx += F * dx;  // grad W = F d
    c.gy += F * dy;
    c.gpx += p * F * dx;
    c.gpy += p * F * dy;
    if (!hessian) continue;
    const double G = cubic_G(W, r);  // Hess W = F I + G d d^T
    c.hxx += F + G * dx * dx;
    c.hxy += G * dx * dy;
    c.hyy += F + G * dy * dy;
    c.phxx += p * (F + G * dx * dx);
    c.phxy += p * G * dx * dy;
    c.phyy += p * (F + G * dy * dy);
  }
  return c;
}

}  // namespace sphib
