#pragma once
/// Whether a scenario will hold real time on this machine, found out before
/// it starts: its first seconds run in virtual time (the same engine, the same
/// worker tuning, no ports), and the speed and CPU time they took say how much
/// of the machine real time needs. A scenario without traffic of its own gets
/// the capacity benchmark's load instead (every node pings a random other
/// node once a second, the answer 5 ms later), as a stand-in for its agents.
/// Nodes whose transceiver is another process run the scenario's built-in PHY
/// (gmsk when that is external too): their processes' cost is not measured.
#include <cstddef>
#include <cstdint>
#include <string>

#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::engine {

struct PreflightReport {
  double virtual_s = 0.0;    ///< emulated
  double wall_s = 0.0;       ///< it took
  double cpu_s = 0.0;        ///< CPU time the process used meanwhile (every thread)
  std::size_t cores = 1;     ///< this machine's
  bool own_traffic = false;  ///< the scenario's traffic, not the stand-in load
  std::uint64_t frames = 0;  ///< handed in during it (the load really ran)

  /// Virtual seconds per wall second: real time holds above 1.
  double speed() const { return wall_s > 0.0 ? virtual_s / wall_s : 0.0; }
  /// Cores real time keeps busy (CPU seconds per virtual second).
  double cores_needed() const { return virtual_s > 0.0 ? cpu_s / virtual_s : 0.0; }
  /// The share of each tick's time left over in real time (1 - 1 / speed);
  /// negative when it falls behind.
  double margin() const { return speed() > 0.0 ? 1.0 - 1.0 / speed() : -1.0; }
  /// One line for a person: "real time holds: needs 0.42 cores of 2 (speed
  /// 4.8x, 79 % margin) under ...", or that it will fall behind and by how much.
  std::string summary() const;
};

/// The margin under which real time is called at risk (a busier moment, a
/// neighbour on the machine) though it held in the preflight.
inline constexpr double kPreflightMinMargin = 0.2;

/// Runs `s`'s first `seconds` (at most its duration, when it has one) in
/// virtual time, or less when that takes longer than `max_wall_s` (a scenario
/// far beyond the machine: what ran by then is measured). Precondition: `s`
/// is validated. Throws what building the engine throws
/// (std::invalid_argument naming the problem).
PreflightReport preflight(const scenario::Scenario& s, double seconds = 2.0,
                          double max_wall_s = 3.0);

}  // namespace rfsitl::engine
