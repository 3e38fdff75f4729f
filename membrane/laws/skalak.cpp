// Skalak membrane in plane strain. The Skalak et al. (1973, Biophys. J. 13, 245) law for red-cell
// membranes, in the form of Barthes-Biesel, Diaz & Dhenin (2002): W = Es/4 (I1^2 + 2 I1 - 2 I2 + C I2^2)
// per unit reference area, I1 = l1^2 + l2^2 - 2, I2 = l1^2 l2^2 - 1, C the area-dilation parameter
// (area modulus K = Es (1 + 2C)). In plane strain (l2 = 1: the 2-D capsule is the section of a cylinder
// whose length does not change) I1 = I2 = lambda^2 - 1, so
//   W = Es/4 (1 + C) (lambda^2 - 1)^2,   T = dW/dlambda = Es (1 + C) lambda (lambda^2 - 1),
//   dT/dlambda = Es (1 + C) (3 lambda^2 - 1).
// Small strains: T ~ 2 Es (1 + C) (lambda - 1), the plane-strain modulus K + Es. Strain hardening
// (T ~ lambda^3), unlike the neo-Hookean law.
#include "membrane/law.hpp"

namespace sphib {

namespace {

class Skalak final : public TensionLaw {
 public:
  Skalak(double Es, double C) : k_(Es * (1.0 + C)) {}
  double energy(double l) const override { return 0.25 * k_ * (l * l - 1.0) * (l * l - 1.0); }
  double tension(double l) const override { return k_ * l * (l * l - 1.0); }
  double stiffness(double l) const override { return k_ * (3.0 * l * l - 1.0); }

 private:
  double k_;  // Es (1 + C)
};

}  // namespace

LawInfo skalak_law() {
  return {"skalak",
          "Skalak law in plane strain: T = Es (1 + C) lambda (lambda^2 - 1) (Es: shear modulus, C: area dilation, "
          "area modulus Es (1 + 2C))",
          {{"C", "Skalak's area-dilation parameter C (law = \"skalak\"): area modulus Es (1 + 2C)", 1.0, 0.0, 1e6}},
          [](double Es, const std::vector<double>& p) { return std::make_unique<Skalak>(Es, p.at(0)); }};
}

}  // namespace sphib
