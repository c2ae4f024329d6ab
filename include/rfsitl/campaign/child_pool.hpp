#pragma once
/// Runs of a campaign as child processes, a bounded number at once. Each child
/// has a process group of its own (a Ctrl-C at the terminal reaches the
/// campaign, which decides what its children get), dies with its parent
/// (PR_SET_PDEATHSIG), and writes its stdout and stderr to a log file.
#include <sys/types.h>
#include <chrono>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace rfsitl::campaign {

/// How a child ended.
struct ChildEnd {
  int exit_code = -1;      ///< when it exited; -1 when a signal ended it
  int signal = 0;          ///< the signal that ended it; 0 when it exited
  bool timed_out = false;  ///< killed by the pool after the timeout
  double wall_s = 0.0;

  bool succeeded() const { return exit_code == 0 && !timed_out; }
  /// "exit code 2", "killed by signal 11 (Segmentation fault)", "timed out after 600 s".
  std::string describe(double timeout_s) const;
};

class ChildPool {
 public:
  /// `program`: the executable every child runs; `slots`: children at once
  /// (>= 1); `timeout_s`: wall seconds before a child is killed.
  ChildPool(std::string program, std::size_t slots, double timeout_s);
  /// Stops what still runs (stop_all()).
  ~ChildPool();
  ChildPool(const ChildPool&) = delete;
  ChildPool& operator=(const ChildPool&) = delete;

  bool has_room() const { return running_.size() < slots_; }
  std::size_t running() const { return running_.size(); }

  /// Starts `program arguments...` with stdout and stderr to `log_path`
  /// (created or truncated); `id` comes back with its end. Throws
  /// std::runtime_error when no process can be made. Precondition: has_room().
  void start(std::size_t id, const std::vector<std::string>& arguments,
             const std::string& log_path);

  /// The children that ended since the last call, with their ids; kills those
  /// past the timeout first (they are reported once they are gone). Does not block.
  std::vector<std::pair<std::size_t, ChildEnd>> reap();

  /// SIGTERM to every running child, SIGKILL to those still there after
  /// `grace`; waits for all. Their ends are not reported.
  void stop_all(std::chrono::milliseconds grace = std::chrono::seconds(5));

 private:
  struct Child {
    std::size_t id;
    pid_t pid;
    std::chrono::steady_clock::time_point started;
    bool timed_out = false;
  };
  std::string program_;
  std::size_t slots_;
  double timeout_s_;
  std::vector<Child> running_;
};

}  // namespace rfsitl::campaign
