#pragma once
// A closed membrane: its markers, its reference (stress-free) state and its material (law.hpp).
#include <string>

#include "membrane/law.hpp"

namespace sphib {

/// nb markers X_k labelled by s_k = k L0/nb, L0 the reference's label length (ref.L0).
struct Membrane {
  Mat2 X;
  Reference ref;
  Material mat;
  int nb() const { return static_cast<int>(X.rows()); }
  double L0() const { return ref.L0; }
  double ds() const { return ref.L0 / nb(); }
};

/// "hookean T0 = 10" / "skalak Es = 1, C = 1, Eb = 0.01": the law and its moduli, for run logs.
std::string describe(const Material& mat);

/// The membrane with markers X (uniform in rest arclength, e.g. from shapes.hpp) whose rest state is a
/// circle of radius r0 (circle_reference) and whose material is the paper's Hookean law with modulus
/// T0 (Eq. 47). Throws std::invalid_argument unless nb >= 4 and r0 is positive and finite.
Membrane make_membrane(Mat2 X, double r0, double T0);

/// The membrane with markers X, reference `ref` and material `mat`. Throws std::invalid_argument
/// (naming the value) for nb < 4, a reference of another size, an unknown law, a law parameter out of
/// its range, or a negative or non-finite modulus.
Membrane make_membrane(Mat2 X, Reference ref, Material mat);

}  // namespace sphib
