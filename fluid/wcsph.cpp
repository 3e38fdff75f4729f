#include "fluid/wcsph.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
using Clock = std::chrono::steady_clock;

void check_params(const FluidParams& p) {
  check_common_params(p);
  positive_param(p.wcsph.gamma, "wcsph.gamma");
  positive_param(p.wcsph.u_scale, "wcsph.u_scale");
  const WcsphParams& w = p.wcsph;
  if (!(w.c >= 0) || !std::isfinite(w.c))
    throw std::invalid_argument("wcsph.c must be >= 0 and finite (got " + std::to_string(w.c) + ")");
  if (!(w.xsph >= 0 && w.xsph <= 1))
    throw std::invalid_argument("wcsph.xsph must be in [0, 1] (got " + std::to_string(w.xsph) + ")");
  if (w.eos != "morris" && w.eos != "tait")
    throw std::invalid_argument("wcsph.eos: \"" + w.eos + "\" is not allowed (allowed: morris | tait)");
  if (w.walls != "virtual" && w.walls != "lennard_jones")
    throw std::invalid_argument("wcsph.walls: \"" + w.walls + "\" is not allowed (allowed: virtual | lennard_jones)");
}

// S = sum_j W(x_0 - x_j) over the infinite lattice of spacings dx, dy (x_0 included).
double kernel_sum_on_lattice(const CubicSplineKernel& W, double dx, double dy) {
  const int Rx = static_cast<int>(std::ceil(W.support() / dx)) + 1;
  const int Ry = static_cast<int>(std::ceil(W.support() / dy)) + 1;
  double S = 0;
  for (int b = -Ry; b <= Ry; ++b)
    for (int a = -Rx; a <= Rx; ++a) S += W.W(std::hypot(a * dx, b * dy));
  return S;
}
}  // namespace

double wcsph_sound_speed(const FluidParams& p) {
  // C Eq. (5): c^2 ~ U0^2 / delta; c = 10 U0 gives delta = |rho/rho0 - 1| ~ (U0/c)^2 ~ 1%.
  return p.wcsph.c > 0 ? p.wcsph.c : 10.0 * p.wcsph.u_scale;
}

double coelho_dt_limit(double h, double c, double nu) {
  return std::min(0.25 * h / c, 0.125 * h * h / nu);  // C Eq. (19), acoustic and viscous terms
}

WcsphFluid::WcsphFluid(const FluidParams& params, const WcsphOptions& options)
    : prm_(params), opt_(options), lat_(make_lattice(params.domain, params.nx, params.ny)),
      W_(params.h_over_dx * 0.5 * (lat_.dx + lat_.dy)) {
  check_params(prm_);
  const Domain& d = prm_.domain;
  if (d.periodic_x && !(W_.support() < 0.5 * d.Lx())) {
    std::ostringstream m;
    m << "kernel support 2h = " << W_.support() << " must be below half the periodic length Lx = " << d.Lx();
    throw std::invalid_argument(m.str());
  }
  if (d.periodic_y && !(W_.support() < 0.5 * d.Ly())) {
    std::ostringstream m;
    m << "kernel support 2h = " << W_.support() << " must be below half the periodic length Ly = " << d.Ly();
    throw std::invalid_argument(m.str());
  }
  eos_ = prm_.wcsph.eos == "tait" ? Eos::Tait : Eos::Morris;
  lj_ = prm_.wcsph.walls == "lennard_jones";
  c_ = wcsph_sound_speed(prm_);
  dt_limit_ = coelho_dt_limit(W_.h, c_, nu());
  if (prm_.dt > dt_limit_) {
    std::ostringstream m;
    m << "time.dt = " << prm_.dt << " exceeds the WCSPH stability limit " << dt_limit_
      << " of Coelho et al. Eq. (19): min(0.25 h/c = " << 0.25 * W_.h / c_ << ", 0.125 h^2/nu = "
      << 0.125 * W_.h * W_.h / nu() << ") with h = " << W_.h << ", c = " << c_ << ", nu = " << nu();
    throw std::invalid_argument(m.str());
  }
  rho0_ = prm_.rho;
  S_ = kernel_sum_on_lattice(W_, lat_.dx, lat_.dy);
  m_ = rho0_ / S_;  // the initial lattice has summation density rho0 exactly
  p_wall_ = eos_pressure(eos_, rho0_, rho0_, c_, prm_.wcsph.gamma);
  lj_D_ = opt_.lj_D > 0 ? opt_.lj_D : prm_.wcsph.u_scale * prm_.wcsph.u_scale;
  lj_r0_ = std::min(lat_.dx, lat_.dy);

  const auto t0 = Clock::now();
  build_walls();
  const int N = lat_.size(), M = static_cast<int>(xw_.rows());
  x_ = lat_.x;
  u_ = u_hat_ = a_ = Mat2::Zero(N, 2);
  rho_ = p_ = V_ = pr_ = Vec::Zero(N);
  all_.resize(N + M, 2);
  if (M) all_.bottomRows(M) = xw_;
  // Cells: along a walled axis the box grows by two supports (the wall rows reach one support
  // and a spacing); the cell width is the largest division of the box not below 2h.
  const bool periodic[2] = {d.periodic_x, d.periodic_y};
  const double lo[2] = {d.x0, d.y0}, hi[2] = {d.x1, d.y1};
  for (int a = 0; a < 2; ++a) {
    const double grow = periodic[a] ? 0.0 : 2.0 * W_.support();
    lo_[a] = lo[a] - grow;
    const double L = hi[a] - lo[a] + 2.0 * grow;
    nc_[a] = std::max(1, static_cast<int>(std::floor(L / W_.support() * (1.0 - 1e-12))));
    cell_[a] = L / nc_[a];
  }
  cell_start_.assign(nc_[0] * nc_[1] + 1, 0);
  cell_of_.resize(N + M);
  cell_items_.resize(N + M);
  cell_x_.resize(N + M);
  cell_y_.resize(N + M);
  find_neighbours();
  setup_.emplace_back("neighbours", seconds_since(t0));
  summation_density();
  xsph_velocity();
  check_density();

  k_drift_ = prof_.phase("drift (V Eq. 22)");
  k_neigh_ = prof_.phase("neighbours");
  k_rho_ = prof_.phase("summation density + EOS (V Eq. 11, 20)");
  k_force_ = prof_.phase("accelerations (C Eq. 17)");
  k_xsph_ = prof_.phase("XSPH (V Eq. 21)");
}

void WcsphFluid::build_walls() {
  const Domain& d = prm_.domain;
  const int nx = lat_.nx, ny = lat_.ny;
  // rows of virtual particles beyond a wall: enough for a complete support 2h
  const int rx = d.periodic_x ? 0 : static_cast<int>(std::ceil(W_.support() / lat_.dx));
  const int ry = d.periodic_y ? 0 : static_cast<int>(std::ceil(W_.support() / lat_.dy));
  const double ox = d.periodic_x ? 0.0 : 0.5, oy = d.periodic_y ? 0.0 : 0.5;  // Eq. (68) offsets
  std::vector<double> xs, ys, us, vs;
  wside_.clear();
  wdist_.clear();
  winner_.clear();
  for (int j = -ry; j < ny + ry; ++j)
    for (int i = -rx; i < nx + rx; ++i) {
      const bool out_x = i < 0 || i >= nx, out_y = j < 0 || j >= ny;
      if (!out_x && !out_y) continue;  // a fluid particle
      const double x = d.x0 + (i + ox) * lat_.dx, y = d.y0 + (j + oy) * lat_.dy;
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
      wside_.push_back(side);
      wdist_.push_back(dist);
      winner_.push_back((out_x && out_y) ? (inner_x && inner_y) : (out_x ? inner_x : inner_y));
    }
  const int M = static_cast<int>(xs.size());
  xw_.resize(M, 2);
  uw_.resize(M, 2);
  for (int k = 0; k < M; ++k) {
    xw_(k, 0) = xs[k];
    xw_(k, 1) = ys[k];
    uw_(k, 0) = us[k];
    uw_(k, 1) = vs[k];
  }
}

void WcsphFluid::find_neighbours() {
  x_eval_ = x_;
  const Domain& d = prm_.domain;
  const int N = lat_.size(), T = static_cast<int>(all_.rows());
  const bool periodic[2] = {d.periodic_x, d.periodic_y};
  const double period[2] = {d.Lx(), d.Ly()};
  all_.topRows(N) = x_;
  // Bin every particle (counting sort, stable in the index).
  const int ncell = nc_[0] * nc_[1];
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  for (int p = 0; p < T; ++p) {
    int k[2];
    for (int a = 0; a < 2; ++a) {
      k[a] = static_cast<int>(std::floor((all_(p, a) - lo_[a]) / cell_[a]));
      if (periodic[a]) k[a] = ((k[a] % nc_[a]) + nc_[a]) % nc_[a];
      else k[a] = std::min(std::max(k[a], 0), nc_[a] - 1);  // a particle outside: the edge cell
    }
    cell_of_[p] = k[0] + nc_[0] * k[1];
    ++cell_start_[cell_of_[p] + 1];
  }
  for (int c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  for (int p = 0; p < T; ++p) cell_items_[cell_start_[cell_of_[p]]++] = p;
  for (int c = ncell; c > 0; --c) cell_start_[c] = cell_start_[c - 1];  // back to the starts
  cell_start_[0] = 0;
  for (int k = 0; k < T; ++k) {  // positions in cell order: the pair loops stream through memory
    cell_x_[k] = all_(cell_items_[k], 0);
    cell_y_[k] = all_(cell_items_[k], 1);
  }

  Pairs& P = pairs_;
  for (auto* v : {&P.i, &P.j}) v->clear();
  for (auto* v : {&P.rx, &P.ry, &P.r, &P.W, &P.F}) v->clear();
  const double r2max = W_.support() * W_.support();
  // W and F = (1/r) dW/dr of kernel.hpp (V Eq. 15), from q = r/h without its divisions by h
  const double inv_h = 1.0 / W_.h, w0 = W_.w0, w6 = W_.w0 / 6.0, f0 = W_.w0 * inv_h * inv_h;
  long nbrs = 0;  // neighbours summed over the fluid particles
  auto add = [&](int a, int b, double dx, double dy, double r2) {
    int i = a, j = b;
    if (a >= N) { i = b; j = a; dx = -dx; dy = -dy; }  // i is the fluid particle
    const double r = std::sqrt(r2), q = r * inv_h, t = 2.0 - q;
    P.i.push_back(i);
    P.j.push_back(j);
    P.rx.push_back(dx);  // x_i - x_j, minimum image
    P.ry.push_back(dy);
    P.r.push_back(r);
    P.W.push_back(q < 1.0 ? w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q) : w6 * t * t * t);  // W_ij
    P.F.push_back(q < 1.0 ? f0 * (-2.0 + 1.5 * q) : -f0 * 0.5 * t * t / q);                   // F_ij
    nbrs += j < N ? 2 : 1;
  };
  // Half stencil: each cell with itself and four forward neighbours, so that every pair of cells
  // is visited once; across a periodic side the neighbour's particles are shifted by the period.
  // With 2h below half a period every pair has one image within 2h, so a cell met twice through
  // different shifts (fewer than three cells along a periodic axis) still yields each pair once.
  static const int kOff[5][2] = {{0, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
  for (int cy = 0; cy < nc_[1]; ++cy)
    for (int cx = 0; cx < nc_[0]; ++cx) {
      const int c = cx + nc_[0] * cy;
      for (const auto& o : kOff) {
        int t[2] = {cx + o[0], cy + o[1]};
        double shift[2] = {0.0, 0.0};
        bool inside = true;
        for (int a = 0; a < 2; ++a) {
          if (t[a] >= 0 && t[a] < nc_[a]) continue;
          if (!periodic[a]) { inside = false; break; }
          shift[a] = t[a] < 0 ? -period[a] : period[a];
          t[a] = t[a] < 0 ? t[a] + nc_[a] : t[a] - nc_[a];
        }
        if (!inside) continue;
        const int c2 = t[0] + nc_[0] * t[1];
        const bool self = o[0] == 0 && o[1] == 0;  // the cell with itself: unordered pairs
        for (int ka = cell_start_[c]; ka < cell_start_[c + 1]; ++ka) {
          const int a = cell_items_[ka];
          const double ax = cell_x_[ka] - shift[0], ay = cell_y_[ka] - shift[1];
          for (int kb = self ? ka + 1 : cell_start_[c2]; kb < cell_start_[c2 + 1]; ++kb) {
            const double dx = ax - cell_x_[kb], dy = ay - cell_y_[kb];
            const double r2 = dx * dx + dy * dy;
            if (r2 >= r2max) continue;
            const int b = cell_items_[kb];
            if (a < N || b < N) add(a, b, dx, dy, r2);  // not wall with wall
          }
        }
      }
    }
  nbrs_last_ = nbrs;
  nbrs_total_ += nbrs;
}

void WcsphFluid::summation_density() {
  const int N = lat_.size();
  const double gamma = prm_.wcsph.gamma;
  rho_.setConstant(W_.W(0.0));  // the particle itself
  const Pairs& P = pairs_;
  for (int k = 0; k < P.size(); ++k) {
    rho_[P.i[k]] += P.W[k];
    if (P.j[k] < N) rho_[P.j[k]] += P.W[k];
  }
  for (int i = 0; i < N; ++i) {
    rho_[i] *= m_;                                            // V Eq. (11): rho_i = sum_j m_j W_ij
    p_[i] = eos_pressure(eos_, rho_[i], rho0_, c_, gamma);    // V Eq. (20) / C Eq. (3)
    pr_[i] = p_[i] / (rho_[i] * rho_[i]);                     // p_i / rho_i^2 of C Eq. (17)
    V_[i] = m_ / rho_[i];
  }
}

void WcsphFluid::accelerations(const Mat2& F) {
  const int N = lat_.size();
  const Domain& d = prm_.domain;
  const Pairs& P = pairs_;
  const double mu = prm_.mu, pr_wall = p_wall_ / (rho0_ * rho0_);
  a_ = F.array().colwise() / rho_.array();  // external force per unit volume / rho_i
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double rx = P.rx[k], ry = P.ry[k], Fk = P.F[k];  // grad_i W_ij = (x_i - x_j) F_ij
    double pr_j, rho_j, du, dv;
    if (j < N) {
      pr_j = pr_[j];
      rho_j = rho_[j];
      du = u_(i, 0) - u_(j, 0);
      dv = u_(i, 1) - u_(j, 1);
    } else {
      const int w = j - N;
      pr_j = pr_wall;
      rho_j = rho0_;
      du = u_(i, 0) - uw_(w, 0);
      dv = u_(i, 1) - uw_(w, 1);
      if (opt_.morris_extrapolation && wside_[w] >= 0) {
        // Morris et al. (1997): u_B = u_w - (d_B/d_A)(u_A - u_w)  =>  u_AB = beta (u_A - u_w).
        // d_A is floored at the initial lattice distance (half a spacing): exact on the lattice,
        // bounded for a particle that comes closer to the wall.
        const int s = wside_[w];
        const double dA = s == Left ? x_(i, 0) - d.x0 : s == Right ? d.x1 - x_(i, 0)
                        : s == Bottom ? x_(i, 1) - d.y0 : d.y1 - x_(i, 1);
        const double dA_min = 0.5 * (s == Left || s == Right ? lat_.dx : lat_.dy);
        const double beta = std::min(opt_.beta_max, 1.0 + wdist_[w] / std::max(dA, dA_min));
        du *= beta;
        dv *= beta;
      }
      if (lj_ && winner_[w] && P.r[k] < lj_r0_) {
        // C Eq. (20): D [(r0/r)^12 - (r0/r)^4] x_ab / r^2, repulsive for r < r0
        const double q = lj_r0_ / P.r[k], q4 = q * q * q * q;
        const double f = lj_D_ * (q4 * q4 * q4 - q4) / (P.r[k] * P.r[k]);
        a_(i, 0) += f * rx;
        a_(i, 1) += f * ry;
      }
    }
    const double cp = -m_ * (pr_[i] + pr_j) * Fk;               // pressure, C Eq. (17) / V Eq. (12)
    const double cv = m_ * 2.0 * mu / (rho_[i] * rho_j) * Fk;   // Morris viscosity, C Eq. (17)
    const double fx = cp * rx + cv * du, fy = cp * ry + cv * dv;
    a_(i, 0) += fx;
    a_(i, 1) += fy;
    if (j < N) {  // the pair seen from j: x_ji = -x_ij, u_ji = -u_ij (equal masses)
      a_(j, 0) -= fx;
      a_(j, 1) -= fy;
    }
  }
}

void WcsphFluid::xsph_velocity() {
  const double eps = prm_.wcsph.xsph;
  if (eps == 0) { u_hat_ = u_; return; }
  const int N = lat_.size();
  const Pairs& P = pairs_;
  const double V_wall = m_ / rho0_;
  Mat2& s = a_;  // workspace: the XSPH sums (a_ is spent once u^{n+1} is known)
  s.setZero();
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double w = P.W[k];
    if (j < N) {
      const double dx = (u_(i, 0) - u_(j, 0)) * w, dy = (u_(i, 1) - u_(j, 1)) * w;  // u_ij W_ij
      s(i, 0) += V_[j] * dx;  // (m_j / rho_j) u_ij W_ij
      s(i, 1) += V_[j] * dy;
      s(j, 0) -= V_[i] * dx;  // (m_i / rho_i) u_ji W_ji
      s(j, 1) -= V_[i] * dy;
    } else {
      s(i, 0) += V_wall * (u_(i, 0) - uw_(j - N, 0)) * w;
      s(i, 1) += V_wall * (u_(i, 1) - uw_(j - N, 1)) * w;
    }
  }
  u_hat_ = u_ - eps * s;  // V Eq. (21)
}

void WcsphFluid::drift(double tau) {
  const Domain& d = prm_.domain;
  x_ += tau * u_hat_;
  for (int i = 0; i < x_.rows(); ++i) {
    for (int a = 0; a < 2; ++a) {
      const bool periodic = a == 0 ? d.periodic_x : d.periodic_y;
      const double lo = a == 0 ? d.x0 : d.y0, hi = a == 0 ? d.x1 : d.y1;
      double& c = x_(i, a);
      if (periodic) {
        c -= (hi - lo) * std::floor((c - lo) / (hi - lo));  // periodic wrap into [lo, hi)
        if (c >= hi) c = lo;  // -tiny + period rounds to hi
      } else if (!(c > lo && c < hi)) {
        std::ostringstream m;
        m << "WCSPH: particle " << i << " crossed the wall " << (a == 0 ? "x = " : "y = ") << (c <= lo ? lo : hi)
          << " (now at " << x_(i, 0) << ", " << x_(i, 1) << ") at t = " << t_ + tau
          << ": the walls no longer hold the fluid (c too low for this flow, or time.dt too large)";
        throw std::runtime_error(m.str());
      }
    }
  }
}

void WcsphFluid::check_density() {
  const int N = lat_.size();
  int worst = 0;
  double dv = 0;
  for (int i = 0; i < N; ++i) {
    const double e = std::fabs(rho_[i] / rho0_ - 1.0);
    if (e > dv || !std::isfinite(e)) { dv = e; worst = i; }
  }
  dvar_ = dv;
  if (dv > dvar_max_) { dvar_max_ = dv; t_dvar_max_ = t_; }
  if (!(dv <= opt_.max_density_variation)) {
    std::ostringstream m;
    m << "WCSPH: density variation |rho/rho0 - 1| = " << dv << " at particle " << worst << " (" << x_(worst, 0)
      << ", " << x_(worst, 1) << ") exceeds " << opt_.max_density_variation << " at t = " << t_
      << ": a blow-up (speed of sound c = " << c_ << " too low for this flow, or time.dt too large)";
    throw std::runtime_error(m.str());
  }
}

void WcsphFluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows() || u0.cols() != 2) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  xsph_velocity();  // with the neighbours of the current positions
}

void WcsphFluid::step(const Mat2& F) {
  ++revision_;
  const double dt = prm_.dt;
  if (F.rows() != u_.rows()) throw std::invalid_argument("WCSPH: force field has the wrong size");
  // C Eq. (19), force term: dt <= 0.25 sqrt(h / |f|), f = F / rho0 the external acceleration
  const double fmax = F.rowwise().norm().maxCoeff() / rho0_;
  if (fmax > 0 && dt > 0.25 * std::sqrt(W_.h / fmax)) {
    std::ostringstream m;
    m << "time.dt = " << dt << " exceeds the force limit 0.25 sqrt(h/|f|) = " << 0.25 * std::sqrt(W_.h / fmax)
      << " of Coelho et al. Eq. (19) (|f| = max |F|/rho = " << fmax << ")";
    throw std::invalid_argument(m.str());
  }
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(0.5 * dt);  // V Eq. (22): x^{n+1/2} = x^n + dt/2 v^n (XSPH velocity, V Eq. 21)
  }
  {
    ScopedTimer tm(prof_, k_neigh_);
    find_neighbours();  // at x^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_rho_);
    summation_density();  // V Eq. (11) and the EOS, V Eq. (20) / C Eq. (3)
  }
  {
    ScopedTimer tm(prof_, k_force_);
    accelerations(F);  // a^{n+1/2}: C Eq. (17) + F / rho (+ C Eq. 20)
    u_ += dt * a_;     // V Eq. (22): v^{n+1} = v^n + dt a^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_xsph_);
    xsph_velocity();  // V Eq. (21) of v^{n+1}, neighbours of x^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(0.5 * dt);  // V Eq. (22): x^{n+1} = x^{n+1/2} + dt/2 v^{n+1}
  }
  t_ += dt;
  ++n_;
  check_density();
}

double WcsphFluid::kinetic_energy() const { return 0.5 * m_ * u_.squaredNorm(); }

double WcsphFluid::max_abs_divergence() const {
  // (div u)_i = sum_j (m/rho_j) (u_i + u_j) . (x_i - x_j) F_ij  (Eq. 30 form), walls carry u_w
  const int N = lat_.size();
  const double V_wall = m_ / rho0_;
  const Pairs& P = pairs_;
  Vec d = Vec::Zero(N);
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double uj = j < N ? u_(j, 0) : uw_(j - N, 0), vj = j < N ? u_(j, 1) : uw_(j - N, 1);
    const double t = ((u_(i, 0) + uj) * P.rx[k] + (u_(i, 1) + vj) * P.ry[k]) * P.F[k];
    d[i] += (j < N ? V_[j] : V_wall) * t;
    if (j < N) d[j] -= V_[i] * t;  // x_ji = -x_ij
  }
  return d.cwiseAbs().maxCoeff();
}

std::vector<std::string> WcsphFluid::describe() const {
  const WcsphParams& w = prm_.wcsph;
  std::vector<std::string> lines;
  {
    std::ostringstream m;
    m << "WCSPH (Morris et al. 1997; Vukcevic et al. 2012; Coelho et al.): " << lat_.nx << " x " << lat_.ny << " = "
      << size() << " moving particles, " << xw_.rows() << " fixed virtual wall particles"
      << (opt_.morris_extrapolation ? " (Morris extrapolated velocity)" : " (wall velocity)")
      << (lj_ ? " + Lennard-Jones repulsion (C Eq. 20)" : "") << ", h = " << W_.h << " (" << prm_.h_over_dx
      << " (dx+dy)/2), " << static_cast<double>(nbrs_total_) / ((n_ + 1.0) * size())
      << " neighbours per particle (mean over the run)";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "EOS ";
    if (eos_ == Eos::Morris) m << "p = c^2 rho (Morris, V Eq. 20; background pressure c^2 rho0 = " << p_wall_ << ")";
    else m << "Tait (C Eq. 3), gamma = " << w.gamma;
    m << ", c = " << c_
      << (w.c > 0 ? " (wcsph.c)" : " (wcsph.c = 0: 10 u_scale, C Eq. 5 scaling for ~1% density variation)")
      << ", rho0 = " << rho0_ << ", m = rho0 / sum_j W_ij = " << m_ << " (lattice kernel sum S dx dy = "
      << lattice_kernel_sum() << ")";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "leapfrog V Eq. (22) (drift-kick-drift), XSPH eps = " << w.xsph << ", dt = " << prm_.dt
      << " (C Eq. 19 limit " << dt_limit_ << ": 0.25 h/c = " << 0.25 * W_.h / c_
      << ", 0.125 h^2/nu = " << 0.125 * W_.h * W_.h / nu() << ")";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "density variation max |rho/rho0 - 1| = " << dvar_max_ << " (at t = " << t_dvar_max_ << "), now "
      << dvar_ << " (papers aim below 0.03; blow-up above " << opt_.max_density_variation << ")";
    lines.push_back(m.str());
  }
  return lines;
}

std::vector<std::pair<std::string, double>> WcsphFluid::figures() const {
  return {{"max_density_variation", dvar_max_},
          {"density_variation", dvar_},
          {"sound_speed", c_},
          {"dt_limit_coelho", dt_limit_},
          {"wall_particles", static_cast<double>(xw_.rows())},
          {"neighbours_per_particle", static_cast<double>(nbrs_last_) / size()},
          {"lattice_kernel_sum", lattice_kernel_sum()}};
}

NamedArrays WcsphFluid::state() const {
  Eigen::MatrixXd clock(1, 5);
  clock << t_, static_cast<double>(n_), dvar_, dvar_max_, t_dvar_max_;
  return {{"x", x_}, {"x_eval", x_eval_}, {"u", u_}, {"u_hat", u_hat_}, {"clock", clock}};
}

void WcsphFluid::restore(const NamedArrays& state) {
  ++revision_;
  const int N = size();
  x_ = state_entry(state, "x_eval", N, 2);
  find_neighbours();  // the neighbours and densities of the last evaluation, exactly
  summation_density();
  x_ = state_entry(state, "x", N, 2);
  u_ = state_entry(state, "u", N, 2);
  u_hat_ = state_entry(state, "u_hat", N, 2);
  const Eigen::MatrixXd& clock = state_entry(state, "clock", 1, 5);
  t_ = clock(0, 0);
  n_ = static_cast<long>(clock(0, 1));
  dvar_ = clock(0, 2);
  dvar_max_ = clock(0, 3);
  t_dvar_max_ = clock(0, 4);
}

double WcsphFluid::setup_seconds(const std::string& what) const {
  for (const auto& [k, s] : setup_)
    if (k == what) return s;
  return 0.0;
}

}  // namespace sphib
