#pragma once
/// The one place a `ports.bind` / `--bind` value becomes an address, so that
/// the node servers, the dashboard and the banner all agree on it.
#include <stdexcept>
#include <string>

namespace rfsitl::io {

/// `name` as a numeric address: an IPv4/IPv6 literal is returned as it is, a
/// host name (e.g. localhost) is resolved, preferring IPv4. Throws
/// std::runtime_error naming the value and the resolver's reason.
std::string resolve_bind_address(const std::string& name);

}  // namespace rfsitl::io
