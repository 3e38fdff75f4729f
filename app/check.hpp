#pragma once
// `sphib check`: builds everything a scene needs (lattice, images, operators, factorisations,
// membranes) without running a step, and prints what it will cost and whether dt is safe.
#include <iosfwd>

#include "io/scene.hpp"

namespace sphib::app {

// Prints the report to out; returns the number of warnings (time-step estimates exceeded).
// Throws what Simulation's constructor throws for a scene that cannot run.
int check_scene(const Scene& scene, std::ostream& out);

}  // namespace sphib::app
