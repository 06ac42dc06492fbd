"""The command line's arguments: those `wgputrace render` and the viewer (`wgputrace view`, app.py)
share, so both read a scene and a size the same way, and the viewer's own."""

from __future__ import annotations

import argparse
from pathlib import Path

from .loaders import FORMATS
from .scenes import BUILTIN_SCENES, DEFAULT_SCENE


def parse_size(text: str) -> tuple[int, int]:
    """argparse type for WIDTHxHEIGHT (also used by the benchmarks)."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 512x512, got {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be positive, got {text!r}")
    return width, height


def add_scene_arguments(parser: argparse.ArgumentParser, *, size: tuple[int, int], scene_note: str = "") -> None:
    """SCENE (as wgputrace.load_scene reads it), --size, --max-depth, --seed and --exposure."""
    parser.add_argument(
        "scene",
        nargs="?",
        default=DEFAULT_SCENE,
        help=f"a built-in scene ({', '.join(BUILTIN_SCENES)}) or a scene file ({' '.join(FORMATS)}; "
        f"a .py file defines scene()){scene_note}",
    )
    parser.add_argument("--size", type=parse_size, default=size, help=f"WIDTHxHEIGHT (default {size[0]}x{size[1]})")
    parser.add_argument("--max-depth", type=int, default=9, help="path vertices, Mitsuba's meaning; -1 = no limit")
    parser.add_argument("--seed", type=int, default=1, help="random seed: same seed and adapter, same image")
    parser.add_argument("--exposure", type=float, default=1.0, help="multiplies radiance before tone mapping")


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """The viewer's arguments, for app.py and `wgputrace view`."""
    add_scene_arguments(parser, size=(640, 480), scene_note="; files reload on change")
    parser.add_argument("--fps", type=float, default=20.0, help="target frames per second (default 20)")
    parser.add_argument("--filter", action="store_true", help="start with the pre-convergence filter on (key N)")
    parser.add_argument("--no-info", action="store_true", help="start with the text overlay hidden (key Tab)")
    parser.add_argument("--screenshots", type=Path, default=Path.cwd(), help="folder for screenshots (key P)")
