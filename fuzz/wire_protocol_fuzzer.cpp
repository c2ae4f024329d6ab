/// External-transceiver protocol (wire_protocol.hpp, message_channel.hpp):
/// every place that decodes a message from the other process.
///
/// Input: [mode byte][mode arguments...]. Modes (mode byte % 9):
///  0  header framing: the rest is one SOCK_SEQPACKET datagram, read back with
///     MessageChannel::receive. kOk only when magic and sizes add up
///     (32 + 8 count + extra_bytes == datagram), and then samples/extra have
///     exactly those sizes; anything else is kMalformed (never kClosed or
///     kTimeout: the datagram is there and the peer is still connected).
///  1  hello, well framed: header kHello + the rest as its JSON, sent to a real
///     ExternalHub (make_external_hub) that declares node 3 (samples) and
///     node 7 (transceiver). The hub must answer kWelcome (valid JSON naming
///     protocol 1 and a declared node) or kReject (non-empty reason).
///  2  hello, raw: the rest as the whole datagram to the same hub (same checks;
///     an empty datagram reads as a close, which may go unanswered).
///  3  welcome/reject, well framed: ExternalClient::connect against a stand-in
///     emulator that answers the hello with header type (byte 1: welcome,
///     reject or other) + the rest as extra. connect() must return a Welcome
///     for the node it asked for or throw std::runtime_error, nothing else;
///     a welcome's "phy" goes through phy_from_json, which must return
///     or throw std::invalid_argument.
///  4  welcome/reject, raw: the rest as the whole answer datagram (same checks).
///  5  kRxResult decoding: the remote-transceiver proxy (make_remote_transceiver
///     over a NodeLink on a socketpair) receives a kRxResult for its tick whose
///     extra is the rest (DecodeRecords + payloads + constellations); every
///     decode it reports must lie inside that extra.
///  6  kTx decoding: the proxy receives a kTx with the rest as samples; it
///     returns at most the tick's samples and fills the rest with zeros.
///  7  discovery (byte 1 even): kDiscover + the rest as its JSON to the hub of
///     mode 1, which must answer kDiscovery listing its two nodes or kReject
///     (non-empty reason); (byte 1 odd): discover() against the stand-in
///     emulator answering kDiscovery + the rest, which must return nodes that
///     read_discovery() checked or throw std::runtime_error naming the socket.
///  8  kTx of the samples role (make_sample_port_transceiver over a NodeLink on
///     a socketpair, a new connection each time): byte 1 = sample count n,
///     then n samples, the rest as extra (a TxReport). A tick with too many
///     samples or an extra that read_tx_report refuses drops the connection
///     and counts nothing; else the node's overflow counter grows by exactly
///     the report's rx_overflows (a new connection counts from 0) and the
///     output is the samples, then zeros.
/// (Modes 1 and 2 accept a kDiscovery answer too: a raw datagram may be a
/// well-formed discovery request.)
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "fuzz_check.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/message_channel.hpp"
#include "rfsitl/external/client/tx_report.hpp"
#include "rfsitl/external/client/wire_protocol.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/external_transceivers.hpp"
#include "rfsitl/external/node_link.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/scenario/scenario.hpp"

using namespace rfsitl;
using namespace rfsitl::external;

namespace {

constexpr int kReplyTimeoutMs = 3000;
constexpr std::uint32_t kTickSamples = 256;

std::vector<std::uint8_t> framed(MsgType type, std::uint16_t flags, std::uint64_t tick,
                                 const std::uint8_t* extra, std::size_t n) {
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(type);
  h.flags = flags;
  h.tick = tick;
  h.extra_bytes = static_cast<std::uint32_t>(n);
  std::vector<std::uint8_t> out(sizeof h + n);
  std::memcpy(out.data(), &h, sizeof h);
  if (n > 0) std::memcpy(out.data() + sizeof h, extra, n);
  return out;
}

void send_raw(int fd, const std::vector<std::uint8_t>& d) {
  const ssize_t n = ::send(fd, d.data(), d.size(), MSG_NOSIGNAL);
  FUZZ_CHECK(n == static_cast<ssize_t>(d.size()), "send of %zu bytes: %zd (%s)", d.size(), n,
             std::strerror(errno));
}

std::string socket_path(const char* what) {
  return "/tmp/rfsitl-fuzz-" + std::to_string(::getpid()) + "-" + what + ".sock";
}

// ---- mode 0 ------------------------------------------------------------------------

void header_framing(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;  // an empty datagram is indistinguishable from a close
  int fds[2];
  FUZZ_CHECK(::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds) == 0, "socketpair");
  MessageChannel ch(fds[0]);
  send_raw(fds[1], std::vector<std::uint8_t>(data, data + size));
  Message m;
  const RecvStatus st = ch.receive(m, 0);
  ::close(fds[1]);
  MsgHeader h;
  const bool whole_header = size >= sizeof h;
  if (whole_header) std::memcpy(&h, data, sizeof h);
  const bool valid = whole_header && h.magic == kMagic &&
                     sizeof h + std::uint64_t{h.count} * sizeof(cf32) + h.extra_bytes == size;
  if (valid) {
    FUZZ_CHECK(st == RecvStatus::kOk, "valid message not accepted (status %d)", int(st));
    FUZZ_CHECK(std::memcmp(&m.header, &h, sizeof h) == 0, "header differs");
    FUZZ_CHECK(m.samples.size() == h.count && m.extra.size() == h.extra_bytes, "sizes differ");
    FUZZ_CHECK(m.extra.empty() ||
                   std::memcmp(m.extra.data(), data + size - h.extra_bytes, h.extra_bytes) == 0,
               "extra differs");
  } else {
    FUZZ_CHECK(st == RecvStatus::kMalformed, "invalid message: status %d", int(st));
  }
}

// ---- modes 1, 2: the hub ------------------------------------------------------------

ExternalHub& hub() {
  static ExternalHub* h = [] {
    HubSettings s;
    s.socket_path = socket_path("hub");
    std::vector<ExternalNodeSpec> nodes(2);
    nodes[0] = {0, 3, Role::kSamples, ""};
    nodes[1] = {1, 7, Role::kTransceiver, phy_to_json("gmsk", scenario::PhyChoice{}.settings)};
    return make_external_hub(s, nodes).release();  // lives until exit
  }();
  return *h;
}

void hello(const std::vector<std::uint8_t>& datagram) {
  MessageChannel ch = MessageChannel::connect_to(hub().socket_path());
  send_raw(ch.fd(), datagram);
  Message reply;
  const RecvStatus st = ch.receive(reply, kReplyTimeoutMs);
  if (datagram.empty() && st == RecvStatus::kClosed) return;
  FUZZ_CHECK(st == RecvStatus::kOk, "hub did not answer a hello (status %d)", int(st));
  if (reply.type() == MsgType::kReject) {
    FUZZ_CHECK(!reply.extra.empty(), "reject without a reason");
    return;
  }
  if (reply.type() == MsgType::kDiscovery) {
    try {
      const auto nodes = read_discovery(reply.extra_text());
      FUZZ_CHECK(nodes.size() == 2 && nodes[0].node_id == 3 && nodes[1].node_id == 7,
                 "discovery lists %zu nodes", nodes.size());
    } catch (const HandshakeError& e) {
      FUZZ_CHECK(false, "hub's own discovery answer does not read: %s", e.what());
    }
    return;
  }
  FUZZ_CHECK(reply.type() == MsgType::kWelcome, "hub answered type %u", reply.header.type);
  const auto j = nlohmann::json::parse(reply.extra_text(), nullptr, false);
  FUZZ_CHECK(j.is_object() && j.value("protocol", 0) == kProtocolVersion, "bad welcome %s",
             reply.extra_text().c_str());
  const unsigned id = j.value("node_id", 0U);
  FUZZ_CHECK(id == 3 || id == 7, "welcome for undeclared node %u", id);
  FUZZ_CHECK(j.contains("phy") == (id == 7), "phy in the welcome of node %u: %d", id,
             j.contains("phy"));
}

// ---- modes 3, 4: the client against a stand-in emulator ------------------------------

class StandInEmulator {
 public:
  StandInEmulator() : path_(socket_path("emu")) {
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path_.c_str(), path_.size() + 1);
    ::unlink(path_.c_str());
    fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    FUZZ_CHECK(fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
                   ::listen(fd_, 8) == 0,
               "stand-in emulator cannot listen on %s", path_.c_str());
    thread_ = std::thread([this] { serve(); });
    thread_.detach();  // lives until exit
  }
  const std::string& path() const { return path_; }
  void set_answer(std::vector<std::uint8_t> a) {
    std::lock_guard lock(mutex_);
    answer_ = std::move(a);
  }

 private:
  void serve() {
    for (;;) {
      const int c = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c < 0) continue;
      MessageChannel ch(c);
      Message hello;
      if (ch.receive(hello, kReplyTimeoutMs) == RecvStatus::kOk) {
        std::vector<std::uint8_t> a;
        {
          std::lock_guard lock(mutex_);
          a = answer_;
        }
        ::send(c, a.data(), a.size(), MSG_NOSIGNAL);
      }
    }
  }
  std::string path_;
  int fd_ = -1;
  std::thread thread_;
  std::mutex mutex_;
  std::vector<std::uint8_t> answer_;
};

/// The one stand-in (it owns the "emu" socket path), for modes 3, 4 and 7.
StandInEmulator& stand_in() {
  static StandInEmulator* emu = new StandInEmulator;  // lives until exit
  return *emu;
}

void welcome(std::vector<std::uint8_t> answer) {
  StandInEmulator* emu = &stand_in();
  emu->set_answer(std::move(answer));
  ExternalClient::Settings s;
  s.socket_path = emu->path();
  s.node_id = 5;
  s.role = "transceiver";
  s.handshake_timeout_ms = kReplyTimeoutMs;
  ExternalClient client(s);
  try {
    const Welcome& w = client.connect();
    FUZZ_CHECK(w.node_id == 5, "welcome accepted for node %u", unsigned{w.node_id});
    if (!w.phy_json.empty()) {
      try {
        (void)phy_from_json(w.phy_json);
      } catch (const std::invalid_argument&) {
      }
    }
  } catch (const std::runtime_error& e) {
    FUZZ_CHECK(std::string(e.what()).find(s.socket_path) != std::string::npos,
               "error does not name the socket: %s", e.what());
  }
}

/// The stand-in's answer read by discover() (the SoapySDR module's find).
void discovery_answer(std::vector<std::uint8_t> answer) {
  StandInEmulator* emu = &stand_in();
  emu->set_answer(std::move(answer));
  try {
    for (const auto& n : discover(emu->path(), kReplyTimeoutMs, "fuzz")) {
      FUZZ_CHECK(n.node_id >= kMinNodeId && n.node_id <= kMaxNodeId && n.sample_rate_hz > 0.0 &&
                     n.tick_samples >= 1 && n.tick_samples <= kMaxExternalTickSamples,
                 "discovery accepted node %u", unsigned{n.node_id});
    }
  } catch (const std::runtime_error& e) {
    FUZZ_CHECK(std::string(e.what()).find(emu->path()) != std::string::npos,
               "error does not name the socket: %s", e.what());
  }
}

// ---- modes 5, 6, 8: replies the proxies decode ---------------------------------------

/// Offers `link` a new connection (a socketpair) and lets `radio` adopt it at
/// tick `tick`; returns the program's end, which the caller closes.
int connect_proxy(NodeLink& link, phy::Transceiver& radio, std::uint64_t tick) {
  int fds[2];
  FUZZ_CHECK(::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds) == 0, "socketpair");
  link.offer(MessageChannel(fds[0]), "fuzz");
  radio.begin_tick(tick, static_cast<SampleTime>(tick * kTickSamples));
  FUZZ_CHECK(link.connected(), "offered connection not adopted");
  return fds[1];
}

struct Proxy {
  std::shared_ptr<NodeLink> link = std::make_shared<NodeLink>(7, kReplyTimeoutMs);
  std::unique_ptr<phy::Transceiver> radio = make_remote_transceiver(link, scenario::PhyChoice{});
  std::uint64_t tick = 0;
};

/// Checks that the decodes a kRxResult yields fit in its extra, and touches every
/// byte of their spans so that ASan checks they lie in live memory.
struct DecodeBounds final : phy::RxHandler {
  std::size_t extra_size = 0;
  std::size_t used = 0;
  void on_rx(const phy::RxEvent& ev) override {
    used += sizeof(DecodeRecord) + ev.payload.size() + ev.symbols.size_bytes();
    FUZZ_CHECK(used <= extra_size, "decodes cover %zu bytes of a %zu-byte extra", used, extra_size);
    volatile std::uint8_t sink = 0;
    for (const std::uint8_t x : ev.payload) sink = static_cast<std::uint8_t>(sink ^ x);
    for (const cf32 z : ev.symbols) sink = static_cast<std::uint8_t>(sink ^ (z.real() > 0));
  }
};

void proxy_reply(bool rx, const std::uint8_t* data, std::size_t size) {
  static Proxy* p = new Proxy;
  if (size == 0) return;
  const std::uint16_t flags = data[0];
  ++data;
  --size;
  const int peer = connect_proxy(*p->link, *p->radio, ++p->tick);
  std::vector<std::uint8_t> reply;
  if (rx) {
    reply = framed(MsgType::kRxResult, flags, p->tick, data, size);
  } else {
    const std::size_t n = size / sizeof(cf32);
    reply = framed(MsgType::kTx, flags, p->tick, nullptr, 0);
    MsgHeader h;
    std::memcpy(&h, reply.data(), sizeof h);
    h.count = static_cast<std::uint32_t>(n);
    std::memcpy(reply.data(), &h, sizeof h);
    reply.insert(reply.end(), data, data + n * sizeof(cf32));
  }
  send_raw(peer, reply);
  if (rx) {
    const std::vector<cf32> in(kTickSamples);
    DecodeBounds h;
    h.extra_size = size;
    p->radio->receive(in, h);
  } else {
    std::vector<cf32> out(kTickSamples, cf32{1.0F, 1.0F});
    const std::size_t n = p->radio->transmit(out);
    FUZZ_CHECK(n <= out.size(), "transmit returned %zu of %zu", n, out.size());
    for (std::size_t i = n; i < out.size(); ++i) {
      FUZZ_CHECK(out[i] == cf32{}, "sample %zu after the %zu sent is not zero", i, n);
    }
    if (size / sizeof(cf32) > kTickSamples) {
      FUZZ_CHECK(n == 0 && !p->link->connected(), "oversized kTx not refused");
    }
  }
  ::close(peer);
}

void samples_reply(const std::uint8_t* data, std::size_t size) {
  struct Port {
    std::shared_ptr<NodeLink> link = std::make_shared<NodeLink>(3, kReplyTimeoutMs);
    std::atomic<std::uint64_t> overflows{0};
    std::unique_ptr<phy::Transceiver> radio =
        make_sample_port_transceiver(link, kTickSamples, overflows);
    std::uint64_t tick = 0;
  };
  static Port* p = new Port;
  if (size == 0) return;
  const std::size_t n = std::min<std::size_t>(data[0], (size - 1) / sizeof(cf32));
  const std::uint8_t* samples = data + 1;
  const std::uint8_t* extra = samples + n * sizeof(cf32);
  const std::size_t extra_size = size - 1 - n * sizeof(cf32);
  const int peer = connect_proxy(*p->link, *p->radio, ++p->tick);
  std::vector<std::uint8_t> reply = framed(MsgType::kTx, 0, p->tick, nullptr, 0);
  MsgHeader h;
  std::memcpy(&h, reply.data(), sizeof h);
  h.count = static_cast<std::uint32_t>(n);
  h.extra_bytes = static_cast<std::uint32_t>(extra_size);
  std::memcpy(reply.data(), &h, sizeof h);
  reply.insert(reply.end(), samples, samples + n * sizeof(cf32) + extra_size);
  send_raw(peer, reply);
  // What the proxy must make of it.
  std::optional<TxReport> report;
  bool report_ok = true;
  try {
    report = read_tx_report({extra, extra_size});
  } catch (const TxReportError&) {
    report_ok = false;
  }
  const bool accepted = report_ok && n <= kTickSamples;
  const std::uint64_t before = p->overflows.load();
  std::vector<cf32> out(kTickSamples, cf32{1.0F, 1.0F});
  const std::size_t sent = p->radio->transmit(out);
  const std::uint64_t added = p->overflows.load() - before;
  FUZZ_CHECK(p->link->connected() == accepted, "kTx of %zu samples, %zu extra bytes: %s", n,
             extra_size, accepted ? "dropped" : "not dropped");
  const std::uint64_t expected = accepted && report ? report->rx_overflows : 0;
  FUZZ_CHECK(added == expected, "counter grew by %llu, expected %llu",
             static_cast<unsigned long long>(added), static_cast<unsigned long long>(expected));
  FUZZ_CHECK(sent <= (accepted ? n : 0), "transmit returned %zu for %zu samples", sent, n);
  for (std::size_t i = sent; i < out.size(); ++i) {
    FUZZ_CHECK(out[i] == cf32{}, "sample %zu after the %zu sent is not zero", i, sent);
  }
  if (p->link->connected()) p->link->drop("fuzz: next input");
  ::close(peer);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);  // rejects and drops are logged; not needed here
  std::atexit([] {
    ::unlink(socket_path("hub").c_str());
    ::unlink(socket_path("emu").c_str());
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int mode = data[0] % 9;
  ++data;
  --size;
  switch (mode) {
    case 0:
      header_framing(data, size);
      break;
    case 1:
      hello(framed(MsgType::kHello, 0, 0, data, size));
      break;
    case 2:
      hello(std::vector<std::uint8_t>(data, data + size));
      break;
    case 3: {
      if (size == 0) return 0;
      const MsgType types[4] = {MsgType::kWelcome, MsgType::kWelcome, MsgType::kReject,
                                static_cast<MsgType>(data[0] >> 2)};
      welcome(framed(types[data[0] & 3], 0, 0, data + 1, size - 1));
      break;
    }
    case 4:
      welcome(std::vector<std::uint8_t>(data, data + size));
      break;
    case 5:
      proxy_reply(true, data, size);
      break;
    case 6:
      proxy_reply(false, data, size);
      break;
    case 7:
      if (size == 0) return 0;
      if (data[0] % 2 == 0) {
        hello(framed(MsgType::kDiscover, 0, 0, data + 1, size - 1));
      } else {
        discovery_answer(framed(MsgType::kDiscovery, 0, 0, data + 1, size - 1));
      }
      break;
    case 8:
      samples_reply(data, size);
      break;
  }
  return 0;
}
