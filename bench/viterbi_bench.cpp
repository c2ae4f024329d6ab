// Decoding throughput of the Viterbi decoders for one 1500-byte PSDU: SERVICE
// (16) + 12000 PSDU bits + 6 tail bits, terminated and open-ended. Reported as
// decoded data bits per second of one core ("Mbit/s"): the default decoder
// (make_viterbi_decoder, the fastest SIMD kernel), each SIMD kernel this CPU
// supports, and libfec's viterbi27 (make_libfec_viterbi_decoder).
//
// Built as rfsitl_viterbi_bench (bash scripts/build.sh release).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include "phy/ofdm/bit_pipeline.hpp"
#include "phy/ofdm/rates.hpp"
#include "phy/ofdm/soft_decoding.hpp"

namespace {

using rfsitl::cf32;
namespace ofdm = rfsitl::phy::ofdm;

constexpr std::size_t kFrameBits = 16 + 8 * 1500 + 6;

/// Random frame with a zero tail, and the rate-1/2 LLRs of its code bits after
/// BPSK in AWGN at 4 dB Es/N0: a realistic mix of confident and doubtful values.
struct Frame {
  std::vector<std::uint8_t> bits;
  std::vector<float> llr;
};

Frame make_frame(std::size_t n_bits) {
  std::mt19937 rng(1500);
  Frame f;
  f.bits.resize(n_bits);
  for (auto& b : f.bits) b = static_cast<std::uint8_t>(rng() & 1U);
  for (std::size_t i = n_bits - 6; i < n_bits; ++i) f.bits[i] = 0;
  const float noise_var = std::pow(10.0F, -0.4F);
  std::normal_distribution<float> noise(0.0F, std::sqrt(noise_var / 2.0F));
  for (std::uint8_t c : ofdm::convolutional_encode(f.bits)) {
    const float y = (c != 0 ? 1.0F : -1.0F) + noise(rng);
    f.llr.push_back(-4.0F * y / noise_var);
  }
  return f;
}

enum class Which { kDefault, kPortable, kSse2, kAvx2, kAvx512, kLibfec };

std::unique_ptr<ofdm::ViterbiDecoder> make(Which which) {
  switch (which) {
    case Which::kPortable:
      return ofdm::make_simd_viterbi_decoder(ofdm::ViterbiKernel::kPortable);
    case Which::kSse2:
      return ofdm::make_simd_viterbi_decoder(ofdm::ViterbiKernel::kSse2);
    case Which::kAvx2:
      return ofdm::make_simd_viterbi_decoder(ofdm::ViterbiKernel::kAvx2);
    case Which::kAvx512:
      return ofdm::make_simd_viterbi_decoder(ofdm::ViterbiKernel::kAvx512);
    case Which::kLibfec:
      return ofdm::make_libfec_viterbi_decoder();
    default:
      return ofdm::make_viterbi_decoder();
  }
}

bool supported(Which which) {
  switch (which) {
    case Which::kSse2:
      return ofdm::viterbi_kernel_supported(ofdm::ViterbiKernel::kSse2);
    case Which::kAvx2:
      return ofdm::viterbi_kernel_supported(ofdm::ViterbiKernel::kAvx2);
    case Which::kAvx512:
      return ofdm::viterbi_kernel_supported(ofdm::ViterbiKernel::kAvx512);
    default:
      return true;
  }
}

void BM_Viterbi1500Bytes(benchmark::State& state, Which which, bool terminated) {
  if (!supported(which)) {
    state.SkipWithError("kernel not supported by this CPU");
    return;
  }
  const Frame frame = make_frame(kFrameBits);
  auto decoder = make(which);
  std::size_t errors = 0;
  for (auto _ : state) {
    std::vector<std::uint8_t> out = decoder->decode(frame.llr, kFrameBits, terminated);
    benchmark::DoNotOptimize(out.data());
    for (std::size_t i = 0; i < kFrameBits; ++i) errors += out[i] != frame.bits[i];
  }
  const double decoded = static_cast<double>(state.iterations()) * static_cast<double>(kFrameBits);
  state.SetItemsProcessed(static_cast<std::int64_t>(decoded));
  state.counters["Mbit/s"] = benchmark::Counter(decoded / 1e6, benchmark::Counter::kIsRate);
  state.counters["bit_errors_per_frame"] =
      static_cast<double>(errors) / static_cast<double>(state.iterations());
}

/// The whole soft receive chain of the same PSDU at 54 Mb/s (64-QAM, R = 3/4):
/// demap, deinterleave, depuncture, Viterbi, from noiseless equalized points.
void BM_SoftChain1500Bytes54Mbps(benchmark::State& state) {
  const ofdm::RateParams rate = *ofdm::rate_from_mbps(54);
  const std::size_t n_sym = (kFrameBits + rate.n_dbps - 1) / rate.n_dbps;
  const std::size_t n_bits = n_sym * rate.n_dbps;  // padded to whole symbols
  const Frame frame = make_frame(n_bits);
  const std::vector<std::uint8_t> coded =
      ofdm::puncture(ofdm::convolutional_encode(frame.bits), rate.coding);
  std::vector<cf32> points;
  for (std::size_t s = 0; s < coded.size(); s += rate.n_cbps) {
    const auto sym = ofdm::interleave(std::span(coded).subspan(s, rate.n_cbps), rate.n_bpsc);
    for (std::size_t k = 0; k < sym.size(); k += rate.n_bpsc) {
      points.push_back(ofdm::map_point(std::span(sym).subspan(k, rate.n_bpsc), rate.n_bpsc));
    }
  }
  auto decoder = ofdm::make_viterbi_decoder();
  std::vector<float> soft(rate.n_cbps);
  std::vector<float> llr;
  for (auto _ : state) {
    llr.clear();
    for (std::size_t s = 0; s < points.size(); s += 48) {
      for (std::size_t k = 0; k < 48; ++k) {
        ofdm::demap_soft(points[s + k], rate.n_bpsc, 0.01F,
                         std::span(soft).subspan(k * rate.n_bpsc, rate.n_bpsc));
      }
      const std::vector<float> d = ofdm::deinterleave(soft, rate.n_bpsc);
      llr.insert(llr.end(), d.begin(), d.end());
    }
    const std::vector<float> half = ofdm::depuncture(llr, rate.coding, n_bits);
    std::vector<std::uint8_t> out = decoder->decode(half, n_bits, false);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n_bits));
}

}  // namespace

BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, default_terminated, Which::kDefault, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, default_open, Which::kDefault, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, avx512_terminated, Which::kAvx512, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, avx512_open, Which::kAvx512, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, avx2_terminated, Which::kAvx2, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, avx2_open, Which::kAvx2, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, sse2_terminated, Which::kSse2, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, sse2_open, Which::kSse2, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, portable_terminated, Which::kPortable, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, portable_open, Which::kPortable, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, libfec_terminated, Which::kLibfec, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Viterbi1500Bytes, libfec_open, Which::kLibfec, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SoftChain1500Bytes54Mbps)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
