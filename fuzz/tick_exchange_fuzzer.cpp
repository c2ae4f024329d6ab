/// Distributed runs: the messages a rank reads from its peers every tick
/// (src/engine/tick_exchange.hpp), on arbitrary bytes.
///
/// Input: [1 byte: which message (TX, ledger ops, counters)][bytes...].
/// Checks: a reader either throws std::runtime_error naming a rank or returns
/// what is consistent with the limits it was given (node indices < nodes,
/// samples within the tick and within the bytes); what it returns, written
/// again and read again, is the same.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "tick_exchange.hpp"

using namespace rfsitl::engine;

namespace {

constexpr std::size_t kNodes = 8;
constexpr std::size_t kTick = 16;

void check_error(const std::runtime_error& e) {
  FUZZ_CHECK(std::string(e.what()).find("rank 1") != std::string::npos, "%s", e.what());
}

void tx(std::span<const std::uint8_t> bytes) {
  TxMessageView v;
  try {
    v = read_tx_message(bytes, 1, kNodes, kTick);
  } catch (const std::runtime_error& e) {
    check_error(e);
    return;
  }
  TxMessage m;
  m.stop = v.stop;
  m.reports = v.reports;
  m.updates = v.updates;
  std::vector<std::vector<rfsitl::cf32>> samples;
  for (std::size_t k = 0; k < v.reports.size(); ++k) {
    FUZZ_CHECK(v.reports[k].node < kNodes, "node %u", v.reports[k].node);
    FUZZ_CHECK(v.reports[k].tx_samples <= kTick, "samples %u", v.reports[k].tx_samples);
    const std::size_t n = v.reports[k].tx_samples;
    FUZZ_CHECK(v.sample_offsets[k] + n * sizeof(rfsitl::cf32) <= bytes.size(), "samples past end");
    samples.emplace_back(n);
    if (n > 0) {
      std::memcpy(samples.back().data(), bytes.data() + v.sample_offsets[k],
                  n * sizeof(rfsitl::cf32));
    }
  }
  for (const auto& s : samples) m.samples.emplace_back(s);
  std::vector<std::uint8_t> again;
  write_tx_message(m, again);
  const TxMessageView w = read_tx_message(again, 1, kNodes, kTick);
  FUZZ_CHECK(w.reports.size() == v.reports.size() && w.updates.size() == v.updates.size(),
             "round trip changed the counts");
  for (std::size_t k = 0; k < w.reports.size(); ++k) {
    FUZZ_CHECK(w.reports[k].node == v.reports[k].node &&
                   w.reports[k].serial == v.reports[k].serial &&
                   w.reports[k].tx_samples == v.reports[k].tx_samples,
               "report %zu changed", k);
  }
}

void ops(std::span<const std::uint8_t> bytes) {
  std::vector<LedgerOp> out;
  try {
    read_ledger_ops(bytes, 1, kNodes, out);
  } catch (const std::runtime_error& e) {
    check_error(e);
    return;
  }
  std::vector<std::uint8_t> again;
  write_ledger_ops(out, again);
  std::vector<LedgerOp> back;
  read_ledger_ops(again, 1, kNodes, back);
  FUZZ_CHECK(back.size() == out.size(), "round trip changed the count");
  for (std::size_t k = 0; k < out.size(); ++k) {
    FUZZ_CHECK(out[k].node < kNodes && back[k].node == out[k].node && back[k].id == out[k].id &&
                   back[k].kind == out[k].kind,
               "op %zu changed", k);
  }
}

void counters(std::span<const std::uint8_t> bytes) {
  RankFigures f;
  std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> out;
  std::vector<ObserverShare> shares;
  try {
    read_counters(bytes, 1, kNodes, f, out, shares);
  } catch (const std::runtime_error& e) {
    check_error(e);
    return;
  }
  for (const auto& [node, c] : out) FUZZ_CHECK(node < kNodes, "node %u", node);
  std::size_t shared = 0;
  for (const auto& s : shares) shared += s.key.size() + s.bytes.size();
  FUZZ_CHECK(shared <= bytes.size(), "%zu bytes of shares from %zu", shared, bytes.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  switch (data[0] % 3) {
    case 0:
      tx(bytes);
      break;
    case 1:
      ops(bytes);
      break;
    default:
      counters(bytes);
      break;
  }
  return 0;
}
