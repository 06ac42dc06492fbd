"""What a cluster job reports after each batch or frame: for one progress bar over the whole job."""

from __future__ import annotations

from dataclasses import dataclass

from .worker import WorkerIdentity


@dataclass(frozen=True)
class ClusterProgress:
    """`done` of `total` batches (or frames) finished; `samples` (pixel samples, the whole cluster's)
    in `seconds` since the job started; `live_workers` started and not lost; `last_worker` the
    worker that finished the latest."""

    done: int
    total: int
    samples: int
    seconds: float
    live_workers: int
    last_worker: WorkerIdentity

    @property
    def samples_per_second(self) -> float:
        return self.samples / self.seconds if self.seconds > 0 else 0.0
