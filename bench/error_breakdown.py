"""Where the Cornell box's remaining error lives, per strategy, and what each policy change buys.

    python -m bench.error_breakdown
    python -m bench.error_breakdown --batches 8 --spp 32 --variants mis bsdf

Every variant (an integrator with shader overrides, the glass sphere made diffuse as a diagnostic,
or Mitsuba 3's `path` integrator) renders the 128x128 Cornell box as `batches` independent images,
taking turns batch by batch so that load slows them alike; the spread of the batches gives each
pixel's relative variance of one sample (as `errors` weighs it), summed per region of what the
pixel centre sees. Efficiency = 1 / (relative variance x seconds per sample): the time to BSDF
sampling's error that `bench.convergence` fits from its curves. Every variant's mean is z-tested
against the reference first. Writes bench/results/error_breakdown_<adapter>.json and .png.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.error_curves import RELATIVE_MSE_EPSILON, errors
from bench.provenance import Run, load_average
from bench.result_files import write_result
from bench.scenes import pixel_centre_rays
from bench.validation import CHANNELS, agreement, sidak_critical_z
from wgputrace import Diffuse, Glossy, Renderer, Scene, load_scene
from wgputrace.bvh.binned_sah import build_bvh
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.testing.oracles import bvh_closest_hit
from wgputrace.testing.references import load_reference

SCENE = "cornell"
BASELINE = "bsdf"
GLASS_SHAPE, LAMP_SHAPE, CEILING_SHAPE, FLOOR_SHAPE = "sphere1", "lamp", "wall_top", "wall_bottom"
# Lamp points per triangle side (a barycentric grid) whose shadow rays define the caustic region:
# enough to trace the penumbra of the 0.15-radius sphere under the 0.4 x 0.4 lamp to a pixel or two.
LAMP_GRID = 9
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise over variants x channels
REGIONS = ("lamp", "glass sphere", "caustic", "glossy: lamp reflected", "glossy: other", "ceiling", "other")
# Mitsuba 3's `path` integrator (MIS, roulette from depth 5) on the same scene: what an independent
# unidirectional path tracer achieves per sample. Its time runs on another engine, so it has no
# time-to-equal-error ratio.
MITSUBA_PATH = "mitsuba path"
# Mitsuba's seeds start here, clear of the references' seeds 0 .. passes - 1.
MITSUBA_SEED = 10_000
GLOSSY_OFF = {"GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS": 1.0}  # above the scene's 0.09: BSDF sampling only there
# A minimum solid angle above the whole sphere's: every light point is sampled uniformly in area.
AREA_SAMPLING = {"SPHERICAL_SAMPLING_MIN_SOLID_ANGLE": 100.0}


@dataclass(frozen=True)
class Variant:
    integrator: str  # ours, or MITSUBA_PATH
    overrides: dict = field(default_factory=dict)
    diffuse_glass: bool = False  # diagnostic only: a different scene, not compared with the reference


def russian_roulette(depth: int, cap: float = 0.95) -> dict:
    return {"RUSSIAN_ROULETTE_DEPTH": depth, "RUSSIAN_ROULETTE_MAX_SURVIVAL": cap}


VARIANTS = {
    "mis": Variant("mis"),
    "bsdf": Variant("bsdf"),
    "nee": Variant("nee"),
    "mis, area light sampling": Variant("mis", AREA_SAMPLING),
    "nee, area light sampling": Variant("nee", AREA_SAMPLING),
    "mis, no light sampling at glossy": Variant("mis", GLOSSY_OFF),
    "mis, roulette from depth 2": Variant("mis", russian_roulette(2)),
    "mis, roulette from depth 5": Variant("mis", russian_roulette(5)),
    "mis, no roulette": Variant("mis", russian_roulette(64)),
    "bsdf, roulette from depth 2": Variant("bsdf", russian_roulette(2)),
    "bsdf, roulette from depth 5": Variant("bsdf", russian_roulette(5)),
    "bsdf, no roulette": Variant("bsdf", russian_roulette(64)),
    "mis, glass made diffuse": Variant("mis", diffuse_glass=True),
    "bsdf, glass made diffuse": Variant("bsdf", diffuse_glass=True),
    MITSUBA_PATH: Variant(MITSUBA_PATH),
    f"{MITSUBA_PATH}, glass made diffuse": Variant(MITSUBA_PATH, diffuse_glass=True),
}


def build_scene(variant: Variant) -> Scene:
    scene = load_scene(SCENE)
    if variant.diffuse_glass:
        scene.shape(GLASS_SHAPE).material = Diffuse("glass made diffuse", color=(0.5, 0.5, 0.9))
    return scene


def _closest(bvh, triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray):
    """(distance, triangle in the scene's order or -1 on a miss) per ray."""
    distance, index = bvh_closest_hit(bvh, triangles, origins, directions)
    hit = index != NO_TRIANGLE
    return distance, np.where(hit, bvh.triangle_order[np.where(hit, index, 0)].astype(np.int64), -1)


def region_masks(scene: Scene, width: int, height: int) -> dict[str, np.ndarray]:
    """One boolean (height, width) mask per region, from rays through the pixel centres."""
    arrays = scene.arrays()
    shape_names = np.array([shape.name for shape in scene.shapes])
    kinds = np.array([material.kind for material in arrays.materials])
    bvh = build_bvh(arrays.vertices)
    triangles = arrays.vertices[bvh.triangle_order].astype(np.float64)
    origins, directions = pixel_centre_rays(scene.camera, width, height, np.float64)
    distance, hit = _closest(bvh, triangles, origins, directions)
    seen = np.where(hit >= 0, shape_names[arrays.shape_index[np.maximum(hit, 0)]], "")
    kind = np.where(hit >= 0, kinds[arrays.material_index[np.maximum(hit, 0)]], -1)
    points = origins + distance[:, None] * directions

    glossy = kind == Glossy.kind
    corners = arrays.vertices[np.maximum(hit, 0)].astype(np.float64)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    mirror = directions - 2.0 * np.sum(directions * normals, axis=-1, keepdims=True) * normals
    _, reflected = _closest(bvh, triangles, points + 1e-4 * mirror, mirror)
    reflects_lamp = (
        glossy & (reflected >= 0) & (shape_names[arrays.shape_index[np.maximum(reflected, 0)]] == LAMP_SHAPE)
    )

    # the caustic: floor points from which the glass sphere hides some lamp point
    sphere = scene.shape(GLASS_SHAPE).world_vertices.reshape(-1, 3).astype(np.float64)
    centre = sphere.mean(axis=0)
    radius = np.linalg.norm(sphere - centre, axis=-1).max()
    lamp = scene.shape(LAMP_SHAPE).world_vertices.astype(np.float64)
    u, v = np.meshgrid(np.linspace(0.0, 1.0, LAMP_GRID), np.linspace(0.0, 1.0, LAMP_GRID))
    u, v = u[u + v <= 1.0], v[u + v <= 1.0]
    lamp_points = lamp[:, :1] + u[:, None] * (lamp[:, 1:2] - lamp[:, :1]) + v[:, None] * (lamp[:, 2:3] - lamp[:, :1])
    lamp_points = lamp_points.reshape(-1, 3)
    floor = seen == FLOOR_SHAPE
    to_lamp = lamp_points[None, :, :] - points[floor][:, None, :]
    length = np.linalg.norm(to_lamp, axis=-1)
    along = np.clip(np.sum((centre - points[floor][:, None, :]) * to_lamp, axis=-1) / length**2, 0.0, 1.0)
    nearest = points[floor][:, None, :] + along[..., None] * to_lamp
    shadowed = np.zeros(len(seen), bool)
    shadowed[floor] = (np.linalg.norm(nearest - centre, axis=-1) < radius).any(axis=1)

    masks = {
        "lamp": seen == LAMP_SHAPE,
        "glass sphere": seen == GLASS_SHAPE,
        "caustic": shadowed,
        "glossy: lamp reflected": reflects_lamp,
        "glossy: other": glossy & ~reflects_lamp,
        "ceiling": seen == CEILING_SHAPE,
    }
    masks["other"] = ~np.any(list(masks.values()), axis=0)
    return {name: mask.reshape(height, width) for name, mask in masks.items()}


def ours(variant: Variant, width: int, height: int, max_depth: int, seed: int) -> Callable[[int, int], np.ndarray]:
    """render(batch, spp) -> one independent image of `spp` samples per pixel."""
    renderer = Renderer(
        build_scene(variant),
        width,
        height,
        seed=seed,
        max_depth=max_depth,
        integrator=variant.integrator,
        shader_overrides=variant.overrides,
    )
    renderer.render(1)  # compiles the shader on lavapipe: not timed
    renderer.reset()

    def render(batch: int, spp: int) -> np.ndarray:
        renderer.render(spp)
        image = renderer.image().astype(np.float64)
        if renderer.dropped_samples:
            raise SystemExit(f"{variant}: {renderer.dropped_samples} dropped samples (non-finite or cut short)")
        renderer.reset()
        return image

    return render


def mitsuba(variant: Variant, width: int, height: int, max_depth: int) -> Callable[[int, int], np.ndarray]:
    from wgputrace.reference.mitsuba_scene import choose_variant, load_mitsuba, mitsuba_scene

    mi = load_mitsuba(choose_variant(None))
    scene = mitsuba_scene(mi, build_scene(variant), width, height, max_depth)
    mi.render(scene, spp=1, seed=MITSUBA_SEED - 1)  # compiles its kernels: not timed

    def render(batch: int, spp: int) -> np.ndarray:
        return np.asarray(mi.render(scene, spp=spp, seed=MITSUBA_SEED + batch), dtype=np.float64)

    return render


def measure(args: argparse.Namespace) -> tuple[dict, dict]:
    reference = load_reference(SCENE)
    width, height, max_depth = (reference.metadata[key] for key in ("width", "height", "max_depth"))
    renderers, batches, seconds, cpu_seconds = {}, {}, {}, {}
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(args.variants) * len(CHANNELS))
    for name in args.variants:
        variant = VARIANTS[name]
        if variant.integrator == MITSUBA_PATH:
            renderers[name] = mitsuba(variant, width, height, max_depth)
        else:
            renderers[name] = ours(variant, width, height, max_depth, args.seed)
        batches[name], seconds[name], cpu_seconds[name] = [], [], []
    for batch in range(args.batches):
        for name, render in renderers.items():
            start, cpu_start = time.perf_counter(), time.process_time()
            batches[name].append(render(batch, args.spp))
            cpu_seconds[name].append(time.process_time() - cpu_start)
            seconds[name].append(time.perf_counter() - start)
        log(f"batch {batch + 1}/{args.batches} done, load {load_average()}")
    masks = region_masks(load_scene(SCENE), width, height)
    denominator = reference.estimate.mean**2 + RELATIVE_MSE_EPSILON
    results, maps = {}, {}
    for name in args.variants:
        stack = np.stack(batches[name])
        mean = stack.mean(axis=0)
        # variance of one sample: the batches' spread times the samples in each
        relative_variance = stack.var(axis=0, ddof=1) * args.spp / denominator
        per_pixel = relative_variance.mean(axis=2)
        total = float(per_pixel.mean())
        seconds_per_sample = float(np.median(seconds[name])) / args.spp
        cpu_per_sample = float(np.median(cpu_seconds[name])) / args.spp
        result = {
            "integrator": VARIANTS[name].integrator,
            "overrides": VARIANTS[name].overrides,
            "diffuse_glass": VARIANTS[name].diffuse_glass,
            "relative_variance_per_sample": total,
            "seconds_per_sample": seconds_per_sample,
            "cpu_seconds_per_sample": cpu_per_sample,
            "efficiency": 1.0 / (total * seconds_per_sample),
            "region_share_of_relative_variance": {
                r: float(per_pixel[m].sum() / per_pixel.sum()) for r, m in masks.items()
            },
            "region_relative_variance_per_pixel": {r: float(per_pixel[m].mean()) for r, m in masks.items()},
        }
        if not VARIANTS[name].diffuse_glass:
            check = agreement(mean.astype(np.float32), reference.estimate.mean.astype(np.float32), z_critical)
            if check["failures"]:
                raise SystemExit(f"{name}: the mean of its batches disagrees with the reference: {check['failures']}")
            result["error_against_reference"] = errors(mean, reference.estimate.mean, reference.estimate.variance)
        results[name] = result
        maps[name] = per_pixel
    for result in results.values():
        base_name = f"{BASELINE}, glass made diffuse" if result["diffuse_glass"] else BASELINE
        if base_name in results and result["integrator"] != MITSUBA_PATH:
            result["time_to_equal_error_vs_" + BASELINE] = results[base_name]["efficiency"] / result["efficiency"]
            result["cpu_time_to_equal_error_vs_" + BASELINE] = (
                result["relative_variance_per_sample"] * result["cpu_seconds_per_sample"]
            ) / (results[base_name]["relative_variance_per_sample"] * results[base_name]["cpu_seconds_per_sample"])
    pixels = {r: int(m.sum()) for r, m in masks.items()}
    return results, {"maps": maps, "masks": masks, "reference": reference, "pixels": pixels}


def plot(path: Path, result: dict, extra: dict) -> None:
    from matplotlib.colors import LogNorm

    maps = extra["maps"]
    shown = [name for name in ("mis", "bsdf") if name in maps]
    chart = figure(15.0, 9.0)
    grid = chart.add_gridspec(2, 4)
    reference = extra["reference"].estimate.mean
    axes = chart.add_subplot(grid[0, 0])
    axes.imshow(np.clip(reference / np.percentile(reference, 99), 0, 1) ** (1 / 2.2))
    axes.set_title("Mitsuba reference", fontsize=9)
    region_index = np.zeros(reference.shape[:2])
    for index, mask in enumerate(extra["masks"].values()):
        region_index[mask] = index
    axes = chart.add_subplot(grid[1, 0])
    axes.imshow(region_index, cmap="tab10", vmin=0, vmax=9, interpolation="nearest")
    labels = [f"{i} {r}" for i, r in enumerate(extra["masks"])]
    axes.set_title("regions: " + ", ".join(labels[:4]) + "\n" + ", ".join(labels[4:]), fontsize=7)
    positive = np.concatenate([maps[name][maps[name] > 0] for name in shown])
    norm = LogNorm(vmin=np.percentile(positive, 1), vmax=positive.max())
    for column, name in enumerate(shown, start=1):
        axes = chart.add_subplot(grid[0, column])
        image = axes.imshow(maps[name], norm=norm, cmap="magma")
        axes.set_title(
            f"{name}: relative variance per sample (mean {result['variants'][name]['relative_variance_per_sample']:.3g})",
            fontsize=8,
        )
        chart.colorbar(image, ax=axes, fraction=0.046)
    if len(shown) == 2:
        axes = chart.add_subplot(grid[0, 3])
        ratio = maps["mis"] / np.maximum(maps["bsdf"], positive.min())
        image = axes.imshow(ratio, norm=LogNorm(vmin=1e-2, vmax=1e2), cmap="coolwarm")
        axes.set_title("mis / bsdf relative variance", fontsize=8)
        chart.colorbar(image, ax=axes, fraction=0.046)
    axes = chart.add_subplot(grid[1, 1:3])
    names = [
        name
        for name in (
            "mis",
            "mis, area light sampling",
            "bsdf",
            "nee",
            "mis, glass made diffuse",
            "bsdf, glass made diffuse",
        )
        if name in maps
    ]
    bottom = np.zeros(len(names))
    for region in extra["masks"]:
        # each region's part of relative variance x time: what sets time to equal error
        values = np.array(
            [
                result["variants"][n]["region_share_of_relative_variance"][region]
                * result["variants"][n]["relative_variance_per_sample"]
                * result["variants"][n]["seconds_per_sample"]
                for n in names
            ]
        )
        axes.bar(range(len(names)), values, bottom=bottom, label=region)
        bottom += values
    axes.set_xticks(range(len(names)), [n.replace(", ", ",\n") for n in names], fontsize=7)
    axes.set_ylabel("relative variance x seconds per sample", fontsize=8)
    axes.legend(fontsize=7)
    axes.set_title("what the error per unit time is made of, by region", fontsize=9)
    axes = chart.add_subplot(grid[1, 3])
    names = list(result["variants"])
    ratios = [result["variants"][n].get(f"time_to_equal_error_vs_{BASELINE}", np.nan) for n in names]
    axes.barh(range(len(names)), ratios, color="#3b75af")
    axes.set_yticks(range(len(names)), names, fontsize=6)
    axes.axvline(0.2, color="red", linestyle=":", label="issue 5 target (1/5)")
    axes.set_xlabel(f"time to reach {BASELINE}'s error / {BASELINE}'s time", fontsize=8)
    axes.legend(fontsize=7)
    axes.invert_yaxis()
    title = (
        f"Cornell box error breakdown, {result['width']}x{result['height']}, {result['batches']} x {result['spp']} spp "
        f"per variant, max depth {result['max_depth']}"
    )
    save_figure(chart, path, result, title, fontsize=10, dpi=100)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, spp=16, seed=1)
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS), metavar="VARIANT")
    parser.add_argument("--batches", type=int, default=8, help="independent images per variant (default 8)")
    args = parse(parser, argv)
    if args.batches < 2:
        parser.error(f"--batches must be at least 2 (their spread is the variance), got {args.batches}")
    run = Run()
    variants, extra = measure(args)
    reference = extra["reference"]
    result = {
        "scene": SCENE,
        "width": reference.metadata["width"],
        "height": reference.metadata["height"],
        "max_depth": reference.metadata["max_depth"],
        "batches": args.batches,
        "spp": args.spp,
        "seed": args.seed,
        "relative_mse_epsilon": RELATIVE_MSE_EPSILON,
        "region_pixels": extra["pixels"],
        "timing": "median wall clock per batch (render and read-back); variants take turns batch by batch",
        "variants": variants,
    }
    write_result("error_breakdown", result, out=args.out, plot=lambda path, data: plot(path, data, extra), run=run)
    for name, variant in variants.items():
        shares = ", ".join(f"{r} {s:.0%}" for r, s in variant["region_share_of_relative_variance"].items())
        ratio = variant.get(f"time_to_equal_error_vs_{BASELINE}", float("nan"))
        print(
            f"{name:34s} rel. variance/sample {variant['relative_variance_per_sample']:.4g}, "
            f"{variant['seconds_per_sample'] * 1e3:.1f} ms/sample, time to {BASELINE}'s error {ratio:.3f}; {shares}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
