#include "fluid/particle_operators.hpp"

#include <algorithm>

namespace sphib {

void ParticleOperators::assemble(const PairList& P, const Images& im, int N, const CubicSplineKernel& W, double V,
                                 double reach, bool new_pattern, Operators& op, const Systems& sys) {
  if (new_pattern || static_cast<int>(diag_.size()) != N) {
    make_pattern(P, im, N);
    shape(op, N, im.size(), sys);
  }
  double *lu = op.lap_u.A.valuePtr(), *gxu = op.grad_ux.A.valuePtr(), *gyu = op.grad_uy.A.valuePtr();
  double *lp = op.lap_phi.valuePtr(), *gxp = op.grad_phix.valuePtr(), *gyp = op.grad_phiy.valuePtr();
  double *lb = op.lap_u.B.valuePtr(), *gxb = op.grad_ux.B.valuePtr(), *gyb = op.grad_uy.B.valuePtr();
  double* cn = sys.A_cn ? sys.A_cn->valuePtr() : nullptr;
  double* ph = sys.A_phi ? sys.A_phi->valuePtr() : nullptr;
  const double na = -sys.a_cn;
  // One pass over the pairs: each pair's coefficients into every operator, in the order of the
  // separate scatters of build_operators (the f_i part on the diagonal, then f_j), so that every sum
  // carries its bits:
  //   Laplacian (Eqs. 28, 31): f_i - f_j with 2 V F_ij; gradient (Eqs. 27, 30): f_i + f_j with
  //   V (x_i - x_j) F_ij; an image j carries f_j = sign f_parent + c_j (velocity; sign +1 for phi).
  // A row without images has one pair per column: each entry is written once (the diagonal summed
  // in registers). A row with images may meet a column twice (a neighbour and an image's parent, or
  // i and its own image): zeroed, then summed in place.
  int b = 0;  // B's entries are the image pairs, in order
  for (int i = 0; i < N; ++i) {
    const int di = diag_[i], k0 = P.offset[i], k1 = P.offset[i + 1];
    if (!row_images_[i]) {
      double dl = 0, dgx = 0, dgy = 0;
      for (int k = k0; k < k1; ++k) {
        const int s = slot_[k];
        double l = 0, gx = 0, gy = 0;  // a Verlet candidate beyond 2h has zero coefficients
        if (P.r[k] < reach) {
          const double F = W.F(P.r[k]);  // (1/r) dW/dr
          const double lap = 2.0 * V * F;
          gx = V * P.rx[k] * F;
          gy = V * P.ry[k] * F;
          l = -1.0 * lap;
          dl += lap;
          dgx += gx;
          dgy += gy;
        }
        lu[s] = lp[s] = l;
        gxu[s] = gxp[s] = gx;
        gyu[s] = gyp[s] = gy;
      }
      lu[di] = lp[di] = dl;
      gxu[di] = gxp[di] = dgx;
      gyu[di] = gyp[di] = dgy;
    } else {
      for (double* v : {lu, gxu, gyu, lp, gxp, gyp}) std::fill(v + outer_[i], v + outer_[i + 1], 0.0);
      for (int k = k0; k < k1; ++k) {
        const int j = P.j[k];
        const bool image = j >= N;
        double lap = 0, gx = 0, gy = 0;
        if (P.r[k] < reach) {
          const double F = W.F(P.r[k]);
          lap = 2.0 * V * F;
          gx = V * P.rx[k] * F;
          gy = V * P.ry[k] * F;
          const int s = slot_[k];
          const double sign = image ? im.v_sign[j - N] : 1.0;
          lu[di] += lap;
          lu[s] += -1.0 * sign * lap;
          gxu[di] += gx;
          gxu[s] += 1.0 * sign * gx;
          gyu[di] += gy;
          gyu[s] += 1.0 * sign * gy;
          lp[di] += lap;
          lp[s] += -1.0 * lap;
          gxp[di] += gx;
          gxp[s] += 1.0 * gx;
          gyp[di] += gy;
          gyp[s] += 1.0 * gy;
        }
        if (image) {
          lb[b] = lap != 0 ? -1.0 * lap : 0.0;
          gxb[b] = gx;
          gyb[b] = gy;
          ++b;
        }
      }
    }
    // The systems of the step, as crank_nicolson_matrix() and -lap_phi make them: I - a lap (Eq. 28),
    // -lap phi (Eq. 32).
    for (int k = outer_[i]; k < outer_[i + 1]; ++k) {
      if (cn) cn[k] = na * lu[k];
      if (ph) ph[k] = -lp[k];
    }
    if (cn) cn[di] += 1.0;
  }
}

void ParticleOperators::shape(Operators& op, int N, int M, const Systems& sys) const {
  auto set = [](SpMat& S, int rows, int cols, const std::vector<int>& outer, const std::vector<int>& inner) {
    S.resize(rows, cols);  // compressed and empty
    S.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), S.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), S.innerIndexPtr());
    std::fill(S.valuePtr(), S.valuePtr() + inner.size(), 0.0);
  };
  for (SpMat* S : {&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A, &op.lap_phi, &op.grad_phix, &op.grad_phiy})
    set(*S, N, N, outer_, inner_);
  for (SpMat* S : {sys.A_cn, sys.A_phi})
    if (S) set(*S, N, N, outer_, inner_);
  for (SpMat* S : {&op.lap_u.B, &op.grad_ux.B, &op.grad_uy.B}) set(*S, N, M, outer_b_, inner_b_);
}

void ParticleOperators::make_pattern(const PairList& P, const Images& im, int N) {
  outer_.assign(N + 1, 0);
  outer_b_.assign(N + 1, 0);
  inner_.clear();
  inner_b_.clear();
  slot_.resize(P.size());
  diag_.resize(N);
  row_images_.assign(N, 0);
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
    row_images_[i] = images > 0;
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

}  // namespace sphib
