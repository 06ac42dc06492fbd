"""The denoiser's guides the path tracer accumulates (WGSL `accumulate_guides`): against a
brute-force cast through sub-pixel positions on the Cornell box, through a glass pane by Fresnel's
odds, through the glass scene's sphere; image() unchanged by them; nothing of them compiled or
allocated without them; the viewer's band-of-rows kernel with and without them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Glass, Renderer, Scene, default_scene, make_box
from wgputrace.gpu.buffers import read_buffer
from wgputrace.gpu.layout import ACCUMULATED_PIXEL
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.scenes import BUILTIN_SCENES
from wgputrace.testing.oracles import brute_force_closest_hit, fresnel_dielectric, record_corners, triangle_normals
from wgputrace.view.banded import BandedRenderer

pytestmark = pytest.mark.gpu

WIDTH, HEIGHT = 40, 30
SPP = 8
SEED = 5
# Sub-pixel positions per axis of the brute-force cast, pixel edges included: a pixel whose rays
# all meet one material on one plane sees nothing else (no feature here is a third of a pixel).
SUBPIXEL_STEPS = 4
# A mean of SPP equal float32 values (Kahan sums), and face normals of one plane computed from
# different triangles' float32 corners.
MEAN_ATOL = 1e-6
NORMAL_ATOL = 1e-5
# The pane's estimate of Fresnel's odds lies within this many standard deviations of them.
Z_LIMIT = 5.0


def camera_rays(renderer: Renderer, offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions) of shape (H, W, len(offsets), 3): WGSL `camera_ray`
    through each pixel at each (x, y) offset in [0, 1]^2."""
    right, up, forward = renderer.scene.camera.image_plane(renderer.width, renderer.height)
    x = (np.arange(renderer.width)[None, :, None] + offsets[None, None, :, 0]) / renderer.width * 2 - 1
    y = (np.arange(renderer.height)[:, None, None] + offsets[None, None, :, 1]) / renderer.height * 2 - 1
    directions = forward + x[..., None] * right - y[..., None] * up
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    return np.broadcast_to(np.asarray(renderer.scene.camera.position), directions.shape), directions


def first_hits(renderer: Renderer, subpixel_steps: int = SUBPIXEL_STEPS) -> dict[str, np.ndarray]:
    """Per pixel and sub-pixel ray (H, W, rays): the triangle hit first (NO_TRIANGLE: none), its
    material's record index (-1: none), its normal facing the ray, whether rounding could pick
    another, and the ray's direction."""
    steps = np.linspace(0.0, 1.0, subpixel_steps)
    offsets = np.stack(np.meshgrid(steps, steps), axis=-1).reshape(-1, 2)
    origins, directions = camera_rays(renderer, offsets)
    shape = directions.shape[:-1]
    corners = record_corners(renderer.records.triangles)
    _, triangle, ambiguous = brute_force_closest_hit(corners, origins.reshape(-1, 3), directions.reshape(-1, 3))
    hit = triangle != NO_TRIANGLE
    normal = np.zeros(directions.shape).reshape(-1, 3)
    normal[hit] = triangle_normals(corners[triangle[hit]])
    normal *= -np.sign(np.sum(normal * directions.reshape(-1, 3), axis=1))[:, None]
    material = np.where(hit, renderer.records.triangles["material"][np.where(hit, triangle, 0)], -1)
    return {
        "triangle": triangle.reshape(shape),
        "material": material.reshape(shape),
        "normal": normal.reshape(*shape, 3),
        "ambiguous": ambiguous.reshape(shape),
        "direction": directions,
    }


def seen_entirely(hits: dict[str, np.ndarray]) -> np.ndarray:
    """(H, W): pixels whose rays all meet one material on one plane (or all miss), unambiguously."""
    same_material = np.all(hits["material"] == hits["material"][..., :1], axis=-1)
    same_plane = np.all(np.abs(hits["normal"] - hits["normal"][..., :1, :]) < NORMAL_ATOL, axis=(-2, -1))
    return same_material & same_plane & ~hits["ambiguous"].any(axis=-1)


@pytest.fixture(scope="module")
def cornell():
    """The Cornell box with guides, and its image without them: the same seed and samples."""
    plain = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED)
    plain.render(SPP)
    guided = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED, guides=True)
    guided.render(SPP)
    return guided, plain.image()


def test_cornell_guides_are_the_first_hit_where_a_pixel_sees_one_surface(cornell):
    renderer, _ = cornell
    guides = renderer.guides()
    hits = first_hits(renderer)
    pure = seen_entirely(hits)
    assert pure.mean() > 0.6
    seen = hits["material"][pure, 0]
    hit = seen >= 0
    colors = np.zeros((len(seen), 3))
    colors[hit] = renderer.records.materials["color"][seen[hit]]
    # emitters' radiance clamped to [0, 1]; zero where the rays escape
    np.testing.assert_allclose(guides["albedo"][pure], np.clip(colors, 0.0, 1.0), atol=MEAN_ATOL)
    np.testing.assert_allclose(guides["normal"][pure], hits["normal"][pure, 0], atol=NORMAL_ATOL)
    assert (colors.max(axis=1) > 1).any(), "the lamp (radiance above 1) should fill some pixels"


def test_guides_leave_the_image_unchanged_and_are_finite(cornell):
    renderer, plain_image = cornell
    assert renderer.image().tobytes() == plain_image.tobytes()
    guides = renderer.guides()
    for name, low in (("albedo", 0.0), ("normal", -1.0)):
        values = guides[name]
        assert values.dtype == np.float32 and values.shape == (HEIGHT, WIDTH, 3)
        assert np.all(np.isfinite(values)) and values.min() >= low and values.max() <= 1.0


WALL_COLOR = (0.8, 0.5, 0.2)
PANE_IOR = 1.5


def pane_scene() -> Scene:
    """A clear glass pane facing the camera in front of a diffuse wall, with nothing behind the
    camera: a sample reflected by the pane escapes, one transmitted ends on the wall."""
    wall = make_box((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), (20.0, 20.0, 0.1), Diffuse("wall", color=WALL_COLOR))
    pane = make_box((0.0, 0.0, 1.5), (0.0, 0.0, 0.0), (0.5, 0.5, 0.05), Glass("pane", ior=PANE_IOR))
    return Scene([wall, pane], Camera((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), vfov_degrees=30.0))


def seen_kind(renderer: Renderer, hits: dict[str, np.ndarray]) -> np.ndarray:
    """(H, W): the material kind the pixel's first sub-pixel ray meets (0: none)."""
    kinds = renderer.records.materials["kind"][np.maximum(hits["material"][..., 0], 0)]
    return np.where(hits["material"][..., 0] >= 0, kinds, 0)


def test_guides_behind_a_glass_pane_are_the_wall_by_fresnel_odds():
    renderer = Renderer(pane_scene(), WIDTH, HEIGHT, seed=SEED, guides=True)
    renderer.render(SPP)
    guides = renderer.guides()
    hits = first_hits(renderer)
    pure = seen_entirely(hits)
    wall_color = np.asarray(WALL_COLOR, np.float32)
    on_pane = pure & (seen_kind(renderer, hits) == Glass.kind)
    # away from the pane's edges, so that every refracted ray leaves through its back face
    inside = on_pane.copy()
    inside[1:-1, 1:-1] &= on_pane[:-2, 1:-1] & on_pane[2:, 1:-1] & on_pane[1:-1, :-2] & on_pane[1:-1, 2:]
    inside[[0, -1], :] = inside[:, [0, -1]] = False
    assert inside.sum() > 50
    on_wall = pure & ~on_pane
    assert on_wall.sum() > 50
    np.testing.assert_allclose(
        guides["albedo"][on_wall], np.broadcast_to(wall_color, (on_wall.sum(), 3)), atol=MEAN_ATOL
    )

    # every sample sees the wall's albedo and normal through the pane, or (reflected) escapes: zero
    fraction = guides["albedo"][inside] / wall_color
    np.testing.assert_allclose(fraction, np.broadcast_to(fraction[:, :1], fraction.shape), atol=MEAN_ATOL)
    np.testing.assert_allclose(fraction * SPP, np.round(fraction * SPP), atol=SPP * MEAN_ATOL)
    wall_normal = np.array([0.0, 0.0, -1.0])
    np.testing.assert_allclose(guides["normal"][inside], fraction[:, :1] * wall_normal, atol=MEAN_ATOL)
    # through the pane's two faces and any number of round trips inside it: T^2 / (1 - R^2)
    cos = np.abs(hits["direction"][inside].mean(axis=1)[:, 2])
    reflectance = fresnel_dielectric(cos, 1.0, PANE_IOR)
    odds = (1 - reflectance) / (1 + reflectance)
    sigma = np.sqrt(np.sum(odds * (1 - odds) / SPP)) / len(odds)
    assert abs(fraction[:, 0].mean() - odds.mean()) <= Z_LIMIT * sigma


def test_guides_see_through_the_glass_scene_sphere():
    renderer = Renderer(BUILTIN_SCENES["glass_grazing"](), WIDTH, HEIGHT, seed=SEED, guides=True)
    renderer.render(SPP)
    guides = renderer.guides()
    # a pixel whose corners all meet the sphere lies on it (its outline is convex): 4 rays suffice
    hits = first_hits(renderer, subpixel_steps=2)
    behind_glass = seen_entirely(hits) & (seen_kind(renderer, hits) == Glass.kind)
    assert behind_glass.sum() > 20
    # what the room's walls show through the glass (their clamped radiance), never zero, and not
    # the glass's own colour, which a first-hit guide would show
    albedo = guides["albedo"][behind_glass]
    assert np.all(albedo.max(axis=-1) > 0)
    glass_color = renderer.records.materials["color"][hits["material"][behind_glass, 0]]
    assert np.mean(np.all(np.abs(albedo - glass_color) < MEAN_ATOL, axis=-1)) < 0.5
    assert np.all(np.isfinite(guides["albedo"])) and np.all(np.isfinite(guides["normal"]))


def test_a_renderer_without_guides_compiles_and_allocates_none(cornell):
    renderer = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED)
    source = renderer.kernel.source.text
    assert "guide_sums" not in source and "guide_albedo" not in source
    assert "guide sums" not in renderer.gpu_image_bytes
    with pytest.raises(ValueError, match="guides are off"):
        renderer.guides()
    guided, _ = cornell
    assert "guide_sums" in guided.kernel.source.text
    assert guided.gpu_image_bytes["guide sums"] == 2 * WIDTH * HEIGHT * ACCUMULATED_PIXEL.size


def sums(renderer: Renderer, binding: str, per_pixel: int) -> bytes:
    """The raw Kahan sums a pixels-group binding holds (accumulation: 1 per pixel, guide_sums: 2)."""
    count = per_pixel * renderer.width * renderer.height
    return read_buffer(renderer.context, renderer.resources[binding], ACCUMULATED_PIXEL.dtype, count).tobytes()


def test_switching_guides_restarts_and_the_viewers_rows_kernel_follows(cornell):
    guided, _ = cornell
    renderer = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED)
    banded = BandedRenderer(renderer)
    banded.add_passes(1)
    renderer.guides_enabled = True
    assert renderer.samples_per_pixel == 0 and not renderer.image().any()
    # the rows kernel's passes from the seed add the same sums as the renderer's own dispatches
    banded.add_passes(SPP)
    assert sums(renderer, "accumulation", 1) == sums(guided, "accumulation", 1)
    assert sums(renderer, "guide_sums", 2) == sums(guided, "guide_sums", 2)
    renderer.guides_enabled = False
    assert "guide_sums" not in renderer.resources and "guide sums" not in renderer.gpu_image_bytes
    renderer.restart()
    banded.add_passes(SPP)
    assert sums(renderer, "accumulation", 1) == sums(guided, "accumulation", 1)
