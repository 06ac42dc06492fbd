"""bench.traversal_ceiling times Embree on rays `pixel_centre_rays` makes in numpy: they must be the
rays our shipped camera_ray traces through the pixel centres."""

from __future__ import annotations

import numpy as np
import pytest

from bench.scenes import pixel_centre_rays
from wgputrace.scenes import scene_by_name
from wgputrace.testing.harness import frame_record, run_kernel

pytestmark = pytest.mark.gpu

# Not square, so that swapped axes or a flipped row order show.
WIDTH, HEIGHT = 7, 5
# float32 camera basis and normalize on the GPU against float64 then rounded in numpy
DIRECTION_ATOL = 1e-6

KERNEL = """
//! include "generated/camera.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let ray = camera_ray(vec2<u32>(i % frame.width, i / frame.width), vec2<f32>(0.5), LENS_CENTRE);
    return vec4<f32>(ray.direction, 0.0);
}
"""


def test_pixel_centre_rays_are_the_shipped_camera_rays(gpu_context):
    camera = scene_by_name("cornell").camera
    frame = frame_record()
    frame["width"], frame["height"] = WIDTH, HEIGHT
    camera.fill_frame(frame, WIDTH, HEIGHT)
    shipped = run_kernel(
        gpu_context,
        KERNEL,
        [],
        np.dtype((np.float32, 4)),
        WIDTH * HEIGHT,
        input_types=[],
        output_type="vec4<f32>",
        scene={"frame": frame},
    )[:, :3]
    origins, directions = pixel_centre_rays(camera, WIDTH, HEIGHT)
    np.testing.assert_array_equal(origins, np.broadcast_to(np.float32(camera.position), origins.shape))
    np.testing.assert_allclose(directions, shipped, rtol=0, atol=DIRECTION_ATOL)
