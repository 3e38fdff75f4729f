#include "fluid/solver_policy.hpp"

#include <sstream>
#include <stdexcept>
#include <utility>

#include "fluid/fft_poisson.hpp"

namespace sphib {

namespace {

// CHOLMOD (auto) or the solver asked for.
std::unique_ptr<LinearSolver> direct(const std::string& system, const SpMat& A, SolverKind kind, Refactor refactor) {
  if (kind != SolverKind::Auto || refactor == Refactor::Once || !is_symmetric(A)) return factorize(system, A, kind);
  return cholmod_by_factor_size(system, A, 1.5e5, "auto, refactorised every step");
}

bool lagged(SolverKind kind) { return kind == SolverKind::PcgFft || kind == SolverKind::PcgCholmod; }

// Moving particles: CG preconditioned by the lattice's FFT solver (kind Auto or PcgFft, where it
// applies) or by a lagged CHOLMOD factor (solver_policy.hpp). `key` names the scene key for errors.
std::unique_ptr<LinearSolver> lagged_solver(const std::string& system, const std::string& key, const SpMat& A,
                                            SolverKind kind, const LatticeReference& near, NullSpaceHooks null) {
  std::string why = "no lattice given";
  std::unique_ptr<LinearSolver> start;
  if (kind != SolverKind::PcgCholmod && near.lattice && near.A)
    start = make_fft_solver(system + " on the lattice", *near.A, *near.lattice, null.singular(), &why);
  if (kind == SolverKind::PcgFft && !start) throw std::invalid_argument(key + " = \"pcg_fft\" does not apply: " + why);
  LaggedPcgOptions opt;
  opt.rtol = 1e-12;
  opt.refresh_iterations = 8;
  auto factorise = [](const std::string& s, const SpMat& D) { return direct(s, D, SolverKind::Auto, Refactor::EveryStep); };
  const bool fft = static_cast<bool>(start);
  auto solver = lagged_pcg(system, A, std::move(start), factorise, std::move(null), opt);
  if (kind == SolverKind::Auto)
    solver->annotate(fft ? " (auto: moving particles near a lattice with an FFT solver)"
                         : " (auto: moving particles; no FFT lattice solver: " + why + ")",
                     0.0);
  return solver;
}

// The FFT lattice solver where `kind` allows it and A has the structure; a refusal when it was asked
// for and does not apply; nullptr otherwise, with the reason in `why`.
std::unique_ptr<LinearSolver> lattice_solver(const std::string& system, const std::string& key, const SpMat& A,
                                             bool singular, SolverKind kind, const Lattice* fixed, std::string& why) {
  if (kind != SolverKind::Auto && kind != SolverKind::Fft) return nullptr;
  if (!fixed) {
    why = "the particles move (the FFT solver needs the fixed lattice)";
  } else if (auto s = make_fft_solver(system, A, *fixed, singular, &why)) {
    if (kind == SolverKind::Auto) s->annotate(" (auto: periodic in x, walled in y)", 0.0);
    return s;
  }
  if (kind == SolverKind::Fft) throw std::invalid_argument(key + " = \"fft\" does not apply: " + why);
  return nullptr;
}

}  // namespace

std::unique_ptr<LinearSolver> crank_nicolson_solver(const SpMat& A, const SpMat& lap, double a, SolverKind kind,
                                                    const Lattice* fixed, Refactor refactor,
                                                    const LatticeReference& near) {
  const std::string system = "Crank-Nicolson";
  std::string why;
  if (lagged(kind) && refactor == Refactor::Once)
    throw std::invalid_argument("solver.crank_nicolson: pcg_fft and pcg_cholmod are for moving particles");
  if (auto s = lattice_solver(system, "solver.crank_nicolson", A, false, kind, fixed, why)) return s;
  const double b = 2.0 * a * lap.diagonal().cwiseAbs().maxCoeff();  // Gershgorin bound (see the header)
  if (lagged(kind) || (kind == SolverKind::Auto && refactor == Refactor::EveryStep && b > 0.5 && is_symmetric(A)))
    return lagged_solver(system, "solver.crank_nicolson", A, kind, near, {});
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
                             const Lattice* fixed, Refactor refactor, const LatticeReference& near) {
  std::string why;
  SystemSolver r;
  if (lagged(kind) && refactor == Refactor::Once)
    throw std::invalid_argument("solver.poisson: pcg_fft and pcg_cholmod are for moving particles");
  if (lagged(kind) || (kind == SolverKind::Auto && refactor == Refactor::EveryStep && is_symmetric(A))) {
    NullSpaceHooks null;
    if (g.dimension() > 0) {
      const int n = static_cast<int>(A.rows());
      null.project = [g, n](double* v) {
        Vec f = Eigen::Map<Vec>(v, n);
        g.project(f);
        Eigen::Map<Vec>(v, n) = f;
      };
      null.definite = [g](const SpMat& M) { return g.pinned(M, false); };
      null.pin_rhs = [g](double* v) {
        for (int p : g.pins()) v[p] = 0.0;
      };
    }
    r.solver = lagged_solver(system, "solver.poisson", A, kind, near, std::move(null));
    r.unpinned = true;
    return r;
  }
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
