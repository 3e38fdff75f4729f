#include "fluid/operators.hpp"

#include <algorithm>
#include <vector>

namespace sphib {

ImageOp assemble_pairs(const PairList& P, int N, const Images& im, ImageRule rule, const double* a,
                       bool difference, bool keep_zeros) {
  const int M = im.size();
  std::vector<Triplet> tA, tB;
  tA.reserve(P.size() + N);
  tB.reserve(M * 8);
  const double s_ij = difference ? -1.0 : 1.0;  // f_i - f_j  or  f_i + f_j
  for (int i = 0; i < N; ++i) {
    double diag = 0.0;
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      diag += a[k];  // the f_i part
      if (j < N) {
        tA.emplace_back(i, j, s_ij * a[k]);
      } else {  // image: f_j = sign f_p + c_j
        const int m = j - N;
        const double sign = rule == ImageRule::Velocity ? im.v_sign[m] : 1.0;
        tA.emplace_back(i, im.parent[m], s_ij * sign * a[k]);
        if (rule == ImageRule::Velocity) tB.emplace_back(i, m, s_ij * a[k]);
      }
    }
    tA.emplace_back(i, i, diag);
  }
  ImageOp op;
  op.A.resize(N, N);
  op.A.setFromTriplets(tA.begin(), tA.end());  // duplicates (i, p) are summed
  if (!keep_zeros) op.A.prune(0.0);
  op.B.resize(N, M);
  op.B.setFromTriplets(tB.begin(), tB.end());
  return op;
}

Operators build_operators(const PairList& P, const Lattice& L, const Images& im, const CubicSplineKernel& W) {
  const int N = L.size(), K = P.size();
  const double V = L.volume;
  std::vector<double> lap(K), gx(K), gy(K);
  for (int k = 0; k < K; ++k) {
    const double F = W.F(P.r[k]);  // (1/r) dW/dr
    lap[k] = 2.0 * V * F;         // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
    gx[k] = V * P.rx[k] * F;      // Eqs. (27), (30): V (x_i - x_j) F_ij
    gy[k] = V * P.ry[k] * F;
  }
  Operators op;  // all with one pattern per image rule, for the fused products
  op.lap_u = assemble_pairs(P, N, im, ImageRule::Velocity, lap.data(), true, true);
  op.grad_ux = assemble_pairs(P, N, im, ImageRule::Velocity, gx.data(), false, true);
  op.grad_uy = assemble_pairs(P, N, im, ImageRule::Velocity, gy.data(), false, true);
  op.lap_phi = assemble_pairs(P, N, im, ImageRule::Scalar, lap.data(), true).A;
  op.grad_phix = assemble_pairs(P, N, im, ImageRule::Scalar, gx.data(), false, true).A;
  op.grad_phiy = assemble_pairs(P, N, im, ImageRule::Scalar, gy.data(), false, true).A;
  return op;
}

void pressure_from_phi(const SpMat& lap_phi, const Vec& phi, double a, Vec& p) {
  p.noalias() = lap_phi * phi;
  p = phi - a * p;
}

}  // namespace sphib
