#pragma once
// Private to src/ip: the file descriptor owner (common's) and the errno
// exceptions its sources share, so that every failure names its subject, step
// and reason alike.
#include <string>
#include <system_error>

#include "rfsitl/common/unique_fd.hpp"

namespace rfsitl::ip::detail {

using rfsitl::UniqueFd;  // rfsitl/common/unique_fd.hpp

/// std::system_error for `err`; what() reads "<what>: <strerror(err)>". Callers
/// copy errno into `err` before building `what`, whose allocations may change errno.
[[noreturn]] inline void throw_errno(int err, const std::string& what) {
  throw std::system_error(err, std::generic_category(), what);
}

}  // namespace rfsitl::ip::detail
