#pragma once
/// One node's listening TCP port: it accepts connections for as long as it is
/// open, admits each to the port's slot (port_slot.hpp) and starts a session on
/// it. A failed accept (out of descriptors, EMFILE) never leaves the port deaf:
/// it is logged and retried after a pause. Runs on its io_context's thread.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "rfsitl/common/types.hpp"
#include "rfsitl/io/port_session.hpp"
#include "rfsitl/io/port_slot.hpp"

namespace rfsitl::io {

/// What a port is, for log lines and errors.
struct PortName {
  const char* role = "net";  ///< "net", "location"
  NodeId node = 1;
  std::uint16_t number = 0;
};

class PortListener {
 public:
  /// Makes the session for a freshly accepted connection on this port.
  using MakeSession =
      std::function<std::shared_ptr<PortSession>(boost::asio::ip::tcp::socket, PortSlot& slot)>;

  /// Binds and listens on `bind_address`:`name.number` now, so that a port in
  /// use fails the start. Throws PortError ("net port 15773 of node 1 on
  /// 127.0.0.1: Address already in use").
  PortListener(boost::asio::io_context& io, const std::string& bind_address, PortName name,
               MakeSession make);

  /// Starts accepting (before the io_context runs, or on its thread).
  void start() { accept(); }

  /// Closes the listener and every connection of the port. I/O thread (or
  /// after it has stopped).
  void close();

  PortSlot& slot() { return slot_; }
  const PortName& name() const { return name_; }

 private:
  void accept();
  void accept_failed(const boost::system::error_code& ec);

  PortName name_;
  MakeSession make_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer retry_;  // re-arms accept after a failure
  PortSlot slot_;
  std::uint64_t accept_failures_ = 0;
};

}  // namespace rfsitl::io
