#pragma once
/// The scenario's channel as the engine uses it: the stages of channel.stages
/// built in order (or the paper's model from its short form), with the radio's
/// transmit power and antenna gains.
#include <memory>

#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// Precondition: `s` is validated (every stage registered, its settings checked).
/// Throws std::invalid_argument when a stage cannot be built.
std::shared_ptr<const channel::LinkBudget> make_link_budget(const Scenario& s);

/// Stage i of channel.stages, built: its data files (relative to
/// s.source_dir) read and checked. Throws std::invalid_argument naming the
/// file and its line when one is broken. (The loader builds each stage once
/// at load, so that a broken file is refused before anything starts.)
std::unique_ptr<channel::GainStage> make_stage(const Scenario& s, std::size_t i);

}  // namespace rfsitl::scenario
