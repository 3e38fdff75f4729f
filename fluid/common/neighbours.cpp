#include "fluid/common/neighbours.hpp"

#include "kernels/cubic_spline.hpp"
#include "kernels/lanes.hpp"  // sqrt2

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

CellGrid::CellGrid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, bool px, bool py, double min_cell)
    : lo_(lo), period_(hi - lo) {
  periodic_[0] = px;
  periodic_[1] = py;
  for (int a = 0; a < 2; ++a) {
    nc_[a] = std::max(1, static_cast<int>(std::floor(period_[a] / min_cell * (1.0 + 1e-12))));
    h_[a] = period_[a] / nc_[a];  // >= min_cell; along a periodic axis cells tile the period exactly
  }
}

void CellGrid::use_lattice(const Lattice& L) {
  if (L.domain.periodic_x != periodic_[0] || L.domain.periodic_y != periodic_[1])
    throw std::logic_error("CellGrid::use_lattice: the lattice's periodic axes differ from the grid's");
  lat_.n[0] = L.nx;
  lat_.n[1] = L.ny;
  lat_.x0[0] = L.domain.x0;
  lat_.x0[1] = L.domain.y0;
  lat_.d[0] = L.dx;
  lat_.d[1] = L.dy;
  lat_.o[0] = L.domain.periodic_x ? 0.0 : 0.5;  // Eq. (68), as make_lattice
  lat_.o[1] = L.domain.periodic_y ? 0.0 : 0.5;
}

void NearPoints::reserve(int m) {
  if (m <= static_cast<int>(j.size())) return;
  const size_t size = std::max<size_t>(static_cast<size_t>(m), 2 * j.size());
  j.resize(size);
  for (auto* v : {&dx, &dy, &r2}) v->resize(size);
}

void CellGrid::gather_near(double qx, double qy, double radius, NearPoints& out, bool offsets) const {
  out.n = 0;
  if (lat_.n[0] == 0) {
    for_each_near(qx, qy, radius, [&](int j, double dx, double dy, double) {
      out.reserve(out.n + 2);
      out.j[out.n] = j;
      out.dx[out.n] = dx;
      out.dy[out.n] = dy;
      out.r2[out.n++] = dx * dx + dy * dy;
    });
    return out.reserve(out.n + 1);
  }
  // for_each_near's lattice loop over the query's box, and a count in place of its branch on r^2
  LatticeBox box;
  lattice_box(qx, qy, radius, box);
  const int ncol = box.ncol;
  out.reserve(ncol * box.nrow + 1);
  double cdx2[LatticeBox::kMax];
  for (int c = 0; c < ncol; ++c) cdx2[c] = box.cdx[c] * box.cdx[c];
  const double r2max = radius * radius;
  int* __restrict j = out.j.data();
  double* __restrict dx = out.dx.data();
  double* __restrict dy = out.dy.data();
  double* __restrict r2 = out.r2.data();
  int n = 0;
  for (int r = 0; r < box.nrow; ++r) {
    const double ry = box.ry[r], ry2 = ry * ry;
    const int row = box.base[r];
    for (int c = 0; c < ncol; ++c) {
      const double d2 = cdx2[c] + ry2;
      j[n] = row + box.col[c];
      if (offsets) {  // (a loop-invariant branch: the compiler makes two loops)
        dx[n] = box.cdx[c];
        dy[n] = ry;
      }
      r2[n] = d2;
      n += d2 < r2max;
    }
  }
  out.n = n;
}

namespace {
// i mod n in [0, n), without a division for the usual i in [-n, 2n)
inline int wrap_index(int i, int n) {
  if (i >= 0) return i < n ? i : (i < 2 * n ? i - n : i % n);
  return i >= -n ? i + n : ((i % n) + n) % n;
}
}  // namespace

void CellGrid::lattice_box(double qx, double qy, double radius, LatticeBox& box) const {
  lattice_box_rows<false>(qx, qy, radius, 0, 0, box);
}

void CellGrid::lattice_box(double qx, double qy, double radius, long base_lo, long base_hi, LatticeBox& box) const {
  lattice_box_rows<true>(qx, qy, radius, base_lo, base_hi, box);
}

// The whole box (Ranged false: its columns first, as they come) or only the rows with a base in
// [base_lo, base_hi) (Ranged: the rows first, the columns only when a row is kept).
template <bool Ranged>
void CellGrid::lattice_box_rows(double qx, double qy, double radius, long base_lo, long base_hi, LatticeBox& box) const {
  int lo[2], hi[2];
  lattice_range(qx, qy, radius, lo, hi);
  const int nx = lat_.n[0], ny = lat_.n[1];
  box.ncol = std::max(hi[0] - lo[0] + 1, 0);
  if (box.ncol > LatticeBox::kMax || hi[1] - lo[1] + 1 > LatticeBox::kMax)
    throw std::invalid_argument("CellGrid: a marker's query spans more than 256 lattice columns or rows");
  auto columns = [&] {
    const double x0 = lat_.x0[0], o = lat_.o[0], d = lat_.d[0];
    for (int c = 0; c < box.ncol; ++c) box.cdx[c] = qx - (x0 + (lo[0] + c + o) * d);
    int iw = periodic_[0] ? wrap_index(lo[0], nx) : lo[0];
    for (int c = 0; c < box.ncol; ++c, iw = iw + 1 == nx ? 0 : iw + 1) box.col[c] = iw;
  };
  if (!Ranged) columns();
  const double r2max = radius * radius;
  const double y0 = lat_.x0[1], oy = lat_.o[1], dy = lat_.d[1];
  int nrow = 0;
  int bw = periodic_[1] ? wrap_index(lo[1], ny) : lo[1];  // b wrapped, stepped along with b
  for (int b = lo[1]; b <= hi[1]; ++b, bw = bw + 1 == ny && periodic_[1] ? 0 : bw + 1) {
    const double ry = qy - (y0 + (b + oy) * dy);
    if (ry * ry >= r2max) continue;
    const int base = nx * bw;
    if (Ranged && (base < base_lo || base >= base_hi)) continue;
    box.base[nrow] = base;
    box.ry[nrow++] = ry;
  }
  box.nrow = nrow;
  if (Ranged && box.nrow > 0) columns();
}

void CellGrid::build(const Mat2& points) {
  lat_.n[0] = lat_.n[1] = 0;
  const int n = static_cast<int>(points.rows());
  const int ncell = nc_[0] * nc_[1];
  start_.assign(ncell + 1, 0);
  cell_.resize(n);
  items_.resize(n);
  x_.resize(n, 2);
  for (int j = 0; j < n; ++j) {
    cell_[j] = cell_of(wrapped(points(j, 0), 0), 0) + nc_[0] * cell_of(wrapped(points(j, 1), 1), 1);
    ++start_[cell_[j] + 1];
  }
  for (int c = 0; c < ncell; ++c) start_[c + 1] += start_[c];
  std::vector<int> next(start_.begin(), start_.end() - 1);
  for (int j = 0; j < n; ++j) {  // counting sort, stable in j
    const int k = next[cell_[j]]++;
    items_[k] = j;
    for (int a = 0; a < 2; ++a) x_(k, a) = wrapped(points(j, a), a);
  }
}

namespace {

void check_support(const Domain& d, double support) {
  if (d.periodic_x && !(support <= 0.5 * d.Lx())) {
    std::ostringstream m;
    m << "kernel support 2h = " << support << " must not exceed half the periodic length Lx = " << d.Lx();
    throw std::invalid_argument(m.str());
  }
  if (d.periodic_y && !(support <= 0.5 * d.Ly())) {
    std::ostringstream m;
    m << "kernel support 2h = " << support << " must not exceed half the periodic length Ly = " << d.Ly();
    throw std::invalid_argument(m.str());
  }
}

// The cells of the particles x and images (numbered N + k) that the pair search walks.
CellGrid pair_grid(const Domain& d, const Mat2& x, const Mat2& image_x, double support) {
  const int N = static_cast<int>(x.rows()), M = static_cast<int>(image_x.rows());
  Mat2 all(N + M, 2);
  all.topRows(N) = x;
  if (M) all.bottomRows(M) = image_x;
  // Bounded axes: the box grows by the support so images get cells of their own.
  Eigen::Vector2d lo(d.x0, d.y0), hi(d.x1, d.y1);
  if (!d.periodic_x) { lo[0] -= support; hi[0] += support; }
  if (!d.periodic_y) { lo[1] -= support; hi[1] += support; }
  CellGrid grid(lo, hi, d.periodic_x, d.periodic_y, support);
  grid.build(all);
  return grid;
}

// The pairs of particles r0 .. r1 - 1 appended to P (P.offset relative to r0: it has one entry
// more than the rows, P.offset[0] as P held before).
void gather_pairs(const CellGrid& grid, const Mat2& x, double support, int r0, int r1, PairList& P) {
  struct Near { int j; double rx, ry, r; };
  std::vector<Near> near;  // the pairs of one particle
  for (int i = r0; i < r1; ++i) {
    near.clear();
    grid.for_each_near(x(i, 0), x(i, 1), support, [&](int j, double dx, double dy, double r) {
      if (j != i) near.push_back({j, dx, dy, r});
    });
    // Sort each particle's pairs by j: a deterministic order, and a cache-friendly assembly.
    std::sort(near.begin(), near.end(), [](const Near& a, const Near& b) { return a.j < b.j; });
    for (const Near& n : near) {
      P.j.push_back(n.j);
      P.rx.push_back(n.rx);
      P.ry.push_back(n.ry);
      P.r.push_back(n.r);
    }
    P.offset.push_back(P.size());
  }
}

// Particle pairs of rows r0 .. (P's pairs from offset[0]): x_i - x_j from the lattice indices,
// (i_x - j_x) dx (minimum image), instead of a difference of rounded positions, so that every pair of
// one lattice offset carries the same bits and the operators' rows away from walls are exact
// translates (fluid/algebra/products.hpp).
void lattice_offsets(const Lattice& L, int r0, PairList& P) {
  const int N = L.size();
  const int rows = static_cast<int>(P.offset.size()) - 1;
  for (int q = 0; q < rows; ++q) {
    const int i = r0 + q;
    for (int k = P.offset[q]; k < P.offset[q + 1]; ++k) {
      const int j = P.j[k];
      if (j >= N) continue;  // an image: reflected positions, left as found
      int di = i % L.nx - j % L.nx, dj = i / L.nx - j / L.nx;
      if (L.domain.periodic_x) di -= L.nx * static_cast<int>(std::lround(static_cast<double>(di) / L.nx));
      if (L.domain.periodic_y) dj -= L.ny * static_cast<int>(std::lround(static_cast<double>(dj) / L.ny));
      P.rx[k] = di * L.dx;
      P.ry[k] = dj * L.dy;
      P.r[k] = std::sqrt(P.rx[k] * P.rx[k] + P.ry[k] * P.ry[k]);
    }
  }
}

}  // namespace

LatticePairs::LatticePairs(const Lattice& L, const Mat2& image_x, double support)
    : L_(L), support_(support), grid_((check_support(L.domain, support), pair_grid(L.domain, L.x, image_x, support))) {}

void LatticePairs::rows(int r0, int r1, PairList& P) const {
  P.offset.assign(1, 0);
  P.j.clear();
  P.rx.clear();
  P.ry.clear();
  P.r.clear();
  gather_pairs(grid_, L_.x, support_, r0, r1, P);
  lattice_offsets(L_, r0, P);
}

long LatticePairs::count() const {
  long n = 0;
  for (int i = 0; i < L_.size(); ++i)
    grid_.for_each_near(L_.x(i, 0), L_.x(i, 1), support_, [&](int j, double, double, double) { n += j != i; });
  return n;
}

PairList find_pairs(const Lattice& L, const Mat2& image_x, double support) {
  PairList P;
  find_pairs(L.domain, L.x, image_x, support, P);
  lattice_offsets(L, 0, P);
  // kept for the setup (EPSPH): no room left from the growth of the arrays (up to twice their size)
  P.j.shrink_to_fit();
  P.rx.shrink_to_fit();
  P.ry.shrink_to_fit();
  P.r.shrink_to_fit();
  return P;
}

void find_pairs(const Domain& d, const Mat2& x, const Mat2& image_x, double support, PairList& P) {
  check_support(d, support);
  const CellGrid grid = pair_grid(d, x, image_x, support);
  P.offset.assign(1, 0);
  P.offset.reserve(x.rows() + 1);
  P.j.clear();
  P.rx.clear();
  P.ry.clear();
  P.r.clear();
  gather_pairs(grid, x, support, 0, static_cast<int>(x.rows()), P);
}

VerletList::VerletList(const Domain& d, double reach, double skin_min, double skin_max)
    : d_(d), reach_(reach), skin_min_(std::max(0.0, skin_min)), skin_max_(std::max(skin_min_, skin_max)) {
  // Room for the skin: minimum image needs reach + skin <= half a period, one image layer per wall
  // needs 2 (reach + skin) <= the distance between opposite walls (make_images).
  for (double L : {d.Lx(), d.Ly()}) skin_max_ = std::min(skin_max_, std::max(0.0, 0.5 * L - reach));
  skin_min_ = std::min(skin_min_, skin_max_);
  skin_ = skin_min_;
}

VerletList::VerletList(const Domain& d, double reach, double skin_min, double skin_max, const Mat2& fixed)
    : VerletList(d, reach, skin_min, skin_max) {
  fixed_ = fixed;
  fixed_mode_ = true;
}

void VerletList::set_fixed(const Mat2& fixed) {
  fixed_ = fixed;
  fixed_mode_ = true;
  x_build_.resize(0, 2);  // build_due: a first build (no skin from a speed)
}

void VerletList::restore(const State& s, const Mat2& x, Images& im, PairList& P) {
  skin_ = s.skin;
  build(s.x_build, im, P);
  move(x, im, P);
  since_build_ = s.since_build;
  builds_ = s.builds;
  updates_ = s.updates;
}

bool VerletList::update(const Mat2& x, Images& im, PairList& P, bool force) {
  if (build_due(x, force)) {
    build(x, im, P);
    return true;
  }
  move(x, im, P);
  return false;
}

bool VerletList::build_due(const Mat2& x, bool force) {
  const bool first = builds_ == 0 || x.rows() != x_build_.rows();
  double spread = 0;
  if (!force && !first && !needs_build(x, spread)) {
    ++updates_;
    ++since_build_;
    return false;
  }
  // The next skin from the relative speed since the last build, v = spread / steps (not after a
  // forced build: a jump of the positions is no speed): the skin that balances a build against the
  // steps' extra candidates, sqrt(kBuildCost v reach) (see the header).
  if (!force && !first) {
    const double v = spread / (since_build_ + 1);
    skin_ = std::clamp(std::sqrt(kBuildCost * v * reach_), skin_min_, skin_max_);
  }
  since_build_ = 0;
  return true;
}

// The walls (bits 1 << Side) within `range` of a particle at (x, y), and bit 16 for a corner, as
// make_images decides which images it makes.
int VerletList::walls_near(double x, double y, double range) const {
  int xw = 0, yw = 0;
  if (!d_.periodic_x) xw = x - d_.x0 < range ? 1 << Left : (d_.x1 - x < range ? 1 << Right : 0);
  if (!d_.periodic_y) yw = y - d_.y0 < range ? 1 << Bottom : (d_.y1 - y < range ? 1 << Top : 0);
  return xw | yw | (xw && yw ? 16 : 0);
}

// A pair (i, j) changes its distance by at most |d_i - d_j|, d the displacements since the build
// (an image's is its parent's, mirrored); a pair that was not a candidate (farther than reach + skin)
// is closer than reach now only if |d_i - d_j| > skin. The diagonal of the box around all the d
// bounds every |d_i - d_j|: a uniform translation does not build, a shear once the layers have slid
// by the skin (less a margin for the rounding of r). And a particle now within reach of a wall it
// has no image across (it came from farther than reach + skin) needs one.
bool VerletList::needs_build(const Mat2& x, double& spread) const {
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  auto add = [&](double dx, double dy) {
    lo[0] = std::min(lo[0], dx); hi[0] = std::max(hi[0], dx);
    lo[1] = std::min(lo[1], dy); hi[1] = std::max(hi[1], dy);
  };
  const int N = static_cast<int>(x.rows());
  bool image_missing = false;
  for (int i = 0; i < N; ++i) {
    const int has = walls_[i];
    image_missing = image_missing || (!fixed_mode_ && (walls_near(x(i, 0), x(i, 1), reach_) & ~has));
    double dx = x(i, 0) - x_build_(i, 0), dy = x(i, 1) - x_build_(i, 1);
    if (d_.periodic_x) dx -= d_.Lx() * std::round(dx / d_.Lx());  // minimum image
    if (d_.periodic_y) dy -= d_.Ly() * std::round(dy / d_.Ly());
    if (i == 0 && !fixed_mode_) lo[0] = hi[0] = dx, lo[1] = hi[1] = dy;  // (fixed points: the box holds 0)
    add(dx, dy);
    if (has & (1 << Left | 1 << Right)) add(-dx, dy);  // the image across x = const
    if (has & (1 << Bottom | 1 << Top)) add(dx, -dy);  // across y = const
    if (has & 16) add(-dx, -dy);                       // the corner image
  }
  spread = std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
  return image_missing || spread >= skin_ - 1e-9 * (reach_ + skin_);
}

int VerletList::images_within_reach(const Images& im, const Mat2& x) const {
  int n = 0;
  for (int m = 0; m < im.size(); ++m) {
    const int p = im.parent[m], w = im.wall[m];
    n += (walls_near(x(p, 0), x(p, 1), reach_) & (w < 0 ? 16 : 1 << w)) != 0;
  }
  return n;
}

void VerletList::build(const Mat2& x, Images& im, PairList& P) {
  const double range = reach_ + skin_;
  if (fixed_mode_) {  // the fixed points, without parents
    const int M = static_cast<int>(fixed_.rows());
    im.x = fixed_;
    im.parent.assign(M, -1);
    im.wall.assign(M, -1);
    im.v_sign.assign(M, 0.0);
    im.s_sign.assign(M, 0.0);
  } else {
    im = make_images(d_, x, range);
  }
  find_pairs(d_, x, im.x, range, P);
  x_build_ = x;
  walls_.resize(x.rows());
  for (int i = 0; i < x.rows(); ++i) walls_[i] = fixed_mode_ ? 0 : walls_near(x(i, 0), x(i, 1), range);
  const int M = im.size();
  mx_.assign(M, 0);
  my_.assign(M, 0);
  for (int m = 0; m < M; ++m) {
    const int w = im.wall[m];  // a corner image (-1) is mirrored across both walls it lies beyond
    if (w == Left || w == Right || w < 0) mx_[m] = im.x(m, 0) < d_.x0 ? -1 : 1;
    if (w == Bottom || w == Top || w < 0) my_[m] = im.x(m, 1) < d_.y0 ? -1 : 1;
  }
  ++builds_;
}

void VerletList::move(const Mat2& x, Images& im, PairList& P) const {
  move_images(x, im);
  move_pairs_to(x, im, P);
}

void VerletList::move_pairs_to(const Mat2& x, const Images& im, PairList& P) const {
  move_pairs(x, im, P, 0, static_cast<int>(x.rows()), P.rx.data(), P.ry.data(), P.r.data(), 0);
}

void VerletList::move_images(const Mat2& x, Images& im) const {
  const int M = im.size();
  for (int m = 0; m < M && !fixed_mode_; ++m) {  // the mirror images of the parents (boundary.hpp), 2 w - x
    const int p = im.parent[m];
    im.x(m, 0) = mx_[m] ? 2.0 * (mx_[m] < 0 ? d_.x0 : d_.x1) - x(p, 0) : x(p, 0);
    im.x(m, 1) = my_[m] ? 2.0 * (my_[m] < 0 ? d_.y0 : d_.y1) - x(p, 1) : x(p, 1);
  }
}

void VerletList::move_pairs(const Mat2& x, const Images& im, const PairList& P, int i0, int i1, double* rx,
                            double* ry, double* r, int k0) const {
  const int N = static_cast<int>(x.rows()), M = im.size();
  // x_i - x_j by minimum image, computed as the cell list does (fluid/common/neighbours.hpp: the query
  // shifted by a whole period, then the difference), so that the bits are a fresh search's.
  const double Lx = d_.x1 - d_.x0, Ly = d_.y1 - d_.y0;
  const bool px = d_.periodic_x, py = d_.periodic_y;
  const double *x0 = x.data(), *x1 = x.data() + N, *j0 = im.x.data(), *j1 = im.x.data() + M;
  for (int i = i0; i < i1; ++i) {
    const double qx = x0[i], qy = x1[i];
    auto difference = [&](int k, double& dx, double& dy) {  // rx, ry of pair k
      const int j = P.j[k];
      const double xj = j < N ? x0[j] : j0[j - N], yj = j < N ? x1[j] : j1[j - N];
      dx = qx - xj, dy = qy - yj;
      if (px && std::fabs(dx) > 0.5 * Lx) dx = (dx > 0 ? qx - Lx : qx + Lx) - xj;
      if (py && std::fabs(dy) > 0.5 * Ly) dy = (dy > 0 ? qy - Ly : qy + Ly) - yj;
      rx[k - k0] = dx;
      ry[k - k0] = dy;
    };
    // The distances two pairs at a time in the lanes of one square root (the same correctly rounded
    // sqrt(dx dx + dy dy) per lane, no FMA: the bits of the scalar form, whose square roots bound the
    // pass: one sqrtsd per pair).
    int k = P.offset[i];
    const int e = P.offset[i + 1];
    for (; k + 2 <= e; k += 2) {
      double ax, ay, bx, by;
      difference(k, ax, ay);
      difference(k + 1, bx, by);
      const Lanes2 dx{ax, bx}, dy{ay, by};
      const Lanes2 d = sqrt2(dx * dx + dy * dy);
      r[k - k0] = d[0];
      r[k + 1 - k0] = d[1];
    }
    if (k < e) {
      double dx, dy;
      difference(k, dx, dy);
      r[k - k0] = std::sqrt(dx * dx + dy * dy);
    }
  }
}

}  // namespace sphib
