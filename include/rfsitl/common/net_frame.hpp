#pragma once
/// A packet as an agent hands it to its net port: source, destination, payload.
#include <cstdint>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl {

struct NetFrame {
  NodeId src = 0;
  NodeId dst = 0;
  std::vector<std::uint8_t> payload;

  friend bool operator==(const NetFrame&, const NetFrame&) = default;
};

}  // namespace rfsitl
