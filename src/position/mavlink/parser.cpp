#include "rfsitl/position/mavlink/parser.hpp"

#include <algorithm>
#include <cstring>

#include "decode_payload.hpp"
#include "rfsitl/position/mavlink/checksum.hpp"
#include "rfsitl/position/mavlink/message_catalog.hpp"

namespace rfsitl::position::mavlink {
namespace {

bool is_magic(std::uint8_t b) {
  return b == kMagicV1 || b == kMagicV2;
}

// The header of the candidate frame at buf[0], once its header bytes are in.
struct Header {
  bool v2;
  std::size_t header_bytes;
  std::size_t payload_bytes;
  std::uint8_t incompat;
  std::uint32_t msgid;

  // Header, payload, checksum and any signature.
  std::size_t frame_bytes() const {
    return header_bytes + payload_bytes + kChecksumBytes +
           ((incompat & kIncompatSigned) != 0 ? kSignatureBytes : 0);
  }
};

std::size_t header_bytes(std::uint8_t magic) {
  return magic == kMagicV2 ? kHeaderBytesV2 : kHeaderBytesV1;
}

// v1: FE len seq sysid compid msgid
// v2: FD len incompat compat seq sysid compid msgid0 msgid1 msgid2
Header read_header(const std::uint8_t* b) {
  if (b[0] == kMagicV2) {
    return {true, kHeaderBytesV2, b[1], b[2],
            b[7] | (std::uint32_t{b[8]} << 8) | (std::uint32_t{b[9]} << 16)};
  }
  return {false, kHeaderBytesV1, b[1], 0, b[5]};
}

FrameInfo frame_info(const std::uint8_t* b, const Header& h) {
  FrameInfo info;
  info.version = h.v2 ? MavlinkVersion::kV2 : MavlinkVersion::kV1;
  info.msgid = h.msgid;
  info.payload_length = static_cast<std::uint8_t>(h.payload_bytes);
  const std::size_t seq_at = h.v2 ? 4 : 2;
  info.seq = b[seq_at];
  info.sysid = b[seq_at + 1];
  info.compid = b[seq_at + 2];
  if (h.v2) {
    info.compat_flags = b[3];
    info.is_signed = (h.incompat & kIncompatSigned) != 0;
  }
  return info;
}

}  // namespace

std::size_t MavlinkParser::feed(std::span<const std::uint8_t> bytes,
                                std::vector<MavlinkMessage>& out) {
  const std::size_t before = out.size();
  // Each pass settles the candidate at the buffer's start or stops for more
  // input. A pass that settles one removes at least one byte from the buffer or
  // the input, so the loop ends. Every decision is taken once exactly the bytes
  // it needs are present, which is why chunking cannot change the outcome.
  for (;;) {
    if (!skip(bytes)) break;
    if (!find_magic(bytes)) break;
    if (!fill(header_bytes(buf_[0]), bytes)) break;
    const Header h = read_header(buf_.data());
    if ((h.incompat & ~kIncompatSigned) != 0) {
      reject(counters_.bad_incompat_flags, h.frame_bytes());
      continue;
    }
    const MessageSpec* spec = find_message_spec(h.msgid);
    if (spec == nullptr) {
      // Unverifiable; in a real stream most likely a real frame of a dialect we
      // do not know, so step over all of it rather than rescan its payload.
      ++counters_.unknown_id;
      skip_ = h.frame_bytes();
      continue;
    }
    if (!h.v2 && h.payload_bytes != spec->base_length) {
      reject(counters_.bad_length, h.frame_bytes());
      continue;
    }
    if (!fill(h.frame_bytes(), bytes)) break;

    const std::size_t crc_at = h.header_bytes + h.payload_bytes;
    const std::uint16_t expected =
        frame_checksum(std::span<const std::uint8_t>(buf_).subspan(1, crc_at - 1), spec->crc_extra);
    const auto received = static_cast<std::uint16_t>(buf_[crc_at] | (buf_[crc_at + 1] << 8));
    if (received != expected) {
      reject(counters_.bad_crc, h.frame_bytes());
      continue;
    }
    accept(frame_info(buf_.data(), h), h.header_bytes, h.frame_bytes(), out);
  }
  return out.size() - before;
}

void MavlinkParser::accept(const FrameInfo& info, std::size_t header_bytes, std::size_t frame_bytes,
                           std::vector<MavlinkMessage>& out) {
  const auto payload =
      std::span<const std::uint8_t>(buf_).subspan(header_bytes, info.payload_length);
  out.push_back(MavlinkMessage{info, detail::decode_payload(info.msgid, payload)});
  ++counters_.frames;
  counters_.frame_bytes += frame_bytes;
  drop_front(frame_bytes);
}

bool MavlinkParser::skip(std::span<const std::uint8_t>& in) noexcept {
  if (skip_ == 0) return true;
  // The frame's first bytes are in the buffer (its header, maybe more after a
  // rescan), the rest still to come.
  const std::size_t from_buffer = std::min(skip_, len_);
  drop_front(from_buffer);
  const std::size_t from_input = std::min(skip_ - from_buffer, in.size());
  in = in.subspan(from_input);
  consumed_ += from_input;
  skip_ -= from_buffer + from_input;
  counters_.unknown_id_bytes += from_buffer + from_input;
  return skip_ == 0;
}

bool MavlinkParser::find_magic(std::span<const std::uint8_t>& in) noexcept {
  if (len_ > 0) {
    const auto* start = buf_.data();
    const std::size_t garbage =
        static_cast<std::size_t>(std::find_if(start, start + len_, is_magic) - start);
    count_unused(garbage);
    drop_front(garbage);
    if (len_ > 0) return true;
  }
  const auto it = std::find_if(in.begin(), in.end(), is_magic);
  const auto garbage = static_cast<std::size_t>(it - in.begin());
  count_unused(garbage);
  consumed_ += garbage;
  in = in.subspan(garbage);
  if (in.empty()) return false;
  buf_[0] = in[0];
  len_ = 1;
  in = in.subspan(1);
  return true;
}

bool MavlinkParser::fill(std::size_t want, std::span<const std::uint8_t>& in) noexcept {
  if (len_ < want) {
    const std::size_t n = std::min(want - len_, in.size());
    if (n == 0) return false;
    std::memcpy(buf_.data() + len_, in.data(), n);
    len_ += n;
    in = in.subspan(n);
  }
  return len_ >= want;
}

void MavlinkParser::reject(std::uint64_t& reason, std::size_t frame_bytes) noexcept {
  ++reason;
  reject_end_ = std::max(reject_end_, consumed_ + frame_bytes);
  count_unused(1);
  drop_front(1);
}

void MavlinkParser::count_unused(std::size_t n) noexcept {
  const std::uint64_t left = reject_end_ > consumed_ ? reject_end_ - consumed_ : 0;
  const std::uint64_t rejected = std::min<std::uint64_t>(n, left);
  counters_.rejected_bytes += rejected;
  counters_.garbage_bytes += n - rejected;
}

void MavlinkParser::drop_front(std::size_t n) noexcept {
  std::memmove(buf_.data(), buf_.data() + n, len_ - n);
  len_ -= n;
  consumed_ += n;
}

void MavlinkParser::reset() noexcept {
  if (len_ > 0 || skip_ > 0) ++counters_.truncated;
  count_unused(len_);
  consumed_ += len_;
  len_ = 0;
  skip_ = 0;
}

}  // namespace rfsitl::position::mavlink
