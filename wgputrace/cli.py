"""Command line: `wgputrace render` (headless, to PNG/EXR/NPY; on a Ray cluster with --ray),
`wgputrace render-frames` (an animation's frames on a Ray cluster), `wgputrace info [FILE]` (the
adapter; an image's provenance; a scene file's cameras) and `wgputrace view` (the window). The benchmarks live in the checkout: `python -m bench`.

Every error is one line on stderr (`--debug` adds its traceback). Exit status: 0 done; 2 bad use
(arguments, scene, more than the device allows); 1 a failure while rendering or writing; 130 or
143 stopped by SIGINT or SIGTERM. The first signal stops a render after the dispatch in flight and
writes the samples done; a second aborts, writing nothing. On a cluster the first ends the workers
at once (render-frames keeps the frames it wrote); a worker's failure is status 1, naming it.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from .cli_arguments import (
    OneLineParser,
    UsageError,
    add_cluster_arguments,
    add_debug_argument,
    add_frames_arguments,
    add_method_arguments,
    add_scene_arguments,
    add_view_arguments,
    apply_lighting,
    frames_address,
    image_path,
    method_options,
    positive_float,
    positive_int,
)
from .image_io import FORMATS, exposure_ev, save_image
from .loaders import FORMATS as SCENE_FORMATS
from .loaders import load_scene
from .loaders.camera_choice import camera_lines
from .render.interrupts import Aborted, Interrupted, deferred_signals, exit_status, signal_name, signals_abort

if TYPE_CHECKING:
    import numpy as np

    from .render import Renderer

EXIT_FAILURE, EXIT_BAD_USE = 1, 2
DEFAULT_SPP = 64
# What stops a render early and is written into the file's metadata (stopped_by) and the summary
STOPPING_SIGNALS = (signal.SIGINT, signal.SIGTERM)
TIME_LIMIT = "time limit"
# What --denoise adds to the provenance metadata (provenance.NAMESPACE keys): the denoiser, and the
# OIDN device it ran on.
DENOISED_BY = "oidn"


def argument_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="wgputrace",
        description="Monte Carlo path tracer on WGSL compute shaders.",
        epilog="The benchmarks run from a source checkout: python -m bench",
    )
    add_debug_argument(parser)
    commands = parser.add_subparsers(dest="command", required=True)

    render = commands.add_parser(
        "render",
        help="render a scene headless to .png, .exr or .npy",
        description="Ctrl-C (SIGINT) or SIGTERM stops after the dispatch in flight and writes the samples done "
        "(exit 130 or 143); a second one aborts at once and writes nothing.",
    )
    add_scene_arguments(render, size=(512, 512))
    render.add_argument(
        "--spp",
        type=positive_int,
        help=f"samples per pixel (default {DEFAULT_SPP}; with --time-limit, at most this many)",
    )
    render.add_argument(
        "--time-limit",
        type=positive_float,
        metavar="SECONDS",
        help="render until SECONDS are spent (at least one sample per pixel)",
    )
    add_method_arguments(render)
    render.add_argument(
        "--denoise",
        action="store_true",
        help="denoise the image with Intel Open Image Denoise, guided by albedo and normal (needs "
        'pip install "wgputrace[denoise]"); an .exr keeps the raw image and the guides as layers',
    )
    render.add_argument(
        "-o", "--output", type=image_path, default="render.png", help=f"output file ({', '.join(FORMATS)})"
    )
    add_cluster_arguments(render, batches=True)

    frames = commands.add_parser(
        "render-frames",
        help="render an animation's frames (a .py file defining scene(frame)) on a Ray cluster, or in order here "
        "with --temporal",
        description="One task per frame; each file is written atomically as its frame finishes, and frames "
        "whose file exists are skipped, so the same command resumes an interrupted job. Ctrl-C (SIGINT) "
        "ends the workers at once and keeps the frames written. With --temporal the frames are rendered in order on "
        "this machine, every pixel keeping its samples from frame to frame, and all are written.",
    )
    add_frames_arguments(frames, default_spp=DEFAULT_SPP)

    info = commands.add_parser(
        "info", help="print the adapter, backend and limits; how an image file was made; or a scene file's cameras"
    )
    info.add_argument(
        "file",
        nargs="?",
        type=Path,
        help=f"an image wgputrace wrote: print its metadata; a scene file ({' '.join(SCENE_FORMATS)}): "
        "list its cameras (the names and indices --camera takes)",
    )
    view = commands.add_parser("view", help="open the interactive viewer (a window; see README)")
    add_view_arguments(view)
    for command in (render, frames, info, view):
        add_debug_argument(command, default=argparse.SUPPRESS)
    return parser


def _check_output(path: Path) -> None:
    """Refuse an output that cannot be written before rendering for it (save_image makes the
    folders that are missing)."""
    if path.is_dir():
        raise ValueError(f"{path}: is a folder; give an image file name")
    existing = next(folder for folder in (path.parent, *path.parent.parents) if folder.exists())
    if not existing.is_dir():
        raise ValueError(f"{path}: cannot be written, {existing} is a file")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(f"{path}: cannot be written, {existing} is not writable")


def _denoiser_device() -> str:
    """The OIDN device --denoise will run on; without the denoise extra, a ValueError (bad use)
    saying how to install it and what works without it."""
    from .denoise import DenoiserMissing, denoiser_device

    try:
        return denoiser_device()
    except DenoiserMissing as missing:
        raise ValueError(
            f"--denoise: {missing}; without it, the viewer's a-trous filter (wgputrace view --filter) "
            "is the dependency-free choice"
        ) from None


@dataclass
class _Denoised:
    """The renderer's image denoised, what an EXR keeps beside it as layers, and the denoiser's time."""

    image: np.ndarray
    layers: dict[str, np.ndarray]
    seconds: float


def _denoised(renderer: Renderer) -> _Denoised:
    from .denoise import denoise

    raw, guides = renderer.image(), renderer.guides()
    start = time.perf_counter()
    image = denoise(raw, **guides)
    return _Denoised(image, {"raw": raw, **guides}, time.perf_counter() - start)


def _check_cluster_options(args: argparse.Namespace) -> None:
    """Refuse what a render on a cluster does not do, and cluster options without --ray."""
    if args.ray is None:
        cluster_only = (("--batches", args.batches), ("--workers", args.workers), ("--tile", args.tile))
        given = [option for option, value in cluster_only if value]
        if given:
            raise ValueError(f"{' and '.join(given)}: only with --ray ADDRESS (a Ray cluster to render on)")
        return
    refused = [option for option, value in (("--time-limit", args.time_limit), ("--denoise", args.denoise)) if value]
    if refused:
        raise ValueError(f"{' and '.join(refused)}: not with --ray (a cluster render takes --spp)")


def _renderer_options(args: argparse.Namespace) -> dict[str, object]:
    """The Renderer's keyword arguments from the command line but the image size: the seed, the
    path depth and how it traces (method_options); a render on a cluster passes them on."""
    return {"seed": args.seed, "max_depth": args.max_depth, **method_options(args)}


def _render_on_cluster(args: argparse.Namespace) -> int:
    from .cluster.command_line import render_on_cluster

    scene = load_scene(args.scene, camera=args.camera)
    lighting = apply_lighting(scene, args)
    if lighting is not None:
        print(f"lighting         {lighting}")
    args.spp = DEFAULT_SPP if args.spp is None else args.spp
    render_on_cluster(args, scene, _renderer_options(args))
    return 0


def _render_frames(args: argparse.Namespace) -> int:
    from .cluster.command_line import render_frames_on_cluster

    args.ray = frames_address(args)
    if args.temporal:
        return _render_temporal_frames(args)
    args.spp = DEFAULT_SPP if args.spp is None else args.spp
    try:
        render_frames_on_cluster(args, _renderer_options(args))
    except Aborted as abort:
        _tell(
            f"wgputrace: {signal_name(abort.signal)}: stopped; the frames written are kept and the same command "
            "renders the rest"
        )
        return exit_status(abort.signal)
    return 0


def _render_temporal_frames(args: argparse.Namespace) -> int:
    """render-frames --temporal: the frames in order on one renderer, a line per frame written."""
    from .temporal_frames import render_temporal_frames

    width, height = args.size
    budget = None if args.frame_ms is None else args.frame_ms / 1000.0
    shown = "filtered" if args.filtered else "accumulated"
    upscaled = f", upsampled {args.upscale}x" if args.upscale != 1 else ""

    def progress(frame) -> None:
        print(f"frame {frame.frame:>6}  {frame.samples_per_pixel} spp  {1000 * frame.seconds:8.1f} ms  {frame.path}")

    try:
        done = render_temporal_frames(
            args.scene,
            args.frames,
            args.output,
            width,
            height,
            spp=args.spp,
            budget=budget,
            filtered=args.filtered,
            upscale=args.upscale,
            exposure=args.exposure,
            tonemap=args.tonemap,
            progress=progress,
            **_renderer_options(args),
        )
    except Interrupted as stop:
        _tell(f"wgputrace: {signal_name(stop.signal)}: stopped; the frames written are kept")
        return exit_status(stop.signal)
    print(f"wrote            {len(done)} frames ({shown}, {width}x{height}, temporal{upscaled})")
    return 0


def _render(args: argparse.Namespace) -> int:
    from .gpu.device import gpu
    from .provenance import NAMESPACE, render_metadata, tone_metadata
    from .render import Renderer

    _check_output(args.output)
    _check_cluster_options(args)
    if args.ray is not None:
        return _render_on_cluster(args)
    denoiser_device = _denoiser_device() if args.denoise else None
    load_start = time.perf_counter()
    scene = load_scene(args.scene, camera=args.camera)
    lighting = apply_lighting(scene, args)
    load_seconds = time.perf_counter() - load_start
    if lighting is not None:
        print(f"lighting         {lighting}")
    width, height = args.size
    context = gpu()
    start = time.perf_counter()
    renderer = Renderer(scene, width, height, guides=args.denoise, **_renderer_options(args))
    setup_seconds = time.perf_counter() - start
    spp = DEFAULT_SPP if args.spp is None and args.time_limit is None else args.spp
    path = denoised = None
    keeps_layers = args.output.suffix.lower() == ".exr"
    # From here a first SIGINT or SIGTERM ends the render after the dispatch in flight and the
    # samples done are still written (and denoised); a second aborts at once, the denoiser included,
    # and save_image leaves no partial file.
    with deferred_signals(*STOPPING_SIGNALS) as deferral:
        try:
            stopped_by = _render_with_progress(renderer, spp, args.time_limit)
            if renderer.samples_per_pixel:
                metadata = render_metadata(renderer, args.scene, renderer.stats.render_seconds, stopped_by=stopped_by)
                if denoiser_device is None:
                    image, layers = renderer.image(), None
                else:
                    denoised = _denoised(renderer)
                    image, layers = denoised.image, denoised.layers if keeps_layers else None
                    metadata |= {NAMESPACE + "denoised": DENOISED_BY, NAMESPACE + "denoiser_device": denoiser_device}
                # "auto" is measured on the image written: the denoised one where it is denoised
                exposure = exposure_ev(image, args.exposure)
                if args.output.suffix.lower() == ".png":
                    metadata |= tone_metadata(args.tonemap, args.exposure, exposure)
                path = save_image(
                    args.output, image, exposure=exposure, tonemap=args.tonemap, metadata=metadata, layers=layers
                )
        except Aborted as abort:
            _tell(f"wgputrace: second signal ({signal_name(abort.signal)}): aborted, {args.output} not written")
            return exit_status(abort.signal)
    stats = renderer.stats
    acceleration = renderer.records.acceleration
    print(f"adapter          {context.adapter_name}")
    print(
        f"scene            {args.scene}: {renderer.triangle_count:,} triangles, {len(renderer.records.materials)} materials, "
        f"loaded in {load_seconds:.2f} s"
    )
    textures = f", textures {renderer.gpu_texture_bytes:,} B" if renderer.gpu_texture_bytes else ""
    print(
        f"gpu memory       {renderer.gpu_bytes_per_triangle:.1f} B per triangle (triangles, BVH nodes, materials, "
        f"lights, vertex attributes; as allocated, spare capacity included){textures}"
    )
    print(
        f"acceleration     {args.accel}: {acceleration.node_count:,} nodes, depth {acceleration.depth}, "
        f"SAH cost {acceleration.sah_cost():.2f}, built in {acceleration.build_seconds * 1e3:.1f} ms"
    )
    print(f"setup            {setup_seconds:.2f} s (BVH, buffers, pipeline)")
    print(
        f"render           {stats.samples_per_pixel} spp at {width}x{height} in {stats.render_seconds:.2f} s, "
        f"{stats.samples_per_second * width * height / 1e6:.3f} M samples/s"
        + ("" if stopped_by is None else f", stopped by {stopped_by}")
    )
    if denoised is not None:
        print(
            f"denoised         Intel Open Image Denoise on {denoiser_device}, guided by albedo and normal, "
            f"in {denoised.seconds:.2f} s"
            + (f"; {args.output.name} keeps {', '.join(denoised.layers)} as layers" if keeps_layers else "")
        )
    if renderer.nonfinite_samples:
        print(f"non-finite       {renderer.nonfinite_samples} samples were NaN or infinite and counted as zero")
    if renderer.cut_short_samples:
        print(
            f"cut short        {renderer.cut_short_samples} samples ran out of the driver's loop budget "
            "and were counted as zero"
        )
    print(f"wrote            {path} ({stats.samples_per_pixel} spp)" if path else "wrote            nothing")
    if deferral.received is None:
        return 0
    held = f"{path} holds {stats.samples_per_pixel} spp" if path else f"no sample finished, {args.output} not written"
    _tell(f"wgputrace: {signal_name(deferral.received)}: stopped, {held}")
    return exit_status(deferral.received)


def _render_with_progress(renderer: Renderer, spp: int | None, seconds: float | None) -> str | None:
    """Render `spp` samples per pixel or for `seconds` under a progress bar; what stopped the render
    before `spp` (SIGINT, SIGTERM, the time limit), or None."""
    from tqdm import tqdm

    pixels = renderer.width * renderer.height
    with tqdm(total=spp, unit="spp", desc="rendering", file=sys.stderr, dynamic_ncols=True) as bar:

        def progress(samples: int) -> None:
            bar.update(samples)
            bar.set_postfix_str(f"{renderer.stats.samples_per_second * pixels / 1e6:.2f} M samples/s")

        try:
            renderer.render(spp, progress, seconds=seconds)
        except Interrupted as stop:
            stopped_by = signal_name(stop.signal)
        else:
            stopped_by = None if seconds is None else TIME_LIMIT
    return None if spp is not None and renderer.samples_per_pixel >= spp else stopped_by


def _info(args: argparse.Namespace) -> int:
    if args.file is None:
        from .gpu.device import describe

        print(json.dumps(describe(), indent=2))
    elif args.file.suffix.lower() in SCENE_FORMATS:
        _print_cameras(args.file)
    else:
        from .provenance import format_metadata, read_metadata

        print(format_metadata(read_metadata(args.file)))
    return 0


def _print_cameras(path: Path) -> None:
    """The cameras scene file `path` brings, one line each, as --camera chooses them."""
    scene = load_scene(path)
    count = len(scene.cameras)
    print(f"{path}: {scene.triangle_count:,} triangles, {count} camera{'' if count == 1 else 's'}")
    if scene.cameras:
        print("\n".join(camera_lines(scene.cameras)))
    else:
        print(f"  no camera of its own: framed automatically ({scene.camera.description()})")


def _run(args: argparse.Namespace) -> int:
    if args.command == "view":
        from .app import run  # the viewer's window and GPU code load only when it runs

        return run(args)
    if args.command == "render-frames":
        return _render_frames(args)
    return _render(args) if args.command == "render" else _info(args)


def _tell(message: str) -> None:
    """Print `message` to stderr on one line (wgpu's errors, and names a user typed, may hold line breaks)."""
    print("; ".join(line.strip() for line in message.splitlines() if line.strip()), file=sys.stderr)


def _failure(error: Exception) -> tuple[int, str]:
    """The exit status and message for an error that ended a command."""
    from .gpu.device import DeviceLimitError

    text = str(error) or type(error).__name__
    if isinstance(error, ValueError | DeviceLimitError):  # SceneLoadError is a ValueError
        return EXIT_BAD_USE, text
    # GpuFailure and the cluster's WorkerFailed are RuntimeErrors, ClusterUnreachable an OSError,
    # RayMissing an ImportError (its message says how to install Ray)
    if isinstance(error, RuntimeError | OSError | MemoryError | ImportError):
        return EXIT_FAILURE, text
    return EXIT_FAILURE, f"internal error: {type(error).__name__}: {text} (--debug shows where)"


def main(argv: list[str] | None = None) -> int:
    """Run the command line `argv` (default sys.argv[1:]); returns the exit status."""
    debug = False
    # until a render defers them, SIGINT and SIGTERM end a command at once, with a one-line message
    with signals_abort(*STOPPING_SIGNALS):
        try:
            args = argument_parser().parse_args(argv)
            debug = args.debug
            return _run(args)
        except UsageError as error:
            _tell(str(error))
            return EXIT_BAD_USE
        except SystemExit as done:  # --help
            return 0 if done.code is None else int(done.code)
        except Aborted as abort:
            _tell(f"wgputrace: {signal_name(abort.signal)}: aborted")
            return exit_status(abort.signal)
        except Exception as error:
            if debug:
                raise
            status, message = _failure(error)
            _tell(f"wgputrace: error: {message}")
            return status
