#include "rfsitl/external/client/message_channel.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfsitl::external {
namespace {

struct ChannelPair {
  MessageChannel a;
  MessageChannel b;
};

ChannelPair make_channel_pair() {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds) != 0) {
    throw std::runtime_error("socketpair failed");
  }
  return ChannelPair{MessageChannel(fds[0]), MessageChannel(fds[1])};
}

/// Sends `bytes` as one datagram, bypassing MessageChannel::send's framing.
bool send_raw(const MessageChannel& ch, const std::vector<std::uint8_t>& bytes) {
  return ::send(ch.fd(), bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
         static_cast<ssize_t>(bytes.size());
}

/// A datagram made of `header` followed by `body_bytes` bytes of filler.
std::vector<std::uint8_t> datagram(const MsgHeader& header, std::size_t body_bytes) {
  std::vector<std::uint8_t> bytes(sizeof header + body_bytes, 0x5A);
  std::memcpy(bytes.data(), &header, sizeof header);
  return bytes;
}

bool same_bits(std::span<const cf32> x, std::span<const cf32> y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size_bytes()) == 0;
}

TEST(ExternalMessageChannel, RoundTripsHeaderSamplesAndExtraBitExactly) {
  auto [a, b] = make_channel_pair();
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kRxResult);
  h.flags = 0xA5C3;
  h.tick = 0x0123456789ABCDEFULL;
  h.time = 0xFEDCBA9876543210ULL;
  h.count = 999;         // send() must replace these with the spans' sizes
  h.extra_bytes = 4321;  //
  using lim = std::numeric_limits<float>;
  const std::vector<cf32> samples = {{1.0F, -2.5F},
                                     {-0.0F, 0.0F},
                                     {lim::denorm_min(), -lim::max()},
                                     {lim::infinity(), lim::quiet_NaN()},
                                     {3.14159F, -1e-30F}};
  std::vector<std::uint8_t> extra(256);
  for (std::size_t i = 0; i < extra.size(); ++i) extra[i] = static_cast<std::uint8_t>(255 - i);

  ASSERT_TRUE(a.send(h, samples, extra));
  Message m;
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);

  EXPECT_EQ(m.header.magic, kMagic);
  EXPECT_EQ(m.type(), MsgType::kRxResult);
  EXPECT_EQ(m.header.flags, h.flags);
  EXPECT_EQ(m.header.tick, h.tick);
  EXPECT_EQ(m.header.time, h.time);
  EXPECT_EQ(m.header.count, samples.size());
  EXPECT_EQ(m.header.extra_bytes, extra.size());
  EXPECT_TRUE(same_bits(m.samples, samples)) << "samples are not bit-identical";
  EXPECT_EQ(m.extra, extra);
}

TEST(ExternalMessageChannel, ReusedMessageTakesTheSizesOfEachNewMessage) {
  auto [a, b] = make_channel_pair();
  const std::vector<cf32> many(100, cf32{1.0F, 1.0F});
  const std::vector<std::uint8_t> text = {'h', 'i'};
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTick);
  ASSERT_TRUE(a.send(h, many, text));
  h.tick = 1;
  ASSERT_TRUE(a.send(h));  // neither samples nor extra
  h.tick = 2;
  const std::vector<cf32> few = {{0.5F, -0.5F}};
  ASSERT_TRUE(a.send(h, few));

  Message m;
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_EQ(m.samples.size(), many.size());
  EXPECT_EQ(m.extra_text(), "hi");
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_EQ(m.header.tick, 1U);
  EXPECT_TRUE(m.samples.empty());
  EXPECT_TRUE(m.extra.empty());
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_EQ(m.header.tick, 2U);
  EXPECT_TRUE(same_bits(m.samples, few));
  EXPECT_TRUE(m.extra.empty());
}

TEST(ExternalMessageChannel, TheLargestExternalTickFitsInOneMessage) {
  // wire_protocol.hpp: kMaxMessageBytes bounds B at kMaxExternalTickSamples.
  ASSERT_LE(sizeof(MsgHeader) + kMaxExternalTickSamples * sizeof(cf32), kMaxMessageBytes);
  auto [a, b] = make_channel_pair();
  std::vector<cf32> samples(kMaxExternalTickSamples);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    samples[i] = cf32{static_cast<float>(i), -static_cast<float>(i) * 0.5F};
  }
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTx);
  ASSERT_TRUE(a.send(h, samples));
  Message m;
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_TRUE(same_bits(m.samples, samples));
}

TEST(ExternalMessageChannel, ReceiveTimesOutWhenNothingIsSentAndTheChannelStaysUsable) {
  auto [a, b] = make_channel_pair();
  Message m;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(b.receive(m, 30), RecvStatus::kTimeout);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(25));
  EXPECT_TRUE(b.is_open());

  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTx);
  h.tick = 17;
  ASSERT_TRUE(a.send(h));
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_EQ(m.type(), MsgType::kTx);
  EXPECT_EQ(m.header.tick, 17U);
}

TEST(ExternalMessageChannel, MessagesSentBeforeThePeerClosedArriveThenReceiveGivesClosed) {
  // The hub relies on this: it sends kReject and closes at once.
  auto [a, b] = make_channel_pair();
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kReject);
  const std::string why = "go away";
  ASSERT_TRUE(a.send(h, {}, {reinterpret_cast<const std::uint8_t*>(why.data()), why.size()}));
  a.close();
  EXPECT_FALSE(a.is_open());

  Message m;
  ASSERT_EQ(b.receive(m, 1000), RecvStatus::kOk);
  EXPECT_EQ(m.extra_text(), why);
  EXPECT_EQ(b.receive(m, 1000), RecvStatus::kClosed);
  EXPECT_FALSE(b.is_open());
  EXPECT_EQ(b.receive(m, 1000), RecvStatus::kClosed);  // and stays closed
}

TEST(ExternalMessageChannel, SendToAClosedPeerFailsAndClosesTheChannel) {
  auto [a, b] = make_channel_pair();
  b.close();
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTick);
  EXPECT_FALSE(a.send(h));  // EPIPE, and no SIGPIPE kills the test
  EXPECT_FALSE(a.is_open());
  EXPECT_FALSE(a.send(h));
}

TEST(ExternalMessageChannel, DatagramWithAWrongMagicIsMalformed) {
  auto [a, b] = make_channel_pair();
  MsgHeader h;
  h.magic = kMagic ^ 0x01000000U;
  h.type = static_cast<std::uint16_t>(MsgType::kTick);
  ASSERT_TRUE(send_raw(a, datagram(h, 0)));
  Message m;
  EXPECT_EQ(b.receive(m, 1000), RecvStatus::kMalformed);
}

TEST(ExternalMessageChannel, DatagramWhoseSizesDoNotAddUpIsMalformed) {
  struct Case {
    const char* what;
    std::uint32_t count;
    std::uint32_t extra_bytes;
    std::size_t body_bytes;  // bytes actually sent after the header
  };
  const Case cases[] = {
      {"one sample missing", 2, 0, 1 * sizeof(cf32)},
      {"one extra byte missing", 0, 5, 4},
      {"one byte too many", 1, 3, sizeof(cf32) + 4},
      {"body without a count", 0, 0, sizeof(cf32)},
      {"count far beyond the datagram", 0xFFFFFFFFU, 0, 2 * sizeof(cf32)},
      {"sizes whose 32-bit sum would wrap", 0x20000000U, 0xFFFFFFFFU, 0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    auto [a, b] = make_channel_pair();
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kTx);
    h.count = c.count;
    h.extra_bytes = c.extra_bytes;
    ASSERT_TRUE(send_raw(a, datagram(h, c.body_bytes)));
    Message m;
    EXPECT_EQ(b.receive(m, 1000), RecvStatus::kMalformed);
  }
}

TEST(ExternalMessageChannel, DatagramShorterThanAHeaderIsMalformed) {
  auto [a, b] = make_channel_pair();
  ASSERT_TRUE(send_raw(a, std::vector<std::uint8_t>(sizeof(MsgHeader) - 1, 0)));
  Message m;
  EXPECT_EQ(b.receive(m, 1000), RecvStatus::kMalformed);
}

TEST(ExternalMessageChannel, DatagramLargerThanTheMessageLimitIsMalformed) {
  auto [a, b] = make_channel_pair();
  const int sndbuf = 1 << 20;  // room for one datagram above kMaxMessageBytes
  ASSERT_EQ(::setsockopt(a.fd(), SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf), 0);
  const std::size_t extra = kMaxMessageBytes - sizeof(MsgHeader) + 8;
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTx);
  h.extra_bytes = static_cast<std::uint32_t>(extra);  // consistent, only too big
  ASSERT_TRUE(send_raw(a, datagram(h, extra)));
  Message m;
  EXPECT_EQ(b.receive(m, 1000), RecvStatus::kMalformed);
}

TEST(ExternalMessageChannel, ConnectToAPathWithoutAnEmulatorThrowsNamingThePath) {
  const std::string path = "/tmp/rfsitl-ut-nobody-listens-" + std::to_string(::getpid()) + ".sock";
  ::unlink(path.c_str());
  try {
    MessageChannel::connect_to(path);
    FAIL() << "connect_to succeeded without a listener";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfsitl::external
