#pragma once
// Walls by image particles (Section 3.3) and the periodic wrap.
//
// Every particle within 2h of a wall gets a mirror image across it, created once (EPSPH).
// Corners: a particle within 2h of two adjacent walls also gets the double reflection
// (the point reflection through the corner), so its kernel support is complete there too.
//
// Image values are affine in the parent's value:  f_img = sign * f_parent + offset, the sign the
// image parity of the wall's kind (fluid/common/boundary_rule.hpp), the offset its prescribed part:
//  - velocity, one wall w:  u_img = parity u_p + (1 - parity) g_w; for a no-slip wall (parity -1)
//                           u_img = 2 g_w - u_p,  g_w = u_w + dt/rho (tau.grad phi~) tau  (Eq. 42)
//  - velocity, corner:      the product of the two sides' parities and the composition of the two
//                           reflections (corner_prescribed, boundary_rule.hpp): across the side A
//                           at the parent's place, then across B, u'' = p_B (p_A u_p + (1 - p_A) g_A)
//                           + (1 - p_B) g_B, per component; an inflow goes first (corner_reflections),
//                           so its profile is taken within the side: at an inflow's corner with a wall
//                           at rest u'' = u_p - 2 u_in(y_p). g includes each side's Eq. (42)
//                           correction of its tangential component (grad phi~ at the parent). Between
//                           sides of constant value the two orders agree except for two no-slip
//                           walls, where they give u_p + 2 (g_B - g_A) and the opposite (walls moving
//                           differently: the lid corner of a cavity, u singular there anyway; or the
//                           two walls' Eq. (42) corrections): there we take their mean, u_img = u_p.
//  - phi (and any scalar with homogeneous Neumann data): the Scalar parity, +1 at a no-slip wall
//    (phi_img = phi_p, Eq. 9); at a corner the product.
#include <string>
#include <vector>

#include "fluid/common/lattice.hpp"

namespace sphib {

struct Images {
  Mat2 x;                       // positions, M x 2
  std::vector<int> parent;      // parent particle of each image
  std::vector<int> wall;        // the wall of a single reflection (Side), or -1 for a corner image
  std::vector<double> v_sign;   // the velocity operators' parity: the stream function's (boundary_rule.hpp),
                                // both velocity components' where they share one: -1 for one no-slip
                                // reflection, +1 for a corner
  std::vector<double> s_sign;   // scalar (phi) parity: +1 at no-slip walls and their corners
  // Per velocity component (columns x, y), its parity minus v_sign: M x 2, nonzero only where the
  // components' parities differ (free-slip: the tangential component's even images, 2); empty when
  // they differ nowhere. The component's image value is then v_sign f_p + c + v_split f_p: the
  // operators with v_sign plus the correction v_split f_p taken with the image offsets.
  Mat2 v_split;

  int size() const { return static_cast<int>(parent.size()); }
  bool split() const { return v_split.size() != 0; }
};

// The correction of images of the velocity u (N x 2) where its components' parities differ from the
// operators' (Images::v_split): c(m, a) += v_split(m, a) u(parent m, a); nothing when !im.split().
void add_split_images(const Images& im, const Mat2& u, Mat2& c);

// The velocity operator on component a (0: x, 1: y) with that component's image parities:
// A + B diag(v_split(:, a)) P, P the images' parents (an image's value v_split f_p folded into its
// parent's column); A itself when !im.split().
SpMat component_matrix(const SpMat& A, const SpMat& B, const Images& im, int a);

// Images of every particle closer than `reach` (= 2h) to a wall.
Images make_images(const Lattice& lattice, double reach);

// The same for arbitrary particle positions x (N x 2) in the domain: the moving particles of LPSPH,
// whose images are made again every step.
Images make_images(const Domain& domain, const Mat2& x, double reach);

// Moving particles (WCSPH, ISPH) at x (N x 2): wrapped into [x0, x1) along periodic axes; a particle
// on or beyond a wall or an open side, or with a non-finite position, throws std::runtime_error
// naming the method, the particle, the side, where it is now and the time t, then `hint` (what to
// change) for a wall crossed.
void keep_in_tank(const Domain& d, Mat2& x, double t, const char* method, const char* hint);

// The velocity a side prescribes at x (on or beyond it): its wall velocity, an inflow's shaped by
// Domain::inflow_profile at x's place along the side.
Eigen::Vector2d side_velocity(const Domain& d, Side w, const Eigen::Vector2d& x);

// The stream function's prescribed value on side w at the place `along` (y on the left and right
// sides, x on the bottom and top; clamped to the side), with u = dpsi/dy, v = -dpsi/dx and psi = 0 at
// the corner (x0, y0): the flux through the sides from there,
//   left   psi(y) =  int_{y0}^{y} u(x0, y') dy'            bottom psi(x) = -int_{x0}^{x} v(x', y0) dx'
//   top    psi(x) =  psi(x0, y1) - int_{x0}^{x} v(x', y1) dx',    psi(x0, y1) =  F_left
//   right  psi(y) =  psi(x1, y0) + int_{y0}^{y} u(x1, y') dy',    psi(x1, y0) = -F_bottom
// (constant along an impermeable wall; the integral of the inflow's profile along an inflow:
// profile_integral, boundary_rule.hpp), F_w a side's whole flux (int u dy, int v dx), the one
// outflow's from the balance F_left + F_bottom - F_right - F_top = 0. Not used on an outflow
// (dpsi/dn = 0 there).
double side_stream_value(const Domain& d, Side w, double along);

// Why a stream function with these prescribed values cannot describe the domain's flow through
// its sides, naming the scene key; empty when it can (no inflow or outflow, or one outflow side and
// any inflows, no periodic axis).
std::string stream_function_refusal(const Domain& d);

// The images' parities of field f at the sides that make images, for the solvers' log lines: "odd
// images", "even images", or e.g. "odd images at the left, bottom and top sides, even at the right".
std::string image_parities_text(const Domain& d, Field f);

// A corner image's two reflections in the order they are composed (corner_prescribed,
// boundary_rule.hpp): across `first`, its value taken at `at_first` (the parent), then across
// `second`, its value taken at `at_second` (the parent's image across `first`). The side with a
// varying value goes first, so that its value is taken within the side: the y side if it is an
// inflow, else the x side. The other order gives the same where the second side's value continues
// beyond the corner as the first side's images make it (a wall's or an outflow's constant).
struct CornerReflections {
  Side first, second;
  Eigen::Vector2d at_first, at_second;
};
CornerReflections corner_reflections(const Domain& d, const Eigen::Vector2d& image);

// The prescribed parts of the stream function's images (M), psi_img = parity psi_p + offset, the
// parity the velocity's (Images::v_sign): (1 - parity) psi_side for a single reflection; at a corner
// the two reflections composed (corner_reflections, corner_prescribed).
void image_stream_offsets(const Images& im, const Domain& d, Vec& offset);

// The offset part of Eq. (42) for every image, M x 2: (1 - parity) u_w for a single reflection
// (an inflow's profile at the image) plus, where the tangential velocity is prescribed and grad_phi
// (N x 2, at the particles) is given, 2 dt/rho (tau.grad phi~_p) tau; at a corner the two
// reflections composed (see the header's velocity, corner).
void image_velocity_offsets(const Images& im, const Domain& d, const Mat2* grad_phi, double dt_over_rho,
                            Mat2& offset);

}  // namespace sphib
