#pragma once
// How much memory a run of a scene will take, estimated from the scene alone before anything is
// allocated (no lattice, operator or factor is built), and how much the machine has: `sphib run`
// refuses a scene whose estimate exceeds limits.memory_gb (default: the machine's memory), and
// `sphib check` prints the estimate without building large scenes.
//
// The model: the process as it is now (libraries, an interpreter), plus a fixed overhead of the run
// (threads, HDF5, FFTW), plus N x n2 x c, with N the particles, n2 the lattice neighbours inside the
// kernel's support 2h and c the bytes per particle and neighbour that the method keeps at its peak
// (pairs, operator matrices, their images, factors, the set-up's temporaries). c was measured for each
// path (/usr/bin/time -v, peak resident memory of two-step runs at 64^2-256^2 and h_over_dx
// 0.9-2.0; see io/footprint.cpp); bench/memory_estimate.sh compares the estimate with the peak
// measured at 64^2 to 1024^2. Markers add a fixed amount each (measured at 32^2-128^2, Nb 1e5-1e6,
// h* 0.7-2.8 h: it depends on neither the lattice nor h*).
#include <string>

namespace sphib {

struct Scene;

struct MemoryEstimate {
  double bytes = 0;          // the run's peak resident memory: base + fluid
  double base = 0;           // this process now and the run's fixed overhead
  double fluid = 0;          // N x (per_particle + n2 x per_neighbour)
  double markers = 0;        // the membranes' markers: Nb x per_marker, summed over membranes
  long marker_count = 0;     // their Nb, summed
  long particles = 0;        // N
  long neighbours = 0;       // n2: lattice neighbours inside the support 2h (the sparsity of every operator)
  double per_neighbour = 0;  // c: bytes per particle and neighbour of the path
  double per_particle = 0;   // a: bytes per particle whatever n2 (0 but for EPSPH's compact storage)
  std::string path;          // which calibration: the method, its solvers and projection
};

// The estimate for a run of the scene in this process.
MemoryEstimate estimate_memory(const Scene& s);

struct MachineMemory {
  double bytes = 0;    // the smaller of the physical memory and the cgroup's limit
  std::string source;  // where it was read
};
MachineMemory machine_memory();

// The limit a run must fit (limits.memory_gb, or the machine's memory when that is 0), and why the
// scene cannot run under it ("" if it can): the estimate, the limit and the key that overrides it.
double memory_limit(const Scene& s, const MachineMemory& m);
std::string memory_problem(const Scene& s, const MemoryEstimate& e, const MachineMemory& m);

// Throws SceneError (naming limits.memory_gb) if the scene's estimate exceeds its limit: before any
// allocation of a run or a Simulation built from Python.
void refuse_if_too_large(const Scene& s);

// "1.23 GB": bytes in SI units, three significant digits.
std::string bytes_text(double bytes);

}  // namespace sphib
