"""Normal maps (Principled.normal_texture, WGSL `normal_mapped`) rendered: a quad facing the
camera under a grazing directional light. A flat map (and scale 0) renders like no map; a map
tilted towards the light brightens the quad, tilted away darkens it, and a tilted map renders as the
same tilt given as corner normals (the same shading normal and shading_weight); the scene's
MikkTSpace tangents are the hand-computed ones; grazing views, noisy maps and degenerate texture
coordinates give no NaN; scenes without normal maps upload one tangent record; the Mitsuba export
refuses a normal map rather than drop it."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import DirectionalLight
from wgputrace.render.renderer import Renderer
from wgputrace.render.scene_mirror import VERTEX_INDICES, VERTEX_TANGENTS, VERTEX_UVS, SceneMirror
from wgputrace.render.shared_vertices import corner_values
from wgputrace.scene import Camera, Principled, Scene, Shape, Texture
from wgputrace.testing.scenes import uv_square

pytestmark = pytest.mark.gpu

SIZE = 16
SPP = 8
# a quad in z = 0 facing the camera at z = -3 (normal -z); u along +x, v down
QUAD, QUAD_UVS = uv_square(normal_z=-1)
CAMERA = Camera.looking_at((0, 0, -3), (0, 0, 0), vfov_degrees=30.0)
# light from the +x side, 11 degrees above the quad's plane: cos 0.2 on the flat quad
LIGHT_DIRECTION = (-1.0, 0.0, 0.2)
# a normal tilted 30 degrees towards the tangent (+x, towards the light): tangent-space and world
TILT = np.radians(30.0)
TILTED = np.array([np.sin(TILT), 0.0, np.cos(TILT)])
TILTED_WORLD = np.array([np.sin(TILT), 0.0, -np.cos(TILT)])


def normal_texture(tangent_space_normal) -> Texture:
    """A linear float texture holding one tangent-space normal, encoded as glTF stores them."""
    texels = np.broadcast_to(np.asarray(tangent_space_normal, np.float32) * 0.5 + 0.5, (2, 2, 3))
    return Texture(np.ascontiguousarray(texels), srgb=False)


def scene_of(material: Principled, **shape_attributes) -> Scene:
    attributes = {"uvs": QUAD_UVS, **shape_attributes}
    scene = Scene([Shape("quad", QUAD, material, **attributes)], CAMERA)
    scene.add_light(DirectionalLight(LIGHT_DIRECTION, 3.0))
    return scene


def render(scene: Scene, spp: int = SPP) -> np.ndarray:
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2)
    renderer.render(spp)
    return renderer.image()


def material(**parameters) -> Principled:
    # a white texture keeps every variant in the textured kernel
    white = Texture(np.full((2, 2, 3), 255, np.uint8))
    return Principled("bumpy", base_color=(0.8, 0.8, 0.8), roughness=1.0, base_color_texture=white, **parameters)


def test_a_flat_map_and_scale_0_render_like_no_map():
    plain = render(scene_of(material()))
    flat = render(scene_of(material(normal_texture=normal_texture((0.0, 0.0, 1.0)))))
    unscaled = render(scene_of(material(normal_texture=normal_texture(TILTED), normal_scale=0.0)))
    assert plain.mean() > 0.01
    np.testing.assert_allclose(flat, plain, rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(unscaled, plain, rtol=1e-4, atol=1e-6)


def test_a_tilted_map_shades_as_the_tilt_given_as_corner_normals():
    """Tilted towards the light the quad brightens, by less than Lambert's cosine ratio (0.66 against
    0.2) because Chiang et al.'s terminator term fades light the flat facet sees at 11 degrees;
    exactly as corner normals tilted alike (the same shading normal and weight); tilted away from
    the light (below its horizon) it goes dark."""
    flat = render(scene_of(material()))
    mapped = render(scene_of(material(normal_texture=normal_texture(TILTED))))
    away = render(scene_of(material(normal_texture=normal_texture(TILTED * (-1.0, 1.0, 1.0)))))
    smooth = render(scene_of(material(), normals=np.broadcast_to(TILTED_WORLD, (2, 3, 3))))
    np.testing.assert_allclose(mapped, smooth, rtol=1e-3, atol=1e-5)
    light = -np.array(LIGHT_DIRECTION) / np.linalg.norm(LIGHT_DIRECTION)
    lambert = np.dot(TILTED_WORLD, light) / np.dot((0.0, 0.0, -1.0), light)
    assert 1.05 < mapped.mean() / flat.mean() < lambert
    assert away.max() == 0.0


def test_the_scene_tangents_are_dp_du_with_the_bitangent_up_the_image():
    """u runs along +x and the image's top is +y: tangent +x; bitangent cross(-z, +x) * w = +y
    needs w = -1."""
    mirror = SceneMirror(scene_of(material(normal_texture=normal_texture((0.0, 0.0, 1.0)))), "bvh")
    tangents = corner_values(mirror.vertices[VERTEX_INDICES], mirror.vertices[VERTEX_TANGENTS])
    np.testing.assert_allclose(tangents, [[[1.0, 0.0, 0.0, -1.0]] * 3] * 2, atol=1e-6)
    assert len(SceneMirror(scene_of(material()), "bvh").vertices[VERTEX_TANGENTS]) == 1


def test_grazing_views_noisy_maps_and_degenerate_uvs_give_no_nan():
    rng = np.random.default_rng(20_261_203)
    noisy = Texture(rng.random((8, 8, 3)).astype(np.float32), srgb=False)
    bumpy = material(normal_texture=noisy, normal_scale=5.0)
    degenerate = np.array([[(0.5, 0.5)] * 3, [(0, 0), (1e30, 0), (0, 0)]], np.float32)
    for scene in (scene_of(bumpy), scene_of(bumpy, uvs=degenerate)):
        for eye in ((0.0, 0.0, -3.0), (3.0, 0.0, -0.02), (0.0, 3.0, 0.01)):
            scene.camera = Camera.looking_at(eye, (0, 0, 0), vfov_degrees=60.0)
            assert np.isfinite(render(scene, spp=2)).all()


def test_the_mitsuba_export_wraps_the_map_flipping_green_for_left_handed_tangents():
    """Mitsuba's `normalmap` reads green along n x dP/du, glTF's along the bitangent w (n x t); the
    scale multiplies x and y (the `normal_mapped_plane` reference case renders it against Mitsuba)."""
    tilted = material(normal_texture=normal_texture((0.0, 0.6, 0.8)), normal_scale=0.5)
    right, left = tilted.mitsuba_bsdf(tangent_handedness=1.0), tilted.mitsuba_bsdf(tangent_handedness=-1.0)
    assert right["type"] == "normalmap" and right["bsdf"]["type"] == "principled"
    assert right["normalmap"]["data"][0, 0] == pytest.approx((0.5, 0.5 + 0.5 * 0.3, 0.9))
    assert left["normalmap"]["data"][0, 0] == pytest.approx((0.5, 0.5 - 0.5 * 0.3, 0.9))


def test_a_normal_map_added_to_and_removed_from_a_live_renderer():
    """Adding the map uploads a tangent record per vertex where there was one (and the
    map's texture), removing it shrinks them back; each picture is what a new Renderer draws (this
    scene's light is direct and smooth: means agree well within the noise allowance)."""
    bumpy = material()
    renderer = Renderer(scene_of(bumpy), SIZE, SIZE, seed=5, max_depth=2)
    renderer.render(SPP)
    bumpy.normal_texture = normal_texture(TILTED)
    uploads = renderer.update()
    assert {VERTEX_TANGENTS, "material textures"} <= set(uploads)
    assert renderer._mirror.vertices[VERTEX_TANGENTS].shape == (len(renderer._mirror.vertices[VERTEX_UVS]),)
    renderer.render(SPP)
    fresh = render(scene_of(material(normal_texture=normal_texture(TILTED))))
    assert renderer.image().mean() == pytest.approx(fresh.mean(), rel=0.02)
    bumpy.normal_texture = None
    renderer.update()
    assert renderer._mirror.vertices[VERTEX_TANGENTS].shape == (1,)
    renderer.render(SPP)
    assert renderer.image().mean() == pytest.approx(render(scene_of(material())).mean(), rel=0.02)
