#include "rfsitl/ip/privileges.hpp"

#include <linux/capability.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <utility>

namespace rfsitl::ip {

namespace {

bool effective(const __user_cap_data_struct (&data)[_LINUX_CAPABILITY_U32S_3], unsigned cap) {
  return (data[cap / 32].effective & (std::uint32_t{1} << (cap % 32))) != 0;
}

}  // namespace

std::optional<std::string> missing_ip_privileges() {
  // The raw syscall keeps libcap out of the build; version 3 covers all 64 bits.
  __user_cap_header_struct header{};
  header.version = _LINUX_CAPABILITY_VERSION_3;
  header.pid = 0;  // the calling thread
  __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
  if (syscall(SYS_capget, &header, data) != 0) {
    const int err = errno;
    return std::string("--ip needs CAP_NET_ADMIN and CAP_SYS_ADMIN, but capget failed (") +
           std::strerror(err) + "): run as root, e.g. sudo rfsitl run ... --ip";
  }
  std::string missing;
  for (const auto& [cap, name] :
       {std::pair<unsigned, const char*>{CAP_NET_ADMIN, "CAP_NET_ADMIN"},
        std::pair<unsigned, const char*>{CAP_SYS_ADMIN, "CAP_SYS_ADMIN"}}) {
    if (!effective(data, cap)) {
      missing += missing.empty() ? name : std::string(", ") + name;
    }
  }
  if (missing.empty()) {
    return std::nullopt;
  }
  return "--ip needs CAP_NET_ADMIN and CAP_SYS_ADMIN (missing: " + missing +
         "): run as root, e.g. sudo rfsitl run ... --ip";
}

}  // namespace rfsitl::ip
