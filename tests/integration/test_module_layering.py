"""The module layering check (scripts/check_modules.py): clean on this tree, and
failing, with the file, line and ring named, when an include crosses into a
module that is not a declared dependency or closes a cycle."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from harness import SOURCE_DIR

CHECK = os.path.join(SOURCE_DIR, "scripts", "check_modules.py")


def run_check(root):
    return subprocess.run([sys.executable, CHECK, root], capture_output=True, text=True,
                          timeout=120)


class ModuleLayeringTest(unittest.TestCase):
    def copy_tree(self, d):
        for top in ("include", "src", "apps"):
            shutil.copytree(os.path.join(SOURCE_DIR, top), os.path.join(d, top))

    def inject(self, d, rel, include):
        with open(os.path.join(d, rel), "a", encoding="utf-8") as f:
            f.write(f'\n#include "{include}"\n')
        with open(os.path.join(d, rel), encoding="utf-8") as f:
            text = f.read()
        return text[:text.rindex("#include")].count("\n") + 1

    def test_this_tree_is_clean(self):
        r = run_check(SOURCE_DIR)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("no cycles", r.stdout)

    def test_mobility_does_not_link_the_channel(self):
        # The geodesy mobility models need is common's: a model links no
        # part of the channel (and including the channel would be an error).
        sys.path.insert(0, os.path.dirname(CHECK))
        import check_modules
        _, declared = check_modules.check(SOURCE_DIR)
        self.assertIn("position/mobility", declared)
        self.assertNotIn("channel", check_modules.closure(declared, "position/mobility"))
        with tempfile.TemporaryDirectory() as d:
            self.copy_tree(d)
            self.inject(d, "src/position/mobility/orbit_model.cpp", "rfsitl/channel/radio.hpp")
            r = run_check(d)
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn("module position/mobility does not link it", r.stdout)

    def assert_include_caught(self, rel, include, target, module):
        """Adds `#include "include"` to the copied tree's file `rel`: the check
        fails naming the line, the include, its module and the includer's."""
        with tempfile.TemporaryDirectory() as d:
            self.copy_tree(d)
            line = self.inject(d, rel, include)
            r = run_check(d)
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn(f"{rel}:{line}: includes {include} (module {target}), but module {module} "
                      "does not link it", r.stdout)
        return r

    def test_a_cycle_between_scenario_and_engine_is_caught(self):
        # The engine includes the scenario; make the scenario include the engine.
        r = self.assert_include_caught("src/scenario/phy_choice.cpp", "rfsitl/engine/engine.hpp",
                                       "engine", "scenario")
        self.assertIn("modules include each other in a ring: ", r.stdout)
        self.assertIn("scenario -> engine (src/scenario/phy_choice.cpp", r.stdout)

    def test_a_phy_reaching_into_the_engine_is_caught(self):
        self.assert_include_caught("src/phy/gmsk/gmsk_component.cpp",
                                   "rfsitl/engine/frame_ledger.hpp", "engine", "phy/gmsk")

    def test_a_phy_reaching_into_another_phys_internals_is_caught(self):
        # A PHY's own headers live in src/phy/<name>/ and are included from
        # elsewhere as "phy/<name>/x.hpp": checked like the public ones.
        self.assert_include_caught("src/phy/gmsk/gmsk_component.cpp", "phy/ofdm/rates.hpp",
                                   "phy/ofdm", "phy/gmsk")

    def test_libraries_linked_in_a_ring_are_caught(self):
        with tempfile.TemporaryDirectory() as d:
            self.copy_tree(d)
            with open(os.path.join(d, "src", "CMakeLists.txt"), "a", encoding="utf-8") as f:
                f.write("\ntarget_link_libraries(rfsitl_channel PUBLIC rfsitl_engine)\n")
            r = run_check(d)
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn("CMake libraries link in a ring: ", r.stdout)


if __name__ == "__main__":
    unittest.main()
