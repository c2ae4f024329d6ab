/// The Session's last two steps, serve and finish, and its teardown.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "rfsitl/monitor/node_counter_report.hpp"
#include "rfsitl/session/session.hpp"

namespace rfsitl::session {
namespace {

// How long the ranks of a distributed run get to stop together.
constexpr auto kPeersGrace = std::chrono::seconds(10);

}  // namespace

ServeResult Session::serve(const ServeHooks& hooks) {
  if (in_parts_) {
    throw SessionStepError("session: serve() after open(): a run in parts goes on by advance()");
  }
  open_faces();
  if (hooks.ready && !hooks.ready()) {
    refusal_ = "the run was cancelled before its first tick";
    return {ServeEnd::kCancelled, {}};
  }

  engine_thread_ = std::thread([this] { engine_main(); });
  const auto ended = [this] {
    std::lock_guard lock(end_mutex_);
    return ended_;
  };
  if (hooks.poll) {
    while (!ended() && hooks.poll()) {
    }
  } else {
    std::unique_lock lock(end_mutex_);
    end_cv_.wait(lock, [this] { return ended_ || stop_.load(); });
  }
  stop_.store(true);
  if (ranks_.distributed()) {
    // The ranks stop together at the next tick's exchange; a rank whose peers
    // died waits there for ever (Open MPI does not survive a lost rank), so
    // after a while it reports what it has and leaves.
    std::unique_lock lock(end_mutex_);
    if (!end_cv_.wait_for(lock, kPeersGrace, [this] { return ended_; })) {
      stuck_ = true;
      refusal_ = "the other ranks stopped answering";
      return {ServeEnd::kPeersLost, {}};
    }
  }
  engine_thread_.join();
  if (!engine_error_.empty()) {
    refusal_ = "the run failed: " + engine_error_;
    return {ServeEnd::kFailed, engine_error_};
  }
  next_ = Step::kFinish;
  return {ServeEnd::kCompleted, {}};
}

void Session::open_faces() {
  // Opening: the sources report into the engine, the net ports and the TAP
  // interfaces hand it frames, the children join its hub. Every rank opens,
  // or none runs.
  run_step(Step::kServe, true, [this] {
    if (sources_) sources_->start(*engine_);
    if (servers_) servers_->start(*engine_);
    if (ip_) ip_->start(*engine_);
    if (external_) external_->start_children();
  });
  if (ip_) {
    // Every rank's interfaces (collective), for the banner and the summary.
    const nlohmann::json mine = ip_->summary();
    for (const std::string& text :
         gather_texts(ranks_, nlohmann::json{mine["nodes"], mine["removed_stale"]}.dump())) {
      const nlohmann::json theirs = nlohmann::json::parse(text);
      for (auto& n : agent_port::ip_nodes_from_json(theirs[0])) ip_nodes_.push_back(std::move(n));
      for (const auto& name : theirs[1]) ip_stale_.push_back(name);
    }
    std::sort(ip_nodes_.begin(), ip_nodes_.end(), [this](const auto& a, const auto& b) {
      return engine_->index_of(a.id) < engine_->index_of(b.id);
    });
  }
}

void Session::open() {
  if (ranks_.distributed() && next_ == Step::kServe) {
    refusal_ = "a distributed run cannot go in parts";
    throw SessionError("a distributed run cannot go in parts: its ticks are collective (serve())");
  }
  open_faces();
  in_parts_ = true;
}

double Session::advance(double until_s) {
  if (!in_parts_ || next_ != Step::kServe) {
    throw SessionStepError(std::string("session: advance() needs open() first (the step due is '") +
                           step_name(next_) + "')");
  }
  const double fs = scenario_.timing.sample_rate_hz;
  const auto until = static_cast<SampleTime>(std::ceil(std::max(0.0, until_s) * fs));
  try {
    return static_cast<double>(engine_->advance(until, stop_)) / fs;
  } catch (const std::exception& e) {
    refusal_ = std::string("the run failed: ") + e.what();
    throw SessionError(refusal_);
  }
}

void Session::engine_main() {
  std::string error;
  try {
    engine_->run(stop_);
  } catch (const std::exception& e) {
    // A distributed run's exchange failed (the run cannot go on).
    error = e.what();
  }
  {
    std::lock_guard lock(end_mutex_);
    ended_ = true;
    engine_error_ = error;
  }
  end_cv_.notify_all();
}

const SessionSummary& Session::finish() {
  // A run in parts ends wherever advance() left it.
  if (in_parts_ && next_ == Step::kServe && refusal_.empty()) next_ = Step::kFinish;
  // Not collective as a step: the one collective part (the external nodes'
  // summaries) every rank reaches alike, its scenario deciding.
  run_step(Step::kFinish, false, [this] {
    close_faces();
    if (sigmf_) sigmf_->finish();
    if (pcap_) pcap_->flush();
    SessionSummary r;
    r.status = engine_->status();
    r.node_ids = engine_->node_ids();
    r.counters = monitor::all_node_counters(*engine_);
    if (external_) {
      r.external =
          merge_external_summaries(gather_texts(ranks_, external_->summary().dump()), *engine_);
    }
    if (pcap_) r.pcap = pcap_->summary();
    if (sigmf_) r.sigmf = sigmf_->summary();
    r.document = summary_json({scenario_, *engine_, sources_.get(), ranks_,
                               external_ ? &r.external : nullptr, pcap_.get(), sigmf_.get(),
                               ip_.get(), ip_nodes_, ip_stale_});
    summary_ = std::move(r);
  });
  return *summary_;
}

void Session::close_faces() {
  if (sources_) sources_->stop();
  if (ip_) ip_->stop();
  if (servers_) servers_->stop();
}

Session::~Session() {
  if (stuck_) {
    // The engine's thread waits in an exchange that will never complete, and
    // uses the engine, its sink, its observers and MPI: leave them to the
    // process's end (the caller ends it) rather than destroy them under it.
    engine_thread_.detach();
    static_cast<void>(engine_.release());
    static_cast<void>(servers_.release());
    static_cast<void>(ip_.release());
    static_cast<void>(external_.release());
    static_cast<void>(pcap_.release());
    static_cast<void>(sigmf_.release());
    static_cast<void>(rank_view_.release());
    static_cast<void>(ranks_.peers.release());
    return;
  }
  stop_.store(true);
  end_cv_.notify_all();
  if (engine_thread_.joinable()) engine_thread_.join();
  close_faces();
}

}  // namespace rfsitl::session
