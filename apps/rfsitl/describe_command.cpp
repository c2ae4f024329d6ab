/// `rfsitl describe`: every registered component (live position source,
/// mobility model, PHY, channel stage; MACs as they arrive) and the radio, with
/// their declared settings. The settings
/// tables in scenarios/README.md are `rfsitl describe --markdown`.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "rfsitl/config/settings_table.hpp"
#include "rfsitl/scenario/all_components.hpp"

namespace rfsitl::app {

namespace {

struct DescribeOptions {
  std::string kind;
  std::string name;
  bool markdown = false;
  bool json = false;
};

std::vector<std::string> kinds() {
  std::vector<std::string> out;
  for (const auto* c : scenario::all_components()) {
    if (out.empty() || out.back() != c->kind) out.push_back(c->kind);
  }
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string markdown() {
  std::string out;
  for (const auto* c : scenario::all_components()) {
    out += "#### " + c->kind + " `" + c->name + "`\n\n" + c->doc + ".\n\n" +
           config::settings_table(*c) + "\n";
  }
  return out;
}

int describe(const DescribeOptions& o) {
  if (o.markdown) {
    std::fputs(markdown().c_str(), stdout);
    return 0;
  }
  if (o.json) {
    std::printf("%s\n", scenario::all_components_json(o.kind).dump(2).c_str());
    return 0;
  }
  std::vector<const config::ComponentInfo*> matches;
  std::vector<std::string> names;
  for (const auto* c : scenario::all_components()) {
    if (!o.kind.empty() && c->kind != o.kind) continue;
    names.push_back(c->name);
    if (o.name.empty() || c->name == o.name) matches.push_back(c);
  }
  if (!o.kind.empty() && names.empty()) {
    std::fprintf(stderr, "rfsitl describe: unknown kind '%s' (known: %s)\n", o.kind.c_str(),
                 join(kinds()).c_str());
    return 2;
  }
  if (!o.name.empty() && matches.empty()) {
    std::fprintf(stderr, "rfsitl describe: no %s named '%s' (known: %s)\n", o.kind.c_str(),
                 o.name.c_str(), join(names).c_str());
    return 2;
  }
  if (!o.name.empty()) {
    const auto* c = matches.front();
    std::printf("%s %s: %s\n\n%s", c->kind.c_str(), c->name.c_str(), c->doc.c_str(),
                config::settings_table(*c).c_str());
    return 0;
  }
  for (const auto* c : matches) {
    std::printf("%-8s %-15s %s\n", c->kind.c_str(), c->name.c_str(), c->doc.c_str());
  }
  std::printf("\n`rfsitl describe KIND NAME` prints a component's settings.\n");
  return 0;
}

}  // namespace

std::function<int()> add_describe_command(CLI::App& parent) {
  auto opts = std::make_shared<DescribeOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "describe",
      "List the registered components (PHYs, ...), or one component's settings: what a "
      "scenario file may say");
  cmd->add_option("kind", opts->kind, "Kind of component, e.g. phy");
  cmd->add_option("name", opts->name, "Its name, e.g. gmsk");
  cmd->add_flag("--markdown", opts->markdown,
                "Every component's settings table in Markdown (as in scenarios/README.md)");
  cmd->add_flag("--json", opts->json,
                "Every component (of KIND, if given) with its declared settings, as JSON")
      ->excludes("--markdown");
  return [opts] { return describe(*opts); };
}

}  // namespace rfsitl::app
