#pragma once
/// Who holds one node's port. A port has at most one agent (the connection its
/// frames go to); a new connection waits as a candidate until it sends its
/// first message (a frame on a net port, a line on a location port) or asks to
/// take over, and only then replaces the agent. So a connect-and-close probe
/// (`nc -z`, a health check) never disturbs a live agent. When the agent's
/// connection ends, the newest waiting candidate takes its place, so a
/// receive-only agent that connected while another was live is not stranded.
/// Every change of agent is logged. Runs on the I/O thread only.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rfsitl::io {

/// The part of a connection a slot needs.
class SlotMember {
 public:
  virtual ~SlotMember() = default;
  virtual void close() = 0;
  virtual bool open() const = 0;
};

class PortSlot {
 public:
  /// Candidates beyond this many are closed, oldest first.
  static constexpr std::size_t kMaxCandidates = 8;

  /// `where` names the port in log lines, e.g. "node 2 net port 15783".
  explicit PortSlot(std::string where) : where_(std::move(where)) {}

  /// A new connection: the agent at once if the port has none, else a candidate.
  void admit(std::shared_ptr<SlotMember> member);

  /// `member` sent its first message or asked to take over: it becomes the
  /// agent, and the previous agent's connection is closed. No-op for the agent.
  void claim(const SlotMember* member, const char* why);

  /// `member`'s connection ended (any reason, including our own close()).
  void closed(const SlotMember* member);

  /// The current agent, or null.
  const std::shared_ptr<SlotMember>& agent() const { return agent_; }

  const std::string& where() const { return where_; }

  bool is_agent(const SlotMember* member) const { return agent_.get() == member; }

  /// True when some connection other than `member` is the agent.
  bool held_by_other(const SlotMember* member) const {
    return agent_ && agent_.get() != member && agent_->open();
  }

  /// Closes every connection (shutdown).
  void close_all();

 private:
  std::string where_;
  std::shared_ptr<SlotMember> agent_;
  std::vector<std::shared_ptr<SlotMember>> candidates_;  // oldest first
  std::uint64_t overflow_closes_ = 0;
};

}  // namespace rfsitl::io
