#pragma once
/// Transceivers whose work happens in another process, as the engine sees
/// them: proxies that implement phy::Transceiver over a NodeLink.
#include <atomic>
#include <cstdint>
#include <memory>

#include "rfsitl/external/node_link.hpp"
#include "rfsitl/phy/transceiver.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {

/// Role "transceiver": a built-in PHY running in an `rfsitl node` process.
/// Every Transceiver call the engine makes is forwarded (two round trips per
/// tick at most, none while the node is idle), so a run gives the same results
/// as with the PHY in the emulator's process. Frame lengths and sensitivity
/// come from a local instance of the same PHY that never processes samples.
/// While the process is away the node is silent and its TX queue holds
/// (tx_busy() is true), so no frame is started into the void.
std::unique_ptr<phy::Transceiver> make_remote_transceiver(std::shared_ptr<NodeLink> link,
                                                          const scenario::PhyChoice& phy);

/// Role "samples": a program that owns the node's net port (a GNU Radio
/// flowgraph) and exchanges B samples per tick. Its receiver always runs (the
/// emulator cannot see inside it), blanked samples during its own
/// transmission are zeros, and its decodes never pass through the emulator.
/// The overflows its process reports with each kTx (tx_report.hpp) are added
/// to `overflows` (the node's NodeCounters::external_overflows), which must
/// outlive the transceiver; an extra that is no report drops the process.
std::unique_ptr<phy::Transceiver> make_sample_port_transceiver(
    std::shared_ptr<NodeLink> link, std::uint32_t tick_samples,
    std::atomic<std::uint64_t>& overflows);

/// What a rank of a distributed run holds for a "samples" node another rank
/// serves: the proxy's figures (no payload, sensitivity and latency 0), and
/// no samples in or out (the engine never runs another rank's transceiver).
std::unique_ptr<phy::Transceiver> make_sample_port_stand_in();

}  // namespace rfsitl::external
