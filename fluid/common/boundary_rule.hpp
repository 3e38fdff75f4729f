#pragma once
// The boundary rule: ONE place that says what each kind of side implies for every field.
//
// A side of the rectangle (fluid/common/lattice.hpp, Domain) is periodic, a wall, or open (free
// space: free-surface methods only). Walls act through image particles (fluid/common/boundary.hpp):
// the mirror image of a particle across the wall carries
//     f_img = parity f_parent + prescribed,    prescribed = (1 - parity) g,
// with g the value the wall prescribes for the field f (Section 3.3). Odd images (parity -1) make
// f = g on the wall (Dirichlet: the no-slip velocity, Eq. 42, prescribed part 2 U_wall); even
// images (parity +1) make df/dn = 0 there (Neumann: phi and the pressure, Eq. 9; no prescribed part).
// A stream function is constant along an impermeable wall (psi = psi_w: odd images). Through an
// inflow it takes the integral of the prescribed normal velocity along the side (psi = psi_in, odd
// images), across an outflow dpsi/dn = 0 (even images: the curl's normal velocity has zero normal
// gradient, as the velocity's even images there); the stream function's images take the velocity's
// parity at every side (the exact projection makes them with the velocity's operators).
// A free-slip wall is impermeable and shear-free: the normal velocity vanishes (odd images), the
// tangential one has zero normal gradient (even images), the stream function is constant (odd).
// The velocity operators' images carry the stream function's parity (make_images: the normal
// component's at every kind); a velocity component whose parity differs there (the tangential one at
// a free-slip wall) takes the difference as a per-component correction (Images::v_split).
//
// Everything that makes or folds images takes its parities from here: the image construction
// (boundary.cpp), the operators' assembly (fluid/algebra/operators.cpp), the exact projection's
// stream function, the gauge's null vectors (fluid/algebra/gauge.cpp) and the fast solvers'
// transforms (fluid/algebra/fft_poisson.cpp: even images -> DCT-II, odd -> DST-II, periodic -> DFT).
//
// A new kind of side: its enumerator below, its row in image_parity (boundary_rule.cpp), its scene
// key and its refusal by the methods that cannot do it (io/scene.cpp).

namespace sphib {

enum class SideKind {
  Periodic,  // the opposite side continues the domain (no images)
  NoSlip,    // a wall with a prescribed velocity (at rest, a moving lid, a Couette wall)
  Open,      // free space beyond it (no images; free-surface methods only)
  Inflow,    // a prescribed velocity profile enters (velocity Dirichlet, phi Neumann)
  Outflow,   // the flow leaves (velocity zero-gradient, phi = 0)
  FreeSlip,  // an impermeable wall without shear (normal velocity 0, tangential du_t/dn = 0; EPSPH only)
};

// The shape of an inflow's velocity along its side: the side's velocity (Domain::wall_velocity)
// times 1 (uniform) or 4 s (1 - s) (parabolic, s in [0, 1] along the side: zero at its ends, the
// side's velocity at its middle).
enum class InflowProfile { None, Uniform, Parabolic };

// The integral of an inflow's shape from the side's start to s in [0, 1]: int_0^s shape(t) dt, s
// (uniform) or 2 s^2 - 4 s^3 / 3 (parabolic, shape 4 t (1 - t)): the stream function along an inflow
// is psi(s) = L u_n profile_integral(s), L the side's length, u_n the side velocity's normal component.
double profile_integral(InflowProfile p, double s);

// The fields an image carries, by their role at the wall: the velocity component normal to the
// wall, the tangential one, a scalar with homogeneous Neumann data (phi, the pressure), a stream
// function (constant on an impermeable wall).
enum class Field { VelocityNormal, VelocityTangential, Scalar, Stream };

// The image parity the kind implies for the field: +1 (even), -1 (odd), 0 where the kind makes no
// images (periodic, open).
int image_parity(SideKind k, Field f);

// Whether the kind is a solid wall (image particles, or the moving methods' virtual wall particles;
// wall loads).
inline bool is_wall_kind(SideKind k) { return k == SideKind::NoSlip; }
// Whether the kind makes image particles (walls, inflow, outflow).
inline bool makes_images(SideKind k) {
  return k == SideKind::NoSlip || k == SideKind::Inflow || k == SideKind::Outflow || k == SideKind::FreeSlip;
}
// Whether the flow crosses a side of this kind (inflow, outflow).
inline bool is_through_kind(SideKind k) { return k == SideKind::Inflow || k == SideKind::Outflow; }

// The velocity's parity across a side of this kind when both components share one (no-slip and
// inflow -1, outflow +1); 0 when they differ (free-slip) or the kind makes no images.
inline int velocity_parity(SideKind k) {
  const int n = image_parity(k, Field::VelocityNormal), t = image_parity(k, Field::VelocityTangential);
  return n == t ? n : 0;
}

// The prescribed part of an image, (1 - parity) g: the value g the wall prescribes (its velocity's
// component, a stream function's wall value) counts twice on odd images, not at all on even ones.
inline double image_prescribed(int parity, double g) { return (1.0 - parity) * g; }

// The prescribed part of a corner image made by two reflections in turn: across side A (parity pA,
// value gA at the parent's place on A), then across side B (parity pB, value gB at the place of the
// parent's image across A on B):
//   f'' = pB (pA f + (1 - pA) gA) + (1 - pB) gB = pA pB f + [pB (1 - pA) gA + (1 - pB) gB],
// the bracket returned. Pass g = 0 for an even side (it prescribes no value).
inline double corner_prescribed(int pA, double gA, int pB, double gB) {
  return pB * image_prescribed(pA, gA) + image_prescribed(pB, gB);
}

// "periodic", "no_slip", "open", "inflow", "outflow", "free_slip".
const char* side_kind_name(SideKind k);

}  // namespace sphib
