#pragma once
/// What a rank's live view tells the other ranks' in a distributed run
/// (EngineObserver::share): which nodes its viewers watch, the link outcomes
/// it counted, the spectra it computed for nodes watched on another rank and
/// the constellations of its receivers' latest decodes. Rank 0's dashboard
/// thus shows every rank's nodes. Pure coding; LiveView does the rest.
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "rfsitl/monitor/live_view.hpp"

namespace rfsitl::monitor {

struct LiveViewShare {
  std::vector<std::uint32_t> watched;  ///< node indices the rank's viewers watch
  struct LinkCell {
    std::uint32_t cell = 0;  ///< tx * N + rx
    std::uint32_t received = 0;
    std::uint32_t lost = 0;
  };
  std::vector<LinkCell> links;  ///< the cells the rank counted (non-zero only)
  struct Spectrum {
    std::uint32_t node = 0;
    std::vector<float> db;  ///< LiveView::kSpectrumBins, DC in the middle
  };
  std::vector<Spectrum> spectra;
  std::vector<std::pair<std::uint32_t, Constellation>> constellations;  ///< by node index
};

std::vector<std::uint8_t> encode_share(const LiveViewShare& share);

/// Reads a share of a run with `nodes` nodes. Throws std::invalid_argument
/// saying what is wrong: short or trailing bytes, another format version, a
/// node or cell index out of range, a spectrum of other than
/// LiveView::kSpectrumBins bins, more than LiveView::kMaxConstellationPoints
/// points.
LiveViewShare decode_share(std::span<const std::uint8_t> bytes, std::size_t nodes);

}  // namespace rfsitl::monitor
