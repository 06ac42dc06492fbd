"""The camera kinds in the renderer: closed forms (a thin lens images its plane in focus sharply and
blurs another by its circle of confusion; a 360 render of a constant environment is constant, one
bright texel of a map lands on that texel, and a map alone renders as itself), bidirectional path
tracing's weights and images under each kind, and a change of kind as an edit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import wgputrace as wt
from wgputrace.scene import CameraWarning
from wgputrace.scene.lights.environment import Environment
from wgputrace.testing.camera_rays import camera_rays
from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.references import assert_same_expectation, batches_of
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SEED = 11
# Float32 arithmetic along a path and in the Kahan sum: a few roundings of relative size 2^-24.
EXACT_RTOL = 1e-5
FAMILY_SIGNIFICANCE = 1e-3

# --- the thin lens: a wall emitting right of a vertical edge, black left of it -------------------
LENS = {"vfov_degrees": 20.0, "aperture_radius": 0.6, "focus_distance": 2.0}
EDGE_SIZE = (24, 4)
# The edge's column, and where in it the edge falls (its pixel's fraction on the emitting side).
EDGE_COLUMN, EDGE_FRACTION = 11, 0.3
EDGE_SPP = 64
# independent batches of EDGE_SPP for the blur's standard errors
BLUR_BATCHES = 16
# The wall out of focus: at half the focus distance, where the blur circle is this many pixels wide
# (its radius on the image plane is aperture_radius |1 / focus - 1 / depth|).
DEFOCUSED_DEPTH = 1.0


def thin_lens() -> wt.ThinLensCamera:
    return wt.ThinLensCamera((0, 0, 0), (0, 0, 1), (0, 1, 0), **LENS)


def pixel_width(camera: wt.Camera, height: int) -> float:
    """A pixel's width on the image plane at distance 1 (square pixels)."""
    return 2.0 * math.tan(math.radians(camera.vfov_degrees) / 2.0) / height


def edge_wall(camera: wt.Camera, depth: float) -> wt.Scene:
    """A wall at `depth` along the camera's axis whose edge the pinhole images EDGE_FRACTION of
    EDGE_COLUMN from that column's right side: right of it a lamp of radiance 1, left of it black."""
    width, height = EDGE_SIZE
    right, up, forward = camera.basis()
    edge = (EDGE_COLUMN + 1.0 - EDGE_FRACTION - width / 2.0) * pixel_width(camera, height) * depth
    reach = 10.0 * depth  # far beyond what the image and its blur see

    def quad(left: float, right_edge: float) -> np.ndarray:
        corners = [
            depth * forward + a * right + b * up
            for a, b in ((left, -reach), (right_edge, -reach), (right_edge, reach), (left, reach))
        ]
        return np.array([[corners[0], corners[1], corners[2]], [corners[0], corners[2], corners[3]]])

    lamp = wt.Shape("lamp", quad(edge, reach), wt.Emitter("lamp", color=(1, 1, 1), emittance=1.0))
    dark = wt.Shape("dark", quad(-reach, edge), wt.Diffuse("black", color=(0, 0, 0)))
    return wt.Scene([lamp, dark], camera)


def column_means(scene: wt.Scene, spp: int) -> np.ndarray:
    image = wt.render(scene, spp, *EDGE_SIZE, seed=SEED, max_depth=1)
    return image[..., 1].mean(axis=0)


def test_a_thin_lens_images_its_plane_in_focus_within_one_pixel(gpu_context):
    """Every ray through a pixel point meets the plane in focus where the pinhole's does: the edge
    stays inside its column, the columns beside it all dark or all lit, sample for sample."""
    columns = column_means(edge_wall(thin_lens(), LENS["focus_distance"]), EDGE_SPP)
    np.testing.assert_array_equal(columns[:EDGE_COLUMN], 0.0)
    np.testing.assert_allclose(columns[EDGE_COLUMN + 1 :], 1.0, rtol=EXACT_RTOL)
    assert columns[EDGE_COLUMN] == pytest.approx(EDGE_FRACTION, abs=0.02)


def disc_side_fraction(offset: np.ndarray, radius: float) -> np.ndarray:
    """The fraction of a disc of `radius` lying beyond a line at `offset` from its centre."""
    s = np.clip(offset / radius, -1.0, 1.0)
    return (np.arccos(s) - s * np.sqrt(1.0 - s * s)) / math.pi


def test_a_thin_lens_blurs_a_plane_out_of_focus_by_its_circle_of_confusion(gpu_context):
    """The wall at DEFOCUSED_DEPTH: each image point sees the wall through the lens as a disc of
    radius aperture_radius |1 / focus_distance - 1 / depth| (image plane at distance 1), uniformly;
    a column's expectation is the lit part of that disc, averaged over the column's width. Columns
    the blur does not reach are exact; the others are t-tested with the spread of independent
    batches (a 3% smaller aperture fails)."""
    camera = thin_lens()
    width, height = EDGE_SIZE
    renderer = wt.Renderer(edge_wall(camera, DEFOCUSED_DEPTH), width, height, seed=SEED, max_depth=1)
    rows = batches_of(renderer, BLUR_BATCHES, EDGE_SPP).batches[..., 1].mean(axis=1)
    columns = Estimate.from_batches(rows[:, None, :, None])
    radius = LENS["aperture_radius"] * abs(1.0 / LENS["focus_distance"] - 1.0 / DEFOCUSED_DEPTH)
    radius_pixels = radius / pixel_width(camera, height)
    assert 2.0 < radius_pixels < EDGE_COLUMN - 2, "the blur must be wider than a pixel and stay in the image"
    points = (np.arange(width)[:, None] + (np.arange(256) + 0.5) / 256).ravel()  # within each column
    edge = EDGE_COLUMN + 1.0 - EDGE_FRACTION
    expected = disc_side_fraction(edge - points, radius_pixels).reshape(width, -1).mean(axis=1)
    mean = columns.mean[0, :, 0]
    sharp = (expected == 0.0) | (expected == 1.0)
    np.testing.assert_allclose(mean[sharp], expected[sharp], rtol=EXACT_RTOL)
    # one sample's worth of the column's samples as a floor: a column the blur just reaches may
    # have had no lit sample yet in any batch
    samples = BLUR_BATCHES * EDGE_SPP * height
    error = np.sqrt(columns.variance[0, :, 0] + samples**-2.0)
    limit = stats.t.isf(sidak(FAMILY_SIGNIFICANCE, int((~sharp).sum())) / 2.0, columns.dof)
    np.testing.assert_array_less(np.abs(mean - expected)[~sharp], limit * error[~sharp])


# --- the equirectangular camera -----------------------------------------------------------------
PANORAMA = (32, 16)
CONSTANT_RADIANCE = (0.8, 0.9, 1.1)


def panorama(environment: Environment, shapes: list[wt.Shape], camera: wt.Sensor | None = None) -> wt.Scene:
    scene = wt.Scene(shapes, camera or wt.EquirectangularCamera())
    scene.environment = environment
    return scene


def speck() -> wt.Shape:
    """A black triangle far below (a scene needs one): only the bottom row, around the pole, sees it."""
    corners = np.array([[[-1.0, -100.0, -1.0], [1.0, -100.0, -1.0], [0.0, -100.0, 1.0]]])
    return wt.Shape("speck", corners, wt.Diffuse("black", color=(0, 0, 0)))


def test_a_360_render_of_a_constant_environment_is_constant(gpu_context):
    """A white diffuse sphere (albedo 1) beside the camera: each BSDF sample leaves the convex
    sphere for the sky with weight 1, so every pixel, the poles and the seam included, is the sky's
    radiance, sample for sample."""
    sphere = wt.make_icosphere((0.0, 0.0, 2.0), (0, 0, 0), 0.8, 3, wt.Diffuse("white", color=(1, 1, 1)), "sphere")
    scene = panorama(Environment(radiance=CONSTANT_RADIANCE), [sphere])
    image = wt.render(scene, 4, *PANORAMA, seed=SEED, integrator="bsdf")
    np.testing.assert_allclose(image, np.broadcast_to(CONSTANT_RADIANCE, image.shape), rtol=EXACT_RTOL)


ONE_TEXEL = (5, 11)  # row, column of a PANORAMA-sized map


@pytest.mark.parametrize("turn_degrees", [0.0, 30.0])
def test_one_bright_texel_lands_on_its_pixel(gpu_context, turn_degrees):
    """A map black but for one texel, seen by a camera of the map's size: the brightest pixel is that
    texel's, and only its bilinear neighbours are lit. Turning the map about +y and the camera with
    it changes nothing."""
    texels = np.zeros((PANORAMA[1], PANORAMA[0], 3), np.float32)
    texels[ONE_TEXEL] = 100.0
    turned = math.radians(turn_degrees)
    camera = wt.EquirectangularCamera(forward=(math.sin(turned), 0.0, math.cos(turned)))
    scene = panorama(Environment(texels=texels, rotation_degrees=turn_degrees), [speck()], camera)
    image = wt.render(scene, 16, *PANORAMA, seed=SEED, max_depth=1)[..., 0]
    assert np.unravel_index(np.argmax(image), image.shape) == ONE_TEXEL
    row, column = ONE_TEXEL
    neighbours = np.zeros_like(image, bool)
    neighbours[row - 1 : row + 2, column - 1 : column + 2] = True
    assert not image[~neighbours].any()


def test_a_map_alone_renders_as_itself(gpu_context):
    """Each pixel's expectation is the map's bilinear radiance averaged over the pixel's directions
    (the numpy Environment.lookup over a grid of points of the pixel, through the camera's numpy
    rays); a smooth sky makes the grid's error negligible. The bottom row, which sees the speck around
    the pole, is left out."""
    environment = Environment(texels=_smooth_sky())
    width, height = PANORAMA
    image = wt.render(panorama(environment, [speck()]), 64, width, height, seed=SEED, max_depth=1)
    grid = (np.arange(8) + 0.5) / 8
    jitter = np.stack(np.meshgrid(grid, grid), axis=-1).reshape(-1, 2)
    pixels = np.stack(np.meshgrid(np.arange(width), np.arange(height)), axis=-1).reshape(-1, 1, 2)
    points = np.broadcast_to(pixels, (len(pixels), len(jitter), 2)).reshape(-1, 2)
    jitters = np.broadcast_to(jitter, (len(pixels), len(jitter), 2)).reshape(-1, 2)
    _, directions = camera_rays(wt.EquirectangularCamera(), width, height, points, jitters, jitters)
    expected = environment.lookup(directions).reshape(height, width, len(jitter), 3).mean(axis=2)
    np.testing.assert_allclose(image[:-1], expected[:-1], rtol=2e-3)


def _smooth_sky() -> np.ndarray:
    """A 64x32 map varying smoothly in every direction and colour."""
    directions = np.stack(np.meshgrid(np.linspace(0, 1, 64), np.linspace(0, 1, 32)), axis=-1)
    u, v = directions[..., 0], directions[..., 1]
    return np.stack(
        [1.0 + 0.5 * np.sin(2 * math.pi * u), 1.0 + 0.5 * np.cos(math.pi * v), 1.2 + 0.3 * u * v], -1
    ).astype(np.float32)


def test_an_equirectangular_image_not_two_by_one_warns(gpu_context):
    scene = panorama(Environment(radiance=1.0), [speck()])
    with pytest.warns(CameraWarning, match="a 16x16 image is not 2:1"):
        wt.Renderer(scene, 16, 16)


# --- every kind under bidirectional path tracing ----------------------------------------------------
KIND_SIZE = 16


def kinds_of(camera: wt.Camera) -> dict[str, wt.Sensor]:
    """The other kinds at `camera`'s pose: a thin lens focused mid-box, an orthographic view of the
    box's width, and the 360 camera."""
    pose = (camera.position, camera.forward, camera.up)
    return {
        "thin_lens": wt.ThinLensCamera(*pose, camera.vfov_degrees, aperture_radius=0.05, focus_distance=1.3),
        "orthographic": wt.OrthographicCamera(*pose, view_height=1.1),
        "equirectangular": wt.EquirectangularCamera(*pose),
    }


def box_seen_by(kind: str) -> wt.Scene:
    """The Cornell box; the 360 camera stands inside it."""
    scene = wt.default_scene()
    scene.camera = kinds_of(scene.camera)[kind]
    if kind == "equirectangular":
        scene.camera = scene.camera.posed((0.0, 0.45, -0.35), (0, 0, 1), (0, 1, 0))
    return scene


def size_of(kind: str) -> tuple[int, int]:
    return (2 * KIND_SIZE, KIND_SIZE) if kind == "equirectangular" else (KIND_SIZE, KIND_SIZE)


@pytest.mark.parametrize("kind", ["thin_lens", "orthographic", "equirectangular"])
def test_bdpt_weights_sum_to_one_under_every_camera_kind(gpu_context, kind):
    """Light tracing weighs its connection to the camera with the kind's camera_connection density,
    the camera subpath its rays' with camera_ray_density: the two must agree for every path."""
    renderer = wt.Renderer(
        box_seen_by(kind),
        *size_of(kind),
        seed=SEED,
        max_depth=6,
        integrator="bdpt",
        shader_overrides={"BDPT_CHECK_WEIGHT_SUMS": True},
    )
    renderer.render(1)
    deviation, paths, strategies = np.moveaxis(renderer.image(), -1, 0)
    assert renderer.nonfinite_samples == 0
    assert deviation.max() < 1e-4, f"{kind}: weights sum to 1 +- {deviation.max():.3g}"
    assert paths.sum() > KIND_SIZE * KIND_SIZE / 4 and strategies.sum() >= 2 * paths.sum()


BATCHES, SPP = 16, 16
BLOCKS = (4, KIND_SIZE)


def batches(kind: str, integrator: str) -> Estimate:
    renderer = wt.Renderer(box_seen_by(kind), *size_of(kind), seed=SEED, max_depth=5, integrator=integrator)
    rendered = batches_of(renderer, BATCHES, SPP)
    assert rendered.nonfinite_samples == 0
    return rendered.estimate


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["thin_lens", "orthographic", "equirectangular"])
def test_bdpt_matches_the_path_tracer_under_every_camera_kind(gpu_context, failure_dir, kind):
    """Light tracing's splats through a lens, from a rectangle of parallel rays and onto the sphere of
    directions converge to the path tracer's picture, block by block (Welch's t-test)."""
    mis, bdpt = batches(kind, "mis"), batches(kind, "bdpt")
    width, height = size_of(kind)
    tests = sum((width // block) * (height // block) for block in BLOCKS) * 3 * 3
    assert_same_expectation(
        f"bdpt_{kind}",
        bdpt,
        mis,
        mis.mean,
        0.0,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=sidak(FAMILY_SIGNIFICANCE, tests),
    )


def test_changing_the_camera_kind_is_an_edit_like_any_other(gpu_context):
    """The new kind compiles a new kernel; the picture is a fresh renderer's, bit for bit."""
    scene = wt.default_scene()
    renderer = wt.Renderer(scene, KIND_SIZE, KIND_SIZE, seed=SEED)
    renderer.render(2)
    pinhole = renderer.image()
    scene.camera = kinds_of(scene.camera)["thin_lens"]
    renderer.render(2)
    assert "ThinLensCamera" in renderer.variant.label
    np.testing.assert_array_equal(renderer.image(), wt.render(scene, 2, KIND_SIZE, KIND_SIZE, seed=SEED))
    assert not np.array_equal(renderer.image(), pinhole)
