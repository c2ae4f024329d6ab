#include "rfsitl/ip/run_registry.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <climits>
#include <stdexcept>
#include <utility>

#include "rfsitl/ip/network_namespace.hpp"
#include "unique_fd.hpp"

namespace rfsitl::ip {

namespace {

using detail::throw_errno;
using detail::UniqueFd;

/// The pid the holder wrote, or "unknown" (it may not have written it yet).
std::string holder_pid(int fd) {
  std::array<char, 32> text{};
  const ssize_t n = ::pread(fd, text.data(), text.size() - 1, 0);
  std::string pid = n > 0 ? std::string(text.data(), static_cast<std::size_t>(n)) : std::string();
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) {
    pid.pop_back();
  }
  return pid.empty() ? "unknown" : pid;
}

/// Whether `fd` is still the file named `path`: the run that held the lock
/// deletes the file on its way out, maybe between our open() and our flock(),
/// and a lock on a deleted file guards nothing.
bool still_named(int fd, const std::string& path) {
  struct stat held {};
  struct stat named {};
  return ::fstat(fd, &held) == 0 && ::stat(path.c_str(), &named) == 0 &&
         held.st_dev == named.st_dev && held.st_ino == named.st_ino;
}

}  // namespace

RunClaim::RunClaim(std::string prefix, std::string path, int fd)
    : prefix_(std::move(prefix)), path_(std::move(path)), fd_(fd) {}

RunClaim RunClaim::claim(const std::string& prefix) {
  const std::string who = "run prefix '" + prefix + "'";
  if (prefix.empty() || prefix == "." || prefix == ".." || prefix.find('/') != std::string::npos ||
      prefix.size() > NAME_MAX - 8) {
    throw std::invalid_argument(who + ": not a valid prefix (a plain file name)");
  }
  if (::mkdir(kRunDir, 0755) != 0 && errno != EEXIST) {
    const int err = errno;
    throw_errno(err, who + ": create " + kRunDir);
  }
  const std::string path = std::string(kRunDir) + "/" + prefix + ".pid";
  // Each retry means another run let go of the file meanwhile; a few suffice.
  for (int attempt = 0; attempt < 16; ++attempt) {
    UniqueFd fd(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
    if (!fd.valid()) {
      const int err = errno;
      throw_errno(err, who + ": open " + path);
    }
    if (::flock(fd.get(), LOCK_EX | LOCK_NB) != 0) {
      if (errno == EINTR) {
        continue;
      }
      if (errno != EWOULDBLOCK) {
        const int err = errno;
        throw_errno(err, who + ": lock " + path);
      }
      throw std::runtime_error(who + ": in use by the live process " + holder_pid(fd.get()) +
                               " (it holds the lock on " + path +
                               "); stop that run or use another prefix");
    }
    if (!still_named(fd.get(), path)) {
      continue;
    }
    RunClaim result(prefix, path, fd.release());
    // From here on the destructor lets go of the claim should anything throw.
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(result.fd_, 0) != 0 ||
        ::pwrite(result.fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
      const int err = errno != 0 ? errno : EIO;  // a short write leaves errno alone
      throw_errno(err, who + ": write " + path);
    }
    // Holding the lock proves that no live run uses the prefix, whether or not
    // the pid file was there before (a run keeps its claim while its
    // namespaces exist), so every namespace under the prefix is stale.
    for (const std::string& name : namespaces_with_prefix(prefix + "-")) {
      remove_namespace(name);
      result.removed_stale_.push_back(name);
    }
    return result;
  }
  throw std::runtime_error(who + ": " + path + " keeps being replaced by other runs");
}

RunClaim::RunClaim(RunClaim&& other) noexcept
    : prefix_(std::move(other.prefix_)),
      path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      removed_stale_(std::move(other.removed_stale_)) {}

RunClaim& RunClaim::operator=(RunClaim&& other) noexcept {
  if (this != &other) {
    release();
    prefix_ = std::move(other.prefix_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    removed_stale_ = std::move(other.removed_stale_);
  }
  return *this;
}

RunClaim::~RunClaim() {
  release();
}

void RunClaim::release() noexcept {
  if (fd_ < 0) {
    return;
  }
  // Deleted while still locked: whoever opens the name afterwards gets a new
  // file, and whoever opened the old one sees (still_named) that it is gone.
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

}  // namespace rfsitl::ip
