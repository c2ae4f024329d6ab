#include "virtual_run.hpp"

#include <stdexcept>

#include "rfsitl/engine/engine.hpp"

namespace rfsitl::python {

struct VirtualRun::Agents final : engine::FrameSink {
  bool keep = true;
  engine::Engine* engine = nullptr;
  void deliver(std::size_t node, NetFrame&&) override {
    // Kept frames reach the caller as "received" events (RunLog).
    if (!keep && engine != nullptr) {
      engine::NodeCounters::bump(engine->counters(node).to_agent_dropped);
    }
  }
};

VirtualRun::VirtualRun(scenario::Scenario scenario, const VirtualRunOptions& options)
    : agents_(std::make_unique<Agents>()) {
  agents_->keep = options.keep_frames;
  session::SessionOptions o;
  o.scenario = std::move(scenario);
  o.settings.push_back({"time.mode", "virtual", "a virtual-time run (rfsitl.Emulator)"});
  o.ports = false;
  o.frames = agents_.get();
  o.pcap.path = options.pcap_path;
  o.sigmf.directory = options.sigmf_dir;
  session_ = std::make_unique<session::Session>(std::move(o));
  session_->assemble();
  engine_ = &session_->engine();
  agents_->engine = engine_;
  const scenario::Scenario& s = session_->scenario();
  log_ = std::make_unique<RunLog>(s.nodes.size(), options.record_events, options.max_events,
                                  options.max_tap_samples);
  taps_ = options.taps;
  if (options.record_events || options.taps) engine_->add_observer(*log_);
  curves_ = monitor::declared_per_curves(s);
  session_->open();
}

VirtualRun::~VirtualRun() = default;

std::size_t VirtualRun::index_of(NodeId id) const {
  if (const auto i = engine_->index_of(id)) return *i;
  std::string nodes;
  for (const NodeId n : engine_->node_ids()) {
    nodes += (nodes.empty() ? "" : ", ") + std::to_string(n);
  }
  throw std::out_of_range("node " + std::to_string(id) + " is not in this run (nodes: " + nodes +
                          ")");
}

double VirtualRun::now_s() const {
  return engine_->status().virtual_s;
}

double VirtualRun::tick_s() const {
  const auto& t = session_->scenario().timing;
  return static_cast<double>(t.tick_samples) / t.sample_rate_hz;
}

double VirtualRun::end_s() const {
  return session_->scenario().timing.duration_s;
}

void VirtualRun::require_open() const {
  if (summary_ != nullptr) throw std::logic_error("the run has finished: no further step");
}

double VirtualRun::advance(double until_s) {
  require_open();
  log_->begin_step();
  return session_->advance(until_s);
}

bool VirtualRun::send(NodeId src, NodeId dst, std::vector<std::uint8_t> payload) {
  require_open();
  const std::size_t i = index_of(src);
  const std::size_t mtu = engine_->max_payload(i);
  if (payload.size() > mtu) {
    throw std::invalid_argument("node " + std::to_string(src) + " sends at most " +
                                std::to_string(mtu) + " bytes a frame, got " +
                                std::to_string(payload.size()));
  }
  return engine_->submit(i, NetFrame{src, dst, std::move(payload)});
}

void VirtualRun::report(NodeId id, const position::StateReport& report) {
  require_open();
  engine_->report(index_of(id), report);
}

std::vector<engine::NodeCountersSnapshot> VirtualRun::counters() {
  std::vector<engine::NodeCountersSnapshot> out;
  for (std::size_t i = 0; i < engine_->num_nodes(); ++i) {
    out.push_back(engine_->counters(i).snapshot());
    out.back().queue_depth = engine_->queue_depth(i);
  }
  return out;
}

std::vector<monitor::LinkRow> VirtualRun::links(std::size_t payload_bytes) const {
  const std::vector<std::optional<Ecef>> positions = engine_->positions();
  const std::vector<float> gains = engine_->link_gains();
  monitor::LinkInputs in;
  in.ids = engine_->node_ids();
  in.positions = positions;
  in.gains = gains;
  in.noise_variance = session_->scenario().channel.noise_variance;
  in.curves = curves_;
  in.payload_bytes = payload_bytes;
  return monitor::link_rows(in);
}

void VirtualRun::set_tap(NodeId id, bool on) {
  if (!taps_) throw std::logic_error("this run was made without taps (iq=False)");
  log_->set_tap(index_of(id), on);
}

TapBuffer VirtualRun::take_samples(NodeId id) {
  return log_->take_tap(index_of(id));
}

const nlohmann::json& VirtualRun::finish() {
  if (summary_ == nullptr) summary_ = &session_->finish().document;
  return *summary_;
}

}  // namespace rfsitl::python
