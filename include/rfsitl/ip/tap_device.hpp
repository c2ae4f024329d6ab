#pragma once
/// A node's IP face: a TAP interface in the node's network namespace. What the
/// node's programs send there (Ethernet frames) the emulator reads from the
/// TAP's descriptor, and frames the emulator writes to it the kernel receives
/// as if from the wire.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "rfsitl/common/ip_prefix.hpp"
#include "rfsitl/ip/network_namespace.hpp"

namespace rfsitl::ip {

struct TapConfig {
  /// The interface's name (1..15 characters, no '/', ':', '%' or whitespace).
  std::string name = "rf0";
  /// All zero: keep the random one the kernel gives. Must be unicast.
  std::array<std::uint8_t, 6> mac{};
  unsigned mtu = 1500;
  std::optional<Ipv4Prefix> ipv4;  ///< the interface's address and prefix length
  /// Added without duplicate address detection, so that it is usable at once.
  std::optional<Ipv6Prefix> ipv6;
};

/// A TAP interface (IFF_TAP | IFF_NO_PI: Ethernet frames without a packet-info
/// header) created inside a network namespace, with its MAC, MTU and addresses
/// set and both it and the namespace's loopback up. Not persistent: the
/// interface disappears when this object (its descriptor) is closed. The
/// descriptor is non-blocking; read() and write() may be called from any one
/// thread (one reader and one writer may run at once), whatever the thread's
/// own namespace.
class TapDevice {
 public:
  /// Creates and configures the interface inside `ns` (on a thread of ns's,
  /// see NetworkNamespace::run_inside). Needs CAP_NET_ADMIN. Throws
  /// std::invalid_argument for a bad name or prefix length, std::system_error
  /// naming the interface, the namespace and the failed step otherwise (e.g. a
  /// name already in use there); then nothing of it is left behind. `ns` is
  /// only used during the call; the interface keeps its namespace alive.
  static TapDevice open(const NetworkNamespace& ns, const TapConfig& c);

  TapDevice(TapDevice&& other) noexcept;
  TapDevice& operator=(TapDevice&& other) noexcept;
  TapDevice(const TapDevice&) = delete;
  TapDevice& operator=(const TapDevice&) = delete;
  /// Closes the descriptor, which removes the interface.
  ~TapDevice();

  /// The non-blocking, O_CLOEXEC descriptor (for poll/epoll), owned by this
  /// object; -1 after a move.
  int fd() const { return fd_; }
  /// The interface's name in its namespace.
  const std::string& name() const { return name_; }

  /// One frame (from the Ethernet header on, without FCS) into `buf`: its
  /// length, or 0 when none is waiting. buf must hold the largest frame, MTU +
  /// 18 bytes (header and a VLAN tag): the kernel drops a frame that does not
  /// fit and reports an error. Throws std::system_error naming the interface
  /// on errors other than "nothing waiting".
  std::size_t read(std::span<std::uint8_t> buf);

  /// Hands one Ethernet frame to the kernel as received on the interface:
  /// false when the kernel would block or refuses it (e.g. shorter than an
  /// Ethernet header, or the interface is down); the caller counts the drop.
  /// Never blocks, never throws.
  bool write(std::span<const std::uint8_t> frame);

 private:
  TapDevice(int fd, std::string name, std::string namespace_name);
  std::string subject() const;

  int fd_ = -1;
  std::string name_;
  std::string namespace_name_;
};

}  // namespace rfsitl::ip
