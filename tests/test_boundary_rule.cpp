// The boundary rule (fluid/common/boundary_rule.hpp): the parities each kind of side implies, and
// the image construction, the gauge and the fast solver taking them from it.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "fluid/algebra/gauge.hpp"
#include "fluid/common/boundary.hpp"
#include "fluid/common/boundary_rule.hpp"

using namespace sphib;

// The table of Section 3.3: a no-slip wall's velocity images are odd (Eq. 42), phi's even (Eq. 9),
// a stream function's odd; periodic and open sides make no images.
TEST(BoundaryRule, ParitiesOfEachKind) {
  EXPECT_EQ(image_parity(SideKind::NoSlip, Field::VelocityNormal), -1);
  EXPECT_EQ(image_parity(SideKind::NoSlip, Field::VelocityTangential), -1);
  EXPECT_EQ(image_parity(SideKind::NoSlip, Field::Scalar), +1);
  EXPECT_EQ(image_parity(SideKind::NoSlip, Field::Stream), -1);
  EXPECT_EQ(velocity_parity(SideKind::NoSlip), -1);
  // inflow: velocity Dirichlet (odd), phi Neumann (even); outflow: velocity zero-gradient (even), phi = 0 (odd)
  EXPECT_EQ(velocity_parity(SideKind::Inflow), -1);
  EXPECT_EQ(image_parity(SideKind::Inflow, Field::Scalar), +1);
  EXPECT_EQ(velocity_parity(SideKind::Outflow), +1);
  EXPECT_EQ(image_parity(SideKind::Outflow, Field::Scalar), -1);
  // the stream function takes the velocity's parity: prescribed (odd) through an inflow, dpsi/dn = 0
  // (even) across an outflow
  for (SideKind k : {SideKind::Inflow, SideKind::Outflow}) {
    EXPECT_TRUE(makes_images(k));
    EXPECT_FALSE(is_wall_kind(k));
    EXPECT_EQ(image_parity(k, Field::Stream), velocity_parity(k));
  }
  // free-slip: the normal velocity odd, the tangential even (no shared parity), phi even, psi odd
  EXPECT_EQ(image_parity(SideKind::FreeSlip, Field::VelocityNormal), -1);
  EXPECT_EQ(image_parity(SideKind::FreeSlip, Field::VelocityTangential), +1);
  EXPECT_EQ(image_parity(SideKind::FreeSlip, Field::Scalar), +1);
  EXPECT_EQ(image_parity(SideKind::FreeSlip, Field::Stream), -1);
  EXPECT_EQ(velocity_parity(SideKind::FreeSlip), 0);
  EXPECT_TRUE(makes_images(SideKind::FreeSlip));
  // the velocity operators' images take the stream function's parity (make_images): the normal
  // component's at every kind that makes images
  for (SideKind k : {SideKind::NoSlip, SideKind::Inflow, SideKind::Outflow, SideKind::FreeSlip})
    EXPECT_EQ(image_parity(k, Field::Stream), image_parity(k, Field::VelocityNormal)) << side_kind_name(k);
  EXPECT_EQ(profile_integral(InflowProfile::Uniform, 0.25), 0.25);
  EXPECT_DOUBLE_EQ(profile_integral(InflowProfile::Parabolic, 1.0), 2.0 / 3.0);  // int_0^1 4 t (1 - t) dt
  EXPECT_DOUBLE_EQ(profile_integral(InflowProfile::Parabolic, 0.5), 1.0 / 3.0);  // half the flux by symmetry
  for (SideKind k : {SideKind::Periodic, SideKind::Open})
    for (Field f : {Field::VelocityNormal, Field::VelocityTangential, Field::Scalar, Field::Stream})
      EXPECT_EQ(image_parity(k, f), 0) << side_kind_name(k);
  EXPECT_TRUE(is_wall_kind(SideKind::NoSlip));
  EXPECT_FALSE(is_wall_kind(SideKind::Open));
  EXPECT_FALSE(is_wall_kind(SideKind::Periodic));
  EXPECT_EQ(image_prescribed(-1, 0.75), 1.5);  // 2 U_wall
  EXPECT_EQ(image_prescribed(+1, 0.75), 0.0);
}

// Domain's accessors follow the sides' kinds: a periodic axis's sides are periodic whatever
// `bounded` holds.
TEST(BoundaryRule, DomainKindsAndAccessors) {
  Domain d;
  d.periodic_x = true;
  d.bounded[Left] = SideKind::Open;  // ignored: x is periodic
  d.bounded[Top] = SideKind::Open;
  EXPECT_EQ(d.kind(Left), SideKind::Periodic);
  EXPECT_EQ(d.kind(Bottom), SideKind::NoSlip);
  EXPECT_EQ(d.kind(Top), SideKind::Open);
  EXPECT_TRUE(d.is_wall(Bottom));
  EXPECT_FALSE(d.is_wall(Top));
  EXPECT_TRUE(d.is_open(Top));
  EXPECT_TRUE(d.any_open());
  EXPECT_EQ(d.parity(Bottom, Field::Scalar), 1);
  EXPECT_EQ(d.parity(Top, Field::Scalar), 0);
}

// The images carry the rule's parities: single reflections the wall's, corners the product; the
// offsets are the prescribed parts (1 - parity) u_w.
TEST(BoundaryRule, ImagesCarryTheRulesParities) {
  Domain d;
  d.periodic_x = d.periodic_y = false;
  d.wall_velocity[Top] = Eigen::Vector2d(1.25, 0.0);
  const Lattice L = make_lattice(d, 12, 12);
  const Images im = make_images(L, 2.0 * L.dx);
  Mat2 c(im.size(), 2);
  image_velocity_offsets(im, d, nullptr, 0.0, c);
  int top = 0;
  for (int k = 0; k < im.size(); ++k) {
    const int w = im.wall[k];
    if (w < 0) {
      EXPECT_EQ(im.v_sign[k], 1.0);
      EXPECT_EQ(im.s_sign[k], 1.0);
      EXPECT_EQ(c(k, 0), 0.0);
      continue;
    }
    EXPECT_EQ(im.v_sign[k], image_parity(SideKind::NoSlip, Field::VelocityNormal));
    EXPECT_EQ(im.s_sign[k], image_parity(SideKind::NoSlip, Field::Scalar));
    EXPECT_EQ(c(k, 0), w == Top ? 2.5 : 0.0);
    top += w == Top;
  }
  EXPECT_GT(top, 0);
  // an open side has no images: refused, naming the side
  d.bounded[Left] = SideKind::Open;
  try {
    make_images(make_lattice(d, 12, 12), 2.0 * L.dx);
    ADD_FAILURE() << "images across an open side";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("left side is open"), std::string::npos) << e.what();
  }
}

// An inflow's images carry 2 u_in(y) - u with the parabolic profile at the image's height, an
// outflow's u (no prescribed part), phi odd there; the corner of an outflow and a wall at rest
// carries -u with no offset.
TEST(BoundaryRule, InflowAndOutflowImages) {
  Domain d;
  d.periodic_x = d.periodic_y = false;
  d.bounded[Left] = SideKind::Inflow;
  d.bounded[Right] = SideKind::Outflow;
  d.inflow_profile = InflowProfile::Parabolic;
  d.wall_velocity[Left] = Eigen::Vector2d(2.0, 0.0);
  const Lattice L = make_lattice(d, 16, 8);
  const Images im = make_images(L, 2.0 * L.dx);
  Mat2 c(im.size(), 2);
  image_velocity_offsets(im, d, nullptr, 0.0, c);
  int left = 0, right = 0, corner = 0;
  for (int k = 0; k < im.size(); ++k) {
    const double y = im.x(k, 1);
    if (im.wall[k] == Left) {
      ++left;
      EXPECT_EQ(im.v_sign[k], -1.0);
      EXPECT_EQ(im.s_sign[k], 1.0);
      EXPECT_NEAR(c(k, 0), 2.0 * 2.0 * 4.0 * y * (1.0 - y), 1e-14);
      EXPECT_EQ(c(k, 1), 0.0);
    } else if (im.wall[k] == Right) {
      ++right;
      EXPECT_EQ(im.v_sign[k], 1.0);
      EXPECT_EQ(im.s_sign[k], -1.0);
      EXPECT_EQ(c(k, 0), 0.0);
    } else if (im.wall[k] < 0 && im.x(k, 0) > d.x1) {  // outflow-wall corner
      EXPECT_EQ(im.v_sign[k], -1.0);
      EXPECT_EQ(im.s_sign[k], -1.0);
      EXPECT_EQ(c(k, 0), 0.0);
    } else if (im.wall[k] < 0) {  // inflow-wall corner: across the inflow at the parent, then the wall
      ++corner;
      const double yp = y < d.y0 ? 2.0 * d.y0 - y : 2.0 * d.y1 - y;  // the parent's height
      EXPECT_EQ(im.v_sign[k], 1.0);
      EXPECT_EQ(im.s_sign[k], 1.0);
      EXPECT_NEAR(c(k, 0), -(1.0 - (-1.0)) * 2.0 * 4.0 * yp * (1.0 - yp), 1e-14);  // p_B (1 - p_A) g_A
      EXPECT_EQ(c(k, 1), 0.0);
    }
  }
  EXPECT_GT(left, 0);
  EXPECT_GT(right, 0);
  EXPECT_GT(corner, 0);
}

// The composition of two reflections: f'' = p_B (p_A f + (1 - p_A) g_A) + (1 - p_B) g_B.
TEST(BoundaryRule, CornerComposesTheTwoReflections) {
  for (int pA : {-1, 1})
    for (int pB : {-1, 1}) {
      const double f = 0.3, gA = pA < 0 ? 0.7 : 0.0, gB = pB < 0 ? -1.1 : 0.0;
      const double once = pA * f + image_prescribed(pA, gA), twice = pB * once + image_prescribed(pB, gB);
      EXPECT_DOUBLE_EQ(pA * pB * f + corner_prescribed(pA, gA, pB, gB), twice);
    }
  EXPECT_EQ(corner_prescribed(-1, 0.0, -1, 0.0), 0.0);  // two walls at rest
}

// The solvers' log lines name the parities the rule gives: the stream function's images are even at
// an outflow.
TEST(BoundaryRule, LogLinesNameTheParities) {
  Domain d;
  d.periodic_x = d.periodic_y = false;
  EXPECT_EQ(image_parities_text(d, Field::Stream), "odd images");
  EXPECT_EQ(image_parities_text(d, Field::Scalar), "even images");
  d.bounded[Left] = SideKind::Inflow;
  d.bounded[Right] = SideKind::Outflow;
  EXPECT_EQ(image_parities_text(d, Field::Stream), "odd images at the left, bottom and top sides, even at the right");
}

// The gauge's null vectors follow the rule's parity across the walls: on a closed box G^T G of phi
// (even images) keeps the constant, of a stream function (odd) the alternating (-1)^{i_x + i_y}; a
// wall facing an open side has no common parity: refused.
TEST(BoundaryRule, GaugeTakesTheParitiesFromTheRule) {
  Domain d;
  d.periodic_x = d.periodic_y = false;
  const Lattice L = make_lattice(d, 6, 6);
  Vec one = Vec::Ones(L.size()), alt(L.size());
  for (int i = 0; i < L.size(); ++i) alt[i] = ((i % 6 + i / 6) & 1) ? -1.0 : 1.0;
  const Gauge phi(L, NullSpace::GradientScalar), psi(L, NullSpace::GradientStream);
  ASSERT_EQ(phi.dimension(), 1);
  ASSERT_EQ(psi.dimension(), 1);
  Vec a = one, b = alt;
  phi.project(a);
  psi.project(b);
  EXPECT_LT(a.cwiseAbs().maxCoeff(), 1e-14);  // the constant is phi's null vector
  EXPECT_LT(b.cwiseAbs().maxCoeff(), 1e-14);  // the alternating one the stream function's
  Vec c = alt;
  phi.project(c);
  EXPECT_EQ((c - alt).cwiseAbs().maxCoeff(), 0.0);
  Domain open = d;
  open.bounded[Right] = SideKind::Open;
  EXPECT_THROW(Gauge(make_lattice(open, 6, 6), NullSpace::GradientScalar), std::invalid_argument);
  // the Morris Laplacian of phi keeps the constant (walls) unless phi's images are odd somewhere (an outflow)
  EXPECT_EQ(Gauge(L, NullSpace::Constants).dimension(), 1);
  Domain outflow = d;
  outflow.bounded[Right] = SideKind::Outflow;
  EXPECT_EQ(Gauge(make_lattice(outflow, 6, 6), NullSpace::Constants).dimension(), 0);
  // an inflow facing an outflow: the stream function's images odd on one side and even on the other,
  // so neither the constant nor the alternating mode continues through both: no null vector
  Domain open_channel = outflow;
  open_channel.bounded[Left] = SideKind::Inflow;
  EXPECT_EQ(Gauge(make_lattice(open_channel, 6, 6), NullSpace::GradientStream).dimension(), 0);
}
