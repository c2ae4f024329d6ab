#include "rfsitl/io/net_framing.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>

namespace rfsitl::io {
namespace {

constexpr std::size_t kHeaderBytes = 2;  // src id, dst id
constexpr std::size_t kTerminatorBytes = sizeof(kFrameTerminator);
// A terminator that straddles two reads begins in at most this many held bytes.
constexpr std::size_t kTailBytes = kTerminatorBytes - 1;

// Index of the first terminator that lies wholly inside [p, p + n), or n if none.
// memchr finds candidate '\r' bytes quickly; only those are compared in full.
std::size_t find_terminator(const std::uint8_t* p, std::size_t n) {
  std::size_t i = 0;
  while (n - i >= kTerminatorBytes) {
    const void* hit = std::memchr(p + i, kFrameTerminator[0], n - i - kTailBytes);
    if (hit == nullptr) return n;
    i = static_cast<std::size_t>(static_cast<const std::uint8_t*>(hit) - p);
    if (std::memcmp(p + i, kFrameTerminator, kTerminatorBytes) == 0) return i;
    ++i;
  }
  return n;
}

// Index in `tail` where a terminator begins that completes in `head`, or tail.size().
// A terminator found wholly inside `head` is not reported: the caller's search of
// the new bytes finds it.
std::size_t find_straddling_terminator(std::span<const std::uint8_t> tail,
                                       std::span<const std::uint8_t> head) {
  std::uint8_t joined[2 * kTailBytes];
  const std::size_t head_len = std::min(head.size(), kTailBytes);
  std::copy(tail.begin(), tail.end(), joined);
  std::copy_n(head.begin(), head_len, joined + tail.size());
  const std::size_t at = find_terminator(joined, tail.size() + head_len);
  return std::min(at, tail.size());
}

FramingError oversized_error(std::size_t max_payload, std::size_t frame_len) {
  return {FramingError::Kind::kOversized, frame_len,
          "frame exceeds the " + std::to_string(max_payload) + "-byte payload limit; discarded " +
              std::to_string(frame_len) + " bytes up to the next terminator"};
}

FramingError too_short_error(std::size_t frame_len) {
  return {FramingError::Kind::kTooShort, frame_len,
          "frame of " + std::to_string(frame_len) + (frame_len == 1 ? " byte" : " bytes") +
              " before the terminator is shorter than the 2-byte header (src, dst); discarded"};
}

}  // namespace

std::vector<std::uint8_t> encode_net_frame(const NetFrame& frame) {
  std::vector<std::uint8_t> out;
  out.reserve(kHeaderBytes + frame.payload.size() + kTerminatorBytes);
  out.push_back(frame.src);
  out.push_back(frame.dst);
  out.insert(out.end(), frame.payload.begin(), frame.payload.end());
  out.insert(out.end(), std::begin(kFrameTerminator), std::end(kFrameTerminator));
  return out;
}

NetFrameParser::NetFrameParser(std::size_t max_payload) : max_payload_(max_payload) {}

// State between calls:
//  - collecting (discarding_ == false): buf_ holds every byte of the current frame
//    so far. It never holds a complete terminator, so only its last kTailBytes can
//    start one; that is why each call searches the new bytes plus that short tail.
//  - discarding: the frame is known to be oversized. buf_ holds only its last
//    kTailBytes bytes (a possible terminator start) and discarded_ counts the rest.
// A frame's length is the number of bytes before its terminator. Once
// max_frame + kTerminatorBytes bytes have arrived without a terminator starting at
// or before max_frame, no terminator can make the frame valid, so the parser stops
// buffering: buf_ never exceeds max_payload + 5 bytes.
void NetFrameParser::feed(std::span<const std::uint8_t> bytes, std::vector<NetFrame>& frames,
                          std::vector<FramingError>& errors) {
  const std::size_t max_frame = kHeaderBytes + max_payload_;
  const std::size_t give_up_len = max_frame + kTerminatorBytes;

  // Reports the frame whose terminator was just found and resets for the next one.
  // `data` holds the frame's bytes when it is being collected (not when discarding).
  auto close_frame = [&](std::size_t frame_len, const std::uint8_t* data) {
    if (discarding_ || frame_len > max_frame) {
      errors.push_back(oversized_error(max_payload_, frame_len));
    } else if (frame_len < kHeaderBytes) {
      errors.push_back(too_short_error(frame_len));
    } else {
      NetFrame frame;
      frame.src = data[0];
      frame.dst = data[1];
      frame.payload.assign(data + kHeaderBytes, data + frame_len);
      frames.push_back(std::move(frame));
    }
    buf_.clear();
    discarding_ = false;
    discarded_ = 0;
  };

  // Keeps the last kTailBytes of (held bytes + `more`) and counts the others as
  // discarded, so memory stays constant while an oversized frame streams past.
  auto keep_tail_only = [&](std::span<const std::uint8_t> more) {
    const std::size_t total = buf_.size() + more.size();
    const std::size_t keep = std::min(total, kTailBytes);
    std::uint8_t tail[kTailBytes];
    for (std::size_t i = 0; i < keep; ++i) {
      const std::size_t at = total - keep + i;
      tail[i] = at < buf_.size() ? buf_[at] : more[at - buf_.size()];
    }
    discarded_ += total - keep;
    buf_.assign(tail, tail + keep);
  };

  while (!bytes.empty()) {
    // 1. A terminator that began in bytes held from an earlier read.
    const std::size_t tail_len = std::min(buf_.size(), kTailBytes);
    if (tail_len > 0) {
      const std::size_t tail_start = buf_.size() - tail_len;
      const std::size_t s = find_straddling_terminator(std::span(buf_).subspan(tail_start), bytes);
      if (s < tail_len) {
        const std::size_t consumed = s + kTerminatorBytes - tail_len;
        close_frame((discarding_ ? discarded_ : tail_start) + s, buf_.data());
        bytes = bytes.subspan(consumed);
        continue;
      }
    }

    // 2. Discarding: skip to the next terminator wherever it is.
    if (discarding_) {
      const std::size_t at = find_terminator(bytes.data(), bytes.size());
      if (at == bytes.size()) {
        keep_tail_only(bytes);
        return;
      }
      close_frame(discarded_ + buf_.size() + at, nullptr);
      bytes = bytes.subspan(at + kTerminatorBytes);
      continue;
    }

    // 3. Collecting: a terminator is only useful if it starts within the limit, so
    // search no further than that (this also bounds the copy into buf_).
    const std::size_t held = buf_.size();
    const std::size_t window = std::min(bytes.size(), give_up_len - held);
    const std::size_t at = find_terminator(bytes.data(), window);
    if (at < window) {
      if (held == 0) {
        close_frame(at, bytes.data());  // whole frame in this read: no copy into buf_
      } else {
        buf_.insert(buf_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(at));
        close_frame(buf_.size(), buf_.data());
      }
      bytes = bytes.subspan(at + kTerminatorBytes);
      continue;
    }
    if (held + window < give_up_len) {
      buf_.insert(buf_.end(), bytes.begin(), bytes.end());  // frame continues in a later read
      return;
    }
    // give_up_len bytes and no terminator within the limit: oversized.
    discarding_ = true;
    keep_tail_only(bytes.first(window));
    bytes = bytes.subspan(window);
  }
}

}  // namespace rfsitl::io
