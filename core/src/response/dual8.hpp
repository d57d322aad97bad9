#pragma once
// Dual numbers over the 7 durations of a 7-segment law in 8 aligned lanes, and the state types
// the DOP853 templates integrate in them (internal to the core; the path sensitivities'
// arithmetic: planar_sensitivity.hpp, tank_planar_sensitivity.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "response/sincos.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "solve/dual.hpp"

namespace slosh::detail {

/// A dual number over the 7 durations in 8 aligned lanes: x[0] the value, x[1 + i] the
/// derivative by duration i. Its operations act on two 4-lane vectors (GCC's vector extension:
/// AVX registers in the AVX clone, SSE pairs otherwise) and are always inlined: this integrator
/// evaluates them millions of times per plan, and in its one large function the compiler's
/// auto-vectoriser left most lane loops scalar. Each lane is the same IEEE operation in the same
/// order as the scalar loop, so the numbers are the same to the bit.
struct D8 {
  alignas(32) std::array<double, 8> x{};
  D8() = default;
  explicit D8(double v) : x{v} {}
  explicit D8(const Dual7& d) {
    x[0] = d.v;
    for (std::size_t i = 0; i < kSegments; ++i) x[1 + i] = d.d[i];
  }
  [[nodiscard]] double value() const { return x[0]; }
};

/// Four lanes of a D8.
using Lanes4 = double __attribute__((vector_size(32)));

// The lane helpers pass 32-byte vectors by value, whose ABI differs with and without AVX; they
// are always inlined, so no call ever crosses that boundary. GCC reports the ABI note at the end
// of the including file, where a pushed state is popped already: the note stays off in the
// files that include this internal header.
#pragma GCC diagnostic ignored "-Wpsabi"

[[gnu::always_inline]] inline Lanes4 half(const D8& a, std::size_t h) {
  Lanes4 r;
  std::memcpy(&r, a.x.data() + 4 * h, sizeof r);
  return r;
}
[[gnu::always_inline]] inline void set_half(D8& a, std::size_t h, Lanes4 v) {
  std::memcpy(a.x.data() + 4 * h, &v, sizeof v);
}
[[gnu::always_inline]] inline Lanes4 broadcast(double v) {
  return Lanes4{v, v, v, v};
}

/// The D8 of two halves, the value lane of `lo` replaced by `value`. Lane 0 is set in the
/// register, never by a scalar store into a stored half: a vector load of a half that a scalar
/// store wrote part of cannot be forwarded from the store buffer and stalls until the store
/// retires (most of this integrator's time went to such stalls).
[[gnu::always_inline]] inline D8 d8_of(Lanes4 lo, Lanes4 hi, double value) {
  lo[0] = value;
  D8 r;
  set_half(r, 0, lo);
  set_half(r, 1, hi);
  return r;
}

#define SLOSH_D8_LANES(expr)                                \
  D8 r;                                                     \
  for (std::size_t h = 0; h < 2; ++h) set_half(r, h, expr); \
  return r

[[gnu::always_inline]] inline D8 operator+(const D8& a, const D8& b) {
  SLOSH_D8_LANES(half(a, h) + half(b, h));
}
[[gnu::always_inline]] inline D8 operator-(const D8& a, const D8& b) {
  SLOSH_D8_LANES(half(a, h) - half(b, h));
}
[[gnu::always_inline]] inline D8 operator-(const D8& a) {
  SLOSH_D8_LANES(-half(a, h));
}
[[gnu::always_inline]] inline D8 operator*(double a, const D8& b) {
  SLOSH_D8_LANES(broadcast(a) * half(b, h));
}
[[gnu::always_inline]] inline D8 operator*(const D8& b, double a) {
  SLOSH_D8_LANES(broadcast(a) * half(b, h));
}
[[gnu::always_inline]] inline D8 operator+(const D8& a, double b) {
  return d8_of(half(a, 0), half(a, 1), a.x[0] + b);
}
[[gnu::always_inline]] inline D8 operator+(double b, const D8& a) {
  return a + b;
}
[[gnu::always_inline]] inline D8 operator-(const D8& a, double b) {
  return a + (-b);
}
/// The dual product (lane 0 the product of the values, lane i the product rule).
[[gnu::always_inline]] inline D8 operator*(const D8& a, const D8& b) {
  const double a0 = a.x[0], b0 = b.x[0];
  return d8_of(half(a, 0) * broadcast(b0) + broadcast(a0) * half(b, 0),
               half(a, 1) * broadcast(b0) + broadcast(a0) * half(b, 1), a0 * b0);
}
[[gnu::always_inline]] inline D8 operator/(const D8& a, const D8& b) {
  const double inv = 1.0 / b.x[0];
  const double q = a.x[0] * inv;
  return d8_of((half(a, 0) - broadcast(q) * half(b, 0)) * broadcast(inv),
               (half(a, 1) - broadcast(q) * half(b, 1)) * broadcast(inv), q);
}
#undef SLOSH_D8_LANES

/// Two duals (q_x, q_y), the state type the DOP853 templates integrate: the scheme's linear
/// combinations act on all 16 lanes alike; only the products with the dual step length are dual
/// products.
struct DualPair {
  std::array<D8, 2> c{};
  DualPair() = default;
  DualPair(double v) : c{D8(v), D8(v)} {}  // NOLINT(google-explicit-constructor): scalars broadcast
  explicit DualPair(const D8& v) { c[0] = c[1] = v; }
};

// Element-wise arithmetic (what the DOP853 templates need), found by argument-dependent lookup.
[[gnu::always_inline]] inline DualPair operator+(const DualPair& a, const DualPair& b) {
  DualPair r;
  r.c[0] = a.c[0] + b.c[0];
  r.c[1] = a.c[1] + b.c[1];
  return r;
}
[[gnu::always_inline]] inline DualPair operator-(const DualPair& a, const DualPair& b) {
  DualPair r;
  r.c[0] = a.c[0] - b.c[0];
  r.c[1] = a.c[1] - b.c[1];
  return r;
}
[[gnu::always_inline]] inline DualPair operator*(double a, const DualPair& b) {
  DualPair r;
  r.c[0] = a * b.c[0];
  r.c[1] = a * b.c[1];
  return r;
}
[[gnu::always_inline]] inline DualPair operator*(const DualPair& b, double a) {
  return a * b;
}
[[gnu::always_inline]] inline DualPair operator*(const DualPair& a, const DualPair& b) {
  DualPair r;
  r.c[0] = a.c[0] * b.c[0];
  r.c[1] = a.c[1] * b.c[1];
  return r;
}
[[gnu::always_inline]] inline DualPair operator*(const DualPair& a, const D8& s) {
  DualPair r;
  r.c[0] = a.c[0] * s;
  r.c[1] = a.c[1] * s;
  return r;
}

/// cos x and sin x of a dual x (one kernel call for both).
[[gnu::always_inline]] inline void dual_cos_sin(const D8& x, D8& c, D8& s) {
  const SinCos v = fast_sincos(x.x[0]);
  c = d8_of(broadcast(-v.sin) * half(x, 0), broadcast(-v.sin) * half(x, 1), v.cos);
  s = d8_of(broadcast(v.cos) * half(x, 0), broadcast(v.cos) * half(x, 1), v.sin);
}

/// a / b for a double b (each lane divided).
[[gnu::always_inline]] inline D8 operator/(const D8& a, double b) {
  D8 r;
  for (std::size_t h = 0; h < 2; ++h) set_half(r, h, half(a, h) / broadcast(b));
  return r;
}

/// |x| and sqrt(x) (x > 0) of a dual x.
[[gnu::always_inline]] inline D8 dual_abs(const D8& x) {
  return x.x[0] < 0.0 ? -x : x;
}
[[gnu::always_inline]] inline D8 dual_sqrt(const D8& x) {
  const double r = std::sqrt(x.x[0]);
  const Lanes4 f = broadcast(r > 0.0 ? 0.5 / r : 0.0);
  return d8_of(f * half(x, 0), f * half(x, 1), r);
}

/// N duals, the state type of a model with N coordinates: as DualPair, element-wise.
template <std::size_t N>
struct DualVec {
  std::array<D8, N> c{};
  DualVec() = default;
  DualVec(double v) {  // NOLINT(google-explicit-constructor): scalars broadcast
    c.fill(D8(v));
  }
  explicit DualVec(const D8& v) { c.fill(v); }
  [[gnu::always_inline]] D8& operator[](std::size_t i) { return c[i]; }
  [[gnu::always_inline]] const D8& operator[](std::size_t i) const { return c[i]; }
};

#define SLOSH_DUALVEC_OP(expr)                         \
  DualVec<N> r;                                        \
  for (std::size_t i = 0; i < N; ++i) r.c[i] = (expr); \
  return r

template <std::size_t N>
[[gnu::always_inline]] inline DualVec<N> operator+(const DualVec<N>& a, const DualVec<N>& b) {
  SLOSH_DUALVEC_OP(a.c[i] + b.c[i]);
}
template <std::size_t N>
[[gnu::always_inline]] inline DualVec<N> operator-(const DualVec<N>& a, const DualVec<N>& b) {
  SLOSH_DUALVEC_OP(a.c[i] - b.c[i]);
}
template <std::size_t N>
[[gnu::always_inline]] inline DualVec<N> operator*(double a, const DualVec<N>& b) {
  SLOSH_DUALVEC_OP(a * b.c[i]);
}
template <std::size_t N>
[[gnu::always_inline]] inline DualVec<N> operator*(const DualVec<N>& b, double a) {
  SLOSH_DUALVEC_OP(a * b.c[i]);
}
template <std::size_t N>
[[gnu::always_inline]] inline DualVec<N> operator*(const DualVec<N>& a, const DualVec<N>& b) {
  SLOSH_DUALVEC_OP(a.c[i] * b.c[i]);
}
#undef SLOSH_DUALVEC_OP

}  // namespace slosh::detail
