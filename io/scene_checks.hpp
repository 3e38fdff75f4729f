#pragma once
// Checks of a scene's values against each other and against the machine, made before anything is
// built: each returns "" when the scene passes, else why it cannot run (the caller names the key).
#include <string>
#include <vector>

#include "coupling/simulation.hpp"

namespace sphib {

struct Scene;

constexpr int kMaxMarkers = 1000000;  // membrane.nb: far beyond any lattice that fits in memory
constexpr long kMaxSteps = 1000000000;  // steps of one run (the HDF5 step attribute is an int32)

// A number as the scene's messages show it (six significant digits).
std::string number_text(double v);

// grid.nx x grid.ny: the particle count and the non-zeros of the widest operator (the exact
// projection's G^T G, radius 4h) must fit the 32-bit indices of the lattice and of Eigen's sparse
// matrices.
std::string lattice_too_large(const FluidParams& f);

// kernel.h_over_dx: the cubic spline's support 2h must reach the nearest particle along x and along
// y (2h > max(dx, dy)), else the SPH operators have no off-diagonal entries along one axis and every
// linear system is singular (measured: CHOLMOD stops at column 1 or 2 for h_over_dx <= 0.5 on a square
// lattice, for h_over_dx <= 0.666 with dy = 2 dx).
std::string kernel_too_narrow(const FluidParams& f);

// A run-time warning (sphib check and the run log), "" if none: h < 0.9 max(dx, dy) runs, but its
// errors are an order of magnitude or more above those at h = dx (docs/validation/kernel_width.md).
std::string kernel_warning(const FluidParams& f);

// walls.<side>: the image particles of a wall are fixed, so a wall moves only along itself; a
// velocity component normal to it (flow through a closed box) cannot be divergence-free.
std::string wall_moves_normally(const Domain& d, int side);

// observe.exact: the reference needs the flow it describes (Poiseuille: a channel driven by a body
// force along x; Couette: a channel with a moving wall; cavity: a closed box with a moving lid;
// membrane_equilibrium: a circular membrane; membrane_oscillation: a free membrane).
std::string exact_cannot_apply(const Scene& s);

// Two membranes whose polygons cross or share a segment (identical membranes), here or across a
// periodic side (one meets the other's periodic image), or a membrane as wide as a period along a
// periodic axis (it meets its own image): why, naming k and l (k < l; k = l for one membrane) and the
// segments that meet; "" if none do. Nested membranes that do not cross are allowed.
std::string membranes_cross(const std::vector<MembraneSetup>& membranes, const Domain& d, size_t* first = nullptr,
                            size_t* second = nullptr);

// fill.shape: a block or circle that holds every lattice site of a tank with no open side leaves
// no free surface, so ISPH's pressure Poisson problem has no Dirichlet row (singular: CHOLMOD "not
// positive definite", or particles thrown out at once). fill.shape = "domain" is the full tank.
std::string fill_leaves_no_surface(const FluidParams& f);

// The steps a run of the scene takes from t = 0: round(time.end / time.dt), capped by
// time.max_steps. steps_problem says why it cannot run ("" if it can): no step at all
// (time.end < time.dt / 2), or more than kMaxSteps.
long planned_steps(const Scene& s);
std::string steps_problem(const Scene& s);

}  // namespace sphib
