"""Writing KTX2 (Basis Universal) textured glTF files for the loader tests: pixels encoded with
alktx2's encoder (basis_universal's, in the test extra), stored as gltfpack's `-tc` stores them:
an image whose mimeType is image/ktx2, named only by the texture's KHR_texture_basisu source.
"""

from __future__ import annotations

import numpy as np

from ..loaders.ktx2_images import BASISU_EXTENSION
from .gltf_files import add_view, textured_square

# The codecs glTF's KHR_texture_basisu allows, by the name alktx2 gives them.
CODECS = ("etc1s", "uastc")
# The encoder's quality setting for each: ETC1S's highest (1..255), UASTC's (0..100) mid-level pack
QUALITY = {"etc1s": 255, "uastc": 100}


def encode_ktx2(pixels: np.ndarray, codec: str, srgb: bool) -> bytes:
    """uint8 (H, W, 4) RGBA pixels as a single-level KTX2 file in `codec`, its header declaring
    the sRGB or linear transfer function."""
    import alktx2

    height, width, _ = pixels.shape
    return alktx2.encode_raw_rgba_to_ktx2(
        np.ascontiguousarray(pixels, np.uint8).tobytes(),
        width,
        height,
        has_alpha=bool((pixels[..., 3] < 255).any()),
        codec=codec,
        quality=QUALITY[codec],
        srgb=srgb,
        linear=not srgb,
        threads=1,
    )


def ktx2_textured_square(ktx2: bytes, material: dict | None = None) -> tuple[dict, bytes]:
    """`gltf_files.textured_square` (every slot reading texture 0) whose texture 0 has no `source`
    of its own, only KHR_texture_basisu's: the image `ktx2` in the binary buffer."""
    document, blob = textured_square("bufferView", material=material)
    view, blob = add_view(document, blob, ktx2)
    document["images"] = [{"bufferView": view, "mimeType": "image/ktx2"}]
    texture = document["textures"][0]
    del texture["source"]
    texture["extensions"] = {BASISU_EXTENSION: {"source": 0}}
    document["extensionsUsed"] = [*document["extensionsUsed"], BASISU_EXTENSION]
    document["extensionsRequired"] = [BASISU_EXTENSION]
    return document, blob
