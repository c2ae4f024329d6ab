#pragma once
/// Which run owns which network namespaces. A run names its namespaces
/// <prefix>-<something> (e.g. rfsitl-15763-1) and claims the prefix first; a
/// run killed with SIGKILL cannot remove its namespaces, so the next run with
/// the same prefix does, and never those of a run that is still alive.
#include <string>
#include <vector>

namespace rfsitl::ip {

/// Where the claims' pid files live.
inline constexpr const char* kRunDir = "/run/rfsitl";

/// Claims `prefix` for this process: /run/rfsitl/<prefix>.pid holds our pid
/// and is locked with flock(LOCK_EX | LOCK_NB) for as long as the object
/// lives. The lock, not the pid, is the proof of life: the kernel drops it
/// when the process dies however it dies, and a reused pid does not hold it.
/// The descriptor is O_CLOEXEC, so programs the run execs do not keep the
/// claim (a fork that does not exec does, until it exits).
class RunClaim {
 public:
  /// Takes the claim. Another live process holding it: throws
  /// std::runtime_error naming that process's pid. Otherwise no live run uses
  /// the prefix (a run keeps its claim while its namespaces exist), so every
  /// namespace named <prefix>-* is a leftover of a dead run: they are removed
  /// and listed in removed_stale(). Throws std::invalid_argument for a prefix
  /// that is not a plain file name, std::system_error naming the prefix when
  /// the pid file or a stale namespace cannot be handled (the claim is then
  /// not held). Prefixes must not nest: claiming "a" would sweep "a-b-1" of a
  /// run that claimed "a-b".
  static RunClaim claim(const std::string& prefix);

  RunClaim(RunClaim&& other) noexcept;
  /// Releases the claim held so far first.
  RunClaim& operator=(RunClaim&& other) noexcept;
  RunClaim(const RunClaim&) = delete;
  RunClaim& operator=(const RunClaim&) = delete;
  /// Deletes the pid file, then unlocks it (in that order, so that no one
  /// takes a lock on a file that is about to disappear).
  ~RunClaim();

  const std::string& prefix() const { return prefix_; }
  /// The stale namespaces removed by claim(), sorted.
  const std::vector<std::string>& removed_stale() const { return removed_stale_; }

 private:
  RunClaim(std::string prefix, std::string path, int fd);
  void release() noexcept;

  std::string prefix_;
  std::string path_;
  int fd_ = -1;
  std::vector<std::string> removed_stale_;
};

}  // namespace rfsitl::ip
