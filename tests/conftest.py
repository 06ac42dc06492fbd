"""Shared fixtures: one GPU device per test session, seeded random generators."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="wgputrace-test-xdg-"))

DATA_DIR = Path(__file__).resolve().parent / "data"
FAILURE_DIR = Path(__file__).resolve().parent / "failures"


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Every test that takes the device (gpu_context, directly or through another fixture) is
    marked `gpu`; modules that reach the adapter another way (a Renderer, a subprocess) say so with
    `pytestmark = pytest.mark.gpu`."""
    for item in items:
        if "gpu_context" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.gpu)


@pytest.fixture(scope="session")
def gpu_context():
    from wgputrace.gpu.device import gpu

    return gpu()


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture(scope="session")
def data_dir() -> Path:
    """tests/data: files the tests read (README.md there says where each comes from)."""
    return DATA_DIR


@pytest.fixture
def failure_dir() -> Path:
    """Where a failing test writes images for a person to look at (git-ignored)."""
    FAILURE_DIR.mkdir(exist_ok=True)
    return FAILURE_DIR
