#include "fluid/algebra/solver_policy.hpp"

#include "fluid/algebra/products.hpp"

#include <sstream>
#include <stdexcept>
#include <utility>

#include "fluid/algebra/fft_poisson.hpp"

namespace sphib {

namespace {

// CHOLMOD (auto) or the solver asked for.
std::unique_ptr<LinearSolver> direct(const std::string& system, const SpMat& A, SolverKind kind, Refactor refactor) {
  if (kind != SolverKind::Auto || refactor == Refactor::Once || !is_symmetric(A)) return factorize(system, A, kind);
  return cholmod_by_factor_size(system, A, 1.5e5, "auto, refactorised every step");
}

bool lagged(SolverKind kind) { return kind == SolverKind::PcgFft || kind == SolverKind::PcgCholmod; }

// Moving particles: the FFT solver of the system on the initial lattice (the preconditioner of
// pcg_fft) where `kind` allows it and it applies, else nullptr with the reason in `why`; a refusal
// when pcg_fft was asked for.
std::unique_ptr<LinearSolver> lattice_preconditioner(const std::string& system, Field field, const std::string& key,
                                                     bool singular, SolverKind kind, const LatticeReference& near,
                                                     std::string& why) {
  std::unique_ptr<LinearSolver> start;
  why = "no lattice given";
  if (kind != SolverKind::PcgCholmod && near.lattice && near.A)
    start = make_fft_solver(system + " on the lattice", *near.A, *near.lattice, field, singular, &why);
  if (kind == SolverKind::PcgFft && !start) throw std::invalid_argument(key + " = \"pcg_fft\" does not apply: " + why);
  return start;
}

// Moving particles: CG preconditioned by `start` (pcg_fft) or, when it is null, by a lagged CHOLMOD
// factor (pcg_cholmod); `note` says why (auto).
std::unique_ptr<LinearSolver> lagged_solver(const std::string& system, const SpMat& A, std::unique_ptr<LinearSolver> start,
                                            NullSpaceHooks null, const std::string& note,
                                            const LaggedPcgOptions& opt = moving_cg_options()) {
  auto factorise = [](const std::string& s, const SpMat& D) { return direct(s, D, SolverKind::Auto, Refactor::EveryStep); };
  auto solver = lagged_pcg(system, A, std::move(start), factorise, std::move(null), opt);
  if (!note.empty()) solver->annotate(note, 0.0);
  return solver;
}

// The FFT lattice solver where `kind` allows it and A has the structure; a refusal when it was asked
// for and does not apply; nullptr otherwise, with the reason in `why`.
std::unique_ptr<LinearSolver> lattice_solver(const std::string& system, Field field, const std::string& key,
                                             const SpMat& A, bool singular, SolverKind kind, const Lattice* fixed,
                                             std::string& why) {
  if (kind != SolverKind::Auto && kind != SolverKind::Fft) return nullptr;
  if (!fixed) {
    why = "the particles move (the FFT solver needs the fixed lattice)";
  } else if (auto s = make_fft_solver(system, A, *fixed, field, singular, &why)) {
    if (kind == SolverKind::Auto) s->annotate(" (auto)", 0.0);
    return s;
  }
  if (kind == SolverKind::Fft) throw std::invalid_argument(key + " = \"fft\" does not apply: " + why);
  return nullptr;
}

}  // namespace

SystemSolver lattice_singular_solver(const std::string& system, Field field, const MatrixRows& A, long n, const Gauge& g,
                                     SolverKind kind, const Lattice& fixed) {
  SystemSolver r;
  if (kind != SolverKind::Auto && kind != SolverKind::Fft) return r;
  std::string why;
  r.solver = make_fft_solver(system, A, n, fixed, field, g.dimension() > 0, &why);  // as lattice_solver
  if (r.solver) {
    if (kind == SolverKind::Auto) r.solver->annotate(" (auto)", 0.0);
    r.unpinned = true;
  } else if (kind == SolverKind::Fft) {
    throw std::invalid_argument("solver.poisson = \"fft\" does not apply: " + why);
  }
  return r;
}

std::unique_ptr<LinearSolver> crank_nicolson_solver(const SpMat& A, const SpMat& lap, double a, SolverKind kind,
                                                    const Lattice* fixed, Refactor refactor,
                                                    const LatticeReference& near, Field field) {
  const std::string system = "Crank-Nicolson", key = "solver.crank_nicolson";
  std::string why;
  if (lagged(kind) && refactor == Refactor::Once)
    throw std::invalid_argument(key + ": pcg_fft and pcg_cholmod are for moving particles");
  if (auto s = lattice_solver(system, field, key, A, false, kind, fixed, why)) return s;
  const double b = 2.0 * a * lap.diagonal().cwiseAbs().maxCoeff();  // Gershgorin bound (see the header)
  std::ostringstream note;
  note << " (auto: " << (refactor == Refactor::EveryStep ? "moving particles; " : "") << "no FFT solver: ";
  const bool moving = kind == SolverKind::Auto && refactor == Refactor::EveryStep && is_symmetric(A);
  if (lagged(kind) || moving) {
    auto start = lattice_preconditioner(system, field, key, false, kind, near, why);
    note << why << "; Gershgorin bound nu dt max|lap_ii| = " << b << (b <= 40 ? " <= 40)" : " > 40)");
    if (lagged(kind) || start) {
      const std::string fft_note = kind == SolverKind::Auto ? " (auto: moving particles near a lattice with an FFT solver)" : "";
      return lagged_solver(system, A, std::move(start), {}, fft_note);
    }
    if (b > 40) return lagged_solver(system, A, nullptr, {}, note.str());
  } else {
    note << why << "; Gershgorin bound nu dt max|lap_ii| = " << b << (b <= 0.5 ? " <= 0.5)" : " > 0.5)");
  }
  auto s = direct(system, A, kind == SolverKind::Auto && (moving || b <= 0.5) ? SolverKind::Pcg : kind, refactor);
  if (kind == SolverKind::Auto) s->annotate(note.str(), 0.0);
  return s;
}

namespace {
RowsOf middle_rows(const SpMat& A) {
  return [&A](int r0, int m) { return SpMat(A.middleRows(r0, m)); };
}
}  // namespace

MatrixRows negated_rows(const SpMat& A) { return negated_rows(middle_rows(A), static_cast<int>(A.rows())); }

MatrixRows negated_rows(RowsOf rows, int n) {
  return [rows = std::move(rows), n](const std::function<void(const SpMat&, int)>& f) {
    const int b = product_block(n);
    for (int r0 = 0; r0 < n; r0 += b) {
      SpMat B = rows(r0, std::min(b, n - r0));
      negate(B);
      f(B, r0);
    }
  };
}

MatrixRows crank_nicolson_rows(const SpMat& lap, double a) {
  return crank_nicolson_rows(middle_rows(lap), static_cast<int>(lap.rows()), a);
}

MatrixRows crank_nicolson_rows(RowsOf lap, int n, double a) {
  return [lap = std::move(lap), n, a](const std::function<void(const SpMat&, int)>& f) {
    const int b = product_block(n);
    for (int r0 = 0; r0 < n; r0 += b) {
      const int m = std::min(b, n - r0);
      SpMat B = lap(r0, m);
      B *= -a;  // as ProjectionFluid::crank_nicolson_matrix (Eq. 28)
      for (int q = 0; q < m; ++q) B.coeffRef(q, r0 + q) += 1.0;
      B.makeCompressed();  // (should a diagonal have been missing)
      f(B, r0);
    }
  };
}

std::unique_ptr<LinearSolver> lattice_crank_nicolson_solver(const MatrixRows& A, long n, SolverKind kind,
                                                            const Lattice& fixed, Field field) {
  if (kind != SolverKind::Auto && kind != SolverKind::Fft) return nullptr;
  std::string why;
  auto s = make_fft_solver("Crank-Nicolson", A, n, fixed, field, false, &why);  // as crank_nicolson_solver
  if (s && kind == SolverKind::Auto) s->annotate(" (auto)", 0.0);
  if (!s && kind == SolverKind::Fft) throw std::invalid_argument("solver.crank_nicolson = \"fft\" does not apply: " + why);
  return s;
}

SystemSolver singular_solver(const std::string& system, Field field, const SpMat& A, const Gauge& g, SolverKind kind,
                             const Lattice* fixed, Refactor refactor, const LatticeReference& near,
                             const LaggedPcgOptions& cg) {
  std::string why;
  SystemSolver r;
  if (lagged(kind) && refactor == Refactor::Once)
    throw std::invalid_argument("solver.poisson: pcg_fft and pcg_cholmod are for moving particles");
  if (lagged(kind) || (kind == SolverKind::Auto && refactor == Refactor::EveryStep && is_symmetric(A))) {
    NullSpaceHooks null;
    if (g.dimension() > 0) {
      const int n = static_cast<int>(A.rows());
      null.project = [g, f = Vec(n)](double* v) mutable {  // f: the gauge's workspace (no allocation)
        f = Eigen::Map<Vec>(v, f.size());
        g.project(f);
        Eigen::Map<Vec>(v, f.size()) = f;
      };
      null.definite = [g](const SpMat& M) { return g.pinned(M, false); };
      null.pin_rhs = [g](double* v) {
        for (int p : g.pins()) v[p] = 0.0;
      };
    }
    auto start = lattice_preconditioner(system, field, "solver.poisson", null.singular(), kind, near, why);
    const std::string note = kind != SolverKind::Auto ? ""
                             : start ? " (auto: moving particles near a lattice with an FFT solver)"
                                     : " (auto: moving particles; no FFT lattice solver: " + why + ")";
    r.solver = lagged_solver(system, A, std::move(start), std::move(null), note, cg);
    r.unpinned = true;
    return r;
  }
  r.solver = lattice_solver(system, field, "solver.poisson", A, g.dimension() > 0, kind, fixed, why);
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
