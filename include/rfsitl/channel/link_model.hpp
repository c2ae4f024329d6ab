#pragma once
/// Link models: distance -> complex channel coefficient c_nm.
#include <memory>
#include <string>

#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// Maps the distance between a transmitter and a receiver to the complex
/// coefficient that scales the transmitter's samples at that receiver.
/// Implementations are pure: the same distance always gives the same value.
class LinkModel {
 public:
  virtual ~LinkModel() = default;
  /// Precondition: distance_m >= 0.
  virtual cf32 coefficient(double distance_m) const = 0;
  virtual std::string describe() const = 0;
};

/// The RF-SITL paper's default: c = (1+j)/sqrt(2) * (d + 1)^-exponent, d in metres
/// (exponent 3 in the paper). Applies to every pair including a node and itself (d = 0).
/// Precondition: exponent >= 0.
std::unique_ptr<LinkModel> make_paper_link_model(double exponent = 3.0);

}  // namespace rfsitl::channel
