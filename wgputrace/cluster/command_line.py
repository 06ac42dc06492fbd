"""`wgputrace render SCENE --ray ADDRESS` and `wgputrace render-frames FILE --ray ADDRESS`: one
progress bar over all batches or frames, with the whole cluster's samples per second and the live
workers, and a summary. `wgputrace.cli` parses the arguments and maps errors to exit statuses; Ctrl-C there
raises at once, which ends the workers (their queued tasks with them) and, for frames, keeps every
frame already written.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from importlib.metadata import version

from ..image_io import save_image
from ..provenance import NAMESPACE
from .progress import ClusterProgress


@contextmanager
def cluster_job(args: argparse.Namespace, unit: str) -> Iterator[dict[str, object]]:
    """The keyword arguments a job on the cluster takes from the command line besides the render's:
    the cluster's address, the most workers, and `progress`, which moves a tqdm bar of `unit`s on
    stderr."""
    from tqdm import tqdm

    with tqdm(unit=unit, desc=f"rendering {unit}s", file=sys.stderr, dynamic_ncols=True) as bar:

        def update(progress: ClusterProgress) -> None:
            bar.total = progress.total
            bar.update(progress.done - bar.n)
            bar.set_postfix_str(
                f"{progress.samples_per_second / 1e6:.2f} M samples/s, {progress.live_workers} workers live"
            )

        yield {"address": args.ray, "workers": args.workers, "progress": update}


def render_on_cluster(args: argparse.Namespace, scene, options: dict[str, object]) -> None:
    """`wgputrace render --ray`: the scene's image from the cluster, written with what made it;
    `options`: the Renderer's keyword arguments (seed, max_depth, accel, ...)."""
    from .batch_render import render_batches

    width, height = args.size
    spp = args.spp
    with cluster_job(args, "batch") as job:
        result = render_batches(scene, spp, width, height, batches=args.batches, tile=args.tile, **job, **options)
    values = {
        "version": version("wgputrace"),
        "scene": args.scene,
        "width": width,
        "height": height,
        "spp": spp,
        "seed": args.seed,
        "integrator": args.integrator,
        "sampler": args.sampler,
        "max_depth": args.max_depth,
        "accel": args.accel,
        "render_seconds": f"{result.wall_seconds:.3f}",
        "cluster": f"{len(result.batches)} batches of {len(result.tiles)} tiles on {len(result.workers)} workers "
        f"of the Ray cluster at {args.ray}",
    }
    metadata = {NAMESPACE + key: str(value) for key, value in values.items()}
    path = save_image(args.output, result.image, exposure=args.exposure, metadata=metadata, tonemap=args.tonemap)
    samples = spp * width * height
    adapters = sorted({worker.adapter for worker in result.workers})
    print(f"cluster          {args.ray}: {len(result.workers)} workers on {', '.join(adapters)}")
    tiles = f" of {len(result.tiles)} tiles" if len(result.tiles) > 1 else ""
    print(
        f"render           {spp} spp at {width}x{height} in {len(result.batches)} batches{tiles}, "
        f"{result.wall_seconds:.2f} s, {samples / result.wall_seconds / 1e6:.3f} M samples/s"
    )
    if result.lost_workers:
        print(
            f"lost workers     {result.lost_workers}; {result.resubmitted_batches} batches ran again elsewhere "
            "(the image is the one without the loss)"
        )
    if result.dropped_samples:
        print(f"dropped          {result.dropped_samples} samples were non-finite or cut short and counted as zero")
    print(f"wrote            {path} ({spp} spp)")


def render_frames_on_cluster(args: argparse.Namespace, options: dict[str, object]) -> None:
    """`wgputrace render-frames`: every frame not written yet, each file as it finishes; `options`:
    the Renderer's keyword arguments (seed, max_depth, accel, ...)."""
    from .frames import render_frames

    width, height = args.size
    with cluster_job(args, "frame") as job:
        report = render_frames(
            args.scene,
            args.frames,
            args.output,
            args.spp,
            width,
            height,
            exposure=args.exposure,
            tonemap=args.tonemap,
            **job,
            **options,
        )
    if report.skipped:
        print(f"skipped          {len(report.skipped)} frames written before ({report.skipped[0]} ...)")
    if report.lost_workers:
        print(f"lost workers     {report.lost_workers}; their frames ran again elsewhere")
    print(f"wrote            {len(report.written)} frames ({args.spp} spp, {width}x{height})")
