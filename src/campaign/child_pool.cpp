#include "rfsitl/campaign/child_pool.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace rfsitl::campaign {

std::string ChildEnd::describe(double timeout_s) const {
  if (timed_out) return "timed out after " + std::to_string(static_cast<long>(timeout_s)) + " s";
  if (signal != 0) {
    return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  }
  return "exit code " + std::to_string(exit_code);
}

ChildPool::ChildPool(std::string program, std::size_t slots, double timeout_s)
    : program_(std::move(program)), slots_(slots < 1 ? 1 : slots), timeout_s_(timeout_s) {}

ChildPool::~ChildPool() {
  stop_all();
}

void ChildPool::start(std::size_t id, const std::vector<std::string>& arguments,
                      const std::string& log_path) {
  // Everything the child needs is made before fork(): after it only
  // async-signal-safe calls.
  std::vector<std::string> words = {program_};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log < 0) throw std::runtime_error(log_path + ": cannot write: " + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before the line above
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);  // the campaign blocks SIGINT/SIGTERM; not its runs
    const int null_in = ::open("/dev/null", O_RDONLY);
    if (null_in >= 0) ::dup2(null_in, STDIN_FILENO);
    ::dup2(log, STDOUT_FILENO);
    ::dup2(log, STDERR_FILENO);
    ::execv(program_.c_str(), argv.data());
    const char msg[] = "rfsitl sweep: cannot start the run's program\n";
    static_cast<void>(::write(STDERR_FILENO, msg, sizeof msg - 1));
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::close(log);
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(fork_errno));
  ::setpgid(pid, pid);  // also here: whichever of the two runs first, the group exists
  running_.push_back({id, pid, std::chrono::steady_clock::now()});
}

std::vector<std::pair<std::size_t, ChildEnd>> ChildPool::reap() {
  std::vector<std::pair<std::size_t, ChildEnd>> ended;
  const auto now = std::chrono::steady_clock::now();
  for (auto it = running_.begin(); it != running_.end();) {
    const double wall_s = std::chrono::duration<double>(now - it->started).count();
    int status = 0;
    const pid_t r = ::waitpid(it->pid, &status, WNOHANG);
    if (r == it->pid) {
      ChildEnd end;
      end.wall_s = wall_s;
      end.timed_out = it->timed_out;
      if (WIFEXITED(status)) end.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) end.signal = WTERMSIG(status);
      ended.emplace_back(it->id, end);
      it = running_.erase(it);
      continue;
    }
    if (!it->timed_out && wall_s > timeout_s_) {
      ::kill(-it->pid, SIGKILL);  // its group: whatever it started goes too
      it->timed_out = true;
    }
    ++it;
  }
  return ended;
}

void ChildPool::stop_all(std::chrono::milliseconds grace) {
  for (const Child& c : running_) ::kill(-c.pid, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (!running_.empty()) {
    for (auto it = running_.begin(); it != running_.end();) {
      int status = 0;
      it = ::waitpid(it->pid, &status, WNOHANG) == it->pid ? running_.erase(it) : it + 1;
    }
    if (running_.empty()) break;
    if (std::chrono::steady_clock::now() > deadline) {
      for (const Child& c : running_) ::kill(-c.pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace rfsitl::campaign
