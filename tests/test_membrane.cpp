// membrane/: periodic spline, Hookean force (Eqs. 47-50), shapes and diagnostics.
// Tolerances are the measured errors (stated beside each) with a small margin.
#include <gtest/gtest.h>

#include <random>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "helpers.hpp"
#include "membrane/geometry.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"
#include "membrane/force.hpp"
#include "membrane/spline.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;

double order(double e_coarse, double e_fine) { return std::log2(e_coarse / e_fine); }

// Max errors of the spline of sin(2 pi s/L) at 8 points per interval: value, d1, d2; and d1
// at the knots.
struct SineErrors {
  double v = 0, d1 = 0, d2 = 0, d1_knots = 0;
};
SineErrors sine_errors(int n) {
  const double L = 2.0, w = 2.0 * kPi / L;
  PeriodicSpline S(n, L);
  Vec y(n), yk(n);
  for (int k = 0; k < n; ++k) y[k] = std::sin(w * k * S.h());
  S.fit(y.data());
  S.d1_at_knots(yk.data());
  SineErrors e;
  for (int k = 0; k < n; ++k)
    e.d1_knots = std::max(e.d1_knots, std::abs(yk[k] - w * std::cos(w * k * S.h())));
  for (int i = 0; i < 8 * n; ++i) {
    const double s = (i + 0.3) * L / (8 * n);
    e.v = std::max(e.v, std::abs(S.value(s) - std::sin(w * s)));
    e.d1 = std::max(e.d1, std::abs(S.d1(s) - w * std::cos(w * s)));
    e.d2 = std::max(e.d2, std::abs(S.d2(s) + w * w * std::sin(w * s)));
  }
  return e;
}

// Exact f = d(T tau)/ds on X(s) = c + (rx cos(s/r0), ry sin(s/r0)), the shape built by ellipse().
Mat2 exact_ellipse_force(int nb, double r0, double rx, double ry, double T0) {
  Mat2 f(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2.0 * kPi * k / nb, c = std::cos(th), s = std::sin(th);
    const double xs = -rx * s / r0, ys = ry * c / r0;                   // X_s
    const double xss = -rx * c / (r0 * r0), yss = -ry * s / (r0 * r0);  // X_ss
    const double nrm = std::hypot(xs, ys);
    const double a = T0 * (1.0 - 1.0 / nrm), b = T0 * (xs * xss + ys * yss) / (nrm * nrm * nrm);
    f(k, 0) = a * xss + b * xs;
    f(k, 1) = a * yss + b * ys;
  }
  return f;
}

double ellipse_force_error(int nb, HookeanScheme scheme) {
  const double r0 = 0.5, T0 = 3.0;
  const Membrane m = make_membrane(ellipse(nb, 0.1, -0.2, 0.75, 0.5), r0, T0);
  MembraneForce H(m, scheme);
  Mat2 f;
  Vec T;
  H.compute(m.X, f, T);
  const Mat2 fe = exact_ellipse_force(nb, r0, 0.75, 0.5, T0);
  return (f - fe).cwiseAbs().maxCoeff() / fe.cwiseAbs().maxCoeff();
}

using sphib_test::blob;

template <class F>
std::string thrown_message(F fn) {
  try {
    fn();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<nothing thrown>";
}

}  // namespace

// ------------------------------------------------------------------ spline

TEST(SplineTest, RejectsFewerThanFourKnots) {
  EXPECT_NE(thrown_message([] { PeriodicSpline(3, 1.0); }).find("n = 3"), std::string::npos);
  EXPECT_THROW(PeriodicSpline(8, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(PeriodicSpline(4, 1.0));
}

TEST(SplineTest, ReproducesConstantExactly) {
  PeriodicSpline S(7, 1.3);
  Vec y = Vec::Constant(7, 2.5);
  S.fit(y.data());
  for (double s : {-0.41, 0.0, 0.2, 0.777, 1.3, 5.0}) {
    EXPECT_EQ(S.value(s), 2.5);
    EXPECT_EQ(S.d1(s), 0.0);
    EXPECT_EQ(S.d2(s), 0.0);
  }
}

TEST(SplineTest, InterpolatesWrapsAndHonoursStride) {
  const int n = 12;
  const double L = 3.0;
  Mat2 Y(n, 2);  // column-major: column 1 starts at Y.data() + n
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> Z(n, 2);  // interleaved: stride 2
  for (int k = 0; k < n; ++k) Y(k, 1) = Z(k, 1) = std::exp(std::sin(2 * kPi * k / n)) + 0.1 * (k % 3);
  PeriodicSpline A(n, L), B(n, L);
  A.fit(Y.data() + n);
  B.fit(Z.data() + 1, 2);
  for (int k = 0; k < n; ++k) EXPECT_NEAR(A.value(k * A.h()), Y(k, 1), 1e-14);
  for (double s : {0.0, 0.13, 1.7, 2.99}) {
    EXPECT_DOUBLE_EQ(A.value(s), B.value(s));
    EXPECT_NEAR(A.value(s + 2 * L), A.value(s), 1e-13);
    EXPECT_NEAR(A.d1(s - 3 * L), A.d1(s), 1e-12);
  }
}

TEST(SplineTest, PairFitGivesTheBitsOfTwoSingleFits) {
  // fit_pair interleaves two splines' sweeps; each must be exactly its own fit(): same knot
  // derivatives bit for bit, and fitted_to recognises the values fitted (and no others).
  const int n = 37;
  const double L = 2.5;
  Mat2 Y(n, 2);
  for (int k = 0; k < n; ++k) {
    Y(k, 0) = std::cos(2 * kPi * k / n) + 0.01 * (k % 5);
    Y(k, 1) = std::exp(std::sin(2 * kPi * k / n)) - 0.03 * (k % 4);
  }
  PeriodicSpline A(n, L), B(n, L), P(n, L), Q(n, L);
  A.fit(Y.data());
  B.fit(Y.data() + n);
  PeriodicSpline::fit_pair(P, Y.data(), Q, Y.data() + n);
  Vec a(n), b(n), p(n), q(n);
  A.d1_at_knots(a.data());
  B.d2_at_knots(b.data());
  P.d1_at_knots(p.data());
  Q.d2_at_knots(q.data());
  EXPECT_EQ(std::memcmp(a.data(), p.data(), sizeof(double) * n), 0);
  EXPECT_EQ(std::memcmp(b.data(), q.data(), sizeof(double) * n), 0);
  EXPECT_TRUE(P.fitted_to(Y.data()));
  EXPECT_FALSE(P.fitted_to(Y.data() + n));
  PeriodicSpline R(n + 1, L);
  EXPECT_THROW(PeriodicSpline::fit_pair(P, Y.data(), R, Y.data()), std::invalid_argument);
}

TEST(SplineTest, ConvergesOnSineAtOrders4_3_2) {
  // Measured at n = 16, 32, 64: value 6.3e-5, 3.9e-6, 2.4e-7 (order 4.0); d1 1.5e-3, 1.9e-4,
  // 2.4e-5 (3.0); d2 0.12, 0.029, 0.0065 (2.1); d1 at the knots 4.2e-4, 2.6e-5, 1.6e-6 (4.0).
  const SineErrors e16 = sine_errors(16), e32 = sine_errors(32), e64 = sine_errors(64);
  EXPECT_GT(order(e32.v, e64.v), 3.9);
  EXPECT_GT(order(e16.v, e32.v), 3.9);
  EXPECT_GT(order(e32.d1, e64.d1), 2.9);
  EXPECT_GT(order(e32.d2, e64.d2), 1.9);
  EXPECT_GT(order(e32.d1_knots, e64.d1_knots), 3.9);
  EXPECT_LT(e64.v, 2.6e-7);
  EXPECT_LT(e64.d1, 2.6e-5);
  EXPECT_LT(e64.d2, 7.0e-3);
  EXPECT_LT(e64.d1_knots, 1.7e-6);
}

// ------------------------------------------------------------------ Hookean

TEST(HookeanTest, RestCircleHasNoTensionBeyondTheSplineSymbol) {
  // At radius r0 the exact |X_s| = 1 (Eq. 64), so T = 0. The spline's knot derivative of
  // (cos, sin)(s/r0) is exact up to the factor 3 sin(th)/(th (2 + cos th)) = 1 - th^4/180,
  // th = 2 pi/nb: T = T0 (that - 1) = -6.8e-8 at nb = 140, reproduced here to round-off
  // (measured deviation 4e-14).
  const int nb = 140;
  const double r0 = 0.5, T0 = 3.0, th = 2 * kPi / nb;
  const double T_spline = T0 * (3 * std::sin(th) / (th * (2 + std::cos(th))) - 1.0);
  for (HookeanScheme scheme : {HookeanScheme::ProductSpline, HookeanScheme::Analytic}) {
    const Membrane m = make_membrane(circle(nb, 0.3, -0.2, r0), r0, T0);
    MembraneForce H(m, scheme);
    Mat2 f;
    Vec T;
    H.compute(m.X, f, T);
    for (int k = 0; k < nb; ++k) EXPECT_NEAR(T[k], T_spline, 1e-13);
    EXPECT_LT(std::abs(T_spline), 7e-8);
    EXPECT_LT(f.cwiseAbs().maxCoeff(), 1.4e-7);  // measured 1.35e-7
  }
}

TEST(HookeanTest, PaperEquilibriumCircleGivesMinusOnePerCurrentLength) {
  // Section 5.2.1: r0 = 0.5, re = 0.6, T0 = 3, Nb = 140. |X_s| = 1.2, T = 0.6, and
  // f.n = -T0 (re/r0 - 1)/r0 = -1.2 per unit rest arclength, i.e. -1 per unit current length
  // and [p] = -1 by Eqs. (65)-(66). Measured max errors in f.n: ProductSpline 1.9e-7,
  // Analytic 2.0e-4; tangential component below 1.1e-11 for both.
  const int nb = 140;
  const double r0 = 0.5, re = 0.6, T0 = 3.0;
  const Membrane m = make_membrane(circle(nb, 0.0, 0.0, re), r0, T0);
  for (auto [scheme, tol] : {std::pair{HookeanScheme::ProductSpline, 2.5e-7},
                             std::pair{HookeanScheme::Analytic, 2.5e-4}}) {
    MembraneForce H(m, scheme);
    Mat2 f;
    Vec T;
    H.compute(m.X, f, T);
    for (int k = 0; k < nb; ++k) {
      const double th = 2 * kPi * k / nb;
      const double f_n = f(k, 0) * std::cos(th) + f(k, 1) * std::sin(th);
      const double f_t = -f(k, 0) * std::sin(th) + f(k, 1) * std::cos(th);
      EXPECT_NEAR(f_n, -1.2, tol);
      EXPECT_NEAR(f_n / (re / r0), -1.0, tol);  // Eq. (65): [p] = f.n/|X_s|
      EXPECT_NEAR(f_t, 0.0, 1e-10);
      EXPECT_NEAR(T[k], 0.6, 1e-7);             // Eq. (47)
    }
  }
}

TEST(HookeanTest, EllipseForceConvergesToExact) {
  // rx = 0.75, ry = 0.5, r0 = 0.5, T0 = 3 (non-uniform stretch), max error / max |f|.
  // Measured at nb = 64, 128, 256: ProductSpline 1.6e-4, 9.6e-6, 5.9e-7 (order 4.0);
  // Analytic 8.0e-4, 2.0e-4, 5.0e-5 (order 2.0, X_ss at the knots is O(h^2)).
  const double p64 = ellipse_force_error(64, HookeanScheme::ProductSpline);
  const double p128 = ellipse_force_error(128, HookeanScheme::ProductSpline);
  const double p256 = ellipse_force_error(256, HookeanScheme::ProductSpline);
  EXPECT_GT(order(p64, p128), 3.9);
  EXPECT_GT(order(p128, p256), 3.9);
  EXPECT_LT(p128, 1.0e-5);
  const double a64 = ellipse_force_error(64, HookeanScheme::Analytic);
  const double a128 = ellipse_force_error(128, HookeanScheme::Analytic);
  const double a256 = ellipse_force_error(256, HookeanScheme::Analytic);
  EXPECT_GT(order(a64, a128), 1.9);
  EXPECT_GT(order(a128, a256), 1.9);
  EXPECT_LT(a128, 2.1e-4);
}

TEST(HookeanTest, TotalForceOnClosedMembraneVanishes) {
  // sum_k f_k ds = 0: the knot derivatives of a periodic spline telescope, so the default
  // (ProductSpline) conserves momentum to round-off on any shape (measured 1.3e-16; the
  // Analytic scheme leaves 3.8e-3 on this shape at nb = 128).
  const int nb = 128;
  const Mat2 X = blob(nb);
  MembraneForce H(make_membrane(X, 0.5, 3.0));
  Mat2 f;
  Vec T;
  H.compute(X, f, T);
  const double scale = f.cwiseAbs().maxCoeff() * H.ds() * nb;
  EXPECT_LT((f.colwise().sum() * H.ds()).norm(), 1e-14 * scale);
}

TEST(HookeanTest, ForceIsMinusEnergyGradient) {
  // f = -dE/dX (E of MembraneDiagnostics::energy): the directional derivative of E along a
  // smooth perturbation dX equals -sum_k f_k . dX_k ds up to the spline error. Measured
  // relative mismatch at nb = 64, 128, 256: ProductSpline 9.5e-5, 5.9e-6, 3.7e-7 (order 4);
  // Analytic 1.2e-2, 2.9e-3, 7.2e-4 (order 2).
  const int nb = 128;
  const double L0 = 2 * kPi * 0.5, T0 = 3.0, eps = 1e-5;
  const Mat2 X = blob(nb);
  Mat2 dX(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2 * kPi * k / nb;
    dX(k, 0) = std::cos(2 * th) + 0.3 * std::sin(th);
    dX(k, 1) = std::sin(3 * th);
  }
  MembraneForce H(make_membrane(X, L0 / (2 * kPi), T0));
  H.fit_energy(X + eps * dX);
  const double Ep = H.energy().total();
  H.fit_energy(X - eps * dX);
  const double Em = H.energy().total();
  Mat2 f;
  Vec T;
  H.compute(X, f, T);
  const double dE = (Ep - Em) / (2 * eps);
  const double fdX = (f.array() * dX.array()).sum() * H.ds();
  EXPECT_NEAR(dE, -fdX, 7e-6 * std::abs(fdX));
}

TEST(HookeanTest, RejectsWrongMarkerCount) {
  MembraneForce H(make_membrane(circle(64, 0, 0, 1.0), 1.0, 1.0));
  Mat2 f;
  Vec T;
  EXPECT_THROW(H.compute(Mat2::Zero(63, 2), f, T), std::invalid_argument);
}

// ------------------------------------------------------------------ geometry

TEST(GeometryTest, ShapesAreAnticlockwiseAndLabelledByRestArclength) {
  const Membrane m = make_membrane(circle(64, 1.0, 2.0, 0.6), 0.5, 3.0);
  EXPECT_EQ(m.nb(), 64);
  EXPECT_DOUBLE_EQ(m.L0(), 2 * kPi * 0.5);
  EXPECT_DOUBLE_EQ(m.ds(), m.L0() / 64);
  EXPECT_DOUBLE_EQ(m.mat.Es, 3.0);
  EXPECT_NEAR(m.X(0, 0), 1.6, 1e-15);
  EXPECT_NEAR(m.X(16, 1), 2.6, 1e-15);
  EXPECT_GT(signed_area(m.X), 0.0);
  EXPECT_TRUE(is_simple(m.X));
  EXPECT_THROW(circle(3, 0, 0, 0.5), std::invalid_argument);
  EXPECT_THROW(make_membrane(circle(64, 0, 0, 0.5), 0.0, 1.0), std::invalid_argument);  // r0 = 0
}

TEST(GeometryTest, CircleAreaLengthConvergeAtOrder4ShoelaceAtOrder2) {
  // r = 0.6, nb = 32, 64, 128. Measured: spline area 4.7e-6, 2.9e-7, 1.8e-8 (order 4.0);
  // shoelace 7.3e-3, 1.8e-3, 4.5e-4 (2.0); length 7.9e-6, 4.9e-7, 3.0e-8 (4.0).
  const double r = 0.6;
  double ea[3], ep[3], el[3];
  int i = 0;
  for (int nb : {32, 64, 128}) {
    const Membrane m = make_membrane(circle(nb, 0.3, -0.1, r), 0.5, 3.0);
    MembraneDiagnostics D(nb, m.L0());
    const MembraneShape g = D.measure(m.X);
    ea[i] = std::abs(g.area - kPi * r * r);
    ep[i] = std::abs(g.area_polygon - kPi * r * r);
    el[i] = std::abs(g.length - 2 * kPi * r);
    EXPECT_NEAR(g.cx, 0.3, 1e-14);
    EXPECT_NEAR(g.cy, -0.1, 1e-14);
    ++i;
  }
  EXPECT_GT(order(ea[0], ea[1]), 3.9);
  EXPECT_GT(order(ea[1], ea[2]), 3.9);
  EXPECT_NEAR(order(ep[0], ep[1]), 2.0, 0.05);
  EXPECT_NEAR(order(ep[1], ep[2]), 2.0, 0.05);
  EXPECT_GT(order(el[1], el[2]), 3.9);
  EXPECT_LT(ea[2], 2e-8);
  EXPECT_LT(el[2], 3.5e-8);
}

TEST(GeometryTest, EllipseHalfAxesRecovered) {
  // nb = 128, rx = 0.75, ry = 0.5. Markers on the axes: exact. Markers shifted by 0.37 of a
  // spacing (crossings inside segments): measured errors 9.9e-9 (rx), 6.6e-9 (ry).
  const int nb = 128;
  const Membrane m = make_membrane(ellipse(nb, 0.3, -0.1, 0.75, 0.5), 0.5, 3.0);
  MembraneDiagnostics D(nb, m.L0());
  MembraneShape g = D.measure(m.X);
  EXPECT_NEAR(g.rx, 0.75, 1e-6);
  EXPECT_NEAR(g.ry, 0.5, 1e-6);
  EXPECT_NEAR(g.area, kPi * 0.75 * 0.5, 2e-8);  // measured 1.9e-8
  Mat2 X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2 * kPi * (k + 0.37) / nb;
    X(k, 0) = 0.3 + 0.75 * std::cos(th);
    X(k, 1) = -0.1 + 0.5 * std::sin(th);
  }
  g = D.measure(X);
  EXPECT_NEAR(g.cx, 0.3, 1e-13);
  EXPECT_NEAR(g.cy, -0.1, 1e-13);
  EXPECT_NEAR(g.rx, 0.75, 1.5e-8);
  EXPECT_NEAR(g.ry, 0.5, 1e-8);
}

// The markers of the coarse oscillating membrane (32 x 32, Nb = 64, dt = 1e-3) at t = 0.76: the
// horizontal line through the centroid (y ~ 1e-17) meets the curve at a knot, where the two
// adjacent pieces' values rounded to opposite sides of the line, so the crossing fell between them
// and rx came out 0. rx must be the half-chord (0.539, as at the neighbouring output times).
TEST(GeometryTest, HalfChordThroughAKnotIsFoundDespiteRoundOff) {
  const double xy[] = {
      0.53907984371595952, -6.4894577305211507e-16, 0.5370485892617749, 0.060519570325482587,
      0.53088339539864404, 0.1207419964371771, 0.52056059889989625, 0.1803740920006934,
      0.50600981650422483, 0.23919950172773177, 0.48717086603181531, 0.296684720548273,
      0.46391826122349694, 0.3524893220318065, 0.43604492156819735, 0.40632557768654681,
      0.40381002874068539, 0.45735968340479027, 0.36686284608692249, 0.50508987774497138,
      0.32521960531492095, 0.54900630799075378, 0.27932000857503869, 0.58791526247482795,
      0.22918961702117283, 0.62130341083575569, 0.17543885520217381, 0.64847016880394437,
      0.1187232485217115, 0.66829535744962199, 0.059921599097591968, 0.68048011446879619,
      6.6215692557324395e-17, 0.68466160024484712, -0.059921599097591954, 0.6804801144687963,
      -0.11872324852171134, 0.66829535744962187, -0.17543885520217378, 0.64847016880394459,
      -0.22918961702117263, 0.62130341083575569, -0.2793200085750388, 0.58791526247482806,
      -0.32521960531492056, 0.54900630799075389, -0.36686284608692266, 0.5050898777449716,
      -0.40381002874068544, 0.4573596834047905, -0.43604492156819702, 0.40632557768654692,
      -0.463918261223497, 0.35248932203180655, -0.48717086603181531, 0.29668472054827338,
      -0.50600981650422494, 0.23919950172773188, -0.52056059889989625, 0.1803740920006936,
      -0.53088339539864404, 0.12074199643717734, -0.53704858926177501, 0.060519570325482747,
      -0.53907984371595952, -4.0769423143278987e-16, -0.53704858926177523, -0.060519570325483676,
      -0.53088339539864382, -0.1207419964371781, -0.52056059889989625, -0.1803740920006946,
      -0.50600981650422494, -0.2391995017277328, -0.48717086603181531, -0.29668472054827427,
      -0.46391826122349694, -0.35248932203180744, -0.43604492156819724, -0.40632557768654776,
      -0.40381002874068539, -0.45735968340479161, -0.36686284608692282, -0.5050898777449726,
      -0.32521960531492083, -0.54900630799075478, -0.2793200085750388, -0.58791526247482917,
      -0.22918961702117302, -0.62130341083575691, -0.17543885520217378, -0.64847016880394559,
      -0.11872324852171166, -0.66829535744962276, -0.059921599097592065, -0.68048011446879797,
      -1.4261407917060872e-16, -0.68466160024484846, 0.059921599097591767, -0.68048011446879797,
      0.11872324852171139, -0.66829535744962276, 0.1754388552021735, -0.64847016880394581,
      0.22918961702117277, -0.62130341083575702, 0.27932000857503847, -0.58791526247482917,
      0.32521960531492067, -0.549006307990755, 0.3668628460869226, -0.50508987774497283,
      0.40381002874068511, -0.45735968340479166, 0.43604492156819702, -0.40632557768654803,
      0.46391826122349694, -0.35248932203180766, 0.48717086603181509, -0.29668472054827438,
      0.50600981650422472, -0.23919950172773316, 0.52056059889989637, -0.18037409200069462,
      0.53088339539864382, -0.12074199643717839, 0.53704858926177501, -0.060519570325483878};
  const int nb = 64;
  Mat2 X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    X(k, 0) = xy[2 * k];
    X(k, 1) = xy[2 * k + 1];
  }
  MembraneDiagnostics D(nb, kPi);  // r0 = 0.5
  const MembraneShape g = D.measure(X);
  EXPECT_NEAR(g.rx, 0.539, 0.002);
  EXPECT_NEAR(g.ry, 0.6847, 0.002);
}

TEST(GeometryTest, StretchedCircleEnergy) {
  // E = T0/2 (re/r0 - 1)^2 L0 (uniform stretch). Measured error 1.8e-8 at nb = 128.
  const int nb = 128;
  const double r0 = 0.5, re = 0.6, T0 = 3.0;
  const Membrane m = make_membrane(circle(nb, 0.0, 0.0, re), r0, T0);
  MembraneForce E(m);
  E.fit_energy(m.X);
  EXPECT_NEAR(E.energy().total(), 0.5 * T0 * std::pow(re / r0 - 1.0, 2) * m.L0(), 3e-8);
  const Membrane rest = make_membrane(circle(nb, 0.0, 0.0, r0), r0, T0);
  E.fit_energy(rest.X);
  EXPECT_LT(E.energy().total(), 1e-14);
}

// elastic_energy (two segments side by side, chunks of 64) is bit for bit the plain loop over
// segments and Gauss points, at nb with an odd tail (65), chunks and a rest (150) and one chunk (64).
TEST(GeometryTest, ElasticEnergyIsThePlainGaussSum) {
  for (const int nb : {64, 65, 150}) {
    const double T0 = 3.0;
    const Membrane m = make_membrane(ellipse(nb, 0.1, -0.2, 0.7, 0.4), 0.5, T0);
    MembraneForce H(m);
    Mat2 f;
    Vec T;
    H.compute(m.X, f, T);
    const PeriodicSpline &sx = H.spline(0), &sy = H.spline(1);
    const double h = sx.h();
    double sum = 0.0, cx[4], cy[4];
    for (int k = 0; k < nb; ++k) {
      sx.segment(k, cx);
      sy.segment(k, cy);
      for (int q = 0; q < 5; ++q) {
        const double t = 0.5 * h * (1.0 + gauss5::x[q]);
        const double xs = cx[1] + t * (2.0 * cx[2] + 3.0 * t * cx[3]);
        const double ys = cy[1] + t * (2.0 * cy[2] + 3.0 * t * cy[3]);
        const double e = std::sqrt(xs * xs + ys * ys) - 1.0;
        sum += gauss5::w[q] * (e * e);
      }
    }
    EXPECT_EQ(elastic_energy(sx, sy, T0), 0.5 * T0 * (0.5 * h * sum)) << "nb " << nb;
  }
}

TEST(GeometryTest, HookeanForceSplinesGiveTheDiagnosticsEnergy) {
  // The guards take the elastic energy from the force's splines when they were fitted to the
  // markers: the same value bit for bit as a diagnostics fit of the same X.
  const int nb = 64;
  const Membrane m = make_membrane(ellipse(nb, 0.1, -0.2, 0.75, 0.5), 0.6, 2.0);
  MembraneForce H(m);
  Mat2 f;
  Vec T;
  H.compute(m.X, f, T);
  ASSERT_TRUE(H.fitted_to(m.X));
  MembraneDiagnostics D(nb, m.L0());
  D.fit(m.X);
  MembraneForce W(m);  // another's splines, fitted for the energy alone
  W.fit_energy(m.X);
  const double E = W.energy().total(), E_h = H.energy().total();
  EXPECT_EQ(E, elastic_energy(H.spline(0), H.spline(1), m.mat.Es));
  EXPECT_EQ(std::memcmp(&E, &E_h, sizeof E), 0);
  Mat2 X = m.X;
  X(3, 1) += 1e-9;
  EXPECT_FALSE(H.fitted_to(X));
}

TEST(GeometryTest, PolygonPredicates) {
  Mat2 sq(4, 2);
  sq << 0, 0, 1, 0, 1, 1, 0, 1;
  EXPECT_DOUBLE_EQ(signed_area(sq), 1.0);
  EXPECT_DOUBLE_EQ(signed_area(sq.colwise().reverse()), -1.0);
  EXPECT_TRUE(is_simple(sq));
  EXPECT_TRUE(polygon_centroid(sq).isApprox(Eigen::Vector2d(0.5, 0.5)));
  Mat2 bow(4, 2);
  bow << 0, 0, 1, 1, 1, 0, 0, 1;
  EXPECT_FALSE(is_simple(bow));
  Mat2 fold(4, 2);  // an edge doubles back along its neighbour
  fold << 0, 0, 2, 0, 1, 0, 1, 1;
  EXPECT_FALSE(is_simple(fold));
  EXPECT_TRUE(is_simple(blob(64)));
}

TEST(GeometryTest, FromPointsResamplesUniformlyInArclength) {
  // 20 unevenly spaced points on a circle of radius 0.6 (chords differ by 22%) -> 128 markers
  // of equal chord (measured spread 2.7e-6, the chord/arc difference of a varying curvature),
  // enclosing pi r^2 to the accuracy of a 20-point spline (measured 3.4e-5).
  Mat2 P(20, 2);
  for (int k = 0; k < 20; ++k) {
    const double th = 2 * kPi * (k / 20.0 + 0.02 * std::sin(2 * kPi * k / 20));
    P(k, 0) = 0.1 + 0.6 * std::cos(th);
    P(k, 1) = 0.6 * std::sin(th);
  }
  const Membrane m = make_membrane(from_points(P, 128), 0.5, 3.0);
  EXPECT_EQ(m.nb(), 128);
  EXPECT_DOUBLE_EQ(m.L0(), kPi);
  EXPECT_DOUBLE_EQ(m.mat.Es, 3.0);
  double dmin = 1e9, dmax = 0;
  for (int k = 0; k < 128; ++k) {
    const double d = (m.X.row((k + 1) % 128) - m.X.row(k)).norm();
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  EXPECT_LT((dmax - dmin) / dmax, 5e-6);
  EXPECT_NEAR(m.X(0, 0), P(0, 0), 1e-15);  // starts at the first point
  EXPECT_NEAR(m.X(0, 1), P(0, 1), 1e-15);
  MembraneDiagnostics D(128, m.L0());
  EXPECT_NEAR(D.measure(m.X).area, kPi * 0.36, 5e-5);
  // A repeated closing point is accepted and changes nothing.
  Mat2 Pc(21, 2);
  Pc << P, P.row(0);
  EXPECT_TRUE(from_points(Pc, 128).isApprox(m.X, 1e-14));
}

TEST(GeometryTest, FromPointsRejectsBadInput) {
  Mat2 P(20, 2);
  for (int k = 0; k < 20; ++k) P.row(k) << std::cos(2 * kPi * k / 20), std::sin(2 * kPi * k / 20);
  const Mat2 cw = P.colwise().reverse();
  EXPECT_NE(thrown_message([&] { from_points(cw, 64); }).find("clockwise"),
            std::string::npos);
  Mat2 bow(4, 2);
  bow << 0, 0, 1, 1, 1, 0, 0, 1;
  EXPECT_NE(thrown_message([&] { from_points(bow, 64); }).find("self-intersects"),
            std::string::npos);
  Mat2 tri(3, 2);
  tri << 0, 0, 1, 0, 0, 1;
  EXPECT_NE(thrown_message([&] { from_points(tri, 64); }).find("at least 4"),
            std::string::npos);
  Mat2 bad = P;
  bad(5, 1) = std::nan("");
  EXPECT_NE(thrown_message([&] { from_points(bad, 64); }).find("NaN"),
            std::string::npos);
}
