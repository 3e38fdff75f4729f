// A locally inextensible membrane (vesicles), by a stiff penalty on the stretch: T = Es (lambda - 1)
// with Es large against the flow's and the bending's stresses, as in the penalty immersed-boundary
// vesicles of Kim & Lai (2010, J. Comput. Phys. 229, 4840). The local length error is |lambda - 1| ~
// T/Es, reported as the diagnostics column m<k>_strain_max (max_k |lambda_k - 1|). Chosen over a tension
// multiplier, whose solve needs the fluid's response at every marker: the penalty's stiffness is what
// the stiff-force filter (coupling/stiff_force.hpp) takes implicitly, so a stiff Es runs at the step
// the flow needs.
#include "membrane/law.hpp"

namespace sphib {

namespace {

class Inextensible final : public TensionLaw {
 public:
  explicit Inextensible(double Es) : Es_(Es) {}
  double energy(double l) const override { return 0.5 * Es_ * (l - 1.0) * (l - 1.0); }
  double tension(double l) const override { return Es_ * (l - 1.0); }
  double stiffness(double) const override { return Es_; }

 private:
  double Es_;
};

}  // namespace

LawInfo inextensible_law() {
  return {"inextensible",
          "locally inextensible (vesicles): penalty tension T = Es (lambda - 1), Es the penalty modulus, large "
          "against the flow's stresses (stretch error ~ T/Es)",
          {},
          [](double Es, const std::vector<double>&) { return std::make_unique<Inextensible>(Es); }};
}

}  // namespace sphib
