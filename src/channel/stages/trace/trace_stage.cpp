// The trace stage: its settings, declared once; the stage that interpolates a
// parsed trace at the grid's times; and the component that reads the files.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/channel/stages/trace.hpp"
#include "trace_text.hpp"

namespace rfsitl::channel {

const config::Fields<TraceSettings>& trace_fields() {
  using S = TraceSettings;
  static const auto f =
      config::Fields<S>()
          .text("file", &S::file,
                "the trace, .csv (t_s,tx,rx,gain_db,phase_deg) or .npy (T x L x 2); relative "
                "to the scenario file's folder (docs/channel_traces.md)")
          .text("links_file", &S::links_file,
                ".npy only: CSV `tx,rx` listing the array's L links in order")
          .real("step_s", &S::step_s, "s", {0.0, 1e6},
                ".npy only: the time between the array's rows (> 0)")
          .real("update_rate_hz", &S::update_rate_hz, "Hz", {1.0, 1e8},
                "gains are computed this often and interpolated linearly between: keep it at "
                "least the trace's sample rate")
          .flag("loop", &S::loop, "repeat the trace with period t_last - t_first after its end")
          .choice("missing", &S::missing,
                  {{"unity", TraceMissing::kUnity}, {"block", TraceMissing::kBlock}},
                  "links the file does not drive: unity (gain 1) or block (gain 0, no link)")
          .flag("reciprocal", &S::reciprocal,
                "a link a->b in the file also drives b->a when the file has no rows for b->a")
          .rule([](const S& s) {
            const auto ext = trace::detail::extension(s.file);
            if (s.file.empty()) throw config::SettingError("file", "required");
            if (ext != ".csv" && ext != ".npy") {
              throw config::SettingError("file", "must end in .csv or .npy");
            }
            if (ext == ".npy" && s.links_file.empty()) {
              throw config::SettingError("links_file", "required with an .npy file");
            }
            if (ext == ".npy" && s.step_s <= 0.0) {
              throw config::SettingError("step_s", "required (> 0) with an .npy file");
            }
            if (ext == ".csv" && !s.links_file.empty()) {
              throw config::SettingError("links_file", "only for .npy files");
            }
            if (ext == ".csv" && s.step_s != 0.0) {
              throw config::SettingError("step_s", "only for .npy files (CSV rows carry t_s)");
            }
          });
  return f;
}

namespace trace {
namespace {

class TraceStage final : public GainStage {
 public:
  TraceStage(const TraceSettings& s, Trace trace, std::span<const NodeId> node_ids)
      : settings_(s), links_(std::move(trace.links)), n_(node_ids.size()), table_(n_ * n_, -1) {
    const detail::IdIndex index = detail::index_of_ids(node_ids);
    auto slot = [&](NodeId tx, NodeId rx) -> std::int32_t& {
      if (index[tx] < 0 || index[rx] < 0) {
        throw std::invalid_argument("trace: link " + detail::link_name({tx, rx}) +
                                    " names a node the scenario does not have");
      }
      return table_[static_cast<std::size_t>(index[tx]) * n_ + static_cast<std::size_t>(index[rx])];
    };
    t_first_ = kMaxTimeS;
    t_last_ = 0.0;
    for (std::size_t i = 0; i < links_.size(); ++i) {
      const std::vector<Sample>& samples = links_[i].samples;
      if (samples.empty() ||
          !std::is_sorted(samples.begin(), samples.end(),
                          [](const Sample& p, const Sample& q) { return p.t_s < q.t_s; })) {
        throw std::invalid_argument("trace: link " + detail::link_name(links_[i].link) +
                                    " has no samples, or samples out of time order");
      }
      slot(links_[i].link.tx, links_[i].link.rx) = static_cast<std::int32_t>(i);
      unwrap(links_[i].samples);
      t_first_ = std::min(t_first_, links_[i].samples.front().t_s);
      t_last_ = std::max(t_last_, links_[i].samples.back().t_s);
    }
    if (s.reciprocal) {  // after every file link is in, so only true gaps are filled
      for (std::size_t i = 0; i < links_.size(); ++i) {
        std::int32_t& reverse = slot(links_[i].link.rx, links_[i].link.tx);
        if (reverse < 0) reverse = static_cast<std::int32_t>(i);
      }
    }
    for (std::size_t a = 0; a < n_; ++a) {
      for (std::size_t b = a + 1; b < n_; ++b) {
        reciprocal_ = reciprocal_ && table_[a * n_ + b] == table_[b * n_ + a];
      }
    }
  }

  std::complex<double> gain(const LinkGeometry& link) const override {
    const std::size_t a = link.tx.index;
    const std::size_t b = link.rx.index;
    if (a == b) return 1.0;  // a node hears itself: the trace says nothing of that
    const std::int32_t i = a < n_ && b < n_ ? table_[a * n_ + b] : -1;
    if (i < 0) return settings_.missing == TraceMissing::kUnity ? 1.0 : 0.0;
    const Sample s = at(links_[static_cast<std::size_t>(i)].samples, folded(link.time_s));
    return std::pow(10.0, s.gain_db / 20.0) *
           std::polar(1.0, s.phase_deg * std::numbers::pi / 180.0);
  }

  bool reciprocal() const override { return reciprocal_; }
  bool time_varying() const override { return true; }
  double update_interval_s() const override { return 1.0 / settings_.update_rate_hz; }

 private:
  /// Each step of the phase taken the shorter way round, in [-180, 180).
  static void unwrap(std::vector<Sample>& samples) {
    double previous_raw = samples.front().phase_deg;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      const double raw = samples[k].phase_deg;
      double step = raw - previous_raw;
      step -= 360.0 * std::floor((step + 180.0) / 360.0);
      samples[k].phase_deg = samples[k - 1].phase_deg + step;
      previous_raw = raw;
    }
  }

  /// `t_s` within the trace's period when looping.
  double folded(double t_s) const {
    const double period = t_last_ - t_first_;
    if (!settings_.loop || period <= 0.0 || t_s < t_first_) return t_s;
    return t_first_ + std::fmod(t_s - t_first_, period);
  }

  /// The samples interpolated at t_s; the end values outside them.
  static Sample at(const std::vector<Sample>& samples, double t_s) {
    // The first sample later than t_s: of equal times the last one holds.
    const auto later = std::upper_bound(samples.begin(), samples.end(), t_s,
                                        [](double t, const Sample& s) { return t < s.t_s; });
    if (later == samples.begin()) return samples.front();
    if (later == samples.end()) return samples.back();
    const Sample& p = *(later - 1);
    const Sample& q = *later;
    const double w = (t_s - p.t_s) / (q.t_s - p.t_s);  // q.t_s > p.t_s: upper_bound
    return {t_s, p.gain_db + w * (q.gain_db - p.gain_db),
            p.phase_deg + w * (q.phase_deg - p.phase_deg)};
  }

  TraceSettings settings_;
  std::vector<LinkTrace> links_;  // phases unwrapped
  std::size_t n_;
  std::vector<std::int32_t> table_;  // [tx index * n + rx index] -> links_ entry, -1: missing
  double t_first_ = 0.0;
  double t_last_ = 0.0;
  bool reciprocal_ = true;
};

}  // namespace

std::unique_ptr<GainStage> make_stage(const TraceSettings& settings, Trace trace,
                                      std::span<const NodeId> node_ids) {
  return std::make_unique<TraceStage>(settings, std::move(trace), node_ids);
}

}  // namespace trace

ChannelStageComponent trace_component() {
  return {trace_fields().info("channel", "trace",
                              "replays measured or ray-traced channels: per-link gain and phase "
                              "over time from a CSV or NPY file"),
          [](const config::Settings& settings, const StageContext& context) {
            const TraceSettings s = trace_fields().build(settings);
            const std::vector<NodeId>& ids = context.node_ids;
            return trace::make_stage(s, trace::load(s, context.source_dir, ids), ids);
          }};
}

}  // namespace rfsitl::channel
