#pragma once
// Shared by the tests that compare two ways of computing a step bit for bit (test_fused_passes,
// test_compact_storage): small lattice boxes of every boundary kind and random fields with signed
// zeros among them.
#include <cstring>
#include <random>

#include "fluid/common/params.hpp"
#include "fluid/common/types.hpp"

namespace sphib::testing {

struct Box {
  int n;
  double h_over_dx;
  bool px, py;
};

inline FluidParams box_params(const Box& b) {
  FluidParams p;
  p.domain.periodic_x = b.px;
  p.domain.periodic_y = b.py;
  p.nx = p.ny = b.n;
  p.h_over_dx = b.h_over_dx;
  p.mu = 0.1;
  p.dt = 1e-3;
  return p;
}

// Random values in [-1, 1], with every seventh exactly +0 or -0.
struct Random {
  explicit Random(unsigned seed) : gen(seed) {}
  std::mt19937 gen;
  std::uniform_real_distribution<double> U{-1.0, 1.0};
  double operator()() {
    const double v = U(gen);
    const unsigned k = gen() % 14;
    return k == 0 ? 0.0 : k == 1 ? -0.0 : v;
  }
  Mat2 mat2(int n) {
    Mat2 m(n, 2);
    for (int i = 0; i < n; ++i) {
      m(i, 0) = (*this)();
      m(i, 1) = (*this)();
    }
    return m;
  }
  Vec vec(int n) {
    Vec v(n);
    for (int i = 0; i < n; ++i) v[i] = (*this)();
    return v;
  }
};

// (n = 0: equal; memcmp may not be handed the null data of an empty array)
inline bool bitwise_equal(const double* a, const double* b, long n) { return n == 0 || std::memcmp(a, b, sizeof(double) * n) == 0; }
// Two dense matrices of the same shape holding the same bits.
template <class A, class B>
bool bitwise_equal(const Eigen::PlainObjectBase<A>& a, const Eigen::PlainObjectBase<B>& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && bitwise_equal(a.data(), b.data(), a.size());
}

}  // namespace sphib::testing
