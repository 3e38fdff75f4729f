#include "fluid/solver_policy.hpp"

#include <sstream>
#include <stdexcept>

#include "fluid/fft_poisson.hpp"

namespace sphib {

namespace {

// CHOLMOD (auto) or the solver asked for.
std::unique_ptr<LinearSolver> direct(const std::string& system, const SpMat& A, SolverKind kind, Refactor refactor) {
  if (kind != SolverKind::Auto || refactor == Refactor::Once || !is_symmetric(A)) return factorize(system, A, kind);
  return cholmod_by_factor_size(system, A, 1.5e5, "auto, refactorised every step");
}

// The FFT lattice solver where `kind` allows it and A has the structure; a refusal when it was asked
// for and does not apply; nullptr otherwise, with the reason in `why`.
std::unique_ptr<LinearSolver> lattice_solver(const std::string& system, const std::string& key, const SpMat& A,
                                             bool singular, SolverKind kind, const Lattice* fixed, std::string& why) {
  if (kind != SolverKind::Auto && kind != SolverKind::Fft) return nullptr;
  if (!fixed) {
    why = "the particles move (the FFT solver needs the fixed lattice)";
  } else if (auto s = make_fft_solver(system, A, *fixed, singular, &why)) {
    if (kind == SolverKind::Auto) s->annotate(" (auto)", 0.0);
    return s;
  }
  if (kind == SolverKind::Fft) throw std::invalid_argument(key + " = \"fft\" does not apply: " + why);
  return nullptr;
}

}  // namespace

std::unique_ptr<LinearSolver> crank_nicolson_solver(const SpMat& A, const SpMat& lap, double a, SolverKind kind,
                                                    const Lattice* fixed, Refactor refactor) {
  const std::string system = "Crank-Nicolson";
  std::string why;
  if (auto s = lattice_solver(system, "solver.crank_nicolson", A, false, kind, fixed, why)) return s;
  const double b = 2.0 * a * lap.diagonal().cwiseAbs().maxCoeff();  // Gershgorin bound (see the header)
  auto s = direct(system, A, kind == SolverKind::Auto && b <= 0.5 ? SolverKind::Pcg : kind, refactor);
  if (kind == SolverKind::Auto) {
    std::ostringstream note;
    note << " (auto: no FFT solver: " << why << "; Gershgorin bound nu dt max|lap_ii| = " << b
         << (b <= 0.5 ? " <= 0.5)" : " > 0.5)");
    s->annotate(note.str(), 0.0);
  }
  return s;
}

SystemSolver singular_solver(const std::string& system, const SpMat& A, const Gauge& g, SolverKind kind,
                             const Lattice* fixed, Refactor refactor) {
  std::string why;
  SystemSolver r;
  r.solver = lattice_solver(system, "solver.poisson", A, g.dimension() > 0, kind, fixed, why);
  if (r.solver) {
    r.unpinned = true;
    return r;
  }
  const SpMat P = g.dimension() == 0 ? A : g.pinned(A, refactor == Refactor::Once);
  r.solver = direct(system, P, kind, refactor);
  if (kind == SolverKind::Auto && fixed) r.solver->annotate(" (auto: no FFT solver: " + why + ")", 0.0);
  return r;
}

}  // namespace sphib
