#include "fluid/common/walls.hpp"

#include <cmath>
#include <string>

namespace sphib {

VirtualWalls make_virtual_walls(const Lattice& L, double support) {
  const Domain& d = L.domain;
  const int nx = L.nx, ny = L.ny;
  // rows of virtual particles beyond each wall: enough for a complete support 2h
  const int rx = static_cast<int>(std::ceil(support / L.dx)), ry = static_cast<int>(std::ceil(support / L.dy));
  const int i0 = d.is_wall(Left) ? -rx : 0, i1 = nx + (d.is_wall(Right) ? rx : 0);
  const int j0 = d.is_wall(Bottom) ? -ry : 0, j1 = ny + (d.is_wall(Top) ? ry : 0);
  const double ox = d.periodic_x ? 0.0 : 0.5, oy = d.periodic_y ? 0.0 : 0.5;  // Eq. (68) offsets
  std::vector<double> xs, ys, us, vs;
  VirtualWalls w;
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) {
      const bool out_x = i < 0 || i >= nx, out_y = j < 0 || j >= ny;
      if (!out_x && !out_y) continue;  // a fluid site
      const double x = d.x0 + (i + ox) * L.dx, y = d.y0 + (j + oy) * L.dy;
      const Side sx = i < 0 ? Left : Right, sy = j < 0 ? Bottom : Top;
      Eigen::Vector2d uw;
      int side = -1;
      double dist = 0;
      if (out_x && out_y) {
        uw = 0.5 * (d.wall_velocity[sx] + d.wall_velocity[sy]);  // corner block: mean of the two walls
      } else if (out_x) {
        side = sx;
        uw = d.wall_velocity[sx];
        dist = sx == Left ? d.x0 - x : x - d.x1;
      } else {
        side = sy;
        uw = d.wall_velocity[sy];
        dist = sy == Bottom ? d.y0 - y : y - d.y1;
      }
      const bool inner_x = i == -1 || i == nx, inner_y = j == -1 || j == ny;
      xs.push_back(x);
      ys.push_back(y);
      us.push_back(uw.x());
      vs.push_back(uw.y());
      w.side.push_back(side);
      w.dist.push_back(dist);
      w.inner.push_back((out_x && out_y) ? (inner_x && inner_y) : (out_x ? inner_x : inner_y));
    }
  const int M = static_cast<int>(xs.size());
  w.x.resize(M, 2);
  w.u.resize(M, 2);
  for (int k = 0; k < M; ++k) {
    w.x(k, 0) = xs[k];
    w.x(k, 1) = ys[k];
    w.u(k, 0) = us[k];
    w.u(k, 1) = vs[k];
  }
  return w;
}

std::optional<ParamProblem> gate_problem(const FluidParams& p) {
  if (!p.gate.on) return std::nullopt;
  const FreeSurfaceParams& fs = p.free_surface;
  const Domain& d = p.domain;
  if (!(p.gate.x > d.x0 && p.gate.x < d.x1) || !std::isfinite(p.gate.x))
    return ParamProblem{"gate.x", "must lie inside the domain, between domain.x's two ends"};
  if (!(p.gate.speed > 0) || !std::isfinite(p.gate.speed)) return ParamProblem{"gate.speed", "must be positive and finite"};
  if (!(p.gate.start >= 0) || !std::isfinite(p.gate.start)) return ParamProblem{"gate.start", "must be >= 0 and finite"};
  if (d.periodic_x || d.periodic_y || !d.is_wall(Bottom))
    return ParamProblem{"gate", "needs a tank with a floor and without periodic sides"};
  const FluidRegion& f = fs.fill;
  if (f.shape != FluidRegion::Shape::Block || !(f.x1 <= p.gate.x + 1e-12 * d.Lx()))
    return ParamProblem{"gate.x", "the fluid must be a block (fill.shape = \"block\") on the gate's low side (fill.x's end <= gate.x)"};
  return std::nullopt;
}

void append_gate(const Lattice& L, double support, const GateParams& g, double top, double t, VirtualWalls& w) {
  const Domain& d = L.domain;
  const int cols = static_cast<int>(std::ceil(support / L.dx));
  const int rows = static_cast<int>(std::ceil((top - d.y0 + support) / L.dy));
  const double lift = g.lift(t);
  const int M0 = w.size(), M = M0 + cols * rows;
  w.x.conservativeResize(M, 2);
  w.u.conservativeResize(M, 2);
  int k = M0;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i, ++k) {
      w.x(k, 0) = g.x + (i + 0.5) * L.dx;
      w.x(k, 1) = d.y0 + (j + 0.5) * L.dy + lift;
      w.u(k, 0) = 0.0;
      w.u(k, 1) = 0.0;  // moved, not sweeping: see walls.hpp
      w.side.push_back(kGateSide);
      w.dist.push_back((i + 0.5) * L.dx);
      w.inner.push_back(i == 0);
    }
}

bool move_gate(const Lattice& L, double support, const GateParams& g, double top, double t, double fluid_top, int tank,
               bool& in, VirtualWalls& w) {
  if (!in) return false;
  if (w.size() > tank && g.velocity(t) == 0 && g.lift(t) == 0) return false;
  w.x.conservativeResize(tank, 2);
  w.u.conservativeResize(tank, 2);
  w.side.resize(tank);
  w.dist.resize(tank);
  w.inner.resize(tank);
  in = L.domain.y0 + g.lift(t) <= fluid_top + support;
  if (in) append_gate(L, support, g, top, t, w);
  return true;
}

}  // namespace sphib
