#pragma once
/// A real-time run with its ports, as `rfsitl run` serves one, started and
/// stopped from Python: the same Session, its serve() on a thread of this
/// object's own so that the caller's thread (Python's) stays free.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/session.hpp"

namespace rfsitl::python {

struct RealTimeRunOptions {
  bool ip = false;                              ///< IP on every node (root), as `rfsitl run --ip`
  bool dashboard = false;                       ///< the web dashboard
  std::optional<std::uint16_t> dashboard_port;  ///< nullopt: 15700 or any free one
  std::string pcap_path;                        ///< "": no trace
};

class RealTimeRun {
 public:
  /// Assembles the run (time.mode forced to real-time): every port is bound
  /// when this returns. Throws session::SessionError.
  RealTimeRun(scenario::Scenario scenario, const RealTimeRunOptions& options);
  /// Stops the run if it still goes on.
  ~RealTimeRun();

  /// Opens the faces and starts the engine's clock on a thread of its own;
  /// returns once the first tick is due. Throws SessionError if opening failed.
  void start();
  /// Waits up to `timeout_s` for the run's end (its duration); true if it ended.
  bool wait(double timeout_s);
  /// Stops the run (if it still goes on) and returns the summary document,
  /// as `rfsitl run --summary-json` writes it. Idempotent.
  const nlohmann::json& stop();

  bool running() const;
  session::Session& session() { return *session_; }
  engine::EngineStatus status() { return session_->engine().status(); }

 private:
  std::unique_ptr<session::Session> session_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool opened_ = false;  // the faces are open (or opening failed: error_)
  bool ended_ = false;   // serve() returned
  std::string error_;
  session::ServeResult result_;
  const nlohmann::json* summary_ = nullptr;
};

}  // namespace rfsitl::python
