#include "fluid/algebra/operators.hpp"

#include <algorithm>
#include <vector>

namespace sphib {

namespace {
// assemble_pairs with the coefficient of pair k given by a(k) (computed as it is read: no array of them)
template <class Coef>
ImageOp assemble(const PairList& P, int N, const Images& im, ImageRule rule, Coef a, bool difference, bool keep_zeros) {
  const int M = im.size();
  std::vector<Triplet> tB;
  tB.reserve(M * 8);
  const double s_ij = difference ? -1.0 : 1.0;  // f_i - f_j  or  f_i + f_j
  // A row by row, straight into its compressed arrays (no triplets): the terms of a column summed
  // in the order they come (as setFromTriplets sums duplicates), the row then sorted by column.
  ImageOp op;
  op.A.resize(N, N);
  op.A.reserve(static_cast<Eigen::Index>(P.size()) + N);  // at most one entry per pair and a diagonal
  std::vector<std::pair<int, double>> row;
  auto add = [&row](int col, double v) {
    for (auto& e : row)
      if (e.first == col) {
        e.second += v;  // duplicates (i, p) are summed
        return;
      }
    row.emplace_back(col, v);
  };
  for (int i = 0; i < N; ++i) {
    double diag = 0.0;
    row.clear();
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      const double ak = a(k);
      diag += ak;  // the f_i part
      if (j < N) {
        add(j, s_ij * ak);
      } else {  // image: f_j = sign f_p + c_j
        const int m = j - N;
        const double sign = rule == ImageRule::Velocity ? im.v_sign[m] : 1.0;
        add(im.parent[m], s_ij * sign * ak);
        if (rule == ImageRule::Velocity) tB.emplace_back(i, m, s_ij * ak);
      }
    }
    add(i, diag);
    std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    op.A.startVec(i);
    for (const auto& [col, v] : row)
      if (keep_zeros || v != 0.0) op.A.insertBack(i, col) = v;
  }
  op.A.finalize();
  op.B.resize(N, M);
  op.B.setFromTriplets(tB.begin(), tB.end());
  return op;
}

}  // namespace

ImageOp assemble_pairs(const PairList& P, int N, const Images& im, ImageRule rule, const double* a,
                       bool difference, bool keep_zeros) {
  return assemble(P, N, im, rule, [a](int k) { return a[k]; }, difference, keep_zeros);
}

Operators build_operators(const PairList& P, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                          OperatorSet set) {
  const bool vel = set == OperatorSet::All || set == OperatorSet::Velocity;
  const bool lap_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::LapPhi;
  const bool grad_phi = set == OperatorSet::All || set == OperatorSet::Phi || set == OperatorSet::GradPhi;
  const int N = L.size();
  const double V = L.volume;
  // The coefficients computed as each operator reads them (no array of them: the assembly's peak
  // holds the pair list and the operators alone); each the same expression, hence the same bits.
  // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
  const auto lap = [&](int k) { return 2.0 * V * W.F(P.r[k]); };
  // Eqs. (27), (30): V (x_i - x_j) F_ij, F = (1/r) dW/dr
  const auto gx = [&](int k) { return V * P.rx[k] * W.F(P.r[k]); };
  const auto gy = [&](int k) { return V * P.ry[k] * W.F(P.r[k]); };
  Operators op;  // all with one pattern per image rule, for the fused products
  auto put = [&](ImageOp& to, auto a, bool difference) {
    ImageOp t = assemble(P, N, im, ImageRule::Velocity, a, difference, true);
    to.swap(t);
  };
  auto put_A = [&](SpMat& to, auto a, bool difference, bool keep_zeros) {
    ImageOp t = assemble(P, N, im, ImageRule::Scalar, a, difference, keep_zeros);
    to.swap(t.A);
  };
  if (vel) put(op.lap_u, lap, true);
  if (lap_phi) put_A(op.lap_phi, lap, true, false);
  if (vel) put(op.grad_ux, gx, false);
  if (grad_phi) put_A(op.grad_phix, gx, false, true);
  if (vel) put(op.grad_uy, gy, false);
  if (grad_phi) put_A(op.grad_phiy, gy, false, true);
  return op;
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
