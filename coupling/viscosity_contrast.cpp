#include "coupling/viscosity_contrast.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {

constexpr double kSnap = 1e-12;  // fractions this close to 0 or 1 are 0 or 1 (round-off of the sums)

// The lattice coordinate of x along one axis, in cell widths: cell a (its particle's column or row
// before wrapping) holds [a, a + 1). Eq. (68): particles at x0 + i dx along a periodic axis, at
// x0 + (i + 1/2) dx between walls.
double cell_coordinate(double x, double x0, double d, bool periodic) { return (x - x0) / d + (periodic ? 0.5 : 0.0); }

}  // namespace

void cell_fractions(const Lattice& L, const Mat2& X, CellFractions& out, CellFractionWork& w) {
  const Domain& D = L.domain;
  const int nb = static_cast<int>(X.rows());
  out.index.clear();
  out.I.clear();
  out.area = 0.0;
  if (nb < 3) return;
  // (u, v): the markers in cell widths; the bounding box of their cells; the orientation (shoelace)
  auto U = [&](int k) { return cell_coordinate(X(k, 0), D.x0, L.dx, D.periodic_x); };
  auto V = [&](int k) { return cell_coordinate(X(k, 1), D.y0, L.dy, D.periodic_y); };
  double umin = U(0), umax = umin, vmin = V(0), vmax = vmin, twice_area = 0.0;
  for (int k = 0; k < nb; ++k) {
    const int k1 = k + 1 == nb ? 0 : k + 1;
    umin = std::min(umin, U(k)), umax = std::max(umax, U(k));
    vmin = std::min(vmin, V(k)), vmax = std::max(vmax, V(k));
    twice_area += U(k) * V(k1) - U(k1) * V(k);
  }
  if (!std::isfinite(twice_area)) throw std::runtime_error("indicator: marker positions are not finite");
  const int a0 = static_cast<int>(std::floor(umin)), a1 = static_cast<int>(std::floor(umax));
  const int b0 = static_cast<int>(std::floor(vmin)), b1 = static_cast<int>(std::floor(vmax));
  auto check_axis = [](int lo, int hi, int n, bool periodic, const char* axis) {
    std::ostringstream m;
    if (periodic && hi - lo + 1 > n)
      m << "indicator: the membrane spans a whole period along " << axis << " (" << hi - lo + 1 << " cells of " << n << ")";
    else if (!periodic && (lo < 0 || hi >= n))
      m << "indicator: the membrane leaves the domain across a wall along " << axis;
    else return;
    throw std::runtime_error(m.str());
  };
  check_axis(a0, a1, L.nx, D.periodic_x, "x");
  check_axis(b0, b1, L.ny, D.periodic_y, "y");
  const int W = a1 - a0 + 1, H = b1 - b0 + 1;
  w.part.assign(static_cast<size_t>(W) * H, 0.0);
  w.full.assign(static_cast<size_t>(W) * H, 0.0);

  // Each edge, cut where it crosses the lines u = integer and v = integer, into pieces inside one
  // cell (a, b): part(a, b) += (mean u of the piece - a) dv (the area between the piece and the
  // cell's left side), full(a, b) += dv (the height every cell left of it in row b receives).
  double t[64];
  for (int k = 0; k < nb; ++k) {
    const int k1 = k + 1 == nb ? 0 : k + 1;
    const double u0 = U(k), v0 = V(k), u1 = U(k1), v1 = V(k1), du = u1 - u0, dv = v1 - v0;
    if (dv == 0.0) continue;  // horizontal: no height, no area
    int n = 0;
    t[n++] = 0.0;
    for (double c = std::floor(std::min(u0, u1)) + 1; c < std::max(u0, u1) && n < 62; c += 1) t[n++] = (c - u0) / du;
    for (double c = std::floor(std::min(v0, v1)) + 1; c < std::max(v0, v1) && n < 62; c += 1) t[n++] = (c - v0) / dv;
    if (n >= 62) throw std::runtime_error("indicator: a membrane edge crosses more than 60 lattice lines");
    std::sort(t + 1, t + n);
    t[n++] = 1.0;
    double ua = u0, va = v0;
    for (int s = 1; s < n; ++s) {
      const double ub = s + 1 == n ? u1 : u0 + t[s] * du, vb = s + 1 == n ? v1 : v0 + t[s] * dv;
      const double tm = 0.5 * (t[s - 1] + t[s]);
      const int a = static_cast<int>(std::floor(u0 + tm * du)), b = static_cast<int>(std::floor(v0 + tm * dv));
      const double h = vb - va;
      const size_t c = static_cast<size_t>(b - b0) * W + (a - a0);
      w.part[c] += (0.5 * (ua + ub) - a) * h;
      w.full[c] += h;
      ua = ub, va = vb;
    }
  }

  // Each row swept from the right: I(a) = part(a) + the heights of the pieces right of a.
  const double sign = twice_area < 0 ? -1.0 : 1.0;
  for (int b = b0; b <= b1; ++b) {
    const int row = L.nx * (D.periodic_y ? ((b % L.ny) + L.ny) % L.ny : b);
    double right = 0.0;
    for (int a = a1; a >= a0; --a) {
      const size_t c = static_cast<size_t>(b - b0) * W + (a - a0);
      double I = sign * (w.part[c] + right);
      right += w.full[c];
      if (I < kSnap) continue;
      if (I > 1.0 - kSnap) I = 1.0;
      out.index.push_back(row + (D.periodic_x ? ((a % L.nx) + L.nx) % L.nx : a));
      out.I.push_back(I);
      out.area += I;
    }
  }
  out.area *= L.dx * L.dy;
}

ViscosityContrast::ViscosityContrast(const Lattice& L, std::vector<double> lambda)
    : L_(L), lambda_(std::move(lambda)), I_(lambda_.size()) {
  for (size_t k = 0; k < lambda_.size(); ++k)
    if (!(lambda_[k] > 0) || !std::isfinite(lambda_[k]))
      throw std::invalid_argument("membrane " + std::to_string(k) + ": viscosity_ratio must be positive and finite (got " +
                                  std::to_string(lambda_[k]) + ")");
  m_ = m_new_ = Vec::Ones(L.size());
  in_new_.assign(L.size(), 0);
}

int ViscosityContrast::update(const std::vector<const Mat2*>& X, FluidSolver& fluid) {
  if (X.size() != lambda_.size()) throw std::logic_error("viscosity contrast: one marker set per membrane");
  // m_new = 1 + sum_k (lambda_k - 1) I_k on the new support
  support_new_.clear();
  for (size_t k = 0; k < X.size(); ++k) {
    if (lambda_[k] == 1.0) continue;
    try {
      cell_fractions(L_, *X[k], I_[k], work_);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("membrane " + std::to_string(k) + ": " + e.what());
    }
    const double d = lambda_[k] - 1.0;
    const CellFractions& f = I_[k];
    for (size_t q = 0; q < f.index.size(); ++q) {
      const int i = f.index[q];
      if (!in_new_[i]) {
        in_new_[i] = 1;
        support_new_.push_back(i);
      }
      m_new_[i] += d * f.I[q];
    }
  }
  // The changes: on the new support, and where the old one is left (back to 1)
  at_.clear();
  val_.clear();
  for (int i : support_)
    if (!in_new_[i] && m_[i] != 1.0) {
      at_.push_back(i);
      val_.push_back(1.0);
      m_[i] = 1.0;
    }
  for (int i : support_new_) {
    if (m_new_[i] != m_[i]) {
      at_.push_back(i);
      val_.push_back(m_new_[i]);
      m_[i] = m_new_[i];
    }
    m_new_[i] = 1.0;
    in_new_[i] = 0;
  }
  support_.swap(support_new_);
  if (!at_.empty()) fluid.set_viscosity(at_.data(), val_.data(), static_cast<int>(at_.size()));
  return static_cast<int>(at_.size());
}

}  // namespace sphib
