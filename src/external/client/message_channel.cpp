#include "rfsitl/external/client/message_channel.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "rfsitl/common/unix_socket_path.hpp"

namespace rfsitl::external {

MessageChannel::MessageChannel(int fd) : fd_(fd) {}

MessageChannel::~MessageChannel() {
  close();
}

MessageChannel::MessageChannel(MessageChannel&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), buffer_(std::move(other.buffer_)) {}

MessageChannel& MessageChannel::operator=(MessageChannel&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    buffer_ = std::move(other.buffer_);
  }
  return *this;
}

void MessageChannel::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

MessageChannel MessageChannel::connect_to(const std::string& path) {
  if (const std::string why = unix_socket_path_error(path); !why.empty()) {
    throw std::runtime_error("emulator socket path '" + path + "' " + why);
  }
  sockaddr_un addr{};
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket(): ") + std::strerror(errno));
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    throw std::runtime_error("cannot connect to emulator socket " + path + ": " +
                             std::strerror(err));
  }
  return MessageChannel(fd);
}

bool MessageChannel::send(MsgHeader header, std::span<const cf32> samples,
                          std::span<const std::uint8_t> extra) {
  if (fd_ < 0) return false;
  header.magic = kMagic;
  header.count = static_cast<std::uint32_t>(samples.size());
  header.extra_bytes = static_cast<std::uint32_t>(extra.size());
  iovec iov[3] = {{&header, sizeof header},
                  {const_cast<cf32*>(samples.data()), samples.size_bytes()},
                  {const_cast<std::uint8_t*>(extra.data()), extra.size()}};
  msghdr msg{};
  msg.msg_iov = iov;
  msg.msg_iovlen = 3;
  for (;;) {
    const ssize_t n = ::sendmsg(fd_, &msg, MSG_NOSIGNAL);
    if (n >= 0) return true;
    if (errno == EINTR) continue;
    close();
    return false;
  }
}

RecvStatus MessageChannel::receive(Message& out, int timeout_ms) {
  if (fd_ < 0) return RecvStatus::kClosed;
  pollfd p{fd_, POLLIN, 0};
  for (;;) {
    const int r = ::poll(&p, 1, timeout_ms);
    if (r > 0) break;
    if (r == 0) return RecvStatus::kTimeout;
    if (errno != EINTR) {
      close();
      return RecvStatus::kClosed;
    }
  }
  buffer_.resize(kMaxMessageBytes);
  ssize_t n;
  do {
    n = ::recv(fd_, buffer_.data(), buffer_.size(), MSG_TRUNC);
  } while (n < 0 && errno == EINTR);
  if (n <= 0) {
    close();
    return RecvStatus::kClosed;
  }
  const auto size = static_cast<std::size_t>(n);
  if (size < sizeof(MsgHeader) || size > buffer_.size()) return RecvStatus::kMalformed;
  std::memcpy(&out.header, buffer_.data(), sizeof(MsgHeader));
  const std::size_t sample_bytes = std::size_t{out.header.count} * sizeof(cf32);
  if (out.header.magic != kMagic ||
      sizeof(MsgHeader) + sample_bytes + out.header.extra_bytes != size) {
    return RecvStatus::kMalformed;
  }
  out.samples.resize(out.header.count);
  if (sample_bytes > 0) {  // data() may be null for an empty vector
    std::memcpy(out.samples.data(), buffer_.data() + sizeof(MsgHeader), sample_bytes);
  }
  const std::uint8_t* extra = buffer_.data() + sizeof(MsgHeader) + sample_bytes;
  out.extra.assign(extra, extra + out.header.extra_bytes);
  return RecvStatus::kOk;
}

const char* message_type_name(std::uint16_t type) {
  switch (static_cast<MsgType>(type)) {
    case MsgType::kHello:
      return "hello";
    case MsgType::kWelcome:
      return "welcome";
    case MsgType::kReject:
      return "reject";
    case MsgType::kTick:
      return "tick";
    case MsgType::kTx:
      return "tx";
    case MsgType::kTxRequest:
      return "tx-request";
    case MsgType::kRx:
      return "rx";
    case MsgType::kRxResult:
      return "rx-result";
    case MsgType::kDiscover:
      return "discover";
    case MsgType::kDiscovery:
      return "discovery";
  }
  return "unknown";
}

}  // namespace rfsitl::external
