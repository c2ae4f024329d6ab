#include "fake_fleet.hpp"

#include <memory>

namespace rfsitl::testing {

FakeConfig& FakeFleet::config(std::size_t node) {
  return per_node_.try_emplace(node, default_).first->second;
}

engine::TransceiverFactory FakeFleet::factory() {
  radios_.clear();
  return [this, air = std::make_shared<FakeAir>()](std::size_t index,
                                                   const scenario::PhyChoice& /*phy*/,
                                                   engine::NodeCounters& /*counters*/) {
    const auto it = per_node_.find(index);
    auto radio =
        std::make_unique<FakeTransceiver>(it != per_node_.end() ? it->second : default_, air);
    if (radios_.size() <= index) radios_.resize(index + 1, nullptr);
    radios_[index] = radio.get();
    return std::unique_ptr<phy::Transceiver>(std::move(radio));
  };
}

std::uint64_t FakeFleet::total(std::uint64_t FakeCalls::*field) const {
  std::uint64_t sum = 0;
  for (const FakeTransceiver* r : radios_) sum += r->calls().*field;
  return sum;
}

}  // namespace rfsitl::testing
