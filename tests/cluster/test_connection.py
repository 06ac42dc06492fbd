"""Reaching Ray without a cluster: what a missing Ray says, that importing wgputrace does not
import Ray, and that a closed address fails at once naming it (only loopback is contacted)."""

from __future__ import annotations

import socket
import subprocess
import sys
import time

import pytest

import wgputrace as wt
from wgputrace.cluster.connection import CONNECT_TIMEOUT_SECONDS, check_reachable, host_and_port, require_ray


def test_a_missing_ray_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # what `import ray` meets without the extra
    with pytest.raises(ImportError, match='pip install "wgputrace\\[ray\\]"'):
        require_ray()
    with pytest.raises(wt.cluster.RayMissing):
        wt.cluster.render(wt.default_scene(), spp=1, width=4, height=4)


def test_importing_wgputrace_does_not_import_ray():
    code = "import sys, wgputrace; print(wgputrace.cluster.render.__name__, 'ray' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert result.stdout.split() == ["render", "False"]


@pytest.mark.parametrize("address", ["nowhere", "host:port", "ray://:6379"])
def test_addresses_that_are_not_host_and_port_are_refused(address):
    with pytest.raises(wt.cluster.ClusterUnreachable, match=f"Ray address {address!r}"):
        host_and_port(address)


def test_a_closed_port_fails_at_once_naming_the_address():
    with socket.socket() as probe:  # a loopback port nothing listens on once closed
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    start = time.monotonic()
    with pytest.raises(wt.cluster.ClusterUnreachable, match=f"Ray cluster at ray://127.0.0.1:{port}: cannot connect"):
        check_reachable(f"ray://127.0.0.1:{port}")
    assert time.monotonic() - start < CONNECT_TIMEOUT_SECONDS
