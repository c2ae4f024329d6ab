/// MAVLink position sources: MavlinkParser on an arbitrary byte stream, and on
/// well-formed frames built from the input.
///
/// Input: [mode][seed of the cut points][data...].
/// Mode even: `data` is the stream. After every read:
///  - buffered() <= kMaxFrameBytes (memory bounded whatever the vehicle sends);
///  - bytes fed == frame_bytes + unknown_id_bytes + rejected_bytes + garbage_bytes +
///    buffered();
///  - every message has version 1 or 2, an id in the catalog, a v1 payload of
///    exactly the message's base length, and a decoded type when it has one;
/// and at the end the same messages, counters and buffered bytes whether the
/// stream came in one read, one byte per read or at the fuzzer's cut points;
/// every decoded message re-encodes (v2) to a frame that parses back to the
/// same payload.
/// Mode odd: data = [catalog index][flags][payload...]: a valid frame of that
/// message (v1 or v2, signed or not, payload as given) between two heartbeats
/// is accepted exactly, and a decoded message re-encoded in the same version
/// gives back the received payload (v1: identical; v2: identical up to trailing
/// zeros, over the bytes the catalog knows).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "fuzz_check.hpp"
#include "rfsitl/position/mavlink/checksum.hpp"
#include "rfsitl/position/mavlink/encoder.hpp"
#include "rfsitl/position/mavlink/message_catalog.hpp"
#include "rfsitl/position/mavlink/parser.hpp"
#include "rfsitl/position/mavlink/requests.hpp"

namespace mav = rfsitl::position::mavlink;
using Bytes = std::vector<std::uint8_t>;

namespace {

struct Result {
  std::vector<mav::MavlinkMessage> messages;
  mav::ParserCounters counters;
  std::size_t buffered = 0;
};

void check_message(const mav::MavlinkMessage& m) {
  const mav::FrameInfo& f = m.frame;
  FUZZ_CHECK(f.version == mav::MavlinkVersion::kV1 || f.version == mav::MavlinkVersion::kV2,
             "version %d", static_cast<int>(f.version));
  const mav::MessageSpec* spec = mav::find_message_spec(f.msgid);
  FUZZ_CHECK(spec != nullptr, "accepted unknown id %u", f.msgid);
  if (f.version == mav::MavlinkVersion::kV1) {
    FUZZ_CHECK(f.payload_length == spec->base_length && !f.is_signed, "v1 %s with %u payload bytes",
               spec->name, f.payload_length);
  }
  const auto* raw = m.get<mav::UndecodedMessage>();
  const bool decodable = f.msgid == mav::Heartbeat::kId || f.msgid == mav::GpsRawInt::kId ||
                         f.msgid == mav::Attitude::kId || f.msgid == mav::GlobalPositionInt::kId ||
                         f.msgid == mav::RequestDataStream::kId ||
                         f.msgid == mav::CommandLong::kId || f.msgid == mav::CommandAck::kId;
  FUZZ_CHECK((raw == nullptr) == decodable, "%s decoded: %d", spec->name, raw == nullptr);
  if (raw != nullptr)
    FUZZ_CHECK(raw->msgid == f.msgid, "undecoded id %u vs %u", raw->msgid, f.msgid);
}

template <class NextLen>
Result run(std::span<const std::uint8_t> stream, NextLen next_len) {
  mav::MavlinkParser parser;
  Result r;
  std::size_t fed = 0;
  while (!stream.empty()) {
    std::size_t n = next_len();
    if (n == 0 || n > stream.size()) n = stream.size();
    const std::size_t before = r.messages.size();
    // Each read in its own allocation so ASan sees reads past its end.
    const Bytes read(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(n));
    parser.feed(read, r.messages);
    stream = stream.subspan(n);
    fed += n;
    const mav::ParserCounters& c = parser.counters();
    FUZZ_CHECK(parser.buffered() <= mav::kMaxFrameBytes, "buffered %zu", parser.buffered());
    FUZZ_CHECK(fed == c.frame_bytes + c.unknown_id_bytes + c.rejected_bytes + c.garbage_bytes +
                          parser.buffered(),
               "fed %zu, frames %llu, unknown %llu, garbage %llu, buffered %zu", fed,
               static_cast<unsigned long long>(c.frame_bytes),
               static_cast<unsigned long long>(c.unknown_id_bytes),
               static_cast<unsigned long long>(c.garbage_bytes), parser.buffered());
    FUZZ_CHECK(c.frames == r.messages.size(), "frames %llu, messages %zu",
               static_cast<unsigned long long>(c.frames), r.messages.size());
    for (std::size_t i = before; i < r.messages.size(); ++i) check_message(r.messages[i]);
  }
  r.counters = parser.counters();
  r.buffered = parser.buffered();
  return r;
}

// Bytes of the messages compared through their encoding: floats may be NaN,
// which operator== would call different from themselves.
Bytes encoding_of(const mav::MavlinkMessage& m, mav::MavlinkVersion version) {
  mav::MavlinkEncoder enc(m.frame.sysid, m.frame.compid, m.frame.seq);
  return std::visit(
      [&](const auto& msg) -> Bytes {
        if constexpr (mav::EncodableMessage<std::decay_t<decltype(msg)>>) {
          return enc.encode(msg, version);
        } else {
          return Bytes(msg.payload.begin(), msg.payload.begin() + msg.length);
        }
      },
      m.payload);
}

void check_same(const Result& a, const Result& b, const char* what) {
  FUZZ_CHECK(a.messages.size() == b.messages.size(), "%s: %zu vs %zu messages", what,
             a.messages.size(), b.messages.size());
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    FUZZ_CHECK(a.messages[i].frame == b.messages[i].frame, "%s: message %zu's frame differs", what,
               i);
    FUZZ_CHECK(encoding_of(a.messages[i], mav::MavlinkVersion::kV2) ==
                   encoding_of(b.messages[i], mav::MavlinkVersion::kV2),
               "%s: message %zu differs", what, i);
  }
  FUZZ_CHECK(a.counters == b.counters, "%s: counters differ", what);
  FUZZ_CHECK(a.buffered == b.buffered, "%s: %zu vs %zu buffered", what, a.buffered, b.buffered);
}

std::vector<mav::MavlinkMessage> parse_all(const Bytes& bytes, mav::ParserCounters* counters) {
  mav::MavlinkParser p;
  std::vector<mav::MavlinkMessage> out;
  p.feed(bytes, out);
  if (counters != nullptr) *counters = p.counters();
  return out;
}

void check_reencoding(const mav::MavlinkMessage& m) {
  if (m.get<mav::UndecodedMessage>() != nullptr) return;
  const Bytes once = encoding_of(m, mav::MavlinkVersion::kV2);
  mav::ParserCounters c;
  const auto again = parse_all(once, &c);
  FUZZ_CHECK(again.size() == 1 && c.garbage_bytes == 0, "re-encoded frame parsed as %zu",
             again.size());
  FUZZ_CHECK(encoding_of(again[0], mav::MavlinkVersion::kV2) == once, "re-encoding not stable");
}

Bytes strip_trailing_zeros(Bytes b) {
  while (b.size() > 1 && b.back() == 0) b.pop_back();
  return b;
}

// Mode odd: one valid frame of a chosen catalog message.
void well_formed_frame(std::span<const std::uint8_t> data) {
  if (data.size() < 2) return;
  const auto catalog = mav::message_catalog();
  const mav::MessageSpec& spec = catalog[data[0] % catalog.size()];
  const std::uint8_t flags = data[1];
  const bool v1 = (flags & 1U) != 0 && spec.id <= 0xFF;
  const bool is_signed = !v1 && (flags & 2U) != 0;
  Bytes payload(data.begin() + 2, data.end());
  payload.resize(v1 ? spec.base_length : std::min<std::size_t>(payload.size(), 255));

  Bytes frame;
  if (v1) {
    frame = {mav::kMagicV1,
             static_cast<std::uint8_t>(payload.size()),
             9,
             1,
             1,
             static_cast<std::uint8_t>(spec.id)};
  } else {
    frame = {mav::kMagicV2,
             static_cast<std::uint8_t>(payload.size()),
             static_cast<std::uint8_t>(is_signed ? mav::kIncompatSigned : 0),
             flags,
             9,
             1,
             1,
             static_cast<std::uint8_t>(spec.id),
             static_cast<std::uint8_t>(spec.id >> 8),
             static_cast<std::uint8_t>(spec.id >> 16)};
  }
  frame.insert(frame.end(), payload.begin(), payload.end());
  const std::uint16_t crc = mav::frame_checksum(std::span(frame).subspan(1), spec.crc_extra);
  frame.push_back(static_cast<std::uint8_t>(crc));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  if (is_signed) frame.insert(frame.end(), mav::kSignatureBytes, flags);

  mav::MavlinkEncoder hb(2, 2);
  const Bytes before = hb.encode(mav::onboard_controller_heartbeat());
  Bytes stream = before;
  stream.insert(stream.end(), frame.begin(), frame.end());
  const Bytes after = hb.encode(mav::onboard_controller_heartbeat());
  stream.insert(stream.end(), after.begin(), after.end());

  mav::ParserCounters c;
  const auto got = parse_all(stream, &c);
  FUZZ_CHECK(got.size() == 3 && c.garbage_bytes == 0 && c.frame_bytes == stream.size(),
             "%s (v%d, %zu bytes): %zu messages, %llu garbage", spec.name, v1 ? 1 : 2,
             payload.size(), got.size(), static_cast<unsigned long long>(c.garbage_bytes));
  const mav::MavlinkMessage& m = got[1];
  FUZZ_CHECK(m.frame.msgid == spec.id && m.frame.payload_length == payload.size() &&
                 m.frame.is_signed == is_signed,
             "%s: frame info differs", spec.name);
  check_message(m);
  if (m.get<mav::UndecodedMessage>() != nullptr) return;

  const Bytes re = encoding_of(m, v1 ? mav::MavlinkVersion::kV1 : mav::MavlinkVersion::kV2);
  const std::size_t header = v1 ? mav::kHeaderBytesV1 : mav::kHeaderBytesV2;
  const Bytes re_payload(re.begin() + static_cast<std::ptrdiff_t>(header),
                         re.end() - static_cast<std::ptrdiff_t>(mav::kChecksumBytes));
  if (v1) {
    FUZZ_CHECK(re == frame, "%s: v1 re-encoding differs", spec.name);
  } else {
    Bytes known = payload;
    known.resize(std::min<std::size_t>(known.size(), spec.max_length));
    if (known.empty()) known.push_back(0);  // a v2 sender keeps at least one byte
    FUZZ_CHECK(re_payload == strip_trailing_zeros(known), "%s: v2 payload re-encodes differently",
               spec.name);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t mode = data[0];
  std::uint32_t seed = data[1];
  const std::span<const std::uint8_t> rest(data + 2, size - 2);
  if ((mode & 1U) != 0) {
    well_formed_frame(rest);
    return 0;
  }
  const Result cut = run(rest, [&seed] {
    seed = seed * 1103515245U + 12345U;
    const std::uint32_t r = (seed >> 16) & 0xFF;
    return r >= 240 ? std::size_t{0} : std::size_t{r % 32 + 1};
  });
  const Result whole = run(rest, [] { return std::size_t{0}; });
  const Result bytewise = run(rest, [] { return std::size_t{1}; });
  check_same(whole, cut, "one read vs fuzzer-chosen reads");
  check_same(whole, bytewise, "one read vs one byte per read");
  for (const mav::MavlinkMessage& m : whole.messages) check_reencoding(m);
  return 0;
}
