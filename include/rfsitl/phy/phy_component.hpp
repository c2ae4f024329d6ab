#pragma once
/// What a PHY registers: its self-description (name, doc, declared settings),
/// what kind of transceiver it is, and how to build one. A PHY is one folder
/// under src/phy/ that defines `PhyComponent <folder>_component()`, plus one
/// line in src/registry/phy_registry.cpp.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "rfsitl/common/spectral_mask.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/phy/per_curve.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

enum class TransceiverKind {
  kBuiltIn,          ///< rfsitl builds it (in the emulator or in an `rfsitl node` child)
  kExternalProgram,  ///< another program exchanges samples over the external protocol
};

/// Every built-in PHY declares this setting: the largest net-frame payload one frame
/// carries (bytes). The scenario checks traffic sizes against it.
inline constexpr std::string_view kMaxPayloadSetting = "max_payload_bytes";

struct PhyComponent {
  config::ComponentInfo info;  ///< kind "phy"
  TransceiverKind kind = TransceiverKind::kBuiltIn;
  /// Builds a transceiver from settings that passed info.validate(); may throw
  /// std::invalid_argument. Empty for kExternalProgram.
  std::function<std::unique_ptr<Transceiver>(const config::Settings&)> make;
  /// A few words for the banner ("ofdm 24 Mbit/s"); empty: the type name.
  std::function<std::string(const config::Settings&)> label;
  /// The declared PER curve (per_curve.hpp) of a transceiver with these
  /// settings (validated); empty when the PHY declares none (another
  /// program's transceiver).
  std::function<PerCurve(const config::Settings&)> per_curve;
  /// The transmitter's spectral mask with these settings (validated), its
  /// offsets in units of the sample rate: what leaks into a neighbouring
  /// channel (channel/radio_tuning.hpp). Empty: flat over the node's channel
  /// bandwidth and nothing beyond it.
  std::function<SpectralMask(const config::Settings&)> spectral_mask;
};

}  // namespace rfsitl::phy
