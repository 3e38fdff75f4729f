#pragma once
// Direct solvers for the lattice operators of EPSPH by fast transforms: the Crank-Nicolson system of
// Eq. (28), the Poisson problem of Eq. (32), the exact projection's G^T G and the markers' stream
// function, on every domain of Eq. (68): channels, doubly periodic boxes, closed boxes.
//
// Why they diagonalise. On the fixed lattice an operator is a convolution with one stencil s(d_x,
// d_y) on the lattice continued through its images: along a periodic axis by the period; along a
// walled axis by mirror images across the wall, which the half-spacing lattice of Eq. (68) places on
// lattice sites (row -1 - j is the image of row j), each carrying +f (even images: phi, Eq. 9) or -f
// (odd images: the velocity's no-slip rule of Eq. (42), a stream function; at corners the double
// reflection carries the product of the signs, fluid/common/boundary.hpp). The image terms fold into the
// matrix: along a walled axis of n sites
//   A(i, j) = s(j - i) +- s(-1 - j - i) +- s(2n - 1 - j - i)     (Toeplitz +- Hankel),
// which is the convolution on the 2n-periodic, half-sample even or odd extension. Such matrices are
// diagonalised exactly by the DCT-II (even) and the DST-II (odd), as circulants are by the DFT
// (S. A. Martucci, "Symmetric convolution and the discrete sine and cosine transforms", IEEE Trans.
// Signal Process. 42:1038, 1994; G. Strang, "The discrete cosine transform", SIAM Rev. 41:135, 1999):
// with s even in d (A symmetric), the eigenvalue of wavenumber theta is sum_d s(d) cos(theta d), with
//   periodic (DFT, FFTW r2c):     theta = 2 pi k / n,    k = 0 .. n/2
//   walls, even (DCT-II, REDFT10): theta = pi k / n,      k = 0 .. n - 1   (inverse REDFT01)
//   walls, odd  (DST-II, RODFT10): theta = pi k / n,      k = 1 .. n       (inverse RODFT01).
//   walls, even at one and odd at the other (DCT-IV REDFT11, DST-IV RODFT11; Martucci's quarter-wave
//   forms): theta = pi (k + 1/2) / n, k = 0 .. n - 1 (each its own inverse).
// Products of such operators (G^T G) have the same structure. Which images a field has at the walls
// (so which transform) is the boundary rule's (fluid/common/boundary_rule.hpp, the caller names the
// field); the solver checks that A has that structure.
//
// Two solvers follow from this, chosen by the y axis:
//  - y walled (channel, closed box): the transform along x only splits A x = b into one real
//    symmetric banded system in y per x wavenumber k,
//      B_k(i_y, i_y + d_y) = sum_{d_x} C(i_y, d_y, d_x) cos(theta_k d_x),
//    C the model of the rows of lattice row i_y (any coefficients in y: the wall folds included), each
//    factorised once by banded Cholesky (LAPACK dpbtrf). A solve is two transforms of n_y rows and the
//    banded substitutions, all wavenumbers at once.
//  - y periodic (doubly periodic box, walls in x and periodic in y): the transform along y too (FFT),
//    after which A is diagonal: a solve is a 2-D transform, a scaling and the inverse transform.
// On a channel (periodic x, walled y) the first is the solver sphib had before closed and doubly
// periodic boxes were added, with unchanged arithmetic.
//
// A is symmetric positive definite (Crank-Nicolson: I - (nu dt/2) lap), or, with `singular`,
// semi-definite (-lap phi without the gauge pin: the constants; G^T G: also alternating vectors,
// fluid/algebra/gauge.hpp): banded, every B_k that annihilates the constants or the alternating vector in y is
// solved with x(k, i_y = 0) = 0; diagonal, every zero eigenvalue's component is set to 0. So a solution
// is returned for every right-hand side orthogonal to the null space; the caller fixes the null
// components (fluid/algebra/gauge.hpp).
#include <functional>
#include <memory>
#include <string>

#include "fluid/common/lattice.hpp"
#include "fluid/algebra/linear_solver.hpp"

namespace sphib {

// A matrix given as consecutive blocks of its rows (make_fft_solver below).
using MatrixRows = std::function<void(const std::function<void(const SpMat& rows, int first_row)>&)>;

// The solver for A on lattice L, A acting on a field of kind `field` (the velocity's Crank-Nicolson
// system: Field::VelocityNormal, the x walls' normal component; phi: Field::Scalar; a stream
// function: Field::Stream), or nullptr when A lacks the structure (`why` then says which check
// failed). The transform along a walled x is the boundary rule's (fluid/common/boundary_rule.hpp):
// the field's image parities at the x walls: even at both -> DCT-II, odd at both -> DST-II, even
// and odd -> DCT-IV, odd and even -> DST-IV (a side without images is refused). Along a periodic axis every row must be a translate of its
// reference row; along a walled axis the translate with the wall images of that parity folded in;
// each to 1e-12 of max |A|, the stencil even along x (and along y when y is periodic), A symmetric,
// the systems positive definite (up to the null space when `singular`). The method text
// (info().method) names the transforms, the images and the systems.
std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L, Field field,
                                              bool singular, std::string* why = nullptr);

// The image parities (+1 even, -1 odd) at the left and right walls of a walled x (unused along a
// periodic x): a field's from the boundary rule (x_parities), or given. Different parities at the two
// walls take the quarter-wave transforms (DCT-IV: even left, odd right; DST-IV: the reverse; FFTW's
// REDFT11 and RODFT11, eigenvalues at theta_k = pi (k + 1/2) / n_x).
struct XParities {
  int left = 0, right = 0;
};
XParities x_parities(const Domain& d, Field field);
std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L, XParities x,
                                              bool singular, std::string* why = nullptr);
std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const MatrixRows& A, long n, const Lattice& L,
                                              XParities x, bool singular, std::string* why = nullptr);

// The same for an n x n matrix given as its rows, a block at a time: A(f) calls
// f(B, r0) for consecutive compressed blocks B of rows r0 .. r0 + B.rows() - 1, every row once, in
// order, once (the model and the rows against it with the rule's x images, in one pass), and twice
// more should A fail a check (the model, then the rows, for the reason). The matrix itself need never
// exist (EPSPH's compact storage: G^T G).
std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const MatrixRows& A, long n, const Lattice& L,
                                              Field field, bool singular, std::string* why = nullptr);

}  // namespace sphib
