// A locally inextensible membrane (vesicles), by a stiff penalty on the stretch: the Hookean form
// T = Es (lambda - 1)
// with Es large against the flow's and the bending's stresses, as in the penalty immersed-boundary
// vesicles of Kim & Lai (2010, J. Comput. Phys. 229, 4840). The local length error is |lambda - 1| ~
// T/Es, reported as the diagnostics column m<k>_strain_max (max_k |lambda_k - 1|). Chosen over a tension
// multiplier, whose solve needs the fluid's response at every marker: the penalty's stiffness is what
// the stiff-force filter (coupling/stiff_force.hpp) takes implicitly, so a stiff Es runs at the step
// the flow needs. A scene gives this law a tension cutoff of 2 dx by default (Material::tension_cutoff):
// the penalty's stretching modes shorter than the lattice carries are otherwise slowly unstable.
#include "membrane/law.hpp"

namespace sphib {

LawInfo inextensible_law() {
  return {"inextensible",
          "locally inextensible (vesicles): penalty tension T = Es (lambda - 1), Es the penalty modulus, large "
          "against the flow's stresses (stretch error ~ T/Es)",
          {},
          [](double Es, const std::vector<double>&) { return tension_law_info("hookean").make(Es, {}); }};
}

}  // namespace sphib
