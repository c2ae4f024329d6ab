#pragma once
/// Builds an engine's transceivers as FakeTransceivers on one FakeAir, and
/// keeps a view of them so that a test can check what each was asked to do.
#include <cstddef>
#include <map>
#include <vector>

#include "fake_transceiver.hpp"
#include "rfsitl/engine/engine.hpp"

namespace rfsitl::testing {

/// Test thread only. The transceivers belong to the engine: radio() is valid
/// while the engine built by the latest factory() lives.
class FakeFleet {
 public:
  explicit FakeFleet(FakeConfig config = {}) : default_(config) {}

  /// Node `node`'s settings (the default unless set); set before factory().
  FakeConfig& config(std::size_t node);

  /// A factory for make_engine: every call makes a new medium, so each engine
  /// (each run) has its own air. The PHY choice of the scenario is ignored.
  engine::TransceiverFactory factory();

  /// Node `node`'s transceiver in the latest engine.
  FakeTransceiver& radio(std::size_t node) const { return *radios_.at(node); }
  std::size_t size() const { return radios_.size(); }

  /// Sum over the fleet of a FakeCalls field, e.g. total(&FakeCalls::receive).
  std::uint64_t total(std::uint64_t FakeCalls::*field) const;

 private:
  FakeConfig default_;
  std::map<std::size_t, FakeConfig> per_node_;
  std::vector<FakeTransceiver*> radios_;
};

}  // namespace rfsitl::testing
