"""The example notebook (examples/python/spacing_sweep.ipynb) executed headless
as a user's Jupyter would run it, on its small grid: every cell runs, the
campaign's table has a row per run, and the plot is written."""

import json
import os
import shutil
import subprocess
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.environ.get("RFSITL_SOURCE_DIR", os.path.join(HERE, "..", ".."))
NOTEBOOK = os.path.join(SOURCE, "examples", "python", "spacing_sweep.ipynb")
NBCONVERT = shutil.which("jupyter-nbconvert")


@unittest.skipUnless(NBCONVERT, "jupyter-nbconvert is not installed (Debian: jupyter-nbconvert)")
@unittest.skipUnless(os.environ.get("RFSITL_BIN"), "RFSITL_BIN names the rfsitl program")
class NotebookTest(unittest.TestCase):
    def test_the_notebook_runs_headless_and_writes_its_plot(self):
        with tempfile.TemporaryDirectory() as tmp:
            env = dict(os.environ, RFSITL_NOTEBOOK_QUICK="1",
                       RFSITL_NOTEBOOK_OUT=os.path.join(tmp, "results"))
            executed = os.path.join(tmp, "executed.ipynb")
            r = subprocess.run([NBCONVERT, "--to", "notebook", "--execute",
                                "--ExecutePreprocessor.timeout=1200", NOTEBOOK,
                                "--output", executed],
                               cwd=os.path.dirname(NOTEBOOK), env=env, capture_output=True,
                               text=True, timeout=1800)
            self.assertEqual(r.returncode, 0, r.stderr[-4000:])
            with open(executed) as f:
                nb = json.load(f)
            outputs = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c["outputs"]]
            self.assertFalse([o for o in outputs if o.get("output_type") == "error"])
            text = "".join("".join(o.get("text", "")) for o in outputs)
            # 2 PHYs x 2 fading models x 3 spacings x 2 seeds.
            self.assertIn("24 runs, 0 failed", text)
            plot = os.path.join(tmp, "results", "delivery_vs_spacing.png")
            self.assertGreater(os.path.getsize(plot), 5000)


if __name__ == "__main__":
    unittest.main(verbosity=2)
