"""Interrupting a render: the signal deferral on its own, then Renderer.render stopped by SIGINT
(from its progress callback, and from another thread) leaving the mean of the complete samples."""

from __future__ import annotations

import _thread
import signal
import threading
from dataclasses import dataclass, field

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.render.interrupts import Aborted, Interrupted, deferred_signals, exit_status, signals_abort

SIZE, SEED = 24, 7
# far more than any of these tests renders before its interrupt
ENDLESS_SPP = 1_000_000


@pytest.fixture(autouse=True)
def python_sigint_handler():
    """Python's own SIGINT handler, as an interactive run has it: a run started in the background
    by a shell without job control inherits SIGINT ignored, which these tests must not depend on."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_first_signal_is_recorded_and_the_second_aborts():
    with deferred_signals(signal.SIGINT) as deferral:
        signal.raise_signal(signal.SIGINT)
        assert deferral.received == signal.SIGINT
        with pytest.raises(Interrupted) as stopped:
            deferral.check()
        assert stopped.value.signal == signal.SIGINT
        with pytest.raises(Aborted) as aborted:
            signal.raise_signal(signal.SIGINT)
        assert aborted.value.signal == signal.SIGINT
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_shield_holds_the_abort_until_it_ends():
    finished = []
    with deferred_signals(signal.SIGINT) as deferral, pytest.raises(Aborted):
        signal.raise_signal(signal.SIGINT)
        with deferral.shield():
            signal.raise_signal(signal.SIGINT)
            finished.append("the shielded work")
    assert finished == ["the shielded work"]


def test_nested_deferrals_are_one_and_restore_what_was_there():
    before = signal.getsignal(signal.SIGTERM)
    with deferred_signals(signal.SIGINT, signal.SIGTERM) as outer:
        with deferred_signals(signal.SIGINT) as inner:
            assert inner is outer
            signal.raise_signal(signal.SIGTERM)
        assert outer.received == signal.SIGTERM
        assert outer.signals == {signal.SIGINT, signal.SIGTERM}
    assert signal.getsignal(signal.SIGTERM) == before
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_signals_abort_raises_at_once_with_the_signal():
    with signals_abort(signal.SIGTERM), pytest.raises(Aborted) as aborted:
        signal.raise_signal(signal.SIGTERM)
    assert exit_status(aborted.value.signal) == 143


def test_outside_the_main_thread_nothing_is_installed():
    seen = []

    def defer():
        with deferred_signals(signal.SIGINT) as deferral:
            seen.append((deferral.received, signal.getsignal(signal.SIGINT)))

    thread = threading.Thread(target=defer)
    thread.start()
    thread.join()
    assert seen == [(None, signal.default_int_handler)]


# --- Renderer.render on the GPU ---------------------------------------------------------------


@pytest.fixture(scope="module")
def scene():
    return wt.load_scene("cornell")


def assert_mean_of_complete_samples(renderer: wt.Renderer, scene) -> None:
    """The interrupted renderer's image is, bit for bit, a fresh render of as many samples."""
    spp = renderer.samples_per_pixel
    assert spp >= 1
    fresh = wt.Renderer(scene, SIZE, SIZE, seed=SEED)
    fresh.render(spp)
    np.testing.assert_array_equal(renderer.image(), fresh.image())


@dataclass
class SigintProgress:
    """A progress callback that records each batch and raises SIGINT `signals` times inside its
    call for batch number `at_batch`; `went_on` says whether that call ran on after the signals."""

    at_batch: int
    signals: int
    batches: list[int] = field(default_factory=list)
    went_on: bool = False

    def __call__(self, samples: int) -> None:
        self.batches.append(samples)
        if len(self.batches) == self.at_batch:
            for _ in range(self.signals):
                signal.raise_signal(signal.SIGINT)
            self.went_on = True


def interrupted_render(scene, progress: SigintProgress, raises: type[BaseException]) -> wt.Renderer:
    """A renderer whose endless render `progress` stopped with `raises`, every batch counted."""
    renderer = wt.Renderer(scene, SIZE, SIZE, seed=SEED)
    with pytest.raises(raises):
        renderer.render(ENDLESS_SPP, progress)
    assert renderer.samples_per_pixel == sum(progress.batches)
    return renderer


@pytest.mark.gpu
def test_sigint_stops_after_the_submit_in_flight(scene):
    progress = SigintProgress(at_batch=3, signals=1)
    renderer = interrupted_render(scene, progress, Interrupted)
    # the signal came inside the third callback: the render ended there
    assert len(progress.batches) == 3
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert_mean_of_complete_samples(renderer, scene)


@pytest.mark.gpu
def test_a_second_sigint_aborts_and_leaves_the_renderer_consistent(scene):
    progress = SigintProgress(at_batch=2, signals=2)
    renderer = interrupted_render(scene, progress, Aborted)
    assert not progress.went_on  # the second signal aborted at once, inside the callback
    assert_mean_of_complete_samples(renderer, scene)
    # and it renders on from there like any renderer
    renderer.render(3)
    assert_mean_of_complete_samples(renderer, scene)


@pytest.mark.gpu
def test_interrupt_from_another_thread(scene):
    renderer = wt.Renderer(scene, SIZE, SIZE, seed=SEED)
    started = threading.Event()

    def interrupt_once_started() -> None:
        started.wait()
        _thread.interrupt_main()  # as a SIGINT does: the main thread's handler runs

    timer = threading.Thread(target=interrupt_once_started)
    timer.start()
    with pytest.raises(Interrupted):
        renderer.render(ENDLESS_SPP, lambda samples: started.set())
    timer.join()
    assert_mean_of_complete_samples(renderer, scene)


@pytest.mark.gpu
def test_render_in_a_thread_takes_no_signals(scene):
    results = []

    def render() -> None:
        renderer = wt.Renderer(scene, SIZE, SIZE, seed=SEED)
        renderer.render(2)
        results.append(renderer.samples_per_pixel)

    thread = threading.Thread(target=render)
    thread.start()
    thread.join()
    assert results == [2]
