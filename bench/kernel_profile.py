"""Where the path tracer's time goes on this adapter, and what each kernel variant changes.

    python -m bench.kernel_profile                        (Cornell box and a 328k-triangle sphere)
    python -m bench.kernel_profile --size 128x128 --repeats 5 --variants function_stack

Every variant is the shipped megakernel with a shipped file rewritten in one named place (generated
from the file as shipped, so it cannot fall behind it), another binding, workgroup size or
renderer setting, on the same scene and seed. Each variant's image is first checked against the
shipped kernel's (bit for bit where the arithmetic is the same, by a paired z-test where only the
order of the work differs); then rounds of one dispatch per variant, the order rotating, and
speed-ups as medians of in-round ratios, which load changing between rounds does not move. Times
are GPU timestamps where the adapter has them. Writes bench/results/kernel_profile_<adapter>.json.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass, field

import numpy as np

from bench.command_line import argument_parser, parse
from bench.provenance import environment, git_revision, load_average
from bench.result_files import slug, write_json
from bench.validation import CHANNELS, agreement, sidak_critical_z
from wgputrace import Renderer, default_scene, make_icosphere
from wgputrace.gpu.bindings import IMAGE_WORKGROUP, STORAGE_READ, TEXTURE_U32, Binding
from wgputrace.gpu.buffers import read_buffer, storage_buffer, write_buffer
from wgputrace.gpu.device import describe, gpu
from wgputrace.gpu.kernel import Pass, Timestamps, submit
from wgputrace.gpu.layout import ACCUMULATED_PIXEL, TRIANGLE
from wgputrace.gpu.shader_source import shader_root
from wgputrace.gpu.texels import GENERATED_TEXEL_LOADERS, TEXEL_STRUCTS, texel_loaders
from wgputrace.kernels.compile import compute_kernel
from wgputrace.kernels.traversal import BVH_STACK_SIZE, GENERATED_TRAVERSAL_STACK, traversal_stack
from wgputrace.render.rng_seed import pixel_rng_states

SEED = 1
MAX_DEPTH = 9
CHECK_SPP = 8
# samples per pixel of one timed submit: one dispatch of one sample each, or of a regenerating
# variant's count
DISPATCH_SAMPLES = 8
# 20 * 4**7 = 327,680 triangles: a mesh big enough that nodes and triangles leave the CPU caches.
BIG_SPHERE_ITERATIONS = 7
# Family-wise false-alarm rate of the mean radiance tests of variants that compute the same image
# by other arithmetic (Sidak-corrected over those variants, scenes and channels).
AGREEMENT_SIGNIFICANCE = 1e-3


def rewritten(file: str, replacements: dict[str, str]) -> str:
    """The shipped `file` with each key replaced by its value; an error if the file no longer has a key."""
    text = (shader_root() / file).read_text()
    for old, new in replacements.items():
        if old not in text:
            raise RuntimeError(f"{file} no longer contains {old!r}; update bench/kernel_profile.py")
        text = text.replace(old, new)
    return text


def function_stack_traversal() -> str:
    """The shipped traverse_bvh.wgsl with its stack a function variable: WGSL then zero-fills it at
    every traversal instead of once per invocation."""
    first_local = "    var stack_size = 0u;\n"
    return rewritten(
        "geometry/traverse_bvh.wgsl",
        {
            "var<private> stack: array<u32, TRAVERSAL_STACK_SIZE>;\n": "",
            first_local: "    var stack: array<u32, TRAVERSAL_STACK_SIZE>;\n" + first_local,
        },
    )


def nearest_first_child_order() -> str:
    """The shipped bvh_child_order.wgsl putting only the nearest child first, the others unsorted."""
    return rewritten(
        "geometry/bvh_child_order.wgsl",
        {
            "    order_pair(c2, c3);\n    order_pair(c0, c2);\n    order_pair(c1, c3);\n    order_pair(c1, c2);\n": (
                "    order_pair(c0, c2);\n    order_pair(c0, c3);\n"
            )
        },
    )


def sampled_texel_loaders() -> dict[str, str]:
    """The shipped texel loaders reading sampled textures (textureLoad with a mip level) instead of
    read-only storage textures: SAMPLED_TEXELS' bindings."""
    storage, sampled = "texture_storage_2d<rgba32uint, read>", "texture_2d<u32>"
    texel_at = rewritten(
        "common/texels.wgsl", {storage: sampled, "countTrailingZeros(width)))": "countTrailingZeros(width)), 0)"}
    )
    return {
        "common/texels.wgsl": texel_at,
        GENERATED_TEXEL_LOADERS: texel_loaders(TEXEL_STRUCTS).replace(storage, sampled),
    }


SAMPLED_TEXELS = (Binding("triangles", TEXTURE_U32), Binding("nodes", TEXTURE_U32))


def storage_triangles_bindings() -> str:
    """The shipped scene_bindings.wgsl reading triangles from a storage buffer (the scene group's
    `triangles` declared as one: STORAGE_TRIANGLES)."""
    return rewritten("geometry/scene_bindings.wgsl", {"load_Triangle(triangles, index)": "triangles[index]"})


STORAGE_TRIANGLES = Binding("triangles", STORAGE_READ, TRIANGLE)


def big_sphere_scene():
    scene = default_scene()
    white = next(m for m in scene.materials if m.name == "white")
    return scene.add(make_icosphere((0.0, 0.35, 0.2), (0, 0, 0), 0.15, BIG_SPHERE_ITERATIONS, white, "big_sphere"))


SCENES = {"cornell": default_scene, "big_sphere": big_sphere_scene}


@dataclass
class Variant:
    """The shipped kernel with `sources` replaced (virtual file -> generated text), another
    workgroup or renderer setting, and the triangles as the shipped texels or a storage buffer."""

    name: str
    sources: dict[str, str] = field(default_factory=dict)
    workgroup: tuple[int, int] = IMAGE_WORKGROUP
    max_depth: int = MAX_DEPTH
    integrator: str = "mis"
    storage_triangles: bool = False
    sampled_texels: bool = False
    # samples of each pixel per dispatch (path regeneration; times are per sample)
    samples_per_dispatch: int = 1
    same_arithmetic: bool = True  # whether its image must equal the shipped kernel's bit for bit
    # Whether it computes the shipped kernel's image by other arithmetic (a traversal visiting
    # nodes in another order resolves exact ties of hit distances its own way): then its mean
    # radiance must agree with the shipped kernel's (paired z-test, `agreement`).
    same_image: bool = False
    what: str = ""


VARIANTS = [
    Variant("shipped", what="the shipped megakernel (MIS, max depth 9; 4-wide BVH records and triangles as texels)"),
    Variant("primary_only", max_depth=1, same_arithmetic=False, what="camera rays' closest hit only (max depth 1)"),
    Variant("direct_only", max_depth=2, same_arithmetic=False, what="max depth 2: primary, shadow ray, one BSDF ray"),
    Variant("no_shadow_rays", integrator="bsdf", same_arithmetic=False, what="BSDF sampling alone: no shadow rays"),
    Variant(
        "nearest_child_first",
        sources={"geometry/bvh_child_order.wgsl": nearest_first_child_order()},
        same_arithmetic=False,
        same_image=True,
        what="4-wide BVH, only the nearest child first (the others unsorted)",
    ),
    Variant(
        "function_stack",
        sources={"generated/acceleration.wgsl": function_stack_traversal()},
        what="the traversal stack a function variable, zero-filled at every traversal",
    ),
    Variant(
        "max_stack",
        sources={GENERATED_TRAVERSAL_STACK: traversal_stack(BVH_STACK_SIZE)},
        what="the shipped kernel with the largest stack (BVH_STACK_SIZE entries) instead of one sized for the tree",
    ),
    Variant(
        "storage_triangles",
        sources={"geometry/scene_bindings.wgsl": storage_triangles_bindings()},
        storage_triangles=True,
        what="triangles in a storage buffer instead of texels",
    ),
    Variant(
        "sampled_texels",
        sources=sampled_texel_loaders(),
        sampled_texels=True,
        what="nodes and triangles read as sampled textures (textureLoad with a level) instead of storage textures",
    ),
    Variant("workgroup_16x16", workgroup=(16, 16), what="workgroup 16x16"),
    Variant("workgroup_64x1", workgroup=(64, 1), what="workgroup 64x1"),
    Variant("workgroup_4x4", workgroup=(4, 4), what="workgroup 4x4"),
    Variant("regeneration_8", samples_per_dispatch=8, what="8 samples of each pixel per dispatch (path regeneration)"),
]


class Run:
    """One variant's kernel, bind groups and per-pixel state on one scene."""

    def __init__(self, variant: Variant, renderer: Renderer) -> None:
        context = renderer.context
        width, height = renderer.width, renderer.height
        self.context, self.variant, self.width, self.height = context, variant, width, height
        self.samples = renderer.samples_per_dispatch
        scene, *groups = renderer.variant.groups()
        resources = renderer.resources
        for binding in SAMPLED_TEXELS if variant.sampled_texels else ():
            scene = scene.with_binding(binding)
        if variant.storage_triangles:
            scene = scene.with_binding(STORAGE_TRIANGLES)
            resources["triangles"] = storage_buffer(context, "triangles", renderer.records.triangles)
        # the renderer's own kernel variant (its scene's traversal, stack and material kinds),
        # with the variant's sources in place of the shipped ones
        self.kernel = compute_kernel(
            context,
            "integrators/path_tracer.wgsl",
            (scene, *groups),
            renderer.variant,
            workgroup_size=variant.workgroup,
            generated=variant.sources,
            constants=renderer.variant.constants,
            label=variant.name,
        )
        self.states = pixel_rng_states(SEED, width * height)
        resources["rng_states"] = self.rng = storage_buffer(context, "rng", self.states)
        resources["accumulation"] = self.accumulation = storage_buffer(
            context, "accumulation", ACCUMULATED_PIXEL.zeros(width * height), read_back=True
        )
        if "dispatch_samples" in resources:  # every dispatch takes the variant's count
            write_buffer(context, resources["dispatch_samples"], 0, np.array([self.samples], np.uint32))
        self.bind_groups = {
            group.name: self.kernel.bind(group.name, **{b.name: resources[b.name] for b in group.bindings})
            for group in (scene, *groups)
        }
        self.timestamps = Timestamps(context) if "timestamp-query" in context.device.features else None

    def dispatch(self, count: int = 1) -> tuple[float, float]:
        """Run `count` dispatches; seconds per sample of the last one (GPU timestamps where the
        adapter has them, else wall time) and process CPU seconds per sample of them all."""
        passes = [Pass(self.kernel, (self.width, self.height), self.bind_groups)] * count
        start, cpu = time.perf_counter(), time.process_time()
        submit(self.context, passes, wait=True, timestamps=self.timestamps)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        seconds = wall / count if self.timestamps is None else self.timestamps.seconds()
        return seconds / self.samples, cpu / count / self.samples

    def image_after(self, spp: int) -> np.ndarray:
        """The sum of the first `spp` samples per pixel from the seed (a multiple of the dispatch's)."""
        device = self.context.device
        device.queue.write_buffer(self.rng, 0, self.states)
        device.queue.write_buffer(self.accumulation, 0, ACCUMULATED_PIXEL.zeros(self.width * self.height))
        self.dispatch(spp // self.samples)
        pixels = read_buffer(self.context, self.accumulation, ACCUMULATED_PIXEL.dtype, self.width * self.height)
        return pixels["sum"][:, :3].reshape(self.height, self.width, 3)


def profile_scene(name: str, width: int, height: int, repeats: int, variants: list[Variant], z_critical: float) -> dict:
    scene = SCENES[name]()
    renderers = {}
    for variant in variants:
        key = (variant.max_depth, variant.integrator, variant.samples_per_dispatch)
        if key not in renderers:
            renderers[key] = Renderer(
                scene,
                width,
                height,
                seed=SEED,
                max_depth=variant.max_depth,
                integrator=variant.integrator,
                samples_per_dispatch=variant.samples_per_dispatch,
            )
    records = renderers[(MAX_DEPTH, "mis", 1)].records
    runs = [Run(v, renderers[(v.max_depth, v.integrator, v.samples_per_dispatch)]) for v in variants]
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
    cpu = {run.variant.name: [] for run in runs}
    for round_index in range(repeats):
        shift = round_index % len(runs)
        for run in runs[shift:] + runs[:shift]:
            timed, process = run.dispatch(max(1, DISPATCH_SAMPLES // run.samples))
            seconds[run.variant.name].append(timed)
            cpu[run.variant.name].append(process)
    base = seconds[variants[0].name]
    base_cpu = cpu[variants[0].name]
    result = {
        "triangles": len(records.triangles),
        "binary_nodes": records.acceleration.node_count,
        "wide_records": len(records.nodes),
        "variants": {},
    }
    for run in runs:
        times = seconds[run.variant.name]
        median = statistics.median(times)
        speedup = statistics.median(b / s for b, s in zip(base, times, strict=True))
        process = cpu[run.variant.name]
        cpu_speedup = statistics.median(b / c for b, c in zip(base_cpu, process, strict=True))
        result["variants"][run.variant.name] = {
            "what": run.variant.what,
            "seconds_per_sample": times,
            "median_seconds": median,
            "speedup_vs_shipped": speedup,
            "process_cpu_seconds_per_sample": process,
            "process_cpu_speedup_vs_shipped": cpu_speedup,
            "mpaths_per_second": width * height / median / 1e6,
            **checks[run.variant.name],
        }
        print(
            f"{name:10s} {run.variant.name:18s} {median * 1e3:8.1f} ms/spp {width * height / median / 1e6:7.3f} Mpaths/s"
            f"  speed x{speedup:5.2f} (process CPU x{cpu_speedup:5.2f})  bit-identical {checks[run.variant.name]['bit_identical']}",
            flush=True,
        )
    return result


def main(argv: list[str] | None = None) -> None:
    parser = argument_parser(__doc__, size=(256, 256), repeats=5)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    names = [v.name for v in VARIANTS]
    parser.add_argument("--variants", nargs="+", default=names, choices=names, help="(the shipped kernel always runs)")
    args = parse(parser, argv)
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
    path = args.out / f"kernel_profile_{slug(device['adapter'], device['backend'])}.json"
    write_json(path, data)
    print(f"load average before {load_before}, after {data['load_average_after']}; wrote {path}")


if __name__ == "__main__":
    main()
