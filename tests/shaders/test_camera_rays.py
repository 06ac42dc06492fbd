"""Every camera kind's shipped WGSL against its numpy model (wgputrace.testing.camera_rays), and light
tracing's way back to the camera (`camera_connection`) against the rays: a point on a camera ray
connects back to that ray's pixel, from the ray's origin, with the density `camera_ray_density`
gives the ray, which is the kind's closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, EquirectangularCamera, OrthographicCamera, ThinLensCamera
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.testing.camera_rays import camera_rays, frame_of
from wgputrace.testing.harness import run_per_case

pytestmark = pytest.mark.gpu

# Not square, so that swapped axes or a flipped row order show; the equirectangular image is 2:1.
SIZES = {Camera: (7, 5), ThinLensCamera: (7, 5), OrthographicCamera: (7, 5), EquirectangularCamera: (10, 5)}
# Tilted poses, so that no basis vector is an axis.
POSITION, FORWARD, UP = (0.3, -0.2, 1.0), (0.2, -0.1, 1.0), (0.1, 1.0, 0.05)
CAMERAS = {
    "pinhole": Camera(POSITION, FORWARD, UP, 50.0),
    "thin_lens": ThinLensCamera(POSITION, FORWARD, UP, 50.0, aperture_radius=0.2, focus_distance=2.5),
    "orthographic": OrthographicCamera(POSITION, FORWARD, UP, view_height=1.7),
    "equirectangular": EquirectangularCamera(POSITION, FORWARD, UP),
}
CASES = 64
# float32 basis vectors, trigonometry and normalisation against float64
ATOL = 2e-6
DENSITY_RTOL = 1e-4


def cases(rng, width: int, height: int) -> dict[str, np.ndarray]:
    pixels = np.stack([rng.integers(0, width, CASES), rng.integers(0, height, CASES)], axis=1)
    # away from the pixel's edges, where float32 may put a point into the neighbour
    return {
        "pixel": pixels.astype(np.float64),
        "jitter": rng.uniform(0.05, 0.95, (CASES, 2)),
        "lens": rng.random((CASES, 2)),
    }


def run(gpu_context, camera, arguments: dict[str, np.ndarray], body: str) -> np.ndarray:
    width, height = SIZES[type(camera)]
    return run_per_case(
        gpu_context,
        ["generated/camera.wgsl"],
        arguments,
        "    let ray = camera_ray(vec2<u32>(pixel), jitter, lens);\n" + body,
        scene={"frame": frame_of(camera, width, height)},
        variant=KernelVariant(SceneFeatures(camera=camera.kind)),
    )


@pytest.mark.parametrize("name", CAMERAS)
def test_camera_ray_is_the_kinds_numpy_model(gpu_context, rng, name):
    camera = CAMERAS[name]
    width, height = SIZES[type(camera)]
    arguments = cases(rng, width, height)
    origins = run(gpu_context, camera, arguments, "    return vec4<f32>(ray.origin, 0.0);")[:, :3]
    directions = run(gpu_context, camera, arguments, "    return vec4<f32>(ray.direction, 0.0);")[:, :3]
    expected_origins, expected_directions = camera_rays(
        camera, width, height, arguments["pixel"].astype(int), arguments["jitter"], arguments["lens"]
    )
    np.testing.assert_allclose(origins, expected_origins, atol=ATOL)
    np.testing.assert_allclose(directions, expected_directions, atol=ATOL)


def density(camera, width: int, height: int, direction: np.ndarray) -> np.ndarray:
    """The kind's closed-form density of camera rays along `direction` (n, 3), over the whole image."""
    frame = frame_of(camera, width, height)
    right, up, forward = (frame[f"camera_{name}"][0].astype(np.float64) for name in ("right", "up", "forward"))
    area = 4.0 * np.linalg.norm(right) * np.linalg.norm(up)
    if isinstance(camera, OrthographicCamera):
        return np.full(len(direction), 1.0 / area)
    if isinstance(camera, EquirectangularCamera):
        return 1.0 / (2.0 * math.pi**2 * np.sqrt(1.0 - (direction @ up) ** 2))
    return 1.0 / (area * (direction @ forward) ** 3)


@pytest.mark.parametrize("name", CAMERAS)
def test_a_point_on_a_camera_ray_connects_back_to_it(gpu_context, rng, name):
    camera = CAMERAS[name]
    width, height = SIZES[type(camera)]
    arguments = cases(rng, width, height) | {"t": rng.uniform(0.5, 4.0, CASES)}
    connected = """    let camera = camera_connection(ray.origin + t * ray.direction, lens);
"""
    found = run(
        gpu_context,
        camera,
        arguments,
        connected
        + "    return vec4<f32>(f32(camera.pixel), camera.pdf, camera_ray_density(ray), select(0.0, 1.0, camera.seen));",
    )
    moved = run(gpu_context, camera, arguments, connected + "    return vec4<f32>(camera.position - ray.origin, 0.0);")
    pixels = arguments["pixel"].astype(int)
    assert found[:, 3].all(), "a point on a camera ray is unseen"
    np.testing.assert_array_equal(found[:, 0], pixels[:, 1] * width + pixels[:, 0])
    np.testing.assert_allclose(moved[:, :3], 0.0, atol=1e-5)
    _, directions = camera_rays(camera, width, height, pixels, arguments["jitter"], arguments["lens"])
    expected = density(camera, width, height, directions)
    np.testing.assert_allclose(found[:, 2], expected, rtol=DENSITY_RTOL)
    np.testing.assert_allclose(found[:, 1], expected, rtol=DENSITY_RTOL)


@pytest.mark.parametrize("name", CAMERAS)
def test_points_outside_the_view_are_unseen(gpu_context, name):
    camera = CAMERAS[name]
    if isinstance(camera, EquirectangularCamera):
        # every direction is in its image but straight up and down, where the density is infinite
        up = np.asarray(camera.basis()[1])
        points = np.asarray(POSITION) + np.stack([up, -up])
    else:
        right, _, forward = camera.basis()
        points = np.asarray(POSITION) + np.stack([-forward, 100.0 * right + forward])
    arguments = {"p": points, "lens": np.full((len(points), 2), 0.5)}
    seen = run_per_case(
        gpu_context,
        ["generated/camera.wgsl"],
        arguments,
        "    return vec4<f32>(select(0.0, 1.0, camera_connection(p, lens).seen));",
        scene={"frame": frame_of(camera, *SIZES[type(camera)])},
        variant=KernelVariant(SceneFeatures(camera=camera.kind)),
    )
    assert not seen[:, 0].any()
