#include "receiver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>  // before liquid.h
#include <numbers>

#include <liquid/liquid.h>

#include "bit_pipeline.hpp"
#include "fcs.hpp"
#include "ltf_search.hpp"
#include "soft_decoding.hpp"
#include "sts_detector.hpp"
#include "waveform.hpp"

namespace rfsitl::phy::ofdm {
namespace {

// After detection, the first long training symbol T1 starts between 12 and 132
// samples later (the plateau is reached 64..160 samples into the 160-sample
// L-STF, and T1 follows it after the 32-sample GI2).
constexpr unsigned kLtfSearch = 160;
// FFT windows start this many samples early, inside the cyclic prefix, so that
// a short multipath channel's delay spread stays within the prefix; the channel
// estimate absorbs the shift as a linear phase.
constexpr unsigned kTimingBackoff = 3;

constexpr unsigned kMaxLength = 4095;

cf32 rotator(double rad) {
  return {static_cast<float>(std::cos(rad)), static_cast<float>(std::sin(rad))};
}

/// Index into a 64-point FFT output of subcarrier k (-32..31).
unsigned bin(int k) {
  return static_cast<unsigned>((k + 64) % 64);
}

/// Time-domain long training symbol (unnormalized inverse FFT), for locating T1
/// by cross-correlation.
std::array<cf32, kFftSize> long_training_time() {
  std::array<cf32, kFftSize> in{};
  std::array<cf32, kFftSize> out{};
  fftplan ifft = fft_create_plan(kFftSize, in.data(), out.data(), LIQUID_FFT_BACKWARD, 0);
  for (int k = -32; k < 32; ++k) in[bin(k)] = long_training_value(k);
  fft_execute(ifft);
  fft_destroy_plan(ifft);
  return out;
}

class StreamingReceiver final : public OfdmReceiver {
 public:
  explicit StreamingReceiver(Handler handler)
      : handler_(std::move(handler)), viterbi_(make_viterbi_decoder()), ltf_(long_training_time()) {
    fft_ = fft_create_plan(kFftSize, fft_in_.data(), fft_out_.data(), LIQUID_FFT_FORWARD, 0);
    reset();
  }
  ~StreamingReceiver() override { fft_destroy_plan(fft_); }
  StreamingReceiver(const StreamingReceiver&) = delete;
  StreamingReceiver& operator=(const StreamingReceiver&) = delete;

  void push(std::span<const cf32> samples) override {
    std::size_t i = 0;
    while (i < samples.size()) {
      if (state_ == State::kSearch) {
        i += detector_.search(samples.subspan(i));
        if (detector_.detected()) {
          coarse_cfo_ = detector_.coarse_cfo();
          state_ = State::kTraining;
          pkt_.clear();
          needed_ = kLtfSearch + 2 * kFftSize + 8;
        }
      } else {
        const std::size_t take = std::min(samples.size() - i, needed_ - pkt_.size());
        pkt_.insert(pkt_.end(), samples.begin() + static_cast<std::ptrdiff_t>(i),
                    samples.begin() + static_cast<std::ptrdiff_t>(i + take));
        i += take;
        if (pkt_.size() >= needed_) advance();
      }
    }
  }

  bool busy() const override { return state_ != State::kSearch; }

  void reset() override {
    state_ = State::kSearch;
    pkt_.clear();
    detector_.reset();
  }

 private:
  enum class State { kSearch, kTraining, kSignal, kData };

  void advance() {
    switch (state_) {
      case State::kTraining:
        train();
        break;
      case State::kSignal:
        decode_signal();
        break;
      case State::kData:
        decode_data_symbol();
        break;
      case State::kSearch:
        break;
    }
  }

  /// Derotated sample i of the packet buffer (CFO removed).
  void window(std::size_t start, double cfo) {
    cf32 rot = rotator(-cfo * static_cast<double>(start));
    const cf32 step = rotator(-cfo);
    for (unsigned k = 0; k < kFftSize; ++k) {
      fft_in_[k] = pkt_[start + k] * rot;
      rot *= step;
    }
  }

  /// Timing from the long training field, fine CFO, channel and noise estimates.
  void train() {
    const LtfTiming timing = ltf_.find(pkt_, coarse_cfo_, kLtfSearch);
    const std::size_t t1 = timing.t1;
    cfo_ = timing.cfo;
    const std::size_t start = t1 - std::min<std::size_t>(t1, kTimingBackoff);
    std::array<cf32, kFftSize> y1{};
    window(start, cfo_);
    fft_execute(fft_);
    y1 = fft_out_;
    window(start + 64, cfo_);
    fft_execute(fft_);
    double noise = 0.0;
    double signal = 0.0;
    for (int k = -26; k <= 26; ++k) {
      if (k == 0) continue;
      const unsigned b = bin(k);
      channel_[b] = (y1[b] + fft_out_[b]) * 0.5F / long_training_value(k);
      noise += std::norm(y1[b] - fft_out_[b]) / 2.0;
      signal += std::norm(channel_[b]);
    }
    noise_var_ = static_cast<float>(std::max(noise / 52.0, 1e-30));
    snr_db_ = static_cast<float>(10.0 * std::log10(std::max(signal / 52.0, 1e-30) / noise_var_));
    // What equalizing needs per data subcarrier is fixed for the packet: the
    // zero-forcing factor conj(H) / |H|^2 and the post-equalization noise.
    for (unsigned d = 0; d < 48; ++d) {
      const unsigned b = bin(data_subcarriers()[d]);
      const float h2 = std::max(std::norm(channel_[b]), 1e-30F);
      inv_channel_[d] = std::conj(channel_[b]) / h2;
      eq_noise_[d] = noise_var_ / h2;
    }
    next_window_ = start + 2 * kFftSize + kCyclicPrefix;
    symbol_index_ = 0;
    state_ = State::kSignal;
    needed_ = next_window_ + kFftSize;
  }

  /// FFT of the next symbol, equalized and pilot-phase corrected, into eq_.
  void equalize_symbol() {
    window(next_window_, cfo_);
    fft_execute(fft_);
    const int polarity = pilot_polarity(symbol_index_);
    static constexpr float kPilotBase[4] = {1.0F, 1.0F, 1.0F, -1.0F};
    cf32 pilot_sum{};
    for (unsigned p = 0; p < 4; ++p) {
      const unsigned b = bin(pilot_subcarriers()[p]);
      pilot_sum +=
          fft_out_[b] * std::conj(channel_[b] * (kPilotBase[p] * static_cast<float>(polarity)));
    }
    const cf32 derotate =
        std::abs(pilot_sum) > 0.0F ? std::conj(pilot_sum) / std::abs(pilot_sum) : cf32{1.0F, 0.0F};
    for (unsigned d = 0; d < 48; ++d) {
      eq_[d] = fft_out_[bin(data_subcarriers()[d])] * (inv_channel_[d] * derotate);
    }
    ++symbol_index_;
    next_window_ += kSymbolSamples;
  }

  /// Soft bits of the equalized symbol, deinterleaved, appended to llr_.
  void collect_llrs(unsigned n_bpsc) {
    const std::span<float> soft = std::span(soft_).first(48 * n_bpsc);
    demap_symbol(eq_, eq_noise_, n_bpsc, soft);
    const std::size_t at = llr_.size();
    llr_.resize(at + soft.size());
    deinterleave_into(soft, n_bpsc, std::span(llr_).subspan(at));
  }

  void decode_signal() {
    equalize_symbol();
    llr_.clear();
    collect_llrs(1);
    const std::vector<float> half = depuncture(llr_, CodeRate::kHalf, 24);
    const std::vector<std::uint8_t> bits = viterbi_->decode(half, 24, true);
    unsigned parity = 0;
    for (unsigned i = 0; i < 18; ++i) parity ^= bits[i];
    std::uint8_t field = 0;
    for (unsigned i = 0; i < 4; ++i) field = static_cast<std::uint8_t>(field | (bits[i] << i));
    unsigned length = 0;
    for (unsigned i = 0; i < 12; ++i) length |= static_cast<unsigned>(bits[5 + i]) << i;
    const auto rate = rate_from_field(field);
    if (parity != 0 || bits[4] != 0 || !rate || length == 0 || length > kMaxLength) {
      restart_after(next_window_);
      return;
    }
    rate_ = *rate;
    length_ = length;
    symbols_left_ = data_symbol_count(rate_, length_);
    llr_.clear();
    symbols_.clear();
    state_ = State::kData;
    needed_ = next_window_ + kFftSize;
  }

  void decode_data_symbol() {
    equalize_symbol();
    symbols_.insert(symbols_.end(), eq_.begin(), eq_.end());
    collect_llrs(rate_.n_bpsc);
    if (--symbols_left_ > 0) {
      needed_ = next_window_ + kFftSize;
      return;
    }
    const std::size_t n_bits = llr_.size() / rate_.n_cbps * rate_.n_dbps;
    const std::vector<float> half = depuncture(llr_, rate_.coding, n_bits);
    std::vector<std::uint8_t> bits = viterbi_->decode(half, n_bits, false);
    // An all-zero seed cannot come from a transmitter (17.3.5.5): the SERVICE
    // bits were corrupted, and so is the frame.
    const std::uint8_t seed = seed_from_service(std::span(bits).first(7));
    if (seed != 0) scramble(bits, seed);
    DecodedPpdu out;
    out.rate = rate_;
    out.psdu = bits_to_bytes(std::span(bits).subspan(16, 8 * length_));
    out.fcs_ok = seed != 0 && fcs_valid(out.psdu);
    out.snr_db = snr_db_;
    out.cfo_rad_per_sample = static_cast<float>(cfo_);
    out.data_symbols = symbols_;
    // Report before searching the buffered tail, so that decodes stay in order.
    handler_(out);
    restart_after(next_window_ - kCyclicPrefix);
  }

  /// Back to searching; samples already buffered beyond `end` are searched too.
  void restart_after(std::size_t end) {
    std::vector<cf32> rest;
    if (end < pkt_.size()) rest.assign(pkt_.begin() + static_cast<std::ptrdiff_t>(end), pkt_.end());
    reset();
    if (!rest.empty()) push(rest);
  }

  Handler handler_;
  std::unique_ptr<ViterbiDecoder> viterbi_;
  fftplan fft_;
  std::array<cf32, kFftSize> fft_in_{};
  std::array<cf32, kFftSize> fft_out_{};
  LtfSearch ltf_;

  State state_ = State::kSearch;
  StsDetector detector_;
  // Packet.
  std::vector<cf32> pkt_;  // samples since detection
  std::size_t needed_ = 0;
  double coarse_cfo_ = 0.0;
  double cfo_ = 0.0;
  std::array<cf32, kFftSize> channel_{};
  float noise_var_ = 1.0F;
  float snr_db_ = 0.0F;
  std::size_t next_window_ = 0;
  unsigned symbol_index_ = 0;
  RateParams rate_{};
  unsigned length_ = 0;
  unsigned symbols_left_ = 0;
  std::array<cf32, 48> eq_{};
  std::array<float, 48> eq_noise_{};
  std::array<cf32, 48> inv_channel_{};
  std::array<float, 48 * 6> soft_{};
  std::vector<float> llr_;
  std::vector<cf32> symbols_;
};

}  // namespace

std::unique_ptr<OfdmReceiver> make_ofdm_receiver(OfdmReceiver::Handler handler) {
  return std::make_unique<StreamingReceiver>(std::move(handler));
}

}  // namespace rfsitl::phy::ofdm
