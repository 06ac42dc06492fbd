"""Textures: WGSL `texture_sample` against a numpy oracle of glTF's lookup (bilinear
between texel centres, each wrap mode, KHR_texture_transform); a marked corner renders where glTF's
convention puts it and an sRGB texel decodes as its linear value; scenes without textures bind,
upload and compile none of it; edits upload only what changed; textures over the device's side
are downscaled with a warning; degenerate coordinates give no NaN."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Environment
from wgputrace.gpu.buffers import storage_buffer
from wgputrace.gpu.float_texture import FloatTexture
from wgputrace.gpu.layout import MATERIAL_TEXTURES, TRIANGLE_VERTICES, VERTEX_TANGENT, VERTEX_UV
from wgputrace.kernels.bind_groups import shading_group
from wgputrace.kernels.textures import textures_hook
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.render.renderer import Renderer
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.render.texture_atlas import TextureWarning, pack_atlas
from wgputrace.scene import Camera, Principled, Scene, SceneError, Shape, Texture, TextureTransform, cornell_box
from wgputrace.scene.texture import WRAP_MODES, srgb_to_linear
from wgputrace.testing.harness import run_kernel
from wgputrace.testing.scenes import SQUARE_CORNERS, uv_square

pytestmark = pytest.mark.gpu

SEED = 20_261_202
SIZE = 24
# a unit quad in z = 0 seen head-on from z = -3: its corner (-1, 1) carries uv (0, 0), the image's top-left
QUAD, QUAD_UVS = uv_square(normal_z=1)
CAMERA = Camera.looking_at((0, 0, -3), (0, 0, 0), vfov_degrees=45.0)

KERNEL = """
//! include "generated/structs.wgsl"
//! include "generated/textures.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let query = inputs_0[i];
    return texture_sample(u32(query.z), query.xy);
}
"""


def wrap(index: np.ndarray, n: int, mode: str) -> np.ndarray:
    """glTF's wrap modes on texel indices (the sampler's REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT)."""
    if mode == "repeat":
        return np.mod(index, n)
    if mode == "clamp":
        return np.clip(index, 0, n - 1)
    period = np.mod(index, 2 * n)
    return np.where(period < n, period, 2 * n - 1 - period)


def oracle(texture: Texture, uv: np.ndarray) -> np.ndarray:
    """Bilinear filtering between texel centres ((j + 1/2) / W) of the transformed coordinates, in float64."""
    t = texture.transform
    c, s = math.cos(t.rotation), math.sin(t.rotation)
    # KHR_texture_transform: translation . rotation . scale, rotation as the extension writes it
    matrix = (
        np.array([[1, 0, t.offset[0]], [0, 1, t.offset[1]], [0, 0, 1]])
        @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
        @ np.diag([t.scale[0], t.scale[1], 1.0])
    )
    st = (np.c_[uv, np.ones(len(uv))] @ matrix.T)[:, :2]
    width, height = texture.size
    xy = st * (width, height) - 0.5
    corner = np.floor(xy).astype(np.int64)
    f = xy - corner
    texels = texture.linear_texels.astype(np.float64)

    def texel(dx: int, dy: int) -> np.ndarray:
        return texels[wrap(corner[:, 1] + dy, height, texture.wrap_t), wrap(corner[:, 0] + dx, width, texture.wrap_s)]

    top = texel(0, 0) * (1 - f[:, :1]) + texel(1, 0) * f[:, :1]
    bottom = texel(0, 1) * (1 - f[:, :1]) + texel(1, 1) * f[:, :1]
    return top * (1 - f[:, 1:]) + bottom * f[:, 1:]


def sample_on_gpu(gpu_context, textures: list[Texture], queries: np.ndarray) -> np.ndarray:
    """texture_sample of (u, v, texture index) queries, the textures packed as a Renderer packs them."""
    atlas = pack_atlas(textures, 8192)
    resources = {
        "triangle_vertices": storage_buffer(gpu_context, "triangle vertices", TRIANGLE_VERTICES.zeros(1)),
        "vertex_uvs": storage_buffer(gpu_context, "vertex uvs", VERTEX_UV.zeros(1)),
        "vertex_tangents": storage_buffer(gpu_context, "vertex tangents", VERTEX_TANGENT.zeros(1)),
        "texture_atlas": FloatTexture(gpu_context, "atlas", atlas.texels).resource,
        "textures": storage_buffer(gpu_context, "textures", atlas.records),
        "material_textures": storage_buffer(gpu_context, "material textures", MATERIAL_TEXTURES.zeros(1)),
        "triangle_light_densities": storage_buffer(gpu_context, "triangle light densities", np.zeros(1, np.float32)),
    }
    return run_kernel(
        gpu_context,
        KERNEL,
        [queries.astype(np.float32)],
        np.dtype((np.float32, 4)),
        len(queries),
        input_types=["vec4<f32>"],
        output_type="vec4<f32>",
        groups={shading_group(smooth=False, textured=True): resources},
        variant=KernelVariant(SceneFeatures(textured=True)),
    )


def test_texture_sample_matches_gltf_lookup_for_every_wrap_mode_and_transform(gpu_context):
    rng = np.random.default_rng(SEED)
    textures = [
        Texture(rng.random((5, 7, 4), dtype=np.float32), srgb=False, wrap_s=s, wrap_t=t, name=f"{s} {t}")
        for s in WRAP_MODES
        for t in WRAP_MODES
    ]
    transform = TextureTransform(offset=(0.3, -0.2), rotation=0.7, scale=(1.5, 0.5))
    textures.append(Texture(rng.random((3, 4, 4), dtype=np.float32), srgb=False, wrap_s="mirror", transform=transform))
    count = 512
    queries = np.zeros((len(textures) * count, 4))
    queries[:, :2] = rng.uniform(-2.5, 2.5, (len(queries), 2))
    queries[:, 2] = np.repeat(np.arange(len(textures)), count)
    result = sample_on_gpu(gpu_context, textures, queries)
    expected = np.concatenate([oracle(t, queries[k * count : (k + 1) * count, :2]) for k, t in enumerate(textures)])
    np.testing.assert_allclose(result, expected, atol=2e-5)


def test_8_bit_textures_stay_bytes_and_decode_texel_by_texel(gpu_context):
    rng = np.random.default_rng(SEED + 1)
    pixels = rng.integers(0, 256, (6, 5, 4), dtype=np.uint8)
    textures = [Texture(pixels, srgb=True, name="srgb"), Texture(pixels, srgb=False, name="linear")]
    atlas = pack_atlas(textures, 8192)
    assert atlas.texels.dtype == np.uint8 and atlas.records["srgb"].tolist() == [1, 0]
    # one float texture makes the atlas float, linear for all
    mixed = pack_atlas([*textures, Texture(np.ones((1, 1, 3), np.float32))], 8192)
    assert mixed.texels.dtype == np.float32 and not mixed.records["srgb"].any()
    count = 512
    queries = np.zeros((2 * count, 4))
    queries[:, :2] = rng.uniform(-1.5, 1.5, (len(queries), 2))
    queries[:, 2] = np.repeat([0, 1], count)
    result = sample_on_gpu(gpu_context, textures, queries)
    expected = np.concatenate([oracle(t, queries[k * count : (k + 1) * count, :2]) for k, t in enumerate(textures)])
    # the GPU's unorm-to-float and pow against float64
    np.testing.assert_allclose(result, expected, atol=1e-5)


def test_texel_centres_give_the_texel_and_midpoints_the_mean(gpu_context):
    texture = Texture(
        np.array([[[0.0], [1.0]], [[0.25], [0.5]]], np.float32), srgb=False, wrap_s="clamp", wrap_t="clamp"
    )
    queries = np.array(
        [[0.25, 0.25, 0, 0], [0.75, 0.25, 0, 0], [0.25, 0.75, 0, 0], [0.5, 0.25, 0, 0], [0.5, 0.5, 0, 0]]
    )
    result = sample_on_gpu(gpu_context, [texture], queries)[:, 0]
    np.testing.assert_allclose(result, [0.0, 1.0, 0.25, 0.5, 0.4375], atol=1e-6)


def test_non_finite_and_huge_coordinates_give_finite_texels(gpu_context):
    texture = Texture(np.full((2, 3, 3), 0.5, np.float32), srgb=False)
    big = np.float32(3e38)
    queries = np.array([[np.nan, 0.5, 0, 0], [np.inf, -np.inf, 0, 0], [big, -big, 0, 0], [1e7, 0.3, 0, 0]])
    result = sample_on_gpu(gpu_context, [texture], queries)
    np.testing.assert_allclose(result[:, :3], 0.5, atol=1e-6)


def quad_image(material: Principled, uvs=QUAD_UVS, spp: int = 16) -> np.ndarray:
    scene = Scene([Shape("quad", QUAD, material, uvs=uvs)], CAMERA)
    scene.environment = Environment(1.0)
    renderer = Renderer(scene, SIZE, SIZE, seed=3, max_depth=2)
    renderer.render(spp)
    return renderer.image()


def brightest_quadrant(image: np.ndarray) -> tuple[int, int]:
    """Of the quad's four quarters in the image (a margin off its edges), the brightest one."""
    half = SIZE // 2
    means = [
        [image[r * half + 3 : (r + 1) * half - 3, c * half + 3 : (c + 1) * half - 3].mean() for c in (0, 1)]
        for r in (0, 1)
    ]
    return np.unravel_index(np.argmax(means), (2, 2))


def test_a_marked_corner_renders_where_gltf_puts_it():
    marked = np.zeros((16, 16, 3), np.uint8)
    marked[:8, :8] = 255  # the image's top-left quarter: uv in [0, 1/2]^2, at the corner (-1, 1)
    textured = quad_image(Principled("marked", base_color=(1, 1, 1), roughness=1.0, base_color_texture=Texture(marked)))
    # the same quarter made of geometry: the quad's quarter at that corner, white, the rest black
    white, black = Principled("white", base_color=(1, 1, 1), roughness=1.0), Principled("black", base_color=(0, 0, 0))
    (a, b, _, d), centre = SQUARE_CORNERS, np.zeros(3, np.float32)
    ab, ad = (a + b) / 2, (a + d) / 2
    quarter = np.array([[a, centre, ab], [a, ad, centre]], np.float32)
    scene = Scene([Shape("mark", quarter, white), Shape("rest", QUAD, black)], CAMERA)
    scene.environment = Environment(1.0)
    renderer = Renderer(scene, SIZE, SIZE, seed=3, max_depth=2)
    renderer.render(16)
    geometric = renderer.image()
    assert brightest_quadrant(textured[..., 0]) == brightest_quadrant(geometric[..., 0])
    mark = brightest_quadrant(textured[..., 0])
    half = SIZE // 2
    rows, cols = (
        slice(mark[0] * half + 3, (mark[0] + 1) * half - 3),
        slice(mark[1] * half + 3, (mark[1] + 1) * half - 3),
    )
    other_rows = slice((1 - mark[0]) * half + 3, (2 - mark[0]) * half - 3)
    assert textured[rows, cols].mean() > 0.5 and textured[other_rows, cols].mean() < 0.05


def test_an_srgb_128_texel_renders_as_its_linear_value():
    grey = np.full((4, 4, 3), 128, np.uint8)
    linear = float(srgb_to_linear(np.float64(128 / 255)))
    assert abs(linear - 0.2158605) < 1e-6
    textured = quad_image(Principled("grey", base_color=(1, 1, 1), base_color_texture=Texture(grey)))
    constant = quad_image(Principled("grey", base_color=(linear, linear, linear)))
    np.testing.assert_allclose(textured, constant, rtol=1e-4, atol=1e-6)


def test_metallic_roughness_texture_scales_roughness_by_g_and_metallic_by_b():
    texels = np.zeros((2, 2, 3), np.float32)
    texels[..., 1], texels[..., 2] = 0.5, 0.25
    texture = Texture(texels, srgb=False)
    textured = quad_image(Principled("mr", metallic=1.0, roughness=0.8, metallic_roughness_texture=texture))
    constant = quad_image(Principled("mr", metallic=0.25, roughness=0.4))
    np.testing.assert_allclose(textured, constant, rtol=1e-4, atol=1e-6)


def test_degenerate_and_huge_uvs_render_without_nan():
    uvs = np.array([[(0.5, 0.5)] * 3, [(1e30, -1e30), (0, 0), (3e38, 3e38)]], np.float32)
    image = quad_image(Principled("t", base_color_texture=Texture(np.full((2, 2, 3), 200, np.uint8))), uvs, spp=4)
    assert np.isfinite(image).all()


def test_scenes_without_textures_bind_compile_and_allocate_none():
    untextured, textured = (textures_hook(KernelVariant(SceneFeatures(textured=on))) for on in (False, True))
    assert "shading/textures.wgsl" not in untextured and "shading/textures.wgsl" in textured
    uvs_only = Scene([Shape("quad", QUAD, Principled("plain"), uvs=QUAD_UVS)], CAMERA)
    for scene in (cornell_box(), uvs_only):
        renderer = Renderer(scene, 16, 16)
        assert "shading" not in renderer.bind_groups and "shading" not in renderer.kernel.groups
        assert set(renderer.gpu_scene_bytes) == {"triangles", "bvh nodes", "materials", "lights"}
        assert renderer.gpu_texture_bytes == 0


def test_edits_upload_only_what_changed():
    texture = Texture(np.full((4, 4, 3), 100, np.uint8))
    material = Principled("t", base_color_texture=texture)
    scene = Scene([Shape("quad", QUAD, material, uvs=QUAD_UVS)], CAMERA)
    renderer = Renderer(scene, 16, 16)
    assert renderer.gpu_scene_bytes["texture atlas"] == renderer.gpu_texture_bytes == 4 * 4 * 4  # 8-bit: bytes
    assert renderer.gpu_bytes_per_triangle == (sum(renderer.gpu_scene_bytes.values()) - 64) / 2
    material.base_color = (0.25, 0.5, 0.75)
    assert set(renderer.update()) == {"materials"}
    material.base_color_texture = Texture(np.full((8, 2, 3), 7, np.uint8))
    uploads = renderer.update()
    assert set(uploads) == {"texture atlas", "textures"}
    assert uploads["texture atlas"].bytes == 8 * 2 * 4 and uploads["textures"].calls == 1
    # one of the same size and kind: the same rectangle, only its changed row of texels
    pixels = np.full((8, 2, 3), 7, np.uint8)
    pixels[5, 1] = 99
    material.base_color_texture = Texture(pixels)
    uploads = renderer.update()
    assert set(uploads) == {"texture atlas"} and uploads["texture atlas"].bytes == 2 * 4
    material.alpha = 0.5
    assert set(renderer.update()) == {"material textures"}
    # a move keeps the corners' coordinates: triangles and nodes only
    moved = np.eye(4)
    moved[0, 3] = 0.1
    scene.shapes[0].transform = moved
    assert set(renderer.update()) == {"triangles", "bvh nodes"}
    material.base_color_texture = None
    renderer.update()
    assert "shading" not in renderer.bind_groups and "texture atlas" not in renderer.gpu_scene_bytes


def test_a_texture_over_the_device_side_is_downscaled_with_a_warning():
    texels = np.zeros((12, 20, 1), np.float32)
    texels[:, :10] = 1.0
    big = Texture(texels, srgb=False, name="big")
    with pytest.warns(TextureWarning, match=r"'big' is 20x12 texels, over the device's 8 per side: downscaled to 7x4"):
        atlas = pack_atlas([big, Texture(np.ones((2, 2, 1), np.float32))], side=8)
    assert atlas.texels.shape[0] <= 8 and atlas.texels.shape[1] <= 8
    assert atlas.records["size"][0].tolist() == [7, 4]
    # box filtering keeps the mean where the factor divides the side (rows: 12 = 3 x 4)
    assert atlas.texels[:4, :7, 0].mean(axis=0)[:3].tolist() == [1.0, 1.0, 1.0]
    # 8-bit sRGB texels average as linear light and stay bytes: black and white make 188, not 128
    stripes = np.zeros((2, 16, 3), np.uint8)
    stripes[:, 1::2] = 255
    with pytest.warns(TextureWarning):
        atlas = pack_atlas([Texture(stripes)], side=8)
    assert atlas.texels.dtype == np.uint8 and (atlas.texels[..., :3] == 188).all()
    mirror_scene = Scene([Shape("quad", QUAD, Principled("t", base_color_texture=big), uvs=QUAD_UVS)], CAMERA)
    with pytest.warns(TextureWarning):
        mirror = SceneMirror(mirror_scene, "bvh", texture_side=8)
    assert max(mirror.atlas_texels.shape[:2]) <= 8


def test_bad_textures_and_uvs_are_scene_errors():
    with pytest.raises(SceneError, match="pixels must be finite"):
        Texture(np.full((2, 2, 3), np.nan, np.float32))
    with pytest.raises(SceneError, match=r"each side must be 1 to"):
        Texture(np.zeros((0, 4, 3), np.uint8))
    with pytest.raises(SceneError, match="wrap_s must be one of"):
        Texture(np.zeros((2, 2, 3), np.uint8), wrap_s="border")
    with pytest.raises(SceneError, match=r"triangle 1 has a NaN or infinite texture coordinate"):
        Shape("quad", QUAD, Principled("p"), uvs=np.where(np.arange(2)[:, None, None] == 1, np.nan, QUAD_UVS))


def test_a_mirroring_transform_swaps_uvs_with_the_corners():
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    shape = Shape("quad", QUAD, Principled("p"), uvs=QUAD_UVS, transform=mirror)
    # each world corner keeps its texture coordinate: find it by position
    for world, uvs in zip(shape.world_vertices, shape.world_uvs, strict=True):
        for corner, uv in zip(world, uvs, strict=True):
            local = corner * (-1, 1, 1)
            matches = np.all(np.isclose(QUAD, local), axis=2)
            assert (QUAD_UVS[matches] == uv).all()


def test_texture_from_file_reads_png_and_names_a_bad_file(tmp_path):
    from PIL import Image

    pixels = np.zeros((3, 5, 3), np.uint8)
    pixels[0, 0] = (255, 0, 0)
    Image.fromarray(pixels).save(tmp_path / "marked.png")
    texture = Texture.from_file(tmp_path / "marked.png", wrap_s="clamp")
    assert texture.size == (5, 3) and texture.name == "marked.png" and texture.wrap_s == "clamp"
    assert texture.encoded_texels[0, 0].tolist() == [255, 0, 0, 255]
    (tmp_path / "corrupt.png").write_bytes(b"\x89PNG\r\n\x1a\n not really")
    with pytest.raises(SceneError, match=r"texture file '.*corrupt.png': cannot read it as an image"):
        Texture.from_file(tmp_path / "corrupt.png")
