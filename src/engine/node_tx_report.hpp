#pragma once
// A node's TX phase as a distributed run's ranks tell each other of it
// (tick_exchange.hpp's TxReport): what the owner reports, and the node as
// the other ranks then hold it. Internal to the engine module.
#include "engine_node.hpp"
#include "tick_exchange.hpp"

namespace rfsitl::engine {

/// Whether the owner has anything to report of `node` this tick: it is on the
/// air, its MAC reached a verdict, or it started a frame.
bool has_tx_report(const Node& node);

/// The owner's report of `node` after its TX phase.
TxReport tx_report_of(const Node& node);

/// Another rank's `node` as its owner's TX phase left it, from the owner's
/// report; the node's first t.tx_samples samples of `tx` must already hold
/// the owner's (RankLink::copy_samples), the rest become zeros.
void take_tx_report(Node& node, const TxReport& t);

}  // namespace rfsitl::engine
