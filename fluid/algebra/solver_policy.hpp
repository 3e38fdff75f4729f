#pragma once
// Which solver each linear system of a projection method gets: ONE policy for EPSPH, LPSPH and
// ISPH (solver.crank_nicolson / solver.poisson = "auto"; another value forces that solver).
//
//   Crank-Nicolson (Eq. 28): on a fixed lattice the FFT lattice solver where the matrix has its
//     structure (fluid/algebra/fft_poisson.hpp); else warm-started Jacobi-PCG when the Gershgorin bound
//     b = 2 a max|lap_ii| <= 0.5 (the eigenvalues of I - a lap lie in [1, 1 + b]: condition number
//     <= 1.5, 4-6 iterations to round-off, each a pass over A, cheaper than two triangular solves:
//     docs/method/choices.md, "Solvers: the thresholds"); else CHOLMOD.
//   Poisson (Eq. 32) and the stream functions: the FFT lattice solver on the singular operator
//     itself (its own gauge: no pin in the right-hand side) where it applies; else CHOLMOD on the
//     operator pinned by its gauge (fluid/algebra/gauge.hpp).
//   CHOLMOD: simplicial or supernodal by the size of the factor, at 8e5 non-zeros in L for a
//     matrix factorised once (the solves dominate) and 1.5e5 for one factorised every step (the
//     numeric factorisation dominates): docs/method/choices.md, "Solvers: the thresholds".
//
// Moving particles (Refactor::EveryStep: LPSPH, ISPH) change the matrices a little every step, and
// refactorising them every step was 80% of an LPSPH step. There (solver.* = "pcg_fft" or
// "pcg_cholmod" force one): conjugate gradients warm-started from the last solution(s) and
// preconditioned by a solver of a nearby matrix (linear_solver.hpp, lagged_pcg), to
// |r| <= 1e-14 |b| (as the Jacobi-PCG) or a backward error of 1e-14:
//   pcg_fft      the FFT solver of the same system on the fixed lattice the particles started on
//                (`near`; where make_fft_solver applies): no factorisation at all while the
//                particles stay near their lattice points; should they drift far (a solve needing
//                more than 8 iterations), the preconditioner becomes a lagged CHOLMOD factor;
//   pcg_cholmod  a CHOLMOD factorisation of an earlier step's matrix, refactorised (symbolic analysis
//                kept while the pattern stays) when a solve needs more than 8 iterations (any
//                threshold from 6 to 12 costs the same: docs/method/choices.md, "Solvers: the
//                thresholds").
//   auto, Crank-Nicolson: pcg_fft where it applies; else Jacobi-PCG while the Gershgorin bound
//     b <= 40 (Jacobi's iterations grow like sqrt(b) and reach pcg_cholmod's cost near b = 40:
//     docs/method/choices.md, "Solvers: the thresholds"); else pcg_cholmod.
//   auto, Poisson: pcg_fft where it applies, else pcg_cholmod; both take the singular operator
//     itself (its gauge inside: linear_solver.hpp), so the system is unpinned.
#include <memory>
#include <string>

#include "fluid/algebra/fft_poisson.hpp"
#include "fluid/algebra/gauge.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/algebra/linear_solver.hpp"

namespace sphib {

// The lagged CG of the moving particles (see above): rtol 1e-14, refreshed above 8 iterations.
inline LaggedPcgOptions moving_cg_options() {
  LaggedPcgOptions o;
  o.rtol = 1e-14;
  o.refresh_iterations = 8;
  return o;
}

// A matrix factorised once for the whole run (EPSPH), or again every step (moving particles:
// LinearSolver::refactorize, the symbolic analysis kept while the pattern stays).
enum class Refactor { Once, EveryStep };

// The fixed lattice the moving particles started on and the system's matrix there (the FFT
// preconditioner's), or nothing.
struct LatticeReference {
  const Lattice* lattice = nullptr;
  const SpMat* A = nullptr;
};

struct SystemSolver {
  std::unique_ptr<LinearSolver> solver;
  bool unpinned = false;  // it takes the singular operator itself: no pin in the right-hand side
};

// The Crank-Nicolson matrix A = I - a lap on the velocity (its images: the boundary rule's velocity
// parity; `field` the component's role at the x walls for the FFT solver: VelocityNormal for both
// components where they share a parity, and for the x component; VelocityTangential for the y
// component where the parities differ, fluid/common/boundary.hpp component_matrix). `fixed`: the
// lattice when the particles never move (the FFT solver needs it), else nullptr. The solver's log
// line says what was chosen and why.
std::unique_ptr<LinearSolver> crank_nicolson_solver(const SpMat& A, const SpMat& lap, double a, SolverKind kind,
                                                    const Lattice* fixed, Refactor refactor,
                                                    const LatticeReference& near = {},
                                                    Field field = Field::VelocityNormal);

// A symmetric positive semi-definite operator A on a field of kind `field` (its images: the FFT
// solver's transform, make_fft_solver) whose null space is that of gauge g. With
// Refactor::EveryStep and a direct solver the pinned matrix keeps A's pattern (refactorize with
// g.pinned(A, false)); an unpinned solver (FFT, the preconditioned CG) is refactorised with A itself.
// `cg`: the lagged CG's tolerance and refresh rule (default rtol 1e-14, 8 iterations; ISPH sets its
// own: isph.cpp, make_solvers).
SystemSolver singular_solver(const std::string& system, Field field, const SpMat& A, const Gauge& g, SolverKind kind,
                             const Lattice* fixed, Refactor refactor, const LatticeReference& near = {},
                             const LaggedPcgOptions& cg = moving_cg_options());

// singular_solver's FFT lattice solver for an n x n operator given by its rows (MatrixRows: the
// matrix need never exist), where `kind` takes it (auto, fft): that solver, or none when `kind`
// is another or A lacks the structure (then the caller makes A for singular_solver; fft refuses
// as singular_solver does).
SystemSolver lattice_singular_solver(const std::string& system, Field field, const MatrixRows& A, long n, const Gauge& g,
                                     SolverKind kind, const Lattice& fixed);

// The rows of -A, and of the Crank-Nicolson matrix I - a lap, a block at a time (each row the same
// bits as the whole matrix's: crank_nicolson_matrix, negate), for the two solvers below: the lattice
// solver reads them without the matrix ever made (EPSPH's compact storage).
// `rows(r0, m)`: the operator's rows r0 .. r0 + m - 1 (an m-row matrix; EPSPH's compact operators
// give them by StencilRows), n its row count.
using RowsOf = std::function<SpMat(int r0, int m)>;
MatrixRows negated_rows(const SpMat& A);
MatrixRows negated_rows(RowsOf rows, int n);
MatrixRows crank_nicolson_rows(const SpMat& lap, double a);
MatrixRows crank_nicolson_rows(RowsOf lap, int n, double a);
// crank_nicolson_solver's FFT lattice solver of I - a lap from its rows, where `kind` takes it (auto,
// fft): that solver, or nullptr when `kind` is another or the matrix lacks the structure (then the
// caller makes the matrix for crank_nicolson_solver; fft refuses as crank_nicolson_solver does).
std::unique_ptr<LinearSolver> lattice_crank_nicolson_solver(const MatrixRows& A, long n, SolverKind kind,
                                                            const Lattice& fixed, Field field = Field::VelocityNormal);

}  // namespace sphib
