#pragma once
// Internal to the DSSS receiver: the preamble search of one listened code
// (see receiver.hpp for the statistic, its threshold and the verification).
// Each code searches on its own, so a false lock on one code never blinds the
// others.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "code_correlator.hpp"
#include "front_end.hpp"
#include "sliding_window.hpp"

namespace rfsitl::phy::dsss::detail {

/// Code periods summed by the detection statistic.
inline constexpr std::size_t kCombPeriods = 8;
/// Periods between a detection and the timing decision; also the periods over
/// which the chosen code phase is scored and verified.
inline constexpr std::size_t kSettlePeriods = 6;

/// A verified preamble: where its code periods end and what the first one despread to.
struct Candidate {
  std::int64_t decided_at = 0;  ///< the sample at which the search made up its mind
  std::int64_t timing = 0;      ///< a sample at which a code period ends (<= decided_at)
  cf32 reference{};             ///< z at `timing`, the phase reference of the next symbol
  float strength = 0.0F;        ///< despread power over its noise mean (~ L S SINR)
};

class CodeSearcher {
 public:
  /// Starts afresh at absolute sample `start`. Precondition: chips not empty.
  void configure(const std::vector<Chip>& chips, unsigned samples_per_chip, std::size_t max_block,
                 float threshold, std::int64_t start);

  const CodeCorrelator& correlator() const { return correlator_; }

  /// Opens the block [first, first + n): its powers start as zeros, computed on demand.
  void begin_block(std::int64_t first, std::size_t n);

  /// Back to searching at `from`, having forgotten everything before it; the
  /// filter outputs before `quiet_until` are ignored too (after a frame the
  /// filter still holds its last period at neighbouring code phases).
  void restart(std::int64_t from, std::int64_t quiet_until);

  /// Searches [position(), to) and stops at the first verified candidate (then
  /// position() is its decided_at) or at `to`. Precondition: to <= block end.
  std::optional<Candidate> advance(const FrontEnd& fe, std::int64_t to);

  std::int64_t position() const { return position_; }
  /// True between a detection and its verdict.
  bool settling() const { return settling_; }

 private:
  void compute(const FrontEnd& fe, std::int64_t from, std::int64_t to);
  std::optional<std::int64_t> first_crossing(const FrontEnd& fe, std::int64_t from,
                                             std::int64_t to) const;
  float comb(std::int64_t t, std::size_t periods) const;
  std::optional<Candidate> verdict(const FrontEnd& fe);

  CodeCorrelator correlator_{std::vector<Chip>{1}, 1};
  SlidingWindow<float> power_;
  std::int64_t computed_end_ = 0;
  std::int64_t start_ = 0;        // last configure(): the warm-up counts from here
  std::int64_t quiet_until_ = 0;  // powers before it stay zero
  std::int64_t position_ = 0;
  std::size_t period_ = 1;
  float threshold_ = 4.0F;
  bool settling_ = false;
  std::int64_t window_begin_ = 0;
  std::int64_t window_end_ = 0;
  std::int64_t best_sample_ = 0;
  float best_score_ = 0.0F;
};

}  // namespace rfsitl::phy::dsss::detail
