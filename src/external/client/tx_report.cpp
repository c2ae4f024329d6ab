#include "rfsitl/external/client/tx_report.hpp"

#include <cstring>
#include <string>

namespace rfsitl::external {

std::array<std::uint8_t, sizeof(TxReport)> tx_report_bytes(const TxReport& report) {
  std::array<std::uint8_t, sizeof(TxReport)> bytes{};
  std::memcpy(bytes.data(), &report, sizeof report);
  return bytes;
}

std::optional<TxReport> read_tx_report(std::span<const std::uint8_t> extra) {
  if (extra.empty()) return std::nullopt;
  if (extra.size() < sizeof(TxReport)) {
    throw TxReportError("tx report of " + std::to_string(extra.size()) + " bytes, expected " +
                        std::to_string(sizeof(TxReport)) + " or more");
  }
  TxReport r;
  // memcpy: the extra bytes follow the samples at any alignment.
  std::memcpy(&r, extra.data(), sizeof r);
  if (r.version == 0) throw TxReportError("tx report version 0");
  return r;
}

}  // namespace rfsitl::external
