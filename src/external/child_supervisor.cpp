#include "rfsitl/external/child_supervisor.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

extern char** environ;

namespace rfsitl::external {
namespace {

using Clock = std::chrono::steady_clock;

class Supervisor final : public ChildSupervisor {
 public:
  explicit Supervisor(ChildSettings s) : settings_(std::move(s)) {
    for (const NodeId id : settings_.node_ids) children_[id].pid = spawn(id);
    thread_ = std::thread([this] { watch(); });
  }

  ~Supervisor() override {
    stopping_.store(true);
    thread_.join();
    std::lock_guard lock(mutex_);
    for (auto& [id, c] : children_) {
      if (c.pid > 0) ::kill(c.pid, SIGTERM);
    }
    const auto deadline = Clock::now() + std::chrono::seconds(2);
    for (auto& [id, c] : children_) {
      while (c.pid > 0) {
        if (::waitpid(c.pid, nullptr, WNOHANG) != 0) {
          c.pid = 0;
        } else if (Clock::now() >= deadline) {
          ::kill(c.pid, SIGKILL);
          ::waitpid(c.pid, nullptr, 0);
          c.pid = 0;
        } else {
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
      }
    }
  }

  int pid_of(NodeId id) const override {
    std::lock_guard lock(mutex_);
    const auto it = children_.find(id);
    return it == children_.end() ? 0 : it->second.pid;
  }

  std::uint64_t restarts() const override { return restarts_.load(); }

 private:
  struct Child {
    int pid = 0;
    Clock::time_point restart_at{};
  };

  int spawn(NodeId id) {
    const std::string id_text = std::to_string(id);
    std::vector<std::string> args = {settings_.executable,  "node", "--socket",
                                     settings_.socket_path, "--id", id_text,
                                     "--exit-with-parent"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The child gets a clean signal mask (the emulator blocks SIGINT/SIGTERM to
    // take them synchronously) and its own process group, so that a Ctrl-C at
    // the terminal reaches the emulator, which then ends its children in order.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETPGROUP);
    pid_t pid = 0;
    const int err =
        ::posix_spawn(&pid, settings_.executable.c_str(), nullptr, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    if (err != 0) {
      throw std::runtime_error("cannot start the transceiver process of node " + id_text + " (" +
                               settings_.executable + "): " + std::strerror(err));
    }
    return pid;
  }

  static std::string describe_exit(int status) {
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return std::string("killed by signal ") + strsignal(WTERMSIG(status));
    return "stopped";
  }

  void watch() {
    while (!stopping_.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      std::lock_guard lock(mutex_);
      for (auto& [id, c] : children_) {
        int status = 0;
        if (c.pid > 0 && ::waitpid(c.pid, &status, WNOHANG) == c.pid) {
          c.pid = 0;
          c.restart_at =
              Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(settings_.restart_delay_s));
          spdlog::warn("node {}: transceiver process {}{}", id, describe_exit(status),
                       settings_.restart ? "; restarting it" : "");
          if (!settings_.restart) c.restart_at = Clock::time_point::max();
        } else if (c.pid == 0 && Clock::now() >= c.restart_at) {
          try {
            c.pid = spawn(id);
            restarts_.fetch_add(1);
          } catch (const std::runtime_error& e) {
            spdlog::error("{}", e.what());
            c.restart_at = Clock::now() + std::chrono::seconds(5);
          }
        }
      }
    }
  }

  ChildSettings settings_;
  mutable std::mutex mutex_;
  std::map<NodeId, Child> children_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> restarts_{0};
  std::thread thread_;
};

}  // namespace

std::unique_ptr<ChildSupervisor> start_children_of(const ChildSettings& settings) {
  return std::make_unique<Supervisor>(settings);
}

std::string current_executable() {
  std::string path(4096, '\0');
  const ssize_t n = ::readlink("/proc/self/exe", path.data(), path.size() - 1);
  if (n <= 0)
    throw std::runtime_error(std::string("readlink(/proc/self/exe): ") + std::strerror(errno));
  path.resize(static_cast<std::size_t>(n));
  return path;
}

}  // namespace rfsitl::external
