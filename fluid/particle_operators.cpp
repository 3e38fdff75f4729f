#include "fluid/particle_operators.hpp"

#include <algorithm>

namespace sphib {

void ParticleOperators::assemble(const PairList& P, const Images& im, int N, const CubicSplineKernel& W, double V,
                                 Operators& op) {
  make_pattern(P, im, N);
  const int K = P.size();
  lap_.resize(K);
  gx_.resize(K);
  gy_.resize(K);
  for (int k = 0; k < K; ++k) {
    const double F = W.F(P.r[k]);  // (1/r) dW/dr
    lap_[k] = 2.0 * V * F;         // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
    gx_[k] = V * P.rx[k] * F;      // Eqs. (27), (30): V (x_i - x_j) F_ij
    gy_[k] = V * P.ry[k] * F;
  }
  scatter(P, im, N, ImageRule::Velocity, lap_, true, op.lap_u.A, &op.lap_u.B);
  scatter(P, im, N, ImageRule::Velocity, gx_, false, op.grad_ux.A, &op.grad_ux.B);
  scatter(P, im, N, ImageRule::Velocity, gy_, false, op.grad_uy.A, &op.grad_uy.B);
  scatter(P, im, N, ImageRule::Scalar, lap_, true, op.lap_phi, nullptr);
  scatter(P, im, N, ImageRule::Scalar, gx_, false, op.grad_phix, nullptr);
  scatter(P, im, N, ImageRule::Scalar, gy_, false, op.grad_phiy, nullptr);
}

void ParticleOperators::make_pattern(const PairList& P, const Images& im, int N) {
  outer_.assign(N + 1, 0);
  outer_b_.assign(N + 1, 0);
  inner_.clear();
  inner_b_.clear();
  slot_.resize(P.size());
  diag_.resize(N);
  std::vector<int> cols;
  for (int i = 0; i < N; ++i) {
    cols.assign(1, i);  // the f_i part of every pair term
    int images = 0;
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      if (j < N) {
        cols.push_back(j);
      } else {  // an image couples i to its parent, and (velocity) to its offset c_m
        cols.push_back(im.parent[j - N]);
        inner_b_.push_back(j - N);  // increasing in m: the pairs are sorted by j
        ++images;
      }
    }
    std::sort(cols.begin(), cols.end());
    cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    const int begin = outer_[i];
    inner_.insert(inner_.end(), cols.begin(), cols.end());
    outer_[i + 1] = begin + static_cast<int>(cols.size());
    outer_b_[i + 1] = outer_b_[i] + images;
    auto where = [&](int col) {
      return begin + static_cast<int>(std::lower_bound(cols.begin(), cols.end(), col) - cols.begin());
    };
    diag_[i] = where(i);
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      slot_[k] = where(j < N ? j : im.parent[j - N]);
    }
  }
}

void ParticleOperators::scatter(const PairList& P, const Images& im, int N, ImageRule rule,
                                const std::vector<double>& a, bool difference, SpMat& A, SpMat* B) const {
  const int M = im.size();
  auto shape = [](SpMat& S, int rows, int cols, const std::vector<int>& outer, const std::vector<int>& inner) {
    S.resize(rows, cols);  // compressed and empty
    S.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), S.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), S.innerIndexPtr());
    std::fill(S.valuePtr(), S.valuePtr() + inner.size(), 0.0);
  };
  shape(A, N, N, outer_, inner_);
  const bool velocity = rule == ImageRule::Velocity;
  if (B) shape(*B, N, M, outer_b_, inner_b_);
  double* va = A.valuePtr();
  double* vb = B ? B->valuePtr() : nullptr;
  const double s_ij = difference ? -1.0 : 1.0;  // f_i - f_j  or  f_i + f_j
  int b = 0;                                    // B's entries are the image pairs, in order
  for (int i = 0; i < N; ++i)
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      va[diag_[i]] += a[k];  // the f_i part
      if (j < N) {
        va[slot_[k]] += s_ij * a[k];
      } else {  // image: f_j = sign f_p + c_j
        const double sign = velocity ? im.v_sign[j - N] : 1.0;
        va[slot_[k]] += s_ij * sign * a[k];
        if (vb) vb[b] = s_ij * a[k];
        ++b;
      }
    }
}

}  // namespace sphib
