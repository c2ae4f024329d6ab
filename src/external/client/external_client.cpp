#include "rfsitl/external/client/external_client.hpp"

#include <stdexcept>

namespace rfsitl::external {

std::vector<DiscoveredNode> discover(const std::string& socket_path, int timeout_ms,
                                     const std::string& program) {
  MessageChannel channel = MessageChannel::connect_to(socket_path);
  const std::string text = discovery_request_json({program});
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kDiscover);
  const std::string where = "emulator socket " + socket_path + ": discovery ";
  if (!channel.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()})) {
    throw std::runtime_error(where + "request failed: connection closed");
  }
  Message answer;
  const RecvStatus st = channel.receive(answer, timeout_ms);
  if (st != RecvStatus::kOk) {
    throw std::runtime_error(where + (st == RecvStatus::kTimeout ? "got no answer within timeout"
                                                                 : "failed: connection closed"));
  }
  if (answer.type() == MsgType::kReject) {
    throw std::runtime_error(where + "refused: " + answer.extra_text());
  }
  if (answer.type() != MsgType::kDiscovery) {
    // An emulator older than discovery answers a kDiscover with kReject
    // ("expected a hello message"), so this is a protocol slip.
    throw std::runtime_error(where + "expected a discovery answer, got " +
                             message_type_name(answer.header.type));
  }
  try {
    return read_discovery(answer.extra_text());
  } catch (const HandshakeError& e) {
    throw std::runtime_error(where + "bad answer: " + e.what());
  }
}

const Welcome& ExternalClient::connect() {
  channel_ = MessageChannel::connect_to(settings_.socket_path);
  // have_tick_ survives a reconnection: the first tick after rejoining is
  // compared with the last one before the drop.
  const std::string text =
      hello_json({settings_.node_id, settings_.role, settings_.program, settings_.exclusive});
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kHello);
  if (!channel_.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()})) {
    throw std::runtime_error("emulator socket " + settings_.socket_path + " closed during hello");
  }
  const RecvStatus st = channel_.receive(message_, settings_.handshake_timeout_ms);
  const std::string where = "emulator socket " + settings_.socket_path + ", node " +
                            std::to_string(settings_.node_id) + ": ";
  if (st != RecvStatus::kOk) {
    channel_.close();
    throw std::runtime_error(where + (st == RecvStatus::kTimeout ? "no welcome within timeout"
                                                                 : "connection closed in hello"));
  }
  if (message_.type() == MsgType::kReject) {
    channel_.close();
    throw ConnectRejected(where + "rejected: " + message_.extra_text(), message_.extra_text());
  }
  if (message_.type() != MsgType::kWelcome) {
    channel_.close();
    throw std::runtime_error(where + "expected welcome, got " +
                             message_type_name(message_.header.type));
  }
  try {
    welcome_ = read_welcome(message_.extra_text());
  } catch (const HandshakeError& e) {
    channel_.close();
    throw std::runtime_error(where + "bad welcome: " + e.what());
  }
  if (welcome_.node_id != settings_.node_id) {
    channel_.close();
    throw std::runtime_error(where + "bad welcome: it is for node " +
                             std::to_string(welcome_.node_id));
  }
  return welcome_;
}

RecvStatus ExternalClient::wait_tick(int timeout_ms) {
  const RecvStatus st = channel_.receive(message_, timeout_ms);
  if (st == RecvStatus::kTimeout || st == RecvStatus::kClosed) return st;
  if (st == RecvStatus::kMalformed || message_.type() != MsgType::kTick) {
    channel_.close();  // a slip in the protocol: start over with a new hello
    return RecvStatus::kMalformed;
  }
  tick_.follows_previous = !have_tick_ || message_.header.tick == tick_.index + 1;
  if (!tick_.follows_previous) ++discontinuities_;
  have_tick_ = true;
  tick_.index = message_.header.tick;
  tick_.time = message_.header.time;
  tick_.rx = message_.samples;
  return RecvStatus::kOk;
}

bool ExternalClient::send_tx(std::span<const cf32> tx) {
  return send_tx_with(tx, {});
}

bool ExternalClient::send_tx(std::span<const cf32> tx, const TxReport& report) {
  if (welcome_.tx_report < 1) return send_tx_with(tx, {});
  const auto bytes = tx_report_bytes(report);
  return send_tx_with(tx, bytes);
}

bool ExternalClient::send_tx_with(std::span<const cf32> tx, std::span<const std::uint8_t> extra) {
  if (tx.size() > welcome_.tick_samples) {
    throw std::invalid_argument("send_tx: " + std::to_string(tx.size()) +
                                " samples exceed the tick of " +
                                std::to_string(welcome_.tick_samples));
  }
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kTx);
  h.tick = tick_.index;
  h.time = tick_.time;
  return channel_.send(h, tx, extra);
}

}  // namespace rfsitl::external
