#pragma once
/// A listening port that could not be opened.
#include <stdexcept>

namespace rfsitl::io {

/// what() names the node, the port's role and number, the address and the
/// system's reason, e.g. "net port 15773 of node 1 on 127.0.0.1: Address already
/// in use".
class PortError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rfsitl::io
