// The paper's Hookean line tension, Eq. (47): T = Es (lambda - 1), W = Es/2 (lambda - 1)^2, with Es
// the paper's T0. Linear in the stretch: no strain hardening, a ring at rest length has no
// first-order resistance to shape changes that keep its length.
#include "membrane/law.hpp"

namespace sphib {

namespace {

class Hookean final : public TensionLaw {
 public:
  explicit Hookean(double Es) : Es_(Es) {}
  double energy(double l) const override { return 0.5 * Es_ * (l - 1.0) * (l - 1.0); }
  double tension(double l) const override { return Es_ * (l - 1.0); }  // Eq. (47)
  double stiffness(double) const override { return Es_; }

 private:
  double Es_;
};

}  // namespace

LawInfo hookean_law() {
  return {"hookean",
          "Hookean line tension T = Es (lambda - 1) (the paper's Eq. 47, Es = T0)",
          {},
          [](double Es, const std::vector<double>&) { return std::make_unique<Hookean>(Es); }};
}

}  // namespace sphib
