"""The viewer's picture on the GPU: guides against a brute-force ray cast, the a-trous filter
against a numpy oracle, its edge stops and fade, and the camera projection of the box overlay."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, default_scene, make_plane
from wgputrace.gpu.layout import ACCUMULATED_PIXEL
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.scene import Principled, Shape, Texture
from wgputrace.testing.oracles import brute_force_closest_hit, record_corners, t_tolerance
from wgputrace.view.banded import BandedRenderer
from wgputrace.view.display import (
    FILTER_ALBEDO_SIGMA,
    FILTER_DEPTH_SIGMA,
    FILTER_FADE_SPP,
    FILTER_NORMAL_POWER,
    FILTER_PASSES,
    Display,
    ViewSettings,
    filter_weight,
)
from wgputrace.view.layout import FILTER_ALBEDO_MIN, GUIDE_ALBEDO_ERROR, GUIDE_NORMAL_ERROR, View
from wgputrace.view.present import camera_clip_matrix

pytestmark = pytest.mark.gpu

WIDTH, HEIGHT = 48, 36
# float32 weights and sums over FILTER_PASSES passes of 25 taps, with float32 exp and pow (each
# within a few ulp), against the float64 oracle.
FILTER_RTOL = 1e-4
B3_SPLINE = np.array([0.375, 0.25, 0.0625])
# The debug views decode the packed guides in float32, the test in float64.
DECODE_ATOL = 1e-6


@pytest.fixture(scope="module")
def display():
    renderer = Renderer(default_scene(), WIDTH, HEIGHT, seed=1)
    banded = BandedRenderer(renderer)
    banded.restart(renderer.scene.camera)
    return Display(banded)


def guides_of(display: Display) -> dict[str, np.ndarray]:
    display.render(ViewSettings())  # traces the guides for the current camera
    return display.read_guides()


def set_mean(display: Display, mean: np.ndarray) -> None:
    """Make the accumulation hold one sample per pixel equal to `mean` (H, W, 3)."""
    pixels = ACCUMULATED_PIXEL.zeros(WIDTH * HEIGHT)
    pixels["sum"][:, :3] = mean.reshape(-1, 3)
    display.context.device.queue.write_buffer(display.banded.renderer.resources["accumulation"], 0, pixels)
    display.banded.samples_per_pixel, display.banded.rows_done = 1, 0


def shown(display: Display, settings: ViewSettings) -> np.ndarray:
    display.camera_changed()  # filter afresh: each test sets its own samples
    display.render(settings)
    return display.read_image()


def test_guides_are_the_first_hit_through_each_pixel_centre(gpu_context, display):
    guides = {name: values.reshape(WIDTH * HEIGHT, -1).squeeze() for name, values in guides_of(display).items()}
    renderer = display.banded.renderer
    camera = renderer.scene.camera
    right, up, forward = camera.image_plane(WIDTH, HEIGHT)
    x, y = np.meshgrid((np.arange(WIDTH) + 0.5) / WIDTH * 2 - 1, (np.arange(HEIGHT) + 0.5) / HEIGHT * 2 - 1)
    directions = forward + x[..., None] * right - y[..., None] * up
    directions = (directions / np.linalg.norm(directions, axis=-1, keepdims=True)).reshape(-1, 3)
    origins = np.broadcast_to(np.asarray(camera.position), directions.shape)
    corners = record_corners(renderer.records.triangles)
    t, triangle, ambiguous = brute_force_closest_hit(corners, origins, directions)
    hit = triangle != NO_TRIANGLE
    sure = hit & ~ambiguous
    assert sure.mean() > 0.9
    np.testing.assert_array_equal(guides["depth"][~hit], 0.0)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    expected = normals[triangle[sure]]
    expected *= -np.sign(np.sum(expected * directions[sure], axis=1))[:, None]  # the side facing the camera
    np.testing.assert_allclose(guides["normal"][sure], expected, atol=GUIDE_NORMAL_ERROR)
    cos = np.sum(expected * directions[sure], axis=1)
    tolerance = t_tolerance(t[sure], cos, origins[sure], corners[triangle[sure]])
    assert np.all(np.abs(guides["depth"][sure] - t[sure]) <= tolerance)
    materials = renderer.records.materials
    colors = materials["color"][renderer.records.triangles["material"][triangle[sure]]]
    np.testing.assert_allclose(guides["albedo"][sure], np.clip(colors, 0, 1), atol=GUIDE_ALBEDO_ERROR)
    assert np.all(guides["steps"][hit] > 0)


def atrous_oracle(mean: np.ndarray, guides: dict[str, np.ndarray], weight: float) -> np.ndarray:
    """The filter in float64: demodulate (the resolve kernel), FILTER_PASSES edge-stopped B3 passes
    (the a-trous kernel), remodulate and blend (the resolve kernel)."""
    albedo = np.maximum(guides["albedo"], FILTER_ALBEDO_MIN)
    normal, depth = guides["normal"], guides["depth"].astype(np.float64)
    hit = depth > 0
    demodulated = mean / albedo
    value = demodulated
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH]
    for k in range(FILTER_PASSES):
        step = 1 << k
        total, weights = np.zeros_like(value), np.zeros(value.shape[:2])
        for dy in range(-2, 3):
            for dx in range(-2, 3):
                ty, tx = ys + dy * step, xs + dx * step
                inside = (ty >= 0) & (ty < HEIGHT) & (tx >= 0) & (tx < WIDTH)
                ty, tx = np.clip(ty, 0, HEIGHT - 1), np.clip(tx, 0, WIDTH - 1)
                both = hit & hit[ty, tx]
                cos = np.maximum(np.sum(normal * normal[ty, tx], axis=-1), 0.0)
                stops = (
                    cos**FILTER_NORMAL_POWER
                    * np.exp(-np.abs(depth - depth[ty, tx]) / (FILTER_DEPTH_SIGMA * np.where(both, depth, 1) * step))
                    * np.exp(
                        -np.sum((guides["albedo"] - guides["albedo"][ty, tx]) ** 2, axis=-1) / FILTER_ALBEDO_SIGMA**2
                    )
                )
                edge = np.where(both, stops, np.where(hit != hit[ty, tx], 0.0, 1.0))
                w = B3_SPLINE[abs(dx)] * B3_SPLINE[abs(dy)] * edge * inside
                total += w[..., None] * value[ty, tx]
                weights += w
        value = np.where(weights[..., None] > 0, total / np.where(weights > 0, weights, 1)[..., None], value)
    return albedo * (demodulated + weight * (value - demodulated))


def test_filter_is_the_edge_avoiding_a_trous_filter(gpu_context, display, rng):
    guides = guides_of(display)
    mean = rng.exponential(1.0, (HEIGHT, WIDTH, 3)) * np.maximum(guides["albedo"], 0.05)
    set_mean(display, mean.astype(np.float32))
    filtered = shown(display, ViewSettings(filter_enabled=True))
    assert display.filter_weight == 1.0
    np.testing.assert_allclose(filtered, atrous_oracle(mean.astype(np.float32), guides, 1.0), rtol=FILTER_RTOL)


@pytest.fixture(scope="module")
def crease_display():
    """A floor meeting a wall at a right angle, both the same white, seen across the crease."""
    white = Diffuse("white", color=(0.7, 0.7, 0.7))
    scene = Scene(
        [
            make_plane((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (4.0, 4.0), white, "floor"),
            make_plane((0.0, 1.0, 1.0), (-np.pi / 2, 0.0, 0.0), (4.0, 2.0), white, "wall"),
            make_plane((0.0, 3.0, -1.0), (0.0, 0.0, 0.0), (0.5, 0.5), Emitter("lamp"), "lamp"),
        ],
        Camera.looking_at((0.0, 1.0, -2.0), (0.0, 0.5, 1.0), vfov_degrees=60.0),
    )
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=1))
    banded.restart(scene.camera)
    return Display(banded)


def test_filter_keeps_flat_lighting_flat_and_nothing_crosses_a_crease(gpu_context, crease_display):
    """Same albedo, continuous depth at the crease: only the normals tell floor from wall. Lit
    evenly, the picture stays as it is; with light on the wall only, none reaches the floor."""
    display = crease_display
    guides = guides_of(display)
    hit = guides["depth"] > 0
    wall = hit & (np.abs(guides["normal"][..., 2]) > 1 - GUIDE_NORMAL_ERROR)
    floor = hit & (np.abs(guides["normal"][..., 1]) > 1 - GUIDE_NORMAL_ERROR)
    assert wall.mean() > 0.2 and floor.mean() > 0.2 and np.all(wall | floor | ~hit)
    albedo = guides["albedo"]
    set_mean(display, (albedo * 2.0).astype(np.float32))
    np.testing.assert_allclose(shown(display, ViewSettings(filter_enabled=True)), albedo * 2.0, rtol=FILTER_RTOL)
    set_mean(display, (albedo * wall[..., None]).astype(np.float32))
    filtered = shown(display, ViewSettings(filter_enabled=True))
    assert np.all(filtered[floor] == 0.0)
    assert np.all(filtered[wall] > 0.0)


def test_filter_fades_out_and_leaves_the_converged_mean_untouched(gpu_context, display, rng):
    assert filter_weight(1) == 1.0 and filter_weight(FILTER_FADE_SPP) == 0.0
    assert filter_weight(4) > filter_weight(16) > filter_weight(64) > 0.0
    set_mean(display, rng.random((HEIGHT, WIDTH, 3), np.float32) * FILTER_FADE_SPP)
    display.banded.samples_per_pixel = FILTER_FADE_SPP
    plain = shown(display, ViewSettings())
    np.testing.assert_array_equal(shown(display, ViewSettings(filter_enabled=True)), plain)
    assert display.filter_weight == 0.0


def test_debug_views_show_the_guides(gpu_context, display):
    guides = guides_of(display)
    hit = guides["depth"] > 0
    normal = shown(display, ViewSettings(view=View.NORMAL))
    np.testing.assert_allclose(normal[hit], guides["normal"][hit] * 0.5 + 0.5, atol=DECODE_ATOL)
    np.testing.assert_allclose(shown(display, ViewSettings(view=View.ALBEDO)), guides["albedo"], atol=DECODE_ATOL)
    scale = 4.0
    depth = shown(display, ViewSettings(view=View.DEPTH, depth_scale=scale))
    np.testing.assert_allclose(depth[..., 0][hit], 1 - np.minimum(guides["depth"][hit] / scale, 1), rtol=1e-6)
    heat = shown(display, ViewSettings(view=View.HEAT))
    # more BVH steps, hotter: red minus blue grows with the step count
    order = np.argsort(guides["steps"][hit])
    warmth = (heat[..., 0] - heat[..., 2])[hit][order]
    assert warmth[-len(order) // 10 :].mean() > warmth[: len(order) // 10].mean()


def test_box_lines_project_where_the_camera_rays_go(rng):
    camera = default_scene().camera
    matrix = camera_clip_matrix(camera, WIDTH, HEIGHT, scene_size=2.0)
    right, up, forward = camera.image_plane(WIDTH, HEIGHT)
    ndc = rng.uniform(-1, 1, (100, 2))
    distance = rng.uniform(0.1, 10, 100)
    # a point on the ray through image-plane point (x, y), y up: camera_ray's direction with row y flipped
    points = camera.position + distance[:, None] * (forward + ndc[:, :1] * right + ndc[:, 1:] * up)
    clip = np.c_[points, np.ones(100)] @ matrix.T
    np.testing.assert_allclose(clip[:, :2] / clip[:, 3:], ndc, atol=1e-9)
    assert np.all((clip[:, 2] >= 0) & (clip[:, 2] <= clip[:, 3]))


# A quad filling the view of QUAD_CAMERA (|x|, |y| < 1.24 seen at z = 0), uv (0, 0) at its top-left corner.
QUAD_CAMERA = Camera.looking_at((0.0, 0.0, -3.0), (0.0, 0.0, 0.0), vfov_degrees=45.0)
QUAD_HALF = 2.0


def quad(z: float) -> np.ndarray:
    a, b, c, d = (
        (-QUAD_HALF, QUAD_HALF, z),
        (QUAD_HALF, QUAD_HALF, z),
        (QUAD_HALF, -QUAD_HALF, z),
        (-QUAD_HALF, -QUAD_HALF, z),
    )
    return np.array([[a, b, c], [a, c, d]], np.float32)


QUAD_UVS = np.array([[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]], np.float32)


def scene_display(shapes: list[Shape]) -> Display:
    banded = BandedRenderer(Renderer(Scene(shapes, QUAD_CAMERA), WIDTH, HEIGHT, seed=1))
    banded.restart(QUAD_CAMERA)
    return Display(banded)


def pixel_centre_uvs(z: float) -> np.ndarray:
    """Where each pixel centre's camera ray meets the quad at `z`, in its uv coordinates (H, W, 2)."""
    right, up, forward = QUAD_CAMERA.image_plane(WIDTH, HEIGHT)
    x, y = np.meshgrid((np.arange(WIDTH) + 0.5) / WIDTH * 2 - 1, (np.arange(HEIGHT) + 0.5) / HEIGHT * 2 - 1)
    directions = forward + x[..., None] * right - y[..., None] * up
    origin = np.asarray(QUAD_CAMERA.position, np.float64)
    points = origin + (z - origin[2]) / directions[..., 2:3] * directions
    return np.stack([points[..., 0] + QUAD_HALF, QUAD_HALF - points[..., 1]], axis=-1) / (2 * QUAD_HALF)


def test_the_albedo_guide_is_the_base_colour_texture_at_the_pixel_centre(gpu_context):
    """Texels affine in their centre's uv (R = u, G = v): bilinear lookups between texel centres
    (all the view sees) give that affine function, so the guide is (u, v, B) at the pixel centre."""
    size = 8
    centres = (np.arange(size) + 0.5) / size
    texels = np.zeros((size, size, 3), np.float32)
    texels[..., 0], texels[..., 1], texels[..., 2] = centres[None, :], centres[:, None], 0.25
    material = Principled("textured", base_color=(1, 1, 1), base_color_texture=Texture(texels, srgb=False))
    display = scene_display([Shape("quad", quad(0.0), material, uvs=QUAD_UVS)])
    uvs = pixel_centre_uvs(0.0)
    assert uvs.min() > centres[0] and uvs.max() < centres[-1]
    expected = np.concatenate([uvs, np.full((HEIGHT, WIDTH, 1), 0.25)], axis=-1)
    np.testing.assert_allclose(guides_of(display)["albedo"], expected, atol=GUIDE_ALBEDO_ERROR)


def test_the_normal_guide_is_the_shading_normal(gpu_context):
    tilted = np.array([0.3, 0.0, -1.0]) / np.linalg.norm([0.3, 0.0, -1.0])
    normals = np.broadcast_to(tilted, (2, 3, 3)).astype(np.float32)
    display = scene_display([Shape("quad", quad(0.0), Diffuse("white"), normals=normals)])
    guides = guides_of(display)
    np.testing.assert_allclose(guides["normal"], np.broadcast_to(tilted, (HEIGHT, WIDTH, 3)), atol=GUIDE_NORMAL_ERROR)


def test_guides_see_through_cut_out_texels_and_follow_the_renderer_to_its_see_through_kernel(gpu_context):
    """A screen before a wall, its texture fully cut out: while OPAQUE the guides show the screen;
    made MASK on the live renderer, they show the wall as a display of the wall alone does."""
    wall = Shape("wall", quad(0.0), Diffuse("wall", color=(0.2, 0.6, 0.4)))
    clear = Texture(np.zeros((2, 2, 4), np.uint8))
    screen_material = Principled("screen", base_color=(1, 1, 1), base_color_texture=clear)
    display = scene_display([Shape("screen", quad(-1.0), screen_material, uvs=QUAD_UVS), wall])
    opaque = guides_of(display)
    behind = guides_of(scene_display([wall]))
    assert np.all(opaque["depth"] < behind["depth"])
    screen_material.alpha_mode = "MASK"
    display.banded.renderer.update()
    cut = guides_of(display)
    for name in ("normal", "albedo", "depth"):
        np.testing.assert_allclose(cut[name], behind[name], atol=1e-6, err_msg=name)
