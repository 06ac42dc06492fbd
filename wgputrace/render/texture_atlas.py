"""The scene's textures as the GPU holds them: one atlas with every texture a rectangle in it, a
TEXTURE record per texture (its rectangle, wrap modes, transform, whether to decode sRGB) and a
MATERIAL_TEXTURES record per material (which textures it reads).

An atlas rather than array layers: layers share one size (a 2048 base colour beside a 256 mask
would pad every layer) and their count is a limit of its own, where one 2D texture holds any mix
and binds as one resource. Textures are not padded against each other: the lookup wraps texel
indices inside each rectangle (`texture_wrap`), so no filter reaches a neighbour. Textures over
the device's side are box-filtered down with a TextureWarning (`fitted_texels`): refusing the
large textures users download would serve them worse than a softer one.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..gpu.layout import MATERIAL_TEXTURES, TEXTURE
from ..kernels.textures import NO_TEXTURE
from ..scene import Material, SceneError
from ..scene.lights.light import LUMINANCE_WEIGHTS
from ..scene.texture import WRAP_MODES, Texture, linear_to_srgb

# the fields of MATERIAL_TEXTURES that hold a parameter (Material.fill_texture_record writes them)
_PARAMETER_FIELDS = ("alpha", "alpha_mode", "alpha_cutoff", "double_sided", "emitted", "normal_scale")
# the slots of MATERIAL_TEXTURES that name a texture (the keys of Material.textures)
TEXTURE_SLOTS = tuple(name for name in MATERIAL_TEXTURES.dtype.names if name not in _PARAMETER_FIELDS)


class TextureWarning(UserWarning):
    """A texture was changed to fit the device (downscaled), and the warning says how."""


@dataclass
class Atlas:
    texels: np.ndarray  # (H, W, 4): uint8 bytes as the textures hold them, or float32 linear RGBA
    records: np.ndarray  # TEXTURE.dtype, one per texture in `used_textures` order


def light_density(material: Material) -> float:
    """The luminance of the radiance a material emits through its texture record x its emission
    texture's mean over every texel: zero where it emits nothing that way (`footprint_means` weighs
    each triangle)."""
    radiance = np.array(material.surface_emission())
    texture = material.textures().get("emission")
    if texture is not None:
        radiance = radiance * texture.linear_texels[..., :3].reshape(-1, 3).mean(axis=0, dtype=np.float64)
    return float(radiance @ LUMINANCE_WEIGHTS)


def needs_material_record(material: Material) -> bool:
    """Whether `material` lets rays through, emits through its MATERIAL_TEXTURES record or turns its
    anisotropy by the record's angle (and reads the tangents that come with the record)."""
    return material.lets_rays_through() or max(material.surface_emission()) > 0 or material.reads_tangent()


def used_textures(materials: list[Material]) -> list[Texture]:
    """Every texture the materials read, each once, in first-use order."""
    seen: dict[int, Texture] = {}
    for material in materials:
        for texture in material.textures().values():
            seen.setdefault(id(texture), texture)
    return list(seen.values())


def material_texture_records(materials: list[Material], textures: list[Texture]) -> np.ndarray:
    """MATERIAL_TEXTURES records: each material's textures as indices into `textures`."""
    index = {id(texture): i for i, texture in enumerate(textures)}
    records = MATERIAL_TEXTURES.zeros(len(materials))
    for record, material in zip(records, materials, strict=True):
        slots = material.textures()
        for slot in TEXTURE_SLOTS:
            record[slot] = index[id(slots[slot])] if slot in slots else NO_TEXTURE
        material.fill_texture_record(record)
    return records


def fitted_texels(texture: Texture, side: int, eight_bit: bool) -> np.ndarray:
    """The texture's texels as the atlas holds them (its bytes where `eight_bit`, else linear
    float32), box-filtered in linear values by the smallest whole factor that fits `side` (with a
    TextureWarning), or as they are where they fit."""
    width, height = texture.size
    factor = math.ceil(max(width, height) / side)
    if factor == 1:
        return texture.encoded_texels if eight_bit else texture.linear_texels
    texels = texture.linear_texels
    fitted_height, fitted_width = math.ceil(height / factor), math.ceil(width / factor)
    # the last block of a side that the factor does not divide repeats its edge texels
    padded = np.pad(texels, ((0, fitted_height * factor - height), (0, fitted_width * factor - width), (0, 0)), "edge")
    fitted = padded.reshape(fitted_height, factor, fitted_width, factor, 4).mean(axis=(1, 3), dtype=np.float64)
    warnings.warn(
        f"texture {texture.name!r} is {width}x{height} texels, over the device's {side} per side: "
        f"downscaled to {fitted_width}x{fitted_height}",
        TextureWarning,
        stacklevel=2,
    )
    if not eight_bit:
        return fitted.astype(np.float32)
    if texture.srgb:
        fitted[..., :3] = linear_to_srgb(fitted[..., :3])
    return np.round(fitted * 255.0).astype(np.uint8)


def pack_atlas(textures: list[Texture], side: int) -> Atlas:
    """The atlas of `textures` (each fitted to `side`), or SceneError naming the limit where their
    rectangles cannot share one texture of that side. 8-bit textures are kept as their bytes
    (rgba8unorm, sRGB decoded by the lookup) while all are 8-bit; one float texture makes the atlas
    linear rgba32float, since one texture has one format. Shelf packing (tallest first) wastes little
    for the few textures a scene has. Without textures (materials that need only their
    MATERIAL_TEXTURES record: alpha modes, sidedness) one unused texel and its record, as the
    bindings need at least one of each.
    """
    if not textures:
        records = TEXTURE.zeros(1)
        records["size"] = (1, 1)
        return Atlas(np.zeros((1, 1, 4), np.uint8), records)
    eight_bit = all(texture.encoded_texels is not None for texture in textures)
    images = [fitted_texels(texture, side, eight_bit) for texture in textures]
    area = sum(image.shape[0] * image.shape[1] for image in images)
    widest = max(image.shape[1] for image in images)
    width = min(side, max(widest, 2 ** math.ceil(math.log2(math.sqrt(area)))))
    origins = np.zeros((len(images), 2), np.int64)
    x = y = shelf_height = 0
    for i in sorted(range(len(images)), key=lambda i: -images[i].shape[0]):
        height_i, width_i = images[i].shape[:2]
        if x + width_i > width:
            x, y, shelf_height = 0, y + shelf_height, 0
        origins[i] = x, y
        x, shelf_height = x + width_i, max(shelf_height, height_i)
    # the shelves' width as used: narrower than `width` where no shelf filled it
    height, width = y + shelf_height, int((origins[:, 0] + [image.shape[1] for image in images]).max())
    if height > side:
        raise SceneError(
            f"the scene's {len(textures)} textures ({area:,} texels) need an atlas {width}x{height}, "
            f"over the device's {side} texels per side"
        )
    texels = np.zeros((height, width, 4), images[0].dtype)
    records = TEXTURE.zeros(len(textures))
    for record, texture, image, (ox, oy) in zip(records, textures, images, origins, strict=True):
        texels[oy : oy + image.shape[0], ox : ox + image.shape[1]] = image
        rows = texture.transform.rows()
        record["transform_u"], record["transform_v"] = rows[0], rows[1]
        record["wrap_s"], record["wrap_t"] = WRAP_MODES.index(texture.wrap_s), WRAP_MODES.index(texture.wrap_t)
        record["origin"], record["size"] = (ox, oy), (image.shape[1], image.shape[0])
        record["srgb"] = eight_bit and texture.srgb
    return Atlas(texels, records)
