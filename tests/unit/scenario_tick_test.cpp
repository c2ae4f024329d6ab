// The tick by duration (`time.tick_us`): it names the same tick as the
// tick_samples it stands for, at the sample rate it is read with, and refuses
// ticks that are not a whole number of samples or are given both ways.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/scenario/scenario_loader.hpp"
#include "scenario_errors.hpp"

namespace rfsitl::scenario {
namespace {

Scenario parse(const std::string& time) {
  return parse_scenario("time: " + time + "\nnodes: [{id: 1}, {id: 2}]\n", "t.yaml");
}

TEST(ScenarioTick, TickUsIsTheSameTickAsItsSampleCount) {
  struct Case {
    const char* by_us;
    const char* by_samples;
  };
  for (const Case& c :
       {Case{"{sample_rate_hz: 20e6, tick_us: 100}", "{sample_rate_hz: 20e6, tick_samples: 2000}"},
        Case{"{sample_rate_hz: 1e6, tick_us: 250}", "{sample_rate_hz: 1e6, tick_samples: 250}"},
        Case{"{sample_rate_hz: 20e6, tick_us: 0.05}", "{sample_rate_hz: 20e6, tick_samples: 1}"},
        // 100.1 us at 20 MHz is 2001.9999999999998 samples in binary: still 2002.
        Case{"{sample_rate_hz: 20e6, tick_us: 100.1}",
             "{sample_rate_hz: 20e6, tick_samples: 2002}"},
        Case{"{tick_us: 1000}", "{tick_samples: 1000}"}}) {
    const Scenario a = parse(c.by_us);
    const Scenario b = parse(c.by_samples);
    EXPECT_EQ(a.timing.tick_samples, b.timing.tick_samples) << c.by_us;
    EXPECT_EQ(a.timing.sample_rate_hz, b.timing.sample_rate_hz) << c.by_us;
  }
}

TEST(ScenarioTick, TheDefaultTickIsUnchanged) {
  // The paper's figures are measured with 250-sample ticks at 1 Msps.
  const Scenario s = parse("{}");
  EXPECT_EQ(s.timing.tick_samples, 250U);
  EXPECT_EQ(s.timing.sample_rate_hz, 1e6);
  EXPECT_EQ(parse("{sample_rate_hz: 20e6}").timing.tick_samples, 250U);
}

TEST(ScenarioTick, RefusesBothFormsFractionsAndRanges) {
  const auto error_of = [](const std::string& time) {
    return parse_error_of("nodes: [{id: 1}]\ntime:\n" + time);
  };
  EXPECT_EQ(error_of("  tick_samples: 2000\n  tick_us: 100\n"),
            "t.yaml:4: time.tick_us: give the tick as tick_samples or as tick_us, not both");
  EXPECT_EQ(error_of("  sample_rate_hz: 3e6\n  tick_us: 0.5\n"),
            "t.yaml:4: time.tick_us: 0.5 us at 3e+06 Hz is 1.5 samples, not a whole number "
            "(use tick_samples, or a duration that is)");
  EXPECT_EQ(error_of("  tick_us: 0\n"), "t.yaml:3: time.tick_us: must be > 0, got 0");
  EXPECT_EQ(error_of("  tick_us: -5\n"), "t.yaml:3: time.tick_us: must be > 0, got -5");
  EXPECT_EQ(error_of("  sample_rate_hz: 1e9\n  tick_us: 1e30\n"),
            "t.yaml:4: time.tick_us: 1e+30 us at 1e+09 Hz is 1e+33 samples; the tick must "
            "be in 1..1048576 samples");
}

TEST(ScenarioTick, ACommandLineTickUsUsesTheRateSetBeforeIt) {
  Scenario s = parse("{sample_rate_hz: 20e6}");
  apply_setting(s, "time.tick_us", "250", "--tick-us");
  EXPECT_EQ(s.timing.tick_samples, 5000U);
  try {
    apply_setting(s, "time.tick_us", "0.01", "--tick-us");
    ADD_FAILURE() << "0.2 samples accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--tick-us: time.tick_us: 0.01 us at 2e+07 Hz is 0.2 samples, not a whole "
              "number (use tick_samples, or a duration that is)");
  }
}

}  // namespace
}  // namespace rfsitl::scenario
