#pragma once
/// The fast GMSK RX path: a streaming state machine over arbitrary block sizes.
///
///   idle     the preamble detector alone (a few operations per sample; this is
///            where a receiver hearing only noise spends its time)
///   search   after a detection: the C0 matched filter and the sync correlator
///            run on every sample, first over the last few dozen samples again
///            (so a late detection still finds a sync word that has begun) and
///            then on new samples, until the normalised correlation passes its
///            threshold; the best value within one symbol after that is the
///            timing and phase. The search ends without a frame once the
///            preamble detector has been quiet for longer than a preamble
///            period plus a sync word.
///   header   80 symbols, one matched-filter sample per symbol; the preamble
///            detector keeps running, so that if the header turns out false
///            (a detection on noise) a real frame that began meanwhile is still
///            searched for
///   payload  one matched-filter sample per symbol and nothing else
///
/// The work goes block by block where the decisions allow it, with the same
/// results as sample by sample: the search computes the matched filter and
/// the sync correlation for a block of samples at once (vectorised across
/// samples, receiver_kernels.hpp) and then walks them; inside a frame, the
/// symbols a block completes are filtered and then decided in one loop
/// (never past the header's or the payload's end, where the state changes).
///
/// Decodes are reported through RxHandler: header_valid false after a sync
/// word whose header fails its CRC-16; header_valid true with payload_valid
/// false/true after the payload CRC-32 (or at once if the announced payload is
/// longer than this receiver accepts).
///
/// Limits: symbol timing is the nearest sample (exact in the emulator, whose
/// delays are whole samples) and is not tracked during the frame. A frame that
/// starts during another frame's payload is lost (no capture). A false lock
/// (the sync threshold passed by noise) reads 80 header symbols before the
/// header is rejected; a real frame that began more than 32 symbols before the
/// false lock has its sync word pass unseen meanwhile and is lost, one that
/// began later is found (the search replays the last 48 symbols). The sync
/// correlation tolerates carrier offsets up to about 0.01 cycles per symbol.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "coherent_detector.hpp"
#include "frame_format.hpp"
#include "gmsk_pulse.hpp"
#include "preamble_detector.hpp"
#include "receiver_kernels.hpp"
#include "rfsitl/phy/transceiver.hpp"
#include "sample_ring.hpp"
#include "sync_correlator.hpp"

namespace rfsitl::phy::gmsk {

class FrameReceiver {
 public:
  /// Normalised sync correlation that starts a lock (see sync_correlator.hpp).
  static constexpr float kSyncThreshold = 0.4F;

  /// `kernels`: which version of the inner loops to run (the tests compare them).
  FrameReceiver(const GmskPulse& pulse, std::size_t max_payload_bytes,
                const ReceiverKernels& kernels = fastest_kernels());

  void push(std::span<const cf32> in, RxHandler& handler);
  void reset();
  bool busy() const { return state_ != State::kIdle; }

 private:
  enum class State { kIdle, kSearch, kHeader, kPayload };

  std::size_t scan_idle(std::span<const cf32> in, std::size_t i, RxHandler& handler);
  std::size_t scan_search(std::span<const cf32> in, std::size_t i, RxHandler& handler);
  std::size_t scan_frame(std::span<const cf32> in, std::size_t i, RxHandler& handler);
  void start_search(std::uint64_t t, std::uint64_t deadline, RxHandler& handler);
  std::size_t search(std::uint64_t first, std::size_t n, const cf32* fresh, RxHandler& handler);
  void filter_search_block(std::uint64_t first, std::size_t n, const cf32* fresh);
  bool search_step(std::uint64_t t, std::size_t j, bool preamble_seen, RxHandler& handler);
  void lock(std::uint64_t t, RxHandler& handler);
  std::size_t symbols_to_boundary() const;
  void demodulate_until(std::uint64_t t, RxHandler& handler);
  void demodulate_symbols(std::size_t count, RxHandler& handler);
  void on_bit(unsigned bit, RxHandler& handler);
  void finish_header(RxHandler& handler);
  void finish_payload(RxHandler& handler);
  void report(const FrameTag& tag, bool header_valid, bool payload_valid,
              std::span<const std::uint8_t> payload, RxHandler& handler);

  /// Symbols decided per demodulate_symbols() call at most (small enough that
  /// their samples fit the ring the search needs anyway, for k up to 8).
  static constexpr std::size_t kSymbolBlock = 32;

  const ReceiverKernels* kernels_;
  unsigned k_;
  std::size_t max_payload_;
  std::vector<float> c0_;
  unsigned period_samples_;       // D, the preamble period
  std::uint64_t replay_samples_;  // looked at again when a search starts
  std::uint64_t search_horizon_;  // how long a search outlives the last detection
  SampleRing ring_;
  std::vector<cf32> delayed_;       // scratch: the D samples before a block
  std::vector<cf32> window_;        // scratch: a search block's samples and the filter's reach
  std::vector<cf32> mf_;            // scratch: matched-filter outputs of a search block
  std::vector<std::uint8_t> bits_;  // scratch: a block's decisions
  PreambleDetector detector_;
  SyncCorrelator sync_;
  CoherentDetector coherent_;

  State state_ = State::kIdle;
  std::uint64_t now_ = 0;  // samples received so far

  // Search.
  std::uint64_t deadline_ = 0;
  bool candidate_ = false;
  std::uint64_t candidate_end_ = 0;
  std::uint64_t best_time_ = 0;
  float best_rho_ = 0.0F;
  cf32 best_gain_{};
  cf32 best_preamble_gain_{};

  // Header and payload.
  std::uint64_t next_symbol_time_ = 0;  // matched-filter time of the next symbol
  bool preamble_during_header_ = false;
  std::uint64_t last_preamble_ = 0;
  Whitener whitener_;
  unsigned bit_in_byte_ = 0;
  std::uint8_t byte_ = 0;
  std::size_t bytes_done_ = 0;
  std::size_t symbols_done_ = 0;
  std::array<std::uint8_t, kHeaderBytes> header_{};
  FrameHeader frame_header_{};
  std::vector<std::uint8_t> payload_;  // payload and CRC-32
  std::vector<cf32> soft_;             // z of every header and payload symbol
  float error_energy_ = 0.0F;          // sum (|Re z| - 1)^2
};

}  // namespace rfsitl::phy::gmsk
