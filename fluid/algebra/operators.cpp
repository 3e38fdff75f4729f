#include "fluid/algebra/operators.hpp"

#include <algorithm>
#include <vector>

namespace sphib {

namespace {
// Rows r0 .. r0 + rows - 1 of one operator (A straight into its compressed arrays, after the rows
// before them; B's terms as triplets) from P, the pairs of those rows (P.offset relative to r0),
// the coefficient of pair k given by a(k) (computed as it is read: no array of them). The terms of
// a column are summed in the order they come (as setFromTriplets sums duplicates), each row then
// sorted by column, so that a row is the same bits however the rows are blocked.
template <class Coef>
void assemble_rows(const PairList& P, int r0, int N, const Images& im, ImageRule rule, Coef a, bool difference,
                   bool keep_zeros, SpMat& A, std::vector<Triplet>& tB, int out0 = 0) {
  const double s_ij = difference ? -1.0 : 1.0;  // f_i - f_j  or  f_i + f_j
  std::vector<std::pair<int, double>> row;
  auto add = [&row](int col, double v) {
    for (auto& e : row)
      if (e.first == col) {
        e.second += v;  // duplicates (i, p) are summed
        return;
      }
    row.emplace_back(col, v);
  };
  const int rows = static_cast<int>(P.offset.size()) - 1;
  for (int q = 0; q < rows; ++q) {
    const int i = r0 + q;
    double diag = 0.0;
    row.clear();
    for (int k = P.offset[q]; k < P.offset[q + 1]; ++k) {
      const int j = P.j[k];
      const double ak = a(k);
      diag += ak;  // the f_i part
      if (j < N) {
        add(j, s_ij * ak);
      } else {  // image: f_j = sign f_p + c_j, the sign the image's parity (boundary_rule.hpp)
        const int m = j - N;
        const double sign = rule == ImageRule::Velocity ? im.v_sign[m] : im.s_sign[m];
        add(im.parent[m], s_ij * sign * ak);
        if (rule == ImageRule::Velocity) tB.emplace_back(i - out0, m, s_ij * ak);
      }
    }
    add(i, diag);
    std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    A.startVec(i - out0);
    for (const auto& [col, v] : row)
      if (keep_zeros || v != 0.0) A.insertBack(i - out0, col) = v;
  }
}

// An operator being assembled a block of rows at a time: A with room for `pairs` entries and a
// diagonal per row (at most one entry per pair), B's triplets.
struct Assembly {
  ImageOp* to = nullptr;
  std::vector<Triplet> tB;
  void begin(ImageOp& op, int N, int M, long pairs) {
    to = &op;
    op.A.resize(N, N);
    op.A.reserve(static_cast<Eigen::Index>(pairs) + N);
    tB.reserve(M * 8);
  }
  void finish(int N, int M) {
    to->A.finalize();
    to->B.resize(N, M);
    to->B.setFromTriplets(tB.begin(), tB.end());
    std::vector<Triplet>().swap(tB);
  }
};

// The operators of `set` from the pairs, given as blocks: pairs(f) calls f(P, r0) for consecutive
// blocks of rows, every row once, in order (P.offset relative to r0).
template <class Blocks>
Operators assemble_set(const Blocks& pairs, long npairs, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                       OperatorSet set) {
  const bool vel = set == OperatorSet::All || set == OperatorSet::Velocity;
  const bool lap_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::LapPhi;
  const bool grad_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::GradPhi;
  const int N = L.size(), M = im.size();
  const double V = L.volume;
  Operators op;  // all with one pattern per image rule, for the fused products
  ImageOp lp, gpx, gpy;  // the scalar rule's (their B stays empty)
  struct Job {
    ImageOp* to;
    ImageRule rule;
    int coef;  // 0: Laplacian, 1: x gradient, 2: y gradient
    bool difference, keep_zeros;
  };
  std::vector<Job> jobs;
  if (vel) jobs.push_back({&op.lap_u, ImageRule::Velocity, 0, true, true});
  if (lap_phi) jobs.push_back({&lp, ImageRule::Scalar, 0, true, false});
  if (vel) jobs.push_back({&op.grad_ux, ImageRule::Velocity, 1, false, true});
  if (grad_phi) jobs.push_back({&gpx, ImageRule::Scalar, 1, false, true});
  if (vel) jobs.push_back({&op.grad_uy, ImageRule::Velocity, 2, false, true});
  if (grad_phi) jobs.push_back({&gpy, ImageRule::Scalar, 2, false, true});
  std::vector<Assembly> as(jobs.size());
  for (size_t q = 0; q < jobs.size(); ++q) as[q].begin(*jobs[q].to, N, jobs[q].rule == ImageRule::Velocity ? M : 0, npairs);
  pairs([&](const PairList& P, int r0) {
    // The coefficients computed as each operator reads them (no array of them); each the same
    // expression, hence the same bits.
    // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
    const auto lap = [&](int k) { return 2.0 * V * W.F(P.r[k]); };
    // Eqs. (27), (30): V (x_i - x_j) F_ij, F = (1/r) dW/dr
    const auto gx = [&](int k) { return V * P.rx[k] * W.F(P.r[k]); };
    const auto gy = [&](int k) { return V * P.ry[k] * W.F(P.r[k]); };
    for (size_t q = 0; q < jobs.size(); ++q) {
      const Job& j = jobs[q];
      SpMat& A = j.to->A;
      if (j.coef == 0) assemble_rows(P, r0, N, im, j.rule, lap, j.difference, j.keep_zeros, A, as[q].tB);
      else if (j.coef == 1) assemble_rows(P, r0, N, im, j.rule, gx, j.difference, j.keep_zeros, A, as[q].tB);
      else assemble_rows(P, r0, N, im, j.rule, gy, j.difference, j.keep_zeros, A, as[q].tB);
    }
  });
  for (size_t q = 0; q < jobs.size(); ++q) as[q].finish(N, jobs[q].rule == ImageRule::Velocity ? M : 0);
  op.lap_phi.swap(lp.A);
  op.grad_phix.swap(gpx.A);
  op.grad_phiy.swap(gpy.A);
  return op;
}

}  // namespace

Operators operator_rows(const PairList& P, int r0, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                        OperatorSet set) {
  const bool vel = set == OperatorSet::All || set == OperatorSet::Velocity;
  const bool lap_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::LapPhi;
  const bool grad_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::GradPhi;
  const int N = L.size(), M = im.size(), m = static_cast<int>(P.offset.size()) - 1;
  const double V = L.volume;
  // the coefficients of build_operators (the same expressions)
  const auto lap = [&](int k) { return 2.0 * V * W.F(P.r[k]); };
  const auto gx = [&](int k) { return V * P.rx[k] * W.F(P.r[k]); };
  const auto gy = [&](int k) { return V * P.ry[k] * W.F(P.r[k]); };
  Operators op;
  auto put = [&](ImageOp& to, ImageRule rule, auto a, bool difference, bool keep_zeros) {
    std::vector<Triplet> tB;
    to.A.resize(m, N);
    to.A.reserve(static_cast<Eigen::Index>(P.size()) + m);
    assemble_rows(P, r0, N, im, rule, a, difference, keep_zeros, to.A, tB, r0);
    to.A.finalize();
    to.B.resize(m, rule == ImageRule::Velocity ? M : 0);
    to.B.setFromTriplets(tB.begin(), tB.end());
  };
  ImageOp t;
  if (vel) {
    put(op.lap_u, ImageRule::Velocity, lap, true, true);
    put(op.grad_ux, ImageRule::Velocity, gx, false, true);
    put(op.grad_uy, ImageRule::Velocity, gy, false, true);
  }
  if (lap_phi) {
    put(t, ImageRule::Scalar, lap, true, false);
    op.lap_phi.swap(t.A);
  }
  if (grad_phi) {
    put(t, ImageRule::Scalar, gx, false, true);
    op.grad_phix.swap(t.A);
    put(t, ImageRule::Scalar, gy, false, true);
    op.grad_phiy.swap(t.A);
  }
  return op;
}

ImageOp assemble_pairs(const PairList& P, int N, const Images& im, ImageRule rule, const double* a,
                       bool difference, bool keep_zeros) {
  ImageOp op;
  Assembly as;
  as.begin(op, N, im.size(), P.size());
  assemble_rows(P, 0, N, im, rule, [a](int k) { return a[k]; }, difference, keep_zeros, op.A, as.tB);
  as.finish(N, im.size());
  return op;
}

Operators build_operators(const PairList& P, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                          OperatorSet set) {
  return assemble_set([&P](const auto& f) { f(P, 0); }, P.size(), L, im, W, set);
}

void pressure_from_phi(const SpMat& lap_phi, const Vec& phi, double a, Vec& p, const RowStencil* st) {
  if (st) {
    p.resize(phi.size());
    apply1(lap_phi, phi.data(), p.data(), st);  // each row summed from 0 in its order, as Eigen's product
  } else {
    p.noalias() = lap_phi * phi;
  }
  p = phi - a * p;
}

}  // namespace sphib
