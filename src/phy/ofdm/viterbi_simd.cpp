// The built-in Viterbi decoder (make_simd_viterbi_decoder, the default
// make_viterbi_decoder): per-block LLR quantization, one add-compare-select
// kernel chosen from the CPU's features (viterbi_kernels.hpp), and a traceback
// over the whole block from a known end state.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "soft_decoding.hpp"
#include "viterbi_kernels.hpp"

namespace rfsitl::phy::ofdm {
namespace {

namespace vt = viterbi;

/// Quantized size of a block's mean finite nonzero |LLR|: the step is 1/40 of
/// the mean, and values up to 127/40 = 3.2 times the mean pass unclipped.
constexpr float kMeanMagnitude = 40.0F;

/// One LLR times the block's scale -> int16 symbol in [-kSymbolLimit,
/// kSymbolLimit]: positive stays positive (bit 0), an erasure stays 0, +-infinity
/// saturates, NaN (no usable information) becomes an erasure. The SSE2 loop
/// below performs exactly these float operations, so both give equal symbols.
std::int16_t quantize_one(float llr, float scale) {
  constexpr auto kLimit = static_cast<float>(vt::kSymbolLimit);
  float x = llr * scale;  // NaN for NaN input and for 0 * infinity
  if (std::isnan(x)) x = 0.0F;
  x = std::max(std::min(x, kLimit), -kLimit);
  // Round half away from zero; the truncating conversion is then exact.
  return static_cast<std::int16_t>(x + std::copysign(0.5F, x));
}

/// Whether |llr| counts toward the block's mean: finite and nonzero.
bool counts(float llr) {
  const float a = std::fabs(llr);
  return a != 0.0F && a < std::numeric_limits<float>::infinity();
}

/// The scale that puts the block's mean finite nonzero |LLR| at kMeanMagnitude.
/// The max-log decision does not change when all LLRs are scaled by one
/// positive factor, so this loses nothing but rounding.
float block_scale(std::span<const float> llr) {
  double sum = 0.0;
  std::size_t count = 0;
  std::size_t i = 0;
#if defined(__SSE2__)
  // Random signs made the branchy scalar loop mispredict on every other value.
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128d acc_lo = _mm_setzero_pd();
  __m128d acc_hi = _mm_setzero_pd();
  for (; i + 4 <= llr.size(); i += 4) {
    const __m128 a = _mm_and_ps(_mm_loadu_ps(llr.data() + i), abs_mask);
    const __m128 use = _mm_and_ps(_mm_cmpneq_ps(a, _mm_setzero_ps()), _mm_cmplt_ps(a, inf));
    const __m128 v = _mm_and_ps(a, use);
    acc_lo = _mm_add_pd(acc_lo, _mm_cvtps_pd(v));
    acc_hi = _mm_add_pd(acc_hi, _mm_cvtps_pd(_mm_movehl_ps(v, v)));
    static constexpr std::array<std::uint8_t, 16> kOnes = {0, 1, 1, 2, 1, 2, 2, 3,
                                                           1, 2, 2, 3, 2, 3, 3, 4};
    count += kOnes[static_cast<unsigned>(_mm_movemask_ps(use))];
  }
  alignas(16) std::array<double, 4> parts{};
  _mm_store_pd(parts.data(), acc_lo);
  _mm_store_pd(parts.data() + 2, acc_hi);
  sum = (parts[0] + parts[1]) + (parts[2] + parts[3]);
#endif
  for (; i < llr.size(); ++i) {
    if (counts(llr[i])) {
      sum += static_cast<double>(std::fabs(llr[i]));
      ++count;
    }
  }
  // Without any finite nonzero LLR only the infinities carry information; a
  // unit scale keeps them (a zero scale would turn them into NaN). A scale that
  // overflows to infinity (denormal mean) still maps each sign to the limit.
  return count > 0 ? static_cast<float>(kMeanMagnitude * static_cast<double>(count) / sum) : 1.0F;
}

void quantize(std::span<const float> llr, std::int16_t* out) {
  const float scale = block_scale(llr);
  std::size_t i = 0;
#if defined(__SSE2__)
  const __m128 s = _mm_set1_ps(scale);
  const __m128 limit = _mm_set1_ps(static_cast<float>(vt::kSymbolLimit));
  const __m128 neg_limit = _mm_set1_ps(-static_cast<float>(vt::kSymbolLimit));
  const __m128 sign = _mm_castsi128_ps(_mm_set1_epi32(static_cast<int>(0x80000000U)));
  const __m128 half = _mm_set1_ps(0.5F);
  const auto one = [&](const float* p) {
    __m128 x = _mm_mul_ps(_mm_loadu_ps(p), s);
    x = _mm_and_ps(x, _mm_cmpord_ps(x, x));  // NaN -> +0
    x = _mm_max_ps(_mm_min_ps(x, limit), neg_limit);
    x = _mm_add_ps(x, _mm_or_ps(_mm_and_ps(x, sign), half));  // x + copysign(0.5, x)
    return _mm_cvttps_epi32(x);
  };
  for (; i + 8 <= llr.size(); i += 8) {
    const __m128i q = _mm_packs_epi32(one(llr.data() + i), one(llr.data() + i + 4));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), q);
  }
#endif
  for (; i < llr.size(); ++i) out[i] = quantize_one(llr[i], scale);
}

class SimdViterbiDecoder final : public ViterbiDecoder {
 public:
  explicit SimdViterbiDecoder(vt::AcsKernel kernel) : kernel_(kernel) {}

  std::vector<std::uint8_t> decode(std::span<const float> llr, std::size_t n_bits,
                                   bool terminated) override {
    // Compared without forming 2 * n_bits, which could wrap.
    if (llr.size() % 2 != 0 || llr.size() / 2 != n_bits) {
      throw std::invalid_argument("ViterbiDecoder::decode: need 2 * n_bits LLRs");
    }
    if (terminated && n_bits < vt::kMemory) {
      throw std::invalid_argument("ViterbiDecoder::decode: a terminated block holds a 6-bit tail");
    }
    if (n_bits == 0) return {};

    // The buffers only grow: a receiver decoding frame after frame allocates
    // once for its longest frame.
    symbols_.resize(llr.size());
    decisions_.resize(n_bits);
    quantize(llr, symbols_.data());

    std::array<std::int16_t, vt::kStates> metrics{};
    metrics.fill(static_cast<std::int16_t>(-vt::kStartPenalty));
    metrics[0] = 0;
    kernel_(symbols_.data(), n_bits, metrics.data(), decisions_.data());

    // A terminated path ends in state 0; an open one in the best state (the
    // lowest-numbered of equals, so that the result is deterministic).
    unsigned state = 0;
    if (!terminated) {
      state =
          static_cast<unsigned>(std::max_element(metrics.begin(), metrics.end()) - metrics.begin());
    }
    // Bit t is the newest bit of the state after step t. Along a path into
    // state 0 the last 6 states' low bits are that state's bits, so a
    // terminated block's tail comes out as zeros by itself.
    std::vector<std::uint8_t> bits(n_bits);
    for (std::size_t t = n_bits; t-- > 0;) {
      bits[t] = static_cast<std::uint8_t>(state & 1U);
      const auto from_p1 = static_cast<unsigned>((decisions_[t] >> state) & 1U);
      state = (state >> 1U) | (from_p1 << 5U);
    }
    return bits;
  }

 private:
  vt::AcsKernel kernel_;
  std::vector<std::int16_t> symbols_;
  std::vector<std::uint64_t> decisions_;
};

bool cpu_has(ViterbiKernel kernel) {
#if defined(__x86_64__) || defined(__i386__)
  // GCC's check includes the OS's XSAVE support for the wider registers.
  __builtin_cpu_init();
  switch (kernel) {
    case ViterbiKernel::kSse2:
#if defined(__SSE2__)
      return true;
#else
      return false;
#endif
    case ViterbiKernel::kAvx2:
      return __builtin_cpu_supports("avx2") != 0;
    case ViterbiKernel::kAvx512:
      return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512bw") != 0;
    default:
      return true;
  }
#else
  return kernel == ViterbiKernel::kBest || kernel == ViterbiKernel::kPortable;
#endif
}

vt::AcsKernel kernel_for(ViterbiKernel kernel) {
#if defined(__x86_64__) || defined(__i386__)
  switch (kernel) {
#if defined(__SSE2__)
    case ViterbiKernel::kSse2:
      return &vt::acs_sse2;
#endif
    case ViterbiKernel::kAvx2:
      return &vt::acs_avx2;
    case ViterbiKernel::kAvx512:
      return &vt::acs_avx512;
    default:
      break;
  }
#else
  (void)kernel;
#endif
  return &vt::acs_portable;
}

}  // namespace

bool viterbi_kernel_supported(ViterbiKernel kernel) {
  return cpu_has(kernel);
}

std::unique_ptr<ViterbiDecoder> make_simd_viterbi_decoder(ViterbiKernel kernel) {
  if (kernel == ViterbiKernel::kBest) {
    kernel = cpu_has(ViterbiKernel::kAvx512) ? ViterbiKernel::kAvx512
             : cpu_has(ViterbiKernel::kAvx2) ? ViterbiKernel::kAvx2
             : cpu_has(ViterbiKernel::kSse2) ? ViterbiKernel::kSse2
                                             : ViterbiKernel::kPortable;
  }
  if (!cpu_has(kernel)) {
    throw std::invalid_argument("make_simd_viterbi_decoder: kernel not supported by this CPU");
  }
  return std::make_unique<SimdViterbiDecoder>(kernel_for(kernel));
}

std::unique_ptr<ViterbiDecoder> make_viterbi_decoder() {
  return make_simd_viterbi_decoder(ViterbiKernel::kBest);
}

}  // namespace rfsitl::phy::ofdm
