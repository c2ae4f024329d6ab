#pragma once
/// The one rule for a Unix socket path (the external-transceiver socket): the
/// scenario checks it at load, so that the error names the file, line and key,
/// and the emulator and `rfsitl node` check it again before bind() and
/// connect(), which would otherwise truncate or refuse it with a bare errno.
#include <sys/un.h>

#include <cstddef>
#include <string>
#include <string_view>

namespace rfsitl {

/// Bytes a socket address holds, less its terminating NUL (107 on Linux).
inline constexpr std::size_t kMaxUnixSocketPathBytes = sizeof(sockaddr_un{}.sun_path) - 1;

/// "" when `path` can name a Unix socket, else why not ("is empty", "is 212
/// bytes long; a Unix socket path holds at most 107"), without the path itself
/// so that each caller puts it where its message needs it.
inline std::string unix_socket_path_error(std::string_view path) {
  if (path.empty()) return "is empty";
  if (path.size() > kMaxUnixSocketPathBytes) {
    return "is " + std::to_string(path.size()) + " bytes long; a Unix socket path holds at most " +
           std::to_string(kMaxUnixSocketPathBytes);
  }
  if (path.find('\0') != std::string_view::npos) return "contains a NUL byte";
  return "";
}

}  // namespace rfsitl
