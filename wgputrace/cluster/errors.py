"""What a cluster render raises: Ray missing, a cluster out of reach, a worker's own error, and
no worker left to run the work."""

from __future__ import annotations

INSTALL_HINT = 'pip install "wgputrace[ray]"'


class RayMissing(ImportError):
    """Ray is not installed; the message says how to install it."""

    def __init__(self) -> None:
        super().__init__(f"rendering on a cluster needs Ray: {INSTALL_HINT}")


class ClusterUnreachable(ConnectionError):
    """The cluster's address cannot be reached (within the stated timeout) or is not a Ray cluster."""


class WorkerFailed(RuntimeError):
    """A worker's code raised (the scene failed to load or build there, the device refused it): the
    same error on any worker, so it ends the job rather than being retried. The message is one line
    naming the worker and the error; `worker_traceback` is the worker's traceback as Ray relayed
    it (the Ray error is also the exception's __cause__)."""

    def __init__(self, message: str, ray_error: BaseException) -> None:
        super().__init__(message)
        self.worker_traceback = str(ray_error)


class NoWorkersLeft(RuntimeError):
    """Every worker died (or none could start) and the replacements allowed are used up."""
