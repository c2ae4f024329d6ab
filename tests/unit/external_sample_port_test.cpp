/// The role "samples" proxy (make_sample_port_transceiver) against a program
/// thread that speaks the protocol through ExternalClient, as a GNU Radio block does.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "external_samples_hub.hpp"
#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/external_transceivers.hpp"

namespace rfsitl::external {
namespace {

using testing::JoiningThread;
using testing::SocketPath;
using testing::wait_until;

constexpr std::uint32_t kB = 64;  // tick samples
constexpr NodeId kNode = 5;
constexpr int kProgramWaitMs = 3000;

/// What the program saw in one kTick.
struct SeenTick {
  std::uint64_t index = 0;
  std::uint64_t time = 0;
  std::vector<cf32> rx;
  bool follows_previous = false;
};

/// The external program: answers every tick with reply(tick index) until the
/// emulator drops it or stays silent for kProgramWaitMs. A reply longer than
/// B goes out raw (ExternalClient::send_tx refuses it).
class Program {
 public:
  using Reply = std::function<std::vector<cf32>(std::uint64_t tick)>;

  Program(ExternalClient& client, Reply reply)
      : client_(client), reply_(std::move(reply)), thread_([this] { run(); }) {}

  void join() { thread_.join(); }

  std::vector<SeenTick> seen() const {
    std::lock_guard lock(mutex_);
    return seen_;
  }
  RecvStatus last_status() const {
    std::lock_guard lock(mutex_);
    return last_status_;
  }

 private:
  void run() {
    for (;;) {
      const RecvStatus st = client_.wait_tick(kProgramWaitMs);
      if (st != RecvStatus::kOk) {
        std::lock_guard lock(mutex_);
        last_status_ = st;
        return;
      }
      const Tick& t = client_.tick();
      {
        std::lock_guard lock(mutex_);
        seen_.push_back(SeenTick{t.index, t.time, {t.rx.begin(), t.rx.end()}, t.follows_previous});
      }
      const std::vector<cf32> tx = reply_(t.index);
      if (tx.size() > client_.welcome().tick_samples) {
        MsgHeader h;
        h.type = static_cast<std::uint16_t>(MsgType::kTx);
        h.tick = t.index;
        h.time = t.time;
        client_.channel().send(h, tx);
      } else {
        client_.send_tx(tx);
      }
    }
  }

  ExternalClient& client_;
  Reply reply_;
  mutable std::mutex mutex_;
  std::vector<SeenTick> seen_;
  RecvStatus last_status_ = RecvStatus::kOk;
  JoiningThread thread_;  // last: joined before the members it uses go away
};

/// Distinct non-zero samples, different per tick.
cf32 pattern(std::uint64_t tick, std::size_t i) {
  return {static_cast<float>(tick) + 0.25F, static_cast<float>(i + 1)};
}
std::vector<cf32> pattern_block(std::uint64_t tick, std::size_t n) {
  std::vector<cf32> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = pattern(tick, i);
  return v;
}

struct Fixture : testing::SamplesHub {
  Fixture() : SamplesHub(kNode, kB) {}

  ExternalClient::Settings client_settings() const {
    ExternalClient::Settings s;
    s.socket_path = path.str();
    s.node_id = kNode;
    s.role = "samples";
    s.handshake_timeout_ms = 3000;
    return s;
  }

  /// The engine's TX phase for this node: begin_tick, then transmit (the
  /// proxy is always tx_busy). `out` starts as garbage that must be overwritten.
  std::size_t tx_phase(std::uint64_t tick, std::vector<cf32>& out) {
    port->begin_tick(tick, static_cast<SampleTime>(tick * kB));
    EXPECT_TRUE(port->tx_busy());
    out.assign(kB, cf32{-99.0F, 99.0F});
    return port->transmit(out);
  }
};

class NoDecodes final : public phy::RxHandler {
 public:
  void on_rx(const phy::RxEvent&) override { ++count; }
  int count = 0;
};

bool all_zero(std::span<const cf32> x) {
  return std::all_of(x.begin(), x.end(), [](cf32 v) { return v == cf32{}; });
}

TEST(ExternalSamplePort, ProxyIsRemoteAndNeverTakesFramesFromTheEmulator) {
  Fixture f;
  EXPECT_TRUE(f.port->remote());
  EXPECT_EQ(f.port->max_payload(), 0U);  // so the engine never starts a frame on it
  EXPECT_TRUE(f.port->tx_busy());
  EXPECT_TRUE(f.port->rx_busy());
}

TEST(ExternalSamplePort, ExchangesBSamplesPerTickWithTheProgramInLockStep) {
  Fixture f;
  ExternalClient client(f.client_settings());
  client.connect();
  ASSERT_TRUE(wait_until([&] { return f.hub->never_joined().empty(); }));

  constexpr std::uint64_t k0 = 10;
  constexpr std::size_t kShort = 40;  // reply of tick k0+1: < B samples
  constexpr std::size_t kLastNonZero = 36;
  constexpr std::size_t kOversize = kB + 1;
  const Program::Reply reply = [&](std::uint64_t tick) -> std::vector<cf32> {
    switch (tick - k0) {
      case 0:
        return pattern_block(tick, kB);
      case 1: {
        // A burst that ends before the reply does, with a zero inside it.
        auto v = pattern_block(tick, kShort);
        v[5] = cf32{};
        std::fill(v.begin() + kLastNonZero + 1, v.end(), cf32{});
        return v;
      }
      case 2:
        return {};
      default:
        return pattern_block(tick, kOversize);
    }
  };
  Program program(client, reply);
  NoDecodes decodes;
  std::vector<cf32> out;

  // Tick k0, the first after joining: the program gets no rx samples; it
  // transmits B, so the engine blanks this node's receiver for the whole tick
  // (no receive() call).
  EXPECT_EQ(f.tx_phase(k0, out), kB);
  EXPECT_EQ(out, pattern_block(k0, kB));
  EXPECT_EQ(f.link->joins(), 1U);

  // Tick k0+1: a short reply is zero-padded; the signal ends at its last
  // non-zero sample. The receiver gets the tail after it.
  EXPECT_EQ(f.tx_phase(k0 + 1, out), kLastNonZero + 1);
  std::vector<cf32> expected = reply(k0 + 1);
  expected.resize(kB, cf32{});
  EXPECT_EQ(out, expected);
  const std::vector<cf32> tail = pattern_block(1000, kB - (kLastNonZero + 1));
  f.port->receive(tail, decodes);

  // Tick k0+2: an empty reply is silence; the receiver gets the whole tick.
  EXPECT_EQ(f.tx_phase(k0 + 2, out), 0U);
  EXPECT_TRUE(all_zero(out));
  const std::vector<cf32> full = pattern_block(2000, kB);
  f.port->receive(full, decodes);

  // Tick k0+3: B+1 samples break the protocol: the link drops, the node is silent.
  EXPECT_EQ(f.tx_phase(k0 + 3, out), 0U);
  EXPECT_TRUE(all_zero(out));
  EXPECT_FALSE(f.link->connected());
  EXPECT_EQ(f.link->drops(), 1U);
  EXPECT_EQ(f.link->timeouts(), 0U);

  program.join();
  EXPECT_EQ(program.last_status(), RecvStatus::kClosed) << "the program should see the drop";
  EXPECT_EQ(decodes.count, 0) << "the program's decodes never pass through the emulator";
  EXPECT_EQ(client.discontinuities(), 0U);

  const std::vector<SeenTick> seen = program.seen();
  ASSERT_EQ(seen.size(), 4U);
  for (std::size_t j = 0; j < seen.size(); ++j) {
    SCOPED_TRACE("tick k0+" + std::to_string(j));
    EXPECT_EQ(seen[j].index, k0 + j);
    EXPECT_EQ(seen[j].time, (k0 + j) * kB);
    EXPECT_TRUE(seen[j].follows_previous);
  }
  EXPECT_TRUE(seen[0].rx.empty()) << "first tick after joining has no previous tick";
  // Tick k0's receiver was blanked whole: B zeros.
  ASSERT_EQ(seen[1].rx.size(), kB);
  EXPECT_TRUE(all_zero(seen[1].rx));
  // Tick k0+1's tail arrives left-padded with zeros for the transmitted part.
  ASSERT_EQ(seen[2].rx.size(), kB);
  std::vector<cf32> padded(kLastNonZero + 1, cf32{});
  padded.insert(padded.end(), tail.begin(), tail.end());
  EXPECT_EQ(seen[2].rx, padded);
  // Tick k0+2's whole-tick reception arrives unchanged.
  EXPECT_EQ(seen[3].rx, full);

  // While the program is away the node is silent, with no round trip.
  EXPECT_EQ(f.tx_phase(k0 + 4, out), 0U);
  EXPECT_TRUE(all_zero(out));
  EXPECT_EQ(f.link->drops(), 1U);
}

TEST(ExternalSamplePort, ProgramThatRejoinsStartsAgainWithAnEmptyRxBlock) {
  Fixture f;
  ExternalClient client(f.client_settings());
  client.connect();
  ASSERT_TRUE(wait_until([&] { return f.hub->never_joined().empty(); }));
  NoDecodes decodes;
  std::vector<cf32> out;
  const std::vector<cf32> heard = pattern_block(3000, kB);
  {
    // Answers ticks 20 and 21, then the oversized tick 22 gets it dropped.
    Program program(client, [](std::uint64_t tick) {
      return tick < 22 ? std::vector<cf32>{} : pattern_block(tick, kB + 1);
    });
    for (std::uint64_t k = 20; k <= 22; ++k) {
      EXPECT_EQ(f.tx_phase(k, out), 0U);
      f.port->receive(heard, decodes);
    }
    program.join();
    EXPECT_FALSE(f.link->connected());
    const auto seen = program.seen();
    ASSERT_EQ(seen.size(), 3U);
    EXPECT_TRUE(seen[0].rx.empty());
    EXPECT_EQ(seen[1].rx, heard);
    EXPECT_EQ(seen[2].rx, heard);
  }
  // Tick 23 passes without the program (its receive() still fills the block).
  EXPECT_EQ(f.tx_phase(23, out), 0U);
  f.port->receive(heard, decodes);

  // The program connects again; begin_tick() adopts the connection.
  client.connect();
  Program program(client, [](std::uint64_t tick) { return pattern_block(tick, kB); });
  bool joined = false;
  for (int i = 0; i < 3000 && !joined; ++i) {
    f.port->begin_tick(24, 24 * kB);
    joined = f.link->connected();
    if (!joined) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(joined);
  out.assign(kB, cf32{-1.0F, 1.0F});
  EXPECT_EQ(f.port->transmit(out), kB);
  EXPECT_EQ(out, pattern_block(24, kB));
  EXPECT_EQ(f.tx_phase(25, out), kB);
  f.link->drop("test over");
  program.join();

  const auto seen = program.seen();
  ASSERT_EQ(seen.size(), 2U);
  EXPECT_EQ(seen[0].index, 24U);
  EXPECT_TRUE(seen[0].rx.empty()) << "the first tick after rejoining reports no rx samples";
  EXPECT_EQ(seen[1].index, 25U);
  ASSERT_EQ(seen[1].rx.size(), kB);
  EXPECT_TRUE(all_zero(seen[1].rx)) << "tick 24 was blanked whole by the node's own B samples";
  EXPECT_EQ(f.link->joins(), 2U);
}

}  // namespace
}  // namespace rfsitl::external
