"""The Debian packages (scripts/package.sh, cmake/rfsitl_package.cmake), as a
user gets them: built from this clone, installed with dpkg, and used from a
temporary folder outside the clone with none of the variables that point into
a build tree (SOAPY_SDR_PLUGIN_PATH, PYTHONPATH, LD_LIBRARY_PATH,
RFSITL_PLUGIN_PATH): `rfsitl --version`; an installed scenario run in virtual
time, found by name; SoapySDR finding the module in its own folder; a channel
stage built out of tree with find_package(rfsitl) against the installed
development package and selected by name from a scenario; /usr/bin/python3
importing the GNU Radio blocks from the package (an older /usr/local install of
scripts/build_gr.sh left out of its path); the manual pages and the bash
completion where man and bash look. Then every package is purged and
none of the files dpkg listed for it is left.

Root only (dpkg). The packages are purged whatever happens (tearDownClass, and
at once when the set-up fails). Refuses to run over an rfsitl that is already
installed from a package, which it would otherwise remove."""

import glob
import json
import os
import shutil
import subprocess
import tempfile
import unittest

from test_plugins import EXTRA_LOSS

SOURCE_DIR = os.environ.get(
    "RFSITL_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
PACKAGES = ("rfsitl", "librfsitl-dev")
MASKED = ("SOAPY_SDR_PLUGIN_PATH", "PYTHONPATH", "LD_LIBRARY_PATH", "RFSITL_PLUGIN_PATH")

STAGE = r'''
// A channel stage built out of tree: a fixed extra loss on every link.
#include <cmath>
#include <complex>
#include <memory>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/plugin.hpp"

namespace {

'''+ EXTRA_LOSS + r'''
void register_stage() {
  rfsitl::channel::channel_stage_registry().add(
      {fields().info("channel", "installed_extra_loss", "a fixed extra loss (package test)"),
       [](const rfsitl::config::Settings& s, const rfsitl::channel::StageContext&) {
         return std::make_unique<ExtraLoss>(fields().build(s).loss_db);
       }});
}

}  // namespace

RFSITL_PLUGIN(register_stage)
'''

CMAKELISTS = '''cmake_minimum_required(VERSION 3.25)
project(installed_stage LANGUAGES CXX)
find_package(rfsitl REQUIRED)
message(STATUS "rfsitl_DIR=${rfsitl_DIR}")
rfsitl_add_plugin(installed_stage stage.cpp)
'''

SCENARIO = '''nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 40, y: 0, z: 10}}
time: {mode: virtual, duration_s: 1}
channel:
  stages:
    - {type: path_loss}
    - {type: installed_extra_loss, loss_db: LOSS}
traffic:
  - {at_s: 0.1, src: 1, dst: 2, size_bytes: 50, repeat: 15, interval_s: 0.05}
'''


def run(cmd, cwd=None, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, env=env,
                          timeout=timeout, stdin=subprocess.DEVNULL)


def installed(package):
    r = run(["dpkg-query", "-W", "-f=${Status}", package])
    return r.returncode == 0 and "installed" in r.stdout.split()


def why_not():
    if os.geteuid() != 0:
        return "needs root: installs Debian packages with dpkg"
    for tool in ("dpkg", "cpack", "cmake", "dpkg-shlibdeps", "c++"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed"
    for p in PACKAGES:
        if installed(p):
            return f"{p} is already installed from a package; this test would remove it"
    return None


@unittest.skipIf(why_not() is not None, why_not() or "")
class InstalledPackageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="rfsitl-package-")
        cls.work = os.path.join(cls.tmp.name, "work")  # where the user stands: nothing else
        os.makedirs(cls.work)
        cls.env = {k: v for k, v in os.environ.items() if k not in MASKED}
        cls.env["HOME"] = cls.tmp.name
        cls.packages = []
        cls.listed = {}
        out = os.path.join(cls.tmp.name, "debs")
        r = run(["bash", os.path.join(SOURCE_DIR, "scripts", "package.sh"), out], timeout=3000)
        assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
        cls.debs = sorted(glob.glob(os.path.join(out, "*.deb")))
        names = [run(["dpkg-deb", "-f", d, "Package"]).stdout.strip() for d in cls.debs]
        for name in names:
            if installed(name):
                raise unittest.SkipTest(f"{name} is already installed; this test would remove it")
        cls.packages = names
        try:
            r = run(["dpkg", "-i"] + cls.debs)
            assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
            for name in names:
                cls.listed[name] = run(["dpkg", "-L", name]).stdout.split("\n")
        except BaseException:
            cls.purge()
            raise

    @classmethod
    def purge(cls):
        if cls.packages:
            cls.purge_result = run(["dpkg", "--purge"] + cls.packages)

    @classmethod
    def tearDownClass(cls):
        cls.purge()  # whatever happened; a second purge of a purged package is a no-op
        cls.tmp.cleanup()

    def user(self, cmd, **kw):
        return run(cmd, cwd=self.work, env=kw.pop("env", self.env), **kw)

    def test_1_packages(self):
        names = set(self.packages)
        self.assertTrue({"rfsitl", "librfsitl-dev"} <= names, names)
        self.assertTrue(any(n.startswith("soapysdr") and n.endswith("-module-rfsitl")
                            for n in names), names)
        depends = run(["dpkg-query", "-W", "-f=${Depends}", "rfsitl"]).stdout
        self.assertIn("libyaml-cpp", depends)  # from dpkg-shlibdeps

    def test_2_version(self):
        self.assertEqual(shutil.which("rfsitl", path=self.env.get("PATH")), "/usr/bin/rfsitl")
        r = self.user(["rfsitl", "--version"])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"^rfsitl \d+\.\d+\.\d+")

    def test_3_installed_scenario_in_virtual_time(self):
        path = "/usr/share/rfsitl/scenarios/six_uav_batch.yaml"
        self.assertTrue(os.path.isfile(path))
        version = self.user(["rfsitl", "--version"]).stdout.split()[-1]
        # By its file name: rfsitl looks among its installed scenarios.
        summary = os.path.join(self.tmp.name, "summary.json")
        r = self.user(["rfsitl", "run", "six_uav_batch.yaml", "--mode", "virtual", "--duration",
                       "2", "--no-dashboard", "--summary-json", summary], timeout=300)
        self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])
        with open(summary) as f:
            j = json.load(f)
        self.assertEqual(j["rfsitl_version"], version)
        self.assertGreater(sum(n["delivered"] for n in j["nodes"]), 0)

    def test_4_soapysdr_finds_the_module(self):
        if shutil.which("SoapySDRUtil") is None:
            self.skipTest("SoapySDRUtil is not installed (soapysdr-tools)")
        module = [p for n in self.packages if n.startswith("soapysdr")
                  for p in self.listed[n] if p.endswith("/libSoapyRfsitl.so")]
        self.assertEqual(len(module), 1, module)
        r = self.user(["SoapySDRUtil", "--info"], timeout=60)
        self.assertIn(f"Module found: {module[0]}", r.stdout)
        self.assertRegex(r.stdout, r"Available factories\.\.\..*\brfsitl\b")

    def test_5_out_of_tree_plugin_against_the_installed_package(self):
        src = os.path.join(self.tmp.name, "plugin-src")
        build = os.path.join(self.tmp.name, "plugin-build")
        plugins = os.path.join(self.tmp.name, "plugins")
        os.makedirs(src)
        os.makedirs(plugins)
        with open(os.path.join(src, "stage.cpp"), "w") as f:
            f.write(STAGE)
        with open(os.path.join(src, "CMakeLists.txt"), "w") as f:
            f.write(CMAKELISTS)
        r = self.user(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"])
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertRegex(r.stdout, r"rfsitl_DIR=/usr/lib/[^/\n]+/cmake/rfsitl")
        r = self.user(["cmake", "--build", build])
        self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr[-3000:])
        shutil.copy(os.path.join(build, "installed_stage.so"), plugins)
        env = dict(self.env, RFSITL_PLUGIN_PATH=plugins)
        r = self.user(["rfsitl", "describe", "channel", "installed_extra_loss"], env=env)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("loss_db", r.stdout)
        delivered = {}
        for loss in (0, 60):
            path = os.path.join(self.tmp.name, f"loss{loss}.yaml")
            with open(path, "w") as f:
                f.write(SCENARIO.replace("LOSS", str(loss)))
            out = os.path.join(self.tmp.name, f"loss{loss}.json")
            r = self.user(["rfsitl", "run", path, "--no-dashboard", "--summary-json", out],
                          env=env, timeout=300)
            self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])
            with open(out) as f:
                delivered[loss] = next(n for n in json.load(f)["nodes"] if n["id"] == 1)["delivered"]
        self.assertGreater(delivered[0], 10)
        self.assertEqual(delivered[60], 0)

    def test_6_manual_pages_and_completion(self):
        files = set(self.listed["rfsitl"])
        for page in ("/usr/share/man/man1/rfsitl.1.gz", "/usr/share/man/man1/rfsitl-run.1.gz",
                     "/usr/share/man/man7/rfsitl-components.7.gz",
                     "/usr/share/bash-completion/completions/rfsitl"):
            self.assertIn(page, files)
        if shutil.which("man"):
            r = self.user(["man", "-P", "cat", "rfsitl-run"], env=dict(self.env, MANWIDTH="200"))
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("--mode", r.stdout.replace("\u2010", "-").replace("\u2212", "-"))
        r = self.user(["bash", "-c", "source /usr/share/bash-completion/completions/rfsitl && "
                       "complete -p rfsitl"])
        self.assertIn("_rfsitl", r.stdout)

    def test_7_gnuradio_blocks(self):
        if "gr-rfsitl" not in self.packages:
            self.skipTest("gr-rfsitl was not built (GNU Radio's development files missing)")
        files = set(self.listed["gr-rfsitl"])
        self.assertTrue(any(p.endswith("/grc/blocks/rfsitl_emulator_source.block.yml")
                            for p in files), files)
        # An older gr-rfsitl of scripts/build_gr.sh in /usr/local comes first on
        # Debian's sys.path: left out, so that the package's is the one found.
        code = ("import sys; sys.path = [p for p in sys.path if not p.startswith('/usr/local/')]\n"
                "from gnuradio import rfsitl\n"
                "rfsitl.ubanc_framing()\n"
                "print(rfsitl.__file__)")
        r = self.user(["/usr/bin/python3", "-c", code], timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr[-2000:])
        self.assertIn(r.stdout.strip(), files)

    def test_8_python_module(self):
        if "python3-rfsitl" not in self.packages:
            self.skipTest("python3-rfsitl was not built (pybind11-dev missing)")
        files = set(self.listed["python3-rfsitl"])
        code = ("import rfsitl\n"
                "emu = rfsitl.Emulator('/usr/share/rfsitl/scenarios/six_uav_batch.yaml')\n"
                "emu.run_for(1.0)\n"
                "print(rfsitl.__file__, int(emu.counters()['delivered'].sum()))")
        r = self.user(["/usr/bin/python3", "-c", code], timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr[-2000:])
        path, delivered = r.stdout.split()
        self.assertIn(path, files)
        self.assertTrue(path.startswith("/usr/lib/python3/dist-packages/rfsitl/"), path)
        self.assertGreater(int(delivered), 0)

    def test_9_purge_leaves_nothing(self):
        self.purge()
        self.assertEqual(self.purge_result.returncode, 0, self.purge_result.stderr)
        for name in self.packages:
            self.assertFalse(installed(name), name)
        left = []
        for name, paths in self.listed.items():
            for p in paths:
                # Folders other packages share (/usr, /usr/share/man/man1) stay.
                if p and (os.path.isfile(p) or os.path.islink(p)):
                    left.append(p)
        for ours in ("/usr/share/rfsitl", "/usr/include/rfsitl", "/usr/share/doc/rfsitl"):
            if os.path.exists(ours):
                left.append(ours)
        left += glob.glob("/usr/lib/*/rfsitl") + glob.glob("/usr/lib/*/cmake/rfsitl")
        self.assertEqual(left, [])


if __name__ == "__main__":
    unittest.main()
