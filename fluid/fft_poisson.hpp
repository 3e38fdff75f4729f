#pragma once
// A direct solver for lattice operators that are periodic in x and walled in y (the Poisson problem
// of Eq. 32 and the Crank-Nicolson system of Eq. 28 on every channel-like domain: Poiseuille, Couette, the membrane cases). On the fixed
// lattice such an operator couples (i_x, i_y) to (i_x + d_x mod n_x, i_y + d_y) with a coefficient
// that depends on i_y, d_y and d_x only (block circulant in x), and that is even in d_x (the
// kernel is radial and the wall images reflect in y). A discrete Fourier transform along x
// (FFTW, real to complex) then splits A x = b into n_x/2 + 1 independent real symmetric banded
// systems in y, one per wavenumber k,
//   B_k(i_y, i_y + d_y) = sum_{d_x} C(i_y, d_y, d_x) cos(2 pi k d_x / n_x),
// each factorised once by banded Cholesky (LAPACK dpbtrf). A solve is two FFTs of n_y rows and
// n_x/2 + 1 banded triangular solves: O(N log n_x) instead of the O(nnz(L)) of a sparse Cholesky.
//
// A is symmetric positive definite (the Crank-Nicolson matrix I - (nu dt/2) lap of Eq. 28), or, with
// `singular`, semi-definite with null vectors that are constant in y (-lap phi without the gauge pin:
// the constants; the exact projection's G^T G: also (-1)^{i_x}): every B_k that annihilates the
// constants in y is solved with x(k, i_y = 0) = 0, so a solution is returned for every right-hand
// side orthogonal to the null space (the caller fixes the null components, fluid/gauge.hpp).
#include <memory>
#include <string>

#include "fluid/lattice.hpp"
#include "fluid/linear_solver.hpp"

namespace sphib {

// The solver for A on lattice L, or nullptr when A lacks that structure (`why` then says which
// check failed): the domain must be periodic in x and walled in y, and every row must equal the
// block-circulant, x-even model of A to 1e-12 of max |A|.
std::unique_ptr<LinearSolver> make_fft_solver(const std::string& system, const SpMat& A, const Lattice& L,
                                              bool singular, std::string* why = nullptr);

}  // namespace sphib
