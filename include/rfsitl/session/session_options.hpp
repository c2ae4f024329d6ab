#pragma once
/// What a Session (session.hpp) is asked to assemble: the scenario and the
/// settings given beside it, which faces to open, which observers to attach.
/// A plain struct: `rfsitl run` fills it from its flags, a benchmark or the
/// Python module from its own arguments; nothing here reads argv.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::session {

/// A scenario setting given beside the file, in the file's own words: it goes
/// through the file's reader and rules (scenario::apply_setting), so a flag and
/// the file accept the same values.
struct SettingOverride {
  std::string key;     ///< dotted scenario key, e.g. "time.mode", "engine.threads"
  std::string value;   ///< as the file would write it: "virtual", "2.5", "true"
  std::string origin;  ///< what an error names (the CLI: the flag, "--mode"); "": the key
};

/// Every node follows a live position source with its flag's setting at
/// `value` (--mavlink ENDPOINT; session/live_sources.hpp, follow_source()).
struct SourceOverride {
  const position::PositionSourceComponent* source = nullptr;  ///< registered; not owned
  std::string value;
};

/// A pcapng trace of every frame event (monitor/pcap_trace.hpp).
struct PcapOptions {
  std::string path;                             ///< "": no trace
  std::uint64_t max_file_bytes = 100ULL << 20;  ///< rotate beyond this
  unsigned files = 5;                           ///< files kept when rotating
};

/// A SigMF recording of received I/Q (monitor/sigmf_recorder.hpp).
struct SigmfOptions {
  std::string directory;                   ///< "": no recording
  std::vector<NodeId> nodes;               ///< nodes recorded; empty: all (of this rank)
  double start_s = 0.0;                    ///< virtual second the recording starts
  double duration_s = 10.0;                ///< virtual seconds recorded
  std::uint64_t max_bytes = 200ULL << 20;  ///< per node
};

/// The web dashboard (monitor/dashboard.hpp); in a distributed run rank 0's.
struct DashboardOptions {
  bool enabled = false;
  std::optional<std::uint16_t> port;  ///< nullopt: 15700, or any free port if taken; 0: any
  bool control = false;               ///< viewers may move nodes
  /// Checked by monitor::control_token_problem(). "": none needed on loopback;
  /// beyond loopback, with control on, one is drawn (Session::dashboard_token()).
  std::string control_token;
};

struct SessionOptions {
  // --- step "scenario": what the run emulates ---
  /// Ready-made (benchmarks, Python): used instead of the file or the default
  /// formation; the overrides below still apply, then it is validated.
  std::optional<scenario::Scenario> scenario;
  std::string scenario_path;              ///< scenario file (YAML); "": the default formation
  std::optional<std::size_t> nodes;       ///< the default formation's size (6); not with a file
  std::vector<SettingOverride> settings;  ///< applied in order, after the file
  std::vector<SourceOverride> follow;     ///< applied after the settings
  /// Where every built-in transceiver runs (--arch): kInline in the emulator,
  /// kChild one `rfsitl node` process each; nullopt: as the scenario says.
  std::optional<scenario::Process> transceivers;

  // --- step "ports": the agents' faces ---
  /// Net ports (one per node) and the live position sources with their
  /// location ports. False: no socket at all; decoded frames go to `frames`.
  bool ports = true;
  /// Without ports: where decoded frames go, called on the engine thread
  /// (engine::FrameSink's contract); nullptr: dropped (still counted as
  /// delivered). Not owned; must outlive the Session.
  engine::FrameSink* frames = nullptr;

  // --- step "observers" ---
  PcapOptions pcap;
  SigmfOptions sigmf;
  DashboardOptions dashboard;
};

}  // namespace rfsitl::session
