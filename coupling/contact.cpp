#include "coupling/contact.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

// A cell list over the markers of several membranes: cells of at least `radius`, markers sorted by
// cell (counting sort, their coordinates and membranes copied in that order), and every unordered
// pair of markers of different membranes closer than `radius` visited once: each occupied cell with
// itself and four of its neighbours (the half stencil). Coordinates wrap along periodic axes (a
// neighbour across the period is shifted by it) and clamp to the edge cells along bounded ones.
class MarkerCells {
 public:
  MarkerCells(const Domain& d, double radius) : d_(d), radius_(radius) {
    const double L[2] = {d.Lx(), d.Ly()};
    const bool per[2] = {d.periodic_x, d.periodic_y};
    for (int a = 0; a < 2; ++a) {
      if (per[a] && !(2.0 * radius < L[a]))
        throw std::invalid_argument("contact: the search radius must be below half the periodic period");
      // at least one cell; no more than 4096 along an axis (a very short range then visits more pairs)
      nc_[a] = static_cast<int>(std::clamp(std::floor(L[a] / radius), 1.0, 4096.0));
      h_[a] = L[a] / nc_[a];
      inv_h_[a] = nc_[a] / L[a];  // (a cell a rounding narrower than h_ would still be at least radius: nc_ floors)
      lo_[a] = a == 0 ? d.x0 : d.y0;
      L_[a] = L[a];
      per_[a] = per[a];
      // The stencil wraps with 3 cells or more; with 1 or 2 a wrapped neighbour is a cell it visits
      // anyway, and the minimum image finds the nearest copy instead.
      wrap_[a] = per[a] && nc_[a] >= 3;
    }
  }

  // Sorts the markers X (membrane k's rows [start[k], start[k+1])) into the cells; returns the
  // membrane of every marker. O(markers): only the occupied cells are counted, given their ranges
  // (in the order they were first met) and cleared again.
  const std::vector<int>& bin(const Mat2& X, const std::vector<int>& start) {
    const int n = static_cast<int>(X.rows());
    owner_.resize(n);
    for (size_t k = 0; k + 1 < start.size(); ++k)
      for (int i = start[k]; i < start[k + 1]; ++i) owner_[i] = static_cast<int>(k);
    for (int c : occupied_) count_[c] = fill_[c] = 0;  // the last bin's cells
    if (count_.empty()) {
      count_.assign(static_cast<size_t>(nc_[0]) * nc_[1], 0);
      first_.assign(count_.size(), 0);
      fill_.assign(count_.size(), 0);
      only_.assign(count_.size(), -1);
    }
    cell_.resize(n);
    wx_.resize(n);
    wy_.resize(n);
    occupied_.clear();
    for (int i = 0; i < n; ++i) {
      wx_[i] = wrapped(X(i, 0), 0);
      wy_[i] = wrapped(X(i, 1), 1);
      const int c = cell_[i] = cell_of(wx_[i], 0) + nc_[0] * cell_of(wy_[i], 1);
      if (count_[c]++ == 0) {
        occupied_.push_back(c);
        only_[c] = owner_[i];
      } else if (only_[c] != owner_[i]) {
        only_[c] = -1;  // markers of several membranes
      }
    }
    int next = 0;
    for (int c : occupied_) first_[c] = next, next += count_[c];
    items_.resize(n);
    sx_.resize(n);
    sy_.resize(n);
    so_.resize(n);
    for (int i = 0; i < n; ++i) {  // stable in i within a cell
      const int c = cell_[i], a = first_[c] + fill_[c]++;
      items_[a] = i;
      sx_[a] = wx_[i];
      sy_[a] = wy_[i];
      so_[a] = owner_[i];
    }
    return owner_;
  }

  // f(i, j, dx, dy, r2) for every pair of markers i, j of different membranes with
  // r2 = |X_i - X_j|^2 < radius^2 (dx, dy = X_i - X_j by minimum image), each pair once.
  template <class F>
  void for_each_pair(F&& f) const {
    static constexpr int kStencil[5][2] = {{0, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    const double r2max = radius_ * radius_;
    for (int c : occupied_) {
      const int cx = c % nc_[0], cy = c / nc_[0];
      const int a0 = first_[c], a1 = a0 + count_[c];
      for (const auto& s : kStencil) {
        int nx = cx + s[0], ny = cy + s[1];
        double shx = 0.0, shy = 0.0;  // the neighbour's coordinates, moved across the period
        if (!neighbour(nx, shx, 0) || !neighbour(ny, shy, 1)) continue;
        const int e = nx + nc_[0] * ny;  // (e == c only for the offset (0, 0): see wrap_)
        if (count_[e] == 0 || (only_[c] >= 0 && only_[e] == only_[c])) continue;  // empty, or one membrane's
        const int b1 = first_[e] + count_[e];
        for (int a = a0; a < a1; ++a) {
          const double xa = sx_[a] - shx, ya = sy_[a] - shy;
          const int oa = so_[a];
          for (int b = (e == c ? a + 1 : first_[e]); b < b1; ++b) {
            if (so_[b] == oa) continue;  // the membrane's own law holds its markers
            double dx = xa - sx_[b], dy = ya - sy_[b];
            if (per_[0] && !wrap_[0]) dx -= L_[0] * std::round(dx / L_[0]);
            if (per_[1] && !wrap_[1]) dy -= L_[1] * std::round(dy / L_[1]);
            const double r2 = dx * dx + dy * dy;
            if (r2 < r2max) f(items_[a], items_[b], dx, dy, r2);
          }
        }
      }
    }
  }

 private:
  double wrapped(double c, int a) const {
    if (!per_[a] || (c >= lo_[a] && c < lo_[a] + L_[a])) return c;  // (most markers: no floor, a libm call)
    c -= L_[a] * std::floor((c - lo_[a]) / L_[a]);
    return c >= lo_[a] + L_[a] ? lo_[a] : c;
  }
  int cell_of(double c, int a) const {  // (truncation is the floor for c >= lo; clamped below)
    const double u = (c - lo_[a]) * inv_h_[a];
    return u < 0 ? 0 : std::min(static_cast<int>(u), nc_[a] - 1);
  }
  // The neighbour's index k along axis a, wrapped (shift: the period it moved by), or false past a
  // bounded edge (or where the stencil does not wrap).
  bool neighbour(int& k, double& shift, int a) const {
    const int n = nc_[a];
    if (k >= 0 && k < n) return true;
    if (!wrap_[a]) return false;
    shift = k < 0 ? -L_[a] : L_[a];
    k = k < 0 ? k + n : k - n;
    return true;
  }

  Domain d_;
  double radius_;
  int nc_[2];
  double h_[2], inv_h_[2], lo_[2], L_[2];
  bool per_[2], wrap_[2];
  std::vector<int> count_, first_, fill_;  // by cell (zero but at the occupied cells)
  std::vector<int> only_;                  // by occupied cell: the one membrane of its markers, or -1
  std::vector<int> cell_, items_, owner_, so_, occupied_;
  std::vector<double> wx_, wy_, sx_, sy_;
};

double morse_repulsion(const ContactParams& p, double r) {
  if (!(r < p.range)) return 0.0;
  const double beta = p.beta > 0 ? p.beta : 2.0 / p.range;
  const double e = std::exp(beta * (p.range - r));
  return 2.0 * beta * p.strength * (e * e - e);  // phi = -dU/dr = 2 beta De [e^{2 beta (r0 - r)} - e^{beta (r0 - r)}]
}

ContactForce::ContactForce(const ContactParams& p, const Domain& d) : p_(p), d_(d) {
  auto refuse = [](const char* key, const std::string& why) {
    throw std::invalid_argument(std::string("contact.") + key + " " + why);
  };
  if (!(p.strength >= 0) || !std::isfinite(p.strength)) refuse("strength", "must be >= 0 and finite");
  if (!(p.range > 0) || !std::isfinite(p.range)) refuse("range", "must be positive and finite");
  if (!(p.beta >= 0) || !std::isfinite(p.beta)) refuse("beta", "must be >= 0 and finite");
  if ((d.periodic_x && !(3.0 * p.range < d.Lx())) || (d.periodic_y && !(3.0 * p.range < d.Ly()))) {
    std::ostringstream m;
    m << "= " << p.range << " must be below a third of the periodic period";
    refuse("range", m.str());
  }
  cells_ = std::make_unique<MarkerCells>(d, p.range);
}

ContactForce::~ContactForce() = default;

void ContactForce::add(const Mat2& X, const std::vector<int>& start, const std::vector<double>& ds, Mat2& f) {
  least_ = std::numeric_limits<double>::infinity();
  pairs_ = 0;
  const std::vector<int>& owner = cells_->bin(X, start);
  cells_->for_each_pair([&](int i, int j, double dx, double dy, double r2) {
    const double r = std::sqrt(r2);
    least_ = std::min(least_, r);
    ++pairs_;
    if (!(r > 0)) return;  // coincident markers: no direction (the pairs around them push)
    const double phi = morse_repulsion(p_, r) / r;  // phi(r) (X_i - X_j)/r per unit length of each
    const double fx = phi * dx, fy = phi * dy;
    const double dsi = ds[owner[i]], dsj = ds[owner[j]];
    f(i, 0) += fx * dsj;  // on i, from membrane j's element ds_j
    f(i, 1) += fy * dsj;
    f(j, 0) -= fx * dsi;  // on j, the opposite (equal and opposite element forces)
    f(j, 1) -= fy * dsi;
  });
  least_so_far_ = std::min(least_so_far_, least_);
  if (!p_.walls) return;
  // A wall at distance d pushes with r0 phi(d) along its inward normal.
  const int n = static_cast<int>(X.rows());
  const double r0 = p_.range;
  if (!d_.periodic_y)
    for (int i = 0; i < n; ++i) {
      const double lo = X(i, 1) - d_.y0, hi = d_.y1 - X(i, 1);
      if (lo < r0) f(i, 1) += r0 * morse_repulsion(p_, std::max(lo, 0.0));
      if (hi < r0) f(i, 1) -= r0 * morse_repulsion(p_, std::max(hi, 0.0));
    }
  if (!d_.periodic_x)
    for (int i = 0; i < n; ++i) {
      const double lo = X(i, 0) - d_.x0, hi = d_.x1 - X(i, 0);
      if (lo < r0) f(i, 0) += r0 * morse_repulsion(p_, std::max(lo, 0.0));
      if (hi < r0) f(i, 0) -= r0 * morse_repulsion(p_, std::max(hi, 0.0));
    }
}

double least_marker_distance(const Mat2& X, const std::vector<int>& start, const Domain& d, double radius) {
  MarkerCells cells(d, radius);
  cells.bin(X, start);
  double least = std::numeric_limits<double>::infinity();
  cells.for_each_pair([&](int, int, double, double, double r2) { least = std::min(least, r2); });
  return std::sqrt(least);
}

}  // namespace sphib
