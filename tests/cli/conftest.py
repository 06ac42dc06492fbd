"""The command line as a user runs it: `python -m wgputrace ...` in a separate process."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import wgputrace

# The folder holding the wgputrace package these tests import: the subprocess runs the same code
# whichever working directory it starts in.
PACKAGE_PARENT = Path(wgputrace.__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def run_cli():
    def run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
        path = os.pathsep.join(filter(None, [str(PACKAGE_PARENT), os.environ.get("PYTHONPATH")]))
        return subprocess.run(
            [sys.executable, "-m", "wgputrace", *args],
            capture_output=True,
            text=True,
            timeout=300,
            cwd=cwd,
            env={**os.environ, "PYTHONPATH": path},
        )

    return run
