#pragma once
/// The interference channel as the engine calls it. For each receiver and tick:
/// the sum of the active transmitters' samples (each through the transmit
/// sample stages, T) through their links (the large-scale coefficients, ramped
/// by the time-varying stages on their grid), plus the receiver's thermal noise,
/// times the front end's fixed gain that puts the noise floor at unit power,
/// then through the receive sample stages R (sample_stage.hpp):
///   y_m[t] = R_m(g (sum_{n != m} c_nm(t) T_n(x_n)[t] + eta_m[t])),  g = 1 / sigma.
/// The noise is R's first stage (noise_stage.hpp).
/// With dispersive stages (delay, multipath) a link is an impulse response over
/// lags (ChannelMatrix::response), each lag's tap ramped the same way:
///   y_m[t] = g (sum_{n != m} sum_k h_nmk(t) x_n[t - lag_k] + eta_m[t]),
/// so the channel keeps each transmitter's last max_lag() samples, and a
/// transmission's tail reaches receivers in the ticks after it ended.
/// The gain changes no SNR. It keeps signals where liquid-dsp's detectors work
/// (they have an absolute floor near -100 dBFS, while the paper's path loss puts
/// signals far below it), as a radio's fixed gain stage puts its noise floor
/// well above its ADC's quantization.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/channel/radio_tuning.hpp"
#include "rfsitl/channel/sample_stage.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

struct ChannelConfig {
  double noise_variance = 1e-12;  ///< sigma^2, mW (the budget's unit)
  bool shared_noise = false;      ///< one noise stream for every receiver (the paper's flowgraph)
  std::uint64_t seed = 1;         ///< of the noise
  double sample_rate_hz = 1e6;
  std::size_t tick_samples = 250;
  /// The centre of the sample grid: a radio tuned here needs no frequency
  /// shift (every radio is, until tune()).
  double carrier_hz = 2.4e9;
};

/// One transmitter on the air this tick: its node and its tick's samples
/// (tick_samples of them: its signal, then zeros if its frame ended).
struct Transmission {
  std::size_t node = 0;
  const cf32* samples = nullptr;  ///< tick_samples of them
};

class Channel {
 public:
  /// Precondition: budget != nullptr; config.tick_samples > 0. `transmit`
  /// and `receive` are the sample stages of every transmitter and receiver,
  /// in order (the noise goes before `receive`'s).
  Channel(std::size_t nodes, std::shared_ptr<const LinkBudget> budget,
          const GeodeticPosition& origin, const ChannelConfig& config, SampleChain transmit = {},
          SampleChain receive = {});

  /// The links, kept in step with positions (engine thread).
  ChannelMatrix& matrix() { return matrix_; }
  const ChannelMatrix& matrix() const { return matrix_; }

  /// The front end's fixed gain g = 1 / sigma (that of a -120 dB floor without noise).
  double front_end_gain() const { return gain_; }

  /// False when a receive stage makes skipping receivers that hear only noise
  /// inexact (SampleStage::keeps_skipping_exact): the engine then runs them all.
  bool skipping_exact() const { return skipping_exact_; }

  /// What one receiver's receive() works in; one per receiver, never shared
  /// between threads.
  struct Scratch {
    std::vector<const cf32*> inputs;
    std::vector<cf32> coeffs;
    std::vector<std::size_t> links;  // transmitters heard
    std::vector<const cf32*> bases;  // each input at the tick's first sample
    std::vector<cf32> at_next;
    std::vector<cf32> ramp_start;
    std::vector<cf32> ramp_step;
    std::vector<std::complex<double>> path_fading;
    std::vector<cf32> path_factor;
  };

  /// Engine thread, between ticks: node `node`'s radio is now at `tuning`,
  /// from the next on_air() on. Until the first call every radio shares one
  /// band (config.carrier_hz, the whole sample rate) and the channel mixes
  /// exactly as without this call; after it, each link is in band (shifted
  /// by its offset), leaking (noise of the power its mask puts in the
  /// receiver's band) or out of band (not heard), and the matrix's
  /// band_gain() says how much of each link's power arrives.
  void tune(std::size_t node, const RadioTuning& tuning);

  /// What receiver `rx` makes of transmitter `tx` (in band when no radio was tuned).
  LinkBand band(std::size_t tx, std::size_t rx) const {
    return bands_.empty() ? LinkBand{} : bands_[rx * tunings_.size() + tx];
  }

  /// Engine thread, once per tick, every tick, before hears_signal() and
  /// receive(): the transmitters on the air in the tick that starts at
  /// tick_start. `active` must stay valid until the tick's last receive().
  /// The transmit stages are applied here (to copies).
  void on_air(SampleTime tick_start, std::span<const Transmission> active);

  /// Engine thread, once per tick, every tick, after on_air() and before
  /// receive(): advances the receive stages (the shared noise is drawn when
  /// some receiver will run).
  void begin_tick(SampleTime tick_start, bool receivers_run);

  /// Whether some other node's signal reaches receiver m in this tick (a
  /// transmission now, or the tail of an earlier one through a delayed path):
  /// without it m's input is noise alone. Thread-safe (const).
  bool hears_signal(std::size_t m) const;

  /// Receiver m's input for samples [first, tick_samples) of this tick (the one
  /// on_air() was told of): y.size() == tick_samples - first. Transmitters with
  /// a zero coefficient and m itself are left out. Thread-safe for different
  /// receivers (const; each with its own scratch).
  void receive(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& scratch) const;

  /// Whether receive_together() may be used this tick: a flat channel without
  /// time-varying stages and at least `min_inputs` transmitters on the air
  /// (below that the inputs fit in L1 and receive() mixes as fast).
  bool mixes_together(std::size_t min_inputs) const;

  /// receive(m, 0, ys[j], scratch) for every m = ms[j] at once, bit for bit the
  /// same, with each transmitter's samples read once for all of them
  /// (mix_rows). Preconditions: mixes_together() this tick; ms.size() ==
  /// ys.size() <= kMaxTogether; each ys[j] has tick_samples samples and overlaps
  /// no other. Thread-safe for disjoint sets of receivers.
  static constexpr std::size_t kMaxTogether = 4;
  void receive_together(std::span<const std::size_t> ms, std::span<cf32* const> ys,
                        Scratch& scratch) const;

 private:
  /// Receiver m's receive stages (its noise first), after its mix.
  void finish(std::size_t m, std::size_t first, std::span<cf32> y) const;
  void mix_flat(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const;
  void gather_lags(std::size_t m, std::size_t first, bool with_taps, Scratch& s) const;
  /// Adds the inputs s.bases[j] (at the tick's first sample) times coefficients
  /// that fill_at(t, out) gives at each grid time t, ramped between grid points.
  template <typename FillAt>
  void mix_ramped(std::size_t first, std::span<cf32> y, Scratch& s, const FillAt& fill_at) const;
  void mix_fading(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const;
  void mix_fading_dispersive(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const;
  bool tail_reaches(std::size_t n, std::size_t m, SampleTime from) const;
  /// Whether n's signal is mixed into m's input (in band, or no radio tuned).
  bool in_band(std::size_t n, std::size_t m) const {
    return bands_.empty() || bands_[m * tunings_.size() + n].relation == BandRelation::kInBand;
  }
  /// Whether n reaches m at all (in band or leaking).
  bool reaches(std::size_t n, std::size_t m) const {
    return bands_.empty() || bands_[m * tunings_.size() + n].relation != BandRelation::kOutOfBand;
  }
  /// Tuned radios: each active transmitter off the grid's centre shifted to
  /// its frequency (a copy), and each one's power this tick for its leakage.
  std::span<const Transmission> shift_transmitters(SampleTime tick_start,
                                                   std::span<const Transmission> active);
  /// Tuned radios, after m's mix and before its noise: the mix brought from
  /// the grid's centre to m's frequency, and the noise of what leaks into m's band.
  void arrive_in_band(std::size_t m, std::size_t first, std::span<cf32> y) const;
  void keep_history(SampleTime tick_start, std::span<const Transmission> active);

  ChannelMatrix matrix_;
  ChannelConfig config_;
  double gain_;
  SampleTime grid_samples_;  // the fading grid; 0 without time-varying stages
  SampleChain transmit_;
  SampleChain receive_;  // the noise (if any) first
  bool skipping_exact_ = true;

  // This tick (on_air()).
  SampleTime tick_start_ = 0;
  std::span<const Transmission> active_;
  // Dispersive links: each transmitter's samples [tick_start_ - history_len_,
  // tick_start_ + tick_samples) in history_[n], zeros where it was silent; the
  // end of its latest signal (one past its last active tick); and the nodes
  // whose history is not all zeros, in order.
  std::size_t history_len_ = 0;
  std::vector<std::vector<cf32>> history_;
  std::vector<SampleTime> signal_end_;
  std::vector<std::size_t> audible_;
  std::vector<const cf32*> transmitting_;  // keep_history's, by node

  // Tuned radios (tune()): each node's tuning, cycles per sample of its tx and
  // rx frequencies from the grid's centre, every link's band (row-major by
  // receiver, as the matrix), this tick's transmitters shifted to their
  // frequencies, and each one's mean power this tick. All empty until tune().
  std::vector<RadioTuning> tunings_;
  std::vector<double> tx_cycles_;
  std::vector<double> rx_cycles_;
  std::vector<LinkBand> bands_;
  std::vector<std::vector<cf32>> shifted_;
  std::vector<Transmission> shifted_active_;
  std::vector<float> tx_power_;

  // The transmitters' samples through the transmit stages (when there are any).
  std::vector<std::vector<cf32>> staged_;
  std::vector<Transmission> staged_active_;
};

}  // namespace rfsitl::channel
