"""Out-of-tree components: a throwaway component of every kind (PHY, MAC,
channel stage, sample stage, position source, mobility model) written in a temporary folder,
configured with find_package(rfsitl) against this build, built as a plugin and
loaded from RFSITL_PLUGIN_PATH: `rfsitl describe` lists each by name, a
scenario selects the channel stage and the sample stage by name and their
losses show in the run, and
a plugin built for another rfsitl is refused with a message, not a crash.
Nothing is written into the source tree."""

import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest

from harness import BIN

BUILD_DIR = os.path.dirname(os.path.dirname(os.path.abspath(BIN)))

# A channel stage written out of tree: a fixed extra loss on every link (also
# test_install_package's, against the installed package).
EXTRA_LOSS = r'''
struct ExtraLossSettings {
  double loss_db = 10.0;
};

const rfsitl::config::Fields<ExtraLossSettings>& fields() {
  static const auto f = rfsitl::config::Fields<ExtraLossSettings>().real(
      "loss_db", &ExtraLossSettings::loss_db, "dB", {0.0, 300.0}, "loss added to every link");
  return f;
}

class ExtraLoss final : public rfsitl::channel::GainStage {
 public:
  explicit ExtraLoss(double loss_db) : amplitude_(std::pow(10.0, -loss_db / 20.0)) {}
  std::complex<double> gain(const rfsitl::channel::LinkGeometry&) const override {
    return amplitude_;
  }

 private:
  double amplitude_;
};
'''

COMPONENTS = r'''
// One throwaway component of each kind. The channel stage (a fixed extra loss
// on every link) and the sample stage (a gain on a radio's samples) are real
// ones; the others are built-ins under another name, which is all the
// registration path needs.
#include <cmath>
#include <complex>
#include <memory>
#include <span>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/mac_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/registry/plugin.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"

namespace {

'''+ EXTRA_LOSS + r'''
struct SampleGainSettings {
  double gain_db = 0.0;
};

const rfsitl::config::Fields<SampleGainSettings>& gain_fields() {
  static const auto f = rfsitl::config::Fields<SampleGainSettings>().real(
      "gain_db", &SampleGainSettings::gain_db, "dB", {-200.0, 200.0}, "gain on every sample");
  return f;
}

class SampleGain final : public rfsitl::channel::SampleStage {
 public:
  explicit SampleGain(double gain_db)
      : amplitude_(static_cast<float>(std::pow(10.0, gain_db / 20.0))) {}
  void apply(std::size_t, rfsitl::SampleTime, std::span<rfsitl::cf32> x) const override {
    for (rfsitl::cf32& v : x) v *= amplitude_;
  }

 private:
  float amplitude_;
};

template <class Component, class Registry>
void renamed(Registry& registry, const Component* original, const char* name) {
  Component c = *original;
  c.info.name = name;
  c.info.doc = "out-of-tree test component";
  registry.add(c);
}

void register_components() {
  rfsitl::channel::channel_stage_registry().add(
      {fields().info("channel", "plugin_extra_loss", "a fixed extra loss on every link (test)"),
       [](const rfsitl::config::Settings& s, const rfsitl::channel::StageContext&) {
         return std::make_unique<ExtraLoss>(fields().build(s).loss_db);
       }});
  rfsitl::channel::sample_stage_registry().add(
      {gain_fields().info("sample", "plugin_sample_gain", "a gain on a radio's samples (test)"),
       [](const rfsitl::config::Settings& s, const rfsitl::channel::SampleStageContext&) {
         return std::make_unique<SampleGain>(gain_fields().build(s).gain_db);
       }});
  renamed(rfsitl::phy::phy_registry(), rfsitl::phy::find_phy("gmsk"), "plugin_gmsk");
  renamed(rfsitl::mac::mac_registry(), rfsitl::mac::find_mac("none"), "plugin_mac");
  renamed(rfsitl::position::position_source_registry(),
          rfsitl::position::find_position_source("location_port"), "plugin_source");
  renamed(rfsitl::position::mobility::mobility_registry(),
          rfsitl::position::mobility::find_mobility("orbit"), "plugin_orbit");
}

}  // namespace

RFSITL_PLUGIN(register_components)
'''

CMAKELISTS = '''cmake_minimum_required(VERSION 3.25)
project(throwaway LANGUAGES CXX)
find_package(rfsitl REQUIRED)
rfsitl_add_plugin(throwaway_components components.cpp)
'''

# The same plugin, but claiming another version: the loader must refuse it.
FOREIGN = r'''
#include "rfsitl/registry/plugin.hpp"
extern "C" __attribute__((visibility("default"))) const char* rfsitl_plugin_abi() {
  return "rfsitl 0.0.1 c++abi 1 cxx11abi 0";
}
extern "C" __attribute__((visibility("default"))) void rfsitl_plugin_register() {
  __builtin_trap();  // never reached: the tag is checked first
}
'''

SCENARIO = '''nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 40, y: 0, z: 10}}
time: {mode: virtual, duration_s: 1}
channel:
  stages:
    - {type: path_loss}
    - {type: plugin_extra_loss, loss_db: LOSS}
  tx_stages:
    - {type: plugin_sample_gain, gain_db: GAIN}
traffic:
  - {at_s: 0.1, src: 1, dst: 2, size_bytes: 50, repeat: 15, interval_s: 0.05}
'''


def run(cmd, env=None, cwd=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd, timeout=timeout,
                          stdin=subprocess.DEVNULL)


@unittest.skipIf(shutil.which("cmake") is None, "cmake is not installed")
class OutOfTreePluginTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="rfsitl-plugin-")
        src = os.path.join(cls.tmp.name, "src")
        cls.plugins = os.path.join(cls.tmp.name, "plugins")
        os.makedirs(src)
        os.makedirs(cls.plugins)
        with open(os.path.join(src, "components.cpp"), "w") as f:
            f.write(COMPONENTS)
        with open(os.path.join(src, "CMakeLists.txt"), "w") as f:
            f.write(CMAKELISTS)
        build = os.path.join(cls.tmp.name, "build")
        r = run(["cmake", "-S", src, "-B", build, f"-Drfsitl_DIR={BUILD_DIR}",
                 "-DCMAKE_BUILD_TYPE=RelWithDebInfo"])
        assert r.returncode == 0, r.stdout + r.stderr
        r = run(["cmake", "--build", build])
        assert r.returncode == 0, r.stdout + r.stderr
        shutil.copy(os.path.join(build, "throwaway_components.so"), cls.plugins)
        cls.env = dict(os.environ, RFSITL_PLUGIN_PATH=cls.plugins)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_describe_lists_a_component_of_every_kind_by_name(self):
        r = run([BIN, "describe"], env=self.env)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("skipped", r.stderr)
        for name in ("plugin_extra_loss", "plugin_sample_gain", "plugin_gmsk", "plugin_mac",
                     "plugin_source", "plugin_orbit"):
            self.assertRegex(r.stdout, rf"\b{name}\b", name)
        r = run([BIN, "describe", "channel", "plugin_extra_loss"], env=self.env)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("loss_db", r.stdout)
        # Without the path, none of them.
        r = run([BIN, "describe"], env={k: v for k, v in self.env.items()
                                         if k != "RFSITL_PLUGIN_PATH"})
        self.assertNotIn("plugin_extra_loss", r.stdout)

    def test_a_scenario_selects_the_plugin_stages_by_name(self):
        delivered = {}
        for loss, gain in ((0, 0), (60, 0), (0, -60)):
            name = f"loss{loss}_gain{gain}"
            path = os.path.join(self.tmp.name, f"{name}.yaml")
            with open(path, "w") as f:
                f.write(SCENARIO.replace("LOSS", str(loss)).replace("GAIN", str(gain)))
            out = os.path.join(self.tmp.name, f"{name}.json")
            r = run([BIN, "run", path, "--no-dashboard", "--summary-json", out], env=self.env)
            self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])
            with open(out) as f:
                node1 = next(n for n in json.load(f)["nodes"] if n["id"] == 1)
            delivered[(loss, gain)] = node1["delivered"]
        # 40 m decodes with the paper's path loss alone; 60 dB more on the link,
        # or 60 dB less on the transmitter's samples, does not.
        self.assertGreater(delivered[(0, 0)], 10)
        self.assertEqual(delivered[(60, 0)], 0)
        self.assertEqual(delivered[(0, -60)], 0)

    def test_a_plugin_for_another_rfsitl_is_refused_with_a_message(self):
        folder = os.path.join(self.tmp.name, "foreign")
        os.makedirs(folder, exist_ok=True)
        source = os.path.join(folder, "foreign.cpp")
        with open(source, "w") as f:
            f.write(FOREIGN)
        include = os.path.join(os.environ.get("RFSITL_SOURCE_DIR", ""), "include")
        r = run(["c++", "-std=c++20", "-shared", "-fPIC", f"-I{include}",
                 f"-I{os.path.join(BUILD_DIR, 'include')}", "-o",
                 os.path.join(folder, "foreign.so"), source])
        self.assertEqual(r.returncode, 0, r.stderr)
        env = dict(self.env, RFSITL_PLUGIN_PATH=folder + ":" + self.plugins)
        r = run([BIN, "describe"], env=env)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stderr, r"plugin .*foreign\.so skipped: built for 'rfsitl 0\.0\.1")
        self.assertIn("rebuild the plugin against this rfsitl", r.stderr)
        self.assertIn("plugin_extra_loss", r.stdout)  # the good one still loads


if __name__ == "__main__":
    unittest.main()
