#include "rfsitl/ip/tap_device.hpp"

#include <fcntl.h>
#include <linux/if_tun.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "unique_fd.hpp"

namespace rfsitl::ip {

namespace {

using detail::throw_errno;
using detail::UniqueFd;

/// The layout of struct in6_ifreq from <linux/ipv6.h>, which cannot be
/// included next to <netinet/in.h> (both define struct in6_addr).
struct In6Ifreq {
  in6_addr addr;
  std::uint32_t prefixlen;
  int ifindex;
};
static_assert(sizeof(In6Ifreq) == 24, "struct in6_ifreq is 24 bytes in the kernel's ABI");

bool valid_interface_name(const std::string& name) {
  return !name.empty() && name.size() < IFNAMSIZ && name != "." && name != ".." &&
         std::none_of(name.begin(), name.end(), [](char ch) {
           // '%' would make TUNSETIFF pick a name (rf%d -> rf0, rf1, ...).
           return ch == '/' || ch == ':' || ch == '%' || ch == ' ' || ch == '\t' || ch == '\n';
         });
}

ifreq request_for(const std::string& name) {
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, name.data(), std::min<std::size_t>(name.size(), IFNAMSIZ - 1));
  return ifr;
}

/// Steps of open() that run inside the namespace; `who` names interface and
/// namespace for the errors.
class Configurer {
 public:
  Configurer(std::string who, std::string name) : who_(std::move(who)), name_(std::move(name)) {}

  void ioctl_or_throw(int fd, unsigned long request, void* arg, const std::string& step) const {
    if (::ioctl(fd, request, arg) != 0) {
      const int err = errno;
      throw_errno(err, who_ + ": " + step);
    }
  }

  /// Writes a /proc/sys file; false (nothing done) when it does not exist.
  /// /proc/sys/net shows the namespace of the thread that opens it, which is
  /// why this runs inside.
  bool write_sysctl(const std::string& path, const char* value) const {
    const UniqueFd file(::open(path.c_str(), O_WRONLY | O_CLOEXEC));
    if (!file.valid()) {
      if (errno == ENOENT) {
        return false;
      }
      const int err = errno;
      throw_errno(err, who_ + ": open " + path);
    }
    const std::size_t length = std::strlen(value);
    if (::write(file.get(), value, length) != static_cast<ssize_t>(length)) {
      const int err = errno;
      throw_errno(err, who_ + ": write " + path);
    }
    return true;
  }

  void bring_up(int socket_fd, const std::string& interface) const {
    ifreq ifr = request_for(interface);
    ioctl_or_throw(socket_fd, SIOCGIFFLAGS, &ifr, "read the flags of " + interface);
    ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
    ioctl_or_throw(socket_fd, SIOCSIFFLAGS, &ifr, "bring " + interface + " up");
  }

  void set_ipv4(int socket_fd, const Ipv4Prefix& a) const {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    std::memcpy(&address.sin_addr, a.bytes.data(), a.bytes.size());
    ifreq ifr = request_for(name_);
    std::memcpy(&ifr.ifr_addr, &address, sizeof address);
    ioctl_or_throw(socket_fd, SIOCSIFADDR, &ifr, "set the IPv4 address");
    // SIOCSIFADDR guesses a classful mask; the real one also fixes the
    // broadcast address and the prefix route.
    const std::uint32_t mask = a.length == 0 ? 0 : ~std::uint32_t{0} << (32 - a.length);
    address.sin_addr.s_addr = htonl(mask);
    ifr = request_for(name_);
    std::memcpy(&ifr.ifr_netmask, &address, sizeof address);
    ioctl_or_throw(socket_fd, SIOCSIFNETMASK, &ifr,
                   "set the IPv4 prefix length /" + std::to_string(a.length));
  }

  void add_ipv6(int inet_fd, const Ipv6Prefix& a) const {
    ifreq ifr = request_for(name_);
    ioctl_or_throw(inet_fd, SIOCGIFINDEX, &ifr, "read the interface index");
    const UniqueFd inet6(::socket(AF_INET6, SOCK_DGRAM | SOCK_CLOEXEC, 0));
    if (!inet6.valid()) {
      const int err = errno;
      throw_errno(err, who_ + ": open an IPv6 socket (is IPv6 disabled in the kernel?)");
    }
    In6Ifreq request{};
    std::memcpy(&request.addr, a.bytes.data(), a.bytes.size());
    request.prefixlen = a.length;
    request.ifindex = ifr.ifr_ifindex;
    ioctl_or_throw(inet6.get(), SIOCSIFADDR, &request, "add the IPv6 address");
  }

  /// Creates and configures the interface; returns its descriptor and name.
  std::pair<UniqueFd, std::string> run(const TapConfig& c) const {
    UniqueFd tun(::open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC));
    if (!tun.valid()) {
      const int err = errno;
      throw_errno(err, who_ + ": open /dev/net/tun");
    }
    ifreq ifr = request_for(name_);
    ifr.ifr_flags = IFF_TAP | IFF_NO_PI;
    // EBUSY here means the namespace has an interface of that name already.
    ioctl_or_throw(tun.get(), TUNSETIFF, &ifr, "create the interface (TUNSETIFF)");
    const UniqueFd inet(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
    if (!inet.valid()) {
      const int err = errno;
      throw_errno(err, who_ + ": open a socket to configure it");
    }
    if (std::any_of(c.mac.begin(), c.mac.end(), [](std::uint8_t b) { return b != 0; })) {
      ifr = request_for(name_);
      ifr.ifr_hwaddr.sa_family = ARPHRD_ETHER;
      std::memcpy(ifr.ifr_hwaddr.sa_data, c.mac.data(), c.mac.size());
      ioctl_or_throw(inet.get(), SIOCSIFHWADDR, &ifr, "set the MAC address");
    }
    ifr = request_for(name_);
    ifr.ifr_mtu = static_cast<int>(c.mtu);
    ioctl_or_throw(inet.get(), SIOCSIFMTU, &ifr, "set the MTU " + std::to_string(c.mtu));
    if (c.ipv6) {
      // Before the interface comes up, so that its link-local address skips
      // duplicate address detection too: a fresh namespace has no duplicates,
      // and a tentative address would refuse to be used for a second or more.
      const std::string conf = "/proc/sys/net/ipv6/conf/" + name_ + "/";
      write_sysctl(conf + "disable_ipv6", "0");
      write_sysctl(conf + "accept_dad", "0");
    }
    if (c.ipv4) {
      set_ipv4(inet.get(), *c.ipv4);
    }
    bring_up(inet.get(), name_);
    bring_up(inet.get(), "lo");
    if (c.ipv6) {
      add_ipv6(inet.get(), *c.ipv6);
    }
    return {std::move(tun), name_};
  }

 private:
  std::string who_;
  std::string name_;
};

}  // namespace

TapDevice::TapDevice(int fd, std::string name, std::string namespace_name)
    : fd_(fd), name_(std::move(name)), namespace_name_(std::move(namespace_name)) {}

TapDevice TapDevice::open(const NetworkNamespace& ns, const TapConfig& c) {
  const std::string who = "TAP '" + c.name + "' in network namespace '" + ns.name() + "'";
  if (!valid_interface_name(c.name)) {
    throw std::invalid_argument(who + ": not a valid interface name (1 to " +
                                std::to_string(IFNAMSIZ - 1) +
                                " characters, no '/', ':', '%' or spaces)");
  }
  if (c.ipv4 && c.ipv4->length > 32) {
    throw std::invalid_argument(who + ": IPv4 prefix length /" + std::to_string(c.ipv4->length) +
                                " is over 32");
  }
  if (c.ipv6 && c.ipv6->length > 128) {
    throw std::invalid_argument(who + ": IPv6 prefix length /" + std::to_string(c.ipv6->length) +
                                " is over 128");
  }
  // The descriptor comes back out of the namespace's thread and stays bound
  // to the interface whichever thread uses it later. Should a step fail,
  // closing the descriptor (UniqueFd) removes the half-made interface.
  const Configurer configurer(who, c.name);
  auto [fd, name] = ns.run_inside([&] { return configurer.run(c); });
  return TapDevice(fd.release(), std::move(name), ns.name());
}

TapDevice::TapDevice(TapDevice&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      name_(std::move(other.name_)),
      namespace_name_(std::move(other.namespace_name_)) {}

TapDevice& TapDevice::operator=(TapDevice&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) {
      ::close(fd_);
    }
    fd_ = std::exchange(other.fd_, -1);
    name_ = std::move(other.name_);
    namespace_name_ = std::move(other.namespace_name_);
  }
  return *this;
}

TapDevice::~TapDevice() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

std::string TapDevice::subject() const {
  return "TAP '" + name_ + "' in network namespace '" + namespace_name_ + "'";
}

std::size_t TapDevice::read(std::span<std::uint8_t> buf) {
  for (;;) {
    const ssize_t n = ::read(fd_, buf.data(), buf.size());
    if (n >= 0) {
      return static_cast<std::size_t>(n);
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return 0;
    }
    if (errno != EINTR) {
      const int err = errno;
      throw_errno(err, subject() + ": read");
    }
  }
}

bool TapDevice::write(std::span<const std::uint8_t> frame) {
  for (;;) {
    const ssize_t n = ::write(fd_, frame.data(), frame.size());
    if (n >= 0) {
      return static_cast<std::size_t>(n) == frame.size();
    }
    if (errno != EINTR) {
      return false;
    }
  }
}

}  // namespace rfsitl::ip
