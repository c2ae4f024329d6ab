#include "rfsitl/io/net_framing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace rfsitl::io {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::size_t kLimit = 2048;

Bytes to_bytes(const std::string& s) {
  return Bytes(s.begin(), s.end());
}

Bytes terminator() {
  return Bytes(std::begin(kFrameTerminator), std::end(kFrameTerminator));
}

NetFrame make_frame(NodeId src, NodeId dst, const std::string& payload) {
  return NetFrame{src, dst, to_bytes(payload)};
}

void append(Bytes& out, const Bytes& more) {
  out.insert(out.end(), more.begin(), more.end());
}

struct Output {
  std::vector<NetFrame> frames;
  std::vector<FramingError> errors;
};

// Feeds `stream` in pieces whose sizes cycle through `chunks` (all at once if empty),
// checking the memory bound after every read.
Output feed_in_chunks(NetFrameParser& parser, std::size_t max_payload, const Bytes& stream,
                      const std::vector<std::size_t>& chunks = {}) {
  Output out;
  std::size_t pos = 0;
  std::size_t k = 0;
  while (pos < stream.size()) {
    const std::size_t want = chunks.empty() ? stream.size() : chunks[k++ % chunks.size()];
    const std::size_t n = std::min(want, stream.size() - pos);
    parser.feed(std::span(stream).subspan(pos, n), out.frames, out.errors);
    EXPECT_LE(parser.buffered(), max_payload + 6);
    pos += n;
  }
  return out;
}

TEST(NetFraming, EncodeWritesSrcDstPayloadThenTerminator) {
  const Bytes wire = encode_net_frame(make_frame(3, 7, "hi"));
  EXPECT_EQ(wire, (Bytes{3, 7, 'h', 'i', '\r', '\r', '\n', '\n'}));
}

TEST(NetFraming, EncodeThenParseRoundTripsEveryByteValue) {
  NetFrame frame{12, 34, {}};
  for (int v = 0; v < 256; ++v) frame.payload.push_back(static_cast<std::uint8_t>(v));
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, encode_net_frame(frame));
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame);
  EXPECT_TRUE(out.errors.empty());
  EXPECT_EQ(parser.buffered(), 0u);
}

TEST(NetFraming, EmptyPayloadIsAValidFrame) {
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, encode_net_frame(make_frame(1, 2, "")));
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], make_frame(1, 2, ""));
  EXPECT_TRUE(out.errors.empty());
}

TEST(NetFraming, FrameSplitAtEveryBoundaryIncludingInsideTerminatorIsReassembled) {
  // The payload ends in '\r' so splits near the end also test partial terminators.
  const NetFrame frame = make_frame(5, 9, "payload\r\n\r");
  const Bytes wire = encode_net_frame(frame);
  for (std::size_t a = 0; a <= wire.size(); ++a) {
    for (std::size_t b = a; b <= wire.size(); ++b) {
      NetFrameParser parser(kLimit);
      Output out;
      parser.feed(std::span(wire).first(a), out.frames, out.errors);
      parser.feed(std::span(wire).subspan(a, b - a), out.frames, out.errors);
      parser.feed(std::span(wire).subspan(b), out.frames, out.errors);
      ASSERT_EQ(out.frames.size(), 1u) << "split at " << a << ", " << b;
      EXPECT_EQ(out.frames[0], frame) << "split at " << a << ", " << b;
      EXPECT_TRUE(out.errors.empty()) << "split at " << a << ", " << b;
      EXPECT_EQ(parser.buffered(), 0u);
    }
  }
}

TEST(NetFraming, ByteAtATimeFeedDecodesSameFramesAsOneRead) {
  Bytes wire;
  for (int i = 0; i < 20; ++i) {
    append(wire, encode_net_frame(make_frame(static_cast<NodeId>(i + 1), 255,
                                             std::string(static_cast<std::size_t>(i), '\r'))));
  }
  NetFrameParser whole(kLimit);
  NetFrameParser bytewise(kLimit);
  const Output a = feed_in_chunks(whole, kLimit, wire);
  const Output b = feed_in_chunks(bytewise, kLimit, wire, {1});
  ASSERT_EQ(a.frames.size(), 20u);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_TRUE(b.errors.empty());
}

TEST(NetFraming, SeveralFramesInOneReadAreDecodedInOrder) {
  const std::vector<NetFrame> sent = {make_frame(1, 2, "first"), make_frame(2, 1, ""),
                                      make_frame(3, 255, "third")};
  Bytes wire;
  for (const NetFrame& f : sent) append(wire, encode_net_frame(f));
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, wire);
  EXPECT_EQ(out.frames, sent);
  EXPECT_TRUE(out.errors.empty());
}

TEST(NetFraming, LoneByteBeforeTerminatorIsTooShortAndNextFrameParses) {
  Bytes wire = {0x42};
  append(wire, terminator());
  append(wire, encode_net_frame(make_frame(4, 5, "ok")));
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, wire);
  ASSERT_EQ(out.errors.size(), 1u);
  EXPECT_EQ(out.errors[0].kind, FramingError::Kind::kTooShort);
  EXPECT_EQ(out.errors[0].bytes_discarded, 1u);
  EXPECT_NE(out.errors[0].message.find("2-byte header"), std::string::npos)
      << out.errors[0].message;
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], make_frame(4, 5, "ok"));
}

TEST(NetFraming, BareTerminatorIsTooShortWithNothingDiscarded) {
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, terminator());
  ASSERT_EQ(out.errors.size(), 1u);
  EXPECT_EQ(out.errors[0].kind, FramingError::Kind::kTooShort);
  EXPECT_EQ(out.errors[0].bytes_discarded, 0u);
  EXPECT_TRUE(out.frames.empty());
}

TEST(NetFraming, RandomGarbageThenTerminatorResynchronizesOnNextFrame) {
  // The protocol has no integrity check: short garbage before a terminator is
  // indistinguishable from a frame. What matters is that the frame after it is intact.
  std::mt19937 rng(7);
  Bytes wire;
  for (int i = 0; i < 40; ++i) wire.push_back(static_cast<std::uint8_t>('a' + rng() % 26));
  append(wire, terminator());
  const NetFrame good = make_frame(8, 9, "after garbage");
  append(wire, encode_net_frame(good));
  NetFrameParser parser(kLimit);
  const Output out = feed_in_chunks(parser, kLimit, wire, {3, 5});
  ASSERT_EQ(out.frames.size(), 2u);
  EXPECT_EQ(out.frames[0].payload.size(), 38u);
  EXPECT_EQ(out.frames[1], good);
}

TEST(NetFraming, OversizedFrameIsReportedOnceDiscardedAndNextFrameParses) {
  constexpr std::size_t kSmall = 16;
  Bytes wire = encode_net_frame(make_frame(1, 2, std::string(kSmall + 1, 'x')));
  const NetFrame good = make_frame(3, 4, "next");
  append(wire, encode_net_frame(good));
  for (const std::vector<std::size_t>& chunks :
       {std::vector<std::size_t>{}, std::vector<std::size_t>{1}, std::vector<std::size_t>{7}}) {
    NetFrameParser parser(kSmall);
    const Output out = feed_in_chunks(parser, kSmall, wire, chunks);
    ASSERT_EQ(out.errors.size(), 1u);
    EXPECT_EQ(out.errors[0].kind, FramingError::Kind::kOversized);
    EXPECT_EQ(out.errors[0].bytes_discarded, 2 + kSmall + 1);
    EXPECT_NE(out.errors[0].message.find("exceeds the 16-byte payload limit"), std::string::npos)
        << out.errors[0].message;
    ASSERT_EQ(out.frames.size(), 1u);
    EXPECT_EQ(out.frames[0], good);
    EXPECT_EQ(parser.buffered(), 0u);
  }
}

TEST(NetFraming, PayloadExactlyAtLimitIsAcceptedOneMoreIsNot) {
  constexpr std::size_t kSmall = 16;
  const NetFrame at_limit = make_frame(1, 2, std::string(kSmall, '\r'));
  NetFrameParser parser(kSmall);
  const Output ok = feed_in_chunks(parser, kSmall, encode_net_frame(at_limit), {1});
  ASSERT_EQ(ok.frames.size(), 1u);
  EXPECT_EQ(ok.frames[0], at_limit);
  EXPECT_TRUE(ok.errors.empty());

  const Output bad = feed_in_chunks(
      parser, kSmall, encode_net_frame(make_frame(1, 2, std::string(kSmall + 1, '\r'))), {1});
  EXPECT_TRUE(bad.frames.empty());
  ASSERT_EQ(bad.errors.size(), 1u);
  EXPECT_EQ(bad.errors[0].kind, FramingError::Kind::kOversized);
}

TEST(NetFraming, MemoryStaysBoundedWhilePeerStreamsMegabytesWithoutTerminator) {
  // Bytes drawn from the terminator's own alphabet, so partial terminators are
  // everywhere, but every complete one is broken.
  std::mt19937 rng(11);
  const char alphabet[] = {'\r', '\n', 'z'};
  Bytes junk(1 << 20);
  for (auto& b : junk) b = static_cast<std::uint8_t>(alphabet[rng() % 3]);
  for (std::size_t i = 3; i < junk.size(); ++i) {
    if (std::equal(junk.begin() + static_cast<std::ptrdiff_t>(i) - 3,
                   junk.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::begin(kFrameTerminator)))
      junk[i] = 'z';
  }
  // Ending on a byte that cannot start a terminator keeps repeated rounds, and the
  // final terminator below, from forming one across the junk's end.
  junk.back() = 'z';
  NetFrameParser parser(kLimit);
  Output out;
  std::size_t sent = 0;
  const std::vector<std::size_t> chunks = {1, 3, 4096, 65536, 2, 1500};
  for (int round = 0; round < 8; ++round) {  // 8 MiB
    std::size_t pos = 0;
    for (std::size_t k = 0; pos < junk.size(); ++k) {
      const std::size_t n = std::min(chunks[k % chunks.size()], junk.size() - pos);
      parser.feed(std::span(junk).subspan(pos, n), out.frames, out.errors);
      ASSERT_LE(parser.buffered(), kLimit + 6);
      pos += n;
    }
    sent += junk.size();
  }
  EXPECT_TRUE(out.frames.empty());
  EXPECT_TRUE(out.errors.empty());  // reported once, when the terminator arrives

  Bytes tail = terminator();
  const NetFrame good = make_frame(6, 255, "still alive");
  append(tail, encode_net_frame(good));
  parser.feed(tail, out.frames, out.errors);
  ASSERT_EQ(out.errors.size(), 1u);
  EXPECT_EQ(out.errors[0].kind, FramingError::Kind::kOversized);
  EXPECT_EQ(out.errors[0].bytes_discarded, sent);
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], good);
}

TEST(NetFraming, BroadcastDestinationIsPreserved) {
  NetFrameParser parser(kLimit);
  const Output out =
      feed_in_chunks(parser, kLimit, encode_net_frame(make_frame(17, kBroadcastId, "all")));
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0].dst, kBroadcastId);
  EXPECT_EQ(out.frames[0].src, 17);
}

// Property: for a stream of frames, short frames and oversized frames, the outcome
// is the one dictated by each segment's length, whatever the read boundaries.
TEST(NetFraming, RandomStreamsDecodeToExpectedOutcomeUnderRandomChunking) {
  constexpr std::size_t kSmall = 24;
  std::mt19937 rng(2024);
  const char alphabet[] = {'\r', '\n', 'a', '\x00', '\xff'};
  for (int iter = 0; iter < 300; ++iter) {
    Bytes wire;
    std::vector<NetFrame> want_frames;
    std::vector<std::pair<FramingError::Kind, std::size_t>> want_errors;
    const int segments = 1 + static_cast<int>(rng() % 8);
    for (int s = 0; s < segments; ++s) {
      const std::size_t len = rng() % 3 == 0 ? rng() % 3 : rng() % (kSmall + 40);
      Bytes seg(len);
      for (auto& b : seg) b = static_cast<std::uint8_t>(alphabet[rng() % 5]);
      for (std::size_t i = 3; i < seg.size(); ++i) {  // no terminator inside a segment
        if (std::equal(seg.begin() + static_cast<std::ptrdiff_t>(i) - 3,
                       seg.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                       std::begin(kFrameTerminator)))
          seg[i] = 'a';
      }
      if (len < 2) {
        want_errors.emplace_back(FramingError::Kind::kTooShort, len);
      } else if (len > kSmall + 2) {
        want_errors.emplace_back(FramingError::Kind::kOversized, len);
      } else {
        want_frames.push_back(NetFrame{seg[0], seg[1], Bytes(seg.begin() + 2, seg.end())});
      }
      append(wire, seg);
      append(wire, terminator());
    }
    std::vector<std::size_t> chunks;
    for (int c = 0; c < 5; ++c) chunks.push_back(1 + rng() % (iter % 2 == 0 ? 5 : 60));
    NetFrameParser parser(kSmall);
    const Output out = feed_in_chunks(parser, kSmall, wire, chunks);
    EXPECT_EQ(out.frames, want_frames) << "iteration " << iter;
    ASSERT_EQ(out.errors.size(), want_errors.size()) << "iteration " << iter;
    for (std::size_t e = 0; e < want_errors.size(); ++e) {
      EXPECT_EQ(out.errors[e].kind, want_errors[e].first) << "iteration " << iter;
      EXPECT_EQ(out.errors[e].bytes_discarded, want_errors[e].second) << "iteration " << iter;
    }
    EXPECT_EQ(parser.buffered(), 0u);
  }
}

}  // namespace
}  // namespace rfsitl::io
