#pragma once
/// UB-ANC stream framing on the net ports: [src u8][dst u8][payload][\r\r\n\n].
///
/// The terminator is not escaped in UB-ANC's protocol, so a payload that itself
/// contains "\r\r\n\n" is split there; that limitation is the protocol's.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/common/net_frame.hpp"

namespace rfsitl::io {

inline constexpr std::uint8_t kFrameTerminator[4] = {'\r', '\r', '\n', '\n'};

/// Serializes one frame with its terminator.
std::vector<std::uint8_t> encode_net_frame(const NetFrame& frame);

/// Why bytes on a net port were rejected.
struct FramingError {
  enum class Kind {
    kTooShort,   ///< fewer than 2 bytes (src, dst) before the terminator
    kOversized,  ///< more than max_payload payload bytes before a terminator
  };
  Kind kind;
  std::size_t bytes_discarded;  ///< bytes dropped for this error, terminator excluded
  std::string message;          ///< human-readable, names the limit that was broken
};

/// Incremental parser for one TCP stream. Reassembles frames split across reads.
/// An oversized frame is reported once and its bytes are discarded up to and
/// including the next terminator (resynchronization); memory stays bounded by
/// max_payload + 6 bytes whatever the peer sends.
class NetFrameParser {
 public:
  explicit NetFrameParser(std::size_t max_payload);

  /// Consumes `bytes`; appends complete frames to `frames` and rejected ones to `errors`.
  void feed(std::span<const std::uint8_t> bytes, std::vector<NetFrame>& frames,
            std::vector<FramingError>& errors);

  /// Bytes held for a frame not yet terminated.
  std::size_t buffered() const { return buf_.size(); }

 private:
  std::size_t max_payload_;
  std::vector<std::uint8_t> buf_;
  bool discarding_ = false;  // inside an oversized frame, waiting for its terminator
  std::size_t discarded_ = 0;
};

}  // namespace rfsitl::io
