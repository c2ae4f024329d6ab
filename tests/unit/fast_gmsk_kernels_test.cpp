/// The fast GMSK receiver's vectorised paths against its scalar reference: the
/// kernels bit for bit on random inputs, and whole receivers on random frames
/// in noise at several SNRs (decoded bytes, soft symbols, RSSI, EVM and the
/// detect/sync state after every block, all identical).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "fast_gmsk_test_support.hpp"
#include "phy/gmsk/frame_receiver.hpp"
#include "phy/gmsk/gmsk_pulse.hpp"
#include "phy/gmsk/receiver_kernels.hpp"

namespace rfsitl::phy {
namespace {

using namespace fast_gmsk_test;
using gmsk::ReceiverKernels;

std::vector<float> random_floats(std::size_t n, std::mt19937& rng) {
  std::normal_distribution<float> g(0.0F, 1.0F);
  std::vector<float> v(n);
  for (float& x : v) x = g(rng);
  return v;
}

/// The same floats, bit for bit (so -0 differs from +0).
void expect_same_bits(const std::vector<float>& a, const std::vector<float>& b, const char* what,
                      const ReceiverKernels& k) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(a[i]), std::bit_cast<std::uint32_t>(b[i]))
        << what << " of " << k.name << " at " << i << ": " << a[i] << " vs " << b[i];
  }
}

TEST(FastGmskKernels, EveryVersionGivesTheReferenceBitsForAnyLengthAndStride) {
  const ReceiverKernels& ref = gmsk::reference_kernels();
  ASSERT_GE(gmsk::supported_kernels().size(), 2U);  // the reference and SSE2 at least
  std::mt19937 rng(5);
  for (const std::size_t n : {1U, 7U, 16U, 33U, 64U}) {
    for (const std::size_t stride : {2U, 3U, 8U}) {
      const std::size_t len = 4 * stride - 1;  // C0's length at k = stride
      const std::vector<float> in = random_floats(2 * n + 2 * len, rng);
      const std::vector<float> taps = random_floats(len, rng);
      const std::vector<float> x = random_floats(n + 31 * stride, rng);
      const std::vector<float> y = random_floats(n + 31 * stride, rng);
      const std::vector<float> rr = random_floats(32, rng);
      const std::vector<float> ri = random_floats(32, rng);
      std::vector<float> want_mf(2 * n);
      std::vector<float> want_re(n);
      std::vector<float> want_im(n);
      std::vector<float> want_e(n);
      ref.matched_filter(in.data(), taps.data(), len, 2 * n, want_mf.data());
      ref.correlate(x.data(), y.data(), stride, rr.data(), ri.data(), n, want_re.data(),
                    want_im.data(), want_e.data());
      for (const ReceiverKernels* k : gmsk::supported_kernels()) {
        std::vector<float> mf(2 * n);
        std::vector<float> re(n);
        std::vector<float> im(n);
        std::vector<float> e(n);
        k->matched_filter(in.data(), taps.data(), len, 2 * n, mf.data());
        k->correlate(x.data(), y.data(), stride, rr.data(), ri.data(), n, re.data(), im.data(),
                     e.data());
        expect_same_bits(mf, want_mf, "matched filter", *k);
        expect_same_bits(re, want_re, "correlation re", *k);
        expect_same_bits(im, want_im, "correlation im", *k);
        expect_same_bits(e, want_e, "energy", *k);
      }
    }
  }
}

/// Everything a receiver reports, floats as bits.
struct Decode {
  std::uint32_t src = 0;
  std::uint32_t dst = 0;
  std::uint32_t serial = 0;
  bool header_valid = false;
  bool payload_valid = false;
  std::vector<std::uint8_t> payload;
  std::uint32_t rssi = 0;
  std::uint32_t evm = 0;
  std::vector<std::uint64_t> symbols;
  bool operator==(const Decode&) const = default;
};

class Recorder final : public RxHandler {
 public:
  void on_rx(const RxEvent& ev) override {
    Decode d{ev.tag.src,
             ev.tag.dst,
             ev.tag.serial,
             ev.header_valid,
             ev.payload_valid,
             {ev.payload.begin(), ev.payload.end()},
             std::bit_cast<std::uint32_t>(ev.rssi_db),
             std::bit_cast<std::uint32_t>(ev.evm_db),
             {}};
    for (const cf32 z : ev.symbols) d.symbols.push_back(std::bit_cast<std::uint64_t>(z));
    decodes.push_back(std::move(d));
  }
  std::vector<Decode> decodes;
};

/// Random frames (random payload sizes, gaps and carrier phases) at unit
/// power, all turned by a small frequency offset, in complex noise of `noise_power`.
std::vector<cf32> random_air(unsigned k, double noise_power, std::uint32_t seed) {
  std::mt19937 rng(seed);
  auto tx = make(k);
  std::vector<cf32> air;
  std::size_t at = std::uniform_int_distribution<std::size_t>(0, 500)(rng);
  for (std::uint32_t f = 0; f < 10; ++f) {
    const std::size_t bytes = std::uniform_int_distribution<std::size_t>(0, 120)(rng);
    at += put_frame(*tx, FrameTag{1, 2, f}, make_payload(bytes, seed + f), air, at,
                    std::uniform_real_distribution<float>(0.0F, 6.28F)(rng));
    at += std::uniform_int_distribution<std::size_t>(0, 600)(rng);
  }
  air.resize(at);
  const float offset = std::uniform_real_distribution<float>(-2e-3F, 2e-3F)(rng);
  for (std::size_t i = 0; i < air.size(); ++i) {
    air[i] *= std::polar(1.0F, offset * static_cast<float>(i));
  }
  add_noise(air, noise_power, seed + 100);
  return air;
}

TEST(FastGmskKernels, ReceiversDecideAsTheScalarReferenceOnRandomFramesInNoise) {
  std::size_t valid = 0;
  std::size_t failed = 0;  // decodes that failed a CRC
  std::size_t frames = 0;
  for (const unsigned k : {2U, 4U, 8U}) {
    FastGmskSettings s;
    s.samples_per_symbol = k;
    const gmsk::GmskPulse pulse = gmsk::make_gmsk_pulse(k, s.bandwidth_time, s.filter_span_symbols);
    for (const double snr_db : {-4.0, 0.0, 3.0, 6.0, 20.0}) {
      // Per-sample SNR at k = 2, as the PHY's sensitivity; the same Eb/N0 at k = 4.
      const double noise_power = std::pow(10.0, -snr_db / 10.0) * k / 2.0;
      const auto seed = static_cast<std::uint32_t>(1000 * k + 10 * (snr_db + 10));
      const std::vector<cf32> air = random_air(k, noise_power, seed);
      frames += 10;

      // The reference: scalar kernels, one sample at a time (the receiver's
      // block paths degenerate to the sample-by-sample state machine).
      gmsk::FrameReceiver ref(pulse, s.max_payload_bytes, gmsk::reference_kernels());
      Recorder want;
      std::vector<bool> busy_after(air.size());
      for (std::size_t i = 0; i < air.size(); ++i) {
        ref.push(std::span(air).subspan(i, 1), want);
        busy_after[i] = ref.busy();
      }
      for (const Decode& d : want.decodes) (d.payload_valid ? valid : failed) += 1;

      for (const ReceiverKernels* kernels : gmsk::supported_kernels()) {
        gmsk::FrameReceiver rx(pulse, s.max_payload_bytes, *kernels);
        Recorder got;
        std::mt19937 rng(seed);
        std::uniform_int_distribution<std::size_t> chunk(1, 400);
        for (std::size_t off = 0; off < air.size();) {
          const std::size_t n = std::min(chunk(rng), air.size() - off);
          rx.push(std::span(air).subspan(off, n), got);
          off += n;
          ASSERT_EQ(rx.busy(), busy_after[off - 1])
              << kernels->name << " k=" << k << " snr=" << snr_db << " after " << off;
        }
        ASSERT_EQ(got.decodes.size(), want.decodes.size())
            << kernels->name << " k=" << k << " snr=" << snr_db;
        for (std::size_t i = 0; i < want.decodes.size(); ++i) {
          EXPECT_TRUE(got.decodes[i] == want.decodes[i])
              << kernels->name << " k=" << k << " snr=" << snr_db << " decode " << i;
        }
      }
    }
  }
  // The SNRs span the whole curve: frames decoded and frames lost to noise.
  EXPECT_GT(valid, frames / 3);
  EXPECT_LT(valid, frames);
  EXPECT_GT(failed, 0U);
}

}  // namespace
}  // namespace rfsitl::phy
