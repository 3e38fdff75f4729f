#include "fluid/common/boundary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
// Mirror of coordinate c across the wall at w.
double mirror(double c, double w) { return 2.0 * w - c; }
}  // namespace

Images make_images(const Lattice& L, double reach) { return make_images(L.domain, L.x, reach); }

namespace {
// The image parity of velocity component a (0: x, 1: y) across a side: x is the normal component on
// the left and right, y on the bottom and top (boundary_rule.hpp).
int component_parity(const Domain& d, Side side, int a) {
  const bool normal = (a == 0) == (side == Left || side == Right);
  return d.parity(side, normal ? Field::VelocityNormal : Field::VelocityTangential);
}
}  // namespace

Images make_images(const Domain& d, const Mat2& X, double reach) {
  // One image layer per wall is complete only if no particle is within reach of two opposite walls.
  if ((!d.periodic_x && d.Lx() < 2.0 * reach) || (!d.periodic_y && d.Ly() < 2.0 * reach)) {
    std::ostringstream m;
    m << "walls: the distance between opposite walls must be at least two kernel supports (4h = "
      << 2.0 * reach << "); the domain is " << d.Lx() << " x " << d.Ly();
    throw std::invalid_argument(m.str());
  }
  Images im;
  std::vector<double> xs, ys;
  // The parities of each side (boundary_rule.hpp): the operators' velocity sign is the stream
  // function's (the normal component's: both components' except at a free-slip wall), with the
  // components' own parities beside it (v_split).
  double v_par[4] = {0, 0, 0, 0}, s_par[4] = {0, 0, 0, 0}, c_par[4][2] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}};
  bool split = false;
  for (int w = 0; w < 4; ++w) {
    const Side side = static_cast<Side>(w);
    if (d.is_periodic(side)) continue;
    if (!makes_images(d.kind(side)))
      throw std::invalid_argument(std::string("walls: the ") + side_name(side) + " side is " +
                                  side_kind_name(d.kind(side)) + ": no image particles there (free-surface methods)");
    v_par[w] = d.parity(side, Field::Stream);
    s_par[w] = d.parity(side, Field::Scalar);
    c_par[w][0] = component_parity(d, side, 0);
    c_par[w][1] = component_parity(d, side, 1);
    split = split || c_par[w][0] != v_par[w] || c_par[w][1] != v_par[w];
  }
  std::vector<double> sx, sy;  // the components' parities, image by image
  auto add = [&](int p, double x, double y, int wall, double v_sign, double s_sign) {
    im.parent.push_back(p);
    im.wall.push_back(wall);
    im.v_sign.push_back(v_sign);
    im.s_sign.push_back(s_sign);
    xs.push_back(x);
    ys.push_back(y);
  };
  auto add_split = [&](double px, double py) {
    sx.push_back(px);
    sy.push_back(py);
  };
  for (int p = 0; p < X.rows(); ++p) {
    const double x = X(p, 0), y = X(p, 1);
    // Walls this particle is within `reach` of, with the mirrored coordinate.
    int xw = -1, yw = -1;
    double xm = 0, ym = 0;
    if (!d.periodic_x) {
      if (x - d.x0 < reach) { xw = Left; xm = mirror(x, d.x0); }
      else if (d.x1 - x < reach) { xw = Right; xm = mirror(x, d.x1); }
    }
    if (!d.periodic_y) {
      if (y - d.y0 < reach) { yw = Bottom; ym = mirror(y, d.y0); }
      else if (d.y1 - y < reach) { yw = Top; ym = mirror(y, d.y1); }
    }
    if (xw >= 0) add(p, xm, y, xw, v_par[xw], s_par[xw]);
    if (yw >= 0) add(p, x, ym, yw, v_par[yw], s_par[yw]);
    if (xw >= 0 && yw >= 0) add(p, xm, ym, -1, v_par[xw] * v_par[yw], s_par[xw] * s_par[yw]);  // corner: point reflection
    if (!split) continue;
    if (xw >= 0) add_split(c_par[xw][0], c_par[xw][1]);
    if (yw >= 0) add_split(c_par[yw][0], c_par[yw][1]);
    if (xw >= 0 && yw >= 0) add_split(c_par[xw][0] * c_par[yw][0], c_par[xw][1] * c_par[yw][1]);
  }
  im.x.resize(static_cast<int>(xs.size()), 2);
  for (int k = 0; k < im.size(); ++k) {
    im.x(k, 0) = xs[k];
    im.x(k, 1) = ys[k];
  }
  if (split) {
    im.v_split.resize(im.size(), 2);
    for (int k = 0; k < im.size(); ++k) {
      im.v_split(k, 0) = sx[k] - im.v_sign[k];
      im.v_split(k, 1) = sy[k] - im.v_sign[k];
    }
  }
  return im;
}

void add_split_images(const Images& im, const Mat2& u, Mat2& c) {
  if (!im.split()) return;
  for (int a = 0; a < 2; ++a)
    for (int m = 0; m < im.size(); ++m)
      if (im.v_split(m, a) != 0.0) c(m, a) += im.v_split(m, a) * u(im.parent[m], a);
}

SpMat component_matrix(const SpMat& A, const SpMat& B, const Images& im, int a) {
  if (!im.split()) return A;
  std::vector<Triplet> t;  // diag(v_split(:, a)) P: image m -> its parent's column
  for (int m = 0; m < im.size(); ++m)
    if (im.v_split(m, a) != 0.0) t.emplace_back(m, im.parent[m], im.v_split(m, a));
  SpMat S(im.size(), A.cols());
  S.setFromTriplets(t.begin(), t.end());
  SpMat C = A + SpMat(B * S);
  C.makeCompressed();
  return C;
}

void keep_in_tank(const Domain& d, Mat2& x, double t, const char* method, const char* hint) {
  for (int i = 0; i < x.rows(); ++i) {
    for (int a = 0; a < 2; ++a) {
      const bool periodic = a == 0 ? d.periodic_x : d.periodic_y;
      const double lo = a == 0 ? d.x0 : d.y0, hi = a == 0 ? d.x1 : d.y1;
      double& c = x(i, a);
      if (periodic) {
        c -= (hi - lo) * std::floor((c - lo) / (hi - lo));  // periodic wrap into [lo, hi)
        if (c >= hi) c = lo;  // -tiny + period rounds to hi
      } else if (!(c > lo && c < hi)) {
        std::ostringstream m;
        const Side side = a == 0 ? (c <= lo ? Left : Right) : (c <= lo ? Bottom : Top);
        m << method << ": particle " << i;
        if (!std::isfinite(c)) m << " has a non-finite position";
        else if (d.is_open(side)) m << " left the tank through its open " << side_name(side) << " side " << (a == 0 ? "x = " : "y = ") << (c <= lo ? lo : hi);
        else m << " crossed the wall " << (a == 0 ? "x = " : "y = ") << (c <= lo ? lo : hi);
        m << " (now at " << x(i, 0) << ", " << x(i, 1) << ") at t = " << t;
        if (std::isfinite(c) && !d.is_open(side)) m << ": " << hint;
        if (std::isfinite(c) && d.is_open(side)) m << " (a splash or a jet: make the tank larger)";
        throw std::runtime_error(m.str());
      }
    }
  }
}

Eigen::Vector2d side_velocity(const Domain& d, Side w, const Eigen::Vector2d& x) {
  const Eigen::Vector2d& u = d.wall_velocity[w];
  if (d.kind(w) != SideKind::Inflow || d.inflow_profile != InflowProfile::Parabolic) return u;
  const bool vertical = w == Left || w == Right;  // the side runs along y
  const double a = vertical ? d.y0 : d.x0, b = vertical ? d.y1 : d.x1;
  const double s = std::clamp(((vertical ? x.y() : x.x()) - a) / (b - a), 0.0, 1.0);
  return (4.0 * s * (1.0 - s)) * u;
}

namespace {
// The flux through side w from its start (x0 or y0) to `along`: int u_n, u_n the side velocity's
// component along the axis normal to the side, shaped by the inflow's profile.
double side_flux(const Domain& d, Side w, double along) {
  const bool vertical = w == Left || w == Right;
  const double a = vertical ? d.y0 : d.x0, b = vertical ? d.y1 : d.x1;
  const double s = std::clamp((along - a) / (b - a), 0.0, 1.0);
  const InflowProfile p = d.kind(w) == SideKind::Inflow ? d.inflow_profile : InflowProfile::Uniform;
  return d.wall_velocity[w][vertical ? 0 : 1] * (b - a) * profile_integral(p, s);
}
}  // namespace

namespace {
// The whole flux F_w through each side, counted along +x on the left and right sides and along +y on
// the bottom and top (int u dy, int v dx): prescribed on an inflow (0 on a wall), and on the one
// outflow side what the balance F_L + F_B - F_R - F_T = 0 (no net source) leaves.
std::array<double, 4> side_fluxes(const Domain& d) {
  std::array<double, 4> F{};
  int out = -1;
  for (int k = 0; k < 4; ++k) {
    const Side w = static_cast<Side>(k);
    if (d.kind(w) == SideKind::Outflow) out = k;
    else F[k] = side_flux(d, w, (w == Left || w == Right) ? d.y1 : d.x1);
  }
  if (out == Left) F[Left] = F[Right] + F[Top] - F[Bottom];
  if (out == Bottom) F[Bottom] = F[Right] + F[Top] - F[Left];
  if (out == Right) F[Right] = F[Left] + F[Bottom] - F[Top];
  if (out == Top) F[Top] = F[Left] + F[Bottom] - F[Right];
  return F;
}
}  // namespace

double side_stream_value(const Domain& d, Side w, double along) {
  switch (w) {
    case Left: return side_flux(d, Left, along);
    case Bottom: return -side_flux(d, Bottom, along);
    case Top: return side_fluxes(d)[Left] - side_flux(d, Top, along);      // psi(x0, y1) = F_L
    case Right: return -side_fluxes(d)[Bottom] + side_flux(d, Right, along);  // psi(x1, y0) = -F_B
  }
  return 0.0;
}

std::string stream_function_refusal(const Domain& d) {
  if (!d.any_through()) return "";
  int inflows = 0, outflows = 0;
  for (int k = 0; k < 4; ++k) {
    inflows += d.kind(static_cast<Side>(k)) == SideKind::Inflow;
    outflows += d.kind(static_cast<Side>(k)) == SideKind::Outflow;
  }
  const std::string key = inflows > 0 ? "domain.inflow" : "domain.outflow";
  if (d.periodic_x || d.periodic_y)
    return key + ": a stream function with flow through a side needs walls on the other axis (not periodic)";
  if (outflows == 0) return "domain.inflow: a stream function needs an outflow side to carry the inflow's flux out";
  if (outflows > 1)
    return "domain.outflow: a stream function with two outflow sides (how the flux divides between them is not "
           "prescribed); use one";
  return "";
}

std::string image_parities_text(const Domain& d, Field f) {
  std::vector<Side> odd, even;
  for (int k = 0; k < 4; ++k) {
    const Side w = static_cast<Side>(k);
    if (d.is_periodic(w) || !makes_images(d.kind(w))) continue;
    (d.parity(w, f) < 0 ? odd : even).push_back(w);
  }
  const auto sides = [](const std::vector<Side>& s) {
    std::string t;
    for (size_t i = 0; i < s.size(); ++i) t += (i == 0 ? "" : i + 1 == s.size() ? " and " : ", ") + std::string(side_name(s[i]));
    return t + (s.size() > 1 ? " sides" : "");
  };
  if (even.empty()) return "odd images";
  if (odd.empty()) return "even images";
  return "odd images at the " + sides(odd) + ", even at the " + sides(even);
}

CornerReflections corner_reflections(const Domain& d, const Eigen::Vector2d& xk) {
  const Side sx = xk.x() < d.x0 ? Left : Right, sy = xk.y() < d.y0 ? Bottom : Top;
  const Eigen::Vector2d parent(sx == Left ? 2.0 * d.x0 - xk.x() : 2.0 * d.x1 - xk.x(),
                               sy == Bottom ? 2.0 * d.y0 - xk.y() : 2.0 * d.y1 - xk.y());
  if (d.kind(sy) != SideKind::Inflow) return {sx, sy, parent, Eigen::Vector2d(xk.x(), parent.y())};
  return {sy, sx, parent, Eigen::Vector2d(parent.x(), xk.y())};
}

void image_stream_offsets(const Images& im, const Domain& d, Vec& offset) {
  offset = Vec::Zero(im.size());
  // psi_w at x on side w where the images are odd; 0 where they are even (an outflow: no value)
  const auto value = [&](Side w, const Eigen::Vector2d& x) {
    return d.parity(w, Field::Stream) > 0 ? 0.0 : side_stream_value(d, w, (w == Left || w == Right) ? x.y() : x.x());
  };
  for (int k = 0; k < im.size(); ++k) {
    const Eigen::Vector2d xk = im.x.row(k).transpose();
    const int w = im.wall[k];
    if (w >= 0) {
      const Side side = static_cast<Side>(w);
      offset[k] = image_prescribed(d.parity(side, Field::Stream), value(side, xk));
      continue;
    }
    // corner: psi'' = p_B (p_A psi + (1 - p_A) psi_A) + (1 - p_B) psi_B, an inflow first (psi_in
    // within the side), then a wall's constant or an outflow's nothing
    const CornerReflections c = corner_reflections(d, xk);
    offset[k] = corner_prescribed(d.parity(c.first, Field::Stream), value(c.first, c.at_first),
                                  d.parity(c.second, Field::Stream), value(c.second, c.at_second));
  }
}

void image_velocity_offsets(const Images& im, const Domain& d, const Mat2* grad_phi, double dt_over_rho,
                            Mat2& offset) {
  // Per side, out of the loop (this runs every step): whether the tangential velocity is prescribed
  // (odd images: the correction of Eq. 42 applies), whether the side's velocity has a profile, and
  // the parity of velocity component a (0: x, 1: y) across it (x the normal one on the left and right)
  bool tangential_odd[4], shaped[4];
  int comp_par[4][2];
  for (int w = 0; w < 4; ++w) {
    const Side side = static_cast<Side>(w);
    tangential_odd[w] = d.parity(side, Field::VelocityTangential) < 0;
    shaped[w] = d.kind(side) == SideKind::Inflow && d.inflow_profile == InflowProfile::Parabolic;
    for (int a = 0; a < 2; ++a) comp_par[w][a] = component_parity(d, side, a);
  }
  const auto parity = [&](Side w, int a) { return comp_par[w][a]; };
  for (int k = 0; k < im.size(); ++k) {
    const int w = im.wall[k];
    if (w < 0) {
      // corner image: u'' = p_B (p_A u + (1 - p_A) g_A) + (1 - p_B) g_B per component (header), an
      // inflow first with its profile at the parent's place; between sides of constant value the
      // mean of the two orders (0 between two no-slip walls)
      const CornerReflections c = corner_reflections(d, im.x.row(k).transpose());
      Eigen::Vector2d gA = side_velocity(d, c.first, c.at_first), gB = side_velocity(d, c.second, c.at_second);
      if (grad_phi) {  // each side's Eq. (42) correction of its tangential component, at the parent
        const int tA = (c.first == Bottom || c.first == Top) ? 0 : 1, tB = 1 - tA;
        if (tangential_odd[c.first]) gA[tA] += dt_over_rho * (*grad_phi)(im.parent[k], tA);
        if (tangential_odd[c.second]) gB[tB] += dt_over_rho * (*grad_phi)(im.parent[k], tB);
      }
      const bool inflow = d.kind(c.first) == SideKind::Inflow || d.kind(c.second) == SideKind::Inflow;
      for (int a = 0; a < 2; ++a) {
        const int pA = parity(c.first, a), pB = parity(c.second, a);
        const double ab = corner_prescribed(pA, gA[a], pB, gB[a]);
        offset(k, a) = inflow ? ab : 0.5 * (ab + corner_prescribed(pB, gB[a], pA, gA[a]));
      }
      continue;
    }
    const int t = (w == Bottom || w == Top) ? 0 : 1;  // tangent direction of the wall
    // u_b: the wall's velocity, an inflow's profile at the image
    Eigen::Vector2d g = shaped[w] ? side_velocity(d, static_cast<Side>(w), im.x.row(k).transpose()) : d.wall_velocity[w];
    if (grad_phi && tangential_odd[w]) {
      // tangential correction dt/rho (tau . grad phi~) tau with phi~ = phi^n (Kim & Moin) where the
      // tangential velocity is prescribed (odd images), Eq. (42)
      g[t] += dt_over_rho * (*grad_phi)(im.parent[k], t);
    }
    // Eq. (42): u*_i' = 2 (u_b + dt/rho grad phi~) - u*_i: the prescribed part (1 - parity) g, each
    // component's parity (the images' own, v_sign, where the components share it)
    offset(k, 0) = image_prescribed(comp_par[w][0], g[0]);
    offset(k, 1) = image_prescribed(comp_par[w][1], g[1]);
  }
}

}  // namespace sphib
