#pragma once
/// Shared helpers of the external-transceiver tests: a socket path per test and
/// process, bounded waits, and a thread that is always joined.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <string>
#include <thread>
#include <utility>

namespace rfsitl::external::testing {

/// A Unix socket path unique to the running test and process (well below the
/// 107-byte sun_path limit), removed again when the guard goes away.
class SocketPath {
 public:
  SocketPath() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? info->name() : "test";
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';  // e.g. "/" of TEST_P
    }
    if (name.size() > 48) name.erase(0, name.size() - 48);  // keep the distinct end
    path_ = "/tmp/rfsitl-ut-" + name + "-" + std::to_string(::getpid()) + ".sock";
    ::unlink(path_.c_str());
  }
  ~SocketPath() { ::unlink(path_.c_str()); }
  SocketPath(const SocketPath&) = delete;
  SocketPath& operator=(const SocketPath&) = delete;

  const std::string& str() const { return path_; }

 private:
  std::string path_;
};

/// Polls `done` every millisecond until it holds or `limit` has passed.
template <class Predicate>
bool wait_until(Predicate done, std::chrono::milliseconds limit = std::chrono::seconds(3)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

/// A std::thread that is joined when it goes out of scope, also when an
/// assertion leaves the test early (the thread body must end by itself within
/// a bounded time).
class JoiningThread {
 public:
  JoiningThread() = default;
  template <class F>
  explicit JoiningThread(F&& f) : thread_(std::forward<F>(f)) {}
  ~JoiningThread() { join(); }
  JoiningThread(JoiningThread&&) = default;
  JoiningThread& operator=(JoiningThread&& other) noexcept {
    join();
    thread_ = std::move(other.thread_);
    return *this;
  }
  void join() {
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::thread thread_;
};

}  // namespace rfsitl::external::testing
