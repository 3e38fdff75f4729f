#pragma once
// Cubic B-spline smoothing kernel in two dimensions, Eq. (19), support 2h.
// Contract: a Kernel gives W(r), dW/dr and (1/r) dW/dr for one smoothing length h.
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sphib {

// Two doubles operated on lane by lane (GCC and Clang vector extensions: SSE2 on x86-64), for the
// markers' kernel loops; LaneMask2 holds a comparison's result (all bits set where true).
using Lanes2 = double __attribute__((vector_size(16)));
using LaneMask2 = long long __attribute__((vector_size(16)));
// Four lanes for the AVX2 clones of the markers' loops (two SSE2 halves in the default ones).
using Lanes4 = double __attribute__((vector_size(32)));
using LaneMask4 = long long __attribute__((vector_size(32)));

inline Lanes2 lanes2(double a) { return Lanes2{a, a}; }
inline Lanes2 sqrt2(Lanes2 x) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(x);
#else
  return Lanes2{std::sqrt(x[0]), std::sqrt(x[1])};
#endif
}
// m ? a : b, lane by lane
inline Lanes2 select2(LaneMask2 m, Lanes2 a, Lanes2 b) {
  return reinterpret_cast<Lanes2>((m & reinterpret_cast<LaneMask2>(a)) | (~m & reinterpret_cast<LaneMask2>(b)));
}
// (The four-lane helpers are inline: passed in registers only inside the AVX2 clones.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class L> struct LaneMaskOf { using type = LaneMask2; };
template <> struct LaneMaskOf<Lanes4> { using type = LaneMask4; };
inline Lanes4 lanes(Lanes4, double a) { return Lanes4{a, a, a, a}; }
inline Lanes2 lanes(Lanes2, double a) { return lanes2(a); }
inline Lanes2 lane_sqrt(Lanes2 x) { return sqrt2(x); }
inline Lanes4 lane_sqrt(Lanes4 x) {  // the square root of each lane, as sqrt2 takes it
  const Lanes2 lo = sqrt2(Lanes2{x[0], x[1]}), hi = sqrt2(Lanes2{x[2], x[3]});
  return Lanes4{lo[0], lo[1], hi[0], hi[1]};
}
inline Lanes2 select(LaneMask2 m, Lanes2 a, Lanes2 b) { return select2(m, a, b); }
inline Lanes4 select(LaneMask4 m, Lanes4 a, Lanes4 b) {
  return reinterpret_cast<Lanes4>((m & reinterpret_cast<LaneMask4>(a)) | (~m & reinterpret_cast<LaneMask4>(b)));
}
#pragma GCC diagnostic pop

struct CubicSplineKernel {
  double h;
  double w0;  // 15 / (7 pi h^2): 2-D normalisation of Eq. (19)

  explicit CubicSplineKernel(double h_) : h(h_), w0(15.0 / (7.0 * M_PI * h_ * h_)) {}

  double support() const { return 2.0 * h; }

  // W(r, h), Eq. (19)
  double W(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
    if (q < 2.0) { const double t = 2.0 - q; return w0 * t * t * t / 6.0; }
    return 0.0;
  }

  // dW/dr
  double dWdr(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 / h * (-2.0 * q + 1.5 * q * q);
    if (q < 2.0) { const double t = 2.0 - q; return -w0 / h * 0.5 * t * t; }
    return 0.0;
  }

  // (1/r) dW/dr, finite as r -> 0 (limit -2 w0 / h^2); the factor every SPH operator of Eqs. (27)-(35) uses.
  double F(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 / (h * h) * (-2.0 + 1.5 * q);
    if (q < 2.0) { const double t = 2.0 - q; return -w0 / (h * h) * 0.5 * t * t / q; }
    return 0.0;
  }

  // The markers' loops (coupling/neighbourhood.hpp) take two points at a time, lane by lane, from
  // squared distances r2: both pieces of Eq. (19) are computed and one selected, without a branch
  // (a query's points fall on either side of q = 1 in no predictable order), with q = r (1/h) and
  // the constant factors folded, so that W takes one square root and no division, F and G one
  // division between them. Equal to W() and F() to a few units in the last place of W(0) and F(0)
  // (tests/test_fluid.cpp, Kernel.TwoLaneFormsMatchTheScalarOnes); 0 from 2h (1 + 1e-12) on.
  // The four-lane forms (L = Lanes4) compute each lane by the same expressions, so the same values.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
  template <class L>
  L W2(L r2) const { return Pieces<L>(*this, r2).W(); }
  template <class L>
  void W_F2(L r2, L& w, L& f) const {
    const Pieces<L> p(*this, r2);
    w = p.W();
    f = p.F();
  }
  // ... and G = (1/r) dF/dr: the Hessian of W(|x|) is F I + G x x^T (0 at r = 0, where G x x^T -> 0).
  template <class L>
  void W_F_G2(L r2, L& w, L& f, L& g) const {
    const Pieces<L> p(*this, r2);
    w = p.W();
    f = p.F();
    g = p.G();
  }

 private:
  template <class L>
  struct Pieces {
    static L c(double a) { return lanes(L{}, a); }
    Pieces(const CubicSplineKernel& K, L r2)
        : k(K), q(lane_sqrt(r2) * c(1.0 / K.h)), t(c(2.0) - q), inner(q < c(1.0)), inside(q < c(2.0)) {}
    L W() const {
      const L w_in = c(k.w0) * (c(2.0 / 3.0) - q * q + c(0.5) * q * q * q);  // q < 1
      const L w_out = c(k.w0 / 6.0) * t * t * t;                              // 1 <= q < 2
      return select(inside, select(inner, w_in, w_out), c(0.0));
    }
    L F() const {  // (1/r) dW/dr
      const double cf = k.w0 / (k.h * k.h);
      const L f_in = c(cf) * (c(-2.0) + c(1.5) * q), f_out = c(-0.5 * cf) * t * t * qinv();
      return select(inside, select(inner, f_in, f_out), c(0.0));
    }
    L G() const {  // (1/r) dF/dr: 1.5 c / (h^2 q) for q < 1, 0.5 c t (q + 2) / (h^2 q^3) for 1 <= q < 2
      const double cg = k.w0 / (k.h * k.h * k.h * k.h);
      const L qi = qinv(), g_in = c(1.5 * cg) * qi, g_out = c(0.5 * cg) * t * (q + c(2.0)) * qi * qi * qi;
      return select(inside & (q > c(0.0)), select(inner, g_in, g_out), c(0.0));
    }
    L qinv() const { return c(1.0) / q; }  // (inf at q = 0, in lanes not selected)
    const CubicSplineKernel& k;
    L q, t;
    typename LaneMaskOf<L>::type inner, inside;
  };
#pragma GCC diagnostic pop
};

}  // namespace sphib
