#pragma once
/// Which rank of a distributed run owns each node: the owner runs the node's
/// agent ports, position source, MAC and transceiver; every rank keeps the
/// whole channel.
#include <cstddef>
#include <string>
#include <vector>

#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::cluster {

/// The expected cost of node `index` per emulated second, relative to a GMSK
/// node: its transceiver's (the README's receiver-throughput table) plus a
/// share of the channel that every node brings.
double expected_cost(const scenario::Scenario& s, std::size_t index);

/// Owner rank of every node, by index: the nodes, dearest first, each to the
/// rank with the least cost so far (lowest rank on a tie). Deterministic: every
/// rank computes the same from the same scenario. Precondition: ranks >= 1.
std::vector<std::size_t> assign_nodes(const scenario::Scenario& s, std::size_t ranks);

/// One line per rank for the banner: "rank 1: node(s) 2 4 6 (cost 3.0) on HOST"
/// (" on HOST" when `hosts`, by rank, names it).
std::string describe_assignment(const scenario::Scenario& s, const std::vector<std::size_t>& owner,
                                std::size_t ranks, const std::vector<std::string>& hosts = {});

}  // namespace rfsitl::cluster
