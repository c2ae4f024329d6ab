#pragma once
/// Keeps a log readable when the same event repeats many times a second (a
/// misconfigured process that reconnects in a loop): the first few events of
/// each kind are logged in full, later ones only as a periodic line with a
/// count. The caller keeps counting every event itself; this only decides what
/// to print. Not thread-safe: one user at a time.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rfsitl::external {

class RepeatLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  struct Settings {
    std::uint32_t full = 3;  ///< events per key that are logged in full
    Clock::duration summary_every = std::chrono::seconds(10);  ///< at most one summary per key
    std::size_t max_keys = 64;  ///< keys beyond this share one bucket (key "")
  };

  enum class Action {
    kLog,        ///< print this event in full
    kLogLast,    ///< print it in full and say that repeats will be summarized
    kSummarize,  ///< print one line for `repeats` events over `seconds`
    kQuiet,      ///< print nothing (counted for the next summary)
  };

  struct Verdict {
    Action action = Action::kLog;
    std::uint64_t repeats = 1;  ///< kSummarize: events since the last line, this one included
    double seconds = 0.0;       ///< kSummarize: time since the last line of this key
    bool other_keys = false;    ///< the event fell into the shared overflow bucket
  };

  /// Events of one key that no line has reported yet.
  struct Pending {
    std::string key;  ///< "" for the overflow bucket
    std::uint64_t repeats = 0;
  };

  RepeatLimiter() : RepeatLimiter(Settings{}) {}
  explicit RepeatLimiter(Settings settings) : settings_(settings) {}

  /// Records one event of kind `key` at `now` (non-decreasing between calls)
  /// and says what to print for it.
  Verdict record(const std::string& key, Clock::time_point now);

  /// The events still unreported (kQuiet since their key's last line), per
  /// key in key order; forgets them. For a last summary at shutdown.
  std::vector<Pending> take_pending();

  const Settings& settings() const { return settings_; }

 private:
  struct Entry {
    std::uint64_t total = 0;
    std::uint64_t unreported = 0;
    Clock::time_point last_line{};
  };

  Settings settings_;
  std::map<std::string, Entry> entries_;
};

}  // namespace rfsitl::external
