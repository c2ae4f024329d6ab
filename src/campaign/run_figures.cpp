#include "rfsitl/campaign/run_figures.hpp"

#include <array>
#include <charconv>
#include <cstdint>
#include <stdexcept>

namespace rfsitl::campaign {
namespace {

/// The run's own counters in the summary (the wall-clock ones are left out).
constexpr std::array<const char*, 5> kRunCounters = {"late_decodes", "late_ticks",
                                                     "receiver_ticks_blanked", "receiver_ticks_run",
                                                     "receiver_ticks_skipped"};

void add(std::map<std::string, std::int64_t>& sums, const std::string& name,
         const nlohmann::json& v) {
  if (v.is_number_integer()) sums[name] += v.get<std::int64_t>();
}

}  // namespace

const std::vector<std::string>& derived_figure_names() {
  static const std::vector<std::string> names = {"delivery_ratio", "delivered_per_s"};
  return names;
}

std::string figure_text(double v) {
  std::array<char, 32> buf{};
  return {buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr};
}

std::map<std::string, std::string> run_figures(const nlohmann::json& summary) {
  if (!summary.is_object() || !summary.contains("nodes") || !summary["nodes"].is_array()) {
    throw std::runtime_error("not a run summary (no \"nodes\" list)");
  }
  std::map<std::string, std::int64_t> sums;
  for (const auto& node : summary["nodes"]) {
    for (const auto& [name, v] : node.items()) {
      if (name == "id") continue;
      if (v.is_object() && name == "lost") {
        for (const auto& [why, n] : v.items()) add(sums, "lost_" + why, n);
      } else {
        add(sums, name, v);  // numbers only: phy, position and source are not counters
      }
    }
  }
  for (const char* name : kRunCounters) {
    if (summary.contains(name)) add(sums, name, summary[name]);
  }
  std::map<std::string, std::string> figures;
  for (const auto& [name, n] : sums) figures[name] = std::to_string(n);
  const double virtual_s = summary.value("virtual_s", 0.0);
  figures["virtual_s"] = figure_text(virtual_s);
  const std::int64_t delivered = sums["delivered"];
  if (sums["handed_in"] > 0) {
    figures["delivery_ratio"] = figure_text(double(delivered) / double(sums["handed_in"]));
  }
  if (virtual_s > 0) figures["delivered_per_s"] = figure_text(double(delivered) / virtual_s);
  return figures;
}

}  // namespace rfsitl::campaign
