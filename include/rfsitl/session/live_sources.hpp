#pragma once
/// The run's live position sources (position/source/position_source.hpp): one
/// source object per registered type that some node uses, each feeding its
/// nodes into the engine. The location port listens for every node: it is the
/// default source, and an override for nodes that follow another.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::session {

class LiveSources {
 public:
  /// Builds the sources of a validated scenario, for the nodes `here` (all when
  /// empty; in a distributed run, the rank's own). Throws std::invalid_argument
  /// naming the node whose settings cannot work (e.g. two nodes on one port).
  LiveSources(const scenario::Scenario& s, const position::SourceContext& context,
              std::vector<bool> here = {});
  ~LiveSources() { stop(); }
  LiveSources(const LiveSources&) = delete;
  LiveSources& operator=(const LiveSources&) = delete;

  /// Starts every source reporting into `sink`. Throws std::runtime_error
  /// (io::PortError for a port in use) naming the node and endpoint that cannot
  /// be opened; the sources started before it are stopped again.
  void start(position::PositionSink& sink);
  /// Stops every source (idempotent); the sink hears nothing afterwards.
  void stop();

  /// Node `index`'s source status: its live source, or "mobility" (with the
  /// location port's overrides); nullopt for a node served elsewhere. Thread-safe.
  std::optional<position::SourceStatus> status(std::size_t index) const;
  /// Where node `index`'s location port listens ("127.0.0.1:15776"), or
  /// "another rank's".
  std::string location_port(std::size_t index) const;
  /// status() as the monitor takes it; valid while this object lives.
  position::SourceStatusFn status_fn() const {
    return [this](std::size_t index) { return status(index); };
  }

 private:
  std::vector<std::string> type_of_;  // per node: its source's type, or "mobility"
  std::vector<bool> here_;            // per node: served by this process
  std::map<std::string, std::unique_ptr<position::PositionSource>> sources_;
};

/// Makes every node follow `source` with its flag's setting at `value` (e.g.
/// --mavlink ENDPOINT): the scenario's position source becomes `source` with
/// that setting (its other settings kept), and nodes' own sources give way to it;
/// nodes with a mobility model keep it. Throws scenario::ScenarioError naming
/// the flag for a bad value, or for a wall-clock source in virtual time.
void follow_source(scenario::Scenario& s, const position::PositionSourceComponent& source,
                   const std::string& value);

}  // namespace rfsitl::session
