"""Screenshot files: what the window shows as PNG and the linear image as EXR, numbered per viewer."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from ..image_io import save_image


class Screenshots:
    """Writes `wgputrace-<scene>-000.png` and `.exr`, then 001 and on, into `folder`."""

    def __init__(self, folder: Path, scene: str) -> None:
        self.folder = folder
        self.name = Path(scene).stem
        self.count = 0

    def save(self, pixels: np.ndarray, linear: np.ndarray) -> tuple[Path, Path]:
        """`pixels` (8-bit sRGB, as shown) as the next PNG, `linear` (float RGB) as its EXR."""
        self.folder.mkdir(parents=True, exist_ok=True)
        stem = self.folder / f"wgputrace-{self.name}-{self.count:03d}"
        self.count += 1
        png = stem.with_suffix(".png")
        Image.fromarray(pixels).save(png)
        return png, save_image(stem.with_suffix(".exr"), linear)
