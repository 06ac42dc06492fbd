"""Rendering on a Ray cluster (issue 19): where a batch's time goes, the speed of one and two
workers, and what those overheads give at 8, 64 and 512 GPUs.

    python -m bench.cluster
    python -m bench.cluster --size 128x128 --batch-spp 4 --batches 16 --repeats 3

Everything runs inside a network namespace of its own (`wgputrace.cluster.sandbox`: two Ray nodes
of one CPU each on 127.0.0.1), which needs root or unprivileged user namespaces. Every job's image
must first equal its batches rendered one after the other here and merged in order; then
`_measure` times each phase of a worker's life and jobs on one and two workers, and `model`
carries the measured overheads to 8, 64 and 512 workers (bench/README.md, "Rendering on a
cluster"). Writes bench/results/cluster_<adapter>.json and .png.
"""

from __future__ import annotations

import importlib
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import REPO_ROOT, Run
from bench.result_files import write_result

SEED = 1
MAX_DEPTH = 9
NODES = 2
CPUS_PER_NODE = 1
WORKER_COUNTS = (1, 2)
MODEL_WORKERS = (8, 64, 512)
# the model's image: the README's 512x512; overheads that grow with the pixels are scaled to it
MODEL_SIZE = (512, 512)
# The driver fetches every batch's image (float32 RGB at MODEL_SIZE) from its worker's node: over
# loopback here; the model adds its bytes over a 10 Gb/s link, as between machines.
LINK_BYTES_PER_SECOND = 10e9 / 8
IMAGE_BYTES = MODEL_SIZE[0] * MODEL_SIZE[1] * 3 * 4
# overhead under this share of the time is the target the batch size is chosen for
OVERHEAD_TARGET = 0.05
MODEL_BATCH_SPP = tuple(2**power for power in range(0, 17))
# the scene whose transfer to another node is timed: a height field (`sheet_scene`)
LARGE_SCENE_TRIANGLES = 1_000_000
# a GPU's speed for the model: the throughput benchmark on a lent H100 (Cornell box, 512x512)
GPU_THROUGHPUT = REPO_ROOT / "bench" / "results" / "throughput_nvidia-h100-80gb-hbm3-vulkan.json"


def _median(values) -> float:
    return float(statistics.median(values))


def _timed(function, *args):
    start = time.perf_counter()
    value = function(*args)
    return value, time.perf_counter() - start


def _expected_image(scene, settings, spp: int, batches: int) -> np.ndarray:
    """The batches rendered one after the other here, merged in order: what every job must give."""
    from wgputrace.cluster.batches import split_samples
    from wgputrace.cluster.merge import OrderedSum
    from wgputrace.cluster.worker import RenderWorker

    worker = RenderWorker()
    worker.prepare(scene, settings)
    merged = OrderedSum()
    for batch in split_samples(spp, settings.seed, batches):
        merged.add(worker.render_batch(batch).image)
    return merged.image()


def _on_another_node(ray):
    """A scheduling strategy that places a task or actor on a node other than the driver's, so
    that what it is sent and what it returns cross nodes."""
    from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

    here = ray.get_runtime_context().get_node_id()
    other = next(node["NodeID"] for node in ray.nodes() if node["Alive"] and node["NodeID"] != here)
    return NodeAffinitySchedulingStrategy(other, soft=False)


def _phases(ray, scene, settings, batches: list) -> dict:
    """One fresh worker's start, scene transfer, build and its batches' phases, in seconds, on a
    node other than the driver's; one batch in flight at a time, so the call's overhead is not
    hidden behind the next batch."""
    from wgputrace.cluster.merge import OrderedSum
    from wgputrace.cluster.worker import RenderWorker

    placement = _on_another_node(ray)
    actor = ray.remote(RenderWorker).options(num_cpus=1, scheduling_strategy=placement).remote(on_cpu=True)
    _, start = _timed(ray.get, actor.identity.remote())
    _, no_op = _timed(ray.get, actor.identity.remote())
    scene_ref = ray.put(scene)
    build, prepare = _timed(ray.get, actor.prepare.remote(scene_ref, settings))
    merged, per_batch = OrderedSum(), []
    for batch in batches:
        submitted = time.perf_counter()
        ref = actor.render_batch.remote(batch)
        ray.wait([ref])
        finished = time.perf_counter()
        outcome, fetch = _timed(ray.get, ref)
        _, merge = _timed(merged.add, outcome.image)
        per_batch.append(
            {
                "render": outcome.render_seconds,
                "readback": outcome.readback_seconds,
                "call": finished - submitted - outcome.render_seconds - outcome.readback_seconds,
                "fetch": fetch,
                "merge": merge,
            }
        )
    ray.kill(actor)
    return {
        "worker_start": start,
        "no_op_call": no_op,
        "scene_transfer": prepare - build - no_op,
        "pipeline_build": build,
        "batches": per_batch,
    }


def _transfer_seconds(ray, scene, small, repeats: int) -> float:
    """Median seconds for `scene`, put into the object store here, to reach a task on another node,
    less the same call given the `small` scene."""
    count = ray.remote(lambda scene: scene.triangle_count).options(
        num_cpus=0, scheduling_strategy=_on_another_node(ray)
    )
    ray.get(count.remote(small))  # warm: the function's own transfer and a worker
    times = []
    for _ in range(repeats):
        _, base = _timed(ray.get, count.remote(ray.put(small)))
        _, full = _timed(ray.get, count.remote(ray.put(scene)))
        times.append(full - base)
    return _median(times)


def _measure(address: str, width: int, height: int, batch_spp: int, batches: int, repeats: int) -> dict:
    """Inside the namespace: validation, phases (at the benchmark's size, and batches of one spp at
    MODEL_SIZE for the overheads that grow with the pixels), a large scene's transfer, and jobs."""
    import pickle

    import ray

    import wgputrace as wt
    from bench.scenes import sheet_scene
    from wgputrace.cluster import render_batches
    from wgputrace.cluster.batches import split_samples
    from wgputrace.cluster.worker import RenderSettings

    scene = wt.default_scene()
    settings = RenderSettings(width, height, SEED, MAX_DEPTH)
    spp = batch_spp * batches
    expected = _expected_image(scene, settings, spp, batches)
    large = sheet_scene(LARGE_SCENE_TRIANGLES)
    ray.init(address=address, log_to_driver=False)
    try:
        phases = []
        for repeat in range(repeats):
            phases.append(_phases(ray, scene, settings, split_samples(spp, SEED, batches)))
            log(f"phases {repeat + 1}/{repeats}: build {phases[-1]['pipeline_build']:.2f} s")
        full_size = RenderSettings(*MODEL_SIZE, SEED, MAX_DEPTH)
        model_size = _phases(ray, scene, full_size, split_samples(repeats, SEED, repeats))
        log(f"batches at {MODEL_SIZE[0]}x{MODEL_SIZE[1]}: fetch {model_size['batches'][0]['fetch'] * 1e3:.1f} ms")
        transfer = {
            "triangles": large.triangle_count,
            "bytes": len(pickle.dumps(large)),
            "seconds": _transfer_seconds(ray, large, scene, repeats),
        }
        jobs = {}
        for workers in WORKER_COUNTS:
            runs = []
            for _ in range(repeats):
                result = render_batches(
                    scene, spp, width, height, seed=SEED, max_depth=MAX_DEPTH, batches=batches, workers=workers
                )
                if not np.array_equal(result.image, expected):
                    raise SystemExit(f"{workers} workers: the image differs from the batches merged in order")
                rendered = sum(timing.render_seconds for timing in result.timings)
                runs.append(
                    {
                        "wall": result.wall_seconds,
                        "render_summed": rendered,
                        "efficiency": rendered / (workers * result.wall_seconds),
                        "workers_used": len(result.workers),
                        "lost": result.lost_workers,
                    }
                )
            jobs[str(workers)] = runs
            log(f"{workers} workers: wall {_median(run['wall'] for run in runs):.2f} s")
        nodes = len([node for node in ray.nodes() if node["Alive"]])
    finally:
        ray.shutdown()
    return {
        "phases": phases,
        "model_size_phases": model_size,
        "large_scene_transfer": transfer,
        "jobs": jobs,
        "nodes": nodes,
        "scene_bytes": len(pickle.dumps(scene)),
    }


def phase_medians(phases: list[dict]) -> dict:
    """Medians over workers (and over each worker's batches) of every phase, in seconds."""
    medians = {key: _median(run[key] for run in phases) for key in phases[0] if key != "batches"}
    return {**medians, "per_batch": batch_medians(phases)}


def batch_medians(phases: list[dict]) -> dict:
    """Medians of each per-batch phase over every batch of `phases`."""
    keys = phases[0]["batches"][0]
    return {key: _median(batch[key] for run in phases for batch in run["batches"]) for key in keys}


def efficiency(workers: int, batch_seconds: float, worker_overhead: float, driver_seconds: float) -> float:
    """The model's efficiency: a worker spends batch_seconds rendering and worker_overhead on each
    batch's other work; the driver spends driver_seconds on each batch (fetch, merge) one after
    the other, so it keeps up with at most 1 / driver_seconds batches a second."""
    per_worker = batch_seconds / (batch_seconds + worker_overhead)
    driver = min(1.0, (batch_seconds + worker_overhead) / (workers * driver_seconds))
    return per_worker * driver


def model(medians: dict, at_model_size: dict, width: int, height: int, gpu_seconds_per_spp: float | None) -> dict:
    """Efficiency against batch size at MODEL_WORKERS, for lavapipe workers and for GPUs, and the
    smallest batch (in spp at MODEL_SIZE) with overhead under OVERHEAD_TARGET. The overheads are
    those measured at MODEL_SIZE (the driver's with the image's bytes over LINK_BYTES_PER_SECOND
    added); a lavapipe worker's rendering is the benchmark size's scaled by the pixels."""
    scale = MODEL_SIZE[0] * MODEL_SIZE[1] / (width * height)
    worker_overhead = at_model_size["call"] + at_model_size["readback"]
    driver_seconds = at_model_size["fetch"] + at_model_size["merge"] + IMAGE_BYTES / LINK_BYTES_PER_SECOND
    speeds = {"lavapipe worker (1 thread)": medians["per_batch"]["render"] / medians["batch_spp"] * scale}
    if gpu_seconds_per_spp is not None:
        speeds["GPU (H100 throughput)"] = gpu_seconds_per_spp
    rows = {}
    for name, seconds_per_spp in speeds.items():
        for workers in MODEL_WORKERS:
            curve = [
                efficiency(workers, spp * seconds_per_spp, worker_overhead, driver_seconds) for spp in MODEL_BATCH_SPP
            ]
            enough = [spp for spp, value in zip(MODEL_BATCH_SPP, curve, strict=True) if value >= 1 - OVERHEAD_TARGET]
            rows[f"{name}, {workers}"] = {
                "kind": name,
                "workers": workers,
                "seconds_per_spp": seconds_per_spp,
                "efficiency_by_batch_spp": dict(zip(map(str, MODEL_BATCH_SPP), curve, strict=True)),
                "batch_spp_for_overhead_under_target": enough[0] if enough else None,
                "batch_seconds_then": enough[0] * seconds_per_spp if enough else None,
            }
    return {
        "image": f"{MODEL_SIZE[0]}x{MODEL_SIZE[1]}",
        "worker_overhead_seconds": worker_overhead,
        "driver_seconds_per_batch": driver_seconds,
        "link_bytes_per_second": LINK_BYTES_PER_SECOND,
        "startup_seconds": medians["worker_start"] + medians["scene_transfer"] + medians["pipeline_build"],
        "overhead_target": OVERHEAD_TARGET,
        "rows": rows,
    }


def gpu_seconds_per_spp() -> float | None:
    """Seconds for one sample per pixel at MODEL_SIZE on the GPU of GPU_THROUGHPUT, if present."""
    if not GPU_THROUGHPUT.exists():
        return None
    result = json.loads(GPU_THROUGHPUT.read_text())
    return result["width"] * result["height"] / result["accelerations"]["bvh"]["paths_per_second"]


def plot(path: Path, result: dict) -> None:
    chart = figure(11, 4.5)
    phases_axes, model_axes = chart.subplots(1, 2)
    medians = result["phase_medians"]
    names = ["worker_start", "scene_transfer", "pipeline_build"]
    batch_names = ["render", "readback", "call", "fetch", "merge"]
    values = [medians[name] for name in names] + [medians["per_batch"][name] for name in batch_names]
    labels = [name.replace("_", " ") for name in names] + [f"batch: {name}" for name in batch_names]
    phases_axes.barh(labels, [max(value, 1e-6) * 1e3 for value in values], color="tab:blue")
    phases_axes.set_xscale("log")
    phases_axes.invert_yaxis()
    phases_axes.set_xlabel("milliseconds (median)")
    phases_axes.set_title(f"one worker, {result['width']}x{result['height']}, {result['batch_spp']} spp batches")
    for key, row in result["model"]["rows"].items():
        curve = row["efficiency_by_batch_spp"]
        style = "-" if row["kind"].startswith("GPU") else "--"
        model_axes.plot([int(spp) for spp in curve], list(curve.values()), style, label=key)
    model_axes.axhline(1 - OVERHEAD_TARGET, color="grey", linewidth=0.8)
    model_axes.set_xscale("log", base=2)
    model_axes.set_ylim(0, 1.02)
    model_axes.set_xlabel(f"batch size, spp at {result['model']['image']}")
    model_axes.set_ylabel("modelled efficiency")
    model_axes.legend(fontsize=6)
    model_axes.set_title("model: workers x batch size")
    save_figure(chart, path, result, "Rendering on a Ray cluster: phases and modelled efficiency")


def main(argv: list[str] | None = None) -> int:
    from wgputrace.cluster.sandbox import NamespacedCluster, NamespaceUnavailable

    parser = argument_parser(__doc__, size=(128, 128), repeats=3)
    parser.add_argument("--batch-spp", type=int, default=4, help="samples per pixel in a batch (default 4)")
    parser.add_argument("--batches", type=int, default=16, help="batches of a job (default 16)")
    args = parse(parser, argv, "batch_spp", "batches")
    run = Run()
    width, height = args.size
    # the namespace's server imports the function by its module's name, which `python -m bench.cluster`
    # runs as __main__: take it from the module under its own name
    measure = importlib.import_module(__spec__.name)._measure
    try:
        with NamespacedCluster(nodes=NODES, cpus_per_node=CPUS_PER_NODE) as cluster:
            measured = cluster.call(
                measure, cluster.address, width, height, args.batch_spp, args.batches, args.repeats, timeout=1800
            )
    except NamespaceUnavailable as why:
        raise SystemExit(f"cluster benchmark: {why}") from None
    medians = {**phase_medians(measured["phases"]), "batch_spp": args.batch_spp}
    jobs = {
        workers: {
            "wall_seconds": _median(run["wall"] for run in runs),
            "efficiency": _median(run["efficiency"] for run in runs),
            "runs": runs,
        }
        for workers, runs in measured["jobs"].items()
    }
    jobs["speedup_2_over_1"] = jobs["1"]["wall_seconds"] / jobs["2"]["wall_seconds"]
    result = {
        "scene": "default Cornell box",
        "width": width,
        "height": height,
        "spp": args.batch_spp * args.batches,
        "max_depth": MAX_DEPTH,
        "batch_spp": args.batch_spp,
        "batches": args.batches,
        "repeats": args.repeats,
        "nodes": measured["nodes"],
        "scene_bytes": measured["scene_bytes"],
        "phase_medians": medians,
        "phases": measured["phases"],
        "jobs": jobs,
        "per_batch_at_model_size": batch_medians([measured["model_size_phases"]]),
        "large_scene_transfer": measured["large_scene_transfer"],
        "model": model(medians, batch_medians([measured["model_size_phases"]]), width, height, gpu_seconds_per_spp()),
        "gpu_throughput_source": str(GPU_THROUGHPUT.relative_to(REPO_ROOT)),
    }
    write_result("cluster", result, out=args.out, plot=plot, run=run)
    for key, row in result["model"]["rows"].items():
        log(f"{key}: batch of {row['batch_spp_for_overhead_under_target']} spp keeps overhead under 5%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
