#pragma once
/// What the IP face (`--ip`: network namespaces with a TAP interface per node)
/// needs from the process, checked up front so that a run without it fails
/// with one clear sentence instead of an EPERM halfway through its set-up.
#include <optional>
#include <string>

namespace rfsitl::ip {

/// nullopt when the calling thread has both CAP_NET_ADMIN (TAP devices,
/// addresses) and CAP_SYS_ADMIN (unshare, mounts under /run/netns) effective;
/// otherwise a message naming the missing ones and how to run instead. Reads
/// the capabilities with capget(2), so it also sees capabilities granted to a
/// non-root user (setcap, ambient). Any thread; no side effects.
std::optional<std::string> missing_ip_privileges();

}  // namespace rfsitl::ip
