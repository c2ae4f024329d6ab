#pragma once
/// I/Q recording in SigMF (1.0): for each selected node, the samples its
/// receiver got during the selected window of virtual time as
/// DIR/node<ID>.sigmf-data (cf32_le, the receiver's front-end scale: noise at
/// unit power) and DIR/node<ID>.sigmf-meta (JSON) with one annotation per frame
/// on the air during the recording: core:sample_start / core:sample_count
/// (relative to the recording's first sample), core:label, and rfsitl:src,
/// rfsitl:dst, rfsitl:serial, rfsitl:outcome ("received" here, or the frame's
/// final "delivered"/"lost"), rfsitl:reason, rfsitl:snr_db. Bounded: recording
/// stops at max_bytes of data per node (the meta then says rfsitl:truncated).
/// A write that fails (a full disk) stops that node's recording, not the run:
/// logged with the file and the reason, in the meta as rfsitl:error, and
/// reported by summary().
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor {

struct SigmfSettings {
  std::string directory;                   ///< created if missing
  std::vector<NodeId> nodes;               ///< node ids to record (must exist)
  double start_s = 0.0;                    ///< virtual time the window opens
  double duration_s = 1.0;                 ///< window length (virtual seconds)
  std::uint64_t max_bytes = 200ULL << 20;  ///< per node
};

class SigmfRecorder : public engine::EngineObserver {
 public:
  /// Writes every .sigmf-meta (also done on destruction). Safe to call once
  /// the engine has stopped.
  virtual void finish() = 0;
  /// Samples written for node id `id` so far.
  virtual std::uint64_t samples_written(NodeId id) const = 0;
  /// For the run's summary: {"directory", "nodes": [{"id", "data",
  /// "samples_written", "truncated" (max_bytes reached), "stopped" (true once
  /// a write of its data failed), "error" (the reason, or null),
  /// "meta_written"}]}. Call after finish() for the final "meta_written".
  virtual nlohmann::json summary() const = 0;
};

/// Throws std::runtime_error naming the directory or file that cannot be
/// written, or the node id the scenario does not have.
std::unique_ptr<SigmfRecorder> make_sigmf_recorder(const SigmfSettings& settings,
                                                   const scenario::Scenario& scenario);

}  // namespace rfsitl::monitor
