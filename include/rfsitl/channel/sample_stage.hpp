#pragma once
/// A sample stage: one effect on a radio's own samples, the second kind of
/// channel stage. Where a channel stage (channel_stage.hpp) gives each link a
/// gain from its geometry, a sample stage acts on one node's samples: every
/// transmitter's before they are mixed (the scenario's `channel.tx_stages`),
/// every receiver's after its mix (`channel.rx_stages`), each list in order.
///
///   x_n -> tx stages -> mix over the links -> + noise -> rx stages -> receiver m
///
/// The receiver's noise is the first receive stage (noise_stage.hpp, built from
/// `channel.noise_*`); `channel.impairments.tx` and `.rx` are short for a
/// leading `impairments` stage on that side. Registered by name
/// (registry/sample_stage_registry.hpp) like every component.
///
/// Units. A receiver's samples are in the front end's units, where its noise
/// floor has unit power (channel.hpp: g = 1 / sigma); a transmitter's have unit
/// power while it sends.
///
/// Determinism. apply() must be a pure function of the node, the absolute
/// sample times and the stage's state after advance(): which ticks a receiver
/// ran, threads and observers must not change its output (randomness keyed by
/// node and sample time, as noise_source.hpp's is).
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/config/settings.hpp"

namespace rfsitl::channel {

enum class SampleSide { kTransmit, kReceive };

class SampleStage {
 public:
  virtual ~SampleStage() = default;

  /// Engine thread, once per tick, every tick, in order, before any apply() of
  /// that tick. `applies` is false when no apply() will follow this tick (no
  /// transmitter on the air, no receiver run): a stage may then skip work that
  /// only apply() needs, but its state must advance as if it had not.
  virtual void advance(SampleTime tick_start, bool applies) {
    (void)tick_start;
    (void)applies;
  }

  /// Node `node`'s samples [first_sample, first_sample + x.size()), absolute
  /// sample times within the current tick (the last advance()), in place.
  /// A transmitter's stages see only the ticks it is on the air (its power
  /// amplifier is off otherwise). Thread-safe for different nodes (const).
  virtual void apply(std::size_t node, SampleTime first_sample, std::span<cf32> x) const = 0;

  /// Receive side: true when skipping a receiver that hears only noise stays
  /// exact with this stage in the chain, i.e. applied to pure noise it gives
  /// nothing a receiver could decode (a gain, a rotation, clipping or
  /// quantization). False (e.g. a stage that injects an interferer of its
  /// own) makes the engine run every receiver every tick.
  virtual bool keeps_skipping_exact() const { return true; }
};

/// A side's stages in the order they apply.
using SampleChain = std::vector<std::unique_ptr<SampleStage>>;

/// What a stage may need beyond its settings.
struct SampleStageContext {
  SampleSide side = SampleSide::kReceive;
  std::size_t nodes = 0;        ///< apply()'s `node` is below this
  double sample_rate_hz = 1e6;  ///< the emulator's (time.sample_rate_hz)
  std::size_t tick_samples = 250;
  std::uint64_t seed = 1;    ///< the scenario's, for stages with random draws
  std::size_t position = 0;  ///< the stage's place in its side's list
  /// Random streams no other stage or node uses: a stage with draws keys node
  /// n's by stream(n) (0 .. 2 nodes - 1 for the first stage of either side).
  std::uint64_t stream(std::size_t node) const {
    return 2 * nodes * position + (side == SampleSide::kReceive ? nodes : 0) + node;
  }
};

/// A registered sample stage: its self-description (kind "sample") and how to
/// build it from checked settings (they passed info.validate()).
struct SampleStageComponent {
  config::ComponentInfo info;
  std::function<std::unique_ptr<SampleStage>(const config::Settings&, const SampleStageContext&)>
      make;
};

}  // namespace rfsitl::channel
