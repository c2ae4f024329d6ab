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
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

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
};

/// The DSSS PHY for the registry. Throws std::invalid_argument naming the bad
/// field (code, modulation, samples_per_chip, max_payload_bytes).
std::unique_ptr<Transceiver> make_dsss_transceiver(const DsssSettings& settings);

/// The same radio with its code-agility interface, for the code adaptation.
std::unique_ptr<DsssTransceiver> make_code_agile_dsss_transceiver(const DsssSettings& settings);

}  // namespace rfsitl::phy
