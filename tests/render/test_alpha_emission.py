"""Alpha and sidedness (WGSL `surface_blocks`): cut-out texels (MASK) let every ray through, the
camera's and the shadow rays', in the fraction the texture cuts; BLEND passes 1 - alpha of the
rays; OPAQUE ignores alpha; a single-sided surface is invisible from behind. Emission
(WGSL `surface_emission`): a panel with an emissive texture lights a room as a uniform emitter of the
texture's mean radiance does, and weighs in the light table by that mean."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import DirectionalLight, Environment
from wgputrace.render.renderer import Renderer
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.scene import Camera, Diffuse, Emitter, Principled, Scene, Shape, Texture

pytestmark = pytest.mark.gpu

SIZE = 24
# The camera at z = -3 looks at a white wall in z = 0 (seen across |x|, |y| < 1.24).
CAMERA = Camera.looking_at((0, 0, -3), (0, 0, 0), vfov_degrees=45.0)
# Stripes: one texel column in four cut out (alpha 0), so MASK cuts a quarter of the surface (the
# bilinear alpha crosses the cutoff 0.5 exactly at the texel boundaries).
STRIPES = Texture(np.array([[[0, 0, 0, 0], [0, 0, 0, 255], [0, 0, 0, 255], [0, 0, 0, 255]]], np.uint8))
CUT_FRACTION = 0.25
# light travels along +z and 3 units in -x a unit of z: the occluder one unit before the wall at
# x in [1.5, 4.5] shadows the wall the camera sees, out of the camera's view (|x| < 0.83 at z = -1)
LIGHT = DirectionalLight((-3.0, 0.0, 1.0), 3.0)


def quad(x0: float, x1: float, y0: float, y1: float, z: float, facing_camera: bool = True) -> np.ndarray:
    a, b, c, d = (x0, y1, z), (x1, y1, z), (x1, y0, z), (x0, y0, z)
    # glTF's front face: counter-clockwise seen from the front
    triangles = [[a, b, c], [a, c, d]] if facing_camera else [[a, c, b], [a, d, c]]
    return np.array(triangles, np.float32)


def quad_uvs(repeats: float, facing_camera: bool = True) -> np.ndarray:
    r = repeats
    uvs = (
        [[(0, 0), (r, 0), (r, r)], [(0, 0), (r, r), (0, r)]]
        if facing_camera
        else [
            [(0, 0), (r, r), (r, 0)],
            [(0, 0), (0, r), (r, r)],
        ]
    )
    return np.array(uvs, np.float32)


def render(shapes: list[Shape], *, light: bool, spp: int = 32, acceleration: str = "bvh") -> np.ndarray:
    scene = Scene(shapes, CAMERA)
    if light:
        scene.add_light(LIGHT)
    else:
        scene.environment = Environment(1.0)
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2, accel=acceleration)
    renderer.render(spp)
    image = renderer.image()
    assert np.isfinite(image).all()
    return image.mean(axis=2)


def wall() -> Shape:
    return Shape("wall", quad(-3, 3, -3, 3, 0.0), Diffuse("white", (0.8, 0.8, 0.8)))


def occluder(material: Principled) -> Shape:
    # 12 stripe periods across 3 units: about 10 in the shadow the camera sees
    return Shape("occluder", quad(1.5, 4.5, -1.5, 1.5, -1.0), material, uvs=quad_uvs(12.0))


def shadowed_fraction(material: Principled, acceleration: str = "bvh") -> float:
    lit = render([wall()], light=True)
    shadowed = render([wall(), occluder(material)], light=True, acceleration=acceleration)
    return 1.0 - shadowed.mean() / lit.mean()


@pytest.mark.parametrize("acceleration", ["bvh", "flat"])
def test_mask_cut_outs_cast_a_shadow_of_the_cut_fraction(acceleration):
    cut = Principled("leaf", base_color_texture=STRIPES, alpha_mode="MASK")
    assert shadowed_fraction(cut, acceleration) == pytest.approx(1.0 - CUT_FRACTION, abs=0.04)
    # the same texture OPAQUE ignores its alpha: a full shadow
    assert shadowed_fraction(Principled("leaf", base_color_texture=STRIPES)) > 0.97


def seen_through_fraction(material: Principled, repeats: float, spp: int = 32) -> float:
    """The fraction of the bright environment a screen covering the view lets the camera see, the
    screen's own reflection (the same material OPAQUE) taken out."""
    screen = Shape("screen", quad(-2, 2, -2, 2, -1.0), material, uvs=quad_uvs(repeats))
    seen = render([screen], light=False, spp=spp).mean()
    mode, material.alpha_mode = material.alpha_mode, "OPAQUE"
    opaque = render([screen], light=False, spp=spp).mean()
    material.alpha_mode = mode
    return (seen - opaque) / (1.0 - opaque)


def black(name: str, **parameters) -> Principled:
    """A material reflecting next to nothing (a conductor of reflectance 0 at normal incidence)."""
    return Principled(name, base_color=(0, 0, 0), metallic=1.0, **parameters)


def test_camera_rays_see_through_cut_texels():
    screen = black("screen", base_color_texture=STRIPES, alpha_mode="MASK")
    # 16 stripe periods across 4 units: about 7 in view
    assert seen_through_fraction(screen, 16.0) == pytest.approx(CUT_FRACTION, abs=0.04)
    # a cutoff at or under every alpha cuts nothing
    screen.alpha_cutoff = 0.0
    assert seen_through_fraction(screen, 16.0) == pytest.approx(0.0, abs=0.01)


def test_blend_at_half_alpha_transmits_half():
    veil = black("veil", alpha=0.5, alpha_mode="BLEND")
    assert shadowed_fraction(veil) == pytest.approx(0.5, abs=0.04)
    assert seen_through_fraction(veil, 1.0, spp=64) == pytest.approx(0.5, abs=0.04)


def cube(half: float) -> np.ndarray:
    """A closed cube about the origin, its front faces outwards (glTF's counter-clockwise)."""
    corners = np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])
    faces = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    triangles = np.array([corners[[a, b, c]] for a, b, c, d in faces] + [corners[[a, c, d]] for a, b, c, d in faces])
    outwards = np.einsum(
        "ij,ij->i",
        np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]),
        triangles.mean(axis=1),
    )
    triangles[outwards < 0] = triangles[outwards < 0][:, ::-1]
    return triangles.astype(np.float32)


def test_a_closed_single_sided_mesh_is_solid_outside_and_open_inside():
    # glTF's doubleSided defaults to false: a closed mesh must still occlude, and rays from inside
    # must not find its faces black
    box = Shape("box", cube(0.5), black("box", double_sided=False))
    assert render([box], light=False, spp=4)[SIZE // 2 - 2 : SIZE // 2 + 2, SIZE // 2 - 2 : SIZE // 2 + 2].max() < 0.05
    scene = Scene([Shape("room", cube(5.0), black("room", double_sided=False))], CAMERA)
    scene.environment = Environment(1.0)
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2)
    renderer.render(4)
    assert renderer.image().min() > 0.99


@pytest.mark.parametrize("double_sided", [True, False])
def test_a_single_sided_surface_is_invisible_from_behind(double_sided):
    card = black("card", double_sided=double_sided)
    away = Shape("card", quad(-2, 2, -2, 2, -1.0, facing_camera=False), card, uvs=quad_uvs(1.0, False))
    towards = Shape("card", quad(-2, 2, -2, 2, -1.0), card, uvs=quad_uvs(1.0))
    # from the front either is dark; from behind the single-sided one shows the environment
    assert render([towards], light=False, spp=4).max() < 0.05
    behind = render([away], light=False, spp=4)
    assert (behind.min() > 0.99) if not double_sided else (behind.max() < 0.05)


def test_editing_sidedness_and_alpha_mode_takes_effect_in_the_next_render():
    card = black("card", double_sided=False)
    scene = Scene(
        [Shape("card", quad(-2, 2, -2, 2, -1.0, facing_camera=False), card, uvs=quad_uvs(1.0, False))], CAMERA
    )
    scene.environment = Environment(1.0)
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2)
    renderer.render(4)
    assert renderer.image().min() > 0.99
    card.double_sided = True  # the scene no longer needs the surface test: the plain kernel again
    renderer.render(4)
    assert renderer.image().max() < 0.05
    card.alpha, card.alpha_mode = 0.0, "MASK"
    renderer.render(4)
    assert renderer.image().min() > 0.99


def test_only_scenes_with_a_see_through_material_compile_the_surface_test():
    leaf = Principled("leaf", base_color_texture=STRIPES)
    scene = Scene([Shape("leaf", quad(-2, 2, -2, 2, -1.0), leaf, uvs=quad_uvs(1.0))], CAMERA)
    renderer = Renderer(scene, 8, 8)
    assert "textured" in renderer.kernel.label and "see-through" not in renderer.kernel.label
    leaf.alpha_mode = "MASK"
    renderer.render(1)
    assert "see-through" in renderer.kernel.label


# a panel in the ceiling of a closed white room, its emission texture a checkerboard of black and
# sRGB 255 (linear 1): mean radiance 0.5 x emission x strength
CHECKER = Texture(np.kron([[0, 255], [255, 0]], np.ones((4, 4)))[..., None].repeat(3, axis=2).astype(np.uint8))
ROOM_CAMERA = Camera.looking_at((0, 0, -0.9), (0, 0, 0), vfov_degrees=80.0)


def ceiling_panel(material, x0: float = -0.5, x1: float = 0.5, u0: float = 0.0, u1: float = 2.0) -> Shape:
    """A horizontal quad under the room's ceiling, its texture coordinates u0..u1 across x, 0..2 along z."""
    uvs = quad_uvs(1.0)
    uvs[..., 0] = u0 + (u1 - u0) * uvs[..., 0]
    uvs[..., 1] *= 2.0
    return Shape("panel", quad(x0, x1, -0.5, 0.5, 0.0)[:, :, [0, 2, 1]] + np.float32([0, 0.99, 0]), material, uvs=uvs)


def lit_room(panel_material, spp: int = 64, panels: list[Shape] | None = None, integrator: str = "mis"):
    panels = [ceiling_panel(panel_material)] if panels is None else panels
    scene = Scene([Shape("room", cube(1.0), Diffuse("white", (0.7, 0.7, 0.7))), *panels], ROOM_CAMERA)
    renderer = Renderer(scene, SIZE, SIZE, seed=7, max_depth=3, integrator=integrator)
    renderer.render(spp)
    image = renderer.image()
    assert np.isfinite(image).all()
    return image, SceneMirror(scene, "bvh")


def test_an_emissive_texture_lights_a_room_as_its_mean_radiance():
    textured = black("panel", emission=(2.0, 2.0, 2.0), emission_texture=CHECKER, emission_strength=1.5)
    image, mirror = lit_room(textured)
    uniform, uniform_mirror = lit_room(Emitter("panel", color=(1.5, 1.5, 1.5)))
    assert image.mean() == pytest.approx(uniform.mean(), rel=0.05)
    # the light table weighs the panel by its mean radiance (area 1 x luminance 1.5), as the emitter
    assert mirror.lights.total_weight == pytest.approx(uniform_mirror.lights.total_weight, rel=1e-6)
    assert mirror.lights.total_weight == pytest.approx(1.5, rel=1e-6)


def test_a_black_emission_texture_is_no_light():
    dark = black("panel", emission=(1.0, 1.0, 1.0), emission_texture=Texture(np.zeros((2, 2, 3), np.uint8)))
    image, mirror = lit_room(dark, spp=4)
    assert mirror.lights.count == 0 and image.max() == 0.0


def test_light_table_weights_follow_the_texture_over_each_footprint():
    # four strips across a texture whose last two of eight texel columns are white: the first two
    # strips read only black texels and are no light; the others weigh by their footprint's mean
    columns = np.zeros((1, 8, 3), np.uint8)
    columns[:, 6:] = 255
    stripes = Texture(columns, wrap_s="clamp", wrap_t="clamp")
    glow = black("glow", emission=(1.0, 1.0, 1.0), emission_texture=stripes)
    strips = [ceiling_panel(glow, -0.5 + i / 4, -0.25 + i / 4, i / 4, (i + 1) / 4) for i in range(4)]
    image, mirror = lit_room(None, spp=64, panels=strips)
    # strip 2 reads texel columns 3..6 (one white of 4), strip 3 columns 5..7 (two of 3); area 1/4 each
    assert mirror.lights.count == 4
    assert mirror.lights.total_weight == pytest.approx(0.25 * (1 / 4 + 2 / 3), rel=1e-5)
    # light sampling by those weights agrees with BSDF sampling alone, which needs no table
    bsdf_only, _ = lit_room(None, spp=256, panels=strips, integrator="bsdf")
    assert image.mean() == pytest.approx(bsdf_only.mean(), rel=0.05)


def test_the_mitsuba_export_cuts_mask_blends_blend_and_exports_emission_as_an_area_emitter():
    # BLEND: opacity alpha x the texel's alpha, bilinear (stochastic transparency's expectation)
    ramp = Texture(np.array([[[255, 255, 255, 255], [255, 255, 255, 51]]], np.uint8))
    blend = Principled("veil", alpha=0.5, alpha_mode="BLEND", base_color_texture=ramp).mitsuba_bsdf()
    assert blend["type"] == "mask" and blend["opacity"]["filter_type"] == "bilinear"
    assert blend["opacity"]["data"][..., 0] == pytest.approx(np.array([[0.5, 0.1]]))
    assert Principled("veil", alpha=0.3, alpha_mode="BLEND").mitsuba_bsdf()["opacity"] == pytest.approx(0.3)
    # MASK: opacity 1 where alpha x the texel's alpha reaches the cutoff, looked up nearest
    half = Texture(np.array([[[255, 255, 255, 255], [255, 255, 255, 100]]], np.uint8))
    mask = Principled("leaf", alpha=0.9, alpha_mode="MASK", base_color_texture=half).mitsuba_bsdf()
    assert mask["type"] == "mask" and mask["bsdf"]["type"] == "principled"
    assert mask["opacity"]["filter_type"] == "nearest"
    assert mask["opacity"]["data"][..., 0].tolist() == [[1.0, 0.0]]
    assert Principled("card", alpha=0.4, alpha_mode="MASK").mitsuba_bsdf()["opacity"] == 0.0
    assert Principled("card", double_sided=False).mitsuba_bsdf()["type"] == "principled"
    assert Principled("card").mitsuba_emitter() is None
    texture = Texture(np.full((2, 2, 3), 255, np.uint8))
    lamp = Principled("lamp", emission=(1.0, 0.5, 0.0), emission_texture=texture, emission_strength=2.0)
    emitter = lamp.mitsuba_emitter()
    assert emitter["type"] == "area" and emitter["radiance"]["type"] == "bitmap"
    assert emitter["radiance"]["data"][1, 1] == pytest.approx((2.0, 1.0, 0.0))
