#pragma once
/// Streaming IEEE 802.11a/g OFDM receiver: packet detection on the short
/// preamble (delay-and-correlate), coarse CFO from the short and fine CFO from
/// the long training field, symbol timing from the long preamble, least-squares
/// channel estimation, per-symbol pilot phase tracking, SIGNAL decoding, and the
/// DATA bit pipeline (soft demapping, deinterleaving, depuncturing, Viterbi,
/// descrambling) up to the FCS check.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "rates.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

struct DecodedPpdu {
  RateParams rate;
  std::vector<std::uint8_t> psdu;  ///< LENGTH octets including the FCS
  bool fcs_ok = false;
  float snr_db = 0.0F;              ///< from the long training field
  float cfo_rad_per_sample = 0.0F;  ///< estimated carrier offset
  std::vector<cf32> data_symbols;   ///< equalized DATA constellation points
};

class OfdmReceiver {
 public:
  /// Called synchronously from push() for each PPDU whose SIGNAL field decoded
  /// (parity and rate valid); fcs_ok tells whether the PSDU is intact.
  using Handler = std::function<void(const DecodedPpdu&)>;

  virtual ~OfdmReceiver() = default;
  /// Feeds samples (any block size).
  virtual void push(std::span<const cf32> samples) = 0;
  /// True from packet detection until the PPDU is decoded or abandoned.
  virtual bool busy() const = 0;
  /// Abandons any packet in progress and returns to searching.
  virtual void reset() = 0;
};

/// Precondition: handler is callable.
std::unique_ptr<OfdmReceiver> make_ofdm_receiver(OfdmReceiver::Handler handler);

}  // namespace rfsitl::phy::ofdm
