"""The command line's arguments: those `wgputrace render` and the viewer (`wgputrace view`,
`python app.py`) share, so both read a scene, a size and its lighting the same way, and the
viewer's own; argparse types that refuse values the renderer cannot use (a negative spp, a NaN
exposure) before anything starts; the parser whose errors are one line; and `apply_lighting`,
which lights a loaded scene as --env, --env-intensity and --env-rotation say, or by the default
environment when it brings no light.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from .image_io import AUTO_EXPOSURE, DEFAULT_TONEMAP, TONEMAP_OPERATORS
from .image_io import FORMATS as IMAGE_FORMATS
from .integrators import integrator, integrator_names
from .kernels.sampler import DEFAULT_SAMPLER, SAMPLERS
from .loaders import FORMATS as SCENE_FORMATS
from .render.temporal_upsampling import UPSCALE_FACTORS, check_upscale
from .scenes import BUILTIN_SCENES, DEFAULT_SCENE

if TYPE_CHECKING:
    from .scene import Scene

# --env's word for no environment at all: black, even for a scene that brings no light (a file of
# that name is ./none)
NO_ENVIRONMENT = "none"
# The viewer's pictures while the camera moves (--preview): render_frame's frames, or today's reset preview.
TEMPORAL_PREVIEW, RESET_PREVIEW = "temporal", "reset"
PREVIEWS = (TEMPORAL_PREVIEW, RESET_PREVIEW)


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


def finite_float(text: str) -> float:
    """argparse type for any finite number (an angle in degrees, stops of exposure)."""
    value = _parse(float, text, "a number")
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def exposure_value(text: str) -> float | str:
    """argparse type for --exposure: stops (EV, any finite number) or AUTO_EXPOSURE."""
    if text == AUTO_EXPOSURE:
        return text
    try:
        return finite_float(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(
            f"must be a finite number of stops (EV) or {AUTO_EXPOSURE}, got {text!r}"
        ) from None


def environment_spec(text: str) -> str | tuple[float, float, float] | Path:
    """argparse type for --env: NO_ENVIRONMENT; a number or r,g,b, a constant radiance (finite,
    >= 0); otherwise the file of an environment map, which must exist (it is read when the scene
    is lit, so the viewer reads it again with each reload)."""
    if text == NO_ENVIRONMENT:
        return text
    parts = text.split(",")
    try:
        numbers = [float(part) for part in parts]
    except ValueError:
        path = Path(text)
        if not path.is_file():
            raise argparse.ArgumentTypeError(
                f"{text}: no such file; give an environment map (.exr, .hdr), a radiance (0.5 or r,g,b) "
                f"or {NO_ENVIRONMENT}"
            ) from None
        return path
    if len(numbers) not in (1, 3) or not all(math.isfinite(n) and n >= 0 for n in numbers):
        raise argparse.ArgumentTypeError(
            f"a constant radiance is one number or r,g,b, each finite and >= 0, got {text!r}"
        )
    return tuple(numbers * 3 if len(numbers) == 1 else numbers)


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


def add_image_arguments(parser: argparse.ArgumentParser, *, size: tuple[int, int]) -> None:
    """--size, --max-depth, --seed, --exposure and --tonemap: what every image a scene is rendered to takes."""
    parser.add_argument("--size", type=parse_size, default=size, help=f"WIDTHxHEIGHT (default {size[0]}x{size[1]})")
    parser.add_argument(
        "--max-depth", type=max_depth, default=9, help="path vertices, Mitsuba's meaning; -1 = no limit"
    )
    parser.add_argument("--seed", type=int, default=1, help="random seed: same seed and adapter, same image")
    parser.add_argument(
        "--exposure",
        type=exposure_value,
        default=0.0,
        metavar=f"EV|{AUTO_EXPOSURE}",
        help="stops of exposure before tone mapping (1 doubles the radiance; default 0); auto: the picture's "
        "log-average luminance to middle grey (the viewer: measured every frame, smoothed)",
    )
    parser.add_argument(
        "--tonemap",
        choices=TONEMAP_OPERATORS,
        default=DEFAULT_TONEMAP,
        help="the tone curve of a PNG and of the viewer: clip (the default, as Mitsuba's PNGs), Khronos PBR "
        "Neutral, AgX or ACES",
    )


def add_method_arguments(parser: argparse.ArgumentParser) -> None:
    """--accel, --integrator and --sampler: how a headless render traces its paths."""
    parser.add_argument("--accel", choices=("bvh", "flat"), default="bvh", help="BVH, or trac0r's flat box list")
    parser.add_argument(
        "--integrator",
        choices=integrator_names(),
        default="mis",
        help="direct light by BSDF sampling, light sampling, or both with MIS (default); bdpt: "
        "bidirectional paths, every connection weighed by MIS; restir: the first vertex resamples light "
        "candidates by their contribution (many lights)",
    )
    parser.add_argument(
        "--sampler",
        choices=SAMPLERS,
        default=DEFAULT_SAMPLER,
        help=f"the random numbers paths draw: Owen-scrambled Sobol points or independent ones (default {DEFAULT_SAMPLER})",
    )


def method_options(args: argparse.Namespace) -> dict[str, str]:
    """The Renderer's keyword arguments that add_method_arguments' options give."""
    return {"accel": args.accel, "integrator": args.integrator, "sampler": args.sampler}


def add_scene_arguments(parser: argparse.ArgumentParser, *, size: tuple[int, int], scene_note: str = "") -> None:
    """SCENE (as wgputrace.load_scene reads it), --camera, --size, --max-depth, --seed, --exposure and the
    lighting options (`apply_lighting` applies them)."""
    parser.add_argument(
        "scene",
        nargs="?",
        default=DEFAULT_SCENE,
        help=f"a built-in scene ({', '.join(BUILTIN_SCENES)}) or a scene file ({' '.join(SCENE_FORMATS)}; "
        f"a .py file defines scene()){scene_note}",
    )
    parser.add_argument(
        "--camera",
        metavar="NAME|INDEX",
        help="one of the scene file's own cameras, by name or index (wgputrace info FILE lists them; default: "
        "the first, or for a file without one a camera framing the whole scene)",
    )
    add_image_arguments(parser, size=size)
    parser.add_argument(
        "--env",
        type=environment_spec,
        metavar="PATH|VALUE",
        help="the environment lighting the scene, replacing its own: an .exr or .hdr map (Mitsuba's envmap "
        f"convention), a constant radiance (0.5, or r,g,b), or {NO_ENVIRONMENT} (black). Without it a scene "
        "that brings no light is lit by a constant radiance of 1",
    )
    parser.add_argument(
        "--env-intensity",
        type=positive_float,
        metavar="S",
        help="multiplies the environment's radiance (default: as the scene or --env has it, 1)",
    )
    parser.add_argument(
        "--env-rotation",
        type=finite_float,
        metavar="DEGREES",
        help="turns the environment map about +y, as Mitsuba's to_world rotate (default: as the scene or --env has it, 0)",
    )


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """The viewer's arguments, for `python app.py` and `wgputrace view`."""
    add_scene_arguments(parser, size=(640, 480), scene_note="; files reload on change")
    parser.add_argument("--fps", type=positive_float, default=20.0, help="target frames per second (default 20)")
    parser.add_argument("--filter", action="store_true", help="start with the pre-convergence filter on (key N)")
    parser.add_argument(
        "--denoise", action="store_true", help="start with the OIDN denoiser on (Shift+D; the denoise extra)"
    )
    parser.add_argument(
        "--preview",
        choices=PREVIEWS,
        default=TEMPORAL_PREVIEW,
        help="the picture while the camera moves: temporal (default) keeps every pixel's samples across frames "
        "and filters them (SVGF; key V shows how it is made); reset starts again at a reduced size on every move",
    )
    viewable = [name for name in integrator_names() if integrator(name).rows_entry is not None]
    parser.add_argument(
        "--integrator",
        choices=viewable,
        default="mis",
        help="how paths take their direct light, as for render (default mis); restir keeps each pixel's light "
        "reservoir from frame to frame while the camera moves; bdpt renders whole images only",
    )
    parser.add_argument("--no-info", action="store_true", help="start with the text overlay hidden (key Tab)")
    parser.add_argument("--screenshots", type=Path, default=Path.cwd(), help="folder for screenshots (key P)")


def ray_address(text: str) -> str:
    """argparse type for --ray: "auto", host:port or ray://host:port (checked when connecting)."""
    from .cluster.connection import AUTO, host_and_port

    if text != AUTO:
        try:
            host_and_port(text)
        except ConnectionError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
    return text


def frame_range(text: str) -> range:
    """argparse type for --frames: START:STOP[:STEP] (STOP excluded) or one frame."""
    from .cluster.frames import parse_frames

    try:
        return parse_frames(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def frame_pattern(text: str) -> str:
    """argparse type for render-frames' output: a file name with {frame} whose extension names a
    format save_image writes."""
    from .cluster.frames import frame_path

    try:
        first = frame_path(text, 0)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    image_path(str(first))
    return text


def add_cluster_arguments(
    parser: argparse.ArgumentParser, *, batches: bool, default_address: str | None = None
) -> None:
    """--ray ADDRESS and --workers N (and for one image, --batches N and --tile SIDE): rendering on a
    Ray cluster. `default_address` is what the help names as the default; --ray itself stays None
    when not given, so that a command can tell (`frames_address` puts the default in)."""
    parser.add_argument(
        "--ray",
        type=ray_address,
        metavar="ADDRESS",
        help="render on the Ray cluster at ADDRESS: host:port of its head, ray://host:port, or auto (the cluster "
        'this machine runs, else a new local one); needs pip install "wgputrace[ray]"'
        + (f" (default {default_address})" if default_address else ""),
    )
    parser.add_argument(
        "--workers", type=positive_int, metavar="N", help="at most N workers (default: one per GPU, else per CPU)"
    )
    if batches:
        parser.add_argument(
            "--batches",
            type=positive_int,
            metavar="N",
            help="split the samples into N batches (default 64, or one per sample where fewer); the image does not depend on "
            "how many workers render them",
        )
        parser.add_argument(
            "--tile",
            type=positive_int,
            metavar="SIDE",
            help="cut the image into tiles of at most SIDE x SIDE pixels, for an image larger than a worker's "
            "device allows (its error names the largest square it can render)",
        )


def add_frames_arguments(parser: argparse.ArgumentParser, *, default_spp: int) -> None:
    """render-frames' arguments: the animation file, its frames, the image, the output pattern, the
    cluster, and --temporal's frames in order on this machine (--frame-ms, --filtered, --upscale)."""
    parser.add_argument("scene", type=Path, help="a .py file defining scene(frame) -> wgputrace.Scene")
    parser.add_argument("--frames", type=frame_range, required=True, help="START:STOP[:STEP] (STOP excluded), or N")
    parser.add_argument(
        "--spp",
        type=positive_int,
        help=f"samples per pixel (default {default_spp}; with --temporal per frame, default 1, and with "
        "--frame-ms at most this many)",
    )
    parser.add_argument(
        "--temporal",
        action="store_true",
        help="render the frames in order on this machine's device, every pixel keeping its samples from frame to "
        "frame (Renderer.render_frame) instead of each frame on the cluster from scratch",
    )
    parser.add_argument(
        "--frame-ms",
        type=positive_float,
        metavar="MS",
        help="with --temporal: trace each frame for MS milliseconds (at least one sample per pixel)",
    )
    parser.add_argument(
        "--filtered", action="store_true", help="with --temporal: write the variance-guided filter's picture (SVGF)"
    )
    parser.add_argument(
        "--upscale",
        type=int,
        choices=(1, *UPSCALE_FACTORS),
        default=1,
        metavar="F",
        help="with --temporal: trace one pixel of every FxF block a frame and rebuild the others from their "
        f"histories (temporal upsampling, for adapters too slow for every pixel: one of {', '.join(map(str, UPSCALE_FACTORS))}; "
        "default 1, every pixel)",
    )
    add_image_arguments(parser, size=(512, 512))
    add_method_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        type=frame_pattern,
        default="frames/{frame:04d}.png",
        help="file of each frame, {frame} replaced by its number (default frames/{frame:04d}.png)",
    )
    from .cluster.connection import AUTO

    add_cluster_arguments(parser, batches=False, default_address=AUTO)


def frames_address(args: argparse.Namespace) -> str | None:
    """render-frames' cluster: --ray, else "auto" (the local cluster, or a new one); None with --temporal,
    which renders here and refuses the cluster options and the options that only --temporal takes without it."""
    from .cluster.connection import AUTO

    if not args.temporal:
        only_temporal = (("--frame-ms", args.frame_ms), ("--filtered", args.filtered), ("--upscale", args.upscale != 1))
        alone = [option for option, value in only_temporal if value]
        if alone:
            raise ValueError(f"{' and '.join(alone)}: only with --temporal (frames rendered in order on one renderer)")
        return AUTO if args.ray is None else args.ray
    refused = [option for option, value in (("--ray", args.ray), ("--workers", args.workers)) if value]
    if refused:
        raise ValueError(
            f"{' and '.join(refused)}: not with --temporal (its frames follow one another on one renderer, "
            "not on a cluster)"
        )
    try:
        integrator(args.integrator).check_gbuffer()
    except ValueError as error:
        raise ValueError(f"--temporal: {error}") from None
    if args.upscale != 1:
        try:
            check_upscale(args.upscale, *args.size)
        except ValueError as error:
            raise ValueError(f"--upscale: {error}") from None
    return None


def apply_lighting(scene: Scene, args) -> str | None:
    """Light `scene` as `args` (the parsed command line, or the viewer's options: anything with
    `env`, `env_intensity` and `env_rotation`) say: --env replaces the scene's environment (or
    removes it, with NO_ENVIRONMENT); without --env, a scene with no light at all (no emitting
    triangle, no environment, no light) gets the default environment, and the line returned says
    so (None otherwise); --env-intensity and --env-rotation then apply to the environment the scene
    has. A bad map, or those two without an environment, raise a one-line ValueError."""
    from .scene.lights.environment import DEFAULT_RADIANCE, Environment, default_environment

    note = None
    if args.env == NO_ENVIRONMENT:
        scene.environment = None
    elif isinstance(args.env, Path):
        scene.environment = Environment.from_file(args.env)
    elif args.env is not None:
        scene.environment = Environment(radiance=args.env)
    elif not scene.has_light():
        scene.environment = default_environment()
        note = (
            f"the scene brings no light: lit by the default environment, a constant radiance of {DEFAULT_RADIANCE:g} "
            f"(--env sets another, --env {NO_ENVIRONMENT} renders it black)"
        )
    for option, attribute, value in (
        ("--env-intensity", "intensity", args.env_intensity),
        ("--env-rotation", "rotation_degrees", args.env_rotation),
    ):
        if value is None:
            continue
        if scene.environment is None:
            why = (
                f"--env {NO_ENVIRONMENT} removed it"
                if args.env == NO_ENVIRONMENT
                else "the scene has none; --env gives one"
            )
            raise ValueError(f"{option} {value:g}: there is no environment to apply it to ({why})")
        setattr(scene.environment, attribute, value)
    return note
