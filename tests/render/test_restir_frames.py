"""The restir integrator's reservoirs kept from frame to frame (`Renderer.render_frame` with the
override RESERVOIR_HISTORY_CAP > 0): each pixel's reservoir combined with the one its surface had
in the previous frame wherever the camera alone moved. Averaged over frames it converges to mis's picture where resampling breaks (Welch's
test per block of independent runs); it lowers each frame's error; at rest frames stand alone (bit
for bit `render`'s samples); after a light moves or switches off no frame shows its old light."""

from __future__ import annotations

import numpy as np
import pytest

from tests.render.test_restir import (
    BLOCK,
    BUILDERS,
    FAMILY_SIGNIFICANCE,
    SCENES,
    SEED,
    SIZE,
    assert_matches_mis,
    lights_behind,
)
from wgputrace import Emitter, Renderer, Scene
from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

# independent runs of FRAMES frames each, one sample per pixel a frame
RUNS = 8
FRAMES = 16
LEVEL = sidak(FAMILY_SIGNIFICANCE, len(SCENES) * 3 * (SIZE // BLOCK) ** 2)
# how far the camera steps, back and forth, between frames: enough to count as moving (the
# reservoirs are handed over), too little to move any pixel's surface
NUDGE = 1e-4
# Bitterli et al.'s cap; restir as shipped keeps none (wgputrace.integrators.restir)
HISTORY = {"RESERVOIR_HISTORY_CAP": 20}


def nudged_frames(renderer: Renderer, scene: Scene, frames: int) -> list[np.ndarray]:
    """`frames` frames of one sample, the camera stepping NUDGE along x and back, each frame's own
    samples (`image`), none non-finite or dropped."""
    start = np.array(scene.camera.position)
    images = []
    for frame in range(frames):
        scene.camera.position = tuple(start + (NUDGE * (frame % 2), 0.0, 0.0))
        renderer.render_frame()
        images.append(renderer.image())
        assert renderer.nonfinite_samples == 0 and renderer.dropped_samples == 0
    scene.camera.position = tuple(start)
    return images


def frame_runs(scene: Scene) -> np.ndarray:
    """(RUNS, SIZE, SIZE, 3): the mean over FRAMES nudged frames of direct light, reservoirs kept,
    each run from a new history (`reset`)."""
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=HISTORY)
    runs = []
    for _ in range(RUNS):
        runs.append(np.mean(nudged_frames(renderer, scene, FRAMES), axis=0))
        renderer.reset()
    return np.stack(runs)


def mis_runs(scene: Scene) -> np.ndarray:
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED + 1, max_depth=2, integrator="mis")
    runs = []
    for _ in range(RUNS):
        renderer.render(FRAMES)
        runs.append(renderer.image())
        renderer.reset()
    return np.stack(runs)


@pytest.mark.parametrize("name", SCENES)
def test_frames_reusing_reservoirs_converge_to_mis(gpu_context, name):
    scene = BUILDERS[name]()
    restir = Estimate.from_batches(frame_runs(scene))
    mis = Estimate.from_batches(mis_runs(scene))
    assert_matches_mis(restir, mis, LEVEL, name)


def test_reused_reservoirs_lower_each_frames_error(gpu_context):
    """On the floor lit by one lamp among 65 whose other lamps face away, the previous frame's
    reservoir holds candidates that found the lamp: each frame's squared error against a converged
    picture falls 3.6-3.9x (seeds 1-3, measured), against its own candidates alone; half of that,
    whose spread over seeds is a few percent, bounds it."""
    scene = lights_behind()
    reference = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="mis")
    reference.render(1024)
    converged = reference.image()
    errors = {}
    for name, overrides in (("alone", {}), ("reused", HISTORY)):
        renderer = Renderer(
            scene, SIZE, SIZE, seed=SEED + 1, max_depth=2, integrator="restir", shader_overrides=overrides
        )
        # after the first frames, whose reservoirs have no history yet
        frames = np.stack(nudged_frames(renderer, scene, FRAMES))[FRAMES // 4 :]
        errors[name] = float(((frames - converged) ** 2).mean())
    assert errors["alone"] >= 1.8 * errors["reused"], errors


def test_at_rest_frames_stand_alone(gpu_context):
    """A resting camera's frames take no reservoir of the frame before: bit for bit, their history
    is a fresh renderer's `render` of as many samples."""
    scene = lights_behind()
    frames = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=HISTORY)
    for _ in range(4):
        image = frames.render_frame()
    fresh = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir")
    fresh.render(4)
    np.testing.assert_array_equal(image, fresh.image())


def move_under_the_floor(scene: Scene) -> None:
    lamp = scene.shape("lamp")
    lamp.transform = np.array([[1, 0, 0, 0], [0, 1, 0, -3.0], [0, 0, 1, 0], [0, 0, 0, 1]], float)


def switch_off(scene: Scene) -> None:
    scene.shape("lamp").material = Emitter("lamp", emittance=0.0)


@pytest.mark.parametrize("edit", [move_under_the_floor, switch_off])
def test_a_light_moved_or_switched_off_leaves_no_light_behind(gpu_context, edit):
    """The one lamp that lights what the camera sees, moved under the floor or switched off while
    the camera moves: from the first frame after, the picture is black (its reservoirs, all of
    which hold the lamp, are not handed over after an edit of the scene)."""
    scene = lights_behind()
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=HISTORY)
    lit = nudged_frames(renderer, scene, 4)[-1]
    assert lit.max() > 0
    edit(scene)
    for k, image in enumerate(nudged_frames(renderer, scene, 3)):
        assert image.max() == 0.0, f"frame {k + 1} after the edit still shows light up to {image.max():.3g}"
