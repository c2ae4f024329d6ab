#include "node_streamer.hpp"

#include <SoapySDR/Logger.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace rfsitl::soapy {
namespace {

/// How long the pump waits for a tick before it looks at stopping_ again.
constexpr int kPumpPollMs = 100;
/// Pause between attempts to join again; an attempt where no emulator listens
/// fails at once, so this is what a lost device costs.
constexpr auto kRejoinPause = std::chrono::milliseconds(200);
/// A rejoin's handshake: a live emulator answers at once, and the destructor
/// waits for an attempt in flight.
constexpr int kRejoinHandshakeMs = 1000;

/// RX capacity: at least two ticks, so that the pump can queue one while the
/// reader takes another.
std::size_t rx_capacity(const external::Welcome& w, double rx_buffer_s) {
  return std::max<std::size_t>(2 * std::size_t{w.tick_samples},
                               static_cast<std::size_t>(rx_buffer_s * w.sample_rate_hz));
}

}  // namespace

NodeStreamer::NodeStreamer(Settings settings)
    : ConnectedClient(settings.socket_path, settings.node_id, settings.program, !settings.takeover),
      StreamBuffers(welcome.sample_rate_hz, rx_capacity(welcome, settings.rx_buffer_s),
                    std::max<std::size_t>(2, settings.tx_queue_ticks) * welcome.tick_samples),
      settings_(std::move(settings)) {
  thread_ = std::thread([this] { pump(); });
}

NodeStreamer::~NodeStreamer() {
  stopping_.store(true);
  thread_.join();
  client.disconnect();
}

long long NodeStreamer::to_ns(SampleTime t) const {
  return std::llround(static_cast<double>(t) * 1e9 / welcome.sample_rate_hz);
}

SampleTime NodeStreamer::to_samples(long long ns) const {
  return std::llround(static_cast<double>(ns) * welcome.sample_rate_hz / 1e9);
}

std::string NodeStreamer::link_state() const {
  std::lock_guard lock(state_mutex_);
  return state_;
}

void NodeStreamer::set_state(std::string state) {
  std::lock_guard lock(state_mutex_);
  state_ = std::move(state);
}

void NodeStreamer::pump() {
  std::vector<cf32> tx(welcome.tick_samples);
  while (!stopping_.load()) {
    if (!client.connected() && !rejoin()) return;
    const external::RecvStatus st = client.wait_tick(kPumpPollMs);
    if (st == external::RecvStatus::kTimeout) continue;
    if (st != external::RecvStatus::kOk) {
      lose(st == external::RecvStatus::kClosed ? "the emulator closed the connection"
                                               : "unexpected message from the emulator");
      continue;
    }
    const external::Tick& tick = client.tick();
    if (reopen_at_next_tick_) {
      // The new emulator's virtual time, from its first tick on.
      reopen(static_cast<SampleTime>(tick.time));
      reopen_at_next_tick_ = false;
      set_state("connected");
    }
    on_tick(static_cast<SampleTime>(tick.time), tick.rx, tx);
    external::TxReport report;
    report.rx_overflows = overflows() - overflows_at_join_;
    if (!client.send_tx(tx, report)) lose("the emulator closed the connection");
  }
}

void NodeStreamer::lose(const std::string& why) {
  SoapySDR::logf(SOAPY_SDR_WARNING, "rfsitl node %u: %s; rejoining when %s serves it again",
                 unsigned{settings_.node_id}, why.c_str(), settings_.socket_path.c_str());
  client.disconnect();
  set_state("rejoining: " + why);
  close();
}

bool NodeStreamer::rejoin() {
  external::ExternalClient::Settings s{settings_.socket_path, settings_.node_id,  "samples",
                                       settings_.program,     kRejoinHandshakeMs, true};
  std::string last_refusal;
  while (!stopping_.load()) {
    client = external::ExternalClient(s);
    try {
      const external::Welcome& w = client.connect();
      if (w.sample_rate_hz != welcome.sample_rate_hz || w.tick_samples != welcome.tick_samples) {
        client.disconnect();
        const std::string why = "the emulator at " + settings_.socket_path + " now runs " +
                                std::to_string(w.sample_rate_hz) + " samples/s, " +
                                std::to_string(w.tick_samples) + " per tick; this device has " +
                                std::to_string(welcome.sample_rate_hz) + " and " +
                                std::to_string(welcome.tick_samples) + ": make a new device";
        SoapySDR::logf(SOAPY_SDR_ERROR, "rfsitl node %u: %s", unsigned{settings_.node_id},
                       why.c_str());
        set_state("stopped: " + why);
        return false;
      }
      overflows_at_join_ = overflows();
      reopen_at_next_tick_ = true;
      rejoins_.fetch_add(1);
      SoapySDR::logf(SOAPY_SDR_INFO, "rfsitl node %u: joined %s again", unsigned{settings_.node_id},
                     settings_.socket_path.c_str());
      return true;
    } catch (const external::ConnectRejected& e) {
      // Refused (the node is held by a program that took it over, or the new
      // emulator has no such node): said once per reason, tried again, since
      // the emulator may yet be restarted with another scenario.
      if (e.reason() != last_refusal) {
        SoapySDR::logf(SOAPY_SDR_WARNING, "rfsitl node %u: cannot rejoin: %s",
                       unsigned{settings_.node_id}, e.reason().c_str());
        last_refusal = e.reason();
        set_state("rejoining: refused: " + e.reason());
      }
    } catch (const std::exception&) {
      // No emulator listening (yet): the usual case while it restarts.
    }
    std::this_thread::sleep_for(kRejoinPause);
  }
  return false;
}

}  // namespace rfsitl::soapy
