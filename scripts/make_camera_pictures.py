"""The pictures of docs/guide/cameras_and_tonemapping.md, made again from the built-in scenes:

    PYTHONPATH=. python scripts/make_camera_pictures.py            # all three, into docs/images/
    PYTHONPATH=. python scripts/make_camera_pictures.py --spp 16   # a quick look

- depth_of_field.png: the `depth_of_field` scene through its thin lens, focused on the green sphere;
- panorama_360.png: `sunlit_spheres` seen by an EquirectangularCamera standing before the spheres;
- tone_curves.png: `sunlit_spheres` (its lit sides up to 35 times white) through clip, Khronos PBR
  Neutral, AgX and ACES, side by side, each labelled.

The two single renders carry their provenance (`wgputrace info FILE`); every render's time is printed.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

import wgputrace as wt
from wgputrace.image_io import TONEMAP_OPERATORS, srgb8, tonemap
from wgputrace.provenance import render_metadata, tone_metadata
from wgputrace.testing.checkout import checkout_root

PICTURES = checkout_root() / "docs" / "images"
# The 360 camera's place: before the spheres, a little above their centres, looking at them.
PANORAMA_POSITION = (-0.3, 0.6, -1.5)
PANORAMA_FORWARD = (0.0, 0.0, 1.0)
# The tone curves are shown at half a stop down: the clipped picture's lit ground is then not all
# white, so what clipping does to the spheres is what differs.
TONE_EXPOSURE = -0.5
LABEL_HEIGHT = 18
LABELS = {"clip": "clip", "pbr_neutral": "Khronos PBR Neutral", "agx": "AgX", "aces": "ACES (Hill)"}


def rendered(scene: wt.Scene, name: str, size: tuple[int, int], spp: int) -> tuple[np.ndarray, dict[str, str]]:
    renderer = wt.Renderer(scene, *size, seed=1)
    start = time.perf_counter()
    renderer.render(spp)
    seconds = time.perf_counter() - start
    print(f"{name}: {spp} spp at {size[0]}x{size[1]} in {seconds:.1f} s", file=sys.stderr)
    return renderer.image(), render_metadata(renderer, name, renderer.stats.render_seconds)


def depth_of_field(spp: int) -> Path:
    image, metadata = rendered(wt.load_scene("depth_of_field"), "depth_of_field", (480, 320), spp)
    metadata |= tone_metadata("agx", 0.5, 0.5)
    return wt.save_image(PICTURES / "depth_of_field.png", image, exposure=0.5, tonemap="agx", metadata=metadata)


def panorama(spp: int) -> Path:
    scene = wt.load_scene("sunlit_spheres")
    scene.camera = wt.EquirectangularCamera(PANORAMA_POSITION, PANORAMA_FORWARD, (0.0, 1.0, 0.0))
    image, metadata = rendered(scene, "sunlit_spheres", (640, 320), spp)
    metadata |= tone_metadata("agx", 0.0, 0.0)
    return wt.save_image(PICTURES / "panorama_360.png", image, tonemap="agx", metadata=metadata)


def labelled(pixels: np.ndarray, label: str) -> np.ndarray:
    """`pixels` (8-bit RGB) with `label` in a black band above them."""
    band = Image.new("RGB", (pixels.shape[1], LABEL_HEIGHT))
    ImageDraw.Draw(band).text((6, 3), label, fill=(255, 255, 255))
    return np.concatenate([np.asarray(band), pixels], axis=0)


def tone_curves(spp: int) -> Path:
    image, _ = rendered(wt.load_scene("sunlit_spheres"), "sunlit_spheres", (360, 240), spp)
    panels = [
        labelled(srgb8(tonemap(image, operator, TONE_EXPOSURE)), LABELS[operator]) for operator in TONEMAP_OPERATORS
    ]
    gap = np.zeros((panels[0].shape[0], 4, 3), np.uint8)
    rows = [np.concatenate([panels[0], gap, panels[1]], axis=1), np.concatenate([panels[2], gap, panels[3]], axis=1)]
    grid = np.concatenate([rows[0], np.zeros((4, rows[0].shape[1], 3), np.uint8), rows[1]], axis=0)
    path = PICTURES / "tone_curves.png"
    Image.fromarray(grid).save(path, optimize=True)
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel (default 256)")
    args = parser.parse_args(argv)
    PICTURES.mkdir(parents=True, exist_ok=True)
    for path in (depth_of_field(args.spp), panorama(args.spp), tone_curves(args.spp)):
        print(f"wrote {path} ({path.stat().st_size / 1024:.0f} KB)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
