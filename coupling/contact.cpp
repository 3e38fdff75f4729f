#include "coupling/contact.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

// A cell list over the markers of several membranes: cells of at least `radius`, markers sorted by
// cell (counting sort), and every unordered pair of markers of different membranes closer than
// `radius` visited once (each cell with itself and four of its neighbours: the half stencil).
// Coordinates wrap along periodic axes and clamp to the edge cells along bounded ones; distances are
// by minimum image.
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
      // The stencil wraps only with 3 cells or more (with 1 or 2 a wrapped neighbour is a cell the
      // stencil visits anyway; minimum image then finds the nearest copy).
      wrap_[a] = per[a] && nc_[a] >= 3;
    }
  }

  // Sorts the markers X (membrane k's rows [start[k], start[k+1])) into the cells; returns the
  // membrane of every marker.
  const std::vector<int>& bin(const Mat2& X, const std::vector<int>& start) {
    const int n = static_cast<int>(X.rows()), ncell = nc_[0] * nc_[1];
    owner_.resize(n);
    for (size_t k = 0; k + 1 < start.size(); ++k)
      for (int i = start[k]; i < start[k + 1]; ++i) owner_[i] = static_cast<int>(k);
    head_.assign(ncell + 1, 0);
    cell_.resize(n);
    items_.resize(n);
    for (int i = 0; i < n; ++i) {
      cell_[i] = cell_of(X(i, 0), 0) + nc_[0] * cell_of(X(i, 1), 1);
      ++head_[cell_[i] + 1];
    }
    for (int c = 0; c < ncell; ++c) head_[c + 1] += head_[c];
    next_.assign(head_.begin(), head_.end() - 1);
    for (int i = 0; i < n; ++i) items_[next_[cell_[i]]++] = i;
    return owner_;
  }

  // f(i, j, dx, dy, r2) for every pair of markers i, j of different membranes with
  // r2 = |X_i - X_j|^2 < radius^2 (dx, dy = X_i - X_j by minimum image), each pair once.
  template <class F>
  void for_each_pair(const Mat2& X, F&& f) const {
    static constexpr int kStencil[5][2] = {{0, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    const double r2max = radius_ * radius_;
    for (int cy = 0; cy < nc_[1]; ++cy)
      for (int cx = 0; cx < nc_[0]; ++cx) {
        const int c = cx + nc_[0] * cy;
        if (head_[c] == head_[c + 1]) continue;
        for (const auto& s : kStencil) {
          const int nx = neighbour(cx + s[0], 0), ny = neighbour(cy + s[1], 1);
          if (nx < 0 || ny < 0) continue;
          const int e = nx + nc_[0] * ny;  // (never c but for the offset (0, 0): see wrap_)
          for (int a = head_[c]; a < head_[c + 1]; ++a) {
            const int i = items_[a];
            for (int b = (e == c ? a + 1 : head_[e]); b < head_[e + 1]; ++b) {
              const int j = items_[b];
              if (owner_[i] == owner_[j]) continue;  // the membrane's own law holds its markers
              double dx = X(i, 0) - X(j, 0), dy = X(i, 1) - X(j, 1);
              if (d_.periodic_x) dx -= d_.Lx() * std::round(dx / d_.Lx());
              if (d_.periodic_y) dy -= d_.Ly() * std::round(dy / d_.Ly());
              const double r2 = dx * dx + dy * dy;
              if (r2 < r2max) f(i, j, dx, dy, r2);
            }
          }
        }
      }
  }

 private:
  int cell_of(double c, int axis) const {
    const double lo = axis == 0 ? d_.x0 : d_.y0, L = axis == 0 ? d_.Lx() : d_.Ly();
    const bool per = axis == 0 ? d_.periodic_x : d_.periodic_y;
    double u = c - lo;
    if (per) u -= L * std::floor(u / L);
    const int k = static_cast<int>(std::floor(u / h_[axis]));
    return std::clamp(k, 0, nc_[axis] - 1);
  }
  // The neighbour's index along an axis, wrapped, or -1 past a bounded edge (or where the stencil does
  // not wrap).
  int neighbour(int k, int axis) const {
    const int n = nc_[axis];
    if (k >= 0 && k < n) return k;
    if (!wrap_[axis]) return -1;
    return k < 0 ? k + n : k - n;
  }

  Domain d_;
  double radius_;
  int nc_[2];
  double h_[2];
  bool wrap_[2];
  std::vector<int> head_, next_, cell_, items_, owner_;
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
  cells_->for_each_pair(X, [&](int i, int j, double dx, double dy, double r2) {
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
  cells.for_each_pair(X, [&](int, int, double, double, double r2) { least = std::min(least, r2); });
  return std::sqrt(least);
}

}  // namespace sphib
