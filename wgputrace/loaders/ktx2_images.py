"""KTX2 images with a Basis Universal payload (glTF's KHR_texture_basisu, gltfpack's `-tc`), both of
its codecs (ETC1S and UASTC), transcoded to RGBA8 through opengl-basisu, the `ktx2` extra: an
alpha-quality binding of Binomial's basis_universal transcoder in an 850 KB wheel (no Linux aarch64
wheel). Imported on first use, so that the loaders work without it and say how to get it.

Level 0 of the file's one image is read; the transfer function its header declares is not used:
the texture slot says whether texels are sRGB, as for PNG and JPEG.
"""

from __future__ import annotations

import struct

import numpy as np

BASISU_EXTENSION = "KHR_texture_basisu"
KTX2_INSTALL_HINT = 'pip install "wgputrace[ktx2]"'
# KTX2's file identifier; pixelWidth and pixelHeight follow vkFormat and typeSize (KTX2 spec 3.1)
KTX2_IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
KTX2_SIZE_OFFSET = len(KTX2_IDENTIFIER) + 8


class Ktx2Missing(ImportError):
    """opengl-basisu is not installed: the message says how to install it."""


class Ktx2Error(ValueError):
    """Bytes that are no KTX2 image the transcoder decodes to RGBA8."""


def ktx2_available() -> bool:
    try:
        import opengl_basisu  # noqa: F401
    except ImportError:
        return False
    return True


def is_ktx2(data: bytes) -> bool:
    return bytes(data[: len(KTX2_IDENTIFIER)]) == KTX2_IDENTIFIER


def ktx2_size(data: bytes) -> tuple[int, int] | None:
    """(width, height) from a KTX2 header, read before anything is decoded, or None if too short."""
    if len(data) < KTX2_SIZE_OFFSET + 8:
        return None
    return struct.unpack_from("<II", data, KTX2_SIZE_OFFSET)


def decode_ktx2(data: bytes) -> np.ndarray:
    """uint8 (H, W, 4) pixels of a KTX2 file's first image, level 0, or Ktx2Error / Ktx2Missing."""
    try:
        import opengl_basisu
    except ImportError:
        raise Ktx2Missing(f"a KTX2 image needs opengl-basisu: {KTX2_INSTALL_HINT}") from None
    try:
        texture = opengl_basisu.open(bytes(data))
        if texture.faces != 1 or texture.is_array:
            raise Ktx2Error(f"a KTX2 with {texture.faces} faces and {texture.layers} layers; a texture has one image")
        image = texture.transcode(opengl_basisu.Target.RGBA8)
    except opengl_basisu.BasisuError as error:
        raise Ktx2Error(f"not a readable KTX2/Basis Universal image: {error}") from None
    return np.ascontiguousarray(image.data, np.uint8).reshape(texture.height, texture.width, 4)
