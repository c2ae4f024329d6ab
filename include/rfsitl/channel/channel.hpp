#pragma once
/// The interference channel as the engine calls it. For each receiver and tick:
/// the sum of the active transmitters' samples through their links (the
/// large-scale coefficients, ramped by the time-varying stages on their grid),
/// plus the receiver's thermal noise, times the front end's fixed gain that puts
/// the noise floor at unit power:
///   y_m[t] = g (sum_{n != m} c_nm(t) x_n[t] + eta_m[t]),  g = 1 / sigma.
/// The gain changes no SNR. It keeps signals where liquid-dsp's detectors work
/// (they have an absolute floor near -100 dBFS, while the paper's path loss puts
/// signals far below it), as a radio's fixed gain stage puts its noise floor
/// well above its ADC's quantization.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/channel/noise_source.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

struct ChannelConfig {
  double noise_variance = 1e-12;  ///< sigma^2, mW (the budget's unit)
  bool shared_noise = false;      ///< one noise stream for every receiver (the paper's flowgraph)
  std::uint64_t seed = 1;         ///< of the noise
  double sample_rate_hz = 1e6;
  std::size_t tick_samples = 250;
};

/// One transmitter on the air this tick: its node and its tick's samples.
struct Transmission {
  std::size_t node = 0;
  const cf32* samples = nullptr;  ///< tick_samples of them
};

class Channel {
 public:
  /// Precondition: budget != nullptr; config.tick_samples > 0.
  Channel(std::size_t nodes, std::shared_ptr<const LinkBudget> budget,
          const GeodeticPosition& origin, const ChannelConfig& config);

  /// The links, kept in step with positions (engine thread).
  ChannelMatrix& matrix() { return matrix_; }
  const ChannelMatrix& matrix() const { return matrix_; }

  /// The front end's fixed gain g = 1 / sigma (that of a -120 dB floor without noise).
  double front_end_gain() const { return gain_; }

  /// What one receiver's receive() works in; one per receiver, never shared
  /// between threads.
  struct Scratch {
    std::vector<const cf32*> inputs;
    std::vector<cf32> coeffs;
    std::vector<std::size_t> links;
    std::vector<cf32> at_next;
    std::vector<cf32> ramp_start;
    std::vector<cf32> ramp_step;
  };

  /// Engine thread, once per tick before receive(): draws the shared noise
  /// (when there is one and some receiver will run).
  void begin_tick(SampleTime tick_start, bool receivers_run);

  /// Receiver m's input for samples [first, tick_samples) of the tick that
  /// starts at tick_start: y.size() == tick_samples - first, and every
  /// transmission's samples are read from its index `first` on. Transmitters
  /// with a zero coefficient and m itself are left out. Thread-safe for
  /// different receivers (const; each with its own scratch).
  void receive(std::size_t m, std::span<const Transmission> active, SampleTime tick_start,
               std::size_t first, std::span<cf32> y, Scratch& scratch) const;

 private:
  void mix_fading(std::size_t m, std::span<const Transmission> active, SampleTime tick_start,
                  std::size_t first, std::span<cf32> y, Scratch& s) const;

  ChannelMatrix matrix_;
  ChannelConfig config_;
  double gain_;
  SampleTime grid_samples_;                        // the fading grid; 0 without time-varying stages
  std::vector<std::optional<NoiseSource>> noise_;  // per receiver, unless shared
  std::optional<NoiseSource> shared_noise_;
  std::vector<cf32> shared_noise_buf_;
};

}  // namespace rfsitl::channel
