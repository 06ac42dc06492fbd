"""One Ray cluster for the tests here that need one: two nodes (a head and a second `ray start
--address` node) on 127.0.0.1 inside a network namespace of its own (wgputrace.cluster.sandbox),
started by the first of them and ended when tests/cluster is done, not held through the rest of the
suite. The tests run their bodies there through `cluster.call`; without Ray or a way to make a
namespace they skip, saying which."""

from __future__ import annotations

import pytest

NODES = 2
# Two workers per node at most: three workers cannot all share one node, so work crosses nodes.
CPUS_PER_NODE = 2


@pytest.fixture(scope="package")
def cluster():
    pytest.importorskip("ray", reason='the ray extra is missing: pip install "wgputrace[ray]"')
    from wgputrace.cluster.sandbox import NamespacedCluster, NamespaceUnavailable, namespace_command

    try:
        namespace_command()
    except NamespaceUnavailable as why:
        pytest.skip(str(why))
    with NamespacedCluster(nodes=NODES, cpus_per_node=CPUS_PER_NODE) as running:
        yield running
