#include "emulator_source_impl.h"

#include <gnuradio/io_signature.h>
#include <pmt/pmt.h>

#include <algorithm>
#include <boost/date_time/posix_time/posix_time_types.hpp>
#include <boost/thread/thread.hpp>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "log_format.h"

namespace gr::rfsitl {

namespace {

using ::rfsitl::external::RecvStatus;
using steady = std::chrono::steady_clock;

/// Longest single blocking wait on the socket: bounds how long tb.stop() waits
/// for this block's thread, since a poll() is not a boost interruption point.
constexpr int kPollSliceMs = 100;
/// Pause between connection attempts while the emulator is not up.
constexpr int kRetryPauseMs = 200;
/// Interval between "still waiting for the emulator" messages.
constexpr auto kWaitLogInterval = std::chrono::seconds(2);
/// Output buffer bound in items. The block produces only as ticks arrive, so
/// it cannot run ahead of the emulator; a small buffer also keeps it from
/// queueing many ticks ahead of a slow receiver chain. 512 gr_complex is one
/// 4 KiB page, GNU Radio's allocation granularity.
constexpr long kMaxOutputBufferItems = 512;

int ms_until(steady::time_point t) {
  const auto d = std::chrono::duration_cast<std::chrono::milliseconds>(t - steady::now());
  return static_cast<int>(std::max<std::int64_t>(0, d.count()));
}

}  // namespace

emulator_source::sptr emulator_source::make(const std::string& socket_path, int node_id,
                                            int timeout_ms, int reconnect_ms) {
  return gnuradio::make_block_sptr<emulator_source_impl>(socket_path, node_id, timeout_ms,
                                                         reconnect_ms);
}

emulator_source_impl::emulator_source_impl(const std::string& socket_path, int node_id,
                                           int timeout_ms, int reconnect_ms)
    : gr::sync_block("emulator_source", gr::io_signature::make(0, 0, 0),
                     gr::io_signature::make(1, 1, sizeof(gr_complex))),
      conn_(emulator_connection::get(socket_path, node_id)),
      timeout_ms_(timeout_ms),
      reconnect_ms_(reconnect_ms) {
  if (timeout_ms <= 0) {
    throw std::invalid_argument("rfsitl emulator_source: timeout_ms must be > 0");
  }
  if (reconnect_ms < 0) {
    throw std::invalid_argument("rfsitl emulator_source: reconnect_ms must be >= 0");
  }
  // The handshake wait cannot be interrupted by tb.stop(); a live emulator
  // answers at once, so it need not be longer than the tick timeout.
  conn_->attach_source(std::clamp(timeout_ms, 100, 5000));
  set_max_output_buffer(0, kMaxOutputBufferItems);
}

emulator_source_impl::~emulator_source_impl() {
  conn_->detach_source();
}

bool emulator_source_impl::start() {
  finished_ = false;
  conn_->set_finished(false);
  return true;
}

bool emulator_source_impl::stop() {
  // Runs on this block's thread after its last work(): leaving now tells the
  // emulator at once instead of after its tick timeout. A sink waiting for
  // room must not wait for a source that is gone.
  if (conn_->client().connected()) leave("flowgraph stopped", true);
  conn_->set_finished(true);
  return true;
}

void emulator_source_impl::leave(const std::string& why, bool expected) {
  conn_->client().disconnect();
  connected_ = false;
  pending_.clear();
  pending_pos_ = 0;
  pending_tag_ = false;
  if (expected) {
    log_info(*d_logger, "{}: left the emulator: {}", conn_->label(), why);
  } else {
    log_warn(*d_logger, "{}: connection to the emulator ended: {}; rejoining", conn_->label(), why);
  }
}

bool emulator_source_impl::join() {
  auto& client = conn_->client();
  const auto start = steady::now();
  const auto deadline = start + std::chrono::milliseconds(reconnect_ms_);
  auto next_log = start;
  for (;;) {
    boost::this_thread::interruption_point();
    try {
      const auto& w = client.connect();
      if (w.sample_rate_hz <= 0.0 || w.tick_samples == 0 ||
          w.tick_samples > ::rfsitl::external::kMaxExternalTickSamples) {
        client.disconnect();
        throw std::runtime_error("welcome with unusable sample rate " +
                                 std::to_string(w.sample_rate_hz) + " Hz or tick of " +
                                 std::to_string(w.tick_samples) + " samples");
      }
      tx_.resize(w.tick_samples);
      sample_rate_hz_ = w.sample_rate_hz;
      tick_samples_ = static_cast<int>(w.tick_samples);
      conn_->set_sample_rate(w.sample_rate_hz, w.tick_samples);
      tag_next_ = true;  // the stream restarts at an arbitrary virtual time
      have_tick_ = false;
      // Counters before the flag: whoever sees connected() sees this join.
      const auto n = ++joins_;
      connected_ = true;
      log_info(*d_logger, "{}: {} the emulator: {} samples/s, {} samples/tick, {} time",
               conn_->label(), n == 1 ? "joined" : "rejoined", w.sample_rate_hz, w.tick_samples,
               w.virtual_time ? "virtual" : "real");
      return true;
    } catch (const std::exception& e) {
      if (steady::now() >= deadline) {
        log_error(*d_logger, "{}: giving up after {} ms without a connection: {}", conn_->label(),
                  reconnect_ms_, e.what());
        return false;
      }
      if (steady::now() >= next_log) {
        log_info(*d_logger, "{}: waiting for the emulator ({}); retrying for {} s more",
                 conn_->label(), e.what(), (ms_until(deadline) + 999) / 1000);
        next_log = steady::now() + kWaitLogInterval;
      }
      // Interruptible pause: tb.stop() must not wait for the retry period.
      boost::this_thread::sleep(
          boost::posix_time::milliseconds(std::min(kRetryPauseMs, ms_until(deadline))));
    }
  }
}

bool emulator_source_impl::serve_tick() {
  auto& client = conn_->client();
  const auto deadline = steady::now() + std::chrono::milliseconds(timeout_ms_);
  bool said_waiting = false;
  for (;;) {
    boost::this_thread::interruption_point();
    const RecvStatus st =
        client.wait_tick(have_tick_ ? std::min(kPollSliceMs, ms_until(deadline)) : kPollSliceMs);
    if (st == RecvStatus::kOk) break;
    if (st == RecvStatus::kClosed) {
      leave(
          "the emulator closed the connection (it stopped, or dropped this node for a late "
          "answer)");
      return false;
    }
    if (st == RecvStatus::kMalformed) {
      leave("unexpected message from the emulator");
      return false;
    }
    if (steady::now() < deadline) continue;
    if (have_tick_) {
      leave("no tick for " + std::to_string(timeout_ms_) + " ms");
      return false;
    }
    // Before its first tick a run may legitimately wait (for every external
    // node to join): no timeout then; a vanished emulator closes the socket.
    if (!said_waiting) {
      said_waiting = true;
      log_info(*d_logger, "{}: joined; waiting for the run to start ticking", conn_->label());
    }
  }
  const auto& tick = client.tick();

  // Answer first: the emulator is waiting for every node before it can mix
  // this tick, so bookkeeping comes after.
  const std::size_t n = conn_->take_tx(tx_.data(), tx_.size());
  // Counted before sending, so that an emulator that has the answer also
  // finds it in the counters.
  ++ticks_;
  tx_samples_sent_ += n;
  if (!client.send_tx({tx_.data(), n})) {
    leave("sending tick " + std::to_string(tick.index) + " failed (" + std::to_string(n) +
          " transmit samples lost)");
    return false;
  }

  if (have_tick_ && !tick.follows_previous) {
    ++discontinuities_;
    tag_next_ = true;
    log_warn(*d_logger, "{}: tick {} after tick {}: {} ticks missed, rx stream re-tagged",
             conn_->label(), tick.index, last_tick_,
             tick.index > last_tick_ ? tick.index - last_tick_ - 1 : 0);
  }
  have_tick_ = true;
  last_tick_ = tick.index;

  if (!tick.rx.empty()) {
    pending_.assign(tick.rx.begin(), tick.rx.end());
    pending_pos_ = 0;
    // kTick k carries the samples of tick k-1, which end where tick k starts.
    pending_tag_ = tag_next_;
    pending_time_ = tick.time >= tick.rx.size() ? tick.time - tick.rx.size() : 0;
    tag_next_ = false;
  }
  return true;
}

void emulator_source_impl::add_time_tags(std::uint64_t offset, std::uint64_t virtual_time) {
  const double fs = sample_rate_hz_;
  // Whole seconds in integers so that long runs keep full precision.
  const auto fs_int = static_cast<std::uint64_t>(fs);
  std::uint64_t full = 0;
  double frac = 0.0;
  if (static_cast<double>(fs_int) == fs) {
    full = virtual_time / fs_int;
    frac = static_cast<double>(virtual_time % fs_int) / fs;
  } else {
    const double secs = static_cast<double>(virtual_time) / fs;
    full = static_cast<std::uint64_t>(std::floor(secs));
    frac = secs - static_cast<double>(full);
  }
  static const pmt::pmt_t kRxTime = pmt::mp("rx_time");
  static const pmt::pmt_t kRxRate = pmt::mp("rx_rate");
  add_item_tag(0, offset, kRxTime, pmt::make_tuple(pmt::from_uint64(full), pmt::from_double(frac)),
               alias_pmt());
  add_item_tag(0, offset, kRxRate, pmt::from_double(fs), alias_pmt());
}

int emulator_source_impl::work(int noutput_items, gr_vector_const_void_star& /*input_items*/,
                               gr_vector_void_star& output_items) {
  auto* out = static_cast<gr_complex*>(output_items[0]);
  while (pending_pos_ == pending_.size()) {
    if (!conn_->client().connected() && !join()) {
      finished_ = true;
      conn_->set_finished(true);
      return WORK_DONE;
    }
    serve_tick();  // on failure the connection is closed and the loop rejoins
  }
  if (pending_pos_ == 0 && pending_tag_) {
    add_time_tags(nitems_written(0), pending_time_);
    pending_tag_ = false;
  }
  // At most one tick per call: downstream sees the samples as soon as the
  // emulator delivered them.
  const std::size_t n =
      std::min(static_cast<std::size_t>(noutput_items), pending_.size() - pending_pos_);
  std::copy_n(pending_.begin() + static_cast<std::ptrdiff_t>(pending_pos_), n, out);
  pending_pos_ += n;
  return static_cast<int>(n);
}

}  // namespace gr::rfsitl
