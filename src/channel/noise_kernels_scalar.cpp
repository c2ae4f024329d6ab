// The noise kernel one sample pair at a time (any CPU; see noise_math.hpp).
#include <bit>
#include <cmath>

#include "noise_kernels.hpp"
#include "noise_math.hpp"

namespace rfsitl::channel::noise_kernels {
namespace {

struct Lane {
  using U = std::uint32_t;
  using F = float;
  static U set1(std::uint32_t v) { return v; }
  static U add(U a, U b) { return a + b; }
  static U sub(U a, U b) { return a - b; }
  static U xor_(U a, U b) { return a ^ b; }
  static U and_(U a, U b) { return a & b; }
  static U or_(U a, U b) { return a | b; }
  template <int N>
  static U srl(U a) {
    return a >> N;
  }
  template <int N>
  static U sll(U a) {
    return a << N;
  }
  static U gt(U a, U b) {
    return static_cast<std::int32_t>(a) > static_cast<std::int32_t>(b) ? 0xFFFFFFFFU : 0U;
  }
  static U mullo(U a, std::uint32_t m) { return a * m; }
  static U mulhi(U a, std::uint32_t m) {
    return static_cast<U>((static_cast<std::uint64_t>(a) * m) >> 32);
  }
  static U lane_index(std::uint32_t first) { return first; }
  static F to_float(U a) { return static_cast<float>(a); }
  static F int_to_float(U a) { return static_cast<float>(static_cast<std::int32_t>(a)); }
  static F set1f(float v) { return v; }
  static F addf(F a, F b) { return a + b; }
  static F subf(F a, F b) { return a - b; }
  static F mulf(F a, F b) { return a * b; }
  static F fma(F a, F b, F c) { return std::fma(a, b, c); }
  static F divf(F a, F b) { return a / b; }
  static F sqrtf(F a) { return std::sqrt(a); }
  static U as_u(F a) { return std::bit_cast<U>(a); }
  static F as_f(U a) { return std::bit_cast<F>(a); }
};

}  // namespace

void group_scalar(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                  float sigma, float* out) {
  for (std::uint32_t j = 0; j < 16; ++j) {
    float v[4];
    noise_math::group_lanes<Lane>(group, j, key, stream, sigma, v);
    out[2 * j] = v[0];
    out[2 * j + 1] = v[1];
    out[2 * (16 + j)] = v[2];
    out[2 * (16 + j) + 1] = v[3];
  }
}

}  // namespace rfsitl::channel::noise_kernels
