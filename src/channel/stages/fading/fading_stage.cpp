// The fading stage: its settings, declared once, and the time-varying stage.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "rfsitl/channel/stages/fading.hpp"

namespace rfsitl::channel {

const config::Fields<FadingSettings>& fading_fields() {
  using S = FadingSettings;
  static const auto f =
      config::Fields<S>()
          .choice("model", &S::model,
                  {{"rayleigh", FadingModel::kRayleigh}, {"rician", FadingModel::kRician}},
                  "rayleigh: scattered waves only; rician: plus a line-of-sight wave (k_db)")
          .real("k_db", &S::k_db, "dB", {-30.0, 40.0},
                "rician: K, the line-of-sight power over the scattered power")
          .integer("sinusoids", &S::sinusoids, "", 8, 1024,
                   "M, plane waves summed per link: more is more Gaussian, and costs M "
                   "sines and cosines per link and grid point")
          .real("update_rate_hz", &S::update_rate_hz, "Hz", {10.0, 1e8},
                "gains are computed this often and interpolated linearly between: keep it "
                "well above the Doppler (speed / wavelength)")
          .integer("seed", &S::seed, "", 0, UINT64_MAX,
                   "0: the scenario's seed; otherwise this stage's own draws");
  return f;
}

namespace {

/// The draws of the link-paths evaluated so far, by (tx, rx, path): made on
/// first use and never changed, shared by every thread that evaluates the
/// stage (the engine's receivers, the dashboard's reader). Sharded locks: a
/// look-up holds one shard's lock for a hash-map find. Bounded: past
/// kMaxBytes a link-path's draws are made again at each evaluation (the same
/// values, more time).
class WaveCache {
 public:
  template <typename Draw>
  const fading::Waves* get(std::size_t tx, std::size_t rx, std::size_t path, std::size_t bytes,
                           const Draw& draw) {
    const std::uint64_t key = (std::uint64_t{tx} << 40) ^ (std::uint64_t{rx} << 16) ^ path;
    Shard& shard = shards_[key % kShards];
    std::lock_guard lock(shard.mutex);
    if (const auto it = shard.waves.find(key); it != shard.waves.end()) return it->second.get();
    if (bytes_.fetch_add(bytes, std::memory_order_relaxed) + bytes > kMaxBytes) {
      bytes_.fetch_sub(bytes, std::memory_order_relaxed);
      return nullptr;
    }
    return shard.waves.emplace(key, std::make_unique<const fading::Waves>(draw()))
        .first->second.get();
  }

  /// 192 MiB: every link of 64 nodes with 24 fading taps each at M = 32.
  static constexpr std::size_t kMaxBytes = std::size_t{192} << 20;

 private:
  static constexpr std::size_t kShards = 64;
  struct Shard {
    std::mutex mutex;
    std::unordered_map<std::uint64_t, std::unique_ptr<const fading::Waves>> waves;
  };
  std::array<Shard, kShards> shards_;
  std::atomic<std::size_t> bytes_{0};
};

class FadingStage final : public GainStage {
 public:
  FadingStage(const FadingSettings& s, double carrier_hz, std::uint64_t seed, std::size_t position)
      : s_(s), carrier_hz_(carrier_hz), seed_(seed), position_(position) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    // What one link-path's draws hold (three vectors of M and the map's node).
    const std::size_t bytes = s_.sinusoids * (2 * sizeof(std::complex<double>) + sizeof(double)) +
                              sizeof(fading::Waves) + 64;
    const auto draw = [&] {
      return fading::draw_waves(s_, seed_, position_, link.tx.index, link.rx.index, link.path);
    };
    if (const fading::Waves* w = cache_.get(link.tx.index, link.rx.index, link.path, bytes, draw)) {
      return fading::gain(s_, carrier_hz_, *w, link.tx, link.rx);
    }
    return fading::gain(s_, carrier_hz_, draw(), link.tx, link.rx);
  }

  bool reciprocal() const override { return false; }
  bool time_varying() const override { return true; }
  double update_interval_s() const override { return 1.0 / s_.update_rate_hz; }

 private:
  FadingSettings s_;
  double carrier_hz_;
  std::uint64_t seed_;
  std::size_t position_;
  mutable WaveCache cache_;
};

}  // namespace

ChannelStageComponent fading_component() {
  return {fading_fields().info("channel", "fading",
                               "Rayleigh or Rician fast fading; its Doppler follows the nodes' "
                               "velocities"),
          [](const config::Settings& settings, const StageContext& context) {
            const FadingSettings s = fading_fields().build(settings);
            return std::make_unique<FadingStage>(
                s, context.carrier_hz, s.seed == 0 ? context.seed : s.seed, context.position);
          }};
}

}  // namespace rfsitl::channel
