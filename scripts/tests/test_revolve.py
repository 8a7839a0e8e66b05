"""scripts/revolve.py refuses, with the fix, what would crash ParaView or end in a traceback:
--png without a display (Debian's ParaView dies with SIGSEGV there), a directory without fields,
and python3 instead of pvpython. Run with python3 (no ParaView needed): each case stops before
ParaView is imported."""

import importlib.util
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "revolve.py"


def revolve(*args, display=None):
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    if display:
        env["DISPLAY"] = display
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, env=env)


class Revolve(unittest.TestCase):
    def setUp(self):
        d = tempfile.TemporaryDirectory()
        self.addCleanup(d.cleanup)
        self.run_dir = Path(d.name)
        (self.run_dir / "fields.xdmf").write_text("<Xdmf/>\n")

    @unittest.skipIf(importlib.util.find_spec("vtkmodules") is not None, "a VTK here may render off-screen")
    def test_png_without_a_display_is_refused_with_xvfb_run(self):
        r = revolve(str(self.run_dir), "--png", str(self.run_dir / "p.png"))
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("--png renders, but there is no display (DISPLAY is not set)", r.stderr)
        self.assertIn("xvfb-run -a pvpython scripts/revolve.py", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertFalse((self.run_dir / "p.png").exists())

    @unittest.skipIf(importlib.util.find_spec("paraview") is not None, "this python3 has ParaView")
    def test_with_a_display_or_without_png_it_goes_on_to_paraview(self):
        # Past the display check: python3 has no ParaView, which is said (pvpython would go on).
        for args, display in (((str(self.run_dir), "--png", "p.png"), ":99"), ((str(self.run_dir), "--vtu", "s.vtu"), None)):
            r = revolve(*args, display=display)
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertIn("run it with ParaView's pvpython", r.stderr)
            self.assertNotIn("no display", r.stderr)

    def test_a_directory_without_fields_is_named(self):
        r = revolve(str(self.run_dir / "nothing"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("nothing/fields.xdmf does not exist", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main()
