#include "fluid/eulerian/exact_projection.hpp"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>

#include "fluid/common/profile.hpp"
#include "fluid/algebra/solver_policy.hpp"

namespace sphib {

namespace {
std::string wall_name(Side w) {
  return w == Left ? "left" : w == Right ? "right" : w == Bottom ? "bottom" : "top";
}
}  // namespace

namespace {
// m from the pairs k0 .. k1 - 1 of the lattice's middle particle (gradient_normalisation)
double normalisation(const Lattice& lat, const PairList& pairs, int k0, int k1, const CubicSplineKernel& W) {
  double mx = 0;
  for (int k = k0; k < k1; ++k) mx -= lat.volume * W.F(pairs.r[k]) * pairs.rx[k] * pairs.rx[k];
  return mx;
}
int middle(const Lattice& lat) { return lat.nx / 2 + lat.nx * (lat.ny / 2); }
}  // namespace

double ExactProjection::gradient_normalisation(const Lattice& lat, const PairList& pairs, const CubicSplineKernel& W) {
  const int i = middle(lat);
  return normalisation(lat, pairs, pairs.offset[i], pairs.offset[i + 1], W);
}

double ExactProjection::gradient_normalisation(const LatticePairs& pairs, const CubicSplineKernel& W) {
  const Lattice& lat = pairs.lattice();
  const int i = middle(lat);
  PairList P;
  pairs.rows(i, i + 1, P);
  return normalisation(lat, P, 0, P.size(), W);
}

ExactProjection::ExactProjection(const Lattice& lat, const Images& im, const Operators& op, double m,
                                 const RowStencil* vel_st, SolverKind kind, bool projection, bool compact,
                                 Divergence* div)
    : lat_(lat), im_(im), op_(op), vel_st_(vel_st), kind_(kind), projection_(projection),
      compact_(compact && projection) {
  // The curl of psi_m reproduces u at long waves as G G^T / lap ~ m: psi_m is divided by m, so that
  // it does exactly (without, the markers moved 0.8% off the fluid's velocity at h = 1.2 dx, at
  // every resolution).
  mpsi_scale_ = 1.0 / m;
  // The stream functions take the velocity's operators (their images): make_images gives them the
  // boundary rule's stream function parity at every side (the velocity's own where both components
  // share one: no-slip and inflow odd, outflow even; at a free-slip wall odd, the normal
  // component's). Flow through the sides: psi's prescribed values (side_stream_value,
  // fluid/common/boundary.hpp) where the domain gives them.
  const std::string refusal = stream_function_refusal(lat_.domain);
  if (!refusal.empty()) throw std::invalid_argument(refusal);
  if (projection_) {
    for (int k = 0; k < 4; ++k) {
      const Side w = static_cast<Side>(k);
      const int normal = (w == Left || w == Right) ? 0 : 1;
      if (lat_.domain.is_wall(w) && lat_.domain.wall_velocity[k][normal] != 0.0)
        throw std::invalid_argument("walls." + wall_name(w) +
                                    ": a wall velocity with a normal component lets fluid through the wall; "
                                    "the exact projection (fluid.projection = \"exact\") needs impermeable walls");
    }
    Divergence made;
    if (!div) made = make_divergence(op_.grad_phix, op_.grad_phiy, compact_);
    Divergence& d = div ? *div : made;
    div_x_.swap(d.x);
    div_y_.swap(d.y);
    div_st_ = std::move(d.st);
    vmodes_ = VelocityModes(lat_);
    parity_.resize(lat_.size());
    for (int i = 0; i < lat_.size(); ++i) parity_[i] = static_cast<unsigned char>(2 * ((i / lat_.nx) & 1) + ((i % lat_.nx) & 1));
    vel_images_ = ImageRows(vel_st_, lat_.size(), {&op_.grad_ux.B, &op_.grad_uy.B});
    if (!compact_) make_psi_solver();
  }
  const int N = lat_.size();
  psi_m_ = cu_ = b_m_ = Vec::Zero(N);
}

ExactProjection::Divergence ExactProjection::make_divergence(const SpMat& grad_phix, const SpMat& grad_phiy,
                                                              bool compact) {
  Divergence d;
  d.x = grad_phix.transpose();
  d.y = grad_phiy.transpose();
  finish_divergence(d, compact);
  return d;
}

ExactProjection::Divergence ExactProjection::divergence_by_blocks(const SpMat& grad_phix, const SpMat& grad_phiy,
                                                                   const RowStencil& st) {
  const int N = static_cast<int>(grad_phix.rows()), block = product_block(N);
  const StencilRows sr(st, N);
  const std::vector<int> cols_x = sr.column_counts(grad_phix), cols_y = sr.column_counts(grad_phiy);
  std::vector<char> mark(N, 0);  // (reach_of's)
  const OperatorRows rows = [&](const std::function<void(const std::vector<const SpMat*>&, int)>& f) {
    for (int r0 = 0; r0 < N; r0 += block) {
      const int m = std::min(block, N - r0);
      const std::vector<int> at = reach_of(sr.rows(grad_phix, r0, m), mark);  // (one pattern)
      SpMat dx = transposed_rows(sr.rows(grad_phix, at), at, cols_x, r0, m, false);
      SpMat dy = transposed_rows(sr.rows(grad_phiy, at), at, cols_y, r0, m, false);
      negate(dx);  // D = -G^T
      negate(dy);
      f({&dx, &dy}, r0);
    }
  };
  Divergence d;
  std::vector<SpMat> kept;
  d.st = find_row_stencil(rows, N, kept);
  d.x.swap(kept[0]);
  d.y.swap(kept[1]);
  return d;
}

void ExactProjection::finish_divergence(Divergence& d, bool compact) {
  negate(d.x);
  negate(d.y);
  d.st = find_row_stencil({&d.x, &d.y});
  if (compact) {
    keep_stencil_rows(d.x, d.st);
    keep_stencil_rows(d.y, d.st);
  }
}

void ExactProjection::make_solvers() {
  if (!psi_solver_) make_psi_solver();
}

void ExactProjection::make_markers_solver() {
  if (mpsi_solver_) return;
  // The markers' psi_m: -lap psi_m = C^T u, lap with odd images (lap_u.A, Eq. 31): definite with a
  // wall, the constants its null space on a doubly periodic box.
  const Domain& d = lat_.domain;
  mpsi_gauge_ = Gauge(lat_, d.periodic_x && d.periodic_y ? NullSpace::Constants : NullSpace::None);
  const std::string system = "stream function of the markers (Morris Laplacian, " + image_parities_text(d, Field::Stream) + ")";
  SystemSolver m;
  const int N = lat_.size();
  std::unique_ptr<StencilRows> sr;  // compact: lap_u.A by its stencil's rows only
  if (compact_) {  // the lattice solver from -lap's rows (no negated copy, lap never whole)
    sr = std::make_unique<StencilRows>(*vel_st_, N);
    m = lattice_singular_solver(system, Field::Stream, negated_rows([&](int r0, int k) { return sr->rows(op_.lap_u.A, r0, k); }, N),
                                N, mpsi_gauge_, kind_, lat_);
  }
  if (!m.solver) {
    SpMat minus_lap = sr ? sr->rows(op_.lap_u.A, 0, N) : op_.lap_u.A;  // -lap (negated in place: an
    negate(minus_lap);                                                 // assigned -A grows its own storage)
    m = singular_solver(system, Field::Stream, minus_lap, mpsi_gauge_, kind_, &lat_, Refactor::Once);
  }
  mpsi_solver_ = std::move(m.solver);
  mpsi_unpinned_ = m.unpinned;
}

void ExactProjection::make_psi_solver() {
  // psi's images are odd (psi = psi_w on the wall): the velocity rule's operators, whose B takes
  // the offsets 2 psi_w. Normal equations of min |(Gy psi + By c, -(Gx psi + Bx c)) - u|^2:
  //   (Gy^T Gy + Gx^T Gx) psi = Gy^T u - Gx^T v - Q (Gy^T By + Gx^T Bx) c1,
  // c1 the offsets of unit flux Q (2 on the images of the top wall, or of the right wall).
  const SpMat& Gx = op_.grad_ux.A;
  const SpMat& Gy = op_.grad_uy.A;
  const int N = lat_.size(), block = product_block(N);
  // The compact storage holds the velocity gradients by their stencil's rows only, and never their
  // transposes whole: a block of the transposes' rows at a time (the same bits as the whole
  // transposes' rows), from the gradients' rows that reach them made whole again (StencilRows), read
  // once for the transposes' stencil, kept rows and the flux terms (find_row_stencil's passes
  // should a class fall short) and once by the lattice solver for G^T G (its two passes should the
  // matrix fail a check); the gradients' rows themselves a block at a time.
  std::unique_ptr<StencilRows> sr;
  std::vector<int> cols_x, cols_y;
  // the block's transposes, and the gradients' rows they reach (`local`: the transposes' columns
  // numbered as those rows, for the products with them)
  std::vector<char> mark(compact_ ? N : 0, 0);  // (reach_of's)
  const auto transposes = [&](int r0, int m, SpMat& ty, SpMat& tx, SpMat* ry, SpMat* rx, bool local) {
    const std::vector<int> at = reach_of(sr->rows(Gy, r0, m), mark);  // (Gx's pattern is Gy's)
    SpMat y = sr->rows(Gy, at), x = sr->rows(Gx, at);
    ty = transposed_rows(y, at, cols_y, r0, m, local);
    tx = transposed_rows(x, at, cols_x, r0, m, local);
    negate(tx);  // -Gx^T
    if (ry) ry->swap(y);
    if (rx) rx->swap(x);
  };
  const auto by_blocks = [&](const std::function<void(int, int)>& f) {
    for (int r0 = 0; r0 < N; r0 += block) f(r0, std::min(block, N - r0));
  };
  const Domain& d = lat_.domain;
  const int M = im_.size();
  psi_ = b_psi_ = psi_flux_ = psi_by1_ = psi_bx1_ = Vec::Zero(N);
  const bool channel = d.periodic_x != d.periodic_y, offsets = channel || d.any_through();
  if (offsets) {
    Vec c1 = Vec::Zero(M);
    if (channel) {
      const Side far = d.periodic_x ? Top : Right;  // the wall that carries psi = Q
      const double c_far = image_prescribed(d.parity(far, Field::Stream), 1.0);  // 2: psi_w = Q = 1, odd images
      for (int m = 0; m < M; ++m)
        if (im_.wall[m] == far) c1[m] = c_far;
    } else {
      // flow through the sides: psi's images carry the prescribed values of the walls and the inflow
      // (psi_img = parity psi + (1 - parity) psi_side, side_stream_value); the flux is the inflow's,
      // so Q = 1 multiplies these offsets every step (flux_)
      image_stream_offsets(im_, d, c1);
    }
    psi_by1_ = op_.grad_uy.B * c1;
    psi_bx1_ = op_.grad_ux.B * c1;
    mpsi_flux_ = op_.lap_u.B * c1;  // lap of psi_m's wall values per unit flux
  } else {
    mpsi_flux_ = Vec::Zero(N);
  }
  if (compact_) {
    sr = std::make_unique<StencilRows>(*vel_st_, N);
    cols_x = sr->column_counts(Gx);
    cols_y = sr->column_counts(Gy);
    // the transposes' stencil and kept rows, and the flux terms Gy^T By c1 + Gx^T Bx c1 (a channel,
    // flow through the sides) by the same rows of the transposes (each row's sums as the whole
    // products')
    const OperatorRows rows = [&](const std::function<void(const std::vector<const SpMat*>&, int)>& f) {
      SpMat ty, tx;
      by_blocks([&](int r0, int m) {
        transposes(r0, m, ty, tx, nullptr, nullptr, false);
        if (offsets) {
          const Vec flux = ty * psi_by1_ - tx * psi_bx1_;
          psi_flux_.segment(r0, m) = flux;
        }
        f({&ty, &tx}, r0);
      });
    };
    std::vector<SpMat> kept;
    psi_st_ = find_row_stencil(rows, N, kept);  // read from here on only through psi_st_
    psi_ty_.swap(kept[0]);
    psi_tx_.swap(kept[1]);
  } else {
    psi_ty_ = Gy.transpose();
    psi_tx_ = Gx.transpose();
    negate(psi_tx_);  // -Gx^T
    psi_st_ = find_row_stencil({&psi_ty_, &psi_tx_});
    if (offsets) psi_flux_ = psi_ty_ * psi_by1_ - psi_tx_ * psi_bx1_;  // Gy^T By c1 + Gx^T Bx c1
  }
  psi_gauge_ = Gauge(lat_, NullSpace::GradientStream);
  // G^T G = Gy^T Gy + Gx^T Gx (Gx^T = -psi_tx_, exactly), a block of rows at a time: the same bits
  // as the whole products. The compact storage hands the lattice solver the blocks alone (G^T G,
  // 3-4 times the non-zeros of G, never held whole); otherwise, or where it lacks the structure,
  // the matrix is made from them.
  const std::string images = image_parities_text(d, Field::Stream);  // what the rule gives at each side
  const std::string system = projection_ ? "Poisson (exact projection: the stream function, G^T G, " + images + ")"
                                         : "stream function (G^T G, " + images + ")";
  SystemSolver s;
  if (compact_) {
    const MatrixRows gtg = [&](const std::function<void(const SpMat&, int)>& f) {
      SumOfProductRows product(N);  // (rows_of_sum_of_products's bits)
      by_blocks([&](int r0, int m) {
        SpMat ty, tx, ry, rx;
        transposes(r0, m, ty, tx, &ry, &rx, true);
        f(product(ty, ry, -1.0, tx, rx), r0);
      });
    };
    s = lattice_singular_solver(system, Field::Stream, gtg, N, psi_gauge_, kind_, lat_);
  }
  if (!s.solver) {
    SpMat A;
    if (compact_) {  // the gradients and their transposes whole again, for the matrix
      const SpMat gx = sr->rows(Gx, 0, N), gy = sr->rows(Gy, 0, N);
      SpMat ty = gy.transpose(), tx = gx.transpose();
      negate(tx);
      A = sum_of_products(ty, gy, -1.0, tx, gx);
    } else {
      A = sum_of_products(psi_ty_, Gy, -1.0, psi_tx_, Gx);
    }
    s = singular_solver(system, Field::Stream, A, psi_gauge_, kind_, &lat_, Refactor::Once);
  }
  psi_solver_ = std::move(s.solver);
  psi_unpinned_ = s.unpinned;
  psi_r1_ = Mat2::Zero(N, 2);
  if (projection_ && d.any_through()) {
    Mat2 b(N, 2);
    b.col(0) = psi_by1_;
    b.col(1) = -psi_bx1_;
    div_source_.resize(N);
    divergence(b, div_source_);
  }
  if (channel) {
    // The flux Q by least squares too: with C psi + Q b1 the velocity of (psi, Q) (b1 = (By c1,
    // -Bx c1)), the best Q for u is <u, r1> / <r1, r1> with r1 = (I - P_C) b1 = C psi1 + b1,
    // psi1 = -(C^T C)^{-1} C^T b1 (P_C the orthogonal projection onto the curls). (The flux from the
    // mean velocity would be off by the lattice's second kernel moment: G of a linear function is
    // not exactly its slope.)
    Vec b = -psi_flux_, psi1 = Vec::Zero(N);
    psi_gauge_.project(b);
    if (!psi_unpinned_) psi_gauge_.pin_rhs(b);
    psi_solver_->solve(b.data(), psi1.data(), 1);
    psi_gauge_.project(psi1);
    if (compact_) {  // by blocks of the gradients' rows: each row's sums as the whole products'
      by_blocks([&](int r0, int m) {
        const SpMat gy = sr->rows(Gy, r0, m), gx = sr->rows(Gx, r0, m);
        const Vec ry = gy * psi1 + psi_by1_.segment(r0, m);
        const Vec rx = -(gx * psi1 + psi_bx1_.segment(r0, m));
        psi_r1_.col(0).segment(r0, m) = ry;
        psi_r1_.col(1).segment(r0, m) = rx;
      });
    } else {
      psi_r1_.col(0) = Gy * psi1 + psi_by1_;
      psi_r1_.col(1) = -(Gx * psi1 + psi_bx1_);
    }
    psi_r1_ /= psi_r1_.squaredNorm();
  }
  if (!mpsi_solver_) make_markers_solver();
}

void ExactProjection::curl_transpose(const Mat2& u) {
  sphib::divergence(psi_ty_, psi_tx_, u, cu_, &psi_st_);  // Gy^T u - Gx^T v (= C^T u)
  // psi on the far wall: the flux (int u dy along a channel in x, -int v dx in y), the least-squares
  // value (make_psi_solver)
  Q_ = flux(u);
}

double ExactProjection::flux(const Mat2& u) const {
  // a channel: the least-squares flux of u (make_psi_solver); flow through the sides: the inflow's,
  // prescribed (1 x the offsets); else none
  const Domain& d = lat_.domain;
  return d.periodic_x != d.periodic_y ? u.cwiseProduct(psi_r1_).sum() : d.any_through() ? 1.0 : 0.0;
}

void ExactProjection::psi_rhs() {
  if (Q_ != 0.0) b_psi_ = cu_ - Q_ * psi_flux_;  // (one pass)
  else b_psi_ = cu_;
  psi_gauge_.project(b_psi_);  // G^T of a uniform flow is 0 on a periodic box: its mean is the stream function's U
}

bool ExactProjection::markers_in_one_pass() const {
  return mpsi_gauge_.dimension() == 0 && (mpsi_unpinned_ || mpsi_gauge_.pins().empty());
}

void ExactProjection::rhs(const Mat2& u_star, long revision) {
  // curl_transpose() and psi_rhs() (and the markers' right-hand side) in one pass: C^T u* and the
  // flux Q of u* (the least-squares value, make_psi_solver), b_psi_ = C^T u* - Q ..., b_m_
  Q_ = flux(u_star);
  const bool bm = markers_in_one_pass();
  curl_transpose_rhs({&psi_ty_, &psi_tx_, &psi_st_, u_star.data(),
                      {Q_, mpsi_scale_, psi_flux_.data(), mpsi_flux_.data(), cu_.data(), b_psi_.data(),
                       bm ? b_m_.data() : nullptr}});
  bm_revision_ = bm ? revision : -1;
  psi_gauge_.project(b_psi_);  // G^T of a uniform flow is 0 on a periodic box: its mean is the stream function's U
  if (!psi_unpinned_) psi_gauge_.pin_rhs(b_psi_);
  cu_revision_ = revision;  // C^T u* = C^T u^{n+1}: the markers' right-hand side of this state
}

void ExactProjection::solve() {
  psi_solver_->solve(b_psi_.data(), psi_.data(), 1);
  psi_gauge_.project(psi_);
}

void ExactProjection::velocity(const Mat2& u_star, double dt_over_rho, Mat2& u, Mat2& grad_phi) {
  // u^{n+1} = (Gy psi + Q By c1, -(Gx psi + Q Bx c1)) + u*'s alternating modes (and mean), and
  // Eq. (34): G phi^{n+1} = rho/dt (u* - u^{n+1}) (phi itself on demand, EulerianFluid::phi), in one
  // pass over the velocity pattern (fluid/eulerian/fused_passes.hpp)
  CurlVelocity p;
  p.gx = &op_.grad_ux.A;
  p.gy = &op_.grad_uy.A;
  p.st = vel_st_;
  p.images = &vel_images_;
  p.psi = psi_.data();
  p.rows.Q = Q_;
  p.rows.r = 1.0 / dt_over_rho;
  p.rows.by1 = psi_by1_.data();
  p.rows.bx1 = psi_bx1_.data();
  p.rows.u_star = u_star.data();
  p.rows.par = parity_.data();
  p.rows.nx = lat_.nx;
  p.rows.modes = vmodes_.addends(u_star);
  p.rows.u = u.data();
  p.rows.grad_phi = grad_phi.data();
  curl_velocity(p);
}

void ExactProjection::divergence(const Mat2& f, Vec& d) const { sphib::divergence(div_x_, div_y_, f, d, &div_st_); }

void ExactProjection::velocity_divergence(const Mat2& u, Vec& d) const {
  divergence(u, d);
  if (div_source_.size() > 0) d -= div_source_;
}

StreamFunction ExactProjection::markers(const Mat2& u, long revision) {
  if (psi_revision_ != revision) {
    if (!psi_solver_) make_psi_solver();
    if (cu_revision_ != revision) curl_transpose(u);  // the exact projection's step made it already
    // -lap psi_m = C^T u with psi_m's wall values (0 and Q): -(A psi_m + Q B c1) = C^T u, divided
    // by m (psi_m / m: make_psi_solver); in one pass where the gauge has nothing to do (walls)
    if (markers_in_one_pass()) {
      if (bm_revision_ != revision) b_m_ = (cu_ + Q_ * mpsi_flux_) * mpsi_scale_;  // (rhs() made it already)
    } else {
      b_m_ = cu_;
      if (Q_ != 0.0) b_m_.noalias() += Q_ * mpsi_flux_;
      mpsi_gauge_.project(b_m_);
      if (!mpsi_unpinned_) mpsi_gauge_.pin_rhs(b_m_);
      b_m_ *= mpsi_scale_;
    }
    mpsi_solver_->solve(b_m_.data(), psi_m_.data(), 1);
    mpsi_gauge_.project(psi_m_);
    mean_.setZero();
    if (lat_.domain.periodic_x && lat_.domain.periodic_y) mean_ << u.col(0).mean(), u.col(1).mean();
    psi_revision_ = revision;
  }
  return {&psi_m_, mean_};
}

double ExactProjection::normal_equations_residual(const Mat2& u_star) {
  // ||A x - b|| / ||b|| with the unpinned operator and the right-hand side of the last step
  curl_transpose(u_star);
  psi_rhs();
  // Gy^T Gy psi + Gx^T Gx psi = Gy^T (Gy psi) + psi_tx_ (-Gx psi), by the stencils (the operators
  // may keep only their stencils' rows)
  const int N = lat_.size();
  Mat2 g(N, 2), w(N, 2);
  gradient(op_.grad_ux.A, op_.grad_uy.A, psi_, g, vel_st_);
  w.col(0) = g.col(1);
  w.col(1) = -g.col(0);
  Vec r(N);
  sphib::divergence(psi_ty_, psi_tx_, w, r, &psi_st_);
  r -= b_psi_;
  const double nb = b_psi_.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

double ExactProjection::floor_seconds(const Mat2& u_star, Mat2& work, int reps) const {
  Vec d(lat_.size()), f = psi_, b = b_psi_;
  auto best = [reps](auto&& kernel) { return best_of(reps, kernel); };
  double total = best([&] { sphib::divergence(psi_ty_, psi_tx_, u_star, d, &psi_st_); });  // C^T u*
  total += best([&] { psi_solver_->solve(b.data(), f.data(), 1); });                         // psi
  total += best([&] { gradient(op_.grad_ux.A, op_.grad_uy.A, psi_, work, vel_st_); });        // its curl
  return total;
}

double ExactProjection::markers_floor_seconds(int reps) const {
  Vec f = psi_m_, b = b_m_;
  return best_of(reps, [&] { mpsi_solver_->solve(b.data(), f.data(), 1); });
}

void ExactProjection::save(NamedArrays& st) const {
  Eigen::MatrixXd q(1, 1);
  q(0, 0) = Q_;
  st.emplace_back("curl_transpose_u_star", cu_);
  st.emplace_back("flux", q);
}

void ExactProjection::load(const NamedArrays& st, long revision) {
  cu_ = state_entry(st, "curl_transpose_u_star", lat_.size(), 1);
  Q_ = state_entry(st, "flux", 1, 1)(0, 0);
  cu_revision_ = revision;
  bm_revision_ = -1;
}

}  // namespace sphib
