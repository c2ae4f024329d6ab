#pragma once
/// A node's mobility model as the engine drives it, built from the scenario:
/// its settings, the scenario's seed and origin, the node's start, and files
/// resolved against the scenario's folder. The loader builds every model once
/// at load, so that a missing or broken trace is refused with the scenario's
/// file and line before anything starts; the engine builds them again to run.
#include <functional>
#include <memory>
#include <string>

#include "rfsitl/position/mobility/mobility_model.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// Node i's model. Preconditions: s.nodes[i].mobility has a value, validated.
/// `warn` is told each problem that does not stop the model (a trace's bad
/// lines); may be empty. Throws std::invalid_argument or std::runtime_error
/// whose message names the file by the path really opened.
std::unique_ptr<position::mobility::MobilityModel> make_mobility(
    const Scenario& s, std::size_t i, std::function<void(const std::string&)> warn);

}  // namespace rfsitl::scenario
