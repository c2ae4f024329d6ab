#include "rfsitl/channel/link_model.hpp"

#include <cassert>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace rfsitl::channel {
namespace {

/// c = (1+j)/sqrt(2) * (d + 1)^-exponent. The (1+j)/sqrt(2) factor has unit
/// magnitude, so |c|^2 = (d + 1)^(-2 exponent) is the power gain, and the +1
/// keeps the gain finite (and exactly 1) at d = 0, the half-duplex self link.
class PaperLinkModel final : public LinkModel {
 public:
  explicit PaperLinkModel(double exponent) : exponent_(exponent) {}

  cf32 coefficient(double distance_m) const override {
    assert(distance_m >= 0.0);
    // Evaluated in double and rounded once, so near-field and far-field gains
    // are both within half a float ulp of the formula.
    const double g = std::pow(distance_m + 1.0, -exponent_) * (1.0 / std::numbers::sqrt2);
    const auto gf = static_cast<float>(g);
    return {gf, gf};
  }

  std::string describe() const override {
    std::ostringstream os;
    os << "paper: c=(1+j)/sqrt2*(d+1)^-" << exponent_;
    return os.str();
  }

 private:
  double exponent_;
};

}  // namespace

std::unique_ptr<LinkModel> make_paper_link_model(double exponent) {
  // Checked here rather than per call: a negative or NaN exponent would make
  // far nodes louder than near ones, a configuration error worth reporting.
  if (!(exponent >= 0.0) || !std::isfinite(exponent)) {
    throw std::invalid_argument("paper link model: path-loss exponent must be finite and >= 0");
  }
  return std::make_unique<PaperLinkModel>(exponent);
}

}  // namespace rfsitl::channel
