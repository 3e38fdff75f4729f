// Membrane laws (membrane/law.hpp, membrane/laws/), bending, reference states, the stiff-force filter
// (coupling/stiff_force.hpp), the B-spline marker interpolation and the scene keys of the material.
// Every registered law is tested through the registry, so a new law is tested here by registering
// it; its own small-strain modulus goes in kModulus below. Tolerances are measured values with a
// margin, stated beside each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <map>
#include <string>

#include "coupling/interpolate.hpp"
#include "coupling/simulation.hpp"
#include "coupling/stiff_force.hpp"
#include "helpers.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "membrane/force.hpp"
#include "membrane/geometry.hpp"
#include "membrane/shapes.hpp"
#include "scene_refusal.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;
using test::refusal;

const char* const kMinimal = sphib_test::kMinimalScene;

using sphib_test::blob;

Material material(const std::string& law, double Es, double Eb) {
  Material m;
  m.law = law;
  m.Es = Es;
  m.Eb = Eb;
  return m;
}

// Relative mismatch between the energy's directional derivative along a smooth dX and -sum f.dX ds.
double gradient_mismatch(const std::string& law, double Eb, int nb) {
  const Mat2 X = blob(nb);
  MembraneForce F(make_membrane(X, circle_reference(0.5), material(law, 3.0, Eb)));
  Mat2 dX(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2 * kPi * k / nb;
    dX(k, 0) = std::cos(2 * th) + 0.3 * std::sin(th);
    dX(k, 1) = std::sin(3 * th);
  }
  const double eps = 1e-6;
  F.fit_energy(X + eps * dX);
  const double Ep = F.energy().total();
  F.fit_energy(X - eps * dX);
  const double Em = F.energy().total();
  Mat2 f;
  Vec T;
  F.compute(X, f, T);
  const double dE = (Ep - Em) / (2 * eps), fdX = (f.array() * dX.array()).sum() * F.ds();
  return std::abs(dE + fdX) / std::abs(fdX);
}

// The small-strain plane-strain modulus dT/dlambda at lambda = 1 of each law with Es = 1 and its
// default parameters (neo-Hookean: K + Es = 4 Es; Skalak, C = 1: 2 Es (1 + C) = 4 Es).
const std::map<std::string, double> kModulus{{"hookean", 1.0}, {"neo_hookean", 4.0}, {"skalak", 4.0}, {"inextensible", 1.0}};

}  // namespace

// ------------------------------------------------------------------ the laws

TEST(MembraneLaws, EveryLawIsStressFreeAtRestAndItsTensionIsItsEnergysDerivative) {
  for (const LawInfo& info : tension_laws()) {
    SCOPED_TRACE(info.name);
    std::vector<double> p;
    for (const LawParam& q : info.params) p.push_back(q.value);
    const auto law = info.make(1.0, p);
    EXPECT_EQ(law->energy(1.0), 0.0);
    EXPECT_EQ(law->tension(1.0), 0.0);
    ASSERT_TRUE(kModulus.count(info.name)) << "a registered law without its expected small-strain modulus here";
    EXPECT_NEAR(law->stiffness(1.0), kModulus.at(info.name), 1e-14);
    for (double l : {0.7, 0.95, 1.2, 1.6}) {  // T = dW/dl, dT/dl, central differences (error ~1e-10)
      const double e = 1e-5;
      EXPECT_NEAR(law->tension(l), (law->energy(l + e) - law->energy(l - e)) / (2 * e), 1e-8 * (1 + std::abs(law->tension(l))));
      EXPECT_NEAR(law->stiffness(l), (law->tension(l + e) - law->tension(l - e)) / (2 * e), 1e-8 * (1 + law->stiffness(l)));
      EXPECT_GT(law->stiffness(l), 0.0);  // all four are monotone in the stretch
    }
  }
}

TEST(MembraneLaws, SkalakHardensAndNeoHookeanSoftens) {
  // At lambda = 1.5, against their common small-strain modulus 4 Es (T ~ 4 Es 0.5 = 2): Skalak
  // (1 + C) 1.5 (1.25) = 3.75 (hardening), neo-Hookean 1.5 - 1/3.375 = 1.2037 (softening).
  const auto sk = tension_law_info("skalak").make(1.0, {1.0});
  const auto nh = tension_law_info("neo_hookean").make(1.0, {});
  EXPECT_NEAR(sk->tension(1.5), 3.75, 1e-14);
  EXPECT_NEAR(nh->tension(1.5), 1.5 - 1.0 / 3.375, 1e-14);
  EXPECT_GT(sk->tension(1.5), 4.0 * 0.5);
  EXPECT_LT(nh->tension(1.5), 4.0 * 0.5);
}

TEST(MembraneLaws, UnknownLawAndBadParametersAreRefusedByName) {
  const Mat2 X = circle(32, 0, 0, 0.5);
  try {
    make_membrane(X, circle_reference(0.5), material("mooney", 1.0, 0.0));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("skalak"), std::string::npos) << e.what();  // the known names are listed
  }
  Material sk = material("skalak", 1.0, 0.0);
  sk.params = {-1.0};
  EXPECT_THROW(make_membrane(X, circle_reference(0.5), sk), std::invalid_argument);
  EXPECT_THROW(make_membrane(X, circle_reference(0.5), material("hookean", 1.0, -1.0)), std::invalid_argument);
  EXPECT_THROW(make_membrane(X, circle_reference(0.5), material("hookean", NAN, 0.0)), std::invalid_argument);
}

TEST(MembraneLaws, AMembraneBuiltFieldByFieldTakesTheLawsDefaultParameters) {
  // A Membrane aggregate (as the Python builders make one) whose material names Skalak without C:
  // its force is the one with the registry's default C, not an out-of-range read; a wrong count is
  // refused naming the law.
  const Mat2 X = ellipse(32, 0, 0, 0.6, 0.45);
  Material bare;
  bare.law = "skalak";
  bare.Es = 2.0;
  const Membrane given = make_membrane(X, circle_reference(0.5), bare);  // fills C with its default
  ASSERT_EQ(given.mat.params.size(), 1u);
  MembraneForce a(Membrane{X, circle_reference(0.5), bare}), b(given);
  Mat2 fa, fb;
  Vec Ta, Tb;
  a.compute(X, fa, Ta);
  b.compute(X, fb, Tb);
  EXPECT_EQ((fa - fb).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(fa.cwiseAbs().maxCoeff(), 0.0);
  bare.params = {1.0, 2.0};
  try {
    make_tension_law(bare);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("\"skalak\" takes 1 parameters, got 2"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------ force = -dE/dX, every law, bending

TEST(MembraneLaws, ForceIsMinusEnergyGradientAtOrderFourWithAndWithoutBending) {
  // Measured at nb = 64, 128, 256 (Es = 3, Eb = 0.7 on the blob): hookean 1.6e-4, 9.7e-6, 6.1e-7;
  // skalak 8.5e-5, 5.3e-6, 3.3e-7; neo_hookean 1.3e-4, 8.2e-6, 5.1e-7: order 4.0 for all.
  for (const LawInfo& info : tension_laws())
    for (double Eb : {0.0, 0.7}) {
      SCOPED_TRACE(info.name + " Eb " + std::to_string(Eb));
      const double e64 = gradient_mismatch(info.name, Eb, 64), e128 = gradient_mismatch(info.name, Eb, 128),
                   e256 = gradient_mismatch(info.name, Eb, 256);
      EXPECT_LT(e128, 2e-5);
      EXPECT_GT(std::log2(e64 / e128), 3.7);
      EXPECT_GT(std::log2(e128 / e256), 3.7);
    }
}

TEST(MembraneLaws, TotalForceVanishesWithBending) {
  // Knot derivatives telescope: sum_k f_k = 0 to round-off for any law with bending (measured
  // 2.4e-13 against max |f| nb ds ~ 1e3).
  const int nb = 128;
  for (const LawInfo& info : tension_laws()) {
    MembraneForce F(make_membrane(blob(nb), circle_reference(0.5), material(info.name, 3.0, 0.7)));
    Mat2 f;
    Vec T;
    F.compute(blob(nb), f, T);
    EXPECT_LT(f.colwise().sum().norm() * F.ds(), 1e-14 * f.cwiseAbs().maxCoeff() * nb * F.ds()) << info.name;
  }
}

TEST(Bending, CircleWithoutSpontaneousCurvaturePushesOutwardByEbOver2R3) {
  // E_b = pi Eb/R: f = -(dE_b/dR)/(2 pi R) = Eb/(2 R^3) outward per unit length, uniform. Hookean
  // T0 = 0, kappa0 = 0. Measured max error 1.1e-7 relative at nb = 128; the energy 2.0e-9.
  const int nb = 128;
  const double R = 0.7, Eb = 0.3;
  Material m = material("hookean", 0.0, Eb);
  m.spontaneous = true;
  MembraneForce F(make_membrane(circle(nb, 0.1, 0.2, R), circle_reference(R), m));
  Mat2 f;
  Vec T;
  F.compute(circle(nb, 0.1, 0.2, R), f, T);
  const double expect = Eb / (2 * R * R * R);
  for (int k = 0; k < nb; ++k) {
    const double th = 2 * kPi * k / nb;
    const double fn = f(k, 0) * std::cos(th) + f(k, 1) * std::sin(th), ft = -f(k, 0) * std::sin(th) + f(k, 1) * std::cos(th);
    EXPECT_NEAR(fn, expect, 2e-7 * expect);  // |X_s| = 1: per unit label = per unit length
    EXPECT_NEAR(ft, 0.0, 1e-10 * expect);
  }
  EXPECT_NEAR(F.energy().bending, kPi * Eb / R, 1e-7 * kPi * Eb / R);  // measured 5.6e-8: the knot derivative's symbol
}

TEST(Bending, CircleAtItsReferenceCurvatureFeelsNoBending) {
  // kappa0 = 1/r0 on the circle reference: the rest circle has no bending force beyond the spline's
  // curvature error (measured max |f| 6.5e-9 with Eb = 1 at nb = 128, against Eb/R^3 = 8).
  const int nb = 128;
  MembraneForce F(make_membrane(circle(nb, 0, 0, 0.5), circle_reference(0.5), material("hookean", 0.0, 1.0)));
  Mat2 f;
  Vec T;
  F.compute(circle(nb, 0, 0, 0.5), f, T);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-8);
}

// ------------------------------------------------------------------ reference states

TEST(Reference, TheInitialShapeIsStressFreeToTheLastBit) {
  // reference = "initial", prestretch 1: lambda = 1 and kappa = kappa0 at every marker exactly, so
  // T, the bending moment and f are exactly zero, for every law, on shapes far from a circle. The energy,
// integrated between the knots, is zero to the splines' error (measured 7e-9 on the blob, 1.8e-7 on
// the 3:1 ellipse of 80 markers).
  for (const Mat2& X : {blob(96), ellipse(80, 0.3, 0.1, 0.9, 0.3)})
    for (const LawInfo& info : tension_laws()) {
      MembraneForce F(make_membrane(X, initial_reference(X), material(info.name, 2.0, 0.5)));
      Mat2 f;
      Vec T;
      F.compute(X, f, T);
      EXPECT_EQ(T.cwiseAbs().maxCoeff(), 0.0) << info.name;
      EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0) << info.name;
      EXPECT_LT(F.energy().total(), 4e-7) << info.name;
    }
}

TEST(Reference, APrestretchedInitialShapeCarriesItsUniformTension) {
  // The initial circle of radius 0.6 with prestretch 1.2 (reference radius 0.5): lambda = 1.2 at
  // every marker, T = T(1.2) for every law (Skalak: 2 (1.2)(0.44) = 1.056 Es).
  const Mat2 X = circle(128, 0, 0, 0.6);
  const Reference ref = initial_reference(X, 1.2);
  EXPECT_NEAR(ref.L0, 2 * kPi * 0.5, 5e-8);  // the spline through 128 points of a circle: 2 pi R (1 - 8.1e-9)
  for (const LawInfo& info : tension_laws()) {
    MembraneForce F(make_membrane(X, ref, material(info.name, 1.0, 0.0)));
    Mat2 f;
    Vec T;
    F.compute(X, f, T);
    std::vector<double> p;
    for (const LawParam& q : info.params) p.push_back(q.value);
    const double T_exact = info.make(1.0, p)->tension(1.2);
    EXPECT_NEAR(T.maxCoeff(), T_exact, 1e-12) << info.name;
    EXPECT_NEAR(T.minCoeff(), T_exact, 1e-12) << info.name;
  }
}

// ------------------------------------------------------------------ shape measures

TEST(ShapeMeasures, SplineMomentsRecoverAnInclinedEllipse) {
  // An ellipse of half-axes 0.8, 0.5 turned by 0.4 rad: the spline's second moments give L, B and
  // theta to 1e-7 at nb = 128 (measured 3e-9, 2e-9, 4e-10), D = 0.3/1.3; the polygon's moments are
  // biased by the isotropic factor of polygon.hpp (1e-4 here).
  const int nb = 128;
  Mat2 X = ellipse(nb, 0, 0, 0.8, 0.5);
  const double a = 0.4;
  for (int k = 0; k < nb; ++k) {
    const double x = X(k, 0), y = X(k, 1);
    X(k, 0) = 0.3 + std::cos(a) * x - std::sin(a) * y;
    X(k, 1) = -0.2 + std::sin(a) * x + std::cos(a) * y;
  }
  MembraneDiagnostics D(nb, 2 * kPi * 0.6);
  const MembraneShape s = D.measure(X);
  EXPECT_NEAR(s.moments.L, 0.8, 1e-7);
  EXPECT_NEAR(s.moments.B, 0.5, 1e-7);
  EXPECT_NEAR(s.moments.theta, a, 1e-7);
  EXPECT_NEAR(s.moments.deformation(), 0.3 / 1.3, 1e-7);
  EXPECT_NEAR(s.moments.centroid.x(), 0.3, 1e-9);
}

// ------------------------------------------------------------------ the stiff-force filter

TEST(StiffForce, KeepsTheTotalForceAndLeavesASoftMembraneAlone) {
  // Sum f~ = sum f (the change's net force is removed); a soft membrane at a small step (every
  // mode far from stiff, theta -> 0) gets f~ = f to 1e-6 relative (measured 2.4e-8).
  const int nb = 128;
  const Mat2 X = blob(nb);
  Mat2 U(nb, 2);
  for (int k = 0; k < nb; ++k) U.row(k) << 0.3 - 0.5 * X(k, 1), 0.1 + 0.5 * X(k, 0);  // translation + rotation
  StiffForceFilter filt(nb);
  for (double dt : {1e-5, 1e-2}) {
    MembraneForce F(make_membrane(X, circle_reference(0.5), material("hookean", 1.0, dt < 1e-3 ? 1e-4 : 10.0)));
    Mat2 f, ft;
    Vec T;
    F.compute(X, f, T);
    filt.apply(F, f, U, {1.0, 0.1, dt, 0.08, 0.056}, ft, false);
    EXPECT_LT((ft.colwise().sum() - f.colwise().sum()).norm(), 1e-12 * f.cwiseAbs().maxCoeff() * nb);
    if (dt < 1e-3) EXPECT_LT((ft - f).cwiseAbs().maxCoeff(), 1e-6 * f.cwiseAbs().maxCoeff());
  }
}

TEST(StiffForce, RigidMotionsDoNotChangeTheForce) {
  // A rigid translation and rotation of a circle are null modes of the filter's stiffness: f~ with U
  // rigid is f~ with U = 0 up to round-off (measured 6.7e-13, the cancellation of terms dt K U ~ 3e2;
  // a uniform strain rate of 0.5 changes f~ by 0.34).
  const int nb = 64;
  const Mat2 X = circle(nb, 0.2, 0.1, 0.5);
  MembraneForce F(make_membrane(X, circle_reference(0.5), material("hookean", 5.0, 2.0)));
  Mat2 f, f0, ft, U(nb, 2);
  Vec T;
  F.compute(X, f, T);
  for (int k = 0; k < nb; ++k) U.row(k) << 1.0 - 3.0 * (X(k, 1) - 0.1), -0.5 + 3.0 * (X(k, 0) - 0.2);
  StiffForceFilter filt(nb);
  filt.apply(F, f, Mat2::Zero(nb, 2), {1.0, 0.1, 1e-2, 0.08, 0.056}, f0, false);  // (no history: G = 0)
  filt.apply(F, f, U, {1.0, 0.1, 1e-2, 0.08, 0.056}, ft, false);
  EXPECT_LT((ft - f0).cwiseAbs().maxCoeff(), 1e-11);
  Mat2 V = U;
  V.col(0) += 0.5 * X.col(0);  // plus a strain: the filter sees it
  filt.apply(F, f, V, {1.0, 0.1, 1e-2, 0.08, 0.056}, ft, false);
  EXPECT_GT((ft - f0).cwiseAbs().maxCoeff(), 0.1);  // measured 0.34
}

TEST(StiffForce, WithTheResidualAMembraneHeldStillByTheFlowReceivesTheExplicitForce) {
  // A stiff blob held still (U = 0 at every step, as a steady shape in a flow that balances its
  // force): the model U^{n+1} = A U^n + B f~ alone expects it to move, so its first f~ is the
  // backward-Euler f / (1 + dt K B), far from f (measured max |f~ - f| / max |f| = 0.31); the
  // residual G learns the velocity the model misses and f~ returns to f, at the rate
  // 1 - w / (1 + dt K B) per step of a resolved mode, w = 0.2 min(1, 1 / (dt K B)) on the stiff
  // modes of this viscous fluid (A < 0.2: the residual's lagged gain), so slowly on the stiffest
  // (measured 1.3e-2 after 200 steps, 4.7e-3 after 400: a factor 0.35; with the full weight 0.2 on
  // every mode it was 6.0e-4 and 3.8e-5). Kernels of width 1e-3 (every mode resolved). Its
  // state goes through state()/set_state() unchanged.
  const int nb = 64;
  const Mat2 X = blob(nb);
  MembraneForce F(make_membrane(X, circle_reference(0.5), material("hookean", 1.0, 0.1)));
  Mat2 f, ft;
  Vec T;
  F.compute(X, f, T);
  const Mat2 U = Mat2::Zero(nb, 2);
  const StiffFluid fl{1.0, 1.0, 1e-2, 1e-3, 1e-3};
  StiffForceFilter filt(nb, true), plain(nb);
  EXPECT_EQ(filt.state().size(), 0);
  const double fmax = f.cwiseAbs().maxCoeff();
  filt.apply(F, f, U, fl, ft);
  EXPECT_GT((ft - f).cwiseAbs().maxCoeff(), 0.2 * fmax);
  for (int n = 1; n < 200; ++n) filt.apply(F, f, U, fl, ft);
  const double e200 = (ft - f).cwiseAbs().maxCoeff() / fmax;
  for (int n = 200; n < 400; ++n) filt.apply(F, f, U, fl, ft);
  const double e400 = (ft - f).cwiseAbs().maxCoeff() / fmax;
  Mat2 fp;
  for (int n = 0; n < 400; ++n) plain.apply(F, f, U, fl, fp);  // without the residual: the bias stays
  EXPECT_GT((fp - f).cwiseAbs().maxCoeff(), 0.2 * fmax);
  EXPECT_LT(e400, 1e-2);
  EXPECT_LT(e400, 0.5 * e200);  // converging geometrically, not stuck at a bias
  StiffForceFilter copy(nb, true);
  copy.set_state(filt.state());
  Mat2 a, b;
  filt.apply(F, f, U, fl, a);
  copy.apply(F, f, U, fl, b);
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(copy.set_state(Eigen::MatrixXd::Zero(3, 12)), std::invalid_argument);
}

// ------------------------------------------------------------------ B-spline interpolation

TEST(BSplineInterpolation, ReproducesQuadraticStreamFunctionsExactly) {
  // sum_i B(x - x_i) = 1, sum_i x_i B = x and sum_i x_i^2 B = x^2 + dx^2/3 on the lattice, so the
  // derivatives of psi = a x^2 + b x y + c y^2 + d x + e y are exact: U = (b x + 2c y + e, -(2a x + b y + d)),
  // dU its gradient (measured errors 4e-15 and 2e-13).
  Domain d;
  d.x0 = -1, d.x1 = 1, d.y0 = -1, d.y1 = 1;
  d.periodic_x = d.periodic_y = true;
  const Lattice L = make_lattice(d, 40, 40);
  CellGrid grid(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1), true, true, L.dx);
  grid.use_lattice(L);
  const double a = 0.3, b = -0.7, c = 0.2, dd = 1.1, e = -0.4;
  Vec psi(L.size());
  for (int i = 0; i < L.size(); ++i) {
    const double x = L.x(i, 0), y = L.x(i, 1);
    psi[i] = a * x * x + b * x * y + c * y * y + dd * x + e * y;
  }
  Mat2 X(50, 2), U(50, 2);
  for (int k = 0; k < 50; ++k) X.row(k) << -0.5 + 0.02 * k + 0.001 * k * k / 7, 0.3 * std::sin(0.37 * k);
  Jacobians J;
  interpolate_curl_bspline(grid, L.dx, L.dy, psi, Eigen::Vector2d::Zero(), X, U, &J);
  for (int k = 0; k < 50; ++k) {
    const double x = X(k, 0), y = X(k, 1);
    EXPECT_NEAR(U(k, 0), b * x + 2 * c * y + e, 1e-12);
    EXPECT_NEAR(U(k, 1), -(2 * a * x + b * y + dd), 1e-12);
    EXPECT_NEAR(J(k, 0), b, 1e-10);
    EXPECT_NEAR(J(k, 1), 2 * c, 1e-10);
    EXPECT_NEAR(J(k, 2), -2 * a, 1e-10);
    EXPECT_NEAR(J(k, 0) + J(k, 3), 0.0, 1e-12);  // divergence-free
  }
}

// ------------------------------------------------------------------ in a run

namespace {
nlohmann::json run_stiff(const std::string& dir, std::vector<std::string> sets) {
  std::vector<std::string> all{"grid.nx=32", "grid.ny=32", "membrane.nb=48", "time.dt=1e-3", "time.end=0.5",
                               "membrane.Eb=10", "output.interval=0"};
  all.insert(all.end(), sets.begin(), sets.end());
  Scene s = load_scene(sphib_test::kOscillation, all);
  RunOptions o;
  o.out_dir = dir;
  return run_scene(s, o);
}
}  // namespace

TEST(StiffForce, StiffBendingBlowsUpExplicitlyAndRunsSemiImplicitly) {
  // The oscillating membrane with Eb = 10 at 32 x 32, 48 markers, dt = 1e-3: the explicit force
  // blows up (measured: the energy guard at step 99), the semi-implicit one runs to t = 0.5 with the
  // area error of a ringing membrane (measured 1.7e-5; explicit at dt = 2e-4: 3.0e-5).
  const std::filesystem::path d = std::filesystem::temp_directory_path() / "sphib_stiff";
  std::filesystem::remove_all(d);
  EXPECT_THROW(run_stiff((d / "explicit").string(), {"membrane.semi_implicit=false"}), std::exception);
  const nlohmann::json j = run_stiff((d / "semi").string(), {"membrane.semi_implicit=true"});
  EXPECT_EQ(j["stop_reason"], "end time");
  EXPECT_LT(std::abs(j["area_relative_error"].get<double>()), 5e-5);
  std::filesystem::remove_all(d);
}

TEST(StiffForce, ARestartWithBendingContinuesBitForBit) {
  // The filter's state is f^n, U^n and the markers, and with membrane.stiff_residual its history
  // (U^{n-1}, f~^{n-1} and the smoothed residual G per mode): a checkpoint holds them, so a restart
  // with bending and the semi-implicit force continues the straight run to the last bit, with and
  // without the residual (without its history in the checkpoint, G would restart from zero).
  for (const bool residual : {false, true}) {
    const std::filesystem::path d = sphib_test::temp_dir(residual ? "stiff_restart_residual" : "stiff_restart");
    const std::vector<std::string> m{"membrane.Eb=0.5", "membrane.semi_implicit=true",
                                     residual ? "membrane.stiff_residual=true" : "membrane.stiff_residual=false"};
    auto with = [&](std::vector<std::string> v) {
      v.insert(v.end(), m.begin(), m.end());
      return v;
    };
    const nlohmann::json straight = run_stiff((d / "a").string(), with({"time.max_steps=40"}));
    run_stiff((d / "b").string(), with({"time.max_steps=15"}));
    std::vector<std::string> all{"grid.nx=32", "grid.ny=32", "membrane.nb=48", "time.dt=1e-3", "time.end=0.5",
                                 "membrane.Eb=10", "output.interval=0", "time.max_steps=40"};
    all.insert(all.end(), m.begin(), m.end());
    Scene s = load_scene(sphib_test::kOscillation, all);
    RunOptions o;
    o.out_dir = (d / "c").string();
    o.restart = (d / "b" / "checkpoint.h5").string();
    const nlohmann::json restarted = run_scene(s, o);
    EXPECT_EQ(restarted["steps"], 40);
    for (const char* k : {"time", "rx", "ry", "area", "kinetic_energy", "elastic_energy", "bending_energy", "deformation"})
      EXPECT_EQ(straight[k].get<double>(), restarted[k].get<double>()) << k << (residual ? " (stiff_residual)" : "");
    std::filesystem::remove_all(d);
  }
}

TEST(StiffForce, TheResidualsGainKeepsItStableWhereTheDefaultIs) {
  // Three rows of the stability map (bench/stability_map --parts B --residual: 32 x 32, 64
  // markers) at a step where the default filter (G = 0) is stable and the residual used to blow up,
  // each held by one ingredient of the residual's gain (coupling/stiff_force.cpp). Measured, with
  // membrane.stiff_residual: all three run to their last step, and
  //   Skalak Es = 1e4, mu = 0.1, dt = 1e-4, 600 steps: without the layer floor (Bt from
  //     sqrt(pi nu dt) < h) blow-up at step ~440;
  //   Skalak Es = 1e3, mu = 0.1, dt = 4e-3, 250 steps: without the lag (full weight on stiff modes)
  //     blow-up at step ~160;
  //   Hookean T0 = 1, Eb = 1, mu = 10, dt = 0.3, 150 steps: without the lag blow-up at step ~50,
  //     without the cap at step ~60 (a marker moving a lattice spacing per step).
  const std::filesystem::path d = sphib_test::temp_dir("stiff_residual_gain");
  struct Row {
    std::string scene, law;
    double modulus, Eb, mu, dt;
    int steps;
  };
  const std::string laws = std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_laws.toml";
  for (const Row& r : {Row{laws, "skalak", 1e4, 0, 0.1, 1e-4, 600}, Row{laws, "skalak", 1e3, 0, 0.1, 4e-3, 250},
                       Row{sphib_test::kOscillation, "hookean", 1, 1, 10, 0.3, 150}})
    for (const bool residual : {false, true}) {
      std::vector<std::string> sets{"grid.nx=32", "grid.ny=32", "membrane.nb=64", "kernel.h_over_dx=1.2",
                                    "membrane.h_star_over_h=1.4", "fluid.mu=" + std::to_string(r.mu),
                                    "time.dt=" + std::to_string(r.dt), "time.max_steps=" + std::to_string(r.steps),
                                    "time.end=" + std::to_string(r.steps * r.dt * (1 + 1e-9)), "output.interval=0",
                                    "membrane.semi_implicit=true",
                                    std::string("membrane.stiff_residual=") + (residual ? "true" : "false")};
      if (r.law == "hookean") {
        sets.push_back("membrane.T0=" + std::to_string(r.modulus));
        sets.push_back("membrane.Eb=" + std::to_string(r.Eb));
      } else {
        sets.push_back("membrane.law=" + r.law);
        sets.push_back("membrane.Es=" + std::to_string(r.modulus));
      }
      Scene s = load_scene(r.scene, sets);
      RunOptions o;
      o.out_dir = (d / "run").string();
      const std::string what = r.law + " " + std::to_string(r.modulus) + " mu " + std::to_string(r.mu) +
                               (residual ? " (stiff_residual)" : " (default)");
      nlohmann::json j;
      ASSERT_NO_THROW(j = run_scene(s, o)) << what;
      EXPECT_EQ(j["steps"], r.steps) << what;
    }
  std::filesystem::remove_all(d);
}

TEST(StiffForce, ItsDepartureFromTheExplicitForceFallsFasterThanTheStep) {
  // The semi-implicit force is the explicit one plus a correction that vanishes with dt
  // (coupling/stiff_force.hpp), so at a step both can take, their runs part by less than the
  // scheme's own time error and the gap closes faster than dt. Relaxation of a slightly elliptic
  // membrane with bending only (Eb = 1, T0 = 0, mu = 1, Stokes flow, 32 x 32, 64 markers) to
  // t = 0.2, where the explicit force is stable up to dt ~ 1e-2. Measured at dt = 1e-3, 5e-4,
  // 2.5e-4: rx semi-implicit minus explicit 7.83e-7, 1.60e-7, 3.08e-8 (halving dt divides it by
  // 4.9 and 5.2: order ~2.3), while the explicit run's own rx error against dt = 1e-5 is 8.0e-5,
  // 4.0e-5, 1.9e-5 (the coupled scheme is first order in dt). The test
  // asks a ratio of at least 3.5 (an O(dt) filter error gives 2) and a gap below a tenth of the
  // explicit run's change from dt to dt/2 (measured 0.019).
  const std::filesystem::path d = sphib_test::temp_dir("stiff_order");
  auto rx = [&](double dt, bool semi) {
    std::vector<std::string> sets{"grid.nx=32", "grid.ny=32", "membrane.nb=64", "time.end=0.2", "membrane.Eb=1",
                                  "membrane.T0=0", "fluid.mu=1", "fluid.convection=false", "output.interval=0",
                                  "membrane.rx=0.55", "membrane.ry=0.4545", "time.dt=" + std::to_string(dt),
                                  semi ? "membrane.semi_implicit=true" : "membrane.semi_implicit=false"};
    Scene s = load_scene(sphib_test::kOscillation, sets);
    RunOptions o;
    o.out_dir = (d / ((semi ? "s" : "e") + std::to_string(dt))).string();
    const nlohmann::json j = run_scene(s, o);
    EXPECT_EQ(j["stop_reason"], "end time");
    return j["rx"].get<double>();
  };
  const double dts[3] = {1e-3, 5e-4, 2.5e-4};
  double gap[3], explicit_rx[3];
  for (int k = 0; k < 3; ++k) {
    explicit_rx[k] = rx(dts[k], false);
    gap[k] = std::abs(rx(dts[k], true) - explicit_rx[k]);
  }
  EXPECT_GT(gap[0] / gap[1], 3.5);
  EXPECT_GT(gap[1] / gap[2], 3.5);
  EXPECT_LT(gap[0], 0.1 * std::abs(explicit_rx[0] - explicit_rx[1]));
  std::filesystem::remove_all(d);
}
// ------------------------------------------------------------------ scene keys

TEST(MembraneKeys, TheMaterialKeysAreReadAndCheckedByName) {
  const std::string mem = std::string(kMinimal) + "[membrane]\nr0 = 0.2\n";
  const Scene s = parse_scene(mem + "law = \"skalak\"\nEs = 2.0\nC = 3.0\nEb = 0.05\n", "scene.toml");
  const Material& m = s.sim.membranes[0].membrane.mat;
  EXPECT_EQ(m.law, "skalak");
  EXPECT_EQ(m.Es, 2.0);
  ASSERT_EQ(m.params.size(), 1u);
  EXPECT_EQ(m.params[0], 3.0);
  EXPECT_EQ(m.Eb, 0.05);
  EXPECT_TRUE(s.sim.membranes[0].semi_implicit);  // with bending, by default
  const Scene h = parse_scene(mem + "T0 = 4.0\n", "scene.toml");
  EXPECT_EQ(h.sim.membranes[0].membrane.mat.Es, 4.0);
  EXPECT_FALSE(h.sim.membranes[0].semi_implicit);
  for (const auto& [extra, key] : std::vector<std::pair<std::string, std::string>>{
           {"T0 = 1.0\nEs = 1.0\n", "membrane.Es"},
           {"law = \"skalak\"\nT0 = 1.0\n", "membrane.T0"},
           {"T0 = 1.0\nC = 2.0\n", "membrane.C"},
           {"T0 = 1.0\nkappa0 = 2.0\n", "membrane.kappa0"},
           {"T0 = 1.0\nprestretch = 1.1\n", "membrane.prestretch"},
           {"law = \"mooney\"\nEs = 1.0\n", "membrane.law"},
           {"law = \"skalak\"\nEs = 1.0\nC = -1\n", "membrane.C"},
           {"T0 = 1.0\nEb = -1.0\n", "membrane.Eb"},
           {"T0 = 1.0\nstiff_residual = true\n", "membrane.stiff_residual"},  // needs semi_implicit
           {"law = \"neo_hookean\"\n", "membrane.Es"}}) {
    const std::string msg = refusal(mem + extra);
    EXPECT_NE(msg.find(key), std::string::npos) << extra << " -> " << msg;
  }
  // reference = "initial": no r0 (the initial shape is the reference), radius required for a circle
  const std::string init = std::string(kMinimal) + "[membrane]\nreference = \"initial\"\nT0 = 1.0\n";
  EXPECT_NE(refusal(init + "r0 = 0.2\nradius = 0.2\n").find("membrane.r0"), std::string::npos);
  const Scene i = parse_scene(init + "radius = 0.25\nprestretch = 1.25\n", "scene.toml");
  EXPECT_NEAR(i.sim.membranes[0].membrane.L0(), 2 * kPi * 0.2, 5e-8);  // (1 - 8.1e-9) as above
}

// ------------------------------------------------------------------ the tension's cutoff (inextensible)

TEST(TensionCutoff, RemovesTheTensionsShortModesOnlyAndKeepsTheTotalForce) {
  // Material::tension_cutoff: the tension T(lambda) loses its Fourier modes (in the label) shorter
  // than the cutoff along the current length, and keeps the others to round-off. A circle of
  // radius 0.5 (length pi) with 64 markers displaced tangentially in modes 3 and 27: with the
  // cutoff pi/10.5 the kept modes are m <= 10. Measured, relative to T's largest mode: modes <= 10
  // changed by 3.1e-16, modes > 10 left at 1.7e-15 (mode 27 was 0.85 of it); the net force 2.8e-16
  // of the largest f. Tolerances 1e-13.
  const int nb = 64;
  const double r0 = 0.5;
  Mat2 X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2 * kPi * k / nb, b = r0 * (0.02 * std::sin(3 * th) + 0.004 * std::cos(27 * th));
    X.row(k) << r0 * std::cos(th + b / r0), r0 * std::sin(th + b / r0);
  }
  Material raw = material("inextensible", 1000.0, 0.0);
  Material cut = raw;
  cut.tension_cutoff = kPi / 10.5;
  MembraneForce Fr(make_membrane(X, circle_reference(r0), raw)), Fc(make_membrane(X, circle_reference(r0), cut));
  Mat2 fr, fc;
  Vec Tr, Tc;
  Fr.compute(X, fr, Tr);
  Fc.compute(X, fc, Tc);
  auto mode = [&](const Vec& T, int m) {
    std::complex<double> s = 0.0;
    for (int k = 0; k < nb; ++k) s += T[k] * std::exp(std::complex<double>(0.0, -2 * kPi * m * k / nb));
    return s;
  };
  double top = 0.0;
  for (int m = 0; m <= nb / 2; ++m) top = std::max(top, std::abs(mode(Tr, m)));
  ASSERT_GT(std::abs(mode(Tr, 27)), 0.1 * top);  // the short mode is there without the cutoff
  for (int m = 0; m <= nb / 2; ++m) {
    if (m <= 10) EXPECT_LT(std::abs(mode(Tc, m) - mode(Tr, m)), 1e-13 * top) << "mode " << m;
    else EXPECT_LT(std::abs(mode(Tc, m)), 1e-13 * top) << "mode " << m;
  }
  // the force is still the derivative of a periodic spline: no net force
  EXPECT_LT(fc.colwise().sum().norm(), 1e-13 * fc.cwiseAbs().maxCoeff());
  // without a short mode to remove (a cutoff below the markers' shortest wavelength) nothing changes
  Material fine = raw;
  fine.tension_cutoff = 0.5 * kPi / nb;
  MembraneForce Ff(make_membrane(X, circle_reference(r0), fine));
  Mat2 ff;
  Vec Tf;
  Ff.compute(X, ff, Tf);
  EXPECT_EQ((ff - fr).cwiseAbs().maxCoeff(), 0.0);
  Material bad = raw;
  bad.tension_cutoff = -1.0;
  EXPECT_THROW(make_membrane(X, circle_reference(r0), bad), std::invalid_argument);
}

TEST(TensionCutoff, EllipseByArclengthIsUniformInItsArclength) {
  // shapes.hpp's ellipse_by_arclength: the arcs between consecutive markers, integrated
  // independently here (Simpson, 2000 intervals per arc), are L/nb to 1e-12 of L/nb (measured
  // 5.1e-14).
  const double rx = 0.75, ry = 0.5;
  const int nb = 128;
  const Mat2 X = ellipse_by_arclength(nb, 0.1, -0.2, rx, ry);
  auto angle = [&](int k) {
    double t = std::atan2((X(k % nb, 1) + 0.2) / ry, (X(k % nb, 0) - 0.1) / rx);
    if (t < 0) t += 2 * kPi;
    return k == nb ? 2 * kPi : t;
  };
  auto arc = [&](double a, double b) {
    const int n = 2000;
    double s = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double t = a + (b - a) * i / n, w = i == 0 || i == n ? 1 : (i % 2 ? 4 : 2);
      s += w * std::hypot(rx * std::sin(t), ry * std::cos(t));
    }
    return s * (b - a) / (3 * n);
  };
  std::vector<double> arcs(nb);
  double L = 0.0;
  for (int k = 0; k < nb; ++k) L += arcs[k] = arc(angle(k), angle(k + 1));
  for (int k = 0; k < nb; ++k) EXPECT_NEAR(arcs[k], L / nb, 1e-12 * L / nb) << k;
  EXPECT_NEAR(X(0, 0), 0.1 + rx, 1e-15);
  EXPECT_THROW(ellipse_by_arclength(nb, 0, 0, rx, -1.0), std::invalid_argument);
}

namespace {
// The column `name` of a run's diagnostics.csv against its t column.
std::vector<std::pair<double, double>> diagnostics_column(const std::filesystem::path& dir, const std::string& name) {
  std::istringstream csv(sphib_test::slurp(dir / "diagnostics.csv"));
  std::string line, cell;
  std::getline(csv, line);
  std::istringstream head(line);
  int col = -1, t = -1;
  for (int c = 0; std::getline(head, cell, ','); ++c) {
    if (cell == name) col = c;
    if (cell == "t") t = c;
  }
  std::vector<std::pair<double, double>> rows;
  if (col < 0 || t < 0) return rows;
  while (std::getline(csv, line)) {
    std::istringstream r(line);
    std::vector<double> v;
    while (std::getline(r, cell, ',')) v.push_back(std::stod(cell));
    rows.emplace_back(v[t], v[col]);
  }
  return rows;
}
}  // namespace

TEST(TensionCutoff, TheStiffPenaltysUnresolvedModesGrowWithoutItAndDecayWithIt) {
  // The oscillating membrane's scene (64 x 64, 128 markers, dt = 1e-4) with the inextensible
  // penalty Es = 1e4 and Eb = 0.01: the stretching modes shorter than 2 dx (m > 42 of 64) are
  // unstable with the penalty's full tension (a spurious flow grows from t ~ 0.9) and not with the
  // default tension_cutoff (2 dx). Measured, max_speed at t = 1.25 over t = 0.875: 1.68 without the
  // cutoff (0.129 / 0.0767), 0.42 with it (0.0313 / 0.0748); the test asks > 1.3 and < 0.7.
  const std::filesystem::path d = sphib_test::temp_dir("tension_cutoff_growth");
  auto growth = [&](bool cut) {
    std::vector<std::string> sets{"membrane.law=inextensible", "membrane.Es=1e4", "membrane.r0=0.6312658",
                                  "membrane.Eb=0.01", "output.interval=0", "time.end=1.25",
                                  "output.diagnostics_every=1250", "observe.exact=none"};
    if (!cut) sets.push_back("membrane.tension_cutoff=0");
    Scene s = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_laws.toml", sets);
    EXPECT_EQ(s.sim.membranes[0].membrane.mat.tension_cutoff, cut ? 2 * 3.0 / 64 : 0.0);
    RunOptions o;
    o.out_dir = (d / (cut ? "cut" : "raw")).string();
    const nlohmann::json j = run_scene(s, o);
    EXPECT_EQ(j["stop_reason"], "end time");
    double early = NAN, late = NAN;
    for (const auto& [t, v] : diagnostics_column(o.out_dir, "max_speed")) {
      if (std::abs(t - 0.875) < 1e-6) early = v;
      if (std::abs(t - 1.25) < 1e-6) late = v;
    }
    return late / early;
  };
  EXPECT_GT(growth(false), 1.3);
  EXPECT_LT(growth(true), 0.7);
  std::filesystem::remove_all(d);
}

TEST(TensionCutoff, TheKeysDefaultsAndRefusals) {
  // membrane.tension_cutoff: 2 max(dx, dy) for law inextensible by default, 0 for the other laws,
  // as given otherwise; membrane.spacing: ellipses only.
  const std::string mem = std::string(kMinimal) + "[membrane]\nr0 = 0.2\n";
  const Scene a = parse_scene(mem + "law = \"inextensible\"\nEs = 100.0\n", "scene.toml");
  const Scene b = parse_scene(mem + "law = \"skalak\"\nEs = 1.0\n", "scene.toml");
  const Scene c = parse_scene(mem + "law = \"skalak\"\nEs = 1.0\ntension_cutoff = 0.3\n", "scene.toml");
  const FluidParams& f = a.sim.fluid;
  const double dx = (f.domain.x1 - f.domain.x0) / f.nx, dy = (f.domain.y1 - f.domain.y0) / f.ny;
  EXPECT_EQ(a.sim.membranes[0].membrane.mat.tension_cutoff, 2 * std::max(dx, dy));
  EXPECT_EQ(b.sim.membranes[0].membrane.mat.tension_cutoff, 0.0);
  EXPECT_EQ(c.sim.membranes[0].membrane.mat.tension_cutoff, 0.3);
  const std::string ell = std::string(kMinimal) + "[membrane]\nT0 = 1.0\nshape = \"ellipse\"\nrx = 0.25\nry = 0.15\nr0 = 0.2\n";
  const Scene e = parse_scene(ell + "spacing = \"arclength\"\n", "scene.toml");
  const Mat2& X = e.sim.membranes[0].membrane.X;
  const Mat2 E = ellipse_by_arclength(static_cast<int>(X.rows()), 0, 0, 0.25, 0.15);
  EXPECT_LT(((X.rowwise() - X.colwise().mean()) - (E.rowwise() - E.colwise().mean())).cwiseAbs().maxCoeff(), 1e-14);
  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {mem + "T0 = 1.0\ntension_cutoff = -1.0\n", "membrane.tension_cutoff"},
           {mem + "T0 = 1.0\nspacing = \"arclength\"\n", "membrane.spacing"},
           {ell + "spacing = \"chord\"\n", "membrane.spacing"}}) {
    const std::string msg = refusal(text);
    EXPECT_NE(msg.find(key), std::string::npos) << text << " -> " << msg;
  }
}
