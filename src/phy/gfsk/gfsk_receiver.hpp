#pragma once
/// The GFSK RX path: a streaming state machine over arbitrary block sizes.
///
/// Every sample goes through the receiver's symbol metric (symbol_metrics.hpp),
/// whose value is kept in a ring, and its hard decision is shifted into one of
/// k 64-bit histories, that of the sample's phase n mod k; each history thus
/// holds the decisions of the symbols that would end at n, n - k, n - 2k, ...
///
///   search   the history just updated is compared with the 48-bit sync
///            pattern (gfsk_frame.hpp); at most kSyncErrors differing bits is
///            a hit. On noise this is all the work besides the metric:
///            P(hit) = sum_{e <= 3} C(48, e) / 2^48 = 7e-11 per sample, one
///            false hit per four hours of 1 Msps (the header CRC then rejects it).
///   align    half a symbol after the hit, the sample within half a symbol of
///            it of largest soft correlation with the pattern becomes the
///            symbol timing; the discriminator's carrier-offset bias is the
///            mean metric over up to 32 preamble symbols before the sync word.
///   header   80 symbols, one metric value per symbol, k samples apart; on a
///            CRC failure the decode is reported with header_valid false and
///            the search resumes at once (the histories kept running, so a
///            real frame that began meanwhile is still found)
///   payload  the announced octets and the CRC-16, then the report.
///
/// Limits: symbol timing is the nearest sample and is not tracked within a
/// frame (no sample clock drift in the emulator); a frame that starts during
/// another's payload is lost (no capture).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "gfsk_frame.hpp"
#include "gfsk_transceiver.hpp"
#include "phy/gmsk/frame_format.hpp"
#include "rfsitl/phy/transceiver.hpp"
#include "symbol_metrics.hpp"

namespace rfsitl::phy::gfsk {

class GfskFrameReceiver {
 public:
  static constexpr unsigned kSyncErrors = 3;
  /// Preamble symbols averaged for the discriminator's offset (at most).
  static constexpr unsigned kOffsetSymbols = 32;

  explicit GfskFrameReceiver(const GfskSettings& settings);

  void push(std::span<const cf32> in, RxHandler& handler);
  void reset();
  bool busy() const { return state_ != State::kSearch; }

 private:
  enum class State { kSearch, kAlign, kHeader, kPayload };

  template <class Metric>
  void run(Metric& metric, std::span<const cf32> in, RxHandler& handler);
  void on_sync_hit();
  void lock();
  void on_symbol(float m, RxHandler& handler);
  void finish_header(RxHandler& handler);
  void finish_payload(RxHandler& handler);
  void report(bool header_valid, bool payload_valid, std::span<const std::uint8_t> payload,
              RxHandler& handler);
  float metric_at(std::uint64_t t) const { return ring_[t & ring_mask_]; }

  unsigned k_;
  GfskReceiver kind_;
  bool whitening_;
  unsigned offset_symbols_;  // even, <= kOffsetSymbols
  std::size_t max_payload_;
  EnergyMetric energy_;
  DiscriminatorMetric discriminator_;
  std::vector<float> ring_;  // metric values by sample time
  std::uint64_t ring_mask_;
  std::vector<std::uint64_t> history_;  // hard decisions, by sample phase
  unsigned phase_ = 0;                  // t_ mod k
  std::uint64_t t_ = 0;                 // samples received since reset

  State state_ = State::kSearch;
  std::uint64_t hit_time_ = 0;
  float offset_ = 0.0F;
  std::uint64_t next_symbol_time_ = 0;
  gmsk::Whitener whitener_;
  std::uint8_t octet_ = 0;
  unsigned bits_in_octet_ = 0;
  std::size_t octets_done_ = 0;
  std::size_t octets_wanted_ = 0;
  std::array<std::uint8_t, kHeaderBytes> header_{};
  FrameTag tag_{};
  std::vector<std::uint8_t> payload_;  // payload and CRC-16
  std::vector<float> soft_;            // metric of every header and payload symbol
  std::vector<cf32> symbols_;          // soft_, scaled, for RxEvent::symbols
  double power_ = 0.0;                 // sum |y|^2 since the lock
  std::uint64_t power_samples_ = 0;
};

}  // namespace rfsitl::phy::gfsk
