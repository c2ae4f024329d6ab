// The results table: its columns' order, CSV quoting read back, and the
// figures a run's summary gives it.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/results_table.hpp"
#include "rfsitl/campaign/run_figures.hpp"

namespace rfsitl::campaign {
namespace {

ResultRow row(std::string value, std::uint64_t seed, std::map<std::string, std::string> figures) {
  ResultRow r;
  r.values = {std::move(value)};
  r.seed = seed;
  r.scenario_hash = "h";
  r.status = std::string(kStatusOk);
  r.figures = std::move(figures);
  return r;
}

TEST(CampaignTable, ColumnsParametersRunDerivedThenCountersByName) {
  ResultsTable t{{"mac.type"}, {}};
  t.rows.push_back(row("csma", 1, {{"zeta", "1"}, {"delivery_ratio", "0.5"}, {"alpha", "2"}}));
  t.rows.push_back(row("none", 2, {{"beta", "3"}}));
  const std::string csv = to_csv(t);
  EXPECT_EQ(csv,
            "mac.type,seed,scenario_hash,status,error,delivery_ratio,delivered_per_s,alpha,beta,"
            "zeta\n"
            "csma,1,h,ok,,0.5,,2,,1\n"
            "none,2,h,ok,,,,,3,\n");
}

TEST(CampaignTable, QuotedCellsReadBackAsWritten) {
  ResultsTable t{{"k"}, {}};
  ResultRow failed = row("a,b", 7, {});
  failed.status = std::string(kStatusFailed);
  failed.error = "exit code 2: \"bad\"\nsecond line";
  t.rows.push_back(failed);
  t.rows.push_back(row("plain", 8, {{"delivered", "12"}}));
  const ResultsTable back = parse_csv(to_csv(t), "r.csv", {"k"});
  ASSERT_EQ(back.rows.size(), 2U);
  EXPECT_EQ(back.rows[0].values, std::vector<std::string>{"a,b"});
  EXPECT_EQ(back.rows[0].error, failed.error);
  EXPECT_EQ(back.rows[0].status, "failed");
  EXPECT_TRUE(back.rows[0].figures.empty());  // empty cells are absent figures
  EXPECT_EQ(back.rows[1].seed, 8U);
  EXPECT_EQ(back.rows[1].figures.at("delivered"), "12");
  EXPECT_EQ(to_csv(back), to_csv(t));
}

TEST(CampaignTable, AnotherCampaignsTableIsRefused) {
  ResultsTable t{{"a"}, {row("1", 1, {})}};
  EXPECT_THROW(parse_csv(to_csv(t), "r.csv", {"b"}), CampaignError);
  EXPECT_THROW(parse_csv("a,seed,scenario_hash,status,error\n1,x,h,ok,\n", "r.csv", {"a"}),
               CampaignError);
  EXPECT_THROW(parse_csv("a,seed,scenario_hash,status,error\n1,2,h,ok\n", "r.csv", {"a"}),
               CampaignError);
}

TEST(CampaignFigures, CountersSummedOverNodesAndDerivedFromThem) {
  const nlohmann::json summary = {{"virtual_s", 2.0},
                                  {"wall_s", 0.37},  // wall-clock: never in the table
                                  {"late_ticks", 1},
                                  {"nodes",
                                   {{{"id", 1},
                                     {"handed_in", 10},
                                     {"delivered", 8},
                                     {"phy", "gmsk"},
                                     {"lost", {{"collision", 2}}}},
                                    {{"id", 2},
                                     {"handed_in", 6},
                                     {"delivered", 4},
                                     {"phy", "gmsk"},
                                     {"lost", {{"collision", 1}}}}}}};
  const auto f = run_figures(summary);
  EXPECT_EQ(f.at("handed_in"), "16");
  EXPECT_EQ(f.at("delivered"), "12");
  EXPECT_EQ(f.at("lost_collision"), "3");
  EXPECT_EQ(f.at("late_ticks"), "1");
  EXPECT_EQ(f.at("delivery_ratio"), figure_text(12.0 / 16.0));
  EXPECT_EQ(f.at("delivered_per_s"), figure_text(12.0 / 2.0));
  EXPECT_EQ(f.count("wall_s"), 0U);
  EXPECT_EQ(f.count("id"), 0U);
  EXPECT_EQ(f.count("phy"), 0U);
  EXPECT_THROW(run_figures(nlohmann::json::object()), std::runtime_error);
}

}  // namespace
}  // namespace rfsitl::campaign
