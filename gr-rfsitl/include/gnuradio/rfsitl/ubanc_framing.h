#pragma once
/// UB-ANC net-port framing <-> packet PDUs.
#include <gnuradio/block.h>
#include <gnuradio/rfsitl/api.h>

#include <cstdint>
#include <memory>

namespace gr::rfsitl {

/// Converts between the UB-ANC agent's byte stream and packet PDUs.
///
/// UB-ANC framing: `[src u8][dst u8][payload][\r\r\n\n]`, dst 255 = broadcast.
///
/// Message ports:
///   - `net_in`: byte chunks as they arrive from the agent (e.g. the `pdus`
///     output of network.socket_pdu("TCP_SERVER", ...)); chunks may split or
///     join frames arbitrarily.
///   - `radio_out`: one PDU (u8vector [src][dst][payload]) per complete frame,
///     for the transmitter.
///   - `radio_in`: decoded PDUs (u8vector [src][dst][payload]) from the
///     receiver.
///   - `net_out`: the frame with its terminator appended, for the agent
///     (e.g. the `pdus` input of the same socket_pdu).
///
/// A frame whose payload exceeds `max_payload` bytes is refused, counted and
/// logged; the stream resynchronizes at the next terminator. A frame shorter
/// than its two header bytes is counted the same way. With `node_id` 1..254,
/// decoded frames whose dst is neither `node_id` nor 255, and the node's own
/// frames (src == `node_id`, heard back by its receiver), are not passed to
/// the agent (counted as filtered); `node_id` 0 passes every frame.
class RFSITL_API ubanc_framing : virtual public gr::block {
 public:
  using sptr = std::shared_ptr<ubanc_framing>;

  static sptr make(int node_id = 0, int max_payload = 2048);

  /// Complete, valid frames sent to `radio_out`.
  virtual std::uint64_t frames_to_radio() const = 0;
  /// Frames sent to `net_out`.
  virtual std::uint64_t frames_to_net() const = 0;
  /// Oversized or too-short frames from the agent, and malformed messages.
  virtual std::uint64_t framing_errors() const = 0;
  /// Decoded frames not addressed to this node, or sent by it.
  virtual std::uint64_t frames_filtered() const = 0;
};

}  // namespace gr::rfsitl
