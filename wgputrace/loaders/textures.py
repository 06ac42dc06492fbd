"""Textures for the scene loaders: image bytes (PNG, JPEG or anything else Pillow reads, and KTX2
through `ktx2_images`) decoded into the uint8 pixel arrays a Texture takes, with a one-line reason where they cannot be; and which
of a material's parameters are textures (a shape then needs texture coordinates).

The size is checked from the image's header (read here for PNG and JPEG, else Pillow's), before
any pixel is decoded, so a file claiming 100,000 pixels a side costs nothing. Images larger than
the GPU allows but within Texture's own limit load, and the renderer downscales them with a
warning (`fitted_texels`).
"""

from __future__ import annotations

import io
import struct
import zlib

import numpy as np
from PIL import Image, UnidentifiedImageError

from ..scene.texture import MAX_TEXTURE_SIDE
from .ktx2_images import Ktx2Error, Ktx2Missing, decode_ktx2, is_ktx2, ktx2_size

# Pillow modes kept as they are; any other is converted to RGBA (palettes, CMYK, 16-bit grey...)
KEPT_MODES = ("L", "LA", "RGB", "RGBA")
SIXTEEN_BIT_MODES = ("I;16", "I;16B", "I;16L", "I")
SIXTEEN_BIT_MAX = 65535
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# JPEG's start-of-frame markers (SOF0..SOF15 less DHT, JPG and DAC, which share the range)
JPEG_FRAME_MARKERS = set(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}


class ImageError(Exception):
    """Bytes that are no usable texture image. The message says why; the caller names the file
    and the field the bytes came from."""


def decode_image(data: bytes) -> np.ndarray:
    """uint8 (H, W, C) pixels, C in 1..4, of an encoded image, or ImageError."""
    if is_ktx2(data):
        return _ktx2_pixels(data)
    size = _png_size(data) or _jpeg_size(data)
    if size:  # before Pillow, which calls a 0-pixel PNG unidentified and a huge one a bomb
        _check_size(*size)
    try:
        with Image.open(io.BytesIO(data)) as image:
            _check_size(*image.size)
            image.load()
            return _pixels(image)
    except UnidentifiedImageError:
        raise ImageError("not an image Pillow reads (PNG, JPEG, ...)") from None
    except Image.DecompressionBombError as error:
        raise ImageError(f"too many pixels to decode safely ({error})") from None
    except (OSError, SyntaxError, ValueError, EOFError, struct.error, zlib.error) as error:
        # Pillow reports corrupt and truncated files through all of these
        raise ImageError(f"not a readable image: {error or type(error).__name__}") from None


def _ktx2_pixels(data: bytes) -> np.ndarray:
    size = ktx2_size(data)
    if size:
        _check_size(*size)
    try:
        return decode_ktx2(data)
    except (Ktx2Error, Ktx2Missing) as error:
        raise ImageError(str(error)) from None


def _png_size(data: bytes) -> tuple[int, int] | None:
    """(width, height) from a PNG's IHDR chunk, or None if `data` is no PNG."""
    if data[:8] != PNG_SIGNATURE or data[12:16] != b"IHDR" or len(data) < 24:
        return None
    return struct.unpack(">II", data[16:24])


def _jpeg_size(data: bytes) -> tuple[int, int] | None:
    """(width, height) from a JPEG's first start-of-frame segment, or None if none is found."""
    if data[:2] != b"\xff\xd8":
        return None
    offset = 2
    while offset + 9 <= len(data) and data[offset] == 0xFF:
        marker = data[offset + 1]
        (length,) = struct.unpack(">H", data[offset + 2 : offset + 4])
        if marker in JPEG_FRAME_MARKERS:
            height, width = struct.unpack(">HH", data[offset + 5 : offset + 9])
            return width, height
        offset += 2 + length
    return None


def _check_size(width: int, height: int) -> None:
    if not (0 < width <= MAX_TEXTURE_SIDE and 0 < height <= MAX_TEXTURE_SIDE):
        raise ImageError(f"{width} x {height} pixels: each side must be 1 to {MAX_TEXTURE_SIDE:,}")


def _pixels(image: Image.Image) -> np.ndarray:
    if image.mode in SIXTEEN_BIT_MODES:  # 16-bit grey PNG: scale, where a conversion would clip
        values = np.asarray(image, np.float64) * (255.0 / SIXTEEN_BIT_MAX)
        return np.clip(np.rint(values), 0, 255).astype(np.uint8)[:, :, None]
    if image.mode not in KEPT_MODES:
        image = image.convert("RGBA")
    pixels = np.asarray(image, np.uint8)
    return pixels[:, :, None] if pixels.ndim == 2 else pixels
