#include "rfsitl/ip/network_namespace.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <linux/nsfs.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "unique_fd.hpp"

namespace rfsitl::ip {

namespace {

using detail::throw_errno;
using detail::UniqueFd;

std::string netns_path(const std::string& name) {
  return std::string(kNetnsDir) + "/" + name;
}

std::string subject(const std::string& name) {
  return "network namespace '" + name + "'";
}

bool valid_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.size() <= NAME_MAX;
}

void check_name(const std::string& name) {
  if (!valid_name(name)) {
    throw std::invalid_argument(subject(name) + ": not a valid name (a file name in " + kNetnsDir +
                                ")");
  }
}

/// What iproute2 does before its first `ip netns add`: /run/netns becomes a
/// mount point of its own with shared propagation, so that the namespace
/// mounts made in it later show up in every mount namespace that has a copy of
/// it (e.g. a container started afterwards that runs `ip netns exec`). Best
/// effort: when it fails, the namespaces still work here, and a /run/netns that
/// takes no mounts at all is reported by the bind mount in create().
void prepare_netns_dir(const std::string& who) {
  // Two threads doing this at once could stack two bind mounts on /run/netns.
  static std::mutex serial;
  const std::lock_guard<std::mutex> lock(serial);
  if (::mkdir(kNetnsDir, 0755) != 0 && errno != EEXIST) {
    const int err = errno;
    throw_errno(err, who + ": create " + kNetnsDir);
  }
  if (::mount("", kNetnsDir, "none", MS_SHARED | MS_REC, nullptr) == 0 || errno != EINVAL) {
    return;  // shared already, or a failure we cannot repair (e.g. no CAP_SYS_ADMIN)
  }
  // EINVAL: /run/netns is not a mount point yet; make it one and retry.
  if (::mount(kNetnsDir, kNetnsDir, "none", MS_BIND | MS_REC, nullptr) == 0) {
    ::mount("", kNetnsDir, "none", MS_SHARED | MS_REC, nullptr);
  }
}

/// Detaches whatever is mounted on `path` and deletes it; missing is fine.
void unmount_and_unlink(const std::string& who, const std::string& path) {
  // EINVAL (not mounted: a half-made one) and ENOENT are expected; any other
  // umount failure shows up as the unlink's EBUSY below.
  ::umount2(path.c_str(), MNT_DETACH | UMOUNT_NOFOLLOW);
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
    const int err = errno;
    throw_errno(err, who + ": delete " + path);
  }
}

}  // namespace

NetworkNamespace::NetworkNamespace(std::string name, int fd, bool owned)
    : name_(std::move(name)), fd_(fd), owned_(owned) {}

NetworkNamespace NetworkNamespace::create(const std::string& name) {
  check_name(name);
  const std::string who = subject(name);
  const std::string path = netns_path(name);
  prepare_netns_dir(who);
  {
    // The mount point. O_EXCL turns an existing name into an error instead of
    // a takeover of someone else's namespace.
    const UniqueFd file(::open(path.c_str(), O_RDONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0));
    if (!file.valid()) {
      const int err = errno;
      throw_errno(err, who + ": create " + path);
    }
  }
  try {
    int failed_errno = 0;
    std::string failed_step;
    // unshare() moves only the calling thread, so a thread of its own makes
    // the namespace and ends; the bind mount is what keeps the namespace alive.
    std::thread maker([&] {
      if (::unshare(CLONE_NEWNET) != 0) {
        failed_errno = errno;
        failed_step = "unshare(CLONE_NEWNET)";
        return;
      }
      // This thread's namespace, not the process's: /proc/self/ns/net would
      // name the main thread's one.
      const std::string own = "/proc/self/task/" + std::to_string(::gettid()) + "/ns/net";
      if (::mount(own.c_str(), path.c_str(), "none", MS_BIND, nullptr) != 0) {
        failed_errno = errno;
        failed_step = "bind mount of " + path;
      }
    });
    maker.join();
    if (failed_errno != 0) {
      throw_errno(failed_errno, who + ": " + failed_step);
    }
    UniqueFd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!fd.valid()) {
      const int err = errno;
      throw_errno(err, who + ": open " + path);
    }
    return NetworkNamespace(name, fd.release(), true);
  } catch (...) {
    try {
      unmount_and_unlink(who, path);
    } catch (...) {
      // The first failure is the one worth reporting.
    }
    throw;
  }
}

NetworkNamespace NetworkNamespace::attach(const std::string& name) {
  check_name(name);
  const std::string who = subject(name);
  const std::string path = netns_path(name);
  UniqueFd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd.valid()) {
    const int err = errno;
    throw_errno(err, who + ": open " + path);
  }
  // A half-made entry (an empty file with nothing mounted on it) would only
  // fail later, in setns(); say so now.
  const int type = ::ioctl(fd.get(), NS_GET_NSTYPE);
  if (type != CLONE_NEWNET) {
    throw_errno(EINVAL, who + ": " + path + " is not a network namespace");
  }
  return NetworkNamespace(name, fd.release(), false);
}

NetworkNamespace NetworkNamespace::attach_pid(int pid) {
  const std::string name = "pid:" + std::to_string(pid);
  const std::string path = "/proc/" + std::to_string(pid) + "/ns/net";
  const std::string who = "network namespace of pid " + std::to_string(pid);
  if (pid <= 0) {
    throw_errno(EINVAL, who + ": not a process id");
  }
  UniqueFd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd.valid()) {
    const int err = errno;
    throw_errno(err, who + ": open " + path);
  }
  return NetworkNamespace(name, fd.release(), false);
}

NetworkNamespace::NetworkNamespace(NetworkNamespace&& other) noexcept
    : name_(std::move(other.name_)),
      fd_(std::exchange(other.fd_, -1)),
      owned_(std::exchange(other.owned_, false)) {}

NetworkNamespace& NetworkNamespace::operator=(NetworkNamespace&& other) noexcept {
  if (this != &other) {
    drop();
    name_ = std::move(other.name_);
    fd_ = std::exchange(other.fd_, -1);
    owned_ = std::exchange(other.owned_, false);
  }
  return *this;
}

NetworkNamespace::~NetworkNamespace() {
  drop();
}

void NetworkNamespace::drop() noexcept {
  if (owned_) {
    try {
      remove();
    } catch (...) {
      // Nothing to tell from a destructor; a stale name is swept by the next
      // run's RunClaim.
    }
  }
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

void NetworkNamespace::remove() {
  if (!owned_ || fd_ < 0) {
    return;
  }
  ::close(fd_);
  fd_ = -1;
  unmount_and_unlink(subject(name_), netns_path(name_));
}

void NetworkNamespace::run_on_thread_inside(const std::function<void()>& body) const {
  std::exception_ptr error;
  // A thread of its own, because setns() moves the calling thread for good;
  // the caller's thread (perhaps the engine's) must stay where it is.
  std::thread worker([&] {
    try {
      if (fd_ < 0) {
        throw_errno(EBADF, subject(name_) + ": enter: it has been removed");
      }
      if (::setns(fd_, CLONE_NEWNET) != 0) {
        const int err = errno;
        throw_errno(err, subject(name_) + ": setns");
      }
      body();
    } catch (...) {
      error = std::current_exception();
    }
  });
  worker.join();
  if (error) {
    std::rethrow_exception(error);
  }
}

bool namespace_exists(const std::string& name) {
  struct stat st {};
  return valid_name(name) && ::lstat(netns_path(name).c_str(), &st) == 0;
}

std::vector<std::string> namespaces_with_prefix(const std::string& prefix) {
  std::vector<std::string> names;
  DIR* dir = ::opendir(kNetnsDir);
  if (dir == nullptr) {
    return names;
  }
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (valid_name(name) && name.starts_with(prefix)) {
      names.push_back(name);
    }
  }
  ::closedir(dir);
  std::sort(names.begin(), names.end());
  return names;
}

void remove_namespace(const std::string& name) {
  check_name(name);
  unmount_and_unlink(subject(name), netns_path(name));
}

}  // namespace rfsitl::ip
