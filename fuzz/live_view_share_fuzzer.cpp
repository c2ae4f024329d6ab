/// Distributed runs: decode_share on arbitrary bytes (what another rank's live
/// view sent rank 0's dashboard).
///
/// Input: [1 byte: node count][share bytes...].
/// Checks:
///  - the only exception is std::invalid_argument, its message starting with
///    "live view share: ";
///  - an accepted share names only nodes and link cells of the run, spectra of
///    LiveView::kSpectrumBins bins and at most kMaxConstellationPoints points;
///  - encoding it and reading that back gives the same share.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

#include "fuzz_check.hpp"
#include "rfsitl/monitor/live_view_share.hpp"

using rfsitl::monitor::LiveView;
using rfsitl::monitor::LiveViewShare;

namespace {

void check_valid(const LiveViewShare& s, std::size_t nodes) {
  for (const auto w : s.watched) FUZZ_CHECK(w < nodes, "watched %u of %zu", w, nodes);
  for (const auto& c : s.links) FUZZ_CHECK(c.cell < nodes * nodes, "cell %u", c.cell);
  for (const auto& sp : s.spectra) {
    FUZZ_CHECK(sp.node < nodes && sp.db.size() == LiveView::kSpectrumBins, "spectrum %u: %zu",
               sp.node, sp.db.size());
  }
  for (const auto& [node, c] : s.constellations) {
    FUZZ_CHECK(node < nodes && c.points.size() <= LiveView::kMaxConstellationPoints,
               "constellation %u: %zu points", node, c.points.size());
  }
}

bool same(const LiveViewShare& a, const LiveViewShare& b) {
  if (a.watched != b.watched || a.links.size() != b.links.size() ||
      a.spectra.size() != b.spectra.size() || a.constellations.size() != b.constellations.size())
    return false;
  for (std::size_t k = 0; k < a.links.size(); ++k) {
    if (a.links[k].cell != b.links[k].cell || a.links[k].received != b.links[k].received ||
        a.links[k].lost != b.links[k].lost)
      return false;
  }
  for (std::size_t k = 0; k < a.spectra.size(); ++k) {
    // Bitwise: a NaN must survive as it came.
    if (a.spectra[k].node != b.spectra[k].node ||
        std::memcmp(a.spectra[k].db.data(), b.spectra[k].db.data(),
                    a.spectra[k].db.size() * sizeof(float)) != 0)
      return false;
  }
  for (std::size_t k = 0; k < a.constellations.size(); ++k) {
    const auto& [na, ca] = a.constellations[k];
    const auto& [nb, cb] = b.constellations[k];
    if (na != nb || ca.time != cb.time || ca.src != cb.src || ca.dst != cb.dst ||
        ca.serial != cb.serial || ca.payload_valid != cb.payload_valid ||
        ca.points.size() != cb.points.size() ||
        (!ca.points.empty() &&  // memcmp of no points would take null pointers
         std::memcmp(ca.points.data(), cb.points.data(), ca.points.size() * sizeof(ca.points[0]))))
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t nodes = data[0];
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  LiveViewShare s;
  try {
    s = rfsitl::monitor::decode_share(bytes, nodes);
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(std::string(e.what()).rfind("live view share: ", 0) == 0, "%s", e.what());
    return 0;
  }
  check_valid(s, nodes);
  FUZZ_CHECK(same(s, rfsitl::monitor::decode_share(rfsitl::monitor::encode_share(s), nodes)),
             "encode and decode changed the share");
  return 0;
}
