#pragma once
// The operators of Eqs. (27)-(34) (operators.hpp) assembled again every step for moving particles
// (LPSPH, ISPH), straight into compressed rows: one pattern from the pair list for every operator
// (A: particle i, its neighbours and the parents of its image neighbours; B: i and its image
// neighbours; explicit zeros kept, so that the fused products of products.hpp apply and a pattern
// that does not change keeps the factorisations' symbolic analysis), then each operator's values by
// scattering the pair terms into it. The values equal build_operators' for the same pairs.
#include <vector>

#include "fluid/operators.hpp"

namespace sphib {

class ParticleOperators {
 public:
  // op at the particles of P (N of them, uniform volume V) and the images im.
  void assemble(const PairList& P, const Images& im, int N, const CubicSplineKernel& W, double V, Operators& op);

 private:
  void make_pattern(const PairList& P, const Images& im, int N);
  void scatter(const PairList& P, const Images& im, int N, ImageRule rule, const std::vector<double>& a,
               bool difference, SpMat& A, SpMat* B) const;
  std::vector<int> outer_, inner_, slot_, diag_, outer_b_, inner_b_;  // the pattern
  std::vector<double> lap_, gx_, gy_;                                 // pair coefficients
};

}  // namespace sphib
