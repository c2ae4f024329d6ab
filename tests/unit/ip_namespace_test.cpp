// The IP face's Linux primitives (rfsitl::ip): namespaces that iproute2 sees,
// TAP interfaces configured in them whose frames really reach the kernel, errors
// that name their subject, and the sweep of a killed run's namespaces. They need
// CAP_NET_ADMIN and CAP_SYS_ADMIN and are skipped without. Every name starts with
// rfsitl-test-<pid>- so that parallel runs never collide, and guards remove
// everything even when an assertion fails.
#include <fcntl.h>
#include <linux/capability.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "rfsitl/ip/network_namespace.hpp"
#include "rfsitl/ip/privileges.hpp"
#include "rfsitl/ip/run_registry.hpp"
#include "rfsitl/ip/tap_device.hpp"

namespace rfsitl::ip {
namespace {

using Mac = std::array<std::uint8_t, 6>;
using Ipv4 = std::array<std::uint8_t, 4>;

#define RFSITL_SKIP_WITHOUT_IP_PRIVILEGES()             \
  do {                                                  \
    if (const auto missing = missing_ip_privileges()) { \
      GTEST_SKIP() << *missing;                         \
    }                                                   \
  } while (false)

std::string test_prefix() {
  return "rfsitl-test-" + std::to_string(::getpid()) + "-";
}

/// Removes every namespace named prefix* (and a claim's pid file, if given)
/// when the test ends, however it ends.
class Sweep {
 public:
  explicit Sweep(std::string prefix, std::string pid_file = {})
      : prefix_(std::move(prefix)), pid_file_(std::move(pid_file)) {}
  Sweep(const Sweep&) = delete;
  Sweep& operator=(const Sweep&) = delete;
  ~Sweep() {
    for (const std::string& name : namespaces_with_prefix(prefix_)) {
      try {
        remove_namespace(name);
      } catch (...) {
      }
    }
    if (!pid_file_.empty()) {
      ::unlink(pid_file_.c_str());
    }
  }

 private:
  std::string prefix_;
  std::string pid_file_;
};

/// The inode of a namespace file: equal inodes, same namespace.
ino_t inode_of(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? st.st_ino : 0;
}

struct InterfaceState {
  bool found = false;
  Mac mac{};
  int mtu = 0;
  bool up = false;
  bool loopback_up = false;
  Ipv4 ipv4{};
  std::string ipv6_lines;  // this interface's lines of /proc/net/if_inet6
};

/// What the kernel says about `name`; call inside the interface's namespace.
InterfaceState read_interface(const std::string& name) {
  InterfaceState s;
  const int sock = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ifreq ifr{};
  const auto ask = [&](const char* interface, unsigned long request) {
    ifr = ifreq{};
    std::strncpy(ifr.ifr_name, interface, IFNAMSIZ - 1);
    return ::ioctl(sock, request, &ifr) == 0;
  };
  s.found = ask(name.c_str(), SIOCGIFHWADDR);
  std::memcpy(s.mac.data(), ifr.ifr_hwaddr.sa_data, s.mac.size());
  s.mtu = ask(name.c_str(), SIOCGIFMTU) ? ifr.ifr_mtu : 0;
  s.up = ask(name.c_str(), SIOCGIFFLAGS) && (ifr.ifr_flags & IFF_UP) != 0;
  s.loopback_up = ask("lo", SIOCGIFFLAGS) && (ifr.ifr_flags & IFF_UP) != 0;
  if (ask(name.c_str(), SIOCGIFADDR)) {
    std::memcpy(s.ipv4.data(), &reinterpret_cast<const sockaddr_in*>(&ifr.ifr_addr)->sin_addr, 4);
  }
  ::close(sock);
  // thread-self: /proc/self/net would show the main thread's namespace.
  std::ifstream inet6("/proc/thread-self/net/if_inet6");
  for (std::string line; std::getline(inet6, line);) {
    if (line.ends_with(" " + name)) {
      s.ipv6_lines += line + "\n";
    }
  }
  return s;
}

TEST(IpNamespace, TapIsMadeInsideWithItsMacMtuAndAddressesAndGoesAwayWithIt) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  const std::string name = test_prefix() + "tap";
  const Sweep sweep(name);
  const ino_t caller_namespace = inode_of("/proc/thread-self/ns/net");
  {
    const NetworkNamespace ns = NetworkNamespace::create(name);
    EXPECT_TRUE(ns.owned());
    EXPECT_EQ(ns.name(), name);
    EXPECT_TRUE(namespace_exists(name));
    const auto listed = namespaces_with_prefix(test_prefix());
    EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end());

    TapConfig c;
    c.name = "rf0";
    c.mac = {0x02, 0x52, 0x46, 0x00, 0x00, 0x01};
    c.mtu = 1400;
    c.ipv4 = Ipv4Prefix{{10, 77, 1, 1}, 24};
    c.ipv6 = Ipv6Prefix{{0xfd, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x01}, 64};
    const TapDevice tap = TapDevice::open(ns, c);
    EXPECT_EQ(tap.name(), "rf0");
    EXPECT_GE(tap.fd(), 0);
    EXPECT_NE(::fcntl(tap.fd(), F_GETFL) & O_NONBLOCK, 0);

    // With accept_dad off the kernel still clears the tentative flag (0x40)
    // from a work queue, a moment after the address was added: wait for it,
    // up to a bound far below DAD's own second or more.
    InterfaceState s = ns.run_inside([] { return read_interface("rf0"); });
    const auto settled = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (s.ipv6_lines.find(" 40 00 80 ") == std::string::npos &&
           std::chrono::steady_clock::now() < settled) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      s = ns.run_inside([] { return read_interface("rf0"); });
    }
    ASSERT_TRUE(s.found) << "rf0 not found inside " << name;
    EXPECT_EQ(s.mac, c.mac);
    EXPECT_EQ(s.mtu, 1400);
    EXPECT_TRUE(s.up);
    EXPECT_TRUE(s.loopback_up);
    EXPECT_EQ(s.ipv4, (Ipv4{10, 77, 1, 1}));
    // Address, ifindex, prefix 40 (= 64), scope, flags: 80 is permanent, so
    // not tentative (no duplicate address detection holding it back).
    EXPECT_NE(s.ipv6_lines.find("fd000000000000000000000000000001 "), std::string::npos)
        << s.ipv6_lines;
    EXPECT_NE(s.ipv6_lines.find(" 40 00 80 "), std::string::npos) << s.ipv6_lines;
    // The namespace's own file, as seen from a thread inside it.
    EXPECT_EQ(ns.run_inside([] { return inode_of("/proc/thread-self/ns/net"); }),
              inode_of(std::string(kNetnsDir) + "/" + name));
  }
  EXPECT_FALSE(namespace_exists(name));
  EXPECT_EQ(inode_of("/proc/thread-self/ns/net"), caller_namespace);
}

std::vector<std::uint8_t> arp(std::uint16_t opcode, const Mac& from_mac, const Ipv4& from_ip,
                              const Mac& to_mac, const Ipv4& to_ip) {
  std::vector<std::uint8_t> f;
  f.insert(f.end(), to_mac.begin(), to_mac.end());
  f.insert(f.end(), from_mac.begin(), from_mac.end());
  f.insert(f.end(),
           {0x08, 0x06, 0x00, 0x01, 0x08, 0x00, 6, 4, 0x00, static_cast<std::uint8_t>(opcode)});
  f.insert(f.end(), from_mac.begin(), from_mac.end());
  f.insert(f.end(), from_ip.begin(), from_ip.end());
  if (opcode == 1) {
    f.insert(f.end(), 6, 0);  // the hardware address asked for
  } else {
    f.insert(f.end(), to_mac.begin(), to_mac.end());
  }
  f.insert(f.end(), to_ip.begin(), to_ip.end());
  return f;
}

TEST(IpNamespace, ArpRequestWrittenToATapIsAnsweredByItsKernel) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  const std::string prefix = test_prefix() + "arp-";
  const Sweep sweep(prefix);
  const Mac mac_a{0x02, 0x52, 0x46, 0x00, 0x00, 0x0a};
  const Mac mac_b{0x02, 0x52, 0x46, 0x00, 0x00, 0x0b};
  const Ipv4 ip_a{10, 77, 2, 1};
  const Ipv4 ip_b{10, 77, 2, 2};
  const NetworkNamespace ns_a = NetworkNamespace::create(prefix + "a");
  const NetworkNamespace ns_b = NetworkNamespace::create(prefix + "b");
  TapConfig config_a;
  config_a.mac = mac_a;
  config_a.ipv4 = Ipv4Prefix{ip_a, 24};
  TapConfig config_b;
  config_b.mac = mac_b;
  config_b.ipv4 = Ipv4Prefix{ip_b, 24};
  TapDevice tap_a = TapDevice::open(ns_a, config_a);
  TapDevice tap_b = TapDevice::open(ns_b, config_b);

  // B asks A, as if B's frame had crossed the radio channel.
  ASSERT_TRUE(tap_a.write(arp(1, mac_b, ip_b, mac_a, ip_a)));
  const std::vector<std::uint8_t> expected = arp(2, mac_a, ip_a, mac_b, ip_b);
  std::optional<std::vector<std::uint8_t>> reply;
  std::array<std::uint8_t, 2048> buf{};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!reply && std::chrono::steady_clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd p{tap_a.fd(), POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(left.count(), 0))) <= 0) {
      continue;
    }
    // Other frames (IPv6 router solicitations, MLD reports) may come first.
    for (std::size_t n = tap_a.read(buf); n > 0 && !reply; n = tap_a.read(buf)) {
      if (n >= 22 && buf[12] == 0x08 && buf[13] == 0x06 && buf[20] == 0x00 && buf[21] == 0x02) {
        reply.emplace(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
      }
    }
  }
  ASSERT_TRUE(reply) << "no ARP reply from " << prefix << "a within 2 s";
  // The kernel may pad the reply to the 60-byte minimum; the ARP part is exact.
  ASSERT_GE(reply->size(), expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), reply->begin()));
  // And B's kernel takes it from its own TAP.
  EXPECT_TRUE(tap_b.write(*reply));
  EXPECT_FALSE(tap_b.write(std::vector<std::uint8_t>(6, 0xff)));  // shorter than a header
}

TEST(IpNamespace, ExistingAndMissingNamesAreErrorsNamingThem) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  const std::string name = test_prefix() + "dup";
  const std::string missing = test_prefix() + "missing";
  const Sweep sweep(name);
  const NetworkNamespace ns = NetworkNamespace::create(name);
  try {
    NetworkNamespace::create(name);
    ADD_FAILURE() << "created " << name << " twice";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), std::errc::file_exists);
  }
  EXPECT_TRUE(namespace_exists(name)) << "the failed create removed the existing namespace";
  try {
    NetworkNamespace::attach(missing);
    ADD_FAILURE() << "attached to " << missing;
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + missing + "'"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), std::errc::no_such_file_or_directory);
  }
  EXPECT_THROW(NetworkNamespace::create("a/b"), std::invalid_argument);
  TapConfig bad;
  bad.name = "much-too-long-name";
  EXPECT_THROW(TapDevice::open(ns, bad), std::invalid_argument);
  {
    const NetworkNamespace attached = NetworkNamespace::attach(name);
    EXPECT_FALSE(attached.owned());
    EXPECT_EQ(attached.run_inside([] { return inode_of("/proc/thread-self/ns/net"); }),
              inode_of(std::string(kNetnsDir) + "/" + name));
    EXPECT_THROW(attached.run_inside([] { throw std::runtime_error("inside"); }),
                 std::runtime_error);
    const NetworkNamespace own = NetworkNamespace::attach_pid(::getpid());
    EXPECT_EQ(own.name(), "pid:" + std::to_string(::getpid()));
  }
  EXPECT_TRUE(namespace_exists(name)) << "an attached namespace was removed";
}

TEST(IpPrivileges, AMissingCapabilityIsNamed) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  // Capabilities are per thread: this thread alone drops CAP_SYS_ADMIN.
  std::optional<std::string> message;
  std::thread([&] {
    __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
    ::syscall(SYS_capget, &header, data);
    data[CAP_SYS_ADMIN / 32].effective &= ~(1U << (CAP_SYS_ADMIN % 32));
    if (::syscall(SYS_capset, &header, data) == 0) {
      message = missing_ip_privileges();
    }
  }).join();
  ASSERT_TRUE(message);
  EXPECT_NE(message->find("(missing: CAP_SYS_ADMIN)"), std::string::npos) << *message;
  EXPECT_NE(message->find("run as root"), std::string::npos) << *message;
}

std::string pid_file_of(const std::string& prefix) {
  return std::string(kRunDir) + "/" + prefix + ".pid";
}

TEST(IpRunClaim, NamespacesOfAKilledRunAreSweptByTheNextClaim) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  const std::string prefix = test_prefix() + "killed";
  const Sweep sweep(prefix + "-", pid_file_of(prefix));
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // A run that dies without cleaning up (as under SIGKILL): its claim and
    // its namespace are alive when it ends, and no destructor runs.
    try {
      const RunClaim claim = RunClaim::claim(prefix);
      const NetworkNamespace ns = NetworkNamespace::create(prefix + "-1");
      ::_exit(0);
    } catch (...) {
      ::_exit(1);
    }
  }
  // Wait for the child with a bound: a pidfd becomes readable when it ends.
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, child, 0));
  pollfd p{pidfd, POLLIN, 0};
  const bool ended = pidfd >= 0 && ::poll(&p, 1, 10'000) == 1;
  if (!ended) {
    ::kill(child, SIGKILL);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  if (pidfd >= 0) {
    ::close(pidfd);
  }
  ASSERT_TRUE(ended) << "the child did not end within 10 s";
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child failed: " << status;
  ASSERT_TRUE(namespace_exists(prefix + "-1"));
  std::ifstream left(pid_file_of(prefix));
  std::string dead_pid;
  left >> dead_pid;
  EXPECT_EQ(dead_pid, std::to_string(child));

  {
    const RunClaim claim = RunClaim::claim(prefix);
    EXPECT_EQ(claim.removed_stale(), std::vector<std::string>{prefix + "-1"});
    EXPECT_FALSE(namespace_exists(prefix + "-1"));
    std::ifstream ours(pid_file_of(prefix));
    std::string our_pid;
    ours >> our_pid;
    EXPECT_EQ(our_pid, std::to_string(::getpid()));
  }
  EXPECT_NE(::access(pid_file_of(prefix).c_str(), F_OK), 0) << "the released claim left its file";
}

TEST(IpRunClaim, ALiveClaimIsRefusedNamingItsPidAndKeepsItsNamespaces) {
  RFSITL_SKIP_WITHOUT_IP_PRIVILEGES();
  const std::string prefix = test_prefix() + "live";
  const Sweep sweep(prefix + "-", pid_file_of(prefix));
  const RunClaim first = RunClaim::claim(prefix);
  EXPECT_TRUE(first.removed_stale().empty());
  const NetworkNamespace ns = NetworkNamespace::create(prefix + "-1");
  try {
    RunClaim::claim(prefix);
    ADD_FAILURE() << "claimed " << prefix << " twice";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("live process " + std::to_string(::getpid())),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(namespace_exists(prefix + "-1"));
}

}  // namespace
}  // namespace rfsitl::ip
