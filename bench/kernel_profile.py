"""Where the path tracer's time goes on this adapter, and what each kernel variant changes.

    python bench/kernel_profile.py                       (Cornell box and a 328k-triangle sphere)
    python bench/kernel_profile.py --size 128x128 --repeats 5 --variants storage_nodes
    python bench/kernel_profile.py --variants binary_nodes    (the 4-wide BVH against the binary one)

Every variant is the shipped megakernel with some shader files replaced (bench/kernel_variants/),
another workgroup size, or another renderer setting, bound to the same scene and seeded alike.
Order of work: compile and warm up every variant (lavapipe compiles at the first dispatch), check
each one's image after CHECK_SPP samples against the shipped kernel's (bit for bit where the
arithmetic is the same: a layout or workgroup change must not alter a single sample; in mean
radiance, by a paired z-test, where only the order of the work differs, as in a traversal that
resolves exact ties of hit distances its own way), then time
`repeats` rounds, each one dispatch of every variant in turn (the order rotating from round to
round). Speed-ups are medians of ratios taken within a round, because other jobs on a shared CPU
change the load between rounds. Times are GPU timestamps around each dispatch where the adapter
has "timestamp-query" (nanoseconds, as WebGPU resolves them), wall time around submit and finish
otherwise. Prints a table and writes bench/results/kernel_profile_<adapter>.json.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import wgpu

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import RESULTS_DIR, environment, git_revision, load_average, slug, write_json  # noqa: E402
from bench.kernel_variants.binary_nodes import binary_traversal_wgsl  # noqa: E402
from bench.kernel_variants.paired_nodes import PAIRED_NODE, paired_fields  # noqa: E402
from bench.throughput import CHANNELS, agreement, sidak_critical_z  # noqa: E402
from wgputrace import Renderer, default_scene, make_icosphere  # noqa: E402
from wgputrace.cli import parse_size  # noqa: E402
from wgputrace.gpu.buffers import read_buffer, storage_buffer, uniform_buffer  # noqa: E402
from wgputrace.gpu.device import describe, gpu  # noqa: E402
from wgputrace.gpu.layout import ACCUMULATED_PIXEL  # noqa: E402
from wgputrace.gpu.material_dispatch import GENERATED_MATERIALS, material_dispatch, shaded_kinds  # noqa: E402
from wgputrace.gpu.pipeline import (  # noqa: E402
    BVH_STACK_SIZE,
    GENERATED_TRAVERSAL_STACK,
    INTEGRATORS,
    compute_kernel,
    dispatch_size,
    traversal_stack,
)
from wgputrace.gpu.shader_source import shader_root  # noqa: E402
from wgputrace.gpu.texels import TrackedTexels  # noqa: E402
from wgputrace.render.rng_seed import pixel_rng_states  # noqa: E402
from wgputrace.render.scene_buffers import node_records  # noqa: E402

VARIANTS_DIR = Path(__file__).resolve().parent / "kernel_variants"
SEED = 1
MAX_DEPTH = 9
CHECK_SPP = 2
# 20 * 4**7 = 327,680 triangles: a mesh big enough that nodes and triangles leave the CPU caches.
BIG_SPHERE_ITERATIONS = 7
SHIPPED_WORKGROUP = (8, 8)
# Family-wise false-alarm rate of the mean radiance tests of variants that compute the same image
# by other arithmetic (Sidak-corrected over those variants, scenes and channels).
AGREEMENT_SIGNIFICANCE = 1e-3


def function_stack_traversal() -> str:
    """The shipped traverse_bvh.wgsl with its stack a function variable, as it was before: WGSL
    then zero-fills it at every traversal instead of once per invocation."""
    text = (shader_root() / "traverse_bvh.wgsl").read_text()
    module_scope = "var<private> stack: array<u32, TRAVERSAL_STACK_SIZE>;\n"
    first_local = "    var stack_size = 0u;\n"
    if module_scope not in text or first_local not in text:
        raise RuntimeError("traverse_bvh.wgsl no longer declares its stack as this benchmark expects; update it")
    local = "    var stack: array<u32, TRAVERSAL_STACK_SIZE>;\n"
    return text.replace(module_scope, "").replace(first_local, local + first_local)


def big_sphere_scene():
    scene = default_scene()
    white = next(m for m in scene.materials if m.name == "white")
    return scene.add(make_icosphere((0.0, 0.35, 0.2), (0, 0, 0), 0.15, BIG_SPHERE_ITERATIONS, white, "big_sphere"))


SCENES = {"cornell": default_scene, "big_sphere": big_sphere_scene}


@dataclass
class Variant:
    """The shipped kernel with `files` replaced (name -> file under kernel_variants/), another
    workgroup or renderer setting, binding 1 holding the triangles as `triangles` and binding 2 the
    nodes as `nodes`."""

    name: str
    files: dict[str, str] = field(default_factory=dict)
    workgroup: tuple[int, int] = SHIPPED_WORKGROUP
    max_depth: int = MAX_DEPTH
    integrator: str = "mis"
    # "texels" (shipped: 4-wide records), or the binary nodes: "binary" (texels, the kernel before
    # 4-wide records), "buffer" (before texels), "uniform" (scenes whose nodes fit 64 KiB), "paired"
    # (paired_nodes.py)
    nodes: str = "texels"
    triangles: str = "texels"  # "texels" (shipped) or "buffer" (before texels)
    same_arithmetic: bool = True  # whether its image must equal the shipped kernel's bit for bit
    # Whether it computes the shipped kernel's image by other arithmetic (a traversal visiting
    # nodes in another order resolves exact ties of hit distances its own way): then its mean
    # radiance must agree with the shipped kernel's (paired z-test, bench/throughput.py).
    same_image: bool = False
    sources: dict[str, str] = field(default_factory=dict)  # files replaced by generated text
    what: str = ""


VARIANTS = [
    Variant("shipped", what="the shipped megakernel (MIS, max depth 9; 4-wide BVH records and triangles as texels)"),
    Variant("primary_only", max_depth=1, same_arithmetic=False, what="camera rays' closest hit only (max depth 1)"),
    Variant("direct_only", max_depth=2, same_arithmetic=False, what="max depth 2: primary, shadow ray, one BSDF ray"),
    Variant("no_shadow_rays", integrator="bsdf", same_arithmetic=False, what="BSDF sampling alone: no shadow rays"),
    Variant(
        "binary_nodes",
        sources={"acceleration.wgsl": binary_traversal_wgsl()},
        nodes="binary",
        same_arithmetic=False,
        same_image=True,
        what="the binary BVH's nodes as texels (the kernel before 4-wide records, kernel_variants/binary_nodes.py)",
    ),
    Variant(
        "binary_primary_only",
        sources={"acceleration.wgsl": binary_traversal_wgsl()},
        nodes="binary",
        max_depth=1,
        same_arithmetic=False,
        what="camera rays' closest hit only (max depth 1) through the binary BVH: compare with primary_only",
    ),
    Variant(
        "nearest_child_first",
        files={"bvh_child_order.wgsl": "wide_nearest_order.wgsl"},
        same_arithmetic=False,
        same_image=True,
        what="4-wide BVH, only the nearest child first (the others unsorted)",
    ),
    Variant(
        "function_stack",
        sources={"acceleration.wgsl": function_stack_traversal()},
        what="the traversal stack a function variable, zero-filled at every traversal (shipped before)",
    ),
    Variant(
        "max_stack",
        sources={GENERATED_TRAVERSAL_STACK: traversal_stack(BVH_STACK_SIZE)},
        what="the shipped kernel with the largest stack (BVH_STACK_SIZE entries) instead of one sized for the tree",
    ),
    Variant(
        "binary_nodes_stack_64",
        sources={"acceleration.wgsl": binary_traversal_wgsl(), GENERATED_TRAVERSAL_STACK: traversal_stack(64)},
        nodes="binary",
        same_arithmetic=False,
        same_image=True,
        what="the kernel shipped before 4-wide records as it was: binary nodes as texels, a 64-entry stack",
    ),
    Variant(
        "storage_nodes",
        files={"acceleration.wgsl": "storage_nodes_traverse_bvh.wgsl"},
        nodes="buffer",
        same_arithmetic=False,
        same_image=True,
        what="binary nodes in a storage buffer (the kernel before texels)",
    ),
    Variant(
        "uniform_nodes",
        files={"acceleration.wgsl": "uniform_nodes_traverse_bvh.wgsl"},
        nodes="uniform",
        same_arithmetic=False,
        same_image=True,
        what="binary nodes in a uniform buffer, the array sized for the scene (a specialization for small scenes)",
    ),
    Variant(
        "storage_triangles",
        files={"scene_bindings.wgsl": "storage_triangles_scene_bindings.wgsl"},
        triangles="buffer",
        what="triangles in a storage buffer (the kernel before triangle texels)",
    ),
    Variant(
        "paired_nodes",
        files={"acceleration.wgsl": "paired_traverse_bvh.wgsl"},
        nodes="paired",
        same_arithmetic=False,
        same_image=True,
        what="binary BVH, both children's boxes in one record (kernel_variants/paired_nodes.py), as texels",
    ),
    Variant("workgroup_16x16", workgroup=(16, 16), what="workgroup 16x16"),
    Variant("workgroup_64x1", workgroup=(64, 1), what="workgroup 64x1"),
    Variant("workgroup_4x4", workgroup=(4, 4), what="workgroup 4x4"),
]


def scene_resources(context, records) -> dict:
    """What variants bind: the nodes five ways (the shipped 4-wide records; the binary nodes four
    ways, uniform: None unless they fit one), the triangles two."""
    fields = paired_fields(records.acceleration)
    paired = PAIRED_NODE.zeros(len(fields["a_ref"]))
    for name, values in fields.items():
        paired[name] = values
    binary = node_records(records.acceleration)
    fits_uniform = binary.nbytes <= context.device.limits["max-uniform-buffer-binding-size"]
    return {
        "nodes": {
            "texels": TrackedTexels(context, "nodes", records.nodes).resource,
            "binary": TrackedTexels(context, "binary nodes", binary).resource,
            "uniform": uniform_buffer(context, "nodes", binary) if fits_uniform else None,
            "buffer": storage_buffer(context, "nodes", binary),
            "paired": TrackedTexels(context, "paired nodes", paired).resource,
        },
        "triangles": {
            "texels": TrackedTexels(context, "triangles", records.triangles).resource,
            "buffer": storage_buffer(context, "triangles", records.triangles),
        },
    }


class Run:
    """One variant's pipeline, bind group and per-pixel state on one scene."""

    def __init__(self, variant: Variant, renderer: Renderer, resources: dict) -> None:
        context = renderer.context
        width, height = renderer.width, renderer.height
        self.context, self.variant, self.width, self.height = context, variant, width, height
        node_count = str(renderer.records.acceleration.node_count)  # the binary nodes (uniform_nodes)
        generated = {
            name: (VARIANTS_DIR / file).read_text().replace("__NODE_COUNT__", node_count)
            for name, file in variant.files.items()
        }
        generated.update(variant.sources)
        generated.setdefault("acceleration.wgsl", '//! include "traverse_bvh.wgsl"\n')
        # the stack the renderer compiles for this scene's tree, unless the variant sizes its own
        generated.setdefault(GENERATED_TRAVERSAL_STACK, traversal_stack(renderer.traversal_stack_size))
        generated[GENERATED_MATERIALS] = material_dispatch(
            shaded_kinds(frozenset(m.kind for m in renderer.scene.materials))
        )
        source = (shader_root() / "path_tracer.wgsl").read_text()
        shipped = "@workgroup_size({}, {})".format(*SHIPPED_WORKGROUP)
        if shipped not in source:
            raise RuntimeError(f"path_tracer.wgsl no longer declares {shipped}; update this benchmark")
        generated["path_tracer.wgsl"] = source.replace(shipped, "@workgroup_size({}, {})".format(*variant.workgroup))
        self.kernel = compute_kernel(
            context,
            "path_tracer.wgsl",
            generated=generated,
            constants={"INTEGRATOR": INTEGRATORS.index(variant.integrator)},
            workgroup_size=variant.workgroup,
            label=variant.name,
        )
        self.states = pixel_rng_states(SEED, width * height)
        self.rng = storage_buffer(context, "rng", self.states)
        self.accumulation = storage_buffer(
            context, "accumulation", ACCUMULATED_PIXEL.zeros(width * height), read_back=True
        )
        triangles, nodes = resources["triangles"][variant.triangles], resources["nodes"][variant.nodes]
        bindings = {**renderer.bindings, 1: triangles, 2: nodes, 4: self.rng, 5: self.accumulation}
        self.bind_group = self.kernel.bind_group(context, 0, bindings)
        self.groups = dispatch_size(width, height, variant.workgroup)
        self.timestamps = "timestamp-query" in context.device.features
        if self.timestamps:
            self.query_set = context.device.create_query_set(type=wgpu.QueryType.timestamp, count=2)
            self.query_buffer = context.device.create_buffer(
                size=16, usage=wgpu.BufferUsage.QUERY_RESOLVE | wgpu.BufferUsage.COPY_SRC
            )

    def dispatch(self, count: int = 1) -> float:
        """Run `count` dispatches; seconds taken by the last one."""
        device = self.context.device
        encoder = device.create_command_encoder()
        for i in range(count):
            writes = None
            if self.timestamps and i == count - 1:
                writes = {"query_set": self.query_set, "beginning_of_pass_write_index": 0, "end_of_pass_write_index": 1}
            compute = encoder.begin_compute_pass(timestamp_writes=writes)
            compute.set_pipeline(self.kernel.pipeline)
            compute.set_bind_group(0, self.bind_group)
            compute.dispatch_workgroups(*self.groups)
            compute.end()
        if self.timestamps:
            encoder.resolve_query_set(self.query_set, 0, 2, self.query_buffer, 0)
        start = time.perf_counter()
        device.queue.submit([encoder.finish()])
        self.context.finish()
        wall = time.perf_counter() - start
        if not self.timestamps:
            return wall / count
        ticks = np.frombuffer(device.queue.read_buffer(self.query_buffer), np.uint64)
        return float(ticks[1] - ticks[0]) * 1e-9

    def image_after(self, spp: int) -> np.ndarray:
        """The sum of the first `spp` samples per pixel from the seed."""
        device = self.context.device
        device.queue.write_buffer(self.rng, 0, self.states)
        device.queue.write_buffer(self.accumulation, 0, ACCUMULATED_PIXEL.zeros(self.width * self.height))
        self.dispatch(spp)
        pixels = read_buffer(self.context, self.accumulation, ACCUMULATED_PIXEL.dtype, self.width * self.height)
        return pixels["sum"][:, :3].reshape(self.height, self.width, 3)


def profile_scene(name: str, width: int, height: int, repeats: int, variants: list[Variant], z_critical: float) -> dict:
    scene = SCENES[name]()
    renderers = {}
    for variant in variants:
        key = (variant.max_depth, variant.integrator)
        if key not in renderers:
            renderers[key] = Renderer(
                scene, width, height, seed=SEED, max_depth=variant.max_depth, integrator=variant.integrator
            )
    records = renderers[(MAX_DEPTH, "mis")].records
    resources = scene_resources(renderers[(MAX_DEPTH, "mis")].context, records)
    skipped = [v.name for v in variants if resources["nodes"][v.nodes] is None]
    if skipped:
        print(f"{name}: skipped {', '.join(skipped)}: the nodes do not fit a uniform buffer", flush=True)
    variants = [v for v in variants if v.name not in skipped]
    runs = [Run(v, renderers[(v.max_depth, v.integrator)], resources) for v in variants]
    for run in runs:
        run.dispatch()  # compiles on lavapipe
    reference = runs[0].image_after(CHECK_SPP)
    checks = {}
    for run in runs:
        image = run.image_after(CHECK_SPP)
        identical = bool(np.array_equal(image, reference))
        checks[run.variant.name] = {"bit_identical": identical, "mean": float(image.mean(dtype=np.float64))}
        if run.variant.same_arithmetic and not identical:
            differing = int(np.count_nonzero((image != reference).any(axis=-1)))
            raise RuntimeError(f"{name}: variant {run.variant.name} changed {differing} pixels; it must change none")
        if run.variant.same_image:
            check = agreement(image, reference, z_critical)
            checks[run.variant.name]["agreement"] = check
            if check["failures"]:
                raise RuntimeError(f"{name}: variant {run.variant.name}'s image: " + "; ".join(check["failures"]))
    seconds = {run.variant.name: [] for run in runs}
    for round_index in range(repeats):
        shift = round_index % len(runs)
        for run in runs[shift:] + runs[:shift]:
            seconds[run.variant.name].append(run.dispatch())
    base = seconds[variants[0].name]
    result = {
        "triangles": len(records.triangles),
        "binary_nodes": records.acceleration.node_count,
        "wide_records": len(records.nodes),
        "skipped": skipped,
        "variants": {},
    }
    for run in runs:
        times = seconds[run.variant.name]
        median = statistics.median(times)
        speedup = statistics.median(b / s for b, s in zip(base, times, strict=True))
        result["variants"][run.variant.name] = {
            "what": run.variant.what,
            "seconds_per_sample": times,
            "median_seconds": median,
            "speedup_vs_shipped": speedup,
            "mpaths_per_second": width * height / median / 1e6,
            **checks[run.variant.name],
        }
        print(
            f"{name:10s} {run.variant.name:18s} {median * 1e3:8.1f} ms/spp {width * height / median / 1e6:7.3f} Mpaths/s"
            f"  speed x{speedup:5.2f}  bit-identical {checks[run.variant.name]['bit_identical']}",
            flush=True,
        )
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=parse_size, default=(256, 256))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    names = [v.name for v in VARIANTS]
    parser.add_argument("--variants", nargs="+", default=names, choices=names, help="(the shipped kernel always runs)")
    args = parser.parse_args()
    width, height = args.size
    variants = [v for v in VARIANTS if v.name == "shipped" or v.name in args.variants]
    tests = len(args.scenes) * sum(v.same_image for v in variants) * len(CHANNELS)
    z_critical = sidak_critical_z(AGREEMENT_SIGNIFICANCE, max(tests, 1))
    load_before = load_average()
    results = {name: profile_scene(name, width, height, args.repeats, variants, z_critical) for name in args.scenes}
    device = describe()
    timestamps = "timestamp-query" in gpu().device.features
    data = {
        "benchmark": "kernel_profile",
        "git_revision": git_revision(),
        "environment": environment(),
        "device": device,
        "size": [width, height],
        "repeats": args.repeats,
        "seed": SEED,
        "max_depth": MAX_DEPTH,
        "timing": "gpu timestamps" if timestamps else "wall time",
        "agreement": {
            "test": "paired z-test on per-pixel differences of the image mean, per channel (same_image variants)",
            "significance_family_wise": AGREEMENT_SIGNIFICANCE,
            "sidak_tests": tests,
            "z_critical": z_critical,
        },
        "load_average_before": load_before,
        "load_average_after": load_average(),
        "scenes": results,
    }
    path = RESULTS_DIR / f"kernel_profile_{slug(device['adapter'], device['backend'])}.json"
    write_json(path, data)
    print(f"load average before {load_before}, after {data['load_average_after']}; wrote {path}")


if __name__ == "__main__":
    main()
