#include "rfsitl/session/run_ranks.hpp"

#include <cstdio>
#include <cstring>
#include <span>

#include "rfsitl/cluster/mpi_launch.hpp"
#include "rfsitl/cluster/node_assignment.hpp"

namespace rfsitl::session {
namespace {

/// FNV-1a, 64 bits: equal texts give equal values on every host.
std::uint64_t fingerprint_hash(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::span<const std::uint8_t> bytes_of(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

std::string text_of(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

std::vector<bool> RunRanks::here_mask(std::size_t nodes) const {
  std::vector<bool> mask(nodes);
  for (std::size_t i = 0; i < nodes; ++i) mask[i] = here(i);
  return mask;
}

std::optional<std::string> start_ranks(const scenario::Scenario& s, const std::string& fingerprint,
                                       RunRanks& ranks) {
  if (!cluster::launched_by_mpirun()) return std::nullopt;
  try {
    ranks.peers = cluster::start_mpi();
  } catch (const std::exception& e) {
    return e.what();
  }
  ranks.rank = ranks.peers->rank();
  ranks.ranks_on_host = cluster::ranks_on_this_host();
  ranks.size = ranks.peers->size();
  // Every rank checks every rank's fingerprint against rank 0's, so that all
  // reach the same verdict and none is left waiting in an exchange.
  const std::uint64_t mine = fingerprint_hash(fingerprint);
  std::uint8_t bytes[sizeof mine];
  std::memcpy(bytes, &mine, sizeof mine);
  cluster::Gathered all;
  ranks.peers->all_gather(bytes, all);
  for (std::size_t r = 1; r < all.ranks(); ++r) {
    if (all.of(r).size() != sizeof mine ||
        std::memcmp(all.of(r).data(), all.of(0).data(), sizeof mine) != 0) {
      return "rank " + std::to_string(r) +
             " was given another scenario or other flags than rank 0 (every rank must run the "
             "same command on the same scenario file)";
    }
  }
  ranks.owner = cluster::assign_nodes(s, ranks.size);
  ranks.local_rank = cluster::local_rank();
  ranks.hosts = gather_texts(ranks, cluster::host_name());
  return std::nullopt;
}

std::optional<std::string> agree(RunRanks& ranks, const std::string& error) {
  if (!ranks.distributed()) {
    return error.empty() ? std::nullopt : std::optional<std::string>(error);
  }
  cluster::Gathered all;
  ranks.peers->all_gather(bytes_of(error), all);
  for (std::size_t r = 0; r < all.ranks(); ++r) {
    if (!all.of(r).empty()) return "rank " + std::to_string(r) + ": " + text_of(all.of(r));
  }
  return std::nullopt;
}

std::vector<std::string> gather_texts(RunRanks& ranks, const std::string& mine) {
  if (!ranks.distributed()) return {mine};
  cluster::Gathered all;
  ranks.peers->all_gather(bytes_of(mine), all);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < all.ranks(); ++r) out.push_back(text_of(all.of(r)));
  return out;
}

std::string rank_file_name(const std::string& path, std::size_t rank) {
  const std::string tag = ".rank" + std::to_string(rank);
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash) || dot == 0 ||
      (slash != std::string::npos && dot == slash + 1)) {
    return path + tag;
  }
  return path.substr(0, dot) + tag + path.substr(dot);
}

std::string describe_ranks(const scenario::Scenario& s, const RunRanks& ranks) {
  return "rfsitl: distributed run on " + std::to_string(ranks.size) + " ranks (this is rank " +
         std::to_string(ranks.rank) + " on " + cluster::host_name() + ")\n" +
         cluster::describe_assignment(s, ranks.owner, ranks.size, ranks.hosts);
}

std::string rank_summary(const engine::Engine& e, double tick_s) {
  std::string out;
  const auto ranks = e.ranks();
  for (std::size_t r = 0; r < ranks.size(); ++r) {
    const engine::RankStatus& st = ranks[r];
    const double ticks = st.wall_s > 0 && tick_s > 0 ? e.status().virtual_s / tick_s : 0.0;
    char line[256];
    std::snprintf(line, sizeof line,
                  "  rank %zu: worst lag %.2f ms, late ticks %llu, sent %.0f B per tick, %.1f %% "
                  "of its wall time in exchanges\n",
                  r, 1e3 * st.max_lag_s, static_cast<unsigned long long>(st.late_ticks),
                  ticks > 0 ? static_cast<double>(st.exchanged_bytes) / ticks : 0.0,
                  st.wall_s > 0 ? 100.0 * st.exchange_wall_s / st.wall_s : 0.0);
    out += line;
  }
  return out;
}

}  // namespace rfsitl::session
