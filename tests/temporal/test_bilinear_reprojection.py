"""The temporal kernel's reprojection alone (TemporalAccumulation on G-buffers and histories made
here): a history that is linear across the image comes back exactly at the point the motion
vectors name, as bilinear taps reproduce a linear function; its moments and length with it."""

from __future__ import annotations

import numpy as np

from wgputrace.gpu.buffers import storage_buffer, write_buffer
from wgputrace.gpu.layout import ACCUMULATED_PIXEL, GBUFFER_PIXEL
from wgputrace.render.temporal_accumulation import TEMPORAL_PIXEL, TemporalAccumulation

WIDTH, HEIGHT = 24, 16
MOTION = (1.3, -0.6)
HISTORY_LENGTH = 4.0
ALBEDO = 0.5


def _linear(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Radiance rising across the image, a different slope per channel."""
    return np.stack([1.0 + 0.1 * x + 0.05 * y, 2.0 - 0.03 * x + 0.02 * y, 0.5 + 0.01 * x], axis=-1)


def _gbuffer(motion) -> np.ndarray:
    records = GBUFFER_PIXEL.zeros(WIDTH * HEIGHT)
    records["normal"] = (0.0, 0.0, -1.0)
    records["depth"] = records["previous_depth"] = 2.0
    records["albedo"] = ALBEDO
    records["surface"] = 1
    records["motion"] = motion
    return records


def test_a_linear_history_reprojects_exactly(gpu_context):
    temporal = TemporalAccumulation(gpu_context, WIDTH, HEIGHT)
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    # the previous history: HISTORY_LENGTH samples of the linear radiance at each pixel
    history = TEMPORAL_PIXEL.zeros(WIDTH * HEIGHT)
    history["sum"][:, :3] = (HISTORY_LENGTH * _linear(columns, rows)).reshape(-1, 3)
    history["moments"] = (0.25, 0.0625)
    history["length"] = HISTORY_LENGTH
    write_buffer(gpu_context, temporal._previous_history, 0, history)
    write_buffer(gpu_context, temporal._previous_gbuffer, 0, _gbuffer((0.0, 0.0)))
    temporal._fresh = False
    # this frame: one sample of what the previous frame showed where the motion vectors point, so the
    # clamp to its neighbourhood keeps the history as it is
    moved = _linear(columns + MOTION[0], rows + MOTION[1])
    frame = ACCUMULATED_PIXEL.zeros(WIDTH * HEIGHT)
    frame["sum"][:, :3] = moved.reshape(-1, 3)
    accumulation = storage_buffer(gpu_context, "frame", frame)
    gbuffer = storage_buffer(gpu_context, "G-buffer", _gbuffer(MOTION), read_back=True)
    temporal.add_frame(accumulation, gbuffer, samples=1, moving=True)
    records = temporal.records()
    # pixels all of whose taps fall inside the image
    inside = (columns + MOTION[0] >= 0) & (columns + MOTION[0] <= WIDTH - 1)
    inside &= (rows + MOTION[1] >= 0) & (rows + MOTION[1] <= HEIGHT - 1)
    image = temporal.image()
    np.testing.assert_allclose(image[inside], moved[inside], rtol=1e-5)
    assert (records["length"].reshape(HEIGHT, WIDTH)[inside] == HISTORY_LENGTH + 1).all()
    assert inside.sum() > WIDTH * HEIGHT // 2
    # the moments: the old ones weighted 4, this frame's (its demodulated luminance) 1
    luminance = (moved / ALBEDO) @ np.array([0.2126, 0.7152, 0.0722])
    expected_mean = (HISTORY_LENGTH * 0.25 + luminance) / (HISTORY_LENGTH + 1)
    np.testing.assert_allclose(
        records["moments"][:, 0].reshape(HEIGHT, WIDTH)[inside], expected_mean[inside], rtol=1e-5
    )


def test_a_tap_that_saw_another_object_is_rejected(gpu_context):
    # the same material, depth and normal everywhere; the left half was another object before
    temporal = TemporalAccumulation(gpu_context, WIDTH, HEIGHT)
    history = TEMPORAL_PIXEL.zeros(WIDTH * HEIGHT)
    history["sum"][:, :3] = HISTORY_LENGTH * ALBEDO
    history["length"] = HISTORY_LENGTH
    write_buffer(gpu_context, temporal._previous_history, 0, history)
    previous = _gbuffer((0.0, 0.0))
    left = (np.arange(WIDTH * HEIGHT) % WIDTH) < WIDTH // 2
    previous["object"][left] = 1
    write_buffer(gpu_context, temporal._previous_gbuffer, 0, previous)
    temporal._fresh = False
    frame = ACCUMULATED_PIXEL.zeros(WIDTH * HEIGHT)
    frame["sum"][:, :3] = ALBEDO
    accumulation = storage_buffer(gpu_context, "frame", frame)
    gbuffer = storage_buffer(gpu_context, "G-buffer", _gbuffer((0.0, 0.0)), read_back=True)
    temporal.add_frame(accumulation, gbuffer, samples=1, moving=True)
    np.testing.assert_array_equal(temporal.records()["length"], np.where(left, 1.0, HISTORY_LENGTH + 1))
