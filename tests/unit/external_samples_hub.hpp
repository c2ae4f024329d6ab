#pragma once
/// A hub with one samples-role node and the emulator's proxy for it
/// (make_sample_port_transceiver), as the engine would hold them: for the
/// tests that play the program's side against it.
#include <atomic>
#include <cstdint>
#include <memory>

#include "external_test_support.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/external_transceivers.hpp"

namespace rfsitl::external::testing {

struct SamplesHub {
  SamplesHub(NodeId node, std::uint32_t tick_samples) {
    HubSettings hs;
    hs.socket_path = path.str();
    hs.reply_timeout_ms = 3000;
    hs.tick_samples = tick_samples;
    hub = make_external_hub(hs, {ExternalNodeSpec{0, node, Role::kSamples, ""}});
    link = hub->link(0);
    port = make_sample_port_transceiver(link, tick_samples, overflows);
  }

  SocketPath path;
  std::unique_ptr<ExternalHub> hub;
  std::shared_ptr<NodeLink> link;
  std::atomic<std::uint64_t> overflows{0};  // the node's counter; before port, which adds to it
  std::unique_ptr<phy::Transceiver> port;
};

}  // namespace rfsitl::external::testing
