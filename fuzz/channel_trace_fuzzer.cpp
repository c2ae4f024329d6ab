/// Channel trace files: trace::parse_csv, parse_links_csv and parse_npy on
/// arbitrary bytes (each input goes through all three).
///
/// Checks:
///  - the only exception that leaves a parser is std::invalid_argument (their
///    contract), and its what() starts with "<source>:" as documented
///    ("fuzz.csv:LINE: reason", "fuzz.npy: byte N (field): reason");
///  - a trace a parser accepts holds distinct links between distinct nodes of
///    the scenario, each with samples in time order within the documented
///    limits; the stage built from it accepts it and gives finite gains no
///    larger than the limits allow, looping or not.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_check.hpp"
#include "rfsitl/channel/stages/trace.hpp"

namespace trace = rfsitl::channel::trace;
using rfsitl::NodeId;

namespace {

const std::vector<NodeId> kIds{1, 2, 3, 4, 5};
const std::vector<trace::LinkIds> kNpyLinks{{1, 2}, {2, 1}, {3, 5}};

bool known(NodeId id) {
  for (const NodeId k : kIds) {
    if (k == id) return true;
  }
  return false;
}

void check_links(const std::vector<trace::LinkIds>& links) {
  std::set<std::pair<NodeId, NodeId>> seen;
  for (const auto& l : links) {
    FUZZ_CHECK(known(l.tx) && known(l.rx), "link %u->%u names an unknown node", unsigned{l.tx},
               unsigned{l.rx});
    FUZZ_CHECK(l.tx != l.rx, "link %u->%u is a node to itself", unsigned{l.tx}, unsigned{l.rx});
    FUZZ_CHECK(seen.insert({l.tx, l.rx}).second, "link %u->%u twice", unsigned{l.tx},
               unsigned{l.rx});
  }
}

void check_trace(const trace::Trace& t) {
  std::vector<trace::LinkIds> links;
  double t_last = 0.0;
  for (const auto& l : t.links) {
    links.push_back(l.link);
    FUZZ_CHECK(!l.samples.empty(), "link without samples");
    for (std::size_t k = 0; k < l.samples.size(); ++k) {
      const trace::Sample& s = l.samples[k];
      FUZZ_CHECK(s.t_s >= 0.0 && s.t_s <= trace::kMaxTimeS, "t_s %g", s.t_s);
      FUZZ_CHECK(s.gain_db >= trace::kMinGainDb && s.gain_db <= trace::kMaxGainDb, "gain_db %g",
                 s.gain_db);
      FUZZ_CHECK(std::abs(s.phase_deg) <= trace::kMaxPhaseDeg, "phase_deg %g", s.phase_deg);
      FUZZ_CHECK(k == 0 || s.t_s >= l.samples[k - 1].t_s, "t_s goes backwards");
      t_last = std::max(t_last, s.t_s);
    }
  }
  check_links(links);
  const double max_amplitude = std::pow(10.0, trace::kMaxGainDb / 20.0) * (1.0 + 1e-9);
  for (const bool loop : {false, true}) {
    rfsitl::channel::TraceSettings s;
    s.loop = loop;
    const auto stage = trace::make_stage(s, t, kIds);
    for (const double at : {0.0, 0.37 * t_last, t_last, 1.5 * t_last + 0.1}) {
      for (std::size_t a = 0; a < kIds.size(); ++a) {
        for (std::size_t b = 0; b < kIds.size(); ++b) {
          rfsitl::channel::LinkGeometry g;
          g.tx.index = a;
          g.rx.index = b;
          g.time_s = at;
          const std::complex<double> h = stage->gain(g);
          FUZZ_CHECK(std::isfinite(h.real()) && std::isfinite(h.imag()), "gain not finite");
          FUZZ_CHECK(std::abs(h) <= max_amplitude, "|gain| %g above the limit", std::abs(h));
        }
      }
    }
  }
}

/// Runs `parse`; an error must be std::invalid_argument naming `source`.
template <class Parse, class Check>
void run(const std::string& source, Parse&& parse, Check&& check) {
  try {
    check(parse());
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind(source + ":", 0) == 0, "error does not name the source: %s",
               what.c_str());
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "%s: threw something other than std::invalid_argument: %s", source.c_str(),
               e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Copies of exactly `size` bytes (no terminator the parsers could rely on).
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::vector<std::uint8_t> bytes(data, data + size);
  run(
      "fuzz.csv", [&] { return trace::parse_csv(text, "fuzz.csv", kIds); }, check_trace);
  run(
      "links.csv", [&] { return trace::parse_links_csv(text, "links.csv", kIds); }, check_links);
  run(
      "fuzz.npy", [&] { return trace::parse_npy(bytes, "fuzz.npy", kNpyLinks, 0.01); },
      check_trace);
  return 0;
}
