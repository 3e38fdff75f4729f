#pragma once
// Neighbour search with a cell grid (periodic axes wrap by the minimum-image convention).
// EPSPH builds the particle pair list once; markers query the same kind of grid each step in O(Nb).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "fluid/common/boundary.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

// The points near one query, gathered by CellGrid::gather_near: n points, each with its index j,
// offset (dx, dy) = q - x_j and squared distance r2 = dx^2 + dy^2. The arrays are longer than n.
struct NearPoints {
  std::vector<int> j;
  std::vector<double> dx, dy, r2;
  int n = 0;
  void reserve(int m);  // room for at least m points (grows, never shrinks)
};

class CellGrid {
 public:
  // Points in the box [lo, hi]; along a periodic axis the box is exactly one period and points wrap.
  // Points outside the box along a bounded axis go to the edge cells. A query visits about
  // (2 radius / cell + 1)^2 cells, so cells of one lattice spacing suit the markers' queries.
  CellGrid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, bool periodic_x, bool periodic_y,
           double min_cell_size);

  void build(const Mat2& points);  // allocates only when the point count grows
  // The points are the fixed lattice L (EPSPH): queries walk the lattice indices inside the query's
  // box directly, without cells (the markers' queries every step). build() leaves this mode.
  void use_lattice(const Lattice& L);

  // Calls f(j, dx, dy, r) for every point j with r = |q - x_j| < radius (minimum image),
  // where (dx, dy) = q - x_j. Any radius below half a periodic period: the cells overlapping the
  // query disc are visited, with their periodic shifts.
  // The points for_each_near visits, in its order and with the same offsets, into `out` (for loops
  // that evaluate a kernel over them without a branch per point). In lattice mode without a branch
  // per point either: every point of the query's box is written, and counted if inside the radius.
  // Leaves room for one point more than out.n (to pad to whole SIMD lanes). Without `offsets` the
  // lattice mode leaves out.dx and out.dy unset (a caller that needs only j and r2).
  void gather_near(double qx, double qy, double radius, NearPoints& out, bool offsets = true) const;

  // Lattice mode: the lattice points of the query's box, by rows (for loops over whole rows): the
  // columns' wrapped indices and offsets qx - x, and the rows within the radius, each as nx times its
  // wrapped index and its offset qy - y. The expressions of for_each_near, so the same values.
  struct LatticeBox {
    static constexpr int kMax = 256;
    int ncol = 0, nrow = 0;
    int col[kMax];
    double cdx[kMax];
    int base[kMax];
    double ry[kMax];
  };
  bool lattice_mode() const { return lat_.n[0] > 0; }
  void lattice_box(double qx, double qy, double radius, LatticeBox& box) const;  // throws past kMax
  // The same box with only the rows whose base (nx times the wrapped row) is in [base_lo, base_hi),
  // in their order; without such rows box.nrow = 0 and the columns are left unset (a thread that owns
  // a range of the lattice's rows skips the markers that do not reach it without their columns).
  void lattice_box(double qx, double qy, double radius, long base_lo, long base_hi, LatticeBox& box) const;

  template <class F>
  void for_each_near(double qx, double qy, double radius, F&& f) const {
    const double r2max = radius * radius;
    if (lat_.n[0] > 0) {  // lattice: x_i = lo + (i + o) d, indices unwrapped around the query
      int lo[2], hi[2];
      lattice_range(qx, qy, radius, lo, hi);
      const int nx = lat_.n[0], ny = lat_.n[1];
      for (int b = lo[1]; b <= hi[1]; ++b) {
        const double dy = qy - (lat_.x0[1] + (b + lat_.o[1]) * lat_.d[1]);
        const double dy2 = dy * dy;
        if (dy2 >= r2max) continue;
        const int row = nx * (periodic_[1] ? ((b % ny) + ny) % ny : b);
        int iw = periodic_[0] ? ((lo[0] % nx) + nx) % nx : lo[0];
        for (int a = lo[0]; a <= hi[0]; ++a, iw = iw + 1 == nx ? 0 : iw + 1) {
          const double dx = qx - (lat_.x0[0] + (a + lat_.o[0]) * lat_.d[0]);
          const double r2 = dx * dx + dy2;
          if (r2 < r2max) f(row + iw, dx, dy, std::sqrt(r2));
        }
      }
      return;
    }
    int xs[kMaxSpan], ys[kMaxSpan];
    double xsh[kMaxSpan], ysh[kMaxSpan];
    const int nxs = span(qx, radius, 0, xs, xsh), nys = span(qy, radius, 1, ys, ysh);
    for (int b = 0; b < nys; ++b)
      for (int a = 0; a < nxs; ++a) {
        const int c = xs[a] + nc_[0] * ys[b];
        const double ox = qx - xsh[a], oy = qy - ysh[b];  // the query, moved by whole periods
        for (int k = start_[c]; k < start_[c + 1]; ++k) {
          const int j = items_[k];
          const double dx = ox - x_(k, 0), dy = oy - x_(k, 1);
          const double r2 = dx * dx + dy * dy;
          if (r2 < r2max) f(j, dx, dy, std::sqrt(r2));
        }
      }
  }

 private:
  // c wrapped into [lo, hi) along a periodic axis (c - period * floor rounds to hi for a tiny negative
  // c - lo: then lo).
  double wrapped(double c, int axis) const {
    if (!periodic_[axis]) return c;
    c -= period_[axis] * std::floor((c - lo_[axis]) / period_[axis]);
    return c >= lo_[axis] + period_[axis] ? lo_[axis] : c;
  }
  // The cell of a wrapped coordinate: the edge cells take points outside a bounded axis, and along a
  // periodic axis a point just below hi whose quotient rounds up to nc stays in the last cell (with
  // the coordinate it is stored with: wrapping its cell to 0 made queries near hi miss it).
  int cell_of(double c, int axis) const {
    const int k = static_cast<int>(std::floor((c - lo_[axis]) / h_[axis]));
    return k < 0 ? 0 : (k >= nc_[axis] ? nc_[axis] - 1 : k);
  }
  static constexpr int kMaxSpan = 64;
  // The cells along an axis that overlap [c - r, c + r], each with the whole-period shift that
  // takes the unwrapped cell to its stored one. Requires r < period / 2 along a periodic axis
  // (then no point qualifies under two shifts).
  int span(double c, double r, int axis, int* out, double* shift) const {
    const int k0 = static_cast<int>(std::floor((c - r - lo_[axis]) / h_[axis]));
    const int k1 = static_cast<int>(std::floor((c + r - lo_[axis]) / h_[axis]));
    const int nc = nc_[axis];
    int n = 0;
    if (periodic_[axis]) {
      // Each unwrapped cell with its own shift: exact minimum image while r < period / 2.
      for (int k = k0; k <= k1 && n < kMaxSpan; ++k) {
        const int w = ((k % nc) + nc) % nc;
        out[n] = w;
        shift[n++] = static_cast<double>((k - w) / nc) * period_[axis];
      }
    } else {
      for (int k = std::max(k0, 0); k <= std::min(k1, nc - 1) && n < kMaxSpan; ++k) {
        out[n] = k;
        shift[n++] = 0.0;
      }
    }
    return n;
  }

  // floor(x) and ceil(x) as int for x within int's range (std::floor's value, by a truncation and a
  // correction: the markers' boxes take four of them per query)
  static int floor_int(double x) {
    const int t = static_cast<int>(x);
    return t - (x < t);
  }
  static int ceil_int(double x) {
    const int t = static_cast<int>(x);
    return t + (x > t);
  }
  // Lattice mode: the unwrapped index ranges [lo, hi] of the lattice points in the query's box.
  template <bool Ranged>
  void lattice_box_rows(double qx, double qy, double radius, long base_lo, long base_hi, LatticeBox& box) const;
  void lattice_range(double qx, double qy, double radius, int lo[2], int hi[2]) const {
    const double q[2] = {qx, qy};
    for (int a = 0; a < 2; ++a) {
      lo[a] = ceil_int((q[a] - radius - lat_.x0[a]) / lat_.d[a] - lat_.o[a]);
      hi[a] = floor_int((q[a] + radius - lat_.x0[a]) / lat_.d[a] - lat_.o[a]);
      if (!periodic_[a]) { lo[a] = std::max(lo[a], 0); hi[a] = std::min(hi[a], lat_.n[a] - 1); }
      else if (hi[a] - lo[a] >= lat_.n[a]) throw std::invalid_argument("CellGrid: query radius exceeds half a period");
    }
  }

  struct {
    int n[2] = {0, 0};  // 0: cells (build); > 0: lattice mode (use_lattice)
    double x0[2], d[2], o[2];
  } lat_;
  Eigen::Vector2d lo_, period_;
  bool periodic_[2];
  int nc_[2];
  double h_[2];
  Mat2 x_;  // the points in cell order, wrapped into the box along periodic axes
  std::vector<int> start_, items_, cell_;
};

// The fixed pair list of EPSPH: for each particle i, every other point j (particle, or image
// numbered N + k) closer than 2h, with x_i - x_j by minimum image and F_ij = (1/r) dW/dr.
struct PairList {
  std::vector<int> offset;  // pairs of particle i: [offset[i], offset[i+1])
  std::vector<int> j;
  std::vector<double> rx, ry, r;
  int size() const { return static_cast<int>(j.size()); }
};

// x_i - x_j and r of pairs: a PairList's (k0 = 0), or a block's from pair k0 on (VerletList::update
// with rows, whose moves leave P's arrays).
struct PairGeometry {
  const double *x, *y, *d;  // rx, ry, r of pair k at k - k0
  int k0 = 0;
  explicit PairGeometry(const PairList& P) : x(P.rx.data()), y(P.ry.data()), d(P.r.data()) {}
  PairGeometry(const double* rx_, const double* ry_, const double* r_, int k0_) : x(rx_), y(ry_), d(r_), k0(k0_) {}
  double rx(int k) const { return x[k - k0]; }
  double ry(int k) const { return y[k - k0]; }
  double r(int k) const { return d[k - k0]; }
};

// Throws std::invalid_argument if 2h exceeds half a periodic period (minimum image would fail).
PairList find_pairs(const Lattice& lattice, const Mat2& image_x, double support);

// The lattice's pairs a block of rows at a time, so that the whole list need never exist (EPSPH's
// compact storage assembles its operators from them: fluid/algebra/operators.hpp). It holds the
// search's cells (the particles' and images' positions, ~30 B per particle).
class LatticePairs {
 public:
  // Throws as find_pairs. L and image_x must outlive it (image_x is copied into the cells).
  LatticePairs(const Lattice& L, const Mat2& image_x, double support);
  // P := the pairs of particles r0 .. r1 - 1, each as find_pairs(L, ...) makes it (the same j, rx,
  // ry, r bits, in its order), P.offset relative to r0 (P.offset[0] = 0, r1 - r0 + 1 entries).
  void rows(int r0, int r1, PairList& P) const;
  long count() const;  // the whole list's length (a pass that counts them)
  const Lattice& lattice() const { return L_; }

 private:
  const Lattice& L_;
  double support_;
  CellGrid grid_;
};

// The same for arbitrary particle positions x (N x 2) in the domain: the moving particles of LPSPH,
// searched again every step (cell list, O(N)). `out` is overwritten, reusing its storage.
void find_pairs(const Domain& domain, const Mat2& x, const Mat2& image_x, double support, PairList& out);

// The neighbours of moving particles kept between steps (a Verlet list; LPSPH, ISPH). A build makes
// the images of every particle within reach + skin of a wall (make_images) and the candidate pairs
// within reach + skin (find_pairs, cell list). Until the next build, update() only moves them: image
// positions mirrored from their parents, x_i - x_j and r of every candidate again, bit for bit as a
// fresh find_pairs computes them (the same periodic shift by minimum image). The candidates contain
// every pair closer than `reach` as long as no two points (particles or images: an image moves as its
// parent, mirrored) have moved relative to each other by more than the skin since the build:
// update() builds again when the box around all the displacements has a diagonal of the skin (less
// a margin for rounding), or when a particle has come within reach of a wall it has no image
// across. Candidates farther than reach stay in the list (the caller's coefficients are zero
// there), so that a pattern made from the list stays the same between builds.
// With fixed points (ISPH: the Morris wall particles of walls.hpp) there are no mirror images: the
// images are the fixed points, numbered as given, without parents (Images::parent -1, v_sign 0),
// candidates of every particle within reach + skin, never moved; a particle's displacement alone then
// bounds the change of its distance to them (the box includes the zero displacement).
class VerletList {
 public:
  // The skin lies in [skin_min, skin_max] (reduced where a periodic period or the walls leave less
  // room: reach + skin <= half a period, 2 (reach + skin) <= the distance between opposite walls;
  // 0: a build every step). It starts at skin_min and is chosen again at every build from the
  // relative speed v of the particles since the last one (the box diagonal over the steps):
  // skin = sqrt(kBuildCost v reach), which minimises (builds per step) x (a build's cost) + (extra
  // candidates per step) x (their cost) when a build costs about kBuildCost / 2 steps' worth of the
  // candidates within reach (see kBuildCost). skin_min = skin_max: a fixed skin.
  VerletList(const Domain& d, double reach, double skin_min, double skin_max);
  VerletList(const Domain& d, double reach, double skin) : VerletList(d, reach, skin, skin) {}
  // With fixed points (M x 2) instead of mirror images.
  VerletList(const Domain& d, double reach, double skin_min, double skin_max, const Mat2& fixed);
  // New fixed points (a gate that moved, isph.cpp): the next update() builds.
  void set_fixed(const Mat2& fixed);

  // The particles at x (N x 2, in the domain: wrapped along periodic axes): the images im and the
  // candidate pairs P (rx, ry, r) moved there, or built again (force: always); returns whether it
  // built. im and P are the list's state, kept by the caller (a fluid's own members, no copies):
  // pass the same objects every time, unchanged in between.
  bool update(const Mat2& x, Images& im, PairList& P, bool force = false);
  // The same, followed row block by row block: after the pairs of rows [i0, i1) have been moved
  // (blocks of kRowBlock rows, in order) or the list built (one call, [0, N)), rows(i0, i1, built, g)
  // is called with their geometry g, so that a pass over those pairs (LPSPH's assembly) finds them
  // in cache. A move writes the blocks' rx, ry, r into a buffer of the block (g), not into P (three
  // arrays less written back to memory per step): until move_pairs_to(x, im, P), P's rx, ry, r are
  // those of the last build or full move.
  static constexpr int kRowBlock = 64;
  template <class Rows>
  bool update(const Mat2& x, Images& im, PairList& P, bool force, Rows&& rows) {
    const int N = static_cast<int>(x.rows());
    if (build_due(x, force)) {
      build(x, im, P);
      rows(0, N, true, PairGeometry(P));
      return true;
    }
    move_images(x, im);
    for (int i0 = 0; i0 < N; i0 += kRowBlock) {
      const int i1 = std::min(N, i0 + kRowBlock), k0 = P.offset[i0], n = P.offset[i1] - k0;
      if (static_cast<int>(block_.size()) < 3 * n) block_.resize(3 * n);
      double *rx = block_.data(), *ry = rx + n, *r = ry + n;
      move_pairs(x, im, P, i0, i1, rx, ry, r, k0);
      rows(i0, i1, false, PairGeometry(rx, ry, r, k0));
    }
    return false;
  }
  // P's rx, ry, r moved to x (im: the list's images at x), as update() without rows writes them.
  void move_pairs_to(const Mat2& x, const Images& im, PairList& P) const;

  // Of the images im (the list's, at x), those that make_images(x, reach) makes: within reach.
  int images_within_reach(const Images& im, const Mat2& x) const;
  double reach() const { return reach_; }
  double skin() const { return skin_; }
  long builds() const { return builds_; }
  long updates() const { return updates_; }

  // What decides the next builds (checkpoints): the positions of the last build, the skin, the moves
  // since, and the counters; restore() builds again at those positions and moves the list to x, the
  // positions of the last update (im, P as update() leaves them), so that the candidates, and the
  // patterns made from them, are the uninterrupted run's.
  struct State {
    Mat2 x_build;
    double skin = 0;
    long since_build = 0, builds = 0, updates = 0;
  };
  State state() const { return {x_build_, skin_, since_build_, builds_, updates_}; }
  void restore(const State& s, const Mat2& x, Images& im, PairList& P);

 private:
  void build(const Mat2& x, Images& im, PairList& P);
  void move(const Mat2& x, Images& im, PairList& P) const;
  void move_images(const Mat2& x, Images& im) const;
  // rows [i0, i1): rx, ry, r of pair k into rx[k - k0], ry[k - k0], r[k - k0]
  void move_pairs(const Mat2& x, const Images& im, const PairList& P, int i0, int i1, double* rx, double* ry,
                  double* r, int k0) const;
  // Whether update() builds (then the next skin is chosen); else it counts a move.
  bool build_due(const Mat2& x, bool force);
  bool needs_build(const Mat2& x, double& spread) const;  // spread: the diagonal of the displacement box
  int walls_near(double x, double y, double range) const;

  Domain d_;
  Mat2 fixed_;          // the fixed points (fixed_mode_)
  bool fixed_mode_ = false;
  static constexpr double kBuildCost = 2.0;  // docs/method/choices.md, "LPSPH: the Verlet skin"
  double reach_, skin_min_, skin_max_, skin_;
  long since_build_ = 0;  // moves since the last build
  Mat2 x_build_;
  std::vector<int> walls_;            // per particle: the walls it has images across (walls_near)
  std::vector<signed char> mx_, my_;  // per image: mirrored across x = x0 (-1), x1 (+1), or not (0); y alike
  long builds_ = 0, updates_ = 0;
  std::vector<double> block_;  // a block's rx, ry, r (update with rows)
};

}  // namespace sphib
