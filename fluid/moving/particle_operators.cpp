#include "fluid/moving/particle_operators.hpp"

#include <algorithm>
#include <stdexcept>

namespace sphib {

// The value arrays a step writes: the six operators' A (same pattern), the three B, the systems.
struct ParticleOperators::Values {
  double *lu, *gxu, *gyu, *lp, *gxp, *gyp;  // lap_u.A, grad_ux.A, grad_uy.A, lap_phi, grad_phix, grad_phiy
  double *lb, *gxb, *gyb;                   // lap_u.B, grad_ux.B, grad_uy.B
  double *cn, *ph;                          // I - a lap_u (Eq. 28), -lap_phi (Eq. 32); null: not asked for
  double na;                                // -a
  double* S;                                // kernel sums (null: not asked for); V, W(0)
  double V, w_0;
  double sd;     // the divergence's diagonal sign: +1 the sum form (Eq. 30), -1 the difference form (A Eq. 14)
  double* divr;  // A Eq. (26)'s div r (null: not asked for)
};

namespace {


// The pair terms of one pair: Laplacian (Eqs. 28, 31) 2 V F_ij on f_i - f_j; gradient (Eqs. 27, 30)
// V (x_i - x_j) F_ij on f_i + f_j. Zero beyond the reach (a Verlet candidate beyond 2h).
struct PairTerms {
  double lap = 0, gx = 0, gy = 0, w = 0;  // w = W_ij (for the kernel sum)
  bool active = false;                    // closer than the reach
  PairTerms(const PairGeometry& g, int k, const KernelWF& W, double V, double reach) {
    if (g.r(k) < reach) {
      active = true;
      const double F = W.F(g.r(k), &w);  // (1/r) dW/dr
      lap = 2.0 * V * F;
      gx = V * g.rx(k) * F;
      gy = V * g.ry(k) * F;
    }
  }
};

}  // namespace

void ParticleOperators::assemble(const PairList& P, const Images& im, int N, const CubicSplineKernel& W, double V,
                                 double reach, bool new_pattern, Operators& op, const Systems& sys,
                                 double* kernel_sums, const PairRules& rules) {
  prepare(P, im, N, new_pattern, op, sys);
  assemble_rows(P, PairGeometry(P), im, N, W, V, reach, 0, N, op, sys, kernel_sums, rules);
}

void ParticleOperators::prepare(const PairList& P, const Images& im, int N, bool new_pattern, Operators& op,
                                const Systems& sys) {
  if (new_pattern || static_cast<int>(diag_.size()) != N) {
    make_pattern(P, im, N);
    shape(op, N, im.size(), sys);
  }
}

void ParticleOperators::assemble_rows(const PairList& P, const PairGeometry& g, const Images& im, int N,
                                      const CubicSplineKernel& W,
                                      double V, double reach, int i0, int i1, Operators& op, const Systems& sys,
                                      double* kernel_sums, const PairRules& rules) {
  Values v{op.lap_u.A.valuePtr(), op.grad_ux.A.valuePtr(), op.grad_uy.A.valuePtr(),
           op.lap_phi.valuePtr(), op.grad_phix.valuePtr(), op.grad_phiy.valuePtr(),
           op.lap_u.B.valuePtr(), op.grad_ux.B.valuePtr(), op.grad_uy.B.valuePtr(),
           sys.A_cn ? sys.A_cn->valuePtr() : nullptr, sys.A_phi ? sys.A_phi->valuePtr() : nullptr, -sys.a_cn,
           kernel_sums, V, W.W(0.0), rules.divergence_difference ? -1.0 : 1.0, rules.position_divergence};
  if (!sys.phi_rows && (!sys.A_phi || rules.divergence_difference))
    throw std::logic_error("ParticleOperators: phi_rows = false needs A_phi and the sum form");
  const KernelWF Wl(W);
  // One pass over the pairs: each pair's terms into every operator, in the order of the separate
  // scatters of build_operators (the f_i part on the diagonal, then f_j), so that every sum carries
  // its bits; an image j carries f_j = sign f_parent + c_j (velocity; sign +1 for phi).
  int b = outer_b_[i0];  // B's entries are the image pairs, in order
  for (int i = i0; i < i1; ++i) {
    if (!row_images_[i]) {
      if (v.cn && v.ph && !sys.phi_rows && !v.divr) row_plain<true, false, false>(P, g, i, Wl, V, reach, v);
      else if (v.cn && v.ph && !sys.phi_rows) row_plain<true, false>(P, g, i, Wl, V, reach, v);
      else if (v.cn && v.ph) row_plain<true>(P, g, i, Wl, V, reach, v);
      else row_plain<false>(P, g, i, Wl, V, reach, v);
    } else {
      row_with_images(P, g, im, i, N, Wl, V, reach, v, rules, b);
    }
  }
}

// A row without images has one pair per column: each entry is written once, the diagonal summed in
// registers. kPhi false: the phi operators' entries are left (ProjectionSystems::phi_rows); kDivr
// false: no div r asked for (v.divr null), and its sum is not made.
template <bool kSystems, bool kPhi, bool kDivr>
void ParticleOperators::row_plain(const PairList& P, const PairGeometry& g, int i, const KernelWF& W, double V, double reach,
                                  const Values& v) const {
  double dl = 0, dgx = 0, dgy = 0, sw = v.w_0, dr = 0;  // sw: W(0) + sum_j W_ij, in pair order
  for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
    const PairTerms t(g, k, W, V, reach);
    if (t.active) sw += t.w;
    if (kDivr) dr -= t.gx * g.rx(k) + t.gy * g.ry(k);  // A Eq. (26): -V (x_i - x_j) . grad_i W_ij
    const int s = slot_[k];
    const double l = t.active ? -1.0 * t.lap : 0.0;
    dl += t.lap;
    dgx += t.gx;
    dgy += t.gy;
    v.lu[s] = l;
    v.gxu[s] = t.gx;
    v.gyu[s] = t.gy;
    if (kPhi) {
      v.lp[s] = l;
      v.gxp[s] = t.gx;
      v.gyp[s] = t.gy;
    }
    if (kSystems) {
      v.cn[s] = v.na * l;  // as crank_nicolson_matrix(): -a lap, then + 1 on the diagonal
      v.ph[s] = -l;
    }
  }
  const int d = diag_[i];
  v.lu[d] = dl;
  if (kPhi) {
    v.lp[d] = dl;
    v.gxp[d] = dgx;
    v.gyp[d] = dgy;
  }
  v.gxu[d] = v.sd * dgx;  // u_i's part: + (sum form) or - (difference form)
  v.gyu[d] = v.sd * dgy;
  if (kDivr && v.divr) v.divr[i] = dr;
  if (kSystems) {
    v.cn[d] = v.na * dl + 1.0;
    v.ph[d] = -dl;
  }
  if (v.S) v.S[i] = v.V * sw;
}

// A row with images may meet a column twice (a neighbour and an image's parent, or i and its own
// image): zeroed, then summed in place. A fixed point (parent < 0) takes the pair-local rules of the
// header.
void ParticleOperators::row_with_images(const PairList& P, const PairGeometry& g, const Images& im, int i, int N,
                                        const KernelWF& W,
                                        double V, double reach, const Values& v, const PairRules& rules,
                                        int& b) const {
  const int d = diag_[i], o0 = outer_[i], o1 = outer_[i + 1];
  for (double* a : {v.lu, v.gxu, v.gyu, v.lp, v.gxp, v.gyp}) std::fill(a + o0, a + o1, 0.0);
  double sw = v.w_0, dr = 0;
  for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
    const int j = P.j[k];
    const bool image = j >= N, fixed = image && im.parent[j - N] < 0;
    const PairTerms t(g, k, W, fixed ? rules.V_fixed : V, reach);
    if (!fixed) dr -= t.gx * g.rx(k) + t.gy * g.ry(k);  // A Eq. (26), the particles' part
    if (fixed) {  // a Morris wall particle: f_w = s f_i + weight c_w (header)
      if (t.active) sw += t.w;
      const double beta = t.active ? rules.wall_beta[k] : 0.0;
      v.lu[d] += beta * t.lap;           // A Eq. (18): u_i - u_w = beta (u_i - c_w)
      v.gxu[d] += v.sd * t.gx - t.gx;    // u_w = 2 c_w - u_i: sum form 0, difference form -2 u_i
      v.gyu[d] += v.sd * t.gy - t.gy;
      v.gxp[d] += 2.0 * t.gx;            // phi_w = phi_i + the caller's offset: (phi_i + phi_w) (A Eq. 13)
      v.gyp[d] += 2.0 * t.gy;
      v.lb[b] = -beta * t.lap;
      v.gxb[b] = 2.0 * t.gx;
      v.gyb[b] = 2.0 * t.gy;
      ++b;
      continue;
    }
    if (t.active) {
      sw += t.w;
      const int s = slot_[k];
      const double sign = image ? im.v_sign[j - N] : 1.0;     // the images' parities (boundary_rule.hpp)
      const double s_sign = image ? im.s_sign[j - N] : 1.0;  // velocity, phi
      v.lu[d] += t.lap;
      v.lu[s] += -1.0 * sign * t.lap;
      v.gxu[d] += v.sd * t.gx;
      v.gxu[s] += 1.0 * sign * t.gx;
      v.gyu[d] += v.sd * t.gy;
      v.gyu[s] += 1.0 * sign * t.gy;
      v.lp[d] += t.lap;
      v.lp[s] += -1.0 * s_sign * t.lap;
      v.gxp[d] += t.gx;
      v.gxp[s] += 1.0 * s_sign * t.gx;
      v.gyp[d] += t.gy;
      v.gyp[s] += 1.0 * s_sign * t.gy;
    }
    if (image) {
      v.lb[b] = t.active ? -1.0 * t.lap : 0.0;
      v.gxb[b] = t.gx;
      v.gyb[b] = t.gy;
      ++b;
    }
  }
  for (int k = o0; k < o1; ++k) {  // the systems, as crank_nicolson_matrix() and -lap_phi make them
    if (v.cn) v.cn[k] = v.na * v.lu[k];
    if (v.ph) v.ph[k] = -v.lp[k];
  }
  if (v.cn) v.cn[d] += 1.0;
  if (v.S) v.S[i] = v.V * sw;
  if (v.divr) v.divr[i] = dr;
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
      } else {  // an image couples i to its parent (a fixed point to none), and (velocity) to its offset c_m
        if (im.parent[j - N] >= 0) cols.push_back(im.parent[j - N]);
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
      const int col = j < N ? j : im.parent[j - N] >= 0 ? im.parent[j - N] : i;  // (a fixed point: unused)
      slot_[k] = where(col);
    }
  }
}

}  // namespace sphib
