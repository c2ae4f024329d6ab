#include "rfsitl/external/transceiver_node.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rfsitl/common/retry_backoff.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::external {
namespace {

/// Serializes decode attempts into a kRxResult's extra bytes.
struct DecodeCollector : phy::RxHandler {
  std::vector<std::uint8_t> bytes;
  void on_rx(const phy::RxEvent& ev) override {
    DecodeRecord r;
    r.serial = ev.tag.serial;
    r.src = ev.tag.src;
    r.dst = ev.tag.dst;
    r.header_valid = ev.header_valid ? 1 : 0;
    r.payload_valid = ev.payload_valid ? 1 : 0;
    r.rssi_db = ev.rssi_db;
    r.evm_db = ev.evm_db;
    r.payload_bytes = static_cast<std::uint32_t>(ev.payload.size());
    r.symbol_count = static_cast<std::uint32_t>(ev.symbols.size());
    const std::size_t at = bytes.size();
    bytes.resize(at + sizeof r + ev.payload.size() + ev.symbols.size_bytes());
    std::memcpy(bytes.data() + at, &r, sizeof r);
    std::copy(ev.payload.begin(), ev.payload.end(), bytes.begin() + at + sizeof r);
    if (!ev.symbols.empty()) {
      std::memcpy(bytes.data() + at + sizeof r + ev.payload.size(), ev.symbols.data(),
                  ev.symbols.size_bytes());
    }
  }
};

std::chrono::milliseconds to_ms(double seconds) {
  return std::chrono::milliseconds(static_cast<std::int64_t>(seconds * 1e3));
}

/// Joins, retrying with exponential backoff until the connect timeout.
/// Returns false if `stop` was set first.
bool connect_with_retry(ExternalClient& client, const TransceiverNodeOptions& o,
                        const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(o.connect_timeout_s));
  RetryBackoff backoff(to_ms(o.retry_first_s), to_ms(o.retry_max_s));
  std::set<std::string> reported;  // refusal reasons already printed
  for (;;) {
    try {
      client.connect();
      return true;
    } catch (const ConnectRejected& e) {
      // The emulator logs its side too, but only this process's user can fix
      // it (the wrong --id, a scenario that gives the node another role).
      if (reported.insert(e.reason()).second) {
        std::fprintf(stderr,
                     "rfsitl node %u: the emulator at %s refused this node: %s (retrying "
                     "with backoff, giving up %g s after start)\n",
                     o.node_id, o.socket_path.c_str(), e.reason().c_str(), o.connect_timeout_s);
      }
      if (Clock::now() >= deadline) throw;
    } catch (const std::runtime_error&) {
      if (Clock::now() >= deadline) throw;
    }
    // Sleep in short slices so that SIGTERM is honoured at once; the last
    // attempt falls on the deadline.
    const Clock::time_point wake =
        std::min<Clock::time_point>(Clock::now() + backoff.next(), deadline);
    while (Clock::now() < wake) {
      if (stop.load(std::memory_order_relaxed)) return false;
      std::this_thread::sleep_for(
          std::min<Clock::duration>(wake - Clock::now(), std::chrono::milliseconds(20)));
    }
    if (stop.load(std::memory_order_relaxed)) return false;
  }
}

}  // namespace

int run_transceiver_node(const TransceiverNodeOptions& o, const std::atomic<bool>& stop) {
  ExternalClient client({o.socket_path, o.node_id, "transceiver", "rfsitl node"});
  if (!connect_with_retry(client, o, stop)) return 0;
  const Welcome& w = client.welcome();
  std::unique_ptr<phy::Transceiver> radio;
  try {
    const PhyRequest request = phy_from_json(w.phy_json);
    radio = phy::make_transceiver(request.type, request.settings);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "rfsitl node %u: %s\n", o.node_id, e.what());
    return 1;
  }
  std::vector<cf32> tx(w.tick_samples);
  DecodeCollector decodes;
  MessageChannel& ch = client.channel();
  Message& msg = client.message();
  const auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "rfsitl node %u: protocol error at tick %llu: %s\n", o.node_id,
                 static_cast<unsigned long long>(msg.header.tick), why.c_str());
    return 1;
  };
  while (!stop.load(std::memory_order_relaxed)) {
    const RecvStatus st = ch.receive(msg, 200);
    if (st == RecvStatus::kTimeout) continue;
    if (st == RecvStatus::kClosed) return 0;
    if (st == RecvStatus::kMalformed) return fail("malformed message");
    MsgHeader reply;
    reply.tick = msg.header.tick;
    reply.time = msg.header.time;
    if (msg.type() == MsgType::kTxRequest) {
      if ((msg.header.flags & kFlagStartFrame) != 0) {
        FrameStart f;
        if (msg.extra.size() < sizeof f) return fail("frame start without a header");
        std::memcpy(&f, msg.extra.data(), sizeof f);
        const std::span<const std::uint8_t> payload(msg.extra.data() + sizeof f,
                                                    msg.extra.size() - sizeof f);
        if (radio->tx_busy() || payload.size() > radio->max_payload()) {
          return fail("frame start while busy or oversized");
        }
        radio->start_frame(phy::FrameTag{f.src, f.dst, f.serial}, payload);
      }
      const std::size_t n = radio->tx_busy() ? radio->transmit(tx) : 0;
      reply.type = static_cast<std::uint16_t>(MsgType::kTx);
      reply.flags = radio->tx_busy() ? kFlagTxBusy : 0;
      if (!ch.send(reply, std::span<const cf32>(tx.data(), n))) return 0;
    } else if (msg.type() == MsgType::kRx) {
      if ((msg.header.flags & kFlagResetReceiver) != 0) radio->reset_receiver();
      decodes.bytes.clear();
      radio->receive(msg.samples, decodes);
      reply.type = static_cast<std::uint16_t>(MsgType::kRxResult);
      reply.flags = radio->rx_busy() ? kFlagRxBusy : 0;
      if (!ch.send(reply, {}, decodes.bytes)) return 0;
    } else {
      return fail(std::string("unexpected ") + message_type_name(msg.header.type));
    }
  }
  return 0;
}

}  // namespace rfsitl::external
