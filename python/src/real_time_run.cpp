#include "real_time_run.hpp"

#include <chrono>

namespace rfsitl::python {

RealTimeRun::RealTimeRun(scenario::Scenario scenario, const RealTimeRunOptions& options) {
  session::SessionOptions o;
  o.scenario = std::move(scenario);
  o.settings.push_back({"time.mode", "realtime", "a real-time run (rfsitl.RealTimeRun)"});
  if (options.ip) o.settings.push_back({"ip.enabled", "true", "ip=True"});
  o.dashboard.enabled = options.dashboard;
  o.dashboard.port = options.dashboard_port;
  o.pcap.path = options.pcap_path;
  session_ = std::make_unique<session::Session>(std::move(o));
  session_->assemble();
}

RealTimeRun::~RealTimeRun() {
  session_->request_stop();
  if (thread_.joinable()) thread_.join();
}

void RealTimeRun::start() {
  if (thread_.joinable()) throw std::logic_error("the run was started already");
  thread_ = std::thread([this] {
    session::ServeResult r;
    std::string error;
    session::ServeHooks hooks;
    hooks.ready = [this] {
      {
        std::lock_guard lock(mutex_);
        opened_ = true;
      }
      cv_.notify_all();
      return true;
    };
    try {
      r = session_->serve(hooks);
    } catch (const std::exception& e) {
      error = e.what();
    }
    {
      std::lock_guard lock(mutex_);
      opened_ = true;
      ended_ = true;
      result_ = r;
      error_ = !error.empty() ? error : r.error;
    }
    cv_.notify_all();
  });
  std::unique_lock lock(mutex_);
  cv_.wait(lock, [this] { return opened_; });
  if (ended_ && !error_.empty()) throw session::SessionError(error_);
}

bool RealTimeRun::wait(double timeout_s) {
  std::unique_lock lock(mutex_);
  return cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [this] { return ended_; });
}

bool RealTimeRun::running() const {
  std::lock_guard lock(mutex_);
  return opened_ && !ended_;
}

const nlohmann::json& RealTimeRun::stop() {
  if (summary_ != nullptr) return *summary_;
  if (!thread_.joinable()) throw std::logic_error("the run was not started");
  session_->request_stop();
  thread_.join();
  if (!error_.empty()) throw session::SessionError(error_);
  summary_ = &session_->finish().document;
  return *summary_;
}

}  // namespace rfsitl::python
