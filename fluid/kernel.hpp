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
  Lanes2 W2(Lanes2 r2) const { return Pieces(*this, r2).W(); }
  void W_F2(Lanes2 r2, Lanes2& w, Lanes2& f) const {
    const Pieces p(*this, r2);
    w = p.W();
    f = p.F();
  }
  // ... and G = (1/r) dF/dr: the Hessian of W(|x|) is F I + G x x^T (0 at r = 0, where G x x^T -> 0).
  void W_F_G2(Lanes2 r2, Lanes2& w, Lanes2& f, Lanes2& g) const {
    const Pieces p(*this, r2);
    w = p.W();
    f = p.F();
    g = p.G();
  }

 private:
  struct Pieces {
    Pieces(const CubicSplineKernel& K, Lanes2 r2)
        : k(K), q(sqrt2(r2) * lanes2(1.0 / K.h)), t(lanes2(2.0) - q), inner(q < lanes2(1.0)), inside(q < lanes2(2.0)) {}
    Lanes2 W() const {
      const Lanes2 w_in = lanes2(k.w0) * (lanes2(2.0 / 3.0) - q * q + lanes2(0.5) * q * q * q);  // q < 1
      const Lanes2 w_out = lanes2(k.w0 / 6.0) * t * t * t;                                        // 1 <= q < 2
      return select2(inside, select2(inner, w_in, w_out), lanes2(0.0));
    }
    Lanes2 F() const {  // (1/r) dW/dr
      const double c = k.w0 / (k.h * k.h);
      const Lanes2 f_in = lanes2(c) * (lanes2(-2.0) + lanes2(1.5) * q), f_out = lanes2(-0.5 * c) * t * t * qinv();
      return select2(inside, select2(inner, f_in, f_out), lanes2(0.0));
    }
    Lanes2 G() const {  // (1/r) dF/dr: 1.5 c / (h^2 q) for q < 1, 0.5 c t (q + 2) / (h^2 q^3) for 1 <= q < 2
      const double c = k.w0 / (k.h * k.h * k.h * k.h);
      const Lanes2 qi = qinv(), g_in = lanes2(1.5 * c) * qi, g_out = lanes2(0.5 * c) * t * (q + lanes2(2.0)) * qi * qi * qi;
      return select2(inside & (q > lanes2(0.0)), select2(inner, g_in, g_out), lanes2(0.0));
    }
    Lanes2 qinv() const { return lanes2(1.0) / q; }  // (inf at q = 0, in lanes not selected)
    const CubicSplineKernel& k;
    Lanes2 q, t;
    LaneMask2 inner, inside;
  };
};

}  // namespace sphib
