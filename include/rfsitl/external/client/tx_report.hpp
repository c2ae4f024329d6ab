#pragma once
/// What a samples-role process tells the emulator with each kTx, after the
/// samples (the message's extra bytes): what only the process sees of the
/// node, for the emulator's node counters (summary, /api/stats, /metrics).
///
/// Versioned apart from the hello: the emulator's welcome names the version it
/// reads (Welcome::tx_report); a process sends a report only when that is at
/// least 1, so an older emulator (no tx_report) gets the kTx it knew, and an
/// older process (no report) is read as before.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace rfsitl::external {

inline constexpr std::uint32_t kTxReportVersion = 1;
/// The largest tx_report a welcome may name (read_welcome refuses more).
inline constexpr std::uint32_t kMaxTxReportVersion = 1000;

/// Version 1, as it travels (host byte order, like MsgHeader). A later version
/// may only append fields, so that a reader of version 1 reads its prefix.
struct TxReport {
  std::uint32_t version = kTxReportVersion;
  std::uint32_t reserved = 0;
  /// RX overflows (times the process's RX buffer dropped samples because the
  /// application read too slowly), counted since this connection's welcome:
  /// a total, so that the emulator adds only what is new and a report that
  /// never arrived loses nothing.
  std::uint64_t rx_overflows = 0;
};
static_assert(sizeof(TxReport) == 16 && std::is_trivially_copyable_v<TxReport>);

/// A kTx extra that is not a report.
class TxReportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The bytes of `report` for kTx's extra.
std::array<std::uint8_t, sizeof(TxReport)> tx_report_bytes(const TxReport& report);

/// Reads a kTx extra: empty means no report (std::nullopt: a process older
/// than reports); else at least sizeof(TxReport) bytes with version >= 1
/// (what follows version 1's fields is skipped). Throws TxReportError naming
/// the size or the version.
std::optional<TxReport> read_tx_report(std::span<const std::uint8_t> extra);

}  // namespace rfsitl::external
