#pragma once
/// One client connection on a node's TCP port (a net port, a location port): it
/// reads until the peer closes and hands every chunk to consume(); pending
/// handlers share its ownership. Its port's slot decides whether it is the
/// port's agent (port_slot.hpp). Runs on its io_context's thread only.
#include <cstdint>
#include <memory>
#include <span>
#include <utility>  // GCC 12 + C++20: before Boost.Asio
#include <vector>

#include <boost/asio/ip/tcp.hpp>

#include "rfsitl/io/port_slot.hpp"

namespace rfsitl::io {

class PortSession : public SlotMember, public std::enable_shared_from_this<PortSession> {
 public:
  PortSession(boost::asio::ip::tcp::socket socket, PortSlot& slot)
      : socket_(std::move(socket)), slot_(slot) {}
  PortSession(const PortSession&) = delete;
  PortSession& operator=(const PortSession&) = delete;

  /// Starts reading. The session lives as long as its reads and writes do.
  void start() { read(); }

  void close() override;
  bool open() const override { return socket_.is_open(); }

 protected:
  /// Bytes as they arrive, in order.
  virtual void consume(std::span<const std::uint8_t> bytes) = 0;

  /// The connection has ended (any reason): account for what it left unfinished.
  /// Called once, before the slot hears of the close.
  virtual void finish() = 0;

  /// Makes this connection the port's agent if it is not yet; false when it can
  /// no longer be (it was closed meanwhile).
  bool claim(const char* why) {
    slot_.claim(this, why);
    return slot_.is_agent(this);
  }

  boost::asio::ip::tcp::socket socket_;
  PortSlot& slot_;

 private:
  void read();

  std::vector<std::uint8_t> buf_ = std::vector<std::uint8_t>(64 * 1024);
};

}  // namespace rfsitl::io
