#pragma once
// Test helper: a FrameEvent with the fields most tests set.
#include <cstdint>
#include <utility>
#include <vector>

#include "rfsitl/engine/frame_event.hpp"

namespace rfsitl::engine::testing {

inline FrameEvent frame_event(FrameEventKind kind, SampleTime t, NodeId src, NodeId dst,
                              NodeId node, std::uint32_t serial, std::uint32_t length_samples = 0,
                              std::vector<std::uint8_t> payload = {}) {
  FrameEvent e;
  e.kind = kind;
  e.time = t;
  e.src = src;
  e.dst = dst;
  e.node = node;
  e.serial = serial;
  e.length_samples = length_samples;
  e.phy = "gmsk";
  e.payload = std::move(payload);
  return e;
}

}  // namespace rfsitl::engine::testing
