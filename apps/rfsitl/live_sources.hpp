#pragma once
/// The run's live position sources (position/source/position_source.hpp): one
/// source object per registered type that some node uses, each feeding its
/// nodes into the engine.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::app {

class LiveSources {
 public:
  /// Builds the sources of a validated scenario. Throws std::invalid_argument
  /// naming the node whose settings cannot work (e.g. two nodes on one port).
  explicit LiveSources(const scenario::Scenario& s);
  ~LiveSources() { stop(); }
  LiveSources(const LiveSources&) = delete;
  LiveSources& operator=(const LiveSources&) = delete;

  bool empty() const { return sources_.empty(); }

  /// Starts every source reporting into `sink`. Throws std::runtime_error
  /// naming the node and endpoint that cannot be opened.
  void start(position::PositionSink& sink);
  /// Stops every source (idempotent); the sink hears nothing afterwards.
  void stop();

  /// Node `index`'s source status (nullopt: no live source). Thread-safe.
  std::optional<position::SourceStatus> status(std::size_t index) const;
  /// status() as the monitor takes it; valid while this object lives.
  position::SourceStatusFn status_fn() const {
    return [this](std::size_t index) { return status(index); };
  }

 private:
  std::vector<std::string> type_of_;  // per node: its live source's type, "" for none
  std::map<std::string, std::unique_ptr<position::PositionSource>> sources_;
};

/// Makes every node follow a MAVLink vehicle at `endpoint` (the --mavlink
/// flag): the scenario's position source becomes mavlink with that endpoint
/// (its other mavlink settings kept), and nodes' own sources give way to it;
/// nodes with a mobility model keep it. Throws scenario::ScenarioError naming
/// --mavlink for a bad endpoint.
void follow_mavlink(scenario::Scenario& s, const std::string& endpoint);

}  // namespace rfsitl::app
