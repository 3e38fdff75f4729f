#pragma once
// Lanes: two or four doubles operated on lane by lane (GCC and Clang vector extensions; SSE2 on
// x86-64, AVX2 inside the clones of kernels/). The fast kernels and the markers' two-lane loops
// are written with them; nothing here knows a fluid or a membrane.
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sphib {

// LaneMask2 holds a comparison's result (all bits set where true).
using Lanes2 = double __attribute__((vector_size(16)));
using LaneMask2 = long long __attribute__((vector_size(16)));
// Four lanes for the AVX2 clones (two SSE2 halves in the default ones).
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

}  // namespace sphib
