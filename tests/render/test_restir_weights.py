"""The restir combinations' resampling weights sum to one, checked on the GPU for the samples they
keep (override RESERVOIR_CHECK_WEIGHT_SUMS, WGSL `checked_weight_sum`): each survivor's share as
the centre's own sample plus its shares as every other reservoir of the combination would hold it
(stored, as a pass keeps it for another, and seen again from the centre). A sample that one
reservoir sees differently from the others, other than by a common factor, breaks the sum (a
triangle's point moved 5 cm in its record: 0.0211 and 0.00974); a common factor leaves the shares
alone, and the Welch tests against mis (test_restir.py, test_restir_frames.py) catch it. Spatial reuse
(RESERVOIR_NEIGHBOURS) on every light kind, and the previous frame's reservoir (RESERVOIR_HISTORY_CAP)
in frames where the camera moves."""

from __future__ import annotations

import numpy as np
import pytest

from tests.render.test_restir import lights_behind
from tests.render.test_restir_frames import nudged_frames
from wgputrace import Renderer, Scene
from wgputrace.scenes import scene_by_name

pytestmark = pytest.mark.gpu

SIZE = 32
SEED = 31
# f32 targets re-evaluated at up to 4 receivers
TOLERANCE = 1e-4
CHECK = {"RESERVOIR_CHECK_WEIGHT_SUMS": True}
# scenes whose camera sees no emitter (what it would see adds to the check's channels): triangle
# lights; point, spot and directional
SCENES = {"lights_behind": lights_behind, "point_spot_directional": lambda: scene_by_name("point_spot_directional")}


def checked(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The deviations |sum - 1| of the pixels whose first vertex checked a combination, and how
    many reservoirs each combined."""
    deviation, _, reservoirs = np.moveaxis(image, -1, 0)
    combined = reservoirs < 0
    return deviation[combined], -reservoirs[combined]


def assert_sums_to_one(image: np.ndarray, what: str, least_reservoirs: float) -> None:
    deviations, reservoirs = checked(image)
    assert deviations.size > SIZE * SIZE / 4, f"{what}: only {deviations.size} combinations checked"
    assert deviations.max() < TOLERANCE, f"{what}: weights sum to 1 +- {deviations.max():.3g}"
    assert reservoirs.mean() >= least_reservoirs, f"{what}: {reservoirs.mean():.2f} reservoirs a combination"


@pytest.mark.parametrize("name", sorted(SCENES))
def test_neighbours_shares_sum_to_one(gpu_context, name):
    overrides = CHECK | {"RESERVOIR_NEIGHBOURS": 3}
    renderer = Renderer(
        SCENES[name](), SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=overrides
    )
    renderer.render(1)
    assert renderer.nonfinite_samples == 0
    # most pixels find two or more of their three neighbours suitable
    assert_sums_to_one(renderer.image(), name, 2.5)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_the_previous_frames_shares_sum_to_one(gpu_context, name):
    scene: Scene = SCENES[name]()
    overrides = CHECK | {"RESERVOIR_HISTORY_CAP": 20}
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=overrides)
    *_, last = nudged_frames(renderer, scene, 3)
    assert_sums_to_one(last, name, 2.0)
