#include "kernels/fused_rows.hpp"

#include <type_traits>

#include "kernels/stencil_rows.hpp"

namespace sphib {

namespace {

using stencil::kBlock;
using stencil::v4d;
using stencil::v4d_unaligned;

// --- Eqs. (28), (39)-(41): the predictor's right-hand side ---------------------------------------

// Rows b + t st, t < m: acc = (lap u, lap v[, d/dx u, d/dx v, d/dy u, d/dy v]) of those rows.
// Images: the rows may have image terms (read bc, lw, cwx, cwy); otherwise those are zero.
template <bool Conv, bool Images, bool Strided>
[[gnu::always_inline]] inline void predictor_rows(const PredictorRows& p, const double* const* acc, int b, int m,
                                                  int stride) {
  const int st = Strided ? stride : 1, N = p.n;
  const double a = p.a, k = p.k, kc = p.kc;
  const bool first = p.first;
  const double *__restrict u0 = p.u + b, *__restrict u1 = p.u + N + b;
  for (int c = 0; c < 2; ++c) {
    const int o = c * N + b;  // row b of column c of the N x 2 fields
    const double *__restrict u = p.u + o, *__restrict F = p.F + o;
    const double *__restrict bc = p.bc + o, *__restrict lw = p.lw + o;
    const double *__restrict cwx = p.cwx + o, *__restrict cwy = p.cwy + o;
    const double* __restrict conv_in = Conv ? nullptr : p.conv + o;
    double* __restrict conv_old = Conv ? p.conv_old + o : nullptr;
    double* __restrict rhs = p.rhs + o;
    const double *__restrict lap = acc[c], *__restrict dx = acc[Conv ? 2 + c : 0], *__restrict dy = acc[Conv ? 4 + c : 0];
    for (int t = 0; t < m; ++t) {
      const int i = t * st;
      double conv;
      if (Conv) {
        const double n = (dx[t] + (Images ? cwx[i] : 0.0)) * u0[i] + (dy[t] + (Images ? cwy[i] : 0.0)) * u1[i];  // Eqs. (40)-(41)
        conv = 1.5 * n - 0.5 * (first ? n : conv_old[i]);  // Eq. (39), AB2
        conv_old[i] = n;
      } else {
        conv = conv_in[i];
      }
      rhs[i] = ((lap[t] + (Images ? bc[i] : 0.0)) + (Images ? lw[i] : 0.0)) * a + u[i] + k * F[i] - kc * conv;  // Eq. (28)
    }
  }
}

template <bool Conv, bool Images>
[[gnu::always_inline]] inline void predictor_block(const PredictorRows& p, const StencilClass& cl,
                                                   const StencilBlock& k, const double* const* w,
                                                   const double* const* in) {
  constexpr int NA = Conv ? 6 : 2;
  double sums[NA][kBlock];
  stencil::accumulate_block<2, Conv ? 3 : 1, false>(cl, k, w, in, sums);
  const double* acc[NA];
  for (int a = 0; a < NA; ++a) acc[a] = sums[a];
  if (k.stride == 1) predictor_rows<Conv, Images, false>(p, acc, k.begin, k.count, 1);
  else predictor_rows<Conv, Images, true>(p, acc, k.begin, k.count, k.stride);
}

}  // namespace

[[gnu::target_clones("avx2", "default")]] void block_predictor(const PredictorRows& p, bool images,
                                                              const StencilClass& cl, const StencilBlock& k,
                                                              const double* const* w, const double* const* in) {
  const bool conv = p.conv_old != nullptr;
  if (conv && images) predictor_block<true, true>(p, cl, k, w, in);
  else if (conv) predictor_block<true, false>(p, cl, k, w, in);
  else if (images) predictor_block<false, true>(p, cl, k, w, in);
  else predictor_block<false, false>(p, cl, k, w, in);
}

void predictor_row(const PredictorRows& p, const double* const* acc, int i) {
  if (p.conv_old) predictor_rows<true, true, false>(p, acc, i, 1, 1);
  else predictor_rows<false, true, false>(p, acc, i, 1, 1);
}

// --- the exact projection: C^T u* and the stream functions' right-hand sides ---------------------

namespace {

template <bool Strided>
[[gnu::always_inline]] inline void curl_transpose_rows(const CurlTransposeRows& p, const double* const* acc, int b,
                                                       int m, int stride) {
  const int st = Strided ? stride : 1;
  const double Q = p.Q, scale = p.scale;
  const double *__restrict flux = p.flux + b, *__restrict mflux = p.mflux + b;
  double *__restrict cu = p.cu + b, *__restrict b_psi = p.b_psi + b, *__restrict b_m = p.b_m ? p.b_m + b : nullptr;
  const double *__restrict ty = acc[0], *__restrict tx = acc[1];
  for (int t = 0; t < m; ++t) {
    const int i = t * st;
    const double c = ty[t] + tx[t];  // Gy^T u - Gx^T v
    cu[i] = c;
    b_psi[i] = Q != 0.0 ? c - Q * flux[i] : c;
    if (b_m) b_m[i] = (c + Q * mflux[i]) * scale;
  }
}

}  // namespace

[[gnu::target_clones("avx2", "default")]] void block_curl_transpose(const CurlTransposeRows& p, const StencilClass& cl,
                                                                   const StencilBlock& k, const double* const* w,
                                                                   const double* const* in) {
  double sums[2][kBlock];
  stencil::accumulate_block<2, 2, true>(cl, k, w, in, sums);
  const double* acc[2] = {sums[0], sums[1]};
  if (k.stride == 1) curl_transpose_rows<false>(p, acc, k.begin, k.count, 1);
  else curl_transpose_rows<true>(p, acc, k.begin, k.count, k.stride);
}

void curl_transpose_row(const CurlTransposeRows& p, const double* const* acc, int i) {
  curl_transpose_rows<false>(p, acc, i, 1, 1);
}

// --- the exact projection: u^{n+1} and grad phi from the curl of psi -----------------------------

namespace {

template <class T>
[[gnu::always_inline]] inline T splat(double x) {
  if constexpr (std::is_same_v<T, double>) return x;
  else return T{x, x, x, x};
}
template <class T>
[[gnu::always_inline]] inline T load(const double* p) {
  if constexpr (std::is_same_v<T, double>) return *p;
  else return *reinterpret_cast<const v4d_unaligned*>(p);
}
template <class T>
[[gnu::always_inline]] inline void put(double* p, T x) {
  if constexpr (std::is_same_v<T, double>) *p = x;
  else *reinterpret_cast<v4d_unaligned*>(p) = x;
}

// One row (T = double) or four (T = v4d) of u^{n+1} and grad phi: md0, md1 the modes' values.
template <class T, bool Images>
[[gnu::always_inline]] inline void curl_velocity_math(const CurlVelocityRows& p, T gx, T gy, T by1, T bx1, T us0,
                                                      T us1, T md0, T md1, T& u0, T& u1, T& g0, T& g1) {
  const T qz = splat<T>(p.Q * 0.0);  // Q by1 where by1 is zero (no image terms)
  T a = gy + (Images ? p.Q * by1 : qz);
  T c = -(gx + (Images ? p.Q * bx1 : qz));
  if (p.modes.has[0]) a = a + md0;  // u*'s alternating modes
  if (p.modes.has[1]) c = c + md1;
  u0 = a;
  u1 = c;
  g0 = p.r * (us0 - a);  // Eq. (34): G phi = rho/dt (u* - u^{n+1})
  g1 = p.r * (us1 - c);
}

// Rows b + t st, t < m, from acc = (Gx psi, Gy psi). The modes' values, by the parity class of each
// row, alternate with t along a lattice row and down a column (alt[c][t & 1]): such contiguous
// blocks go four rows at a time.
template <bool Images, bool Strided>
[[gnu::always_inline]] inline void curl_velocity_rows(const CurlVelocityRows& p, const double* const* acc, int b,
                                                      int m, int stride) {
  const int st = Strided ? stride : 1, N = p.n;
  const int nx = p.nx, iy = b / nx, ix = b - iy * nx;
  const auto& mv = p.modes.value;
  bool alternating = false;
  double alt[2][2] = {};
  if ((st == 1 && ix + m <= nx) || st == nx) {  // along lattice row iy, or down lattice column ix
    alternating = true;
    for (int c = 0; c < 2; ++c) {
      alt[c][0] = mv[c][iy & 1][ix & 1];
      alt[c][1] = st == 1 ? mv[c][iy & 1][(ix + 1) & 1] : mv[c][(iy + 1) & 1][ix & 1];
    }
  }
  double *u0 = p.u, *u1 = p.u + N, *g0 = p.grad_phi, *g1 = p.grad_phi + N;
  const double *gx = acc[0], *gy = acc[1];
  const double *us0 = p.u_star, *us1 = p.u_star + N;
  int t = 0;
  if (!Strided && alternating) {
    const v4d md0 = {alt[0][0], alt[0][1], alt[0][0], alt[0][1]}, md1 = {alt[1][0], alt[1][1], alt[1][0], alt[1][1]};
    for (; t + 4 <= m; t += 4) {
      const int i = b + t;
      v4d a, c, ga, gc;
      curl_velocity_math<v4d, Images>(p, load<v4d>(gx + t), load<v4d>(gy + t), load<v4d>(p.by1 + i),
                                      load<v4d>(p.bx1 + i), load<v4d>(us0 + i), load<v4d>(us1 + i), md0, md1, a, c,
                                      ga, gc);
      put(u0 + i, a);
      put(u1 + i, c);
      put(g0 + i, ga);
      put(g1 + i, gc);
    }
  }
  for (; t < m; ++t) {
    const int i = b + t * st, q = p.par[i];
    const double md0 = alternating ? alt[0][t & 1] : mv[0][q >> 1][q & 1];
    const double md1 = alternating ? alt[1][t & 1] : mv[1][q >> 1][q & 1];
    curl_velocity_math<double, Images>(p, gx[t], gy[t], p.by1[i], p.bx1[i], us0[i], us1[i], md0, md1, u0[i],
                                       u1[i], g0[i], g1[i]);
  }
}

template <bool Images>
[[gnu::always_inline]] inline void curl_velocity_block(const CurlVelocityRows& p, const StencilClass& cl,
                                                       const StencilBlock& k, const double* const* w,
                                                       const double* const* in) {
  double sums[2][kBlock];
  stencil::accumulate_block<1, 2, false>(cl, k, w, in, sums);
  const double* acc[2] = {sums[0], sums[1]};
  if (k.stride == 1) curl_velocity_rows<Images, false>(p, acc, k.begin, k.count, 1);
  else curl_velocity_rows<Images, true>(p, acc, k.begin, k.count, k.stride);
}

}  // namespace

[[gnu::target_clones("avx2", "default")]] void block_curl_velocity(const CurlVelocityRows& p, bool images,
                                                                  const StencilClass& cl, const StencilBlock& k,
                                                                  const double* const* w, const double* const* in) {
  if (images) curl_velocity_block<true>(p, cl, k, w, in);
  else curl_velocity_block<false>(p, cl, k, w, in);
}

void curl_velocity_row(const CurlVelocityRows& p, const double* const* acc, int i) {
  curl_velocity_rows<true, false>(p, acc, i, 1, 1);
}

// --- the plain forms: one row at a time, each sum and each line as written ------------------------

namespace {

// (A x)_row = sum_s w[s] x[row + off_s]: one operator's row applied to one input, term by term
double row_sum(const StencilClass& cl, const double* w, const double* x, int row) {
  double y = 0.0;
  for (size_t s = 0; s < cl.offset.size(); ++s) y += w[s] * x[row + cl.offset[s]];
  return y;
}

}  // namespace

void block_predictor_plain(const PredictorRows& p, const StencilClass& cl, const StencilBlock& k,
                           const double* const* w, const double* const* in) {
  const int N = p.n;
  for (int t = 0; t < k.count; ++t) {
    const int row = k.begin + t * k.stride;
    for (int c = 0; c < 2; ++c) {
      const int i = c * N + row;
      const double lap = row_sum(cl, w[0], in[c], row);
      double conv = 0.0;
      if (p.conv_old) {
        const double dudx = row_sum(cl, w[1], in[c], row), dudy = row_sum(cl, w[2], in[c], row);
        const double n = (dudx + p.cwx[i]) * p.u[row] + (dudy + p.cwy[i]) * p.u[N + row];  // Eqs. (40)-(41)
        const double n_old = p.first ? n : p.conv_old[i];  // first step: Euler, N^{-1} = N^0
        conv = 1.5 * n - 0.5 * n_old;                      // Eq. (39), AB2
        p.conv_old[i] = n;
      } else {
        conv = p.conv[i];
      }
      p.rhs[i] = ((lap + p.bc[i]) + p.lw[i]) * p.a + p.u[i] + p.k * p.F[i] - p.kc * conv;  // Eq. (28)
    }
  }
}

void block_curl_transpose_plain(const CurlTransposeRows& p, const StencilClass& cl, const StencilBlock& k,
                                const double* const* w, const double* const* in) {
  for (int t = 0; t < k.count; ++t) {
    const int i = k.begin + t * k.stride;
    const double cu = row_sum(cl, w[0], in[0], i) + row_sum(cl, w[1], in[1], i);  // Gy^T u + (-Gx^T) v
    p.cu[i] = cu;
    p.b_psi[i] = p.Q != 0.0 ? cu - p.Q * p.flux[i] : cu;
    if (p.b_m) p.b_m[i] = (cu + p.Q * p.mflux[i]) * p.scale;
  }
}

void block_curl_velocity_plain(const CurlVelocityRows& p, const StencilClass& cl, const StencilBlock& k,
                               const double* const* w, const double* const* in) {
  const int N = p.n;
  for (int t = 0; t < k.count; ++t) {
    const int i = k.begin + t * k.stride, q = p.par[i];
    const double gx = row_sum(cl, w[0], in[0], i), gy = row_sum(cl, w[1], in[0], i);
    double u = gy + p.Q * p.by1[i];     // C psi = (Gy psi, -Gx psi), plus the flux's curl
    double v = -(gx + p.Q * p.bx1[i]);
    if (p.modes.has[0]) u = u + p.modes.value[0][q >> 1][q & 1];  // u*'s alternating modes
    if (p.modes.has[1]) v = v + p.modes.value[1][q >> 1][q & 1];
    p.u[i] = u;
    p.u[N + i] = v;
    p.grad_phi[i] = p.r * (p.u_star[i] - u);  // Eq. (34): G phi = rho/dt (u* - u^{n+1})
    p.grad_phi[N + i] = p.r * (p.u_star[N + i] - v);
  }
}

}  // namespace sphib
