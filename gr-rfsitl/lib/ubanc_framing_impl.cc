#include "ubanc_framing_impl.h"

#include <gnuradio/io_signature.h>

#include <algorithm>
#include <array>
#include <stdexcept>

#include "log_format.h"

namespace gr::rfsitl {

namespace {

constexpr std::array<std::uint8_t, 4> kTerminator = {'\r', '\r', '\n', '\n'};
constexpr std::size_t kHeaderBytes = 2;  // src, dst
constexpr int kBroadcast = 255;

const pmt::pmt_t& port_net_in() {
  static const pmt::pmt_t p = pmt::mp("net_in");
  return p;
}
const pmt::pmt_t& port_net_out() {
  static const pmt::pmt_t p = pmt::mp("net_out");
  return p;
}
const pmt::pmt_t& port_radio_in() {
  static const pmt::pmt_t p = pmt::mp("radio_in");
  return p;
}
const pmt::pmt_t& port_radio_out() {
  static const pmt::pmt_t p = pmt::mp("radio_out");
  return p;
}

/// The u8vector of a PDU (pair of metadata and u8vector) or of a bare
/// u8vector; PMT_NIL for anything else.
pmt::pmt_t pdu_bytes(const pmt::pmt_t& msg, pmt::pmt_t& meta) {
  meta = pmt::PMT_NIL;
  if (pmt::is_pair(msg)) {
    meta = pmt::car(msg);
    const pmt::pmt_t data = pmt::cdr(msg);
    return pmt::is_u8vector(data) ? data : pmt::PMT_NIL;
  }
  return pmt::is_u8vector(msg) ? msg : pmt::PMT_NIL;
}

pmt::pmt_t make_pdu(const pmt::pmt_t& meta, const std::uint8_t* data, std::size_t n) {
  return pmt::cons(pmt::is_dict(meta) ? meta : pmt::make_dict(), pmt::init_u8vector(n, data));
}

}  // namespace

ubanc_framing::sptr ubanc_framing::make(int node_id, int max_payload) {
  return gnuradio::make_block_sptr<ubanc_framing_impl>(node_id, max_payload);
}

ubanc_framing_impl::ubanc_framing_impl(int node_id, int max_payload)
    : gr::block("ubanc_framing", gr::io_signature::make(0, 0, 0), gr::io_signature::make(0, 0, 0)),
      node_id_(node_id),
      max_payload_(static_cast<std::size_t>(std::max(max_payload, 0))) {
  if (node_id < 0 || node_id > 254) {
    throw std::invalid_argument("rfsitl ubanc_framing: node_id must be 0 (no filter) or 1..254");
  }
  if (max_payload < 1 || max_payload > 65535) {
    throw std::invalid_argument("rfsitl ubanc_framing: max_payload must be 1..65535");
  }
  message_port_register_in(port_net_in());
  message_port_register_in(port_radio_in());
  message_port_register_out(port_radio_out());
  message_port_register_out(port_net_out());
  set_msg_handler(port_net_in(), [this](const pmt::pmt_t& msg) { handle_net_in(msg); });
  set_msg_handler(port_radio_in(), [this](const pmt::pmt_t& msg) { handle_radio_in(msg); });
}

void ubanc_framing_impl::framing_error(const std::string& what) {
  const auto n = ++framing_errors_;
  log_warn(*d_logger, "framing error #{} from the agent: {}", n, what);
}

void ubanc_framing_impl::handle_net_in(const pmt::pmt_t& msg) {
  pmt::pmt_t meta;
  const pmt::pmt_t bytes = pdu_bytes(msg, meta);
  if (pmt::is_null(bytes)) {
    ++framing_errors_;
    log_warn(*d_logger, "net_in: ignoring a message that is not a u8vector PDU");
    return;
  }
  std::size_t len = 0;
  const auto* data = pmt::u8vector_elements(bytes, len);
  buf_.insert(buf_.end(), data, data + len);
  extract_frames();
}

void ubanc_framing_impl::extract_frames() {
  for (;;) {
    const auto it = std::search(buf_.begin() + static_cast<std::ptrdiff_t>(scanned_), buf_.end(),
                                kTerminator.begin(), kTerminator.end());
    if (it == buf_.end()) break;
    const auto frame_len = static_cast<std::size_t>(it - buf_.begin());
    if (discarding_) {
      discarding_ = false;  // end of the refused frame: in sync again
    } else if (frame_len < kHeaderBytes) {
      framing_error("frame of " + std::to_string(frame_len) +
                    " bytes is shorter than its [src][dst] header; dropped");
    } else if (frame_len - kHeaderBytes > max_payload_) {
      framing_error("payload of " + std::to_string(frame_len - kHeaderBytes) +
                    " bytes exceeds max_payload " + std::to_string(max_payload_) + "; dropped");
    } else {
      // Count first: a reader that sees the message must also see the count.
      ++frames_to_radio_;
      message_port_pub(port_radio_out(), make_pdu(pmt::PMT_NIL, buf_.data(), frame_len));
    }
    buf_.erase(buf_.begin(), it + kTerminator.size());
    scanned_ = 0;
  }
  // Bytes that may begin a terminator split across chunks stay for rescanning.
  constexpr std::size_t kKeep = kTerminator.size() - 1;
  if (!discarding_ && buf_.size() > kHeaderBytes + max_payload_ + kKeep) {
    framing_error("more than " + std::to_string(max_payload_) +
                  " payload bytes without a terminator; discarding up to the next one");
    discarding_ = true;
  }
  if (discarding_ && buf_.size() > kKeep) {
    // Memory stays bounded however long the garbage is.
    buf_.erase(buf_.begin(), buf_.end() - static_cast<std::ptrdiff_t>(kKeep));
  }
  scanned_ = buf_.size() > kKeep ? buf_.size() - kKeep : 0;
}

void ubanc_framing_impl::handle_radio_in(const pmt::pmt_t& msg) {
  pmt::pmt_t meta;
  const pmt::pmt_t bytes = pdu_bytes(msg, meta);
  if (pmt::is_null(bytes)) {
    log_warn(*d_logger, "radio_in: ignoring a message that is not a u8vector PDU");
    return;
  }
  std::size_t len = 0;
  const auto* data = pmt::u8vector_elements(bytes, len);
  if (len < kHeaderBytes) {
    log_warn(*d_logger, "radio_in: ignoring a {}-byte packet without [src][dst] header", len);
    return;
  }
  const int src = data[0];
  const int dst = data[1];
  // A half-duplex radio hears its own transmissions; they are not news to
  // the agent that sent them.
  if (node_id_ != 0 && (src == node_id_ || (dst != node_id_ && dst != kBroadcast))) {
    ++frames_filtered_;
    return;
  }
  std::vector<std::uint8_t> frame(data, data + len);
  frame.insert(frame.end(), kTerminator.begin(), kTerminator.end());
  ++frames_to_net_;  // before publishing, as above
  message_port_pub(port_net_out(), make_pdu(meta, frame.data(), frame.size()));
}

}  // namespace gr::rfsitl
