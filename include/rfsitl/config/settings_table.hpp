#pragma once
/// A component's settings as a Markdown table (`rfsitl describe` and the tables
/// in scenarios/README.md are both this text).
#include <string>

#include "rfsitl/config/component_info.hpp"

namespace rfsitl::config {

/// | setting | type | unit | default | allowed | meaning |, one row per setting;
/// then, for each list setting, a table of the fields its items may give
/// (| field | unit | default | allowed | meaning |). Every line ends in '\n'.
/// A component without settings gives "(no settings)\n".
std::string settings_table(const ComponentInfo& component);

}  // namespace rfsitl::config
