#pragma once
/// What every registered component says about itself: its kind and name (as the
/// scenario selects it), a one-line doc, and its settings' declarations.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/config/setting.hpp"
#include "rfsitl/config/settings.hpp"

namespace rfsitl::config {

struct ComponentInfo {
  std::string kind;  ///< "phy", "mac", "channel stage", "position source"
  std::string name;  ///< what a scenario's `type:` says, e.g. "gmsk"
  std::string doc;   ///< one line
  std::vector<Setting> settings;
  /// Rules across settings (e.g. "adaptive needs a Gold code"), run after every
  /// value passed its own limits. Throws SettingError naming one key. May be empty.
  std::function<void(const Settings&)> check;

  /// The declaration of `name`, or nullptr.
  const Setting* find(std::string_view name) const;

  /// Every declared setting at its default.
  Settings defaults() const;

  /// Checks that `s` holds exactly the declared settings, each of its type and
  /// within its limits, then the cross-setting rules. Throws SettingError.
  void validate(const Settings& s) const;
};

}  // namespace rfsitl::config
