#pragma once
// Free surfaces (Afanasiev, Makarchuk & Popov 2011 ["A"], Sections 3.5 and 3.7), shared by every
// moving-particle method that has one (WCSPH now; ISPH next: see supports_free_surface):
//  - the fluid's initial particle set: a region of the tank (a block, a circle or the whole tank),
//    the lattice sites of Eq. (68) inside it or, for a circle, concentric rings;
//  - the hydrostatic depth and fluid height that set A Eqs. (27)-(28);
//  - surface detection: A Eq. (26) (Lee et al. 2008) or Dilts' algorithm (Dilts 2000).
// Free-surface particles get p = 0 (A Section 3.5): WCSPH sets their pressure, ISPH embeds the
// Dirichlet condition in its Poisson matrix.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fluid/common/lattice.hpp"
#include "fluid/common/pair_search.hpp"
#include "fluid/common/params.hpp"

namespace sphib {

// The methods that support a free surface (open sides, a partly filled tank, gravity): wcsph, isph.
bool supports_free_surface(FluidMethod method);

// A partly filled tank or an open side: the fluid has a free surface.
bool has_free_surface(const Domain& d, const FreeSurfaceParams& fs);


// What is wrong with a free-surface set-up for `method`, if anything: a free surface (a partly filled
// tank or an open side) or gravity for a method without free surfaces, gravity along a periodic
// axis or towards an open side (nothing holds the fluid), beta or the Dilts radius out of range, a
// fluid region outside the tank. Methods add their own (FluidSolver's free_surface_problem).
std::optional<ParamProblem> free_surface_problem(FluidMethod method, const Domain& d, const FreeSurfaceParams& fs,
                                                 const Eigen::Vector2d& gravity);

// Auto resolved: see SurfaceDetection (params.hpp).
SurfaceDetection detection_for(FluidMethod method, const Domain& d, const FreeSurfaceParams& fs);

// The initial particles: positions and the volume of each (lattice: dx dy; rings: pi dx^2 / 3, the
// area of a ring's cell). Throws std::invalid_argument (naming fill.*) for a region outside the
// tank or one without particles.
struct ParticleSet {
  Mat2 x;
  double volume = 0;
};
ParticleSet fill_particles(const Lattice& L, const FluidRegion& r);

// Depth of each particle below the region's top along gravity g ((x - x_top) . g/|g|), and the
// fluid's height along g (A Eq. 27's H): for hydrostatic pressure rho0 |g| depth (A Eq. 28).
Vec hydrostatic_depth(const Mat2& x, const FluidRegion& r, const Domain& d, const Eigen::Vector2d& g);
double fluid_height(const FluidRegion& r, const Domain& d, const Eigen::Vector2d& g);

// Flags free-surface particles from the pairs of the last neighbour search (fluid/common/pair_search.hpp;
// fixed points, the wall particles, complete the support near walls).
//  - Divergence, A Eq. (26) (Lee et al. 2008): div r_i = -sum_j V_j (x_i - x_j) . grad_i W_ij < 2 beta.
//    The sum is 2 (the dimension) for a complete support and about 1 at a flat surface. A writes the
//    sum without the minus sign, which makes it -2 in the bulk; the divergence of position is meant.
//  - Dilts (2000): particle i is on the surface when some arc of its circle of radius R is covered
//    by no neighbour's circle of radius R; neighbour j at distance d < 2R covers the arc within
//    acos(d / 2R) of its direction. Exact, without trigonometry (free_surface.cpp).
class SurfaceDetector {
 public:
  SurfaceDetector(SurfaceDetection method, double beta, double radius);

  // N particles with volumes V (m/rho), fixed points of volume V_fixed; flags[i] = 1 on the surface.
  void detect(int N, const ParticlePairs& P, const Vec& V, double V_fixed, std::vector<char>& flags);
  // A Eq. (26) from the sums div r_i already at hand (ISPH's assembly: particle_operators.hpp).
  void flag_divergence(const Vec& div_r, std::vector<char>& flags) const;
  SurfaceDetection method() const { return method_; }
  const Vec& position_divergence() const { return div_r_; }  // A Eq. (26)'s sum, last detection (Divergence)

 private:
  void divergence(int N, const ParticlePairs& P, const Vec& V, double V_fixed, std::vector<char>& flags);
  void dilts(int N, const ParticlePairs& P, std::vector<char>& flags);
  bool circle_covered(int begin, int end);  // the arcs [begin, end) of one particle cover the circle

  SurfaceDetection method_;
  double beta_, R_;
  Vec div_r_;
  std::vector<std::uint64_t> sectors_;      // per particle: the sectors inside some arc (quick test)
  std::vector<int> first_, fill_;           // per particle: its arcs in [first_[i], first_[i + 1])
  std::vector<double> lo_, hi_;             // arc ends, pseudo-angles (hi may pass 4)
  std::vector<std::pair<double, double>> arcs_;  // workspace: one particle's arcs as [lo, hi]
};

}  // namespace sphib
