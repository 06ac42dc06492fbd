"""Reaching Ray: the import that says how to install it, and the connection to a cluster by
address, which fails within CONNECT_TIMEOUT_SECONDS naming the address rather than waiting for Ray's
own retries (which last minutes)."""

from __future__ import annotations

import socket
from contextlib import contextmanager
from types import ModuleType
from typing import TYPE_CHECKING

from .errors import ClusterUnreachable, RayMissing

if TYPE_CHECKING:
    from collections.abc import Iterator

# How long an address may take to accept a connection before the render gives up on it
CONNECT_TIMEOUT_SECONDS = 10.0
# address="auto": the cluster `ray start` runs on this machine, else a local instance of our own
AUTO = "auto"
RAY_CLIENT_SCHEME = "ray://"


def require_ray() -> ModuleType:
    """The ray module, or RayMissing saying how to install it."""
    try:
        import ray
    except ImportError:
        raise RayMissing() from None
    return ray


def host_and_port(address: str) -> tuple[str, int]:
    """(host, port) of "host:port" or "ray://host:port"; a ClusterUnreachable naming the address
    when it is neither."""
    bare = address.removeprefix(RAY_CLIENT_SCHEME)
    host, _, port = bare.rpartition(":")
    if not host or not port.isdigit():
        raise ClusterUnreachable(f"Ray address {address!r}: expected host:port, ray://host:port or {AUTO}")
    return host.strip("[]"), int(port)


def check_reachable(address: str, timeout: float = CONNECT_TIMEOUT_SECONDS) -> None:
    """Open and close a TCP connection to `address`'s host and port, or raise ClusterUnreachable
    naming it within `timeout` seconds."""
    host, port = host_and_port(address)
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as error:
        reason = "no answer" if isinstance(error, TimeoutError) else (error.strerror or str(error))
        raise ClusterUnreachable(
            f"Ray cluster at {address}: cannot connect to {host}:{port} within {timeout:g} s ({reason})"
        ) from None


@contextmanager
def connected(address: str | None, timeout: float = CONNECT_TIMEOUT_SECONDS) -> Iterator[ModuleType]:
    """Ray, connected for the duration. A process holds one Ray connection: where the caller made
    one (ray.init), it is used whatever `address` says, and stays open. Otherwise: None, Ray's own
    default (RAY_ADDRESS, else a new local instance); AUTO, the cluster `ray start` runs on this
    machine, else a new local instance; "host:port" of a head node or "ray://host:port" of a Ray
    Client server, whose port must answer within `timeout`. A connection made here is closed on
    leaving, and a local instance started here with it."""
    ray = require_ray()
    if ray.is_initialized():
        yield ray
        return
    if address == AUTO:
        try:
            ray.init(address=AUTO, log_to_driver=False)
        except ConnectionError:  # no cluster running here: a local instance
            ray.init(log_to_driver=False)
    elif address is None:
        ray.init(log_to_driver=False)
    else:
        check_reachable(address, timeout)
        try:
            ray.init(address=address, log_to_driver=False)
        except (ConnectionError, RuntimeError) as error:
            raise ClusterUnreachable(f"Ray cluster at {address}: {str(error).splitlines()[0]}") from None
    try:
        yield ray
    finally:
        ray.shutdown()
