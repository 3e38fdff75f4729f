#include "fluid/operators.hpp"

#include <algorithm>
#include <vector>

namespace sphib {

ImageOp assemble_pairs(const PairList& P, int N, const Images& im, ImageRule rule, const double* a,
                       bool difference, bool keep_zeros) {
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
      diag += a[k];  // the f_i part
      if (j < N) {
        add(j, s_ij * a[k]);
      } else {  // image: f_j = sign f_p + c_j
        const int m = j - N;
        const double sign = rule == ImageRule::Velocity ? im.v_sign[m] : 1.0;
        add(im.parent[m], s_ij * sign * a[k]);
        if (rule == ImageRule::Velocity) tB.emplace_back(i, m, s_ij * a[k]);
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

Operators build_operators(const PairList& P, const Lattice& L, const Images& im, const CubicSplineKernel& W) {
  const int N = L.size(), K = P.size();
  const double V = L.volume;
  // One coefficient array at a time, each for its two operators (velocity and scalar images)
  std::vector<double> a(K);
  Operators op;  // all with one pattern per image rule, for the fused products
  for (int k = 0; k < K; ++k) a[k] = 2.0 * V * W.F(P.r[k]);  // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
  auto put = [&](ImageOp& to, ImageRule rule, bool difference, bool keep_zeros) {
    ImageOp t = assemble_pairs(P, N, im, rule, a.data(), difference, keep_zeros);
    to.swap(t);
  };
  auto put_A = [&](SpMat& to, bool difference, bool keep_zeros) {
    ImageOp t = assemble_pairs(P, N, im, ImageRule::Scalar, a.data(), difference, keep_zeros);
    to.swap(t.A);
  };
  put(op.lap_u, ImageRule::Velocity, true, true);
  put_A(op.lap_phi, true, false);
  for (int k = 0; k < K; ++k) a[k] = V * P.rx[k] * W.F(P.r[k]);  // Eqs. (27), (30): V (x_i - x_j) F_ij, F = (1/r) dW/dr
  put(op.grad_ux, ImageRule::Velocity, false, true);
  put_A(op.grad_phix, false, true);
  for (int k = 0; k < K; ++k) a[k] = V * P.ry[k] * W.F(P.r[k]);
  put(op.grad_uy, ImageRule::Velocity, false, true);
  put_A(op.grad_phiy, false, true);
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
