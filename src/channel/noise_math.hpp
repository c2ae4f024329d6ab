#pragma once
// Internal to the channel module: the noise source's arithmetic, written once
// over a lane type V and instantiated by each kernel (noise_kernels_*.cpp:
// one lane, 8 lanes of AVX2, 16 of AVX-512). Every step is an IEEE operation
// with one rounding (add, multiply, fused multiply-add, divide, square root,
// exact integer work), the same in every kernel, so all of them give the same
// bits and a seed names the same noise on any x86-64 CPU.
//
// V provides, for U (32-bit unsigned lanes) and F (float lanes):
//   U: set1, add, sub, xor_, and_, srl<n>, sll<n>, gt (signed >, all ones or
//      zero), mullo/mulhi (the low and high words of the 64-bit product by a
//      constant), lane_index (0, 1, ... plus a first), to_float (unsigned,
//      correctly rounded), int_to_float (signed, exact for small values);
//   F: set1f, addf, subf, mulf, fma (a * b + c, one rounding), divf, sqrtf,
//      as_u, as_f (bit casts).
// Everything here has internal linkage, so that a kernel compiled for AVX-512
// never lends its copy to another translation unit.
#include <cstdint>

namespace rfsitl::channel::noise_math {
namespace {

/// The ten Philox4x32 rounds (common/philox.hpp, lane by lane).
template <class V>
inline void philox(typename V::U& c0, typename V::U& c1, typename V::U& c2, typename V::U& c3,
                   std::uint32_t k0, std::uint32_t k1) {
  constexpr std::uint32_t kM0 = 0xD2511F53;
  constexpr std::uint32_t kM1 = 0xCD9E8D57;
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      k0 += 0x9E3779B9;
      k1 += 0xBB67AE85;
    }
    const auto lo0 = V::mullo(c0, kM0);
    const auto hi0 = V::mulhi(c0, kM0);
    const auto lo1 = V::mullo(c2, kM1);
    const auto hi1 = V::mulhi(c2, kM1);
    c0 = V::xor_(V::xor_(hi1, c1), V::set1(k0));
    c1 = lo1;
    c2 = V::xor_(V::xor_(hi0, c3), V::set1(k1));
    c3 = lo0;
  }
}

/// ln(u) for u in [2^-32, 1]: u = 2^e m with m in [sqrt(1/2), sqrt(2)), and
/// ln m = 2 atanh(y), y = (m - 1) / (m + 1), |y| <= 0.172, by its series to
/// y^11 (the next term is below 2e-11).
template <class V>
inline typename V::F log_unit(typename V::F u) {
  const auto bits = V::as_u(u);
  auto m_bits = V::or_(V::and_(bits, V::set1(0x007FFFFFU)), V::set1(0x3F800000U));
  auto e = V::sub(V::template srl<23>(bits), V::set1(127U));  // a small signed number
  const auto over = V::gt(m_bits, V::set1(0x3FB504F3U));      // m > sqrt(2): halve m
  m_bits = V::sub(m_bits, V::and_(over, V::set1(0x00800000U)));
  e = V::sub(e, over);  // over is -1 where m was halved
  const auto m = V::as_f(m_bits);
  const auto one = V::set1f(1.0F);
  const auto y = V::divf(V::subf(m, one), V::addf(m, one));
  const auto y2 = V::mulf(y, y);
  auto p = V::fma(y2, V::set1f(1.0F / 11.0F), V::set1f(1.0F / 9.0F));
  p = V::fma(y2, p, V::set1f(1.0F / 7.0F));
  p = V::fma(y2, p, V::set1f(1.0F / 5.0F));
  p = V::fma(y2, p, V::set1f(1.0F / 3.0F));
  p = V::fma(y2, p, one);
  const auto ln_m = V::mulf(V::addf(y, y), p);
  // ln 2 in two parts, so that e ln 2 keeps float precision up to e = -32.
  const auto ef = V::int_to_float(e);
  return V::fma(ef, V::set1f(0.693145751953125F),
                V::fma(ef, V::set1f(1.428606765330187e-06F), ln_m));
}

/// cos and sin of 2 pi b / 2^32: the top two bits of b pick the quadrant, the
/// other 30 give x in [0, pi/2), where the Taylor series of sin to x^11 and of
/// cos to x^12 are within 6e-8 of the truth.
template <class V>
inline void unit_circle(typename V::U b, typename V::F& cos_out, typename V::F& sin_out) {
  const auto q = V::template srl<30>(b);
  const auto x = V::mulf(V::to_float(V::and_(b, V::set1(0x3FFFFFFFU))),
                         V::set1f(1.5707963267948966F * 0x1.0p-30F));
  const auto x2 = V::mulf(x, x);
  auto ps = V::fma(x2, V::set1f(-1.0F / 39916800.0F), V::set1f(1.0F / 362880.0F));
  ps = V::fma(x2, ps, V::set1f(-1.0F / 5040.0F));
  ps = V::fma(x2, ps, V::set1f(1.0F / 120.0F));
  ps = V::fma(x2, ps, V::set1f(-1.0F / 6.0F));
  ps = V::fma(x2, ps, V::set1f(1.0F));
  const auto s = V::as_u(V::mulf(x, ps));
  auto pc = V::fma(x2, V::set1f(1.0F / 479001600.0F), V::set1f(-1.0F / 3628800.0F));
  pc = V::fma(x2, pc, V::set1f(1.0F / 40320.0F));
  pc = V::fma(x2, pc, V::set1f(-1.0F / 720.0F));
  pc = V::fma(x2, pc, V::set1f(1.0F / 24.0F));
  pc = V::fma(x2, pc, V::set1f(-0.5F));
  pc = V::fma(x2, pc, V::set1f(1.0F));
  const auto c = V::as_u(pc);
  // Quadrant q turns (c, s) by q quarter turns: (c, s), (-s, c), (-c, -s), (s, -c).
  const auto swap = V::sub(V::set1(0U), V::and_(q, V::set1(1U)));  // all ones for odd q
  const auto diff = V::and_(V::xor_(c, s), swap);
  const auto first = V::xor_(c, diff);   // c, or s when swapped
  const auto second = V::xor_(s, diff);  // s, or c when swapped
  const auto sign_cos = V::template sll<30>(V::and_(V::add(q, V::set1(1U)), V::set1(2U)));
  const auto sign_sin = V::template sll<30>(V::and_(q, V::set1(2U)));
  cos_out = V::as_f(V::xor_(first, sign_cos));
  sin_out = V::as_f(V::xor_(second, sign_sin));
}

/// Box-Muller: from two 32-bit words, one circular complex Gaussian sample of
/// `sigma` per dimension. u1 = (a + 1) / 2^32 is in (0, 1] (never ln 0), so the
/// largest radius is 6.66 sigma, beyond which a Gaussian has 2e-10 of its samples.
template <class V>
inline void gaussian(typename V::U a, typename V::U b, typename V::F sigma, typename V::F& re,
                     typename V::F& im) {
  const auto u1 = V::mulf(V::addf(V::to_float(a), V::set1f(1.0F)), V::set1f(0x1.0p-32F));
  const auto r = V::mulf(sigma, V::sqrtf(V::mulf(V::set1f(-2.0F), log_unit<V>(u1))));
  typename V::F c;
  typename V::F s;
  unit_circle<V>(b, c, s);
  re = V::mulf(r, c);
  im = V::mulf(r, s);
}

/// Samples 32 g + j (words 0 and 1 of block 16 g + j) and 32 g + 16 + j (words
/// 2 and 3) for the lanes j = first, first + 1, ...: their real and imaginary
/// parts. Counter of block k: (k low, k high, stream low, stream high).
template <class V>
inline void group_lanes(std::uint64_t group, std::uint32_t first, const std::uint32_t key[2],
                        const std::uint32_t stream[2], float sigma, typename V::F out[4]) {
  const std::uint64_t block0 = group * 16;
  auto c0 = V::or_(V::set1(static_cast<std::uint32_t>(block0)), V::lane_index(first));
  auto c1 = V::set1(static_cast<std::uint32_t>(block0 >> 32));
  auto c2 = V::set1(stream[0]);
  auto c3 = V::set1(stream[1]);
  philox<V>(c0, c1, c2, c3, key[0], key[1]);
  const auto s = V::set1f(sigma);
  gaussian<V>(c0, c1, s, out[0], out[1]);
  gaussian<V>(c2, c3, s, out[2], out[3]);
}

}  // namespace
}  // namespace rfsitl::channel::noise_math
