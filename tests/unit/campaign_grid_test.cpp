// The campaign file's reader and the grid: the order of grid points and runs,
// zip groups, seeds, and errors that name the file's line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/run_plan.hpp"
#include "temp_dir.hpp"

namespace rfsitl::campaign {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_campaign(yaml, "c.yaml", "");
  } catch (const CampaignError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << yaml;
  return {};
}

std::vector<std::string> texts(const GridPoint& p) {
  std::vector<std::string> out;
  for (const SettingValue* v : p.values) out.push_back(v->text);
  return out;
}

TEST(CampaignGrid, CartesianProductFirstAxisSlowestZipGroupsTogether) {
  const CampaignSpec spec = parse_campaign(
      "scenario: s.yaml\n"
      "parameters:\n"
      "  a: [1, 2]\n"
      "  b: [x, y, z]\n"
      "zip:\n"
      "  - {c: [p, q], d: [r, s]}\n"
      "seeds: 2\n",
      "c.yaml", "");
  ASSERT_EQ(spec.parameter_keys(), (std::vector<std::string>{"a", "b", "c", "d"}));
  const std::vector<GridPoint> grid = expand_grid(spec);
  ASSERT_EQ(grid.size(), 2U * 3U * 2U);
  // Point i in mixed radix (2, 3, 2), the last axis fastest; c and d move together.
  const std::vector<std::string> a = {"1", "2"};
  const std::vector<std::string> b = {"x", "y", "z"};
  const std::vector<std::string> c = {"p", "q"};
  const std::vector<std::string> d = {"r", "s"};
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const std::size_t ia = i / 6;
    const std::size_t ib = (i / 2) % 3;
    const std::size_t iz = i % 2;
    EXPECT_EQ(texts(grid[i]), (std::vector<std::string>{a[ia], b[ib], c[iz], d[iz]})) << i;
  }
}

TEST(CampaignGrid, NoParametersIsOnePointAndSeedsCountOrList) {
  const CampaignSpec counted = parse_campaign("scenario: s.yaml\nseeds: 3\n", "c.yaml", "");
  EXPECT_EQ(expand_grid(counted).size(), 1U);
  EXPECT_EQ(counted.seeds, (std::vector<std::uint64_t>{1, 2, 3}));
  const CampaignSpec listed = parse_campaign("scenario: s.yaml\nseeds: [9, 4]\n", "c.yaml", "");
  EXPECT_EQ(listed.seeds, (std::vector<std::uint64_t>{9, 4}));
}

TEST(CampaignGrid, PathsResolveAgainstTheCampaignFolder) {
  const CampaignSpec spec =
      parse_campaign("scenario: ../s.yaml\nseeds: 1\n", "dir/sweep.yaml", "dir");
  EXPECT_EQ(spec.scenario_path, "s.yaml");
  EXPECT_EQ(spec.output_dir, "dir/sweep.results");  // default: beside the file, named after it
}

TEST(CampaignGrid, ErrorsNameTheLineAndTheKey) {
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 1\nparameters:\n  a: [1, 2]\n  a: [3]\n"),
            "c.yaml:5: a: given twice (in settings:, parameters: or zip:)");
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 1\nparameters:\n  seed: [1, 2]\n")
                .rfind("c.yaml:4: seed: set by the campaign itself", 0),
            0U);
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 1\nzip:\n  - {a: [1, 2], b: [3]}\n"),
            "c.yaml:4: b: a zip group's keys vary together: 1 values here, 2 for a");
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: [1, 1]\n"), "c.yaml:2: seeds: seed 1 twice");
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 1\nparameters:\n  a: []\n"),
            "c.yaml:4: a: give a list of one or more values, e.g. [1, 2, 3]");
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 1\nparameters:\n  a: [[1]]\n"),
            "c.yaml:4: a: a value must be a single value (a scalar)");
  EXPECT_EQ(error_of("scenario: s.yaml\nsede: 1\n").rfind("c.yaml:2: sede: unknown key", 0), 0U);
  EXPECT_EQ(error_of("seeds: 1\n"), "c.yaml: scenario: missing: the base scenario file");
  // A repeated section: YAML keeps both; the second seeds: would add to the first.
  EXPECT_EQ(error_of("scenario: s.yaml\nseeds: 2\nseeds: 2\n"), "c.yaml:3: seeds: given twice");
}

/// A campaign over a scenario file, both written into a temporary folder.
struct Files {
  rfsitl::testing::TempDir dir{"campaign-plan"};
  std::string campaign;

  explicit Files(const std::string& campaign_text) {
    std::ofstream(dir.path("s.yaml")) << "name: t\ntime: {duration_s: 1}\n"
                                         "nodes:\n  - {id: 1}\n  - {id: 2}\n";
    campaign = dir.path("c.yaml");
    std::ofstream(campaign) << campaign_text;
  }
};

TEST(CampaignPlan, RunsInGridThenSeedOrderEachPointItsOwnHash) {
  const Files f(
      "scenario: s.yaml\nparameters:\n  channel.noise_power_db: [-100, -90]\nseeds: [5, 3]\n");
  const CampaignSpec spec = load_campaign_file(f.campaign);
  const std::vector<PlannedRun> runs = plan_runs(spec, f.dir.path("runs"));
  ASSERT_EQ(runs.size(), 4U);
  const std::vector<std::pair<std::string, std::uint64_t>> order = {
      {"-100", 5}, {"-100", 3}, {"-90", 5}, {"-90", 3}};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].values, std::vector<std::string>{order[i].first});
    EXPECT_EQ(runs[i].seed, order[i].second);
    EXPECT_EQ(runs[i].key, runs[i].scenario_hash + "-s" + std::to_string(order[i].second));
  }
  EXPECT_EQ(runs[0].scenario_hash, runs[1].scenario_hash);  // the seed is not in the hash
  EXPECT_NE(runs[0].scenario_hash, runs[2].scenario_hash);
  const std::vector<std::string>& args = runs[2].arguments;
  EXPECT_NE(std::find(args.begin(), args.end(), "channel.noise_power_db=-90"), args.end());
  EXPECT_EQ(args.back(), f.dir.path("runs/" + runs[2].key + "/summary.json"));
}

TEST(CampaignPlan, EveryGridPointIsValidatedFirstNamingTheCampaignLine) {
  const Files bad_value(
      "scenario: s.yaml\nparameters:\n  channel.noise_power_db: [-100,\n    900]\nseeds: 1\n");
  try {
    plan_runs(load_campaign_file(bad_value.campaign), bad_value.dir.path("runs"));
    ADD_FAILURE() << "accepted";
  } catch (const CampaignError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  bad_value.campaign + ":4: channel.noise_power_db: must be in", 0),
              0U)
        << e.what();
  }
  const Files no_end("scenario: s.yaml\nsettings: {time.duration_s: 0}\nseeds: 1\n");
  EXPECT_THROW(plan_runs(load_campaign_file(no_end.campaign), no_end.dir.path("runs")),
               CampaignError);
}

TEST(CampaignPlan, ShellLineQuotesWhatAShellWouldSplit) {
  EXPECT_EQ(shell_line({"rfsitl", "run", "a b.yaml", "--set", "x=it's"}),
            "rfsitl run 'a b.yaml' --set 'x=it'\\''s'");
}

}  // namespace
}  // namespace rfsitl::campaign
