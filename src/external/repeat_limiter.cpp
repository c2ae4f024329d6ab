#include "rfsitl/external/repeat_limiter.hpp"

namespace rfsitl::external {

RepeatLimiter::Verdict RepeatLimiter::record(const std::string& key, Clock::time_point now) {
  Verdict v;
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    // Each distinct key costs memory, and a peer chooses the key (its node id
    // and hello text): past the limit, the rest share one bucket.
    const bool room = entries_.size() < settings_.max_keys;
    v.other_keys = !room;
    it = entries_.try_emplace(room ? key : std::string()).first;
  } else {
    v.other_keys = key.empty();
  }
  Entry& e = it->second;
  ++e.total;
  if (e.total <= settings_.full) {
    e.last_line = now;
    v.action = e.total == settings_.full ? Action::kLogLast : Action::kLog;
    return v;
  }
  ++e.unreported;
  if (now - e.last_line < settings_.summary_every) {
    v.action = Action::kQuiet;
    v.repeats = 0;
    return v;
  }
  v.action = Action::kSummarize;
  v.repeats = e.unreported;
  v.seconds = std::chrono::duration<double>(now - e.last_line).count();
  e.unreported = 0;
  e.last_line = now;
  return v;
}

std::vector<RepeatLimiter::Pending> RepeatLimiter::take_pending() {
  std::vector<Pending> out;
  for (auto& [key, e] : entries_) {
    if (e.unreported == 0) continue;
    out.push_back(Pending{key, e.unreported});
    e.unreported = 0;
  }
  return out;
}

}  // namespace rfsitl::external
