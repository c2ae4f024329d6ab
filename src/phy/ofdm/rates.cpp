#include "rates.hpp"

namespace rfsitl::phy::ofdm {
namespace {

/// R1..R4 as written in Table 17-6 (R1 first) -> field value with R1 in bit 0.
constexpr std::uint8_t field(int r1, int r2, int r3, int r4) {
  return static_cast<std::uint8_t>(r1 | (r2 << 1) | (r3 << 2) | (r4 << 3));
}

// IEEE 802.11-2016 Table 17-4 (20 MHz channel spacing) and Table 17-6.
constexpr RateParams kRates[8] = {
    {6, field(1, 1, 0, 1), 1, CodeRate::kHalf, 48, 24},
    {9, field(1, 1, 1, 1), 1, CodeRate::kThreeQuarters, 48, 36},
    {12, field(0, 1, 0, 1), 2, CodeRate::kHalf, 96, 48},
    {18, field(0, 1, 1, 1), 2, CodeRate::kThreeQuarters, 96, 72},
    {24, field(1, 0, 0, 1), 4, CodeRate::kHalf, 192, 96},
    {36, field(1, 0, 1, 1), 4, CodeRate::kThreeQuarters, 192, 144},
    {48, field(0, 0, 0, 1), 6, CodeRate::kTwoThirds, 288, 192},
    {54, field(0, 0, 1, 1), 6, CodeRate::kThreeQuarters, 288, 216},
};

}  // namespace

std::optional<RateParams> rate_from_mbps(unsigned mbps) {
  for (const RateParams& r : kRates) {
    if (r.mbps == mbps) return r;
  }
  return std::nullopt;
}

std::optional<RateParams> rate_from_field(std::uint8_t rate_field) {
  for (const RateParams& r : kRates) {
    if (r.rate_field == rate_field) return r;
  }
  return std::nullopt;
}

const RateParams (&all_rates())[8] {
  return kRates;
}

}  // namespace rfsitl::phy::ofdm
