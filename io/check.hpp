#pragma once
// `sphib check`: builds everything a scene needs (lattice, images, operators, factorisations,
// membranes) without running a step, and prints what it will cost and whether dt is safe. A scene
// whose estimated peak memory is above 1 GB is not built (unless asked): the report then comes from
// the scene, its lattice and its membranes alone.
#include <iosfwd>

#include "io/scene.hpp"

namespace sphib {

// Prints the report to out; returns the number of warnings (a narrow kernel, sparse markers,
// time-step estimates exceeded, more memory than the run may take). Throws what Simulation's
// constructor throws for a scene that cannot run (when it builds it).
int check_scene(const Scene& scene, std::ostream& out, bool build = false);

// The warnings alone, for a simulation already built (sphib run prints them before running and
// refuses the scene with --strict): a kernel narrower than 0.9 lattice spacings, markers farther
// apart than a lattice spacing, dt above the convective CFL estimate (the velocity scale from the
// walls, the initial flow, a body force, gravity or a membrane's elastic energy), dt above the
// explicit elastic estimate, WCSPH's acoustic limit, ISPH's explicit viscous limit. Returns their number.
int time_step_warnings(const Scene& scene, const Simulation& sim, std::ostream& out);

}  // namespace sphib
