#include "receiver.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "code_channel.hpp"
#include "front_end.hpp"

namespace rfsitl::phy::dsss {
namespace {

// Samples per processing block: the working set of a block (y, energies, the
// powers of a few codes) stays in L1/L2 while each array is swept once.
constexpr std::size_t kBlock = 1024;

void check(const ReceiverSettings& s, const std::vector<ListenCode>& codes) {
  if (s.samples_per_chip < 1 || s.samples_per_chip > 8) {
    throw std::invalid_argument("samples_per_chip " + std::to_string(s.samples_per_chip) +
                                " is outside 1..8");
  }
  if (codes.empty() || codes.size() > kMaxListenCodes) {
    throw std::invalid_argument("a DSSS receiver listens on 1.." + std::to_string(kMaxListenCodes) +
                                " codes, not " + std::to_string(codes.size()));
  }
  for (const auto& c : codes) {
    if (c.chips.empty() || c.chips.size() != codes.front().chips.size()) {
      throw std::invalid_argument("the listened codes must all have one nonzero length");
    }
  }
}

}  // namespace

class DsssReceiver::Impl {
 public:
  Impl(const ReceiverSettings& s, std::vector<ListenCode> codes) : settings_(s) {
    check(s, codes);
    codes_ = std::move(codes);
    const std::size_t length = codes_.front().chips.size();
    period_ = length * s.samples_per_chip;
    const std::size_t lookback = (length - 1) * s.samples_per_chip;
    // y: a candidate's verification reaches kSettlePeriods periods back from up
    // to a period before the block, plus the filter span and early/late taps.
    fe_.configure(s.samples_per_chip, period_, detail::kCombPeriods,
                  (detail::kSettlePeriods + 2) * period_ + lookback + 8, 2 * period_ + 8, kBlock);
    configure_channels(0);
  }

  void set_codes(std::vector<ListenCode> codes) {
    check(settings_, codes);
    if (codes.front().chips.size() != codes_.front().chips.size()) {
      throw std::invalid_argument("new listened codes have length " +
                                  std::to_string(codes.front().chips.size()) + ", the receiver " +
                                  std::to_string(codes_.front().chips.size()));
    }
    pending_codes_ = std::move(codes);
    has_pending_codes_ = true;
  }

  void push(std::span<const cf32> in, FrameSink& sink) {
    for (std::size_t done = 0; done < in.size();) {
      const std::size_t n = std::min(kBlock, in.size() - done);
      const std::int64_t a = fe_.end();
      if (has_pending_codes_) apply_pending_codes(a);
      fe_.ingest(in.subspan(done, n));
      const std::int64_t b = a + static_cast<std::int64_t>(n);
      for (auto& c : channels_) c.begin_block(a, n);
      for (auto& c : channels_) c.process(fe_, b, channels_, sink);
      done += n;
    }
  }

  void reset() {
    fe_.reset();
    if (has_pending_codes_) {
      codes_ = std::move(pending_codes_);
      has_pending_codes_ = false;
    }
    configure_channels(0);
  }

  bool busy() const {
    return std::any_of(channels_.begin(), channels_.end(),
                       [](const detail::CodeChannel& c) { return c.busy(); });
  }

  std::size_t period() const { return period_; }

 private:
  /// Switches to the pending listening set, unless a code it drops is inside a
  /// frame (then it waits for the frame's end). Codes in both sets keep their
  /// state, even mid-frame; new ones start at `start`.
  void apply_pending_codes(std::int64_t start) {
    auto kept = [&](const detail::CodeChannel& c) {
      return std::any_of(pending_codes_.begin(), pending_codes_.end(), [&](const ListenCode& w) {
        return c.code().id == w.id && c.code().chips == w.chips;
      });
    };
    for (const auto& c : channels_) {
      if (c.committed() && !kept(c)) return;
    }
    std::vector<detail::CodeChannel> next(pending_codes_.size());
    for (std::size_t k = 0; k < pending_codes_.size(); ++k) {
      const ListenCode& want = pending_codes_[k];
      const auto same = std::find_if(channels_.begin(), channels_.end(), [&](const auto& c) {
        return c.code().id == want.id && c.code().chips == want.chips;
      });
      if (same != channels_.end()) {
        next[k] = std::move(*same);
      } else {
        next[k].configure(want, settings_, kBlock, start);
      }
    }
    channels_ = std::move(next);
    codes_ = std::move(pending_codes_);
    has_pending_codes_ = false;
  }

  void configure_channels(std::int64_t start) {
    channels_.resize(codes_.size());
    for (std::size_t k = 0; k < codes_.size(); ++k) {
      channels_[k].configure(codes_[k], settings_, kBlock, start);
    }
  }

  ReceiverSettings settings_;
  std::vector<ListenCode> codes_;
  std::vector<ListenCode> pending_codes_;
  bool has_pending_codes_ = false;
  std::size_t period_ = 1;
  detail::FrontEnd fe_;
  std::vector<detail::CodeChannel> channels_;
};

DsssReceiver::DsssReceiver(const ReceiverSettings& settings, std::vector<ListenCode> codes)
    : impl_(std::make_unique<Impl>(settings, std::move(codes))) {}
DsssReceiver::~DsssReceiver() = default;

void DsssReceiver::set_codes(std::vector<ListenCode> codes) {
  impl_->set_codes(std::move(codes));
}
void DsssReceiver::push(std::span<const cf32> in, FrameSink& sink) {
  impl_->push(in, sink);
}
void DsssReceiver::reset() {
  impl_->reset();
}
bool DsssReceiver::busy() const {
  return impl_->busy();
}
std::size_t DsssReceiver::period() const {
  return impl_->period();
}

}  // namespace rfsitl::phy::dsss
