/// The built-in (SIMD) Viterbi decoder against libfec's on many random short
/// blocks: block agreement, the size of every disagreement as a near-tie, and
/// the BER of both, per Es/N0 (BPSK in AWGN, rate 1/2, LLR = 4y/N0).
///
///   rfsitl_viterbi_agreement [--blocks N] [--seed S]
///
/// N blocks in all (default 10^6), split evenly over 1, 2, 3, 4 and 6 dB, of
/// 24 ... 200 data bits, alternately terminated and open-ended.
/// tests/unit/viterbi_simd_test.cpp runs the same comparison on fewer blocks.
///
/// "gap" is how close a disagreement is to a tie: the difference of the two
/// decoded paths' exact float metrics (sum of +-LLR over the code bits), in
/// units of the block's mean |LLR|. A clear decision differs by at least ~10
/// such units (free distance 10 at mean confidence).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "phy/ofdm/bit_pipeline.hpp"
#include "phy/ofdm/soft_decoding.hpp"

namespace {

namespace ofdm = rfsitl::phy::ofdm;
using Bits = std::vector<std::uint8_t>;

/// Correlation of the codeword of `bits` with the LLRs: what max-log maximizes.
double path_metric(const Bits& bits, const std::vector<float>& llr) {
  const Bits coded = ofdm::convolutional_encode(bits);
  double m = 0.0;
  for (std::size_t i = 0; i < coded.size(); ++i) m += coded[i] != 0 ? -llr[i] : llr[i];
  return m;
}

struct Tally {
  std::uint64_t blocks = 0;
  std::uint64_t bits = 0;
  std::uint64_t disagreements = 0;
  std::uint64_t simd_errors = 0;
  std::uint64_t libfec_errors = 0;
  double max_gap = 0.0;
};

Tally run(double snr_db, std::uint64_t blocks, std::mt19937_64& rng) {
  auto simd = ofdm::make_viterbi_decoder();
  auto libfec = ofdm::make_libfec_viterbi_decoder();
  const double n0 = std::pow(10.0, -snr_db / 10.0);
  std::normal_distribution<double> noise(0.0, std::sqrt(n0 / 2.0));
  std::uniform_int_distribution<std::size_t> length(24, 200);
  Tally tally;
  Bits bits;
  std::vector<float> llr;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const bool terminated = (b & 1U) != 0;
    bits.resize(length(rng));
    for (auto& bit : bits) bit = static_cast<std::uint8_t>(rng() & 1U);
    if (terminated) std::fill(bits.end() - 6, bits.end(), 0);
    llr.clear();
    double mean = 0.0;
    for (std::uint8_t c : ofdm::convolutional_encode(bits)) {
      const double y = (c != 0 ? -1.0 : 1.0) + noise(rng);
      llr.push_back(static_cast<float>(4.0 * y / n0));
      mean += std::fabs(4.0 * y / n0);
    }
    mean /= static_cast<double>(llr.size());
    const Bits a = simd->decode(llr, bits.size(), terminated);
    const Bits l = libfec->decode(llr, bits.size(), terminated);
    for (std::size_t i = 0; i < bits.size(); ++i) {
      tally.simd_errors += a[i] != bits[i];
      tally.libfec_errors += l[i] != bits[i];
    }
    if (a != l) {
      ++tally.disagreements;
      const double gap = std::fabs(path_metric(a, llr) - path_metric(l, llr)) / mean;
      tally.max_gap = std::max(tally.max_gap, gap);
    }
    ++tally.blocks;
    tally.bits += bits.size();
  }
  return tally;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"SIMD vs libfec Viterbi: agreement and BER per Es/N0"};
  std::uint64_t blocks = 1000000;
  std::uint64_t seed = 1;
  app.add_option("--blocks", blocks, "blocks in all, split over the SNR points");
  app.add_option("--seed", seed, "random seed");
  CLI11_PARSE(app, argc, argv);

  const double snrs[] = {1.0, 2.0, 3.0, 4.0, 6.0};
  std::mt19937_64 rng(seed);
  std::uint64_t total = 0;
  std::uint64_t total_disagreements = 0;
  std::printf("%8s %9s %8s %10s %9s %11s %11s %10s\n", "EsN0_dB", "blocks", "differ", "differ_%",
              "max_gap", "BER_simd", "BER_libfec", "BER_ratio");
  for (double snr : snrs) {
    const Tally t = run(snr, blocks / std::size(snrs), rng);
    const double bits = static_cast<double>(t.bits);
    const double ratio = t.libfec_errors > 0 ? static_cast<double>(t.simd_errors) /
                                                   static_cast<double>(t.libfec_errors)
                                             : 1.0;
    std::printf("%8.1f %9llu %8llu %10.4f %9.3f %11.3e %11.3e %10.3f\n", snr,
                static_cast<unsigned long long>(t.blocks),
                static_cast<unsigned long long>(t.disagreements),
                100.0 * static_cast<double>(t.disagreements) / static_cast<double>(t.blocks),
                t.max_gap, static_cast<double>(t.simd_errors) / bits,
                static_cast<double>(t.libfec_errors) / bits, ratio);
    total += t.blocks;
    total_disagreements += t.disagreements;
  }
  std::printf("all: %llu blocks, %llu differ (%.4f %%)\n", static_cast<unsigned long long>(total),
              static_cast<unsigned long long>(total_disagreements),
              100.0 * static_cast<double>(total_disagreements) / static_cast<double>(total));
  return 0;
}
