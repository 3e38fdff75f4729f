#pragma once
// SPH operators on the fixed lattice as sparse matrices, assembled once (Eqs. 27-34).
// All use F_ij = (1/r) dW/dr and the particle volume V = m/rho (uniform density):
//   Laplacian (Morris form, Eqs. 28/31):   (lap f)_i  = sum_j 2 V (f_i - f_j) F_ij
//   gradient / divergence (Eqs. 27/30):    (grad f)_i = sum_j V (f_i + f_j) (x_i - x_j) F_ij
// A neighbour j that is an image carries f_j = sign_j f_parent + c_j (boundary.hpp), so each
// operator on a field with images is a pair (A, B):  Op f = A f + B c.
// A is square over particles; note that an image still couples particle i to the image's
// parent p, so image terms move into A(i, p) rather than dropping out.
#include "fluid/common/boundary.hpp"
#include "kernels/cubic_spline.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/algebra/products.hpp"

namespace sphib {

struct ImageOp {
  SpMat A;  // N x N, on the particle values
  SpMat B;  // N x M, on the image offsets c (zero columns for scalar images)
  void swap(ImageOp& o) {  // (Eigen's sparse matrices have no move assignment: an assignment copies)
    A.swap(o.A);
    B.swap(o.B);
  }
};

struct Operators {
  ImageOp lap_u;            // velocity Laplacian, images by Eq. (42)
  ImageOp grad_ux, grad_uy;  // x and y derivative of a velocity component (Eqs. 30, 40)
  SpMat lap_phi;            // Laplacian of phi, images phi_i' = phi_i (Eq. 31)
  SpMat grad_phix, grad_phiy;  // gradient of phi (Eqs. 27, 34)
  void swap(Operators& o) {
    lap_u.swap(o.lap_u);
    grad_ux.swap(o.grad_ux);
    grad_uy.swap(o.grad_uy);
    lap_phi.swap(o.lap_phi);
    grad_phix.swap(o.grad_phix);
    grad_phiy.swap(o.grad_phiy);
  }
};

struct OperatorRequest {
  bool velocity_gradient = true;  // divergence of u* (always needed by the projection)
};

enum class ImageRule { Velocity, Scalar };

// One operator: coefficient a_k of pair k, "difference" f_i - f_j or "sum" f_i + f_j.
// keep_zeros: explicit zeros stay, so that operators built from one pair list share one pattern
// (the fused products below need that).
ImageOp assemble_pairs(const PairList& P, int N, const Images& im, ImageRule rule, const double* a,
                       bool difference, bool keep_zeros = false);



// Eq. (35): p^{n+1/2} = phi^{n+1} - (nu dt / 2) lap phi^{n+1}, with a = nu dt / 2 (zero mean, as phi).
// `st`: lap_phi's stencil (find_row_stencil({&lap_phi})), the product through it (the same bits;
// needed when lap_phi keeps only its stencil's rows: stencil_rows_only).
void pressure_from_phi(const SpMat& lap_phi, const Vec& phi, double a, Vec& p, const RowStencil* st = nullptr);

// Which operators build_operators assembles (the others stay empty): all, the velocity operators
// (lap_u, grad_ux, grad_uy), the phi operators (lap_phi, grad_phix, grad_phiy), or lap_phi or the
// phi gradients alone. Each is the same, bit for bit, whichever set it is assembled with (EPSPH's
// compact storage assembles the sets one after another, so that they are never held whole
// together: eulerian.cpp).
enum class OperatorSet { All, Velocity, Phi, LapPhi, GradPhi };
Operators build_operators(const PairList& P, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                          OperatorSet set = OperatorSet::All);
// The rows a block of pairs gives at a time (EPSPH's compact storage: LatticePairs, operator_rows).
constexpr int kAssemblyRows = 4096;
// The rows r0 .. r0 + m - 1 alone of the operators of `set` (A m x N, B m x M, row q the operator's
// row r0 + q; the others empty) from P, the pairs of those rows (P.offset relative to r0:
// LatticePairs::rows): the same bits as those rows of build_operators'.
Operators operator_rows(const PairList& P, int r0, const Lattice& L, const Images& im, const CubicSplineKernel& W,
                        OperatorSet set);
Operators build_operators(const LatticePairs& pairs, long npairs, const Images& im, const CubicSplineKernel& W,
                          OperatorSet set = OperatorSet::All, int block_rows = kAssemblyRows);

}  // namespace sphib
