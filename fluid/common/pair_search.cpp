#include "fluid/common/pair_search.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

PairSearch::PairSearch(const Domain& d, const CubicSplineKernel& W, int N, const Mat2& fixed)
    : d_(d), W_(W), N_(N) {
  const char* axis[2] = {"x", "y"};
  const bool periodic[2] = {d.periodic_x, d.periodic_y};
  const double length[2] = {d.Lx(), d.Ly()};
  for (int a = 0; a < 2; ++a)
    if (periodic[a] && !(W_.support() < 0.5 * length[a])) {
      std::ostringstream m;
      m << "kernel support 2h = " << W_.support() << " must be below half the periodic length L" << axis[a] << " = "
        << length[a];
      throw std::invalid_argument(m.str());
    }
  const int M = static_cast<int>(fixed.rows());
  all_.resize(N + M, 2);
  if (M) all_.bottomRows(M) = fixed;
  // Cells: along a non-periodic axis the box grows by two supports; the cell width is the largest
  // division of the box not below 2h.
  const double lo[2] = {d.x0, d.y0}, hi[2] = {d.x1, d.y1};
  for (int a = 0; a < 2; ++a) {
    const double grow = periodic[a] ? 0.0 : 2.0 * W_.support();
    lo_[a] = lo[a] - grow;
    const double L = hi[a] - lo[a] + 2.0 * grow;
    nc_[a] = std::max(1, static_cast<int>(std::floor(L / W_.support() * (1.0 - 1e-12))));
    cell_[a] = L / nc_[a];
  }
  cell_start_.assign(nc_[0] * nc_[1] + 1, 0);
  moving_.assign(nc_[0] * nc_[1], 0);
  cell_of_.resize(N + M);
  cell_items_.resize(N + M);
  cell_x_.resize(N + M);
  cell_y_.resize(N + M);
}

void PairSearch::find(const Mat2& x, ParticlePairs& P) {
  const int N = N_, T = static_cast<int>(all_.rows());
  const bool periodic[2] = {d_.periodic_x, d_.periodic_y};
  const double period[2] = {d_.Lx(), d_.Ly()};
  all_.topRows(N) = x;
  // Bin every particle (counting sort, stable in the index).
  const int ncell = nc_[0] * nc_[1];
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  std::fill(moving_.begin(), moving_.end(), 0);
  for (int p = 0; p < T; ++p) {
    int k[2];
    for (int a = 0; a < 2; ++a) {
      k[a] = static_cast<int>(std::floor((all_(p, a) - lo_[a]) / cell_[a]));
      if (periodic[a]) k[a] = ((k[a] % nc_[a]) + nc_[a]) % nc_[a];
      else k[a] = std::min(std::max(k[a], 0), nc_[a] - 1);  // a particle outside: the edge cell
    }
    cell_of_[p] = k[0] + nc_[0] * k[1];
    ++cell_start_[cell_of_[p] + 1];
    if (p < N) ++moving_[cell_of_[p]];
  }
  for (int c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  for (int p = 0; p < T; ++p) cell_items_[cell_start_[cell_of_[p]]++] = p;
  for (int c = ncell; c > 0; --c) cell_start_[c] = cell_start_[c - 1];  // back to the starts
  cell_start_[0] = 0;
  for (int k = 0; k < T; ++k) {  // positions in cell order: the pair loops stream through memory
    cell_x_[k] = all_(cell_items_[k], 0);
    cell_y_[k] = all_(cell_items_[k], 1);
  }

  for (auto* v : {&P.i, &P.j}) v->clear();
  for (auto* v : {&P.rx, &P.ry, &P.r, &P.W, &P.F}) v->clear();
  const double r2max = W_.support() * W_.support();
  // W and F = (1/r) dW/dr of kernels/cubic_spline.hpp, from q = r/h without its divisions by h
  const double inv_h = 1.0 / W_.h, w0 = W_.w0, w6 = W_.w0 / 6.0, f0 = W_.w0 * inv_h * inv_h;
  long nbrs = 0;  // neighbours summed over the moving particles
  auto add = [&](int a, int b, double dx, double dy, double r2) {
    int i = a, j = b;
    if (a >= N) { i = b; j = a; dx = -dx; dy = -dy; }  // i is the moving particle
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
          // a cell lists its moving particles first (the sort is stable in the index): a fixed
          // point meets only those (fixed with fixed is no pair)
          const int kb_end = a < N ? cell_start_[c2 + 1] : cell_start_[c2] + moving_[c2];
          for (int kb = self ? ka + 1 : cell_start_[c2]; kb < kb_end; ++kb) {
            const double dx = ax - cell_x_[kb], dy = ay - cell_y_[kb];
            const double r2 = dx * dx + dy * dy;
            if (r2 >= r2max) continue;
            const int b = cell_items_[kb];
            if (a < N || b < N) add(a, b, dx, dy, r2);  // not fixed with fixed
          }
        }
      }
    }
  nbrs_ = nbrs;
}

}  // namespace sphib
