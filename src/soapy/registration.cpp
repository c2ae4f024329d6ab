/// `driver=rfsitl` in SoapySDR's registry: find lists the nodes running
/// emulators wait for (asking each emulator socket with a discovery message,
/// which claims nothing); make claims one.
///
/// Device arguments:
///   socket=PATH     the emulator's external socket (default: every
///                   /tmp/rfsitl-*.sock that answers)
///   node=ID         the node to be (default: the only unclaimed one)
///   takeover=1      claim a node another program holds (the emulator then
///                   drops that program: how a crashed application rejoins);
///                   without it the claim is exclusive: the emulator refuses
///                   it while another program holds the node, even one that
///                   claimed it at the same instant
///   buffer_ms=MS    RX buffer in virtual milliseconds (default 1000); an
///                   application that falls further behind gets
///                   SOAPY_SDR_OVERFLOW
#include <glob.h>

#include <SoapySDR/Logger.hpp>
#include <SoapySDR/Registry.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl_device.hpp"

namespace rfsitl::soapy {
namespace {

/// A discovery round trip is local (a Unix socket): an emulator that takes
/// longer than this is not answering.
constexpr int kDiscoveryTimeoutMs = 1000;

struct Found {
  std::string socket;
  external::DiscoveredNode node;
};

std::string arg(const SoapySDR::Kwargs& args, const std::string& key) {
  const auto it = args.find(key);
  return it == args.end() ? std::string() : it->second;
}

std::vector<std::string> default_sockets() {
  std::vector<std::string> paths;
  glob_t g{};
  if (::glob("/tmp/rfsitl-*.sock", 0, nullptr, &g) == 0) {
    for (std::size_t i = 0; i < g.gl_pathc; ++i) paths.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  return paths;
}

/// "node=" as a node id; throws std::runtime_error on anything else.
int node_arg(const SoapySDR::Kwargs& args) {
  const std::string text = arg(args, "node");
  if (text.empty()) return 0;
  std::size_t used = 0;
  int id = 0;
  try {
    id = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || id < kMinNodeId || id > kMaxNodeId) {
    throw std::runtime_error("rfsitl: node=" + text + " is not a node id (1..254)");
  }
  return id;
}

/// The samples-role nodes of the emulator(s) the arguments name. With an
/// explicit socket= a failing emulator is an error; while scanning /tmp, a
/// socket that does not answer (a stale file) is skipped.
std::vector<Found> discover_nodes(const SoapySDR::Kwargs& args) {
  const std::string socket = arg(args, "socket");
  const int node = node_arg(args);
  std::vector<Found> found;
  for (const auto& path : socket.empty() ? default_sockets() : std::vector{socket}) {
    std::vector<external::DiscoveredNode> nodes;
    try {
      nodes = external::discover(path, kDiscoveryTimeoutMs, "soapy find");
    } catch (const std::exception& e) {
      if (!socket.empty()) throw;
      SoapySDR::logf(SOAPY_SDR_DEBUG, "rfsitl: skipping %s: %s", path.c_str(), e.what());
      continue;
    }
    for (auto& n : nodes) {
      // Transceiver-role nodes are `rfsitl node` children, not for SDR programs.
      if (n.role != "samples" || (node != 0 && n.node_id != node)) continue;
      // Claimed means: by another program. The answer for a node this process
      // holds stays what it was before the claim, so that SoapySDR's device
      // table hands the same device to every make of the process.
      if (RfsitlDevice::held_here(path, n.node_id)) n.claimed = false;
      found.push_back({path, n});
    }
  }
  return found;
}

SoapySDR::KwargsList find_rfsitl(const SoapySDR::Kwargs& args) {
  if (const std::string d = arg(args, "driver"); !d.empty() && d != "rfsitl") return {};
  std::vector<Found> found;
  try {
    found = discover_nodes(args);
  } catch (const std::exception& e) {
    SoapySDR::logf(SOAPY_SDR_ERROR, "%s", e.what());
    return {};
  }
  SoapySDR::KwargsList list;
  for (const auto& f : found) {
    list.push_back(
        {{"driver", "rfsitl"},
         {"socket", f.socket},
         {"node", std::to_string(f.node.node_id)},
         {"label", RfsitlDevice::label_of(f.node) + (f.node.claimed ? " (claimed)" : "")},
         {"serial", f.socket + "#" + std::to_string(f.node.node_id)},
         {"claimed", f.node.claimed ? "1" : "0"}});
  }
  return list;
}

bool takeover_arg(const SoapySDR::Kwargs& args) {
  const std::string t = arg(args, "takeover");
  if (t.empty() || t == "0" || t == "false" || t == "no") return false;
  if (t == "1" || t == "true" || t == "yes") return true;
  throw std::runtime_error("rfsitl: takeover=" + t + " (expected 1 or 0)");
}

double buffer_s_arg(const SoapySDR::Kwargs& args) {
  const std::string text = arg(args, "buffer_ms");
  if (text.empty()) return 1.0;
  std::size_t used = 0;
  double ms = 0.0;
  try {
    ms = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(ms >= 1.0 && ms <= 60000.0)) {
    throw std::runtime_error("rfsitl: buffer_ms=" + text + " (expected 1 .. 60000)");
  }
  return ms / 1e3;
}

SoapySDR::Device* make_rfsitl(const SoapySDR::Kwargs& args) {
  const bool takeover = takeover_arg(args);
  const double buffer_s = buffer_s_arg(args);
  std::vector<Found> found = discover_nodes(args);
  if (arg(args, "node").empty()) {
    std::erase_if(found, [](const Found& f) { return f.node.claimed; });
  }
  if (found.size() != 1) {
    const std::string where = arg(args, "socket").empty()
                                  ? " (searched /tmp/rfsitl-*.sock; pass socket=PATH)"
                                  : " at " + arg(args, "socket");
    const std::string node = arg(args, "node");
    throw std::runtime_error(
        std::string("rfsitl: ") +
        (!found.empty() ? std::to_string(found.size()) + " nodes match; choose one with node=ID"
         : node.empty() ? "no emulator node waits for an SDR program"
                        : "node " + node + " is not a node with phy: {type: external}") +
        where);
  }
  const Found& f = found.front();
  if (RfsitlDevice::held_here(f.socket, f.node.node_id)) {
    // SoapySDR shares the device it made; reaching here means other arguments.
    throw std::runtime_error("rfsitl: node " + std::to_string(f.node.node_id) + " of " + f.socket +
                             " is held by this process already (make it with the same arguments "
                             "to share the device)");
  }
  if (f.node.claimed && !takeover) {
    throw std::runtime_error("rfsitl: node " + std::to_string(f.node.node_id) + " of " + f.socket +
                             " is already claimed by another program; pass takeover=1 to take "
                             "it over");
  }
  NodeStreamer::Settings s;
  s.socket_path = f.socket;
  s.node_id = f.node.node_id;
  s.program = "soapy";
  s.rx_buffer_s = buffer_s;
  s.takeover = takeover;
  try {
    return new RfsitlDevice(f.socket, f.node, s);
  } catch (const external::ConnectRejected& e) {
    // Discovery said the node was free, and another program claimed it since
    // (the emulator admits one exclusive claim at a time), or the emulator
    // refused for another reason: say which.
    throw std::runtime_error("rfsitl: node " + std::to_string(f.node.node_id) + " of " + f.socket +
                             ": the emulator refused the claim: " + e.reason() +
                             (takeover ? "" : " (takeover=1 takes a claimed node over)"));
  }
}

[[maybe_unused]] const SoapySDR::Registry registration("rfsitl", &find_rfsitl, &make_rfsitl,
                                                       SOAPY_SDR_ABI_VERSION);

}  // namespace
}  // namespace rfsitl::soapy
