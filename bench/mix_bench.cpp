/// Throughput of the channel's mixing kernel (channel::mix) beside the CPU's
/// measured peak, both on one thread in the same run.
///
///   rfsitl_mix_bench [--csv FILE] [--seconds S]
///
/// Mixing: complex multiply-accumulates per second, N active inputs x B samples
/// per call. Peak: tight loops of independent float operations over several
/// accumulators (no memory traffic), one per instruction set the CPU has
/// (SSE mul+add, AVX2 FMA, AVX-512 FMA), counted in flops and converted to
/// complex-MAC equivalents: 1 complex MAC = 4 real mul + 4 real add = 8 flops.
///
/// Noise: the receivers' Gaussian noise (channel::NoiseSource, counter-based),
/// samples per second added to B-sample blocks, the other half of a receiver's
/// channel work per tick.
#include <immintrin.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/channel/mixer.hpp"
#include "rfsitl/channel/noise_source.hpp"

namespace {

using namespace rfsitl;
using Clock = std::chrono::steady_clock;

constexpr double kFlopsPerComplexMac = 8.0;
constexpr int kRepeats = 5;  // median of this many timed runs
// The fading mixer's traffic per complex MAC: the input sample, read once (its
// output is read and written once per block of all inputs, not per input).
constexpr double kRampedBytesPerMac = 8.0;
// Its arithmetic: four FMAs per vector per input (the coefficient's re and im
// ramped in the lanes, then the two products), twice the flat mixer's, so its
// compute bound is half the FMA peak.
constexpr double kRampedFmaFactor = 0.5;

double elapsed_s(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// --- Peak loops. Every accumulator is an independent dependency chain, enough
// of them to cover the latency of the FP units; x * m + a converges to a / (1-m)
// so values stay normal. Returns flops per second.

double sse_peak(long iters, float* sink) {
  constexpr int kAcc = 12;
  __m128 acc[kAcc];
  for (int i = 0; i < kAcc; ++i) acc[i] = _mm_set1_ps(1.0F + 0.01F * static_cast<float>(i));
  const __m128 m = _mm_set1_ps(0.999F);
  const __m128 a = _mm_set1_ps(0.001F);
  const auto t0 = Clock::now();
  for (long k = 0; k < iters; ++k) {
    for (int i = 0; i < kAcc; ++i) acc[i] = _mm_add_ps(_mm_mul_ps(acc[i], m), a);
  }
  const double s = elapsed_s(t0);
  __m128 sum = acc[0];
  for (int i = 1; i < kAcc; ++i) sum = _mm_add_ps(sum, acc[i]);
  *sink += _mm_cvtss_f32(sum);
  return static_cast<double>(iters) * kAcc * 4 * 2 / s;  // 4 lanes, mul + add
}

__attribute__((target("avx2,fma"))) double avx2_fma_peak(long iters, float* sink) {
  constexpr int kAcc = 12;
  __m256 acc[kAcc];
  for (int i = 0; i < kAcc; ++i) acc[i] = _mm256_set1_ps(1.0F + 0.01F * static_cast<float>(i));
  const __m256 m = _mm256_set1_ps(0.999F);
  const __m256 a = _mm256_set1_ps(0.001F);
  const auto t0 = Clock::now();
  for (long k = 0; k < iters; ++k) {
    for (int i = 0; i < kAcc; ++i) acc[i] = _mm256_fmadd_ps(acc[i], m, a);
  }
  const double s = elapsed_s(t0);
  __m256 sum = acc[0];
  for (int i = 1; i < kAcc; ++i) sum = _mm256_add_ps(sum, acc[i]);
  *sink += _mm256_cvtss_f32(sum);
  return static_cast<double>(iters) * kAcc * 8 * 2 / s;  // 8 lanes, 2 flops per FMA
}

__attribute__((target("avx512f"))) double avx512_fma_peak(long iters, float* sink) {
  constexpr int kAcc = 12;
  __m512 acc[kAcc];
  for (int i = 0; i < kAcc; ++i) acc[i] = _mm512_set1_ps(1.0F + 0.01F * static_cast<float>(i));
  const __m512 m = _mm512_set1_ps(0.999F);
  const __m512 a = _mm512_set1_ps(0.001F);
  const auto t0 = Clock::now();
  for (long k = 0; k < iters; ++k) {
    for (int i = 0; i < kAcc; ++i) acc[i] = _mm512_fmadd_ps(acc[i], m, a);
  }
  const double s = elapsed_s(t0);
  __m512 sum = acc[0];
  for (int i = 1; i < kAcc; ++i) sum = _mm512_add_ps(sum, acc[i]);
  float lanes[16];
  _mm512_storeu_ps(lanes, sum);  // (_mm512_reduce_add_ps trips GCC 12's -Wuninitialized)
  for (const float v : lanes) *sink += v;
  return static_cast<double>(iters) * kAcc * 16 * 2 / s;  // 16 lanes, 2 flops per FMA
}

/// Median flops/s of `loop`, with the iteration count calibrated to `seconds`.
template <typename Loop>
double measure_peak(Loop loop, double seconds, float* sink) {
  long iters = 1 << 12;
  for (;;) {
    const auto t0 = Clock::now();
    loop(iters, sink);
    const double s = elapsed_s(t0);
    if (s > 0.02) {
      iters = std::max<long>(1, static_cast<long>(static_cast<double>(iters) * seconds / s));
      break;
    }
    iters *= 4;
  }
  std::vector<double> rates;
  for (int r = 0; r < kRepeats; ++r) rates.push_back(loop(iters, sink));
  return median(rates);
}

/// Units per second of `call` (which runs the work `calls` times and returns
/// the seconds it took, `units` per run): the call count is calibrated to last
/// about `seconds`, then the median of kRepeats timed runs.
template <typename Call>
double median_rate(const Call& call, double units, double seconds) {
  long calls = 16;
  while (call(calls) < 0.02) calls *= 4;
  calls = std::max<long>(1, static_cast<long>(static_cast<double>(calls) * seconds / call(calls)));
  std::vector<double> rates;
  for (int r = 0; r < kRepeats; ++r)
    rates.push_back(static_cast<double>(calls) * units / call(calls));
  return median(rates);
}

/// Signals of n inputs x b samples and their pointers, the same for every kernel.
struct Inputs {
  std::vector<std::vector<cf32>> signals;
  std::vector<const cf32*> pointers;
  Inputs(std::size_t n, std::size_t b) : signals(n, std::vector<cf32>(b)), pointers(n) {
    std::mt19937 rng(static_cast<std::uint32_t>(n * 1000 + b));
    std::normal_distribution<float> g(0.0F, 1.0F);
    for (std::size_t i = 0; i < n; ++i) {
      for (auto& v : signals[i]) v = {g(rng), g(rng)};
      pointers[i] = signals[i].data();
    }
  }
};

/// Median complex MAC/s of channel::mix with n inputs of b samples each.
double measure_mix(std::size_t n, std::size_t b, double seconds, float* sink) {
  const Inputs in(n, b);
  const std::vector<const cf32*>& inputs = in.pointers;
  std::vector<cf32> coeffs(n);
  for (std::size_t i = 0; i < n; ++i) {
    coeffs[i] = {0.5F + 0.01F * static_cast<float>(i), -0.25F};  // all nonzero: all active
  }
  std::vector<cf32> out(b);
  const auto call = [&](long calls) {
    const auto t0 = Clock::now();
    for (long c = 0; c < calls; ++c) {
      channel::mix(inputs, coeffs, out);
      // Keep every call observable without adding work inside the kernel.
      *sink += out[static_cast<std::size_t>(c) % b].real();
    }
    return elapsed_s(t0);
  };
  return median_rate(call, static_cast<double>(n * b), seconds);
}

/// Median complex MAC/s of channel::mix_rows: every one of n receivers mixes the
/// same n inputs of b samples (a full tick of an N-node flat channel, each
/// receiver's own input with coefficient 0 as in the engine); counted MACs are
/// the nonzero ones, n * (n - 1) * b per call.
double measure_mix_rows(std::size_t n, std::size_t b, double seconds, float* sink) {
  const Inputs in(n, b);
  const std::vector<const cf32*>& inputs = in.pointers;
  std::vector<cf32> coeffs(n * n);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t i = 0; i < n; ++i)
      coeffs[r * n + i] = r == i ? cf32{} : cf32{0.5F + 0.01F * static_cast<float>(i), -0.25F};
  std::vector<std::vector<cf32>> outs(n, std::vector<cf32>(b));
  std::vector<cf32*> ys(n);
  for (std::size_t r = 0; r < n; ++r) ys[r] = outs[r].data();
  const auto call = [&](long calls) {
    const auto t0 = Clock::now();
    for (long c = 0; c < calls; ++c) {
      channel::mix_rows(inputs, coeffs, ys, b);
      *sink += outs[static_cast<std::size_t>(c) % n][static_cast<std::size_t>(c) % b].real();
    }
    return elapsed_s(t0);
  };
  return median_rate(call, static_cast<double>(n * (n - 1) * b), seconds);
}

/// The fading mixer (channel::mix_ramped_add): n inputs of b samples, each with
/// a coefficient ramping across the block. Complex MAC/s.
double measure_ramped(std::size_t n, std::size_t b, double seconds, float* sink) {
  const Inputs in(n, b);
  std::vector<cf32> start(n), step(n);
  for (std::size_t i = 0; i < n; ++i) {
    start[i] = {0.5F + 0.01F * static_cast<float>(i), -0.25F};
    step[i] = {1e-4F, -2e-4F};
  }
  std::vector<cf32> out(b);
  const auto call = [&](long calls) {
    const auto t0 = Clock::now();
    for (long c = 0; c < calls; ++c) {
      std::fill(out.begin(), out.end(), cf32{});
      channel::mix_ramped_add(in.pointers, start, step, out);
      *sink += out[static_cast<std::size_t>(c) % b].real();
    }
    return elapsed_s(t0);
  };
  return median_rate(call, static_cast<double>(n * b), seconds);
}

/// Bytes per second of reading the same n inputs of b samples once each, in
/// 64-byte vectors (AVX-512 when the CPU has it, as the kernel): the fading
/// mixer reads each input sample once per call (8 bytes per complex MAC) and
/// writes its output once per block, so this bounds what it can reach.
__attribute__((target("avx512f"))) float read_all_avx512(const std::vector<const cf32*>& xs,
                                                         std::size_t b) {
  __m512 acc[4] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps(),
                   _mm512_setzero_ps()};
  for (const cf32* x : xs) {
    const float* f = reinterpret_cast<const float*>(x);
    std::size_t j = 0;
    for (; j + 64 <= 2 * b; j += 64) {
      for (std::size_t k = 0; k < 4; ++k) {
        acc[k] = _mm512_add_ps(acc[k], _mm512_loadu_ps(f + j + 16 * k));
      }
    }
    for (; j + 16 <= 2 * b; j += 16) acc[0] = _mm512_add_ps(acc[0], _mm512_loadu_ps(f + j));
    if (j < 2 * b) {
      const auto mask = static_cast<__mmask16>((1U << (2 * b - j)) - 1);
      acc[1] = _mm512_add_ps(acc[1], _mm512_maskz_loadu_ps(mask, f + j));
    }
  }
  float lanes[16];
  _mm512_storeu_ps(lanes,
                   _mm512_add_ps(_mm512_add_ps(acc[0], acc[1]), _mm512_add_ps(acc[2], acc[3])));
  return lanes[0];
}

float read_all_plain(const std::vector<const cf32*>& xs, std::size_t b) {
  float acc[16] = {};
  for (const cf32* x : xs) {
    const float* f = reinterpret_cast<const float*>(x);
    for (std::size_t j = 0; j < 2 * b; ++j) acc[j % 16] += f[j];
  }
  return acc[0];
}

double measure_read_bandwidth(std::size_t n, std::size_t b, double seconds, float* sink) {
  const Inputs in(n, b);
  const bool wide = __builtin_cpu_supports("avx512f");
  const auto call = [&](long calls) {
    const auto t0 = Clock::now();
    for (long c = 0; c < calls; ++c) {
      *sink += wide ? read_all_avx512(in.pointers, b) : read_all_plain(in.pointers, b);
    }
    return elapsed_s(t0);
  };
  return median_rate(call, static_cast<double>(n * b * sizeof(cf32)), seconds);
}

/// Noise samples per second added by NoiseSource::add_to to `b`-sample blocks,
/// with `kernel`.
double measure_noise(std::size_t b, double seconds, float* sink, channel::NoiseKernel kernel) {
  const channel::NoiseSource noise(1, 0, 1.0F);
  std::vector<cf32> out(b);
  std::uint64_t t = 0;
  const auto call = [&](long calls) {
    const auto t0 = Clock::now();
    for (long c = 0; c < calls; ++c, t += b) {
      noise.add_to(out, t, kernel);
      *sink += out[static_cast<std::size_t>(c) % b].real();
    }
    return elapsed_s(t0);
  };
  return median_rate(call, static_cast<double>(b), seconds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"channel::mix throughput beside the CPU's measured peak (one thread)"};
  std::string csv = "mix_bench.csv";
  double seconds = 0.2;
  std::vector<std::size_t> ns = {6, 15, 32, 64, 128};
  std::vector<std::size_t> blocks = {250, 1000};
  app.add_option("--csv", csv, "Output CSV")->capture_default_str();
  app.add_option("--seconds", seconds, "Seconds per timed run (median of 5)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--nodes", ns, "Active inputs per call")->capture_default_str();
  app.add_option("--blocks", blocks, "Samples per call")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  float sink = 0.0F;
  struct Peak {
    std::string isa;
    double flops;
  };
  std::vector<Peak> peaks;
  peaks.push_back({"sse_mul_add", measure_peak(sse_peak, seconds, &sink)});
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    peaks.push_back({"avx2_fma", measure_peak(avx2_fma_peak, seconds, &sink)});
  }
  if (__builtin_cpu_supports("avx512f")) {
    peaks.push_back({"avx512_fma", measure_peak(avx512_fma_peak, seconds, &sink)});
  }
  const auto best = std::max_element(
      peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.flops < b.flops; });
  const double peak_cmacs = best->flops / kFlopsPerComplexMac;

  std::ofstream out(csv);
  out << "kind,name,n_inputs,block,cmac_per_s,gflops,fraction_of_peak,samples_per_s,"
         "memory_bound_cmac_per_s\n";
  for (const auto& p : peaks) {
    std::printf("peak %-11s %8.2f Gflop/s = %7.3f G complex-MAC/s\n", p.isa.c_str(), p.flops / 1e9,
                p.flops / kFlopsPerComplexMac / 1e9);
    out << "peak," << p.isa << ",,," << p.flops / kFlopsPerComplexMac << "," << p.flops / 1e9 << ","
        << p.flops / best->flops << ",,\n";
  }
  for (const std::size_t b : blocks) {
    for (const std::size_t n : ns) {
      const double r = measure_mix(n, b, seconds, &sink);
      std::printf("mix N=%3zu B=%4zu %7.3f G complex-MAC/s = %5.1f%% of peak (%s)\n", n, b, r / 1e9,
                  100.0 * r / peak_cmacs, best->isa.c_str());
      out << "mix,channel::mix," << n << "," << b << "," << r << ","
          << r * kFlopsPerComplexMac / 1e9 << "," << r / peak_cmacs << ",,\n";
    }
  }
  for (const std::size_t b : blocks) {
    for (const std::size_t n : ns) {
      const double r = measure_mix_rows(n, b, seconds, &sink);
      std::printf("mix_rows N=%3zu B=%4zu %7.3f G complex-MAC/s = %5.1f%% of peak (%s)\n", n, b,
                  r / 1e9, 100.0 * r / peak_cmacs, best->isa.c_str());
      out << "mix,channel::mix_rows," << n << "," << b << "," << r << ","
          << r * kFlopsPerComplexMac / 1e9 << "," << r / peak_cmacs << ",,\n";
    }
  }
  for (const std::size_t b : blocks) {
    for (const std::size_t n : ns) {
      const double r = measure_ramped(n, b, seconds, &sink);
      const double bw = measure_read_bandwidth(n, b, seconds, &sink);
      const double bound = bw / kRampedBytesPerMac;
      const double compute = kRampedFmaFactor * peak_cmacs;
      std::printf(
          "mix_ramped_add N=%3zu B=%4zu %7.3f G complex-MAC/s; memory bound %6.2f G/s (read "
          "%5.1f GB/s / 8 B) = %5.1f%%; compute bound %6.2f G/s = %5.1f%%\n",
          n, b, r / 1e9, bound / 1e9, bw / 1e9, 100.0 * r / bound, compute / 1e9,
          100.0 * r / compute);
      out << "ramped,channel::mix_ramped_add," << n << "," << b << "," << r << ","
          << r * kFlopsPerComplexMac / 1e9 << "," << r / peak_cmacs << ",," << bound << "\n";
    }
  }
  // The noise with each kernel this CPU runs (all give the same bits).
  const std::pair<channel::NoiseKernel, const char*> noise_kernels[] = {
      {channel::NoiseKernel::kScalar, "scalar"},
      {channel::NoiseKernel::kAvx2, "avx2"},
      {channel::NoiseKernel::kAvx512, "avx512"}};
  for (const std::size_t b : blocks) {
    for (const auto& [kernel, name] : noise_kernels) {
      if (!channel::noise_kernel_supported(kernel)) continue;
      const double r = measure_noise(b, seconds, &sink, kernel);
      std::printf("noise %-6s B=%4zu %7.2f M samples/s = %5.2f ns/sample\n", name, b, r / 1e6,
                  1e9 / r);
      out << "noise,channel::NoiseSource " << name << ",," << b << ",,,," << r << ",\n";
    }
  }
  std::printf("mix_bench: wrote %s (checksum %g)\n", csv.c_str(), static_cast<double>(sink));
  return 0;
}
