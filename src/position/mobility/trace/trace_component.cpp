// The mobility model "trace": replay of a CSV trace or an ns-2 setdest file.
#include <filesystem>

#include "../component_support.hpp"
#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/ns2_trace.hpp"
#include "rfsitl/position/mobility/trace_replay_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using namespace detail;

struct TraceFields {
  std::string file;
  std::string format = "csv";
  std::string coordinates = "local";
  std::uint64_t node = 0;
};

const config::Fields<TraceFields>& trace_fields() {
  using S = TraceFields;
  static const auto f =
      config::Fields<S>()
          .text("file", &S::file, "trace file; relative to the scenario file's folder")
          .choice("format", &S::format, {"csv", "ns2"},
                  "csv: `t, node, x, y, z` or `t, node, lat, lon, alt`; ns2: setdest movement file")
          .choice("coordinates", &S::coordinates, {"local", "geodetic"},
                  "csv without a header line: x/y/z metres or lat/lon/alt")
          .integer("node", &S::node, "", 0, 65535, "the node number in the file; 0: this node's id")
          .rule([](const S& s) {
            if (s.file.empty()) throw config::SettingError("file", "required");
          });
  return f;
}

std::unique_ptr<MobilityModel> make_trace(const TraceFields& t, const MobilityContext& c) {
  std::filesystem::path path(t.file);
  if (path.is_relative() && !c.base_dir.empty()) path = std::filesystem::path(c.base_dir) / path;
  const TraceParseResult r =
      t.format == "ns2" ? read_ns2_trace(path.string())
                        : read_csv_trace(path.string(), {c.origin, t.coordinates == "geodetic"
                                                                       ? CsvCoordinates::kGeodetic
                                                                       : CsvCoordinates::kLocal});
  if (c.warn) {
    for (const auto& e : r.errors) c.warn(r.message(e));
    if (r.bad_lines > r.errors.size()) {
      c.warn(path.string() + ": " + std::to_string(r.bad_lines - r.errors.size()) +
             " more bad lines");
    }
  }
  const std::uint32_t wanted = t.node != 0 ? static_cast<std::uint32_t>(t.node) : c.node;
  const auto it = r.tracks.find(wanted);
  if (it == r.tracks.end()) {
    throw std::invalid_argument(path.string() + ": no track for node " + std::to_string(wanted));
  }
  return std::make_unique<TraceReplayModel>(it->second);
}

}  // namespace

MobilityComponent trace_component() {
  return {trace_fields().info("mobility", "trace", "replay of a CSV trace or an ns-2 setdest file"),
          [](const config::Settings& s, const MobilityContext& c) {
            return make_trace(trace_fields().build(s), c);
          }};
}

}  // namespace rfsitl::position::mobility
