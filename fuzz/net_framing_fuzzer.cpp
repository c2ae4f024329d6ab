/// Net ports: NetFrameParser on an arbitrary byte stream cut into reads at
/// points the fuzzer chooses.
///
/// Input: [2 bytes: max_payload][1 byte: seed of the cut points][stream...].
/// Checks after every read:
///  - buffered() <= max_payload + 6 (memory bounded whatever the peer sends);
///  - every frame's payload <= max_payload and holds no terminator;
///  - every error has a non-empty message; kTooShort errors discard < 2 bytes,
///    kOversized ones > max_payload + 2;
/// and at the end:
///  - the frames and errors do not depend on how the stream was cut: the same
///    stream in one read and one byte per read gives the same result;
///  - re-encoding each frame and parsing it again gives the same frame.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "fuzz_check.hpp"
#include "rfsitl/io/net_framing.hpp"

using rfsitl::NetFrame;
using rfsitl::io::FramingError;
using rfsitl::io::NetFrameParser;

namespace {

struct Result {
  std::vector<NetFrame> frames;
  std::vector<FramingError> errors;
  std::size_t buffered = 0;
};

bool has_terminator(const std::vector<std::uint8_t>& p) {
  for (std::size_t i = 0; i + 4 <= p.size(); ++i) {
    if (std::memcmp(p.data() + i, rfsitl::io::kFrameTerminator, 4) == 0) return true;
  }
  return false;
}

/// Feeds `stream` in reads whose lengths come from `next_len`; checks the
/// per-read invariants.
template <class NextLen>
Result run(std::size_t max_payload, std::span<const std::uint8_t> stream, NextLen next_len) {
  NetFrameParser parser(max_payload);
  Result r;
  while (!stream.empty()) {
    std::size_t n = next_len();
    if (n == 0 || n > stream.size()) n = stream.size();
    const std::size_t frames_before = r.frames.size();
    const std::size_t errors_before = r.errors.size();
    // Copy each read into its own allocation so ASan sees reads past its end.
    const std::vector<std::uint8_t> read(stream.begin(), stream.begin() + n);
    parser.feed(read, r.frames, r.errors);
    stream = stream.subspan(n);
    FUZZ_CHECK(parser.buffered() <= max_payload + 6, "buffered %zu, max_payload %zu",
               parser.buffered(), max_payload);
    for (std::size_t i = frames_before; i < r.frames.size(); ++i) {
      FUZZ_CHECK(r.frames[i].payload.size() <= max_payload, "payload %zu > max_payload %zu",
                 r.frames[i].payload.size(), max_payload);
      FUZZ_CHECK(!has_terminator(r.frames[i].payload), "payload holds a terminator");
    }
    for (std::size_t i = errors_before; i < r.errors.size(); ++i) {
      const FramingError& e = r.errors[i];
      FUZZ_CHECK(!e.message.empty(), "error without a message");
      if (e.kind == FramingError::Kind::kTooShort) {
        FUZZ_CHECK(e.bytes_discarded < 2, "too-short error discarding %zu bytes",
                   e.bytes_discarded);
      } else {
        FUZZ_CHECK(e.bytes_discarded > max_payload + 2,
                   "oversized error discarding only %zu bytes (max_payload %zu)", e.bytes_discarded,
                   max_payload);
      }
    }
  }
  r.buffered = parser.buffered();
  return r;
}

void check_same(const Result& a, const Result& b, const char* what) {
  FUZZ_CHECK(a.frames.size() == b.frames.size(), "%s: %zu frames vs %zu", what, a.frames.size(),
             b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    FUZZ_CHECK(a.frames[i].src == b.frames[i].src && a.frames[i].dst == b.frames[i].dst &&
                   a.frames[i].payload == b.frames[i].payload,
               "%s: frame %zu differs", what, i);
  }
  FUZZ_CHECK(a.errors.size() == b.errors.size(), "%s: %zu errors vs %zu", what, a.errors.size(),
             b.errors.size());
  for (std::size_t i = 0; i < a.errors.size(); ++i) {
    FUZZ_CHECK(a.errors[i].kind == b.errors[i].kind &&
                   a.errors[i].bytes_discarded == b.errors[i].bytes_discarded,
               "%s: error %zu differs (%zu vs %zu bytes discarded)", what, i,
               a.errors[i].bytes_discarded, b.errors[i].bytes_discarded);
  }
  FUZZ_CHECK(a.buffered == b.buffered, "%s: %zu vs %zu bytes buffered", what, a.buffered,
             b.buffered);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) return 0;
  // Small limits reach the oversized paths with short inputs; any value up to
  // the protocol's 65535 is allowed.
  std::size_t max_payload = data[0] | (std::size_t{data[1]} << 8);
  if (data[1] < 0xF0) max_payload %= 64;  // mostly 0..63, sometimes up to 65535
  std::uint32_t seed = data[2];
  const std::span<const std::uint8_t> stream(data + 3, size - 3);

  // Cut points from a tiny PRNG seeded by the input (lengths 1..16, or the rest).
  const Result cut = run(max_payload, stream, [&seed] {
    seed = seed * 1103515245U + 12345U;
    const std::uint32_t r = (seed >> 16) & 0xFF;
    return r >= 240 ? std::size_t{0} : std::size_t{r % 16 + 1};
  });
  const Result whole = run(max_payload, stream, [] { return std::size_t{0}; });
  const Result bytewise = run(max_payload, stream, [] { return std::size_t{1}; });
  check_same(whole, cut, "one read vs fuzzer-chosen reads");
  check_same(whole, bytewise, "one read vs one byte per read");

  // Round trip: every frame re-encoded parses back to itself.
  for (const NetFrame& f : whole.frames) {
    const std::vector<std::uint8_t> wire = rfsitl::io::encode_net_frame(f);
    NetFrameParser p(max_payload);
    std::vector<NetFrame> frames;
    std::vector<FramingError> errors;
    p.feed(wire, frames, errors);
    FUZZ_CHECK(frames.size() == 1 && errors.empty() && p.buffered() == 0,
               "re-encoded frame parsed as %zu frames, %zu errors", frames.size(), errors.size());
    FUZZ_CHECK(frames[0].src == f.src && frames[0].dst == f.dst && frames[0].payload == f.payload,
               "re-encoded frame differs");
  }
  return 0;
}
