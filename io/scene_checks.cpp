#include "io/scene_checks.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <sstream>

#include "io/scene.hpp"

namespace sphib {

namespace {

std::string str(double v) { return number_text(v); }

double spacing_x(const FluidParams& f) { return f.domain.Lx() / f.nx; }
double spacing_y(const FluidParams& f) { return f.domain.Ly() / f.ny; }
double smoothing_length(const FluidParams& f) { return f.h_over_dx * 0.5 * (spacing_x(f) + spacing_y(f)); }

using P = Eigen::Vector2d;

double cross(const P& o, const P& a, const P& b) { return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x(); }

bool within(const P& a, const P& b, const P& p) {  // p on the bounding box of the segment ab
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

// Segments ab and cd meet: cross at a point, touch, or overlap along a line.
bool segments_meet(const P& a, const P& b, const P& c, const P& d) {
  const double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && within(c, d, a)) || (d2 == 0 && within(c, d, b)) || (d3 == 0 && within(a, b, c)) ||
         (d4 == 0 && within(a, b, d));
}

// The first pair of segments (i of A, j of B) that meet, by binning B's segments in square cells
// as wide as its longest segment: O(nb) for membranes of similar spacing.
bool polygons_meet(const Mat2& A, const Mat2& B, long& i_out, long& j_out) {
  const long na = A.rows(), nb = B.rows();
  double cell = 0;
  for (long j = 0; j < nb; ++j) cell = std::max(cell, (B.row((j + 1) % nb) - B.row(j)).norm());
  if (!(cell > 0)) cell = 1;
  const P lo = B.colwise().minCoeff().transpose();
  auto key = [&](double x, double y) {
    return std::make_pair(static_cast<long>(std::floor((x - lo.x()) / cell)), static_cast<long>(std::floor((y - lo.y()) / cell)));
  };
  std::map<std::pair<long, long>, std::vector<long>> bins;
  for (long j = 0; j < nb; ++j) {
    const P c = B.row(j).transpose(), d = B.row((j + 1) % nb).transpose();
    const auto k0 = key(std::min(c.x(), d.x()), std::min(c.y(), d.y())), k1 = key(std::max(c.x(), d.x()), std::max(c.y(), d.y()));
    for (long u = k0.first; u <= k1.first; ++u)
      for (long v = k0.second; v <= k1.second; ++v) bins[{u, v}].push_back(j);
  }
  for (long i = 0; i < na; ++i) {
    const P a = A.row(i).transpose(), b = A.row((i + 1) % na).transpose();
    const auto k0 = key(std::min(a.x(), b.x()), std::min(a.y(), b.y())), k1 = key(std::max(a.x(), b.x()), std::max(a.y(), b.y()));
    if (k1.first - k0.first > 4 * nb || k1.second - k0.second > 4 * nb) {  // a segment far longer than B: test all
      for (long j = 0; j < nb; ++j)
        if (segments_meet(a, b, B.row(j).transpose(), B.row((j + 1) % nb).transpose())) return i_out = i, j_out = j, true;
      continue;
    }
    for (long u = k0.first; u <= k1.first; ++u)
      for (long v = k0.second; v <= k1.second; ++v) {
        const auto it = bins.find({u, v});
        if (it == bins.end()) continue;
        for (long j : it->second)
          if (segments_meet(a, b, B.row(j).transpose(), B.row((j + 1) % nb).transpose())) return i_out = i, j_out = j, true;
      }
  }
  return false;
}

}  // namespace

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string lattice_too_large(const FluidParams& f) {
  const double N = static_cast<double>(f.nx) * f.ny;
  if (N > INT_MAX)
    return str(f.nx) + " x " + str(f.ny) + " = " + str(N) + " particles: more than 2^31 - 1 (32-bit particle indices)";
  const double h = smoothing_length(f), reach = 4.0 * h;  // G^T G couples particles up to 2 x 2h apart
  const double per_row = std::min(N, M_PI * reach * reach / (spacing_x(f) * spacing_y(f)) + 1.0);
  if (N * per_row > INT_MAX)
    return str(f.nx) + " x " + str(f.ny) + " particles with h = " + str(f.h_over_dx) +
           " (dx + dy)/2: about " + str(N * per_row) + " operator non-zeros, more than the 2^31 - 1 of 32-bit sparse indices";
  return "";
}

std::string kernel_too_narrow(const FluidParams& f) {
  const double dmax = std::max(spacing_x(f), spacing_y(f)), h = smoothing_length(f);
  if (2.0 * h > dmax) return "";
  const double limit = dmax / (spacing_x(f) + spacing_y(f));
  return "value " + str(f.h_over_dx) + " leaves particles without a neighbour inside the kernel's support 2h (h = " +
         str(h) + ", the lattice spacing " + str(dmax) + "): every linear system would be singular; it must exceed " +
         str(limit) + " on this lattice (0.5 when dx = dy)";
}

std::string kernel_warning(const FluidParams& f) {
  const double dmax = std::max(spacing_x(f), spacing_y(f)), h = smoothing_length(f);
  if (h >= 0.9 * dmax) return "";
  return "kernel.h_over_dx = " + str(f.h_over_dx) + " gives h = " + str(h / dmax) +
         " max(dx, dy): below 0.9 the SPH operators are inaccurate (Couette and Poiseuille errors at h = 0.8 dx are "
         "28 and 14 times those at h = dx; README \"Kernel width\")";
}

std::string wall_moves_normally(const Domain& d, int side) {
  const Side s = static_cast<Side>(side);
  if (!d.is_wall(s)) return "";
  const Eigen::Vector2d& v = d.wall_velocity[side];
  const double normal = (s == Left || s == Right) ? v.x() : v.y();
  if (normal == 0) return "";
  return std::string("velocity [") + str(v.x()) + ", " + str(v.y()) + "] has a component " + str(normal) + " normal to the wall (" +
         ((s == Left || s == Right) ? "x" : "y") +
         "): a wall moves only along itself here (its image particles are fixed; flow through it cannot be divergence-free)";
}

std::string exact_cannot_apply(const Scene& s) {
  const Domain& d = s.sim.fluid.domain;
  const bool channel = d.periodic_x && !d.periodic_y, box = !d.periodic_x && !d.periodic_y;
  const bool membranes = !s.sim.membranes.empty();
  const auto& w = d.wall_velocity;
  const bool force = s.sim.body_force.norm() > 0 || s.sim.body_force_field;
  if (s.exact == "poiseuille") {
    if (!channel) return "\"poiseuille\" needs a channel: periodic_x = true, periodic_y = false";
    if (membranes) return "\"poiseuille\" is the flow without membranes";
    if (w[Bottom].norm() > 0 || w[Top].norm() > 0) return "\"poiseuille\" needs walls at rest (use \"couette\")";
    if (s.sim.body_force_field || !(s.sim.body_force.x() != 0) || s.sim.body_force.y() != 0)
      return "\"poiseuille\" needs a constant fluid.body_force along x, [F, 0] with F != 0";
    return "";
  }
  if (s.exact == "couette") {
    if (!channel) return "\"couette\" needs a channel: periodic_x = true, periodic_y = false";
    if (membranes) return "\"couette\" is the flow without membranes";
    if (force) return "\"couette\" is the flow without a body force";
    if (w[Top].x() == w[Bottom].x()) return "\"couette\" needs the walls to move relative to each other (walls.top, walls.bottom)";
    return "";
  }
  if (s.exact == "cavity") {
    if (!box) return "\"cavity\" needs a closed box: periodic_x = false, periodic_y = false";
    if (!(w[Top].x() != 0)) return "\"cavity\" needs a moving lid: walls.top = [U, 0] with U != 0";
    return "";
  }
  if (s.exact == "membrane_equilibrium") {
    if (!membranes) return "\"membrane_equilibrium\" needs a membrane";
    if (!s.membranes.empty() && s.membranes[0].shape != "circle")
      return "\"membrane_equilibrium\" needs a circular membrane (membrane.shape = \"circle\")";
    if (!s.membranes.empty() && s.membranes[0].reference != "circle")
      return "\"membrane_equilibrium\" needs the circle reference (membrane.reference = \"circle\")";
    return "";
  }
  if (s.exact == "membrane_oscillation") {
    if (!membranes) return "\"membrane_oscillation\" needs a membrane";
    if (s.sim.membranes[0].fixed) return "\"membrane_oscillation\" needs membrane 0 free (fixed = false)";
    return "";
  }
  return "";
}

std::string membranes_cross(const std::vector<MembraneSetup>& m, const Domain& d, size_t* first, size_t* second) {
  const double L[2] = {d.Lx(), d.Ly()};
  const bool periodic[2] = {d.periodic_x, d.periodic_y};
  // A membrane as wide as a period meets its own periodic image.
  for (size_t k = 0; k < m.size(); ++k) {
    const Mat2& X = m[k].membrane.X;
    for (int a = 0; a < 2; ++a) {
      const double extent = X.col(a).maxCoeff() - X.col(a).minCoeff();
      if (!periodic[a] || extent < L[a]) continue;
      if (first) *first = k;
      if (second) *second = k;
      return "membrane " + std::to_string(k) + " is " + number_text(extent) + " wide along the periodic " +
             (a == 0 ? "x" : "y") + " axis, not less than its period " + number_text(L[a]) +
             ": it would meet its own periodic image";
    }
  }
  // Two membranes meet here, or one meets the other's image across a periodic side.
  for (size_t k = 0; k < m.size(); ++k)
    for (size_t l = k + 1; l < m.size(); ++l)
      for (int sx = periodic[0] ? -1 : 0; sx <= (periodic[0] ? 1 : 0); ++sx)
        for (int sy = periodic[1] ? -1 : 0; sy <= (periodic[1] ? 1 : 0); ++sy) {
          Mat2 B = m[l].membrane.X;
          B.col(0).array() += sx * L[0];
          B.col(1).array() += sy * L[1];
          long i = 0, j = 0;
          if (!polygons_meet(m[k].membrane.X, B, i, j)) continue;
          if (first) *first = k;
          if (second) *second = l;
          return "membrane " + std::to_string(l) + (sx || sy ? "'s periodic image" : "") + " crosses or touches membrane " +
                 std::to_string(k) + " (its segment " + std::to_string(j) + " meets segment " + std::to_string(i) + ")" +
                 (sx || sy ? std::string(" across the periodic ") + (sx && sy ? "corner" : sx ? "x sides" : "y sides") : "");
        }
  return "";
}

std::string fill_leaves_no_surface(const FluidParams& f) {
  const FluidRegion& r = f.free_surface.fill;
  const Domain& d = f.domain;
  if (r.shape == FluidRegion::Shape::Domain || d.any_open() || f.method != FluidMethod::Isph) return "";
  // The lattice of Eq. (68): sites at x0 + (i + o) dx, o = 1/2 between walls, 0 along a periodic axis.
  const double dx = spacing_x(f), dy = spacing_y(f), ox = d.periodic_x ? 0.0 : 0.5, oy = d.periodic_y ? 0.0 : 0.5;
  const double xa = d.x0 + ox * dx, xb = d.x0 + (f.nx - 1 + ox) * dx, ya = d.y0 + oy * dy, yb = d.y0 + (f.ny - 1 + oy) * dy;
  bool all = false;
  if (r.shape == FluidRegion::Shape::Block) all = r.x0 <= xa && r.x1 >= xb && r.y0 <= ya && r.y1 >= yb;
  else {  // a circle holds the box of the sites when it holds its four corners
    all = true;
    for (double x : {xa, xb})
      for (double y : {ya, yb}) all = all && std::hypot(x - r.centre.x(), y - r.centre.y()) <= r.radius;
  }
  if (!all) return "";
  return std::string("the ") + (r.shape == FluidRegion::Shape::Block ? "block" : "circle") +
         " holds every particle of a tank with no open side: no free surface is left, and ISPH's pressure has no "
         "surface to take p = 0 from; a tank full of fluid is fill.shape = \"domain\"";
}

long planned_steps(const Scene& s) {
  const double by_end = std::round(s.t_end / s.sim.fluid.dt);
  const double steps = s.max_steps > 0 ? std::min(by_end, static_cast<double>(s.max_steps)) : by_end;
  return static_cast<long>(std::clamp(steps, 0.0, static_cast<double>(kMaxSteps) + 1));
}

std::string steps_problem(const Scene& s) {
  const double by_end = s.t_end / s.sim.fluid.dt;
  if (!(std::round(by_end) >= 1))
    return "value " + str(s.t_end) + " is less than half a step of time.dt = " + str(s.sim.fluid.dt) + ": no step would run";
  if (planned_steps(s) > kMaxSteps)
    return "needs " + str(by_end) + " steps of time.dt, more than " + str(static_cast<double>(kMaxSteps)) +
           " (a run that long is a mistake; set time.max_steps to run part of it)";
  return "";
}

}  // namespace sphib
