#include "rfsitl/position/mavlink/message_catalog.hpp"

#include <algorithm>
#include <array>

namespace rfsitl::position::mavlink {
namespace {

constexpr MessageSpec kCatalog[] = {
#include "message_catalog_table.inc"
};

constexpr bool sorted_by_unique_id() {
  for (std::size_t i = 1; i < std::size(kCatalog); ++i) {
    if (kCatalog[i - 1].id >= kCatalog[i].id) return false;
  }
  return true;
}
static_assert(sorted_by_unique_id(), "find_message_spec binary-searches the table");

}  // namespace

const MessageSpec* find_message_spec(std::uint32_t id) noexcept {
  const auto* it = std::lower_bound(std::begin(kCatalog), std::end(kCatalog), id,
                                    [](const MessageSpec& s, std::uint32_t v) { return s.id < v; });
  return it != std::end(kCatalog) && it->id == id ? it : nullptr;
}

std::span<const MessageSpec> message_catalog() noexcept {
  return kCatalog;
}

}  // namespace rfsitl::position::mavlink
