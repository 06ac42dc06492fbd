"""Shared settings of the property-based fuzz tests: fixed example streams, bounded time per example.

`derandomize=True` draws the same examples on every run (CI stays reproducible; the seed is the
test's name), and no example database is written into the tree. Hypothesis's `deadline` reports
slow examples only after they finish; `time_limit` also stops one that never would (a hang), with
SIGALRM in the main thread.
"""

from __future__ import annotations

import signal
from contextlib import contextmanager
from datetime import timedelta

from hypothesis import HealthCheck, settings

# Per example: a loader finishes in milliseconds and a tiny render in tens of them, so seconds
# mean something went quadratic or stuck.
EXAMPLE_DEADLINE = timedelta(seconds=5)
EXAMPLE_TIME_LIMIT_SECONDS = 20


def fuzz_settings(max_examples: int, **extra) -> settings:
    return settings(
        max_examples=max_examples,
        deadline=EXAMPLE_DEADLINE,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
        **extra,
    )


class ExampleHung(Exception):
    """An example ran past EXAMPLE_TIME_LIMIT_SECONDS."""


@contextmanager
def time_limit(seconds: float = EXAMPLE_TIME_LIMIT_SECONDS):
    def expire(signum, frame):
        raise ExampleHung(f"example still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
