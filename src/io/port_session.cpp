#include "rfsitl/io/port_session.hpp"

#include <boost/asio/buffer.hpp>

namespace rfsitl::io {

void PortSession::close() {
  boost::system::error_code ignored;
  socket_.shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
}

void PortSession::read() {
  socket_.async_read_some(
      boost::asio::buffer(buf_),
      [self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
        if (ec) {
          self->close();
          self->finish();
          self->slot_.closed(self.get());
          return;
        }
        self->consume({self->buf_.data(), n});
        self->read();
      });
}

}  // namespace rfsitl::io
