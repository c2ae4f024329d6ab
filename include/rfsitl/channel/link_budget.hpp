#pragma once
/// A link's coefficient in physical units: transmit power and antenna gains,
/// times the chain of channel stages. With samples of unit mean power leaving
/// every transmitter, |c|^2 is the received power in mW, so a noise variance in
/// mW (radio.hpp) gives the SNR. The paper's model is the chain of one stage
/// (path_loss, model paper) at 0 dBm.
///
/// The chain's large-scale stages make coefficient(), held between position
/// updates; its time-varying stages make fading(), evaluated on a grid in time.
/// A link's coefficient at a moment is their product.
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

class LinkBudget {
 public:
  /// fixed_gain_db: what every link shares, in dB relative to 1 mW (transmit
  /// power plus both antennas' gains); `stages` apply in order.
  LinkBudget(double fixed_gain_db, std::vector<std::unique_ptr<GainStage>> stages);

  /// The large-scale coefficient: the fixed gain times every stage that is not
  /// time-varying. Thread-safe (const).
  cf32 coefficient(const LinkGeometry& link) const;

  /// The product of the time-varying stages' gains (1 without any), at the
  /// ends' positions in `link`, for its path `link.path`. Thread-safe (const).
  std::complex<double> fading(const LinkGeometry& link) const;

  /// True when some stage is dispersive (delay, multipath): links are then
  /// impulse responses (paths()), not single coefficients.
  bool dispersive() const { return !dispersive_.empty(); }

  /// The link's paths: the convolution of the dispersive stages' path lists,
  /// each path's gain times the fixed gain and every other large-scale stage
  /// (one path at delay 0 with coefficient()'s value when no stage is
  /// dispersive). Replaces `out`'s contents. Thread-safe (const).
  void paths(const LinkGeometry& link, std::vector<Path>& out) const;

  /// True when every large-scale stage is reciprocal.
  bool reciprocal() const { return reciprocal_; }

  /// True when some large-scale stage depends on the ends' attitudes.
  bool depends_on_attitude() const { return depends_on_attitude_; }

  /// True when some stage is time-varying.
  bool time_varying() const { return !fading_.empty(); }

  /// The finest grid the time-varying stages ask for, seconds (0 without any).
  double update_interval_s() const { return update_interval_s_; }

  double fixed_gain_db() const { return fixed_gain_db_; }

 private:
  double fixed_gain_db_;
  double fixed_amplitude_;
  std::vector<std::unique_ptr<GainStage>> large_scale_;
  std::vector<std::unique_ptr<GainStage>> fading_;
  std::vector<const GainStage*> dispersive_;  // of large_scale_, in chain order
  bool reciprocal_ = true;
  bool depends_on_attitude_ = false;
  double update_interval_s_ = 0.0;
};

}  // namespace rfsitl::channel
