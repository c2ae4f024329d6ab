#pragma once
// Private to src/ip: the file descriptor owner and the errno exceptions its
// sources share, so that every failure names its subject, step and reason alike.
#include <unistd.h>

#include <string>
#include <system_error>
#include <utility>

namespace rfsitl::ip::detail {

/// Owns one file descriptor (-1: none) and closes it when destroyed.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
      reset(std::exchange(other.fd_, -1));
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  /// Gives the descriptor up to the caller, who closes it.
  int release() { return std::exchange(fd_, -1); }
  void reset(int fd = -1) {
    if (fd_ >= 0) {
      // close() errors are not retried: on Linux the descriptor is gone either way.
      ::close(fd_);
    }
    fd_ = fd;
  }

 private:
  int fd_ = -1;
};

/// std::system_error for `err`; what() reads "<what>: <strerror(err)>". Callers
/// copy errno into `err` before building `what`, whose allocations may change errno.
[[noreturn]] inline void throw_errno(int err, const std::string& what) {
  throw std::system_error(err, std::generic_category(), what);
}

}  // namespace rfsitl::ip::detail
