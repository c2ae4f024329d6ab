#pragma once
/// `mpirun -n K rfsitl run ...`: what a session does differently as one rank
/// of a distributed run (README, "Distributed runs"): which nodes are its own,
/// and the collective verdicts and gathers its steps take together.
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/cluster/peers.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::session {

/// This process's part of the run: every node its own without mpirun.
struct RunRanks {
  std::unique_ptr<cluster::Peers> peers;  ///< nullptr: one process
  std::vector<std::size_t> owner;         ///< owner rank of each node (empty: one process)
  std::size_t rank = 0;
  std::size_t size = 1;

  bool distributed() const { return peers != nullptr; }
  bool here(std::size_t node) const { return owner.empty() || owner[node] == rank; }
  /// here() for every node, as LiveSources takes it.
  std::vector<bool> here_mask(std::size_t nodes) const;
  std::vector<std::string> hosts;  ///< the host of each rank (distributed runs)
  std::size_t ranks_on_host = 1;
  std::size_t local_rank = 0;  ///< among the ranks on this host
  /// Whether this process does the host-wide chores (one per host).
  bool first_on_host() const { return local_rank == 0; }
  engine::Distribution distribution() const { return {peers.get(), owner, ranks_on_host}; }
};

/// Under mpirun: starts MPI, checks that every rank was given the same
/// scenario and flags (`fingerprint`: the scenario file's bytes and the
/// options), and shares the nodes out. Every rank reaches the same verdict.
/// Returns the error to print and exit 2 with, or nullopt. Without mpirun it
/// does nothing.
std::optional<std::string> start_ranks(const scenario::Scenario& s, const std::string& fingerprint,
                                       RunRanks& ranks);

/// Collective in a distributed run: every rank gives its setup error ("" if
/// none) and every rank gets the same verdict, the first failing rank's error
/// prefixed "rank R: ", or nullopt. It is also a barrier: what every rank did
/// before it is done before any rank goes on. In one process: `error` or
/// nullopt.
std::optional<std::string> agree(RunRanks& ranks, const std::string& error);

/// Collective in a distributed run: every rank's `mine`, in rank order (in one
/// process: {mine}).
std::vector<std::string> gather_texts(RunRanks& ranks, const std::string& mine);

/// `path` with ".rankR" before its extension ("run.pcapng" -> "run.rank1.pcapng").
std::string rank_file_name(const std::string& path, std::size_t rank);

/// The lines that say how the run is shared: one per rank with its nodes and
/// its host, rank 0's banner.
std::string describe_ranks(const scenario::Scenario& s, const RunRanks& ranks);

/// After the run, on rank 0: one line per rank (worst lag, bytes sent per
/// tick, time in the exchanges).
std::string rank_summary(const engine::Engine& e, double tick_s);

}  // namespace rfsitl::session
