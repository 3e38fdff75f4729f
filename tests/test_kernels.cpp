// The fast kernels (kernels/) against their plain forms (the equation as written, one term at a time)
// on small random inputs. Where the fast form computes the same terms in the same order (the gauge's
// row sums, the alternating addition, LPSPH's three products) they must agree bit for bit; where it
// takes the branch-free lane form of Eq. (19) (spreading, the curl sums) they agree to rounding, with
// the tolerances measured below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "kernels/alternating.hpp"
#include "kernels/banded.hpp"
#include "kernels/cubic_spline_lanes.hpp"
#include "kernels/curl_sums.hpp"
#include "kernels/fused_rows.hpp"
#include "kernels/lanes.hpp"
#include "kernels/sparse_rows.hpp"
#include "kernels/stencil_products.hpp"
#include "kernels/spread.hpp"

using namespace sphib;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Points near a marker as the markers' gathering gives them: n offsets within reach (some beyond the
// support 2h, where W = 0), padded to whole pairs with a point at twice the support.
struct RandomPoints {
  std::vector<int> j;
  std::vector<double> dx, dy, r2;
  MarkerPoints view() const { return {static_cast<int>(j.size()) / 2, j.data(), dx.data(), dy.data(), r2.data()}; }
};
RandomPoints random_points(std::mt19937& rng, int n, int N, double h) {
  std::uniform_real_distribution<double> off(-2.3 * h, 2.3 * h);
  std::uniform_int_distribution<int> idx(0, N - 1);
  RandomPoints p;
  for (int m = 0; m < n; ++m) {
    const double x = m == 0 ? 0.0 : off(rng), y = m == 0 ? 0.0 : off(rng);  // one point on the marker
    p.j.push_back(idx(rng));
    p.dx.push_back(x);
    p.dy.push_back(y);
    p.r2.push_back(x * x + y * y);
  }
  if (n % 2) {
    p.j.push_back(p.j[0]);
    p.dx.push_back(0.0);
    p.dy.push_back(0.0);
    p.r2.push_back(16.0 * h * h);
  }
  return p;
}

}  // namespace

// sqrt2 (kernels/lanes.hpp) against std::sqrt lane by lane: both the correctly rounded square root
// (IEEE 754), so bit for bit, over magnitudes 1e-300-1e300, exact squares and zero.
TEST(Kernels, TwoLaneSquareRootEqualsStdSqrtBitForBit) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> mant(1.0, 10.0), expo(-300.0, 300.0);
  int differ = 0, n = 0;
  for (int k = 0; k < 20000; ++k) {
    const double a = mant(rng) * std::pow(10.0, expo(rng)), b = k < 100 ? double(k) * k : mant(rng);
    const Lanes2 r = sqrt2(Lanes2{a, b});
    differ += !same_bits(r[0], std::sqrt(a)) + !same_bits(r[1], std::sqrt(b));
    n += 2;
  }
  EXPECT_EQ(differ, 0) << "of " << n;
}

// The lane form of G = (1/r) dF/dr against the plain one, relative to max(|G(r)|, G(h)) (G grows as
// 1/r towards r = 0): measured 1.4e-15 (h = 0.05625, 0.7, 3.7; 20001 radii over [0, 2.2h]);
// tolerance 1e-14. (W and F of the lane form are checked against the scalar forms in tests/test_fluid.cpp, Kernel.TwoLaneFormsMatchTheScalarOnes.)
TEST(Kernels, LaneHessianFactorMatchesThePlainOne) {
  for (double h : {0.05625, 0.7, 3.7}) {
    const CubicSpline K = CubicSpline::of(h);
    const double G1 = 1.5 * K.w0 / (h * h * h * h);
    double worst = 0;
    for (int k = 0; k <= 20000; k += 2) {
      const double r0 = k * 2.2 * h / 20000, r1 = (k + 1) * 2.2 * h / 20000;
      const Lanes2 g = CubicSplineLanes<Lanes2>(K, Lanes2{r0 * r0, r1 * r1}).G();
      for (int l = 0; l < 2; ++l) {
        const double G = cubic_G(K, l ? r1 : r0);
        worst = std::max(worst, std::abs(g[l] - G) / std::max(std::abs(G), G1));
      }
    }
    EXPECT_LT(worst, 1e-14) << h;
    std::printf("G lanes, h = %g: max |fast - plain| / max(|G|, G(h)) = %.2g\n", h, worst);
  }
}

// Eq. (53) over a lattice box: random boxes of 1-13 rows and 1-13 columns (some wrapping around a
// periodic row: not contiguous), offsets within 2.5 h*, random F beforehand. Measured max
// |fast - plain| / (|f| W(0)) 4.2e-16; tolerance 1e-14 (the lane form of W within a few units in the
// last place of W(0); every point receives one term).
TEST(Kernels, SpreadRowsMatchesThePlainSum) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double h = 0.05 + 0.1 * (u(rng) + 1.0), d = h / 1.3;
    const CubicSpline K = CubicSpline::of(h);
    const int ncol = 1 + trial % 13, nrow = 1 + (trial / 13) % 13, width = ncol + 3 + trial % 5;
    const int c0 = trial % 3 == 0 ? width - ncol / 2 - 1 : trial % width;  // every third wraps
    std::vector<int> col(ncol), base(nrow);
    std::vector<double> cdx(ncol), ry(nrow);
    const double sx = u(rng) * d, sy = u(rng) * d;
    for (int c = 0; c < ncol; ++c) {
      col[c] = (c0 + c) % width;
      cdx[c] = (c - ncol / 2) * d + sx;
    }
    for (int r = 0; r < nrow; ++r) {
      base[r] = r * width;
      ry[r] = (r - nrow / 2) * d + sy;
    }
    const LatticeRows box{ncol, nrow, col.data(), cdx.data(), base.data(), ry.data()};
    const double fx = u(rng), fy = u(rng);
    std::vector<double> Fx(nrow * width), Fy(nrow * width);
    for (double& v : Fx) v = u(rng);
    for (double& v : Fy) v = u(rng);
    std::vector<double> Gx = Fx, Gy = Fy;
    spread_rows(box, K, fx, fy, Fx.data(), Fy.data());
    spread_rows_plain(box, K, fx, fy, Gx.data(), Gy.data());
    const double scale = std::max(std::abs(fx), std::abs(fy)) * cubic_W(K, 0.0);
    for (size_t i = 0; i < Fx.size(); ++i)
      worst = std::max({worst, std::abs(Fx[i] - Gx[i]) / scale, std::abs(Fy[i] - Gy[i]) / scale});
  }
  EXPECT_LT(worst, 1e-14);
  std::printf("spread_rows: max |fast - plain| / (|f| W(0)) = %.2g\n", worst);
}

// Eq. (53) over gathered points (the markers away from the fixed lattice): 1-40 points, some
// repeated indices. Measured 7.6e-16 of |f| W(0); tolerance 1e-14, as above.
TEST(Kernels, SpreadPairsMatchesThePlainSum) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double h = 0.05 + 0.1 * (u(rng) + 1.0);
    const CubicSpline K = CubicSpline::of(h);
    const int N = 30;
    const RandomPoints p = random_points(rng, 1 + trial % 40, N, h);
    const double fx = u(rng), fy = u(rng);
    std::vector<double> Fx(N), Fy(N);
    for (double& v : Fx) v = u(rng);
    for (double& v : Fy) v = u(rng);
    std::vector<double> Gx = Fx, Gy = Fy;
    spread_pairs(p.view(), K, fx, fy, Fx.data(), Fy.data());
    spread_pairs_plain(p.view(), K, fx, fy, Gx.data(), Gy.data());
    const double scale = std::max(std::abs(fx), std::abs(fy)) * cubic_W(K, 0.0);
    for (int i = 0; i < N; ++i)
      worst = std::max({worst, std::abs(Fx[i] - Gx[i]) / scale, std::abs(Fy[i] - Gy[i]) / scale});
  }
  EXPECT_LT(worst, 1e-14);
  std::printf("spread_pairs: max |fast - plain| / (|f| W(0)) = %.2g\n", worst);
}

// The divergence-free interpolation's sums (kernels/curl_sums.hpp), with and without the Hessians:
// fast (two lanes, summed pairwise) against plain (one point at a time), relative to n times the
// largest term (|psi| <= 1: W(0) for s and sp; |F(0)| 2h for the gradients; 3 |F(0)| for the
// Hessians). Measured max 1.4e-16; tolerance 1e-14 (the lanes add the even and the odd points
// apart: a different order of the same terms, plus the lane form's rounding).
TEST(Kernels, CurlSumsMatchThePlainSums) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double h = 0.05 + 0.1 * (u(rng) + 1.0);
    const CubicSpline K = CubicSpline::of(h);
    const int N = 50, n = 1 + trial % 45;
    const RandomPoints p = random_points(rng, n, N, h);
    std::vector<double> psi(N);
    for (double& v : psi) v = u(rng);
    const bool hessian = trial % 2;
    const CurlSums a = curl_sums(p.view(), K, psi.data(), hessian), b = curl_sums_plain(p.view(), K, psi.data(), hessian);
    const double sw = n * cubic_W(K, 0.0), F0 = std::abs(cubic_F(K, 0.0)), sg = n * F0 * 2.0 * h, sh = n * 3.0 * F0;
    const double e[] = {std::abs(a.s - b.s) / sw,       std::abs(a.sp - b.sp) / sw,     std::abs(a.gx - b.gx) / sg,
                        std::abs(a.gy - b.gy) / sg,     std::abs(a.gpx - b.gpx) / sg,   std::abs(a.gpy - b.gpy) / sg,
                        std::abs(a.hxx - b.hxx) / sh,   std::abs(a.hxy - b.hxy) / sh,   std::abs(a.hyy - b.hyy) / sh,
                        std::abs(a.phxx - b.phxx) / sh, std::abs(a.phxy - b.phxy) / sh, std::abs(a.phyy - b.phyy) / sh};
    for (double x : e) worst = std::max(worst, x);
    if (!hessian) EXPECT_EQ(a.hxx, 0.0);
  }
  EXPECT_LT(worst, 1e-14);
  std::printf("curl_sums: max |fast - plain| / scale = %.2g\n", worst);
}

// The gauge's passes: the same sums in the same order, so bit for bit (odd and even nx, 1-9 rows).
TEST(Kernels, GaugeRowPassesEqualThePlainOnesBitForBit) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int nx : {1, 2, 7, 16, 33}) {
    for (int m = 1; m <= 9; ++m) {
      std::vector<double> f(static_cast<size_t>(nx) * (m + 2));
      for (double& v : f) v = u(rng);
      std::vector<double> e(m), o(m), ep(m), op(m);
      row_sums(f.data(), nx, 1, m, e.data(), o.data());
      row_sums_plain(f.data(), nx, 1, m, ep.data(), op.data());
      for (int l = 0; l < m; ++l) {
        EXPECT_TRUE(same_bits(e[l], ep[l])) << nx << " " << m << " " << l;
        EXPECT_TRUE(same_bits(o[l], op[l])) << nx << " " << m << " " << l;
      }
    }
    std::vector<double> r(nx), q;
    for (double& v : r) v = u(rng);
    q = r;
    const double even = u(rng), odd = u(rng);
    add_alternating_row(r.data(), nx, even, odd);
    add_alternating_row_plain(q.data(), nx, even, odd);
    for (int ix = 0; ix < nx; ++ix) EXPECT_TRUE(same_bits(r[ix], q[ix])) << nx << " " << ix;
  }
}

// LPSPH's three products in one pass: each lane the scalar sum term by term, so bit for bit, on a
// random pattern (0-12 entries a row, some columns repeated) over a row range.
TEST(Kernels, ThreeRowProductsEqualThePlainSumsBitForBit) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 40;
  std::vector<int> o{0}, col;
  std::vector<double> lap, cn, ph;
  for (int i = 0; i < n; ++i) {
    const int len = (i * 7) % 13;
    for (int k = 0; k < len; ++k) {
      col.push_back(static_cast<int>((u(rng) + 1.0) * 0.5 * (n - 1)));
      lap.push_back(u(rng));
      cn.push_back(u(rng));
      ph.push_back(u(rng));
    }
    o.push_back(static_cast<int>(col.size()));
  }
  std::vector<double> x4(4 * n), phi(n);
  for (double& v : x4) v = u(rng);
  for (double& v : phi) v = u(rng);
  const Rows3 in{o.data(), col.data(), lap.data(), cn.data(), ph.data(), x4.data(), phi.data()};
  std::vector<double> a(5 * n, 7.0), b(5 * n, 7.0);
  double* oa[5];
  double* ob[5];
  for (int m = 0; m < 5; ++m) {
    oa[m] = a.data() + m * n;
    ob[m] = b.data() + m * n;
  }
  rows3(in, oa, 3, n - 2);
  rows3_plain(in, ob, 3, n - 2);
  for (int k = 0; k < 5 * n; ++k) EXPECT_TRUE(same_bits(a[k], b[k])) << k;
}

// The fixed lattice's five block products (kernels/stencil_products.hpp): each row's sum term by
// term in the row's order in both forms, so bit for bit; blocks of 1-256 rows (the lanes' four- and
// eight-row steps and the leftover rows), contiguous and strided, a 9- and a 25-point class.
TEST(Kernels, StencilBlockProductsEqualThePlainSumsBitForBit) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Kernel = void (*)(const StencilClass&, const StencilBlock&, const double* const*, const double* const*,
                          double* const*);
  struct Pair {
    Kernel fast, plain;
    int outputs;
    const char* name;
  };
  const Pair kernels[] = {{block_apply2, block_apply2_plain, 2, "apply2"},
                          {block_apply1, block_apply1_plain, 1, "apply1"},
                          {block_gradient2, block_gradient2_plain, 4, "gradient2"},
                          {block_divergence, block_divergence_plain, 1, "divergence"},
                          {block_gradient, block_gradient_plain, 2, "gradient"}};
  const int nx = 40, ny = 300, n = nx * ny;
  for (int radius : {1, 2}) {
    StencilClass cl;
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) cl.offset.push_back(dy * nx + dx);
    const int S = static_cast<int>(cl.offset.size());
    std::vector<double> w0(S), w1(S);
    for (int s = 0; s < S; ++s) {
      w0[s] = u(rng);
      w1[s] = u(rng);
    }
    const double* w[2] = {w0.data(), w1.data()};
    std::vector<double> x0(n), x1(n);
    for (int i = 0; i < n; ++i) {
      x0[i] = u(rng);
      x1[i] = u(rng);
    }
    const double* in[2] = {x0.data(), x1.data()};
    for (int count : {1, 3, 4, 7, 8, 13, 32, 33, 255, 256})
      for (int stride : {1, nx}) {
        if (stride == nx && count > ny - 2 * radius - 2) continue;
        const StencilBlock k{0, radius * nx + radius + 1, count, stride};
        for (const Pair& p : kernels) {
          std::vector<double> a(4 * n, 7.0), b(4 * n, 7.0);
          double* oa[4] = {a.data(), a.data() + n, a.data() + 2 * n, a.data() + 3 * n};
          double* ob[4] = {b.data(), b.data() + n, b.data() + 2 * n, b.data() + 3 * n};
          p.fast(cl, k, w, in, oa);
          p.plain(cl, k, w, in, ob);
          int differ = 0;
          for (int i = 0; i < 4 * n; ++i) differ += !same_bits(a[i], b[i]);
          EXPECT_EQ(differ, 0) << p.name << " radius " << radius << " count " << count << " stride " << stride;
        }
      }
  }
}

// The lattice Poisson solver's banded substitutions (kernels/banded.hpp): every value's terms in the
// order of d in both forms, so bit for bit; half-bandwidths 1-4 (a value in a register) and 6 (whole-
// row updates), real and complex rows, odd and even wavenumber counts, a sub-range of wavenumbers.
// Random factors (not a Cholesky factor: the arithmetic is the same for any values).
TEST(Kernels, BandedSubstitutionsEqualThePlainOnesBitForBit) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int ny = 17;
  for (int w : {1, 2, 3, 4, 6})
    for (bool pairs : {false, true})
      for (int nk : {5, 8}) {
        const int ldab = w + 1, n = pairs ? 2 * nk : nk;
        std::vector<double> lrow(static_cast<size_t>(ny) * ldab * nk), lcol(lrow.size()), rdiag(ny * nk), h(ny * n);
        for (double& v : lrow) v = 0.3 * u(rng);
        for (double& v : lcol) v = 0.3 * u(rng);
        for (double& v : rdiag) v = 1.0 + 0.5 * u(rng);
        for (double& v : h) v = u(rng);
        const BandedFactors f{ny, w, ldab, nk, pairs, lrow.data(), lcol.data(), rdiag.data()};
        for (auto [k0, k1] : {std::pair<int, int>{0, nk}, std::pair<int, int>{2, nk - 1}}) {
          std::vector<double> a = h, b = h;
          substitute_bands(a.data(), f, k0, k1);
          substitute_bands_plain(b.data(), f, k0, k1);
          int differ = 0;
          for (size_t i = 0; i < h.size(); ++i) differ += !same_bits(a[i], b[i]);
          EXPECT_EQ(differ, 0) << "w " << w << " pairs " << pairs << " nk " << nk << " k " << k0 << ".." << k1;
        }
      }
}

// EPSPH's fused passes (kernels/fused_rows.hpp): every row's sums term by term in the class's order
// and every line of the row's arithmetic in the same order in both forms, so bit for bit (measured:
// no value differs; without FMA, which the default flags do not enable, that holds in both clones).
// A 40 x 300 lattice, stencils of radius 1 and 2, blocks of 1-256 rows along and across lattice rows,
// starting at both column parities (the curl velocity's four-row path takes the parity's modes).
namespace {

struct FusedCase {
  int nx = 40, ny = 300, n = nx * ny;
  StencilClass cl;
  std::vector<double> w[3];
  std::vector<StencilBlock> blocks;
};
FusedCase fused_case(std::mt19937& rng, int radius) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FusedCase f;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) f.cl.offset.push_back(dy * f.nx + dx);
  for (auto& w : f.w)
    for (size_t s = 0; s < f.cl.offset.size(); ++s) w.push_back(u(rng));
  for (int count : {1, 3, 4, 7, 8, 13, 32, 33, 255, 256})
    for (int stride : {1, f.nx})
      for (int ix : {radius + 1, radius + 2}) {
        if (stride == f.nx && count > f.ny - 2 * radius - 2) continue;
        f.blocks.push_back({0, radius * f.nx + ix, count, stride});
      }
  return f;
}
std::vector<double> random_field(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> x(n);
  for (double& v : x) v = u(rng);
  return x;
}
int differing(const std::vector<double>& a, const std::vector<double>& b) {
  int d = 0;
  for (size_t i = 0; i < a.size(); ++i) d += !same_bits(a[i], b[i]);
  return d;
}

}  // namespace

TEST(Kernels, FusedPredictorEqualsThePlainRowsBitForBit) {
  std::mt19937 rng(29);
  for (int radius : {1, 2}) {
    const FusedCase f = fused_case(rng, radius);
    const int N = f.n;
    const std::vector<double> u = random_field(rng, 2 * N), F = random_field(rng, 2 * N), conv = random_field(rng, 2 * N),
                              old = random_field(rng, 2 * N), zero(2 * N, 0.0);
    const double* in[2] = {u.data(), u.data() + N};
    const double* w[3] = {f.w[0].data(), f.w[1].data(), f.w[2].data()};
    for (bool images : {false, true}) {
      // the image terms: random where the block may have them, the zeros the callers keep elsewhere
      const std::vector<double> bc = images ? random_field(rng, 2 * N) : zero, lw = images ? random_field(rng, 2 * N) : zero,
                                cwx = images ? random_field(rng, 2 * N) : zero, cwy = images ? random_field(rng, 2 * N) : zero;
      for (bool convective : {false, true})
        for (bool first : {false, true})
          for (const StencilBlock& k : f.blocks) {
            std::vector<double> old_a = old, old_b = old, rhs_a(2 * N, 7.0), rhs_b(2 * N, 7.0);
            PredictorRows p{N, u.data(), F.data(), bc.data(), lw.data(), cwx.data(), cwy.data(), 0.31, 0.017, 0.0023,
                            first, nullptr, conv.data(), nullptr};
            PredictorRows q = p;
            p.conv_old = convective ? old_a.data() : nullptr;
            q.conv_old = convective ? old_b.data() : nullptr;
            p.rhs = rhs_a.data();
            q.rhs = rhs_b.data();
            block_predictor(p, images, f.cl, k, w, in);
            block_predictor_plain(q, f.cl, k, w, in);
            EXPECT_EQ(differing(rhs_a, rhs_b) + differing(old_a, old_b), 0)
                << "radius " << radius << " images " << images << " convective " << convective << " first " << first
                << " block " << k.begin << "+" << k.count << "x" << k.stride;
          }
    }
  }
}

TEST(Kernels, FusedCurlTransposeEqualsThePlainRowsBitForBit) {
  std::mt19937 rng(31);
  for (int radius : {1, 2}) {
    const FusedCase f = fused_case(rng, radius);
    const int N = f.n;
    const std::vector<double> u = random_field(rng, 2 * N), flux = random_field(rng, N), mflux = random_field(rng, N);
    const double* in[2] = {u.data(), u.data() + N};
    const double* w[2] = {f.w[0].data(), f.w[1].data()};
    for (double Q : {0.0, 0.37})
      for (bool markers : {false, true})
        for (const StencilBlock& k : f.blocks) {
          std::vector<double> a(3 * N, 7.0), b(3 * N, 7.0);
          const CurlTransposeRows p{Q, 1.9, flux.data(), mflux.data(), a.data(), a.data() + N,
                                    markers ? a.data() + 2 * N : nullptr};
          const CurlTransposeRows q{Q, 1.9, flux.data(), mflux.data(), b.data(), b.data() + N,
                                    markers ? b.data() + 2 * N : nullptr};
          block_curl_transpose(p, f.cl, k, w, in);
          block_curl_transpose_plain(q, f.cl, k, w, in);
          EXPECT_EQ(differing(a, b), 0) << "radius " << radius << " Q " << Q << " markers " << markers << " block "
                                        << k.begin << "+" << k.count << "x" << k.stride;
        }
  }
}

TEST(Kernels, FusedCurlVelocityEqualsThePlainRowsBitForBit) {
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int radius : {1, 2}) {
    const FusedCase f = fused_case(rng, radius);
    const int N = f.n;
    const std::vector<double> psi = random_field(rng, N), u_star = random_field(rng, 2 * N), zero(N, 0.0);
    std::vector<unsigned char> par(N);
    for (int i = 0; i < N; ++i) par[i] = static_cast<unsigned char>(2 * ((i / f.nx) & 1) + ((i % f.nx) & 1));
    const double* in[1] = {psi.data()};
    const double* w[2] = {f.w[0].data(), f.w[1].data()};
    for (bool images : {false, true}) {
      const std::vector<double> by1 = images ? random_field(rng, N) : zero, bx1 = images ? random_field(rng, N) : zero;
      for (int has : {0, 1, 3}) {
        ParityModes modes;
        modes.has[0] = has & 1;
        modes.has[1] = (has & 2) != 0;
        for (auto& c : modes.value)
          for (auto& y : c)
            for (double& v : y) v = uni(rng);
        for (double Q : {0.0, 0.37})
          for (const StencilBlock& k : f.blocks) {
            std::vector<double> a(4 * N, 7.0), b(4 * N, 7.0);
            const CurlVelocityRows p{N, f.nx, Q, 2.3, by1.data(), bx1.data(), u_star.data(), par.data(), modes,
                                     a.data(), a.data() + 2 * N};
            const CurlVelocityRows q{N, f.nx, Q, 2.3, by1.data(), bx1.data(), u_star.data(), par.data(), modes,
                                     b.data(), b.data() + 2 * N};
            block_curl_velocity(p, images, f.cl, k, w, in);
            block_curl_velocity_plain(q, f.cl, k, w, in);
            EXPECT_EQ(differing(a, b), 0) << "radius " << radius << " images " << images << " modes " << has << " Q "
                                          << Q << " block " << k.begin << "+" << k.count << "x" << k.stride;
          }
      }
    }
  }
}
