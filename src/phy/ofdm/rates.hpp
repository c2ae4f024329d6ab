#pragma once
/// IEEE 802.11-2016 clause 17 (OFDM PHY) rate-dependent parameters, Table 17-4.
#include <cstdint>
#include <optional>

namespace rfsitl::phy::ofdm {

enum class CodeRate : std::uint8_t { kHalf, kTwoThirds, kThreeQuarters };

struct RateParams {
  unsigned mbps;            ///< data rate at 20 MHz channel spacing (6 ... 54)
  std::uint8_t rate_field;  ///< R1..R4 of the SIGNAL field, R1 in bit 0
  unsigned n_bpsc;          ///< coded bits per subcarrier: 1, 2, 4, 6
  CodeRate coding;
  unsigned n_cbps;  ///< coded bits per OFDM symbol = 48 n_bpsc
  unsigned n_dbps;  ///< data bits per OFDM symbol
};

/// Parameters for one of the eight rates (mbps = 6, 9, 12, 18, 24, 36, 48, 54), or
/// nullopt for any other value.
std::optional<RateParams> rate_from_mbps(unsigned mbps);

/// Parameters named by a SIGNAL field RATE value (4 bits, R1 in bit 0), or nullopt
/// for a value that names no rate.
std::optional<RateParams> rate_from_field(std::uint8_t rate_field);

/// Every rate, slowest first.
const RateParams (&all_rates())[8];

}  // namespace rfsitl::phy::ofdm
