#pragma once
/// A radio front end's imperfections, the `impairments` sample stage
/// (`channel.impairments.tx` and `.rx` are its short form): carrier frequency offset, phase
/// noise, I/Q imbalance and DC offset, applied to one node's samples as a chain
/// of pure per-sample steps.
///
///   transmitter: x -> I/Q imbalance -> + DC (LO leakage) -> x e^{j(2 pi f t + phi(t))}
///   receiver:    y -> y e^{j(2 pi f t + phi(t))} -> I/Q imbalance -> + DC
///
/// f is the node's offset (cfo_hz plus its own draw of N(0, cfo_spread_hz^2),
/// so that nodes differ, as their oscillators do); phi a Wiener process, the
/// phase noise of a free-running oscillator, whose single-sideband level at
/// offset f_o is L(f_o) = b / (pi f_o^2) for a linewidth b (valid for f_o >> b),
/// so b = pi f_o^2 10^(L/10) and each sample adds N(0, 2 pi b / fs) to phi.
/// I/Q imbalance with amplitude ratio g (dB) and skew p: y = mu x + nu x*,
/// mu = (1 + g e^{-jp}) / 2, nu = (1 - g e^{jp}) / 2, an image at |nu / mu|^2.
/// DC offset: a constant (1 + j) / sqrt2 times dc_offset in units of the
/// signal's RMS (transmitter: its unit power; receiver: the noise floor's).
///
/// Determinism. t is the absolute sample time; phi at tick boundaries advances
/// on the engine thread every tick for every node (advance()), by Philox draws
/// keyed by the node and the tick, and between them follows a Brownian bridge
/// of per-sample draws keyed by the sample time: a node's impairments do not
/// depend on which ticks its receiver ran, on threads or on observers.
#include <cstdint>
#include <optional>
#include <span>

#include "rfsitl/channel/noise_source.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

struct FrontEndSettings {
  double cfo_hz = 0.0;                 ///< every node's carrier offset
  double cfo_spread_hz = 0.0;          ///< plus a draw per node of this standard deviation
  double phase_noise_dbc_hz = -200.0;  ///< L at phase_noise_offset_hz; -200: none
  double phase_noise_offset_hz = 1e4;  ///< where phase_noise_dbc_hz is given
  double iq_imbalance_db = 0.0;        ///< the Q branch's gain over the I branch's
  double iq_imbalance_deg = 0.0;       ///< the Q branch's skew from 90 degrees
  double dc_offset = 0.0;              ///< in units of the signal's RMS amplitude
};

const config::Fields<FrontEndSettings>& front_end_fields();

/// The self-description of the `impairments` sample stage (kind "sample"),
/// which wraps one FrontEnd per node (channel/sample_stages/impairments).
const config::ComponentInfo& front_end_info();

/// True when the settings change nothing (every node's front end is perfect).
bool is_ideal(const FrontEndSettings& s);

enum class FrontEndSide { kTransmit, kReceive };

/// One node's front end on one side.
class FrontEnd {
 public:
  /// `stream` keeps the draws of different nodes and sides apart.
  FrontEnd(const FrontEndSettings& s, FrontEndSide side, double sample_rate_hz,
           std::size_t tick_samples, std::uint64_t seed, std::uint64_t stream);

  /// The node's carrier offset, Hz (cfo_hz plus its draw).
  double offset_hz() const { return offset_hz_; }

  /// Engine thread, once per tick, every tick, in order: the phase noise's
  /// value at the end of the tick that starts at tick_start.
  void advance(SampleTime tick_start);

  /// Applies the impairments to samples [first_sample, first_sample + x.size())
  /// of the current tick (the last advance()), in place. Thread-safe (const).
  void apply(SampleTime first_sample, std::span<cf32> x) const;

 private:
  void rotate(SampleTime first_sample, std::span<cf32> x) const;
  void distort(std::span<cf32> x) const;

  FrontEndSide side_;
  double fs_;
  std::size_t tick_;
  double offset_hz_;
  double phase_step_sigma_ = 0.0;  // of phi per sample, rad
  std::optional<NoiseSource> per_sample_;
  std::optional<NoiseSource> per_tick_;
  SampleTime tick_start_ = 0;
  double phi_start_ = 0.0;  // phi at tick_start_
  double phi_end_ = 0.0;    // and at the tick's end
  cf32 mu_{1.0F, 0.0F};
  cf32 nu_{};
  cf32 dc_{};
  bool iq_ = false;
};

}  // namespace rfsitl::channel
