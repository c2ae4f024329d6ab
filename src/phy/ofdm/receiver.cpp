#include "rfsitl/phy/ofdm/receiver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>  // before liquid.h
#include <numbers>

#include <liquid/liquid.h>

#include "rfsitl/phy/ofdm/bit_pipeline.hpp"
#include "rfsitl/phy/ofdm/fcs.hpp"
#include "rfsitl/phy/ofdm/soft_decoding.hpp"
#include "rfsitl/phy/ofdm/waveform.hpp"

namespace rfsitl::phy::ofdm {
namespace {

// Packet detection (delay-and-correlate on the 16-sample periodic L-STF):
// M = |sum x[n-16] x*[n]| / sum |x[n]|^2 over a window of kWindow samples is
// about 1 / sqrt(kWindow) on noise and S / (S + N) on the L-STF. A packet is
// declared when M stays above kThreshold for kPlateau consecutive samples
// (about 0 dB SNR and up).
constexpr unsigned kLag = 16;
constexpr unsigned kWindow = 48;
constexpr double kThreshold = 0.55;
constexpr unsigned kPlateau = 24;

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

class StreamingReceiver final : public OfdmReceiver {
 public:
  explicit StreamingReceiver(Handler handler)
      : handler_(std::move(handler)), viterbi_(make_viterbi_decoder()) {
    fft_ = fft_create_plan(kFftSize, fft_in_.data(), fft_out_.data(), LIQUID_FFT_FORWARD, 0);
    // Time-domain long training symbol, for locating T1 by cross-correlation.
    fftplan ifft =
        fft_create_plan(kFftSize, fft_in_.data(), fft_out_.data(), LIQUID_FFT_BACKWARD, 0);
    for (int k = -32; k < 32; ++k) fft_in_[bin(k)] = long_training_value(k);
    fft_execute(ifft);
    fft_destroy_plan(ifft);
    std::copy(fft_out_.begin(), fft_out_.end(), ltf_time_.begin());
    reset();
  }
  ~StreamingReceiver() override { fft_destroy_plan(fft_); }
  StreamingReceiver(const StreamingReceiver&) = delete;
  StreamingReceiver& operator=(const StreamingReceiver&) = delete;

  void push(std::span<const cf32> samples) override {
    std::size_t i = 0;
    while (i < samples.size()) {
      if (state_ == State::kSearch) {
        i += search(samples.subspan(i));
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
    delay_.fill(cf32{});
    prods_.fill({});
    powers_.fill(0.0);
    sum_prod_ = {};
    sum_pow_ = 0.0;
    pos_ = 0;
    plateau_ = 0;
    filled_ = 0;
  }

 private:
  enum class State { kSearch, kTraining, kSignal, kData };

  /// Runs the detector over `x`; returns how many samples it consumed (all of
  /// them, or up to and including the one that completed a detection).
  std::size_t search(std::span<const cf32> x) {
    for (std::size_t n = 0; n < x.size(); ++n) {
      const cf32 s = x[n];
      const auto slot = static_cast<unsigned>(pos_ % kLag);
      const std::complex<double> older = delay_[slot];
      const std::complex<double> prod = older * std::conj(std::complex<double>(s));
      delay_[slot] = s;
      const auto w = static_cast<unsigned>(pos_ % kWindow);
      sum_prod_ += prod - prods_[w];
      const double pw = std::norm(std::complex<double>(s));
      sum_pow_ += pw - powers_[w];
      prods_[w] = prod;
      powers_[w] = pw;
      ++pos_;
      if (filled_ < kWindow + kLag) {
        ++filled_;
        continue;
      }
      const bool above =
          sum_pow_ > 0.0 && std::norm(sum_prod_) > kThreshold * kThreshold * sum_pow_ * sum_pow_;
      plateau_ = above ? plateau_ + 1 : 0;
      if (plateau_ >= kPlateau) {
        coarse_cfo_ = -std::arg(sum_prod_) / kLag;
        state_ = State::kTraining;
        pkt_.clear();
        needed_ = kLtfSearch + 2 * kFftSize + 8;
        return n + 1;
      }
    }
    return x.size();
  }

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

  std::complex<double> ltf_correlation(std::size_t m) const {
    std::complex<double> acc;
    cf32 rot = rotator(-coarse_cfo_ * static_cast<double>(m));
    const cf32 step = rotator(-coarse_cfo_);
    for (unsigned k = 0; k < kFftSize; ++k) {
      acc += std::complex<double>(pkt_[m + k] * rot * std::conj(ltf_time_[k]));
      rot *= step;
    }
    return acc;
  }

  /// Timing from the long training field, fine CFO, channel and noise estimates.
  void train() {
    double best = -1.0;
    std::size_t t1 = 0;
    for (std::size_t m = 0; m + 2 * kFftSize <= pkt_.size() && m <= kLtfSearch; ++m) {
      const double metric = std::abs(ltf_correlation(m)) + std::abs(ltf_correlation(m + 64));
      if (metric > best) {
        best = metric;
        t1 = m;
      }
    }
    // Residual CFO from the two repetitions T1, T2 (after the coarse correction).
    std::complex<double> f;
    for (unsigned k = 0; k < kFftSize; ++k) {
      const double a = coarse_cfo_ * static_cast<double>(t1 + k);
      const double b = coarse_cfo_ * static_cast<double>(t1 + 64 + k);
      f += std::complex<double>(pkt_[t1 + k] * rotator(-a)) *
           std::conj(std::complex<double>(pkt_[t1 + 64 + k] * rotator(-b)));
    }
    cfo_ = coarse_cfo_ - std::arg(f) / 64.0;
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
      const unsigned b = bin(data_subcarriers()[d]);
      const float h2 = std::max(std::norm(channel_[b]), 1e-30F);
      eq_[d] = fft_out_[b] * std::conj(channel_[b]) / h2 * derotate;
      eq_noise_[d] = noise_var_ / h2;
    }
    ++symbol_index_;
    next_window_ += kSymbolSamples;
  }

  /// Soft bits of the equalized symbol, deinterleaved, appended to llr_.
  void collect_llrs(unsigned n_bpsc) {
    soft_.resize(48 * n_bpsc);
    for (unsigned d = 0; d < 48; ++d) {
      demap_soft(eq_[d], n_bpsc, eq_noise_[d], std::span<float>(soft_).subspan(d * n_bpsc, n_bpsc));
    }
    const std::vector<float> deint = deinterleave(soft_, n_bpsc);
    llr_.insert(llr_.end(), deint.begin(), deint.end());
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
  std::array<cf32, kFftSize> ltf_time_{};

  State state_ = State::kSearch;
  // Detector.
  std::array<cf32, kLag> delay_{};
  std::array<std::complex<double>, kWindow> prods_{};
  std::array<double, kWindow> powers_{};
  std::complex<double> sum_prod_;
  double sum_pow_ = 0.0;
  std::uint64_t pos_ = 0;
  unsigned plateau_ = 0;
  unsigned filled_ = 0;
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
  std::vector<float> soft_;
  std::vector<float> llr_;
  std::vector<cf32> symbols_;
};

}  // namespace

std::unique_ptr<OfdmReceiver> make_ofdm_receiver(OfdmReceiver::Handler handler) {
  return std::make_unique<StreamingReceiver>(std::move(handler));
}

}  // namespace rfsitl::phy::ofdm
