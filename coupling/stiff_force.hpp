#pragma once
// The stiff-force filter: the membrane force the fluid receives, taken semi-implicitly so that stiff
// membranes (bending, large moduli, inextensible penalties) run at the time step the flow needs.
//
// The force f^n = f(X^n) is explicit (Eq. 50 at t_n, spread by Eq. 53), so a membrane mode of
// wavenumber k and stiffness K(k) (Eb k^4 for bending, E_t k^2 for stretching) is stable only while
// dt K(k) B(k) stays below ~2, B(k) the velocity the fluid gives that mode per unit force in one step
// (the h^3 limit of bending). This filter spreads instead a prediction of f^{n+1}, backward-Euler
// style, linearised about X^n:
//   f~ = f^n - dt K U^{n+1},   U^{n+1} ~ A U^n + B f~ + G,
//   i.e.   f~ = (I + dt K B)^{-1} (f^n - dt K (A U^n + G)),
// where U^n is the markers' velocity, A U^n + B f~ the fluid's one-step response to the membrane's
// own force, per Fourier mode m along the membrane, and G what that model misses: the velocity the
// rest of the flow gives the mode (a shear holding a capsule deformed) and the model's error. G is
// measured, the residual of the last step's prediction, G^n = U^n - A U^{n-1} - B f~^{n-1},
// smoothed over steps (weight 0.2, lowered on stiff modes and capped: stiff_force.cpp, "the
// residual's gain") and kept on the well-resolved modes only, when asked
// (membrane.stiff_residual = true; otherwise G = 0, the backward-Euler prediction alone). Without G (G = 0) the
// filter's steady state is wrong: a mode held still by the flow (U = 0) receives f^n / (1 + dt K B)
// instead of f^n, so a stiff capsule in shear deformed 4 times too much at the flow's step; with G
// a steady state (U^{n+1} = U^n, K U = 0) receives f^n, as the explicit force gives it. It is not
// the default: its largest stable step is below the default's on some scenes (0.65 to 1.3 times it
// on the stability map, docs/membranes.md), and it reaches a steady force slowly on stiff modes in
// a very viscous flow.
// This is the small-scale decomposition of Hou, Lowengrub & Shelley (1994, J. Comput. Phys. 114,
// 312): the stiff terms, linearised, are implicit in the membrane's own Fourier modes, where they are
// diagonal. The markers still move with the fluid (the divergence-free interpolation keeps the
// enclosed area); only the force differs. The filter keeps U^{n-1}, f~^{n-1} and G between steps
// (its state(), in the checkpoint).
//
// Per mode m (wavenumber k = m/R, R = L/(2 pi), L the current length), on the inward normal and
// tangential displacements (a, b) of a circle of radius R, the stiffness of stretch
// eps = (b_theta - a)/R, curvature change dkappa = (a_thetatheta + a)/R^2 and tension T > 0 is
//   K = [ E_t/R^2 + Eb (m^2 - 1)^2/R^4 + T (m^2 - 1)/R^2    -i m E_t/R^2 ]
//       [ i m E_t/R^2                                        m^2 E_t/R^2  ]
// (translations, m = 1 with b = i a, and rotations, m = 0 with a = 0, are its null modes), E_t the
// largest dT/dlambda. The fluid's response is that of a flat sheet: the Stokes mobility 1/(4 mu k)
// (a line force density at wavenumber k moves the line at f/(4 mu k) in 2-D Stokes flow) capped by
// the inertial one-step response, dt k/(2 rho) for normal modes (added mass 2 rho/k) and
// dt/(2 rho delta) for tangential ones (the viscous layer delta = min(1/k, sqrt(pi nu dt))), and the
// velocity a mode keeps over a step, A = 1/(1 + 2 nu k^2 dt). Without G, overestimating K or B only
// damps more: a model of one mode (a Stokes-Darcy oscillator) is stable for any K >= K_true,
// B >= B_true and A in [0, 1.5]; with G it is stable with exact estimates but less tolerant of loose
// ones (scripts/stiff_force_model.py, docs/membranes.md), hence G on the well-resolved modes only,
// smoothed. B includes an upper bound of the spreading and interpolation
// kernels' attenuation of mode k. Modes far from stiff (dt K B << 0.1) lean back to the explicit f^n
// (theta = min(1, dt K B/0.1) in place of dt K B: stable in the same model), so a membrane that is
// not stiff runs as the paper's scheme does.
#include <fftw3.h>

#include <complex>
#include <vector>

#include "membrane/force.hpp"

namespace sphib {

struct StiffFluid {
  double rho = 1.0, mu = 1.0, dt = 1e-3;
  double h_star = 0.0, h = 0.0;  // the spreading's and the interpolation's smoothing lengths
};

class StiffForceFilter {
 public:
  /// residual: predict U^{n+1} with the model's residual G (membrane.stiff_residual); without it G = 0.
  explicit StiffForceFilter(int nb, bool residual = false);
  ~StiffForceFilter();
  StiffForceFilter(const StiffForceFilter&) = delete;
  StiffForceFilter& operator=(const StiffForceFilter&) = delete;

  /// f_tilde from the force f (per unit label, of the markers `force` last computed), the markers'
  /// velocity U^n and the membrane's stiffness. Allocation-free after construction.
  void apply(const MembraneForce& force, const Mat2& f, const Mat2& U, const StiffFluid& fluid, Mat2& f_tilde,
             bool record = true);

  /// The history `apply` keeps (U^{n-1}, f~^{n-1} and G by mode: nb/2 + 1 rows, 12 columns of real
  /// and imaginary parts), empty before the first step and without the residual; set_state restores it (a restart), throwing
  /// std::invalid_argument when its shape does not fit.
  Eigen::MatrixXd state() const;
  void set_state(const Eigen::MatrixXd& s);

 private:
  int nb_, nm_;               // markers, modes (nb/2 + 1)
  bool residual_;
  std::vector<std::complex<double>> hist_;  // U^{n-1}, f~^{n-1}, G (normal and tangential modes each)
  bool have_prev_ = false;
  double* in_ = nullptr;      // 4 nb reals: f_n, f_t, U_n, U_t
  fftw_complex* hat_ = nullptr;  // 4 nm modes
  fftw_plan fwd_ = nullptr, inv_ = nullptr;  // 4 forward; 2 inverse (f~_n, f~_t)
};

}  // namespace sphib
