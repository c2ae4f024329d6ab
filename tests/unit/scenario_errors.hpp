#pragma once
// The message of the ScenarioError that parsing a YAML text throws; a test
// failure (and "") when the text is accepted.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::scenario {

inline std::string parse_error_of(const std::string& yaml) {
  try {
    parse_scenario(yaml, "t.yaml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << yaml;
  return {};
}

}  // namespace rfsitl::scenario
