"""The command line's arguments: those `wgputrace render` and the viewer (`wgputrace view`, app.py)
share, so both read a scene and a size the same way, and the viewer's own; the argparse types that
refuse values the renderer cannot use (a negative spp, a NaN exposure) before anything starts; and
the parser whose errors are one line."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from .image_io import FORMATS as IMAGE_FORMATS
from .loaders import FORMATS as SCENE_FORMATS
from .scenes import BUILTIN_SCENES, DEFAULT_SCENE


class UsageError(Exception):
    """The command line is wrong; the message is one line naming the command and pointing at its --help."""


class OneLineParser(argparse.ArgumentParser):
    """argparse's parser, whose errors raise UsageError instead of printing usage and an error on
    two lines; its subcommands' parsers are of this class too."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: error: {message} (see {self.prog} --help)")


def parse_size(text: str) -> tuple[int, int]:
    """argparse type for WIDTHxHEIGHT (also used by the benchmarks)."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 512x512, got {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be positive, got {text!r}")
    return width, height


def positive_int(text: str) -> int:
    """argparse type for counts that must be at least 1 (samples per pixel)."""
    value = _parse(int, text, "an integer")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text!r}")
    return value


def positive_float(text: str) -> float:
    """argparse type for finite numbers above 0 (seconds, exposure, frames per second)."""
    value = _parse(float, text, "a number")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a finite number above 0, got {text!r}")
    return value


def max_depth(text: str) -> int:
    """argparse type for Mitsuba's max_depth: at least 1, or -1 for no limit."""
    value = _parse(int, text, "an integer")
    if value < 1 and value != -1:
        raise argparse.ArgumentTypeError(f"must be at least 1, or -1 for no limit, got {text!r}")
    return value


def _parse(kind: type, text: str, what: str):
    try:
        return kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None


def image_path(text: str) -> Path:
    """argparse type for an output image: its extension must name a format save_image writes, so
    a wrong one is refused before the render, not after it."""
    path = Path(text)
    if path.suffix.lower() not in IMAGE_FORMATS:
        raise argparse.ArgumentTypeError(
            f"{text}: unknown image format {path.suffix.lower()!r}; use one of {', '.join(IMAGE_FORMATS)}"
        )
    return path


def add_debug_argument(parser: argparse.ArgumentParser, *, default: object = False) -> None:
    """--debug: errors show their traceback. Given to the program and to each command (there with
    default=argparse.SUPPRESS, so a command's parser does not reset what the program's set)."""
    parser.add_argument("--debug", action="store_true", default=default, help="show tracebacks of errors")


def add_scene_arguments(parser: argparse.ArgumentParser, *, size: tuple[int, int], scene_note: str = "") -> None:
    """SCENE (as wgputrace.load_scene reads it), --size, --max-depth, --seed and --exposure."""
    parser.add_argument(
        "scene",
        nargs="?",
        default=DEFAULT_SCENE,
        help=f"a built-in scene ({', '.join(BUILTIN_SCENES)}) or a scene file ({' '.join(SCENE_FORMATS)}; "
        f"a .py file defines scene()){scene_note}",
    )
    parser.add_argument("--size", type=parse_size, default=size, help=f"WIDTHxHEIGHT (default {size[0]}x{size[1]})")
    parser.add_argument(
        "--max-depth", type=max_depth, default=9, help="path vertices, Mitsuba's meaning; -1 = no limit"
    )
    parser.add_argument("--seed", type=int, default=1, help="random seed: same seed and adapter, same image")
    parser.add_argument("--exposure", type=positive_float, default=1.0, help="multiplies radiance before tone mapping")


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """The viewer's arguments, for app.py and `wgputrace view`."""
    add_scene_arguments(parser, size=(640, 480), scene_note="; files reload on change")
    parser.add_argument("--fps", type=positive_float, default=20.0, help="target frames per second (default 20)")
    parser.add_argument("--filter", action="store_true", help="start with the pre-convergence filter on (key N)")
    parser.add_argument("--no-info", action="store_true", help="start with the text overlay hidden (key Tab)")
    parser.add_argument("--screenshots", type=Path, default=Path.cwd(), help="folder for screenshots (key P)")
