#pragma once
/// The "scenario" step's work, apart from the Session's bookkeeping: the
/// scenario a SessionOptions describes, and what every rank of a distributed
/// run must have been given alike.
#include <string>

#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/session_options.hpp"

namespace rfsitl::session {

/// The file (or the ready-made scenario, or the default formation) with the
/// overrides applied in order, then the sources followed and the transceivers
/// placed, validated. Throws scenario::ScenarioError; an override's error
/// names its origin (the flag).
scenario::Scenario assemble_scenario(const SessionOptions& o);

/// The scenario file's bytes and every option that shapes the scenario, as
/// one text: equal on every rank that was given the same command. A
/// ready-made scenario counts by its name and size only.
std::string run_fingerprint(const SessionOptions& o);

}  // namespace rfsitl::session
