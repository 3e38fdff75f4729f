#pragma once
// The cubic B-spline kernel of Eq. (19) in lane form, for the fast kernels' loops over two or four
// points at a time; the scalar form it is tested against is kernels/cubic_spline.hpp.
#include "kernels/cubic_spline.hpp"
#include "kernels/lanes.hpp"

namespace sphib {

// The lane form, from squared distances r2: both pieces of Eq. (19) are computed and one selected,
// without a branch (a marker's points fall on either side of q = 1 in no predictable order), with
// q = r (1/h) and the constant factors folded, so that W takes one square root and no division, F
// and G one division between them. Within a few units in the last place of W(0) and F(0) of the
// scalar forms (tests/test_kernels.cpp); 0 from 2h on. Every lane by the same expressions, so two
// and four lanes give the same values. Holds a reference to the scale: construct it from a
// CubicSpline that outlives it.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class L>
struct CubicSplineLanes {
  static L c(double a) { return lanes(L{}, a); }
  CubicSplineLanes(const CubicSpline& K, L r2)
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
  const CubicSpline& k;  // (a reference: its constant factors stay out of the callers' loops)
  L q, t;
  typename LaneMaskOf<L>::type inner, inside;
};
#pragma GCC diagnostic pop

}  // namespace sphib
