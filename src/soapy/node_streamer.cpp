#include "node_streamer.hpp"

#include <SoapySDR/Logger.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace rfsitl::soapy {
namespace {

/// How long the pump waits for a tick before it looks at stopping_ again.
constexpr int kPumpPollMs = 100;

/// RX capacity: at least two ticks, so that the pump can queue one while the
/// reader takes another.
std::size_t rx_capacity(const external::Welcome& w, double rx_buffer_s) {
  return std::max<std::size_t>(2 * std::size_t{w.tick_samples},
                               static_cast<std::size_t>(rx_buffer_s * w.sample_rate_hz));
}

}  // namespace

NodeStreamer::NodeStreamer(Settings settings)
    : ConnectedClient(settings.socket_path, settings.node_id, settings.program),
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

void NodeStreamer::pump() {
  std::vector<cf32> tx(welcome.tick_samples);
  while (!stopping_.load()) {
    const external::RecvStatus st = client.wait_tick(kPumpPollMs);
    if (st == external::RecvStatus::kTimeout) continue;
    if (st != external::RecvStatus::kOk) {
      return close_with(st == external::RecvStatus::kClosed
                            ? "the emulator closed the connection"
                            : "unexpected message from the emulator");
    }
    const external::Tick& tick = client.tick();
    on_tick(static_cast<SampleTime>(tick.time), tick.rx, tx);
    if (!client.send_tx(tx)) return close_with("the emulator closed the connection");
  }
}

void NodeStreamer::close_with(const std::string& why) {
  SoapySDR::logf(SOAPY_SDR_WARNING, "rfsitl node %u: %s", unsigned{settings_.node_id}, why.c_str());
  close();
}

}  // namespace rfsitl::soapy
