#pragma once
/// Symbol timing and fine carrier offset from the 802.11a/g long training
/// field: the start T1 of the first long training symbol maximizes
/// |C(m)| + |C(m + 64)|, C(m) the cross-correlation of the (coarsely
/// derotated) packet with the time-domain long training symbol at lag m; the
/// residual offset is the phase between the two repetitions T1 and T2.
///
/// Single precision and one correlation per lag: the packet is derotated once
/// (not once per lag), C(m + 64) is the C of a later lag (not computed twice),
/// and the lags run in the inner loop, where the compiler vectorizes them.
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

struct LtfTiming {
  std::size_t t1 = 0;  ///< sample index of T1 in the packet buffer
  double cfo = 0.0;    ///< coarse plus fine carrier offset, radians per sample
};

class LtfSearch {
 public:
  /// `ltf_time`: the 64 time-domain samples of one long training symbol.
  explicit LtfSearch(std::span<const cf32, 64> ltf_time);

  /// Searches T1 over lags 0..max_lag of `pkt` (samples since detection) after
  /// removing `coarse_cfo` (radians per sample; sample i turned by
  /// -coarse_cfo * i). Precondition: pkt.size() >= max_lag + 128.
  LtfTiming find(std::span<const cf32> pkt, double coarse_cfo, std::size_t max_lag);

 private:
  std::array<float, 64> ref_re_{};  // conj(ltf_time), split into re and im
  std::array<float, 64> ref_im_{};
  std::vector<float> re_;  // the derotated packet, split
  std::vector<float> im_;
  std::vector<float> c_re_;  // C(m) for m in 0..max_lag + 64
  std::vector<float> c_im_;
};

}  // namespace rfsitl::phy::ofdm
