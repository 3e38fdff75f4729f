#pragma once
// The operators of Eqs. (27)-(34) (operators.hpp) assembled again every step for moving particles
// (LPSPH, ISPH), straight into compressed rows: one pattern from the pair list for every operator
// (A: particle i, its neighbours and the parents of its image neighbours; B: i and its image
// neighbours; explicit zeros kept, so that the fused products of products.hpp apply and a pattern
// that does not change keeps the factorisations' symbolic analysis), then the values of all six
// operators in one pass over the pairs. The values equal build_operators' for the same pairs.
//
// ISPH (isph.hpp) asks for two differences (PairRules): the divergence in the difference form of
// Afanasiev et al. ["A"] Eq. (14), and neighbours that are fixed points, the Morris wall particles
// (walls.hpp), instead of mirror images. A fixed point is an image without a parent (Images::parent
// < 0); the value it carries is an affine function of the PAIR's own particle i and of its offset c_w
// (the wall particle's prescribed velocity), f_w = s f_i + weight c_w, by operator:
//   lap_u (A Eq. 18, Morris et al. 1997):  u_w = (1 - beta) u_i + beta c_w, beta = 1 + d_w/d_i the
//        pair's Morris factor (walls.hpp, morris_wall_factor): the linear extrapolation through the
//        wall velocity, so that u_i - u_w = beta (u_i - c_w): A(i, i) += beta a_k, B(i, w) = -beta a_k;
//   grad_ux, grad_uy (the divergence):     u_w = 2 c_w - u_i, the mirror rule of Eq. (42) taken pair by
//        pair: the wall's whole flux jump enters the divergence (with u_w = c_w only half of it would,
//        the other half lying in the wall particles' own rows, which are no unknowns here);
//   lap_phi:                                phi_w = phi_i, the homogeneous Neumann condition of A
//        Section 3.6 taken pair by pair: a wall pair drops out of the Laplacian, which stays the
//        symmetric graph Laplacian of the fluid pairs;
//   grad_phix, grad_phiy (sum form, A Eq. 13): phi_w = phi_i + o_iw, the pair's own value and an
//        offset the caller adds (ISPH: the hydrostatic rho g . (x_w - x_i) of Adami et al., isph.hpp):
//        (phi_i + phi_w) puts 2 phi_i on the diagonal.
// So A's pattern has no column for a fixed point (B has one per pair), and the Poisson matrix
// -lap_phi is symmetric: no Neumann row breaks it (A's PGMRES is not needed; CHOLMOD and CG apply).
//
// With a Verlet list (neighbours.hpp) the pairs are candidates that may lie beyond the reach 2h; they
// stay in the pattern with zero coefficients (the kernel vanishes there), so that the pattern is
// made only when the list is built again and a step computes the values alone (no allocation).
#include <vector>

#include "fluid/algebra/operators.hpp"

namespace sphib {

// The kernel of Eq. (19) for a pass over pairs: W(r) and F(r) = (1/r) dW/dr together, bit for bit
// CubicSplineKernel's W and F (kernels/cubic_spline.hpp), from one q = r / h and with the factor w0 / h^2 computed
// once: inside the kernel's branches the compiler may not hoist that division, and it was a third
// of the assembly's time (perf, 64^2). Tested equal to W.W and W.F bit for bit
// (tests/test_lagrangian.cpp).
struct KernelWF {
  double h, w0, c;  // c = w0 / (h h), as kernels/cubic_spline.hpp computes it
  explicit KernelWF(const CubicSplineKernel& W) : h(W.h), w0(W.w0), c(W.w0 / (W.h * W.h)) {}
  double F(double r, double* w = nullptr) const {  // also W(r) into *w when asked
    const double q = r / h;
    if (q < 1.0) {
      if (w) *w = w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
      return c * (-2.0 + 1.5 * q);
    }
    if (q < 2.0) {
      const double t = 2.0 - q;
      if (w) *w = w0 * t * t * t / 6.0;
      return -c * 0.5 * t * t / q;
    }
    if (w) *w = 0.0;
    return 0.0;
  }
};

// What ISPH changes (see the header); the defaults give LPSPH's operators.
struct PairRules {
  bool divergence_difference = false;  // grad_ux, grad_uy by A Eq. (14): sum_j V (u_j - u_i) . grad_i W_ij
  const double* wall_beta = nullptr;   // per pair (read at pairs with a fixed point): Morris's beta
  double V_fixed = 0;                  // the volume of a fixed point (its lattice cell dx dy)
  // N, when given: A Eq. (26)'s div r_i = -sum_j V_j (x_i - x_j) . grad_i W_ij over the particles and
  // the images with a parent (the fixed points' part is the caller's: isph.cpp)
  double* position_divergence = nullptr;
};

// The two systems of a projection step, assembled with the operators when given (their pattern):
// A_cn = I - a_cn lap_u (Eq. 28, as ProjectionFluid::crank_nicolson_matrix) and A_phi = -lap_phi
// (Eq. 32).
// phi_rows = false (with A_phi, the sum form): the values of the phi operators (lap_phi, grad_phix,
// grad_phiy) are written only in the rows with images; in the others they are, bit for bit, -A_phi
// and grad_ux.A, grad_uy.A (images carry phi and u alike only there), and the caller takes them
// from those (LPSPH: ProjectionFluid's phi_ops_from_, operators()).
struct ProjectionSystems {
  double a_cn = 0;
  SpMat* A_cn = nullptr;
  SpMat* A_phi = nullptr;
  bool phi_rows = true;
};

class ParticleOperators {
 public:
  using Systems = ProjectionSystems;
  // op at the particles of P (N of them, uniform volume V) and the images im; pairs at r >= reach
  // contribute zeros. `new_pattern`: P's pairs (or im) changed since the last call, else only their
  // geometry did and op (and the systems) keep their pattern. `kernel_sums` (N, when given): the
  // kernel sums S_i = V (W(0) + sum_j W_ij) over the same pairs (LPSPH's breakdown check, Section
  // 5.2.2), summed in pair order. `rules`: ISPH's (PairRules), required when im has fixed points.
  void assemble(const PairList& P, const Images& im, int N, const CubicSplineKernel& W, double V, double reach,
                bool new_pattern, Operators& op, const Systems& sys = {}, double* kernel_sums = nullptr,
                const PairRules& rules = {});
  // The same in two parts, for a pass that follows the Verlet list's moves row block by row block
  // (VerletList::update with rows): prepare() the pattern (when new) and shape, then rows [i0, i1)
  // in order over all rows; the same values as assemble().
  void prepare(const PairList& P, const Images& im, int N, bool new_pattern, Operators& op, const Systems& sys = {});
  // g: the pairs' rx, ry, r (P's, or a block's: VerletList::update with rows).
  void assemble_rows(const PairList& P, const PairGeometry& g, const Images& im, int N, const CubicSplineKernel& W,
                     double V, double reach,
                     int i0, int i1, Operators& op, const Systems& sys = {}, double* kernel_sums = nullptr,
                     const PairRules& rules = {});
  // The position of the diagonal entry of row i in the values of op's A matrices.
  const std::vector<int>& diagonal() const { return diag_; }

 private:
  struct Values;  // the value arrays a step writes (particle_operators.cpp)
  void make_pattern(const PairList& P, const Images& im, int N);
  void shape(Operators& op, int N, int M, const Systems& sys) const;
  template <bool kSystems, bool kPhi = true, bool kDivr = true>
  void row_plain(const PairList& P, const PairGeometry& g, int i, const KernelWF& W, double V, double reach, const Values& v) const;
  void row_with_images(const PairList& P, const PairGeometry& g, const Images& im, int i, int N, const KernelWF& W, double V,
                       double reach, const Values& v, const PairRules& rules, int& b) const;
  std::vector<int> outer_, inner_, slot_, diag_, outer_b_, inner_b_;  // the pattern
  std::vector<char> row_images_;                                      // row i has image pairs
};

}  // namespace sphib
