"""Signals that stop work at a safe point instead of at once: the first SIGINT (or SIGTERM, where
asked) is recorded and the work asks for it between steps; the second aborts at once.

Python runs signal handlers in the main thread only, between bytecodes, so a handler that raises
can land anywhere: between a GPU submit and the line that counts it, or inside wgpu's own polling
loop. `deferred_signals` turns the first signal into a request the renderer answers after the
batch in flight (`Deferral.check` raises `Interrupted`), and a `Deferral.shield` section (a submit,
its wait and its accounting) holds even the second signal's `Aborted` until the section is done.
Waiting for the GPU is one C call that no Python handler interrupts anyway, so the shield delays an
abort by microseconds, not by the batch.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType


def signal_name(number: int) -> str:
    """'SIGINT', 'SIGTERM', ..."""
    return signal.Signals(number).name


def exit_status(number: int) -> int:
    """The shell's status for a process ended by signal `number` (130 for SIGINT, 143 for SIGTERM)."""
    return 128 + number


class Interrupted(KeyboardInterrupt):
    """Raised where the work stopped at a safe point after `signal` (a number) was received:
    everything done so far is accounted for."""

    def __init__(self, number: int) -> None:
        super().__init__(f"{signal_name(number)}: stopped after the work in flight")
        self.signal = number


class Aborted(KeyboardInterrupt):
    """Raised at once by `signal` (a number): a second one while the first was being answered, or
    any under `signals_abort`."""

    def __init__(self, number: int) -> None:
        super().__init__(f"{signal_name(number)}: aborted")
        self.signal = number


class Deferral:
    """What `deferred_signals` yields: `received` is the first signal's number (None until one
    arrives). Outside the main thread it never receives anything (signals go to the main thread)."""

    def __init__(self) -> None:
        self.received: int | None = None
        self.signals: set[int] = set()
        self._shielded = 0
        self._pending_abort: int | None = None

    def check(self) -> None:
        """Raise `Interrupted` if a signal was received: call it where stopping is safe."""
        if self.received is not None:
            raise Interrupted(self.received)

    @contextmanager
    def shield(self) -> Iterator[None]:
        """A section no signal breaks into: an abort asked for inside is raised when it ends."""
        self._shielded += 1
        try:
            yield
        finally:
            self._shielded -= 1
        if not self._shielded and self._pending_abort is not None:
            raise Aborted(self._pending_abort)

    def _handle(self, number: int, frame: FrameType | None) -> None:
        if self.received is None:
            self.received = number
        elif self._shielded:
            self._pending_abort = self._pending_abort or number
        else:
            raise Aborted(number)


# The deferral installed in the main thread, which nested `deferred_signals` calls join, so the
# renderer's deferral of SIGINT and the command line's of SIGINT and SIGTERM are one.
_active: Deferral | None = None


@contextmanager
def deferred_signals(*signals: int) -> Iterator[Deferral]:
    """Defer `signals` (default SIGINT) while the block runs, restoring the previous handlers after
    it. Inside another deferral, joins it: the same Deferral, with `signals` added for the block."""
    global _active
    signals = signals or (signal.SIGINT,)
    if threading.current_thread() is not threading.main_thread():
        yield Deferral()
        return
    outer = _active
    deferral = outer or Deferral()
    added = [number for number in signals if number not in deferral.signals]
    previous = {}
    try:
        for number in added:
            previous[number] = signal.signal(number, deferral._handle)
            deferral.signals.add(number)
        _active = deferral
        yield deferral
    finally:
        for number, handler in previous.items():
            # None: a handler installed outside Python, which Python cannot put back; the default is closest
            signal.signal(number, signal.SIG_DFL if handler is None else handler)
            deferral.signals.discard(number)
        _active = outer


@contextmanager
def signals_abort(*signals: int) -> Iterator[None]:
    """While the block runs (main thread only), each of `signals` raises `Aborted` at once: SIGTERM
    then ends a command with the same one-line message and status as SIGINT."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def abort(number: int, frame: FrameType | None) -> None:
        raise Aborted(number)

    previous = {number: signal.signal(number, abort) for number in signals}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, signal.SIG_DFL if handler is None else handler)
