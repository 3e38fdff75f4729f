// EPSPH's compact storage (eulerian.hpp): operators that keep only their stencils' rows give the
// products of the whole matrices bit for bit; G^T G by row blocks equals the whole products and
// their sum; the assembly straight into compressed rows equals the triplet assembly it replaced; and
// a compact fluid steps exactly as one holding the whole matrices. Inputs hold exact zeros of both
// signs among random values. (Checked that they fail: a class's reference row dropped from
// stencil_rows_only fails the first and the fourth.)
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <cmath>
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

// SumOfProductRows (the setup's G^T G by blocks, its scratch kept from block to block) gives
// rows_of_sum_of_products's bits: on the lattices' normal equations by blocks of 7 rows, and on random
// sparse matrices holding exact zeros of both signs (so that a product alone is -0 somewhere, which
// Eigen's sum turns into +0: dropping the kernel's "+ 0.0" fails this), with s2 = -1 and +1.
TEST(CompactStorage, SumOfProductRowsGiveEigensBits) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const SpMat& Gx = op.grad_ux.A;
    const SpMat& Gy = op.grad_uy.A;
    const SpMat ty = Gy.transpose(), tx = -SpMat(Gx.transpose());
    const int N = f.size();
    SumOfProductRows product(N);
    bool same = true;
    for (int r0 = 0; r0 < N; r0 += 7) {
      const int m = std::min(7, N - r0);
      same &= same_matrix(product(SpMat(ty.middleRows(r0, m)), Gy, -1.0, SpMat(tx.middleRows(r0, m)), Gx),
                          rows_of_sum_of_products(ty, Gy, -1.0, tx, Gx, r0, m));
    }
    EXPECT_TRUE(same) << box.n;
  }
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const auto random = [&](int rows, int cols, double fill) {
    std::vector<Triplet> t;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        if (U(gen) < 2 * fill - 1) {
          const double r = U(gen);
          t.emplace_back(i, j, r < -0.6 ? -0.0 : r < -0.2 ? 0.0 : U(gen));
        }
    SpMat A(rows, cols);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  SumOfProductRows product(40);
  int negative_zeros = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const SpMat A1 = random(9, 30, 0.2), B1 = random(30, 40, 0.15), A2 = random(9, 30, 0.2), B2 = random(30, 40, 0.15);
    const double s2 = trial % 2 ? 1.0 : -1.0;
    const SpMat P = SpMat(A1 * B1);
    for (Eigen::Index k = 0; k < P.nonZeros(); ++k) negative_zeros += P.valuePtr()[k] == 0.0 && std::signbit(P.valuePtr()[k]);
    EXPECT_TRUE(same_matrix(product(A1, B1, s2, A2, B2), rows_of_sum_of_products(A1, B1, s2, A2, B2, 0, 9))) << trial;
  }
  EXPECT_GT(negative_zeros, 0);  // (the case the comment names occurs)
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
              else t.emplace_back(i, im.parent[j - N], s * (rule == ImageRule::Velocity ? im.v_sign[j - N] : im.s_sign[j - N]) * a[k]);
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

// The pairs a block of rows at a time (LatticePairs, which the compact storage assembles from) are
// the whole list's, and the operators' rows assembled from them (operator_rows) the whole
// operators' rows bit for bit, blocks of 7 rows (not dividing a lattice row) as of the whole lattice.
TEST(CompactStorage, AssemblyByBlocksOfPairsEqualsTheWholePairList) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Images& im = f.images();
    const PairList P = find_pairs(f.lattice(), im.x, f.kernel().support());
    const LatticePairs lp(f.lattice(), im.x, f.kernel().support());
    const int N = f.size();
    EXPECT_EQ(lp.count(), P.size()) << box.n;
    PairList B;
    bool same = true;
    for (int r0 = 0; r0 < N; r0 += 7) {
      const int r1 = std::min(N, r0 + 7);
      lp.rows(r0, r1, B);
      const int k0 = P.offset[r0];
      same &= static_cast<int>(B.offset.size()) == r1 - r0 + 1 && B.size() == P.offset[r1] - k0;
      for (int q = 0; same && q <= r1 - r0; ++q) same &= B.offset[q] == P.offset[r0 + q] - k0;
      for (int k = 0; same && k < B.size(); ++k)
        same &= B.j[k] == P.j[k0 + k] && bitwise_equal(&B.rx[k], &P.rx[k0 + k], 1) &&
                bitwise_equal(&B.ry[k], &P.ry[k0 + k], 1) && bitwise_equal(&B.r[k], &P.r[k0 + k], 1);
    }
    EXPECT_TRUE(same) << box.n;
    const Operators whole = build_operators(P, f.lattice(), im, f.kernel());
    for (int rows : {7, N}) {
      bool rows_same = true;
      for (int r0 = 0; r0 < N; r0 += rows) {
        const int r1 = std::min(N, r0 + rows), m = r1 - r0;
        lp.rows(r0, r1, B);
        const Operators b = operator_rows(B, r0, f.lattice(), im, f.kernel(), OperatorSet::All);
        for (auto [a, c] : {std::pair{&whole.lap_u.A, &b.lap_u.A}, {&whole.lap_u.B, &b.lap_u.B},
                            {&whole.grad_ux.A, &b.grad_ux.A}, {&whole.grad_ux.B, &b.grad_ux.B},
                            {&whole.grad_uy.A, &b.grad_uy.A}, {&whole.grad_uy.B, &b.grad_uy.B},
                            {&whole.lap_phi, &b.lap_phi}, {&whole.grad_phix, &b.grad_phix},
                            {&whole.grad_phiy, &b.grad_phiy}})
          rows_same &= same_matrix(SpMat(a->middleRows(r0, m)), *c);
      }
      EXPECT_TRUE(rows_same) << box.n << " " << rows;
    }
  }
}

bool same_stencil(const RowStencil& a, const RowStencil& b) {
  if (a.classes.size() != b.classes.size() || a.blocks.size() != b.blocks.size() || a.rest != b.rest) return false;
  for (size_t k = 0; k < a.classes.size(); ++k)
    if (a.classes[k].ref != b.classes[k].ref || a.classes[k].offset != b.classes[k].offset) return false;
  for (size_t k = 0; k < a.blocks.size(); ++k)
    if (a.blocks[k].cls != b.blocks[k].cls || a.blocks[k].begin != b.blocks[k].begin ||
        a.blocks[k].count != b.blocks[k].count || a.blocks[k].stride != b.blocks[k].stride)
      return false;
  return true;
}

// The transposes of the velocity gradients by blocks of rows (transposed_rows) are the whole
// transposes' rows, and their stencil and kept rows found from the blocks (three passes) those of
// the whole matrices: blocks of 7 rows and of the whole lattice.
TEST(CompactStorage, TransposesAndTheirStencilByBlocksEqualTheWholeOnes) {
  for (const Box& box : kBoxes) {
    const EulerianFluid f(box_params(box));
    const Operators& op = f.operators();
    const int N = f.size();
    SpMat ty = op.grad_uy.A.transpose(), tx = op.grad_ux.A.transpose();
    negate(tx);
    const RowStencil whole = find_row_stencil({&ty, &tx});
    const std::vector<int> cy = column_counts(op.grad_uy.A), cx = column_counts(op.grad_ux.A);
    for (int block : {7, N}) {
      bool same = true;
      const OperatorRows rows = [&](const std::function<void(const std::vector<const SpMat*>&, int)>& g) {
        for (int r0 = 0; r0 < N; r0 += block) {
          const int m = std::min(block, N - r0);
          const SpMat by = transposed_rows(op.grad_uy.A, cy, r0, m);
          SpMat bx = transposed_rows(op.grad_ux.A, cx, r0, m);
          negate(bx);
          same &= same_matrix(by, SpMat(ty.middleRows(r0, m))) && same_matrix(bx, SpMat(tx.middleRows(r0, m)));
          g({&by, &bx}, r0);
        }
      };
      std::vector<SpMat> kept;
      const RowStencil st = find_row_stencil(rows, N, kept);
      EXPECT_TRUE(same) << box.n << " " << block;
      EXPECT_TRUE(same_stencil(st, whole)) << box.n << " " << block;
      ASSERT_EQ(kept.size(), 2u);
      EXPECT_TRUE(same_matrix(kept[0], stencil_rows_only(ty, whole))) << box.n << " " << block;
      EXPECT_TRUE(same_matrix(kept[1], stencil_rows_only(tx, whole))) << box.n << " " << block;
    }
    // D = -G^T of the phi gradients kept compact, by blocks (the compact setup's), as from the whole
    const RowStencil ps = find_row_stencil({&op.grad_phix, &op.grad_phiy});
    const ExactProjection::Divergence a = ExactProjection::divergence_by_blocks(
        stencil_rows_only(op.grad_phix, ps), stencil_rows_only(op.grad_phiy, ps), ps);
    const ExactProjection::Divergence b = ExactProjection::make_divergence(op.grad_phix, op.grad_phiy, true);
    EXPECT_TRUE(same_matrix(a.x, b.x) && same_matrix(a.y, b.y) && same_stencil(a.st, b.st)) << box.n;
    // a pattern that is not symmetric is refused
    SpMat upper = op.grad_ux.A.triangularView<Eigen::StrictlyUpper>();  // row 0 reaches columns whose rows never reach 0
    EXPECT_THROW(transposed_rows(upper, column_counts(upper), 0, N), std::logic_error) << box.n;
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
