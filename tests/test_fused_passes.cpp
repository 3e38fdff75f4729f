// The fused passes of EPSPH's step (fluid/eulerian/fused_passes.hpp) against the separate products and
// loops they replace (the step's code before the fusion, written out here): equal bit for bit, on
// a channel, a closed box, a doubly periodic box and a lattice whose kernel is too wide for stencil
// rows, with and without the lattice stencils (the rows from the compressed arrays). The inputs
// hold exact zeros of both signs among random values. (Checked that they fail: the Laplacian's two
// wall terms added in the other order, or the modes' parity table transposed, each fail.)
#include <gtest/gtest.h>

#include <random>

#include "fluid/eulerian/eulerian.hpp"
#include "lattice_fields.hpp"
#include "fluid/eulerian/fused_passes.hpp"

using namespace sphib;
using namespace sphib::testing;

namespace {

const Box kBoxes[] = {{64, 1.2, true, false}, {20, 1.2, false, false}, {24, 1.5, true, true}, {16, 3.0, false, false}};


}  // namespace

// Eqs. (28), (39)-(41): the predictor's right-hand side with and without convection, first step
// (Euler) and later (AB2).
TEST(FusedPasses, PredictorRhsEqualsTheSeparateProducts) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const int N = f.size(), M = f.images().size();
    const RowStencil st = find_row_stencil({&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A});
    const ImageRows images(&st, N, {&op.lap_u.B, &op.grad_ux.B, &op.grad_uy.B});
    Random R(11);
    const Mat2 u = R.mat2(N), F = R.mat2(N), c_star = R.mat2(M), c_wall = R.mat2(M), conv_prev = R.mat2(N);
    const std::vector<int> lb = nonempty_rows(op.lap_u.B), xb = nonempty_rows(op.grad_ux.B),
                           yb = nonempty_rows(op.grad_uy.B);
    Mat2 lw = Mat2::Zero(N, 2), cwx = Mat2::Zero(N, 2), cwy = Mat2::Zero(N, 2), bc = Mat2::Zero(N, 2);
    add_image_terms(op.lap_u.B, lb, c_wall, lw);
    add_image_terms(op.grad_ux.B, xb, c_wall, cwx);
    add_image_terms(op.grad_uy.B, yb, c_wall, cwy);
    set_image_terms(op.lap_u.B, lb, c_star, bc);
    const double a = 0.05, k = 1e-3, kc = 1e-3;
    for (int variant = 0; variant < 3; ++variant) {  // convection (first step, later), Stokes
      const bool conv_on = variant < 2, first = variant == 0;
      // the separate products and loops
      Mat2 du_dx(N, 2), du_dy(N, 2), conv = Mat2::Zero(N, 2), old = conv_prev, rhs(N, 2);
      if (conv_on) {
        gradient2(op.grad_ux.A, op.grad_uy.A, u, du_dx, du_dy);
        for (int c = 0; c < 2; ++c)
          for (int i = 0; i < N; ++i) {
            const double n = (du_dx(i, c) + cwx(i, c)) * u(i, 0) + (du_dy(i, c) + cwy(i, c)) * u(i, 1);
            conv(i, c) = 1.5 * n - 0.5 * (first ? n : old(i, c));
            old(i, c) = n;
          }
      }
      apply2(op.lap_u.A, u, rhs);
      add_image_terms(op.lap_u.B, lb, c_star, rhs);
      for (int c = 0; c < 2; ++c)
        for (int i = 0; i < N; ++i) rhs(i, c) = (rhs(i, c) + lw(i, c)) * a + u(i, c) + k * F(i, c) - kc * conv(i, c);
      for (const RowStencil* s : {&st, static_cast<const RowStencil*>(nullptr)}) {
        Mat2 fused_old = conv_prev, fused_rhs = Mat2::Constant(N, 2, 7.0);
        const Mat2 zero = Mat2::Zero(N, 2);
        predictor_rhs({&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A, s, &images,
                       {0, u.data(), F.data(), bc.data(), lw.data(), cwx.data(), cwy.data(), a, k, kc, first,
                        conv_on ? fused_old.data() : nullptr, zero.data(), fused_rhs.data()}});
        EXPECT_TRUE(bitwise_equal(fused_rhs, rhs)) << box.n << " variant " << variant << (s ? " stencil" : " rows");
        EXPECT_TRUE(bitwise_equal(fused_old, old)) << box.n << " variant " << variant << (s ? " stencil" : " rows");
      }
    }
  }
}

// The exact projection's right-hand sides: C^T u*, the normal equations' b_psi, the markers' b_m.
TEST(FusedPasses, CurlTransposeRhsEqualsTheSeparateProducts) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const int N = f.size();
    const SpMat ty = op.grad_uy.A.transpose(), tx = -SpMat(op.grad_ux.A.transpose());
    const RowStencil st = find_row_stencil({&ty, &tx});
    Random R(11);
    const Mat2 u = R.mat2(N);
    const Vec flux = R.vec(N), mflux = R.vec(N);
    const double scale = 1.0093;
    for (double Q : {0.0, -0.37}) {
      Vec cu(N), b_psi(N), b_m(N);
      divergence(ty, tx, u, cu);
      if (Q != 0.0) b_psi = cu - Q * flux;
      else b_psi = cu;
      b_m = (cu + Q * mflux) * scale;
      for (const RowStencil* s : {&st, static_cast<const RowStencil*>(nullptr)}) {
        Vec fcu(N), fb(N), fm(N);
        curl_transpose_rhs({&ty, &tx, s, u.data(), {Q, scale, flux.data(), mflux.data(), fcu.data(), fb.data(), fm.data()}});
        EXPECT_TRUE(bitwise_equal(fcu, cu) && bitwise_equal(fb, b_psi) && bitwise_equal(fm, b_m))
            << box.n << " Q " << Q << (s ? " stencil" : " rows");
      }
    }
  }
}

// The exact projection's velocity: the curl of psi with the flux's wall terms, u*'s alternating
// modes, and G phi = r (u* - u^{n+1}).
TEST(FusedPasses, CurlVelocityEqualsTheSeparateProducts) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const Lattice& L = f.lattice();
    const int N = f.size(), M = f.images().size();
    const RowStencil st = find_row_stencil({&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A});
    const ImageRows images(&st, N, {&op.grad_ux.B, &op.grad_uy.B});
    Random R(11);
    const Vec psi = R.vec(N), c1 = R.vec(M);
    const Vec by1 = op.grad_uy.B * c1, bx1 = op.grad_ux.B * c1;  // zero off the rows with image terms
    const Mat2 u_star = R.mat2(N);
    const VelocityModes modes(L);
    std::vector<unsigned char> par(N);
    for (int i = 0; i < N; ++i) par[i] = static_cast<unsigned char>(2 * ((i / L.nx) & 1) + ((i % L.nx) & 1));
    const double r = 1.0 / 1.3e-3;
    for (double Q : {0.0, 0.21, -0.21}) {
      Mat2 g(N, 2), u(N, 2);
      gradient(op.grad_ux.A, op.grad_uy.A, psi, g);
      for (int i = 0; i < N; ++i) {
        u(i, 0) = g(i, 1) + Q * by1[i];
        u(i, 1) = -(g(i, 0) + Q * bx1[i]);
      }
      modes.add_components(u_star, u);
      const Mat2 grad_phi = r * (u_star - u);
      for (const RowStencil* s : {&st, static_cast<const RowStencil*>(nullptr)}) {
        Mat2 fu(N, 2), fg(N, 2);
        curl_velocity({&op.grad_ux.A, &op.grad_uy.A, s, &images, psi.data(),
                       {0, L.nx, Q, r, by1.data(), bx1.data(), u_star.data(), par.data(), modes.addends(u_star),
                        fu.data(), fg.data()}});
        EXPECT_TRUE(bitwise_equal(fu, u) && bitwise_equal(fg, grad_phi)) << box.n << " Q " << Q << (s ? " stencil" : " rows");
      }
    }
  }
}
