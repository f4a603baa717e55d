"""Shared pieces of the Python module's tests (run by ctest: python/CMakeLists.txt)."""
import os
import shutil
import tempfile
import unittest

SOURCE_DIR = os.environ.get("PERI_SOURCE_DIR",
                            os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..")))
QUICKSTART = os.path.join(SOURCE_DIR, "examples", "quickstart.yaml")

# The quickstart on a grid twice as coarse (16,000 nodes instead of 36,000: the edge regions
# still hold one row) and over 15 of its 43 microseconds: the crack has started from the
# notch, and the run takes seconds.
QUICKSTART_SHORT = {"discretization.spacing": 0.5e-3, "discretization.horizon": 1.5e-3,
                    "solver.end_time": 15e-6}


class TempDirCase(unittest.TestCase):
    """A test with its own output folder, removed afterwards."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="peri_python_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def out(self, name):
        return os.path.join(self.tmp, name)
