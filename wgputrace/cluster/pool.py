"""Workers as Ray actors, and tasks spread over them with the lost ones run again.

One actor per GPU where the cluster has GPUs, else one per CPU slot (lavapipe on one thread). The
driver keeps IN_FLIGHT tasks queued on every worker, so the work balances by measured speed. A
worker that dies fails its queued tasks with a RayActorError; they go back to the front of the
queue and a replacement starts (as many as there were workers). Each task's result depends on the
task alone, so the job's result is the one without the fault. An exception of the worker's own
code would be raised by any worker: it ends the job as WorkerFailed instead of being retried.
"""

from __future__ import annotations

import itertools
import re
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import Any, TypeVar

from .errors import NoWorkersLeft, WorkerFailed
from .worker import RenderWorker, WorkerIdentity

Task = TypeVar("Task")
# tasks queued on each worker: one running, one waiting for it
IN_FLIGHT = 2
# A worker's start: process, imports, device, and its prepare call (BVH, pipeline compile; tens of
# seconds for a large scene on lavapipe). Past it the worker counts as lost.
START_TIMEOUT_SECONDS = 300.0
# how often the driver looks at workers still starting while it waits for results
_POLL_SECONDS = 1.0
# the colours Ray puts into the tracebacks it relays
_TERMINAL_COLOURS = re.compile(r"\x1b\[[0-9;]*m")


def _last_line(traceback_text: str) -> str:
    """The exception line that ends a traceback ("SceneLoadError: file.py:2: ..."), without the
    module path Python puts before the exception's name."""
    lines = [line.strip() for line in _TERMINAL_COLOURS.sub("", traceback_text).splitlines() if line.strip()]
    kind, colon, message = lines[-1].partition(": ")
    return f"{kind.rpartition('.')[2]}{colon}{message}"


@dataclass(frozen=True)
class Placement:
    """How many workers to start and what each asks Ray for."""

    count: int
    on_gpu: bool

    @classmethod
    def for_cluster(cls, ray: ModuleType, workers: int | None) -> Placement:
        """One worker per GPU the cluster has, else per CPU slot; at most `workers` (None: no cap)."""
        resources = ray.cluster_resources()
        gpus, cpus = int(resources.get("GPU", 0)), int(resources.get("CPU", 0))
        slots = gpus or cpus
        if slots == 0:
            raise NoWorkersLeft(f"the Ray cluster offers no GPU and no CPU to run workers on ({resources})")
        if workers is not None and workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        return cls(slots if workers is None else min(workers, slots), gpus > 0)

    def actor_options(self) -> dict:
        return {"num_gpus": 1} if self.on_gpu else {"num_cpus": 1}


@dataclass
class _Worker:
    """An actor, what it said about itself, and the call that prepares it (pending until it answers)."""

    key: int
    actor: Any
    identity: Any  # the ObjectRef of identity(), then the WorkerIdentity
    prepared: Any  # the ObjectRef of prepare(), then its value
    started: float
    ready: bool = False
    in_flight: int = 0


class WorkerPool:
    """Actors of RenderWorker, each made ready by `prepare(actor)` (an ObjectRef), which run tasks."""

    def __init__(self, ray: ModuleType, placement: Placement, prepare: Callable[[Any], Any]) -> None:
        self.ray, self.placement, self._prepare = ray, placement, prepare
        self._actor_class = ray.remote(RenderWorker).options(**placement.actor_options(), max_restarts=0)
        self._workers: dict[int, _Worker] = {}
        self._keys = itertools.count()
        self.replacements_left = placement.count
        self.lost = 0  # workers lost
        self.resubmitted = 0  # tasks queued again after their worker was lost
        for _ in range(placement.count):
            self._start()

    @property
    def live(self) -> int:
        """Workers started and not lost (ready or still preparing)."""
        return len(self._workers)

    def setups(self) -> list[Any]:
        """What prepare() returned on each worker that is ready."""
        return [worker.prepared for worker in self._workers.values() if worker.ready]

    def _start(self) -> None:
        actor = self._actor_class.remote(on_cpu=not self.placement.on_gpu)
        key = next(self._keys)
        self._workers[key] = _Worker(key, actor, actor.identity.remote(), self._prepare(actor), time.monotonic())

    def _lose(self, worker: _Worker, why: str) -> None:
        """Forget a worker that died or never started, and start a replacement if one is left."""
        self.lost += 1
        self.ray.kill(worker.actor, no_restart=True)
        if self.replacements_left:
            self.replacements_left -= 1
            self._start()
        elif not self._workers:
            raise NoWorkersLeft(
                f"all workers are lost and the {self.placement.count} replacements are used up (last: {why})"
            )

    def _answer(self, ref: Any, worker: _Worker) -> tuple[bool, Any]:
        """(True, the value) of a finished call; (False, why) if its worker died; WorkerFailed if
        the worker's code raised (Ray brings that as a RayTaskError, or, where the exception does
        not pickle, an UnserializableException holding the worker's traceback as text)."""
        try:
            return True, self.ray.get(ref)
        except self.ray.exceptions.RayActorError as lost:
            return False, str(lost).splitlines()[0]
        except self.ray.exceptions.RayError as error:
            where = worker.identity if isinstance(worker.identity, WorkerIdentity) else "a worker"
            raise WorkerFailed(f"{where}: {_last_line(str(error))}", error) from error

    def _check_starts(self) -> None:
        """Lose the workers that have not finished preparing within START_TIMEOUT_SECONDS."""
        now = time.monotonic()
        for worker in list(self._workers.values()):
            if not worker.ready and now - worker.started > START_TIMEOUT_SECONDS:
                del self._workers[worker.key]
                self._lose(worker, f"not ready within {START_TIMEOUT_SECONDS:g} s")

    def run(
        self, tasks: Sequence[Task], submit: Callable[[Any, Task], Any]
    ) -> Iterator[tuple[Task, Any, WorkerIdentity]]:
        """(task, result, the worker that ran it) for every task as it finishes; `submit(actor,
        task)` starts one (an ObjectRef)."""
        queue: deque[Task] = deque(tasks)
        in_flight: dict[Any, tuple[_Worker, Task]] = {}
        while queue or in_flight:
            for worker in list(self._workers.values()):
                while worker.ready and queue and worker.in_flight < IN_FLIGHT:
                    task = queue.popleft()
                    in_flight[submit(worker.actor, task)] = (worker, task)
                    worker.in_flight += 1
            preparing = {worker.prepared: worker for worker in self._workers.values() if not worker.ready}
            done, _ = self.ray.wait([*in_flight, *preparing], num_returns=1, timeout=_POLL_SECONDS)
            for ref in done:
                if ref in in_flight:
                    worker, task = in_flight.pop(ref)
                    worker.in_flight -= 1
                    answered, value = self._answer(ref, worker)
                    if answered:
                        yield task, value, worker.identity
                        continue
                    queue.appendleft(task)
                    self.resubmitted += 1
                    if self._workers.pop(worker.key, None) is not None:
                        self._lose(worker, value)
                else:
                    self._ready(preparing[ref])
            self._check_starts()

    def _ready(self, worker: _Worker) -> None:
        """A worker's prepare() answered: it takes tasks from now on, or is lost if it died."""
        for name in ("identity", "prepared"):
            answered, value = self._answer(getattr(worker, name), worker)
            if not answered:
                del self._workers[worker.key]
                self._lose(worker, value)
                return
            setattr(worker, name, value)
        worker.ready = True

    def close(self) -> None:
        """End every worker, and with them the tasks still queued on them."""
        for worker in self._workers.values():
            self.ray.kill(worker.actor, no_restart=True)
        self._workers.clear()
