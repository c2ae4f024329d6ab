#pragma once
/// A link's coefficient in physical units: transmit power and antenna gains,
/// times the chain of channel stages. With samples of unit mean power leaving
/// every transmitter, |c|^2 is the received power in mW, so a noise variance in
/// mW (radio.hpp) gives the SNR. The paper's model is the chain of one stage
/// (path_loss, model paper) at 0 dBm.
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

  /// The coefficient that scales the transmitter's samples at the receiver.
  /// Thread-safe (const).
  cf32 coefficient(const LinkGeometry& link) const;

  /// True when every stage is reciprocal.
  bool reciprocal() const { return reciprocal_; }

  double fixed_gain_db() const { return fixed_gain_db_; }

 private:
  double fixed_gain_db_;
  double fixed_amplitude_;
  std::vector<std::unique_ptr<GainStage>> stages_;
  bool reciprocal_ = true;
};

}  // namespace rfsitl::channel
