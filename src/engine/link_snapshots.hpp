#pragma once
// What other threads (the dashboard, /api/stats) read of the channel while the
// engine runs: copies of the positions and link gains that the engine thread
// makes after something moved, at most once per period of virtual time, so a
// reader never touches the live channel and the engine thread never waits
// for one. Internal to the engine module.
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::engine {

class LinkSnapshots {
 public:
  explicit LinkSnapshots(double sample_rate_hz) : fs_(sample_rate_hz) {}

  /// Engine thread: a node moved or turned since the last copy.
  void mark_stale() { stale_ = true; }

  /// Engine thread, once per tick after positions are applied: copies the
  /// channel if something moved and the period since the last copy passed.
  /// Large-scale gains (an O(N^2) copy every kGainsPeriodS) for a channel
  /// without time-varying stages; otherwise the links themselves (every
  /// kLinksPeriodS), from which readers compute the gains of their moment.
  void maybe_copy(const channel::ChannelMatrix& channel, SampleTime now);
  /// Engine thread: copies now if something moved since the last copy,
  /// whatever the period (a run in parts, between two parts: the caller reads
  /// what its moves did).
  void copy_if_stale(const channel::ChannelMatrix& channel, SampleTime now);

  /// Any thread: every node's position at the latest copy.
  std::vector<std::optional<Ecef>> positions() const;

  /// Any thread: every link's power gain (tx-major, N x N) at `now` (the
  /// engine's virtual time) rounded down to a multiple of kLinksPeriodS, with
  /// time-varying stages evaluated by the first reader of each period and
  /// kept for the others (the dashboard reads twice per push, and every
  /// viewer shares a push). This only reads a copy, so it changes no outcome.
  std::vector<float> link_gains(SampleTime now) const;

  static constexpr double kGainsPeriodS = 0.02;
  // With time-varying stages: how often the links are copied after a move,
  // and the step in virtual time of the gains that link_gains() computes. A
  // person reads the dashboard's 4 snapshots a second (fast fading, tens to
  // hundreds of Hz at drone speeds, is sampled there, never followed), so 10
  // steps a second of virtual time are more than anyone can watch, and each
  // step evaluates the time-varying stages once per link and path (a fading
  // stage: M sines and cosines each, 32 by default), N^2 P evaluations that
  // the engine thread would pay whether anyone watches or not; so the reader
  // pays instead, and only while someone reads.
  static constexpr double kLinksPeriodS = 0.1;

 private:
  void copy_gains(const channel::ChannelMatrix& channel);
  void copy_links(const channel::ChannelMatrix& channel);
  /// After a copy: the next waits for a move and `period_s` of virtual time.
  void copied(SampleTime now, double period_s);

  double fs_;
  bool stale_ = true;  // positions changed since the last copy (or none yet)
  SampleTime next_copy_ = 0;
  mutable std::mutex mutex_;
  std::vector<std::optional<Ecef>> positions_;
  std::vector<float> gains_;
  std::shared_ptr<const channel::ChannelMatrix> links_;  // time-varying chains only
  mutable std::mutex faded_mutex_;                       // the gains last computed from links_:
  mutable std::vector<float> faded_;
  mutable std::shared_ptr<const channel::ChannelMatrix> faded_of_;  // ... from this copy
  mutable SampleTime faded_at_ = 0;                                 // ... at this time
};

}  // namespace rfsitl::engine
