// EPSPH's compact storage (eulerian.hpp): operators that keep only their stencils' rows give the
// products of the whole matrices bit for bit; G^T G by row blocks equals the whole products and
// their sum; the assembly straight into compressed rows equals the triplet assembly it replaced; and
// a compact fluid steps exactly as one holding the whole matrices. Inputs hold exact zeros of both
// signs among random values. (Checked that they fail: a class's reference row dropped from
// stencil_rows_only fails the first and the fourth.)
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "fluid/eulerian/eulerian.hpp"
#include "lattice_fields.hpp"
#include "fluid/algebra/operators.hpp"
#include "fluid/algebra/products.hpp"

using namespace sphib;
using namespace sphib::testing;

namespace {

// a channel, a closed box, a doubly periodic box, a kernel too wide for stencil rows
const Box kBoxes[] = {{48, 1.2, true, false}, {20, 1.2, false, false}, {24, 1.5, true, true}, {16, 3.0, false, false}};

bool same_matrix(const SpMat& A, const SpMat& B) {
  return same_pattern(A, B) && bitwise_equal(A.valuePtr(), B.valuePtr(), A.nonZeros());
}

}  // namespace

TEST(CompactStorage, StencilRowsOnlyGiveTheWholeMatricesProducts) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();  // the whole matrices
    const int N = f.size();
    const RowStencil st = find_row_stencil({&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A});
    const SpMat L = stencil_rows_only(op.lap_u.A, st), Gx = stencil_rows_only(op.grad_ux.A, st),
                Gy = stencil_rows_only(op.grad_uy.A, st);
    if (box.h_over_dx < 2)  // a lattice: a handful of classes and the corner rows (measured: 0.29 of
                            // the non-zeros on the 20^2 closed box, 0.14 on the 24^2 periodic one,
                            // falling like 1/n: the classes run along the walls)
      EXPECT_LT(L.nonZeros(), op.lap_u.A.nonZeros() / 3) << box.n;
    else  // no stencil: every row kept
      EXPECT_TRUE(same_matrix(L, op.lap_u.A)) << box.n;
    Random R(5);
    const Mat2 u = R.mat2(N);
    Mat2 a(N, 2), b(N, 2), c(N, 2), d(N, 2);
    apply2(op.lap_u.A, u, a, &st);
    apply2(L, u, b, &st);
    EXPECT_TRUE(bitwise_equal(a, b)) << box.n;
    gradient2(op.grad_ux.A, op.grad_uy.A, u, a, b, &st);
    gradient2(Gx, Gy, u, c, d, &st);
    EXPECT_TRUE(bitwise_equal(a, c) && bitwise_equal(b, d)) << box.n;
    Vec v(N), w(N);
    divergence(op.grad_ux.A, op.grad_uy.A, u, v, &st);
    divergence(Gx, Gy, u, w, &st);
    EXPECT_TRUE(bitwise_equal(v, w)) << box.n;
    // one column (the pressure, Eq. 35): as Eigen's product of the whole matrix
    const RowStencil ps = find_row_stencil({&op.lap_phi});
    const SpMat Lp = stencil_rows_only(op.lap_phi, ps);
    const Vec phi = u.col(0);
    Vec p1(N), p2(N);
    pressure_from_phi(op.lap_phi, phi, 0.3, p1);
    pressure_from_phi(Lp, phi, 0.3, p2, &ps);
    EXPECT_TRUE(bitwise_equal(p1, p2)) << box.n;
  }
}

TEST(CompactStorage, NormalEquationsByRowBlocksEqualTheWholeProducts) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const SpMat& Gx = op.grad_ux.A;
    const SpMat& Gy = op.grad_uy.A;
    const SpMat ty = Gy.transpose(), tx = -SpMat(Gx.transpose());  // as the exact projection keeps them
    const SpMat whole = ty * Gy + SpMat(Gx.transpose()) * Gx;
    for (int block : {0, 7, 1000000}) {
      const SpMat blocks = sum_of_products(ty, Gy, -1.0, tx, Gx, block);
      EXPECT_TRUE(same_matrix(blocks, whole)) << box.n << " block " << block;
    }
  }
}

// The assembly the operators had before (triplets, duplicates summed by setFromTriplets, exact
// zeros pruned where asked), written out: the compressed rows assemble_pairs makes equal it.
TEST(CompactStorage, AssemblyEqualsTheTripletAssembly) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const PairList& P = f.pairs();
    const Images& im = f.images();
    const int N = f.size(), M = im.size();
    std::vector<double> a(P.size());
    for (int k = 0; k < P.size(); ++k) a[k] = f.lattice().volume * P.rx[k] * f.kernel().F(P.r[k]);
    for (ImageRule rule : {ImageRule::Velocity, ImageRule::Scalar})
      for (bool difference : {true, false})
        for (bool keep_zeros : {true, false}) {
          std::vector<Triplet> t;
          for (int i = 0; i < N; ++i) {
            double diag = 0.0;
            for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
              const int j = P.j[k];
              const double s = difference ? -1.0 : 1.0;
              diag += a[k];
              if (j < N) t.emplace_back(i, j, s * a[k]);
              else t.emplace_back(i, im.parent[j - N], s * (rule == ImageRule::Velocity ? im.v_sign[j - N] : 1.0) * a[k]);
            }
            t.emplace_back(i, i, diag);
          }
          SpMat A(N, N);
          A.setFromTriplets(t.begin(), t.end());
          if (!keep_zeros) A.prune(0.0);
          const ImageOp op = assemble_pairs(P, N, im, rule, a.data(), difference, keep_zeros);
          EXPECT_TRUE(same_matrix(op.A, A)) << box.n;
          EXPECT_EQ(op.B.cols(), M);
        }
  }
}

// A compact fluid (the default with the exact projection and the lattice solvers) against one that
// holds the whole matrices (operators() asked for before the first step): the same bits after a
// few steps, velocity, phi and pressure.
TEST(CompactStorage, StepsAsTheWholeMatrices) {
  for (const Box& box : kBoxes) {
    EulerianFluid compact(box_params(box)), whole(box_params(box));
    whole.operators();
    EXPECT_TRUE(compact.compact_storage()) << box.n;
    EXPECT_FALSE(whole.compact_storage()) << box.n;
    const int N = compact.size();
    Random R(5);
    const Mat2 u0 = 0.1 * R.mat2(N), F = R.mat2(N);
    compact.set_velocity(u0);
    whole.set_velocity(u0);
    for (int s = 0; s < 3; ++s) {
      compact.step(F);
      whole.step(F);
    }
    EXPECT_TRUE(bitwise_equal(compact.u(), whole.u())) << box.n;
    EXPECT_TRUE(bitwise_equal(compact.phi(), whole.phi())) << box.n;
    EXPECT_TRUE(bitwise_equal(compact.p(), whole.p())) << box.n;
    EXPECT_EQ(compact.max_abs_divergence(), whole.max_abs_divergence()) << box.n;
  }
}

TEST(CompactStorage, OffWhereASolverKeyForcesAnotherSolverOrTheProjectionIsApproximate) {
  FluidParams p = box_params(kBoxes[1]);
  p.cn_solver = SolverKind::CholmodSimplicial;
  EXPECT_FALSE(EulerianFluid(p).compact_storage());
  p = box_params(kBoxes[1]);
  p.projection = Projection::Approximate;
  EXPECT_FALSE(EulerianFluid(p).compact_storage());
  p = box_params(kBoxes[1]);
  p.poisson_solver = SolverKind::Fft;
  EXPECT_TRUE(EulerianFluid(p).compact_storage());
}
