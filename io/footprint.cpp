#include "io/footprint.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "io/scene.hpp"

namespace sphib {

namespace {

// Bytes per particle and lattice neighbour at a run's peak, measured (/usr/bin/time -v, two-step
// runs of cases/membrane_oscillation.toml, poiseuille.toml, cavity_re100.toml, wcsph_couette.toml and
// membrane_oscillation_lagrangian.toml at 64^2-512^2, h_over_dx = 0.9, 1.2, 1.5, 2.0; peak minus the
// 31.4 MB of a 16^2 run, over N n2):
//   EPSPH, FFT solvers (a channel): exact projection (the compact storage, fluid/eulerian/eulerian.hpp:
//     no operator and no pair list is ever whole, so its peak is about the stepping state: the
//     fields, the lattice solvers and the compact operators, which hardly grow with n2)
//     700 per particle + 4 per particle and neighbour (peaks of 1.17, 1.29, 1.30 and 1.36 kB per
//     particle at n2 = 8, 20, 28, 44 at 256^2, 0.93 and 0.99 kB at n2 = 20, 44 at 512^2, 0.84 and
//     0.74 kB at n2 = 20 at 1024^2 and 2048^2, the process included); approximate 165-189;
//   EPSPH, CHOLMOD (a box, doubly periodic, or solvers chosen): the factors grow like log2 N:
//     exact 34-51 x log2 N, approximate 11-25 x log2 N (44 and 22 keep 64^2-256^2 within 18%);
//   LPSPH (rebuilt every step): 19-26 x log2 N;  WCSPH (no linear system): 8-50 (not monotone in N);
//   ISPH (cases/dam_break.toml at 200 x 800 to 800 x 3200, 5000-80000 fluid particles;
//     still_tank_isph.toml at 160^2): 14-19 x log2 N, N the fluid particles (not the lattice's sites).
// The constants are chosen for the main path's error across 64^2-1024^2 (docs/performance/memory.md).
constexpr double kFftExact = 4, kFftExactPerParticle = 700, kFftApproximate = 185;
constexpr double kCholmodExactPerLog = 44, kCholmodApproximatePerLog = 22;
constexpr double kLagrangianPerLog = 24, kWcsph = 40;
constexpr double kIsphPerLog = 19;
// Bytes per membrane marker at a run's peak (positions, forces, tension, the spline, the spreading's
// and the interpolation's weights, the marker update's iterates): 541-553 kB per 1000 markers,
// measured from the peaks of two-step runs of membrane_oscillation.toml at Nb = 1e5, 3e5 and 1e6 on
// 32^2, 64^2 and 128^2 lattices and h* = 0.7, 1.4, 2.8 h (docs/data_safety.md, "Memory").
constexpr double kPerMarker = 570;
// The run's fixed overhead over the process before it (OpenMP threads, HDF5, FFTW, CHOLMOD):
// a 16^2 run peaks at 32.2 MB, the command holds 15.7 MB when it estimates (/proc/self/statm).
constexpr double kOverhead = 16.5e6;

// The process's resident memory now (/proc/self/statm), 0 if unknown.
double resident_bytes() {
  std::ifstream in("/proc/self/statm");
  double size = 0, resident = 0;
  if (!(in >> size >> resident)) return 0;
  return resident * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

// Lattice offsets (i dx, j dy) != 0 strictly inside the support 2h (W = 0 at q = 2): every
// particle's neighbours away from walls.
long lattice_neighbours(const FluidParams& f) {
  const double dx = f.domain.Lx() / f.nx, dy = f.domain.Ly() / f.ny, h = f.h_over_dx * 0.5 * (dx + dy), R = 2 * h;
  const double ix = std::ceil(R / dx), jy = std::ceil(R / dy);
  if (ix * jy > 1e6) return static_cast<long>(M_PI * R * R / (dx * dy));  // a huge kernel: its area
  long n = 0;
  for (long i = -static_cast<long>(ix); i <= ix; ++i)
    for (long j = -static_cast<long>(jy); j <= jy; ++j)
      if ((i || j) && (i * dx) * (i * dx) + (j * dy) * (j * dy) < R * R) ++n;
  return n;
}

// The particles a run starts with: the lattice, or for a fluid region (free-surface methods) the
// lattice sites inside it, counted by its area (a block or circle of the lattice's sites; rings hold
// as many to within one ring).
long particle_count(const FluidParams& f) {
  const double lattice = static_cast<double>(f.nx) * f.ny;
  const FluidRegion& r = f.free_surface.fill;
  if (r.shape == FluidRegion::Shape::Domain) return static_cast<long>(lattice);
  const Domain& d = f.domain;
  double area = 0;
  if (r.shape == FluidRegion::Shape::Block)
    area = std::max(0.0, std::min(r.x1, d.x1) - std::max(r.x0, d.x0)) * std::max(0.0, std::min(r.y1, d.y1) - std::max(r.y0, d.y0));
  else
    area = M_PI * r.radius * r.radius;
  return static_cast<long>(std::ceil(std::min(1.0, area / (d.Lx() * d.Ly())) * lattice));
}

// EPSPH's systems go to the lattice solvers of fluid/algebra/fft_poisson.hpp on every domain kind (channel,
// closed box, doubly periodic) unless a solver key asks for another.
bool fft_solvers(const FluidParams& f) {
  auto fft_or_auto = [](SolverKind k) { return k == SolverKind::Auto || k == SolverKind::Fft; };
  return fft_or_auto(f.cn_solver) && fft_or_auto(f.poisson_solver);
}

}  // namespace

std::string bytes_text(double b) {
  const char* unit[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int k = 0;
  while (b >= 1000 && k < 6) b /= 1000, ++k;
  std::ostringstream s;
  s.precision(3);
  s << b << " " << unit[k];
  return s.str();
}

MemoryEstimate estimate_memory(const Scene& s) {
  const FluidParams& f = s.sim.fluid;
  MemoryEstimate e;
  e.particles = particle_count(f);
  e.neighbours = lattice_neighbours(f);
  const double log2N = std::log2(std::max(2.0, static_cast<double>(e.particles)));
  const bool approximate = f.projection == Projection::Approximate ||
                           (f.projection == Projection::Auto && f.method == FluidMethod::Lagrangian);
  if (f.method == FluidMethod::Wcsph) {
    e.path = "WCSPH";
    e.per_neighbour = kWcsph;
  } else if (f.method == FluidMethod::Isph) {
    e.path = "ISPH";
    e.per_neighbour = kIsphPerLog * log2N;
  } else if (f.method == FluidMethod::Lagrangian) {
    e.path = "LPSPH";
    e.per_neighbour = kLagrangianPerLog * log2N;
  } else if (fft_solvers(f)) {
    e.path = std::string("EPSPH, FFT solvers, ") + (approximate ? "approximate" : "exact") + " projection";
    e.per_neighbour = approximate ? kFftApproximate : kFftExact;
    e.per_particle = approximate ? 0.0 : kFftExactPerParticle;
  } else {
    e.path = std::string("EPSPH, sparse Cholesky factors, ") + (approximate ? "approximate" : "exact") + " projection";
    e.per_neighbour = (approximate ? kCholmodApproximatePerLog : kCholmodExactPerLog) * log2N;
  }
  e.base = resident_bytes() + kOverhead;
  e.fluid = static_cast<double>(e.particles) * (e.per_particle + static_cast<double>(e.neighbours) * e.per_neighbour);
  for (const MembraneScene& m : s.membranes) e.marker_count += m.nb;
  e.markers = kPerMarker * static_cast<double>(e.marker_count);
  e.bytes = e.base + e.fluid + e.markers;
  return e;
}

MachineMemory machine_memory() {
  MachineMemory m;
  std::ifstream info("/proc/meminfo");
  std::string key;
  double kb = 0;
  while (info >> key >> kb) {
    if (key == "MemTotal:") {
      m.bytes = kb * 1024.0;
      m.source = "MemTotal in /proc/meminfo";
      break;
    }
    info.ignore(256, '\n');
  }
  for (const char* cg : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(cg);
    double limit = 0;
    if (in >> limit && limit > 0 && (m.bytes == 0 || limit < m.bytes)) {
      m.bytes = limit;
      m.source = std::string("the cgroup's limit, ") + cg;
    }
  }
  return m;
}

double memory_limit(const Scene& s, const MachineMemory& m) { return s.memory_limit_gb > 0 ? s.memory_limit_gb * 1e9 : m.bytes; }

std::string memory_problem(const Scene& s, const MemoryEstimate& e, const MachineMemory& m) {
  const double limit = memory_limit(s, m);
  if (!(limit > 0) || e.bytes <= limit) return "";
  std::ostringstream w;
  w << "the run would need about " << bytes_text(e.bytes) << " (" << e.particles << " particles x ";
  if (e.per_particle > 0) w << "(" << bytes_text(e.per_particle) << " + ";
  w << e.neighbours << " neighbours x " << bytes_text(e.per_neighbour) << (e.per_particle > 0 ? ")" : "") << ", " << e.path;
  if (e.marker_count > 0) w << ", + " << e.marker_count << " markers x " << bytes_text(kPerMarker);
  w << ", + " << bytes_text(e.base) << "), more than ";
  if (s.memory_limit_gb > 0) w << "limits.memory_gb = " << s.memory_limit_gb;
  else w << "this machine's " << bytes_text(m.bytes) << " (" << m.source << ")";
  w << "; set limits.memory_gb to run it anyway (see `sphib check`)";
  return w.str();
}

void refuse_if_too_large(const Scene& s) {
  if (const std::string why = memory_problem(s, estimate_memory(s), machine_memory()); !why.empty())
    throw SceneError(s.path + ": limits.memory_gb: " + why);
}

}  // namespace sphib
