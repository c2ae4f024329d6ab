#pragma once
/// The DSSS transceiver: 802.11b-style direct-sequence spread spectrum (DBPSK or
/// DQPSK over Barker-11, m-sequences or Gold codes), scaled to the emulator's
/// sample rate: chip rate = fs / samples_per_chip, one symbol per code period.
/// Frame format: see frame_format.hpp; receiver: see receiver.hpp.
///
/// Code agility (the seam for the cognitive code adaptation): the radio holds a
/// code book whose entry 0 is the settings' code, the common default. Its TX path
/// picks each frame's code from a per-destination table, its RX path listens on
/// up to kMaxListenCodes codes of the book at once (each with its own search and
/// demodulator, so frames on different codes may overlap) and says which one a
/// frame came on, and every frame header carries a 16-bit control field
/// (ControlField in frame_format.hpp) set by set_tx_control. Which code to ask
/// for, and when, is the adaptation's business; this class only carries it out.
/// Isolation between codes of one family is finite (see receiver.hpp): a
/// strong enough frame on one code can also be heard on another.
///
/// Cognitive code adaptation (DsssSettings::adaptive). Both ends derive the same
/// candidate list from the default code (adaptation_candidates in
/// code_adaptation.hpp: the default, then its Gold family) and add it to the
/// book; the control field carries an index into that list.
///  * Measuring. The receiver feeds its chip-rate samples (one per chip) to a
///    lag estimator (code_adaptation.hpp) in blocks. Blocks are held back for
///    one longest-frame time; a block that overlaps a frame of its own link (a
///    frame whose header names this node as destination, decoded or not in its
///    payload) is discarded, so R is interference plus noise. The node learns
///    its own id from the src of the first frame it sends.
///  * Choosing. Every adapt_windows estimator windows the receiver runs
///    CodeSelector::choose over the candidates with hysteresis
///    adapt_hysteresis_db from its current preferred code, then restarts the
///    estimate.
///  * State (receiver side): preferred P (initially 0, the default), previous Q
///    (none or the code P replaced), epoch E (4 bits). Listening set: {0, P, Q}.
///      on a better code C:   Q := P (if P != 0), P := C, E := E + 1 mod 16.
///      on a frame to me on P from peer X: record X as switched; when no peer's
///        latest frame to me came on Q, drop Q.
///    Every frame it sends carries ControlField{request, P, E}.
///  * Transmitter side: on any decoded header from X whose control field is a
///    request for candidate C (a new (C, E) from X), frames to X go out on C from
///    then on (set_tx_code). A frame without a request leaves the table alone.
///  * Robustness. The request is repeated in every frame, so a lost frame only
///    delays the peer's switch; until a frame arrives on P the receiver still
///    listens on 0 and Q, where the peer's frames keep arriving; and the default
///    code is always heard, so the reverse link (which carries the requests)
///    works whatever the codes. Limitation: the request must get through to the
///    transmitter: if both ends are jammed on the codes they send to each other
///    on, neither learns the other's choice (the default code is then the only
///    way, and it is jammed).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

struct DsssSettings {
  /// "barker11", "mseq<N>" (N = 2^n - 1, n = 5..10) or "gold<N>[:k]"
  /// (N = 31, 63, 127, 511, 1023; k = family member, default 0).
  std::string code = "barker11";
  /// "dbpsk" (1 bit per code period) or "dqpsk" (2 bits).
  std::string modulation = "dbpsk";
  unsigned samples_per_chip = 1;         ///< 1..8
  std::size_t max_payload_bytes = 2048;  ///< 1..65535
  /// Cognitive code adaptation (see above); off by default.
  bool adaptive = false;
  /// Estimator windows (code periods of interference, one every max(1, L / 16)
  /// chips) per adaptation decision; >= 1.
  std::size_t adapt_windows = 8192;
  /// A new code must promise this much more output SINR than the current one.
  double adapt_hysteresis_db = 1.0;
  /// Size of the candidate list (default code included); 1..1024.
  std::size_t adapt_max_candidates = 128;
};

/// The adaptation's state, for observers and tests.
struct DsssAdaptationStatus {
  bool enabled = false;
  std::size_t preferred = 0;  ///< book index of the code it asks peers to use
  std::size_t previous = 0;   ///< book index still listened on during a change
  bool has_previous = false;
  std::uint8_t epoch = 0;
  std::size_t decisions = 0;       ///< adaptation steps run
  std::size_t switches = 0;        ///< changes of the preferred code
  double preferred_sinr_db = 0.0;  ///< predicted output SINR at the last decision
  double default_sinr_db = 0.0;    ///< ... of the default code at the last decision
};

/// What a decode revealed beyond RxEvent; valid from the on_rx callback of that
/// decode until the next one.
struct DsssRxInfo {
  std::size_t code = 0;       ///< code book index the frame arrived on
  std::uint16_t control = 0;  ///< header control field (0 if the header failed)
  float despread_snr_db = 0.0F;
};

class DsssTransceiver : public Transceiver {
 public:
  /// Adds a code to the book (or finds it) and returns its index.
  /// Throws std::invalid_argument if the name is not a code or its length differs
  /// from the default code's (frame lengths must not depend on the code).
  virtual std::size_t add_code(const std::string& name) = 0;
  virtual std::size_t code_count() const = 0;
  /// Canonical name of a book entry. Precondition: index < code_count().
  virtual const std::string& code_name(std::size_t index) const = 0;

  /// Frames to `dst` (including kBroadcastId) go out on book entry `code` from the
  /// next start_frame on. Precondition: code < code_count(), else std::out_of_range.
  virtual void set_tx_code(NodeId dst, std::size_t code) = 0;
  /// The code frames to `dst` use: the table's entry, else 0.
  virtual std::size_t tx_code(NodeId dst) const = 0;

  /// Listen on these book entries (1..dsss::kMaxListenCodes = 4 of them, e.g.
  /// {0, mine}) from the next receive() on; a code dropped while it is inside a
  /// frame first finishes that frame, codes kept carry on undisturbed. Each code
  /// costs one more correlator per sample. Throws std::invalid_argument on a bad
  /// count, std::out_of_range on a bad index.
  virtual void set_listen_codes(std::span<const std::size_t> codes) = 0;

  /// The control field of every following frame header (see ControlField).
  virtual void set_tx_control(std::uint16_t control) = 0;

  virtual const DsssRxInfo& last_rx_info() const = 0;

  /// The codes the RX path listens on (book indices).
  virtual std::vector<std::size_t> listen_codes() const = 0;
  virtual const DsssAdaptationStatus& adaptation_status() const = 0;
  /// Book index of candidate `index` of the adaptation's list (see above), or
  /// std::out_of_range; the list has one entry (the default) when not adaptive.
  virtual std::size_t candidate_code(std::size_t index) const = 0;
  virtual std::size_t candidate_count() const = 0;
};

/// The DSSS PHY for the registry. Throws std::invalid_argument naming the bad
/// field (code, modulation, samples_per_chip, max_payload_bytes, adapt_*).
std::unique_ptr<Transceiver> make_dsss_transceiver(const DsssSettings& settings);

/// The same radio with its code-agility interface, for the code adaptation.
std::unique_ptr<DsssTransceiver> make_code_agile_dsss_transceiver(const DsssSettings& settings);

}  // namespace rfsitl::phy
