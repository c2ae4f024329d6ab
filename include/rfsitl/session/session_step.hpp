#pragma once
/// The named steps a Session (session.hpp) assembles a run in, in the only
/// order they can run, and the two ways a step can fail.
#include <stdexcept>
#include <string>

namespace rfsitl::session {

/// In order: each step needs what the ones before it built.
enum class Step {
  kScenario,   ///< read the scenario and apply the settings given beside it
  kPlacement,  ///< a distributed run's ranks: which nodes are this process's
  kPorts,      ///< the net ports and live position sources (made, not yet open)
  kIp,         ///< the nodes' network namespaces and TAP interfaces
  kExternal,   ///< the hub of transceivers in other processes
  kEngine,     ///< the lock-step engine and its transceivers
  kObservers,  ///< traces, recordings, the dashboard
  kServe,      ///< open every face, run the engine to its end
  kFinish,     ///< close every face, gather the summary
  kDone,       ///< nothing left to run
};

/// "scenario", "placement", ... as errors name the steps.
const char* step_name(Step step);

/// A step could not be done: the scenario is invalid, a port is taken, a rank
/// failed (in a distributed run every rank gets the same error, prefixed
/// "rank R: " by the one that failed). what() is for the user, without a
/// program name. The Session refuses every further step.
class SessionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A step was called out of order, twice, or after a failed one: a mistake
/// of the caller's, not of the run's. what() names the step and the one due.
class SessionStepError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

}  // namespace rfsitl::session
