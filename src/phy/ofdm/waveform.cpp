#include "waveform.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>  // before liquid.h, so liquid_float_complex is std::complex<float>
#include <stdexcept>

#include <liquid/liquid.h>

#include "bit_pipeline.hpp"

namespace rfsitl::phy::ofdm {
namespace {

constexpr unsigned kDataSubcarriers = 48;
constexpr unsigned kServiceBits = 16;  // 17.3.5.2
constexpr unsigned kTailBits = 6;      // 17.3.5.3
constexpr unsigned kShortSamples = 160;
constexpr unsigned kLongSamples = 160;
constexpr unsigned kLongGuard = 32;  // GI2 of the L-LTF (17.3.3)

constexpr std::array<int, 4> kPilots = {-21, -7, 7, 21};
/// Pilot base values P_{-21,-7,7,21} (17.3.5.10).
constexpr std::array<float, 4> kPilotBase = {1.0F, 1.0F, 1.0F, -1.0F};

constexpr std::array<int, 48> make_data_subcarriers() {
  std::array<int, 48> idx{};
  std::size_t n = 0;
  for (int k = -26; k <= 26; ++k) {
    if (k == 0 || k == -21 || k == -7 || k == 7 || k == 21) continue;
    idx[n++] = k;
  }
  return idx;
}
constexpr std::array<int, 48> kDataIdx = make_data_subcarriers();

/// 17.3.5.10: the pilot polarity sequence p_0..p_126 is the 17.3.5.5 scrambler
/// output for the all-ones initial state, with 0 -> +1 and 1 -> -1.
constexpr std::array<std::int8_t, 127> make_polarity() {
  std::array<std::int8_t, 127> p{};
  unsigned state = 0x7F;
  for (auto& v : p) {
    const unsigned out = ((state >> 6U) ^ (state >> 3U)) & 1U;
    state = ((state << 1U) | out) & 0x7FU;
    v = out != 0 ? std::int8_t{-1} : std::int8_t{1};
  }
  return p;
}
constexpr std::array<std::int8_t, 127> kPolarity = make_polarity();

// clang-format off
/// 17.3.3, short training sequence: S_{-26..26} / (sqrt(13/6) (1 + j)), one
/// line for k = -26..-1, DC, one line for k = 1..26; nonzero every 4th subcarrier.
constexpr std::array<std::int8_t, 53> kShortSigns = {
    0, 0, 1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0,
    0,
    0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
/// 17.3.3, long training sequence: L_{-26..26}, laid out as above.
constexpr std::array<std::int8_t, 53> kLongValues = {
    1, 1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1, 1, 1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1,
    0,
    1, -1, -1, 1, 1, -1, 1, -1, 1, -1, -1, -1, -1, -1, 1, 1, -1, -1, 1, -1, 1, -1, 1, 1, 1, 1};
// clang-format on

/// One OFDM symbol's 64 subcarrier values, indexed by IFFT bin (k mod 64).
using Spectrum = std::array<cf32, kFftSize>;

constexpr std::size_t bin(int k) {
  return static_cast<std::size_t>((k + 64) % 64);
}

/// 64-point inverse DFT with the 1/64 scaling that Annex I's time-domain tables
/// use (e.g. Table I-3 sample 0 = 2 sqrt(13/6) / 64 = 0.046). One plan and its
/// buffers serve every symbol of a PPDU.
class Ifft64 {
 public:
  Ifft64() : plan_(fft_create_plan(kFftSize, in_.data(), out_.data(), LIQUID_FFT_BACKWARD, 0)) {}
  ~Ifft64() { fft_destroy_plan(plan_); }
  Ifft64(const Ifft64&) = delete;
  Ifft64& operator=(const Ifft64&) = delete;

  const Spectrum& run(const Spectrum& freq) {
    in_ = freq;
    fft_execute(plan_);  // liquid's backward FFT is unnormalized
    for (cf32& v : out_) v *= 1.0F / static_cast<float>(kFftSize);
    return out_;
  }

 private:
  Spectrum in_{};
  Spectrum out_{};
  fftplan plan_;
};

/// Adds one field of `length` samples taken from the 64-periodic waveform
/// `period`, starting at phase `offset` (48 for a 16-sample GI, 32 for GI2), at
/// out[start]. Windowed, the field follows the 17.3.2.5 window function with
/// T_TR = 100 ns: at 20 Msps w = 1/2 on the first sample and on one extra sample
/// past the end (the periodic continuation); there it overlaps the next field's
/// first sample, and the two halves add.
void add_field(std::vector<cf32>& out, std::size_t start, const Spectrum& period, unsigned offset,
               unsigned length, bool windowed) {
  const float edge = windowed ? 0.5F : 1.0F;
  out[start] += edge * period[offset % kFftSize];
  for (unsigned n = 1; n < length; ++n) out[start + n] += period[(offset + n) % kFftSize];
  if (windowed) out[start + length] += edge * period[(offset + length) % kFftSize];
}

/// 17.3.5.10: data points on the 48 data subcarriers, pilots p_n P_k on the four
/// pilot subcarriers, zero on DC and the guard subcarriers.
Spectrum symbol_spectrum(std::span<const cf32, kDataSubcarriers> points, unsigned n) {
  Spectrum s{};
  for (std::size_t i = 0; i < kDataSubcarriers; ++i) s[bin(kDataIdx[i])] = points[i];
  const auto p = static_cast<float>(pilot_polarity(n));
  for (std::size_t i = 0; i < kPilots.size(); ++i) s[bin(kPilots[i])] = p * kPilotBase[i];
  return s;
}

/// Maps one interleaved symbol (48 n_bpsc bits) to the 48 data subcarriers.
void map_symbol(std::span<const std::uint8_t> bits, unsigned n_bpsc,
                std::array<cf32, kDataSubcarriers>& points) {
  for (std::size_t i = 0; i < kDataSubcarriers; ++i) {
    points[i] = map_point(bits.subspan(i * n_bpsc, n_bpsc), n_bpsc);
  }
}

Spectrum training_spectrum(cf32 (*value)(int)) {
  Spectrum s{};
  for (int k = -32; k < 32; ++k) s[bin(k)] = value(k);
  return s;
}

/// The DATA field bits before coding (17.3.5.2 - 17.3.5.5): SERVICE (16 zeros),
/// PSDU, 6 tail bits and pad bits up to N_SYM N_DBPS, scrambled, with the tail
/// bits reset to zero after scrambling so that the encoder returns to state 0.
std::vector<std::uint8_t> scrambled_data_bits(std::span<const std::uint8_t> psdu,
                                              const RateParams& rate, std::uint8_t seed) {
  const unsigned n_sym = data_symbol_count(rate, static_cast<unsigned>(psdu.size()));
  std::vector<std::uint8_t> bits(static_cast<std::size_t>(n_sym) * rate.n_dbps, 0);
  const std::vector<std::uint8_t> payload = bytes_to_bits(psdu);
  std::copy(payload.begin(), payload.end(), bits.begin() + kServiceBits);
  scramble(bits, seed);
  const std::size_t tail = kServiceBits + payload.size();
  std::fill_n(bits.begin() + static_cast<std::ptrdiff_t>(tail), kTailBits, std::uint8_t{0});
  return bits;
}

}  // namespace

const std::array<int, 48>& data_subcarriers() {
  return kDataIdx;
}

const std::array<int, 4>& pilot_subcarriers() {
  return kPilots;
}

int pilot_polarity(unsigned n) {
  return kPolarity[n % kPolarity.size()];
}

cf32 short_training_value(int k) {
  if (k < -26 || k > 26) return {0.0F, 0.0F};
  const float a =
      std::sqrt(13.0F / 6.0F) * static_cast<float>(kShortSigns[static_cast<std::size_t>(k + 26)]);
  return {a, a};
}

cf32 long_training_value(int k) {
  if (k < -26 || k > 26) return {0.0F, 0.0F};
  return {static_cast<float>(kLongValues[static_cast<std::size_t>(k + 26)]), 0.0F};
}

std::vector<std::uint8_t> signal_field_bits(const RateParams& rate, unsigned length_bytes) {
  if (length_bytes >= 4096) throw std::invalid_argument("signal_field_bits: LENGTH >= 4096");
  // 17.3.4.1, Figure 17-5: R1..R4 (bits 0-3), reserved (4), LENGTH LSB first
  // (5-16), even parity over bits 0-16 (17), SIGNAL TAIL (18-23).
  std::vector<std::uint8_t> bits(24, 0);
  for (unsigned i = 0; i < 4; ++i) bits[i] = static_cast<std::uint8_t>((rate.rate_field >> i) & 1U);
  for (unsigned i = 0; i < 12; ++i) {
    bits[5 + i] = static_cast<std::uint8_t>((length_bytes >> i) & 1U);
  }
  unsigned parity = 0;
  for (unsigned i = 0; i < 17; ++i) parity ^= bits[i];
  bits[17] = static_cast<std::uint8_t>(parity);
  return bits;
}

unsigned data_symbol_count(const RateParams& rate, unsigned length_bytes) {
  // 17.3.5.4: N_SYM = ceil((16 + 8 LENGTH + 6) / N_DBPS).
  const unsigned n_bits = kServiceBits + 8 * length_bytes + kTailBits;
  return (n_bits + rate.n_dbps - 1) / rate.n_dbps;
}

std::vector<cf32> build_ppdu(std::span<const std::uint8_t> psdu, const RateParams& rate,
                             std::uint8_t scrambler_seed, bool windowed) {
  if (psdu.empty() || psdu.size() > 4095) throw std::invalid_argument("build_ppdu: PSDU size");
  if (scrambler_seed == 0 || scrambler_seed > 127) {
    throw std::invalid_argument("build_ppdu: scrambler seed must be in 1..127");
  }
  const auto length = static_cast<unsigned>(psdu.size());
  const unsigned n_sym = data_symbol_count(rate, length);
  std::vector<cf32> out(kPreambleSamples + kSymbolSamples * (1 + n_sym) + (windowed ? 1 : 0));
  Ifft64 ifft;

  // 17.3.3: L-STF = 10 repetitions of 16 samples (2.5 periods of the 64-point
  // IFFT); L-LTF = GI2 (the last 32 samples) followed by two full periods.
  add_field(out, 0, ifft.run(training_spectrum(short_training_value)), 0, kShortSamples, windowed);
  add_field(out, kShortSamples, ifft.run(training_spectrum(long_training_value)),
            kFftSize - kLongGuard, kLongSamples, windowed);

  // 17.3.4: SIGNAL is BPSK at R = 1/2, not scrambled, pilot polarity p_0.
  std::array<cf32, kDataSubcarriers> points{};
  const std::vector<std::uint8_t> signal_coded =
      convolutional_encode(signal_field_bits(rate, length));
  map_symbol(interleave(signal_coded, 1), 1, points);
  add_field(out, kPreambleSamples, ifft.run(symbol_spectrum(points, 0)), kFftSize - kCyclicPrefix,
            kSymbolSamples, windowed);

  // 17.3.5: DATA symbols 1..N_SYM use pilot polarities p_1..p_N_SYM.
  const std::vector<std::uint8_t> coded =
      puncture(convolutional_encode(scrambled_data_bits(psdu, rate, scrambler_seed)), rate.coding);
  const std::vector<unsigned> perm = interleaver_permutation(rate.n_cbps, rate.n_bpsc);
  std::vector<std::uint8_t> interleaved(rate.n_cbps);
  for (unsigned n = 0; n < n_sym; ++n) {
    const std::size_t first = static_cast<std::size_t>(n) * rate.n_cbps;
    for (unsigned k = 0; k < rate.n_cbps; ++k) interleaved[perm[k]] = coded[first + k];
    map_symbol(interleaved, rate.n_bpsc, points);
    add_field(out, kPreambleSamples + kSymbolSamples * (1 + n),
              ifft.run(symbol_spectrum(points, n + 1)), kFftSize - kCyclicPrefix, kSymbolSamples,
              windowed);
  }
  return out;
}

}  // namespace rfsitl::phy::ofdm
