#pragma once
// Internal to the DSSS receiver: everything the receiver does for one listened
// code, from preamble search to the frame's report. Codes run side by side on
// the shared front end, so a frame on one code never keeps the receiver from
// acquiring and decoding a frame on another.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "code_searcher.hpp"
#include "frame_demodulator.hpp"
#include "front_end.hpp"
#include "receiver.hpp"

namespace rfsitl::phy::dsss::detail {

class CodeChannel {
 public:
  void configure(const ListenCode& code, const ReceiverSettings& settings, std::size_t max_block,
                 std::int64_t start);

  /// Opens the block [first, first + n) (see CodeSearcher::begin_block).
  void begin_block(std::int64_t first, std::size_t n) { searcher_.begin_block(first, n); }

  /// Runs this code over the samples before b, in time order, reporting frames
  /// to `sink`; `others` are the other listened codes (see consider()).
  void process(const FrontEnd& fe, std::int64_t b, std::span<CodeChannel> others, FrameSink& sink);

  /// True from a detection until the frame is reported or abandoned.
  bool busy() const { return demod_active_ || searcher_.settling(); }
  /// True inside a frame whose SFD was found.
  bool committed() const { return demod_active_ && demod_.committed(); }
  const ListenCode& code() const { return code_; }

 private:
  enum class DemodResult { kRunning, kCommitted, kFinished };

  void consider(const Candidate& c, std::span<CodeChannel> others);
  bool same_signal(std::int64_t timing) const;
  DemodResult run_demod(const FrontEnd& fe, std::int64_t limit, std::int64_t b, FrameSink& sink);
  std::int64_t track_timing(const FrontEnd& fe, std::int64_t t, cf32 z);

  CodeSearcher searcher_;
  FrameDemodulator demod_;
  std::optional<Candidate> pending_;
  ListenCode code_;
  std::size_t period_ = 1;
  bool track_ = false;  // early-late gate, with two or more samples per chip
  bool demod_active_ = false;
  float strength_ = 0.0F;  // of the candidate the demodulator started on
  std::int64_t next_symbol_ = 0;
  std::int64_t last_symbol_ = 0;
  float early_ = 0.0F;
  float on_time_ = 0.0F;
  float late_ = 0.0F;
  std::size_t tracked_ = 0;
};

}  // namespace rfsitl::phy::dsss::detail
