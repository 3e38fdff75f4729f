#pragma once
// The blow-up guards: checked after every step, they stop a run within the step an instability
// appears in (before anything of that step is written), with a message naming the step and time.
#include <vector>

#include "coupling/simulation.hpp"

namespace sphib {

class Guards {
 public:
  // `params` says whether the flow is forced (body force, moving walls); an unforced flow with
  // membranes can only lose energy, which arms the energy bound.
  Guards(const SimulationParams& params, const Simulation& sim);

  // Throws std::runtime_error if the velocity or a membrane became non-finite, a particle moves by
  // more than a lattice spacing in one step, or an unforced flow's energy grew tenfold.
  void check(const Simulation& sim);

 private:
  double elastic_energy(const Simulation& sim);  // of the splines through the markers (a blow-up of the
                                                 // elastic force is marker-scale: the knots alone miss it)

  std::vector<MembraneForce> E_;  // workspace: the energy of markers the force's splines were not fitted to
  double h_min_;
  double v_min_;             // the smallest particle volume (fixed particles: once)
  double energy_bound_ = 0;  // 0: not armed
};

}  // namespace sphib
