// Neo-Hookean membrane in plane strain. The 3-D law of a thin incompressible neo-Hookean sheet
// (Barthes-Biesel & Rallison 1981; Barthes-Biesel, Diaz & Dhenin 2002, J. Fluid Mech. 460, 211) has
// the energy per unit reference area W = Es/2 (l1^2 + l2^2 + 1/(l1 l2)^2 - 3) and the principal
// tension T1 = (1/l2) dW/dl1. A 2-D capsule is the cross-section of a long cylinder whose length does
// not change, l2 = 1 (the plane-strain reduction used for 2-D capsules, e.g. Breyiannis & Pozrikidis
// 2000, Theor. Comput. Fluid Dyn. 13, 327), so with lambda = l1:
//   W = Es/2 (lambda^2 + lambda^-2 - 2),   T = Es (lambda - lambda^-3),   dT/dlambda = Es (1 + 3 lambda^-4).
// Small strains: T ~ 4 Es (lambda - 1), the plane-strain modulus K + Es with area modulus K = 3 Es.
// Strain softening at large stretch (T ~ Es lambda).
#include <cmath>

#include "membrane/law.hpp"

namespace sphib {

namespace {

class NeoHookean final : public TensionLaw {
 public:
  explicit NeoHookean(double Es) : Es_(Es) {}
  double energy(double l) const override { return 0.5 * Es_ * (l * l + 1.0 / (l * l) - 2.0); }
  double tension(double l) const override { return Es_ * (l - 1.0 / (l * l * l)); }
  double stiffness(double l) const override { return Es_ * (1.0 + 3.0 / (l * l * l * l)); }

 private:
  double Es_;
};

}  // namespace

LawInfo neo_hookean_law() {
  return {"neo_hookean",
          "neo-Hookean sheet in plane strain: T = Es (lambda - lambda^-3) (Es: shear modulus; small-strain "
          "modulus 4 Es)",
          {},
          [](double Es, const std::vector<double>&) { return std::make_unique<NeoHookean>(Es); }};
}

}  // namespace sphib
