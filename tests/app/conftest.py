"""A virtual X display for the whole session: the viewer's windows open on it."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def x_display():
    from wgputrace.testing.display import virtual_display

    with virtual_display() as name:
        yield name
