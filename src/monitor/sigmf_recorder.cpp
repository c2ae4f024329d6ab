#include "rfsitl/monitor/sigmf_recorder.hpp"

#include "rfsitl/common/build_version.hpp"
#include "rfsitl/monitor/json_text.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

namespace rfsitl::monitor {
namespace {

using Json = nlohmann::ordered_json;

constexpr std::size_t kBytesPerSample = 8;  // cf32_le: float32 I, float32 Q

double round_to(double v, double step) {
  return std::round(v / step) * step;
}

/// One frame on the air during the window, with what became of it.
struct AirFrame {
  std::uint32_t serial = 0;
  NodeId src = 0;
  NodeId dst = 0;
  NodeId sender = 0;  ///< the transmitting node's id
  SampleTime start = 0;
  SampleTime length = 0;
  std::string phy;
  unsigned rate_mbps = 0;
  enum class Outcome { kPending, kDelivered, kLost } outcome = Outcome::kPending;
  std::optional<engine::LossReason> reason;
  std::optional<double> snr_db;  ///< at the receiver its final outcome concerns
  /// Receivers (ids) that decoded it and handed it to their agent, with their SNR.
  std::vector<std::pair<NodeId, std::optional<double>>> received_by;
};

/// Contiguous run of recorded samples: data samples [sample_start, +count)
/// are virtual samples [global_index, +count).
struct Segment {
  std::uint64_t sample_start = 0;
  SampleTime global_index = 0;
  std::uint64_t count = 0;
};

struct Channel {
  NodeId id = 0;
  std::size_t index = 0;
  std::string data_path;
  std::string meta_path;
  std::FILE* data = nullptr;
  std::uint64_t written = 0;
  std::uint64_t limit = 0;  ///< samples allowed by max_bytes
  std::vector<Segment> segments;
  bool truncated = false;
  std::string error;  ///< why writing the data stopped early; "" while it works
  bool meta_written = false;
  std::atomic<bool> done{false};  ///< no more samples wanted
};

class SigmfRecorderImpl final : public SigmfRecorder {
 public:
  SigmfRecorderImpl(const SigmfSettings& s, const scenario::Scenario& sc)
      : settings_(s),
        fs_(sc.timing.sample_rate_hz),
        scenario_name_(sc.name),
        seed_(sc.seed),
        tick_samples_(sc.timing.tick_samples),
        noise_variance_(sc.channel.noise_variance),
        slot_of_(sc.nodes.size(), -1) {
    if (!(fs_ > 0.0)) throw std::runtime_error("sigmf: the sample rate must be positive");
    if (!(s.duration_s > 0.0) || s.start_s < 0.0) {
      throw std::runtime_error("sigmf: the window must start at >= 0 s and last > 0 s");
    }
    window_start_ = static_cast<SampleTime>(std::llround(s.start_s * fs_));
    window_end_ = window_start_ + std::max<SampleTime>(1, std::llround(s.duration_s * fs_));
    for (std::size_t i = 0; i < sc.nodes.size(); ++i) ids_.push_back(sc.nodes[i].id);

    std::vector<NodeId> wanted;
    for (const NodeId id : s.nodes) {
      if (std::find(wanted.begin(), wanted.end(), id) == wanted.end()) wanted.push_back(id);
    }
    std::vector<std::size_t> indices;
    for (const NodeId id : wanted) {
      const auto it = std::find(ids_.begin(), ids_.end(), id);
      if (it == ids_.end()) {
        throw std::runtime_error("sigmf: node " + std::to_string(id) + " is not in the scenario");
      }
      indices.push_back(static_cast<std::size_t>(it - ids_.begin()));
    }
    std::error_code ec;
    std::filesystem::create_directories(s.directory, ec);
    if (ec || !std::filesystem::is_directory(s.directory)) {
      throw std::runtime_error("sigmf: cannot create directory " + s.directory + ": " +
                               (ec ? ec.message() : std::string("not a directory")));
    }
    channels_ = std::vector<Channel>(wanted.size());
    for (std::size_t k = 0; k < wanted.size(); ++k) {
      Channel& c = channels_[k];
      c.id = wanted[k];
      c.index = indices[k];
      const std::string base =
          (std::filesystem::path(s.directory) / ("node" + std::to_string(c.id))).string();
      c.data_path = base + ".sigmf-data";
      c.meta_path = base + ".sigmf-meta";
      c.limit = s.max_bytes / kBytesPerSample;
      c.data = std::fopen(c.data_path.c_str(), "wb");
      if (c.data == nullptr) {
        const std::string why = std::strerror(errno);
        close_all();
        throw std::runtime_error("sigmf: cannot open " + c.data_path + ": " + why);
      }
      std::setvbuf(c.data, nullptr, _IOFBF, 1 << 18);
      slot_of_[c.index] = static_cast<int>(k);
    }
  }

  ~SigmfRecorderImpl() override {
    finish();
    close_all();
  }

  bool wants_samples(std::size_t node, SampleTime tick_start,
                     std::size_t tick_samples) const override {
    if (node >= slot_of_.size() || slot_of_[node] < 0) return false;
    // Only ticks that overlap the window: before it the receiver may skip silence.
    const SampleTime tick_end = tick_start + static_cast<SampleTime>(tick_samples);
    if (tick_end <= window_start_ || tick_start >= window_end_) return false;
    return !channels_[static_cast<std::size_t>(slot_of_[node])].done.load(
        std::memory_order_relaxed);
  }

  void on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) override {
    if (node >= slot_of_.size() || slot_of_[node] < 0) return;
    Channel& c = channels_[static_cast<std::size_t>(slot_of_[node])];
    if (c.done.load(std::memory_order_relaxed)) return;
    const SampleTime end = time + static_cast<SampleTime>(samples.size());
    const SampleTime lo = std::max(time, window_start_);
    const SampleTime hi = std::min(end, window_end_);
    std::lock_guard lock(mutex_);
    if (finished_) return;
    if (lo < hi) {
      if (c.segments.empty() ||
          c.segments.back().global_index + static_cast<SampleTime>(c.segments.back().count) != lo) {
        c.segments.push_back(Segment{c.written, lo, 0});  // first samples, or after a gap
      }
      std::uint64_t n = static_cast<std::uint64_t>(hi - lo);
      if (n > c.limit - c.written) {
        n = c.limit - c.written;
        c.truncated = true;
      }
      if (n > 0 && !write_samples(c, samples.subspan(static_cast<std::size_t>(lo - time), n))) {
        n = 0;
      }
      c.written += n;
      c.segments.back().count += n;
      if (c.segments.back().count == 0) c.segments.pop_back();
    }
    if (end >= window_end_ || c.truncated || !c.error.empty()) {
      c.done.store(true, std::memory_order_relaxed);
    }
  }

  void on_frame_event(const engine::FrameEvent& e) override {
    using K = engine::FrameEventKind;
    switch (e.kind) {
      case K::kTransmitted: {
        const SampleTime length = e.length_samples;
        if (e.time >= window_end_ || e.time + length <= window_start_ || length <= 0) return;
        AirFrame f;
        f.serial = e.serial;
        f.src = e.src;
        f.dst = e.dst;
        f.sender = e.node;
        f.start = e.time;
        f.length = length;
        f.phy = e.phy;
        f.rate_mbps = e.rate_mbps;
        std::lock_guard lock(mutex_);
        if (finished_ || after_every_recording(e.time)) return;
        frames_.insert_or_assign(e.serial, std::move(f));
        return;
      }
      case K::kReceived: {
        std::lock_guard lock(mutex_);
        if (const auto it = frames_.find(e.serial); it != frames_.end()) {
          it->second.received_by.emplace_back(e.node, e.snr_db);
        }
        return;
      }
      case K::kDelivered:
      case K::kLost: {
        std::lock_guard lock(mutex_);
        if (const auto it = frames_.find(e.serial); it != frames_.end()) {
          AirFrame& f = it->second;
          f.outcome =
              e.kind == K::kDelivered ? AirFrame::Outcome::kDelivered : AirFrame::Outcome::kLost;
          f.reason = e.reason;
          f.snr_db = e.snr_db;
        }
        return;
      }
      case K::kHandedIn:
      case K::kQueueDropped:
        return;  // never on the air
    }
  }

  void finish() override {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    for (Channel& c : channels_) {
      c.done.store(true, std::memory_order_relaxed);
      if (c.data != nullptr) {
        // Closing writes out the buffered tail: on a full disk that fails too.
        if (std::fclose(c.data) != 0 && c.error.empty()) {
          c.error = std::strerror(errno);
          spdlog::error("sigmf: writing {} failed: {}; the recording ends before its last samples",
                        c.data_path, c.error);
        }
        c.data = nullptr;
      }
      try {
        std::ofstream out(c.meta_path, std::ios::trunc);
        out << json_text(meta_of(c), 2) << '\n';
        out.close();
        c.meta_written = static_cast<bool>(out);
        if (!out) spdlog::error("sigmf: cannot write {}: {}", c.meta_path, std::strerror(errno));
      } catch (const std::exception& ex) {
        spdlog::error("sigmf: cannot write {}: {}", c.meta_path, ex.what());
      }
    }
  }

  std::uint64_t samples_written(NodeId id) const override {
    std::lock_guard lock(mutex_);
    for (const Channel& c : channels_) {
      if (c.id == id) return c.written;
    }
    return 0;
  }

  nlohmann::json summary() const override {
    std::lock_guard lock(mutex_);
    nlohmann::json nodes = nlohmann::json::array();
    for (const Channel& c : channels_) {
      nodes.push_back(
          {{"id", c.id},
           {"data", c.data_path},
           {"samples_written", c.written},
           {"truncated", c.truncated},
           {"stopped", !c.error.empty()},
           {"error", c.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.error)},
           {"meta_written", c.meta_written}});
    }
    return {{"directory", settings_.directory}, {"nodes", std::move(nodes)}};
  }

 private:
  /// Whether every recording is complete and ends at or before `t`: then a
  /// frame starting at `t` is in none of them. Under mutex_.
  bool after_every_recording(SampleTime t) const {
    for (const Channel& c : channels_) {
      if (!c.done.load(std::memory_order_relaxed)) return false;
      if (!c.segments.empty() &&
          c.segments.back().global_index + static_cast<SampleTime>(c.segments.back().count) > t) {
        return false;
      }
    }
    return true;
  }

  void close_all() {
    for (Channel& c : channels_) {
      if (c.data != nullptr) std::fclose(c.data);
      c.data = nullptr;
    }
  }

  /// Appends samples as little-endian float32 I, Q pairs. Under mutex_.
  bool write_samples(Channel& c, std::span<const cf32> s) {
    bool ok = true;
    if constexpr (std::endian::native == std::endian::little) {
      // std::complex<float> is laid out as float[2]: real, imaginary.
      ok = std::fwrite(s.data(), kBytesPerSample, s.size(), c.data) == s.size();
    } else {
      for (const cf32 v : s) {
        std::uint8_t b[kBytesPerSample];
        const float parts[2] = {v.real(), v.imag()};
        for (int p = 0; p < 2; ++p) {
          const auto u = std::bit_cast<std::uint32_t>(parts[p]);
          for (int k = 0; k < 4; ++k) b[4 * p + k] = static_cast<std::uint8_t>(u >> (8 * k));
        }
        ok = ok && std::fwrite(b, 1, sizeof b, c.data) == sizeof b;
      }
    }
    if (!ok) {
      c.error = std::strerror(errno);
      spdlog::error("sigmf: writing {} failed: {}; recording stopped", c.data_path, c.error);
    }
    return ok;
  }

  static const char* outcome_name(AirFrame::Outcome o) {
    switch (o) {
      case AirFrame::Outcome::kDelivered:
        return "delivered";
      case AirFrame::Outcome::kLost:
        return "lost";
      case AirFrame::Outcome::kPending:
        return "pending";
    }
    return "pending";
  }

  double noise_db() const {
    return noise_variance_ > 0.0 ? 10.0 * std::log10(noise_variance_) : -120.0;
  }

  Json annotation_of(const Channel& c, const AirFrame& f, std::uint64_t sample_start,
                     std::uint64_t sample_count) const {
    const auto rx = std::find_if(f.received_by.begin(), f.received_by.end(),
                                 [&](const auto& r) { return r.first == c.id; });
    const bool received = rx != f.received_by.end();
    const bool own = f.sender == c.id;
    const std::string outcome = received ? "received" : outcome_name(f.outcome);
    const std::optional<double> snr = received ? rx->second : f.snr_db;
    std::string label = std::to_string(f.src) + "->" + std::to_string(f.dst) + " " + outcome;
    if (!received && f.reason) label += ":" + std::string(engine::loss_reason_name(*f.reason));
    if (own) label += " (own)";
    char serial[16];
    std::snprintf(serial, sizeof serial, "0x%08x", f.serial);

    Json a;
    a["core:sample_start"] = sample_start;
    a["core:sample_count"] = sample_count;
    a["core:label"] = label;
    std::string comment = std::string(own ? "transmitted by this node"
                                          : "heard from node " + std::to_string(f.sender)) +
                          ", serial " + serial + ", " + f.phy;
    if (f.rate_mbps != 0) comment += " " + std::to_string(f.rate_mbps) + " Mbit/s";
    a["core:comment"] = comment;
    a["core:generator"] = std::string("rfsitl ") + build_version();
    a["rfsitl:src"] = f.src;
    a["rfsitl:dst"] = f.dst;
    a["rfsitl:serial"] = f.serial;
    a["rfsitl:outcome"] = outcome;
    if (!received && f.reason)
      a["rfsitl:reason"] = std::string(engine::loss_reason_name(*f.reason));
    if (snr) a["rfsitl:snr_db"] = round_to(*snr, 0.01);
    a["rfsitl:final_outcome"] = outcome_name(f.outcome);
    a["rfsitl:own"] = own;
    a["rfsitl:phy"] = f.phy;
    if (f.rate_mbps != 0) a["rfsitl:rate_mbps"] = f.rate_mbps;
    a["rfsitl:frame_start"] = f.start;
    a["rfsitl:frame_samples"] = f.length;
    return a;
  }

  Json meta_of(const Channel& c) const {
    Json global;
    global["core:datatype"] = "cf32_le";
    global["core:sample_rate"] = fs_;
    global["core:version"] = "1.0.0";
    global["core:num_channels"] = 1;
    char desc[256];
    std::snprintf(desc, sizeof desc,
                  "rfsitl: I/Q received by node %u (scenario '%s'), virtual time %.6f s to %.6f s",
                  c.id, scenario_name_.c_str(), static_cast<double>(window_start_) / fs_,
                  static_cast<double>(window_end_) / fs_);
    global["core:description"] = desc;
    global["core:recorder"] = std::string("rfsitl ") + build_version();
    global["core:extensions"] =
        Json::array({Json{{"name", "rfsitl"}, {"version", "1.0.0"}, {"optional", true}}});
    global["rfsitl:node_id"] = c.id;
    global["rfsitl:node_index"] = c.index;
    global["rfsitl:scenario"] = scenario_name_;
    global["rfsitl:seed"] = seed_;
    global["rfsitl:tick_samples"] = tick_samples_;
    global["rfsitl:noise_db"] = round_to(noise_db(), 1e-6);
    // Samples are the receiver input times the front-end gain 1/sigma, so the
    // noise has unit power: power relative to unit TX power = |x|^2 * sigma^2.
    global["rfsitl:front_end_gain_db"] = round_to(-noise_db(), 1e-6);
    global["rfsitl:scale"] =
        "front end: noise at unit power; 10log10|x|^2 + rfsitl:noise_db = dB relative to unit TX "
        "power; zeros while this node transmits";
    global["rfsitl:window_start_sample"] = window_start_;
    global["rfsitl:window_samples"] = window_end_ - window_start_;
    global["rfsitl:window_start_s"] = static_cast<double>(window_start_) / fs_;
    global["rfsitl:window_duration_s"] = static_cast<double>(window_end_ - window_start_) / fs_;
    global["rfsitl:recorded_samples"] = c.written;
    global["rfsitl:max_bytes"] = settings_.max_bytes;
    global["rfsitl:truncated"] = c.truncated;
    if (!c.error.empty()) global["rfsitl:error"] = c.error;

    Json captures = Json::array();
    for (const Segment& s : c.segments) {
      captures.push_back(
          Json{{"core:sample_start", s.sample_start},
               {"core:global_index", s.global_index},
               {"rfsitl:virtual_time_s", static_cast<double>(s.global_index) / fs_}});
    }
    if (captures.empty()) {
      captures.push_back(Json{{"core:sample_start", 0},
                              {"core:global_index", window_start_},
                              {"rfsitl:virtual_time_s", static_cast<double>(window_start_) / fs_}});
    }

    // Every frame overlapping a recorded segment, clipped to it.
    std::vector<const AirFrame*> frames;
    frames.reserve(frames_.size());
    for (const auto& [serial, f] : frames_) frames.push_back(&f);
    std::sort(frames.begin(), frames.end(), [](const AirFrame* a, const AirFrame* b) {
      return a->start != b->start ? a->start < b->start : a->serial < b->serial;
    });
    std::vector<std::pair<std::uint64_t, Json>> annotations;
    for (const AirFrame* f : frames) {
      for (const Segment& s : c.segments) {
        const SampleTime seg_end = s.global_index + static_cast<SampleTime>(s.count);
        const SampleTime lo = std::max(f->start, s.global_index);
        const SampleTime hi = std::min(f->start + f->length, seg_end);
        if (lo >= hi) continue;
        const std::uint64_t start =
            s.sample_start + static_cast<std::uint64_t>(lo - s.global_index);
        annotations.emplace_back(start,
                                 annotation_of(c, *f, start, static_cast<std::uint64_t>(hi - lo)));
      }
    }
    std::stable_sort(annotations.begin(), annotations.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    Json list = Json::array();
    for (auto& [start, a] : annotations) list.push_back(std::move(a));

    Json meta;
    meta["global"] = std::move(global);
    meta["captures"] = std::move(captures);
    meta["annotations"] = std::move(list);
    return meta;
  }

  const SigmfSettings settings_;
  const double fs_;
  const std::string scenario_name_;
  const std::uint64_t seed_;
  const std::uint32_t tick_samples_;
  const double noise_variance_;
  SampleTime window_start_ = 0;
  SampleTime window_end_ = 0;
  std::vector<NodeId> ids_;
  std::vector<int> slot_of_;  // node index -> channel, or -1
  std::vector<Channel> channels_;
  mutable std::mutex mutex_;
  bool finished_ = false;
  std::unordered_map<std::uint32_t, AirFrame> frames_;  // by serial
};

}  // namespace

std::unique_ptr<SigmfRecorder> make_sigmf_recorder(const SigmfSettings& settings,
                                                   const scenario::Scenario& scenario) {
  return std::make_unique<SigmfRecorderImpl>(settings, scenario);
}

}  // namespace rfsitl::monitor
