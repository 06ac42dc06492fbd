"""A Ray cluster of several nodes on 127.0.0.1, inside a network namespace of its own, for the
tests and the benchmark: work crosses node processes while no packet leaves loopback (Ray binds
to the machine's own address wherever it can see one; a fresh namespace has only loopback). The
namespace is also a PID namespace whose first process is the server below, so when it exits the
kernel ends whatever is left. Each cluster has its own auth token (in the environment, never on
disk) and temporary folder.

    with NamespacedCluster(nodes=2, cpus_per_node=2) as cluster:
        image = cluster.call(function, *args)  # function(*args) inside, connected to the cluster

`function` must be a module-level function; its exceptions come back raised in the caller.
"""

from __future__ import annotations

import fcntl
import os
import pickle
import secrets
import select
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any, BinaryIO

# every wait here is bounded: the namespace check, the cluster's start, each call, the stop
PROBE_TIMEOUT_SECONDS = 10.0
START_TIMEOUT_SECONDS = 90.0
CALL_TIMEOUT_SECONDS = 120.0
STOP_TIMEOUT_SECONDS = 20.0
# the head's port: any port is free in a namespace of our own
HEAD_PORT = 6379
# PID namespace with /proc of its own, so the server is its first process; a network namespace
# with only loopback. As root (CI) these need nothing else; elsewhere a user namespace maps us to
# root inside it (unprivileged user namespaces, where the kernel allows them).
_UNSHARE = ["unshare", "--net", "--pid", "--fork", "--kill-child", "--mount-proc"]
_AS_USER = ["--map-root-user"]
_HEADER = struct.Struct(">Q")
# Linux's struct ifreq as the interface-flags ioctls read it: the name, the flags, padding to 40 bytes
_IFREQ_FLAGS = "16sH22x"
_LOOPBACK = b"lo"
_SIOCGIFFLAGS, _SIOCSIFFLAGS, _IFF_UP = 0x8913, 0x8914, 0x1


class NamespaceUnavailable(RuntimeError):
    """Neither `unshare` as root nor with a user namespace works here; the message says what failed."""


class RemoteTraceback(Exception):
    """The traceback of an exception raised inside the namespace (as concurrent.futures shows a
    worker process's)."""

    def __str__(self) -> str:
        return "\n" + self.args[0]


def namespace_command() -> list[str]:
    """The unshare command line that runs a command in a new network and PID namespace here."""
    attempts = [_UNSHARE] if os.geteuid() == 0 else []
    attempts.append(_UNSHARE + _AS_USER)
    failures = []
    for command in attempts:
        try:
            probe = subprocess.run(
                [*command, "true"], capture_output=True, text=True, timeout=PROBE_TIMEOUT_SECONDS, check=False
            )
        except (OSError, subprocess.TimeoutExpired) as error:
            failures.append(f"{' '.join(command)}: {error}")
            continue
        if probe.returncode == 0:
            return command
        failures.append(f"{' '.join(command)}: {probe.stderr.strip() or f'exit status {probe.returncode}'}")
    raise NamespaceUnavailable("no network namespace for a Ray cluster: " + "; ".join(failures))


def _send(stream: BinaryIO, message: Any) -> None:
    body = pickle.dumps(message)
    stream.write(_HEADER.pack(len(body)) + body)
    stream.flush()


def _read_exactly(fd: int, count: int, deadline: float | None) -> bytes:
    chunks, left = [], count
    while left:
        if deadline is not None:
            ready, _, _ = select.select([fd], [], [], max(deadline - time.monotonic(), 0.0))
            if not ready:
                raise TimeoutError
        chunk = os.read(fd, left)
        if not chunk:
            raise EOFError
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def _receive(fd: int, deadline: float | None = None) -> Any:
    (length,) = _HEADER.unpack(_read_exactly(fd, _HEADER.size, deadline))
    return pickle.loads(_read_exactly(fd, length, deadline))


class NamespacedCluster:
    """`nodes` Ray nodes of `cpus_per_node` CPUs (and `gpus_per_node` GPUs) on 127.0.0.1 in a network
    namespace, and a server there that runs calls; a context manager."""

    def __init__(self, nodes: int = 2, cpus_per_node: int = 1, gpus_per_node: int = 0) -> None:
        self.nodes, self.cpus_per_node, self.gpus_per_node = nodes, cpus_per_node, gpus_per_node
        self.address = f"127.0.0.1:{HEAD_PORT}"
        self._process: subprocess.Popen | None = None

    def __enter__(self) -> NamespacedCluster:
        command = [
            *namespace_command(),
            sys.executable,
            "-m",
            __name__,
            str(self.nodes),
            str(self.cpus_per_node),
            str(self.gpus_per_node),
        ]
        # the calls' functions are imported by name inside: the same import path as here
        path = os.pathsep.join(entry for entry in sys.path if entry and Path(entry).is_dir())
        self._process = subprocess.Popen(
            command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, env={**os.environ, "PYTHONPATH": path}
        )
        try:
            ready = self._reply(START_TIMEOUT_SECONDS, "starting the cluster")
        except BaseException:
            self._end()
            raise
        if ready != "ready":
            self._end()
            raise RuntimeError(f"the namespaced Ray cluster did not start: {ready}")
        return self

    def call(self, function: Callable, *args, timeout: float = CALL_TIMEOUT_SECONDS, **kwargs) -> Any:
        """function(*args, **kwargs) run inside the namespace, within `timeout` seconds (past it the
        cluster is ended and TimeoutError raised)."""
        _send(self._process.stdin, ("call", function, args, kwargs))
        outcome, value, trace = self._reply(timeout, f"{function.__name__}")
        if outcome == "ok":
            return value
        raise value from RemoteTraceback(trace)

    def _reply(self, timeout: float, what: str) -> Any:
        try:
            return _receive(self._process.stdout.fileno(), time.monotonic() + timeout)
        except TimeoutError:
            self._end()
            raise TimeoutError(
                f"namespaced Ray cluster: {what} took over {timeout:g} s; the cluster was ended"
            ) from None
        except EOFError:
            status = self._process.wait(STOP_TIMEOUT_SECONDS)
            raise RuntimeError(f"namespaced Ray cluster: the server exited (status {status}) during {what}") from None

    def _end(self) -> None:
        """Kill the server by its pid: unshare --kill-child passes it on, and the namespace's
        processes end with its first one."""
        if self._process.poll() is None:
            self._process.kill()
        self._process.wait(STOP_TIMEOUT_SECONDS)

    def __exit__(self, *exc) -> None:
        if self._process.poll() is None:
            try:
                _send(self._process.stdin, ("stop",))
                self._process.wait(STOP_TIMEOUT_SECONDS)
            except (OSError, subprocess.TimeoutExpired):
                pass
        self._end()


# -- inside the namespace ---------------------------------------------------------------------------


def _loopback_up() -> None:
    """Bring the namespace's loopback interface up (it starts down), as `ip link set lo up` would,
    without needing iproute2: the SIOCGIFFLAGS and SIOCSIFFLAGS ioctls on a socket."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        request = struct.pack(_IFREQ_FLAGS, _LOOPBACK, 0)
        _, flags = struct.unpack(_IFREQ_FLAGS, fcntl.ioctl(probe, _SIOCGIFFLAGS, request))
        fcntl.ioctl(probe, _SIOCSIFFLAGS, struct.pack(_IFREQ_FLAGS, _LOOPBACK, flags | _IFF_UP))


def _wait_for_port(port: int, deadline: float) -> None:
    while True:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=1.0):
                return
        except OSError:
            if time.monotonic() > deadline:
                raise TimeoutError(
                    f"the head node did not open port {port} within {START_TIMEOUT_SECONDS:g} s"
                ) from None
            time.sleep(0.1)


def _start_nodes(nodes: int, cpus: int, gpus: int, temp: Path) -> list[subprocess.Popen]:
    """`ray start --block` for the head and then each other node; every one up within the timeout."""
    ray_command = str(Path(sys.executable).with_name("ray"))
    common = ["--block", "--node-ip-address=127.0.0.1", f"--num-cpus={cpus}", f"--num-gpus={gpus}"]
    head = [
        "--head",
        f"--port={HEAD_PORT}",
        "--include-dashboard=false",
        "--disable-usage-stats",
        f"--temp-dir={temp}",
    ]
    deadline = time.monotonic() + START_TIMEOUT_SECONDS
    started = [subprocess.Popen([ray_command, "start", *head, *common], stdout=sys.stderr)]
    _wait_for_port(HEAD_PORT, deadline)
    for _ in range(nodes - 1):
        started.append(
            subprocess.Popen([ray_command, "start", f"--address=127.0.0.1:{HEAD_PORT}", *common], stdout=sys.stderr)
        )
    return started


def _wait_for_nodes(nodes: int, deadline: float) -> None:
    """Until `nodes` nodes are alive; the calls then make connections of their own, as a user's
    program would (cluster.render(address=...))."""
    import ray

    ray.init(address=f"127.0.0.1:{HEAD_PORT}", log_to_driver=False)
    try:
        while sum(node["Alive"] for node in ray.nodes()) < nodes:
            if time.monotonic() > deadline:
                raise TimeoutError(f"{nodes} nodes did not join within {START_TIMEOUT_SECONDS:g} s: {ray.nodes()}")
            time.sleep(0.2)
    finally:
        ray.shutdown()


def _stop(started: list[subprocess.Popen]) -> None:
    """End the nodes we started, by pid: SIGTERM lets `ray start --block` stop its node's processes."""
    for process in reversed(started):
        process.send_signal(signal.SIGTERM)
    for process in reversed(started):
        try:
            process.wait(STOP_TIMEOUT_SECONDS)
        except subprocess.TimeoutExpired:
            process.kill()


def _serve(nodes: int, cpus: int, gpus: int) -> None:
    replies = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)  # what the calls print goes to stderr, not into the replies
    requests = sys.stdin.buffer.fileno()
    _loopback_up()
    # this cluster's own token, in the environment of its nodes, workers and driver alike
    os.environ.update(RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=secrets.token_hex(16))
    temp = Path(tempfile.mkdtemp(prefix="wgputrace-ray-"))
    started: list[subprocess.Popen] = []
    try:
        deadline = time.monotonic() + START_TIMEOUT_SECONDS
        started = _start_nodes(nodes, cpus, gpus, temp)
        _wait_for_nodes(nodes, deadline)
        _send(replies, "ready")
        while True:
            try:
                request = _receive(requests)
                if request[0] == "stop":
                    break
                _, function, args, kwargs = request
                _send(replies, ("ok", function(*args, **kwargs), ""))
            except EOFError:  # the caller is gone
                break
            except (Exception, SystemExit) as error:  # the call's (a benchmark's exit too), or its request's
                _send(replies, ("error", _picklable(error), traceback.format_exc()))
    except Exception:
        _send(replies, traceback.format_exc())
    finally:
        _stop(started)
        shutil.rmtree(temp, ignore_errors=True)


def _picklable(error: BaseException) -> BaseException:
    """`error`, or a RuntimeError with its text where it does not pickle."""
    try:
        pickle.loads(pickle.dumps(error))
    except Exception:
        return RuntimeError(f"{type(error).__name__}: {error}")
    return error


if __name__ == "__main__":
    _serve(*(int(argument) for argument in sys.argv[1:4]))
