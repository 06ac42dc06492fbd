"""Textures: an image a material parameter reads through a shape's texture coordinates.

Coordinates follow glTF: (0, 0) is the image's top-left texel corner, u runs right and v down;
texel (row i, column j) covers [j, j + 1] / W x [i, i + 1] / H. Outside [0, 1] each axis wraps by
its mode ("repeat", "clamp" to the edge texel, "mirror"); a TextureTransform (KHR_texture_transform)
maps a shape's coordinates before the lookup. An 8-bit image is kept as its bytes
(`encoded_texels`), which the GPU decodes texel by texel before interpolating (decoding after would
darken edges); float pixels are kept as given; `linear_texels` is what both mean, for the host.
Fewer than four channels fill out as glTF reads them. A Texture is not edited in place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from .errors import SceneError

WRAP_MODES = ("repeat", "clamp", "mirror")
# the largest side a Texture accepts; the GPU's own limit (`atlas_side`) may be smaller, and
# a texture over it is downscaled with a warning there
MAX_TEXTURE_SIDE = 65536


@dataclass(frozen=True)
class TextureTransform:
    """KHR_texture_transform: uv' = offset + R(rotation) S(scale) uv (rotation in radians,
    counter-clockwise in the image as the extension defines it)."""

    offset: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    scale: tuple[float, float] = (1.0, 1.0)

    def rows(self) -> np.ndarray:
        """(2, 3) float32: u' = rows[0] . (u, v, 1), v' = rows[1] . (u, v, 1) (the extension's matrix)."""
        c, s = math.cos(self.rotation), math.sin(self.rotation)
        (su, sv), (ou, ov) = self.scale, self.offset
        return np.array([[c * su, s * sv, ou], [-s * su, c * sv, ov]], np.float32)


def srgb_to_linear(values: np.ndarray) -> np.ndarray:
    """The sRGB transfer function inverted (IEC 61966-2-1), values in [0, 1]."""
    return np.where(values <= 0.04045, values / 12.92, ((values + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(values: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1), values in [0, 1]."""
    return np.where(values <= 0.0031308, values * 12.92, 1.055 * np.maximum(values, 0.0031308) ** (1 / 2.4) - 0.055)


class Texture:
    """An image a material parameter reads (`Principled`'s textures).

    Args:
        pixels: uint8 (H, W, C) or float (H, W, C), C in 1..4 (a (H, W) array is one channel).
        srgb: the colour channels are sRGB-encoded (base colour, emission), else linear data
            (metallic-roughness, normals); float pixels are taken as they are, alpha is always linear.
        wrap_s: how u wraps outside [0, 1]: "repeat", "clamp" (to the edge texel) or "mirror".
        wrap_t: the same for v.
        name: names it in errors.
        transform: maps a shape's texture coordinates before the lookup (KHR_texture_transform).

    Raises:
        SceneError: (a ValueError) bad pixels or wrap mode, naming the texture.
    """

    def __init__(
        self,
        pixels,
        *,
        srgb: bool = True,
        wrap_s: str = "repeat",
        wrap_t: str = "repeat",
        name: str = "",
        transform: TextureTransform = TextureTransform(),
    ) -> None:
        self.name, self.srgb, self.transform = name, bool(srgb), transform
        for axis, mode in (("wrap_s", wrap_s), ("wrap_t", wrap_t)):
            if mode not in WRAP_MODES:
                raise SceneError(f"texture {name!r}: {axis} must be one of {WRAP_MODES}, got {mode!r}")
        self.wrap_s, self.wrap_t = wrap_s, wrap_t
        texels = _rgba(name, pixels)
        # the 8-bit bytes, or None where the pixels are floats (`float_texels`)
        self.encoded_texels = texels if texels.dtype == np.uint8 else None
        self._float_texels = None if texels.dtype == np.uint8 else texels

    @cached_property
    def linear_texels(self) -> np.ndarray:
        """Read-only float32 (H, W, 4) linear RGBA: the float pixels, or the bytes / 255 with the
        colour channels sRGB-decoded where `srgb`."""
        if self._float_texels is not None:
            return self._float_texels
        texels = self.encoded_texels.astype(np.float32) / 255.0
        if self.srgb:
            texels[..., :3] = srgb_to_linear(texels[..., :3])
        texels.flags.writeable = False
        return texels

    @classmethod
    def from_file(cls, path, *, srgb: bool = True, **options) -> Texture:
        """A texture of the image file at `path` (any format PIL reads), named by the file; `srgb`
        and the other `options` as Texture takes them. SceneError naming the file where it cannot."""
        from PIL import Image, UnidentifiedImageError

        path = Path(path)
        try:
            with Image.open(path) as image:
                image.load()
                mode = image.mode if image.mode in ("L", "LA", "RGB", "RGBA") else "RGBA"
                pixels = np.asarray(image.convert(mode))
        except (OSError, UnidentifiedImageError, Image.DecompressionBombError) as error:
            raise SceneError(f"texture file {str(path)!r}: cannot read it as an image ({error})") from None
        return cls(pixels, srgb=srgb, name=options.pop("name", path.name), **options)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in texels."""
        texels = self._float_texels if self.encoded_texels is None else self.encoded_texels
        return texels.shape[1], texels.shape[0]

    def mitsuba_bitmap(self, texels: np.ndarray) -> dict:
        """Mitsuba 3's `bitmap` of `texels` (this texture's linear_texels, with the channels a
        material reads and its factors multiplied in) looked up as ours is: bilinear, this wrap mode,
        this transform (Mitsuba maps (u, v, 0) through the 4x4 `to_uv`). Mitsuba's coordinates are
        glTF's (row 0 at v = 0: checked on a marked texel); it has one wrap mode for both axes."""
        if self.wrap_s != self.wrap_t:
            raise ValueError(
                f"texture {self.name!r}: Mitsuba's bitmap has one wrap mode, not {self.wrap_s}/{self.wrap_t}"
            )
        rows = self.transform.rows().astype(np.float64)
        to_uv = np.eye(4)
        to_uv[:2, :2], to_uv[:2, 3] = rows[:, :2], rows[:, 2]
        return {
            "type": "bitmap",
            "data": np.ascontiguousarray(texels, np.float32),
            "raw": True,
            "filter_type": "bilinear",
            "wrap_mode": self.wrap_s,
            "to_uv": to_uv,
        }

    def __repr__(self) -> str:
        return f"Texture({self.name!r}, {self.size[0]}x{self.size[1]}, srgb={self.srgb})"


def _rgba(name: str, pixels) -> np.ndarray:
    """Read-only (H, W, 4) RGBA of `pixels`, uint8 or float32 as given, or SceneError naming what is wrong."""
    array = np.asarray(pixels)
    if array.ndim == 2:
        array = array[:, :, None]
    if array.ndim != 3 or not 1 <= array.shape[2] <= 4:
        raise SceneError(f"texture {name!r}: pixels must be (H, W, C) with C in 1..4, got shape {array.shape}")
    height, width, channels = array.shape
    if not (0 < height <= MAX_TEXTURE_SIDE and 0 < width <= MAX_TEXTURE_SIDE):
        raise SceneError(f"texture {name!r}: {width}x{height} texels, each side must be 1 to {MAX_TEXTURE_SIDE:,}")
    if array.dtype == np.uint8:
        opaque = 255
    elif np.issubdtype(array.dtype, np.floating):
        array, opaque = array.astype(np.float32), 1.0
        if not np.isfinite(array).all():
            raise SceneError(f"texture {name!r}: pixels must be finite")
    else:
        raise SceneError(f"texture {name!r}: pixels must be uint8 or float, got {array.dtype}")
    texels = np.full((height, width, 4), opaque, array.dtype)
    texels[:, :, :3] = array[:, :, : 3 if channels >= 3 else 1]
    if channels in (2, 4):
        texels[:, :, 3] = array[:, :, channels - 1]
    texels.flags.writeable = False
    return texels
