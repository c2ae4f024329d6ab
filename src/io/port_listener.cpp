#include "rfsitl/io/port_listener.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "rfsitl/io/port_error.hpp"

namespace rfsitl::io {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

constexpr std::chrono::milliseconds kAcceptRetry{100};

std::string slot_name(const PortName& n) {
  return "node " + std::to_string(n.node) + " " + n.role + " port " + std::to_string(n.number);
}

}  // namespace

PortListener::PortListener(asio::io_context& io, const std::string& bind_address, PortName name,
                           MakeSession make)
    : name_(name), make_(std::move(make)), acceptor_(io), retry_(io), slot_(slot_name(name)) {
  const std::string where = std::string(name.role) + " port " + std::to_string(name.number) +
                            " of node " + std::to_string(name.node) + " on " + bind_address;
  boost::system::error_code ec;
  tcp::resolver resolver(io);
  const auto endpoints = resolver.resolve(bind_address, std::to_string(name.number),
                                          tcp::resolver::numeric_service, ec);
  if (ec || endpoints.empty()) throw PortError(where + ": cannot resolve address: " + ec.message());
  const tcp::endpoint ep = endpoints.begin()->endpoint();
  acceptor_.open(ep.protocol(), ec);
  if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(ep, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw PortError(where + ": " + ec.message());
}

void PortListener::close() {
  slot_.close_all();
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  retry_.cancel();
}

void PortListener::accept() {
  acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec) return accept_failed(ec);
    std::shared_ptr<PortSession> session = make_(std::move(socket), slot_);
    slot_.admit(session);
    session->start();
    accept();
  });
}

// Out of descriptors (EMFILE, ENFILE) or any other transient failure: the
// listener must not go deaf for the rest of the run. It retries after a pause,
// so that a full descriptor table does not turn into a busy loop, on the port's
// own timer: nothing to allocate while descriptors (or memory) are short.
void PortListener::accept_failed(const boost::system::error_code& ec) {
  if (ec == asio::error::operation_aborted || !acceptor_.is_open()) return;  // shutdown
  ++accept_failures_;
  if (accept_failures_ <= 20 || accept_failures_ % 1000 == 0) {
    spdlog::warn("{}: cannot accept a connection ({}); retrying in {} ms", slot_.where(),
                 ec.message(), kAcceptRetry.count());
  }
  retry_.expires_after(kAcceptRetry);
  retry_.async_wait([this](const boost::system::error_code& wait_ec) {
    if (!wait_ec && acceptor_.is_open()) accept();
  });
}

}  // namespace rfsitl::io
