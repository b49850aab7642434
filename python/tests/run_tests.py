#!/usr/bin/env python3
"""Runs the module's pytest suite (ctest test python_module). Exits 77 (ctest's skip) where
pytest is not installed; the module is found through PLIMSOLL_PYTHON_PATH."""
import os
import sys

try:
    import pytest
except ImportError:
    print("python_module: skipped, pytest is not installed for", sys.executable,
          "(scripts/install-deps.sh installs python3-pytest)")
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
# -p no:cacheprovider: nothing is written into the source tree.
sys.exit(pytest.main([here, "-q", "-rs", "-p", "no:cacheprovider"] + sys.argv[1:]))
