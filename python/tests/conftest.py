# Fixtures of the module's tests: the module (from PLIMSOLL_PYTHON_PATH, as ctest sets it), the
# command line and float_body to compare with, and sample projects copied into a temporary
# folder so that their caches are written there.
import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

if os.environ.get("PLIMSOLL_PYTHON_PATH"):
    sys.path.insert(0, os.environ["PLIMSOLL_PYTHON_PATH"])


@pytest.fixture(scope="session")
def plimsoll():
    try:
        import plimsoll as module
    except ImportError as e:
        pytest.skip(f"the plimsoll module is not built or not on PLIMSOLL_PYTHON_PATH: {e}")
    return module


def executable(variable):
    path = os.environ.get(variable, "")
    if not path or not os.access(path, os.X_OK):
        pytest.skip(f"${variable} does not name an executable (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `plimsoll ARGS...`; returns the CompletedProcess (text)."""
    path = executable("PLIMSOLL")

    def run(*args, check=True):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"plimsoll {' '.join(map(str, args))}: exit {done.returncode}\n{done.stderr}")
        return done
    return run


@pytest.fixture(scope="session")
def float_body():
    return executable("PLIMSOLL_FLOAT_BODY")


def asset(name):
    return os.path.join(ROOT, "assets", name)


@pytest.fixture(scope="session")
def sample_projects(tmp_path_factory):
    """projects/ and assets/ copied, so that a project's caches go to the copy."""
    top = tmp_path_factory.mktemp("samples")
    shutil.copytree(os.path.join(ROOT, "projects"), top / "projects",
                    ignore=shutil.ignore_patterns("*.cache"))
    shutil.copytree(os.path.join(ROOT, "assets"), top / "assets")
    return top / "projects"
