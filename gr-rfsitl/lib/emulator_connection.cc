#include "emulator_connection.h"

#include <algorithm>
#include <boost/date_time/posix_time/posix_time_types.hpp>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "log_format.h"

namespace gr::rfsitl {

namespace {

/// How long a full buffer may wait without any emulator_source for the node
/// before the sink warns that nothing will ever drain it.
constexpr int kNoSourceWarnMs = 2000;

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

std::map<std::pair<std::string, int>, std::weak_ptr<emulator_connection>>& registry() {
  static std::map<std::pair<std::string, int>, std::weak_ptr<emulator_connection>> r;
  return r;
}

}  // namespace

std::shared_ptr<emulator_connection> emulator_connection::get(const std::string& socket_path,
                                                              int node_id) {
  if (socket_path.empty()) throw std::invalid_argument("rfsitl: empty emulator socket path");
  if (node_id < ::rfsitl::kMinNodeId || node_id > ::rfsitl::kMaxNodeId) {
    throw std::invalid_argument("rfsitl: node id " + std::to_string(node_id) + " outside 1.." +
                                std::to_string(::rfsitl::kMaxNodeId));
  }
  std::lock_guard lock(registry_mutex());
  auto& reg = registry();
  // Forget nodes whose blocks are all gone, so a later flowgraph starts afresh.
  std::erase_if(reg, [](const auto& entry) { return entry.second.expired(); });
  auto& slot = reg[{socket_path, node_id}];
  if (auto existing = slot.lock()) return existing;
  auto created = std::make_shared<emulator_connection>(socket_path, node_id);
  slot = created;
  return created;
}

emulator_connection::emulator_connection(const std::string& socket_path, int node_id)
    : socket_path_(socket_path),
      node_id_(node_id),
      label_("node " + std::to_string(node_id) + " (" + socket_path + ")"),
      logger_("rfsitl node " + std::to_string(node_id)) {}

void emulator_connection::attach_source(int handshake_timeout_ms) {
  gr::thread::scoped_lock lock(mutex_);
  if (source_attached_) {
    throw std::runtime_error("rfsitl: " + label_ +
                             " already has an emulator_source in this process");
  }
  ::rfsitl::external::ExternalClient::Settings s;
  s.socket_path = socket_path_;
  s.node_id = static_cast<::rfsitl::NodeId>(node_id_);
  s.role = "samples";
  s.program = "gr-rfsitl";
  s.handshake_timeout_ms = handshake_timeout_ms;
  client_ = std::make_unique<::rfsitl::external::ExternalClient>(std::move(s));
  source_attached_ = true;
}

void emulator_connection::detach_source() {
  gr::thread::scoped_lock lock(mutex_);
  client_.reset();
  source_attached_ = false;
}

void emulator_connection::set_sample_rate(double sample_rate_hz, std::uint32_t tick_samples) {
  {
    gr::thread::scoped_lock lock(mutex_);
    sample_rate_hz_ = sample_rate_hz;
    tick_samples_ = tick_samples;
  }
  // A larger bound may let a waiting sink continue.
  space_cv_.notify_all();
}

void emulator_connection::attach_sink(double buffer_seconds) {
  gr::thread::scoped_lock lock(mutex_);
  if (sink_attached_) {
    throw std::runtime_error("rfsitl: " + label_ + " already has an emulator_sink in this process");
  }
  sink_attached_ = true;
  buffer_seconds_ = buffer_seconds;
}

void emulator_connection::detach_sink() {
  gr::thread::scoped_lock lock(mutex_);
  sink_attached_ = false;
}

std::size_t emulator_connection::bound_locked() const {
  // At least a few ticks, so that a tiny max_buffer_s cannot starve the
  // emulator of a full tick.
  const auto by_time = static_cast<std::size_t>(buffer_seconds_ * sample_rate_hz_);
  return std::max<std::size_t>({by_time, std::size_t{4} * tick_samples_, 1024});
}

std::size_t emulator_connection::take_tx(gr_complex* out, std::size_t max) {
  std::size_t n = 0;
  {
    gr::thread::scoped_lock lock(mutex_);
    n = std::min(max, released_);
    if (n == 0) return 0;
    std::copy_n(tx_.begin(), n, out);
    tx_.erase(tx_.begin(), tx_.begin() + static_cast<std::ptrdiff_t>(n));
    released_ -= n;
  }
  space_cv_.notify_all();
  return n;
}

void emulator_connection::set_finished(bool finished) {
  {
    gr::thread::scoped_lock lock(mutex_);
    finished_ = finished;
  }
  space_cv_.notify_all();
}

std::size_t emulator_connection::put_tx(const gr_complex* in, std::size_t n) {
  if (n == 0) return 0;
  gr::thread::scoped_lock lock(mutex_);
  int waited_ms = 0;
  for (;;) {
    if (finished_) return 0;
    const std::size_t bound = bound_locked();
    if (tx_.size() < bound) {
      const std::size_t k = std::min(n, bound - tx_.size());
      tx_.insert(tx_.end(), in, in + k);
      return k;
    }
    if (released_ == 0) {
      // Full of one unreleased burst: only releasing it can make room. The
      // sink avoids this for bursts that fit; this keeps any other case live.
      log_warn(logger_, "{}: transmit buffer full of an incomplete burst; releasing it early",
               label_);
      released_ = tx_.size();
      continue;
    }
    // boost's timed wait is an interruption point: tb.stop() ends it. (The
    // posix_time form avoids a dependency on libboost_chrono.)
    constexpr int kSliceMs = 200;
    space_cv_.timed_wait(lock, boost::posix_time::milliseconds(kSliceMs));
    waited_ms += kSliceMs;
    if (!source_attached_ && !warned_no_source_ && waited_ms >= kNoSourceWarnMs) {
      warned_no_source_ = true;
      log_warn(logger_,
               "{}: transmit buffer full and no emulator_source for this node in this process; "
               "nothing will drain it",
               label_);
    }
  }
}

void emulator_connection::release() {
  gr::thread::scoped_lock lock(mutex_);
  released_ = tx_.size();
}

std::size_t emulator_connection::buffered() const {
  gr::thread::scoped_lock lock(mutex_);
  return tx_.size();
}

std::size_t emulator_connection::capacity() const {
  gr::thread::scoped_lock lock(mutex_);
  return bound_locked();
}

}  // namespace gr::rfsitl
