// PHY "external": another program (a GNU Radio flowgraph, a SoapySDR
// application) modulates and demodulates and serves the node's net port; rfsitl
// only exchanges its samples. It has no settings of its own here.
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {

PhyComponent external_program_component() {
  return {{"phy",
           "external",
           "another program's transceiver, exchanging samples with the emulator over its Unix "
           "socket",
           {},
           {}},
          TransceiverKind::kExternalProgram,
          {},
          [](const config::Settings&) { return std::string("external program"); },
          {},   // no PER curve: rfsitl does not know the program's receiver
          {}};  // nor its spectrum: flat over the node's channel
}

}  // namespace rfsitl::phy
