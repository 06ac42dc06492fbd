"""Below which roughness should a glossy vertex skip light sampling? Measured, not guessed.

    python -m bench.glossy_light_sampling

For each roughness, a glossy sphere lit by one small area light (nothing else in the scene, so
every pixel's error comes from the glossy vertex) is rendered with MIS twice: light sampling at
the glossy vertex on (threshold 0) and off (threshold above every roughness: BSDF sampling
only). Both are unbiased, so the reference is a long render averaging both. The efficiency of
each is 1 / (relative MSE x seconds); the threshold to choose is the smallest roughness from
which light sampling is at least as efficient. Writes bench/results/glossy_light_sampling_<adapter>.json
and .png; the value in shaders/integrators/path_tracer.wgsl (GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS) comes from it.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from bench.common import Run, argument_parser, figure, image_failures, log, parse, save_figure, write_result
from wgputrace import Camera, Emitter, Glossy, Renderer, Scene, make_icosphere, make_plane

ROUGHNESSES = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5)
THRESHOLD = "GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS"
POLICIES = {"light sampling on": 0.0, "light sampling off": 2.0}
# Direct light only: the glossy vertex is the only one whose strategy differs.
MAX_DEPTH = 2
# The two long renders must agree within this many standard errors of their mean difference.
AGREEMENT_Z = 4.0


def glossy_sphere(roughness: float) -> Scene:
    sphere = make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 4, Glossy("metal", color=(0.9, 0.9, 0.9), roughness=roughness))
    # a light a fifth of the sphere's size, above and in front, so its highlight is in view
    lamp = make_plane((0, 2.5, -1.5), (0.6, 0, 0), (0.4, 0.4), Emitter("lamp", emittance=40.0), "lamp")
    return Scene([sphere, lamp], Camera.looking_at((0, 0.5, -3.5), (0, 0, 0), vfov_degrees=40.0))


def render_timed(scene: Scene, size: int, spp: int, threshold: float, seed: int) -> tuple[np.ndarray, float]:
    renderer = Renderer(scene, size, size, seed=seed, max_depth=MAX_DEPTH, shader_overrides={THRESHOLD: threshold})
    renderer.render(1)  # warm-up: the first dispatch compiles the shader on lavapipe
    renderer.reset()
    stats = renderer.render(spp)
    image = renderer.image()
    failures = image_failures(image, renderer.dropped_samples)
    if failures:
        raise SystemExit(f"threshold {threshold}: {'; '.join(failures)}")
    return image, stats.render_seconds


def relative_mse(image: np.ndarray, reference: np.ndarray) -> float:
    """Mean over pixels of (error / (reference + 0.01))^2: bright highlights do not dominate."""
    return float(np.mean(((image - reference) / (reference + 0.01)) ** 2))


def measure(size: int, spp: int, reference_spp: int, repeats: int) -> list[dict]:
    rows = []
    for roughness in ROUGHNESSES:
        scene = glossy_sphere(roughness)
        references = [
            render_timed(scene, size, reference_spp, t, seed=1000 + i)[0] for i, t in enumerate(POLICIES.values())
        ]
        reference = np.mean(references, axis=0)
        # validate before timing: both policies are unbiased, so the mean of their per-pixel
        # difference is zero within its standard error (pixels are independent)
        difference = (references[0] - references[1]).reshape(-1)
        z = difference.mean() / (difference.std(ddof=1) / np.sqrt(difference.size))
        if abs(z) > AGREEMENT_Z:
            raise SystemExit(f"roughness {roughness}: long renders disagree (z = {z:.1f}); a policy is biased")
        row = {"roughness": roughness}
        for name, threshold in POLICIES.items():
            errors, seconds = [], []
            for repeat in range(repeats):
                image, spent = render_timed(scene, size, spp, threshold, seed=repeat + 1)
                errors.append(relative_mse(image, reference))
                seconds.append(spent)
            mse, time_spent = float(np.median(errors)), float(np.median(seconds))
            row[name] = {"relative_mse": mse, "seconds": time_spent, "efficiency": 1.0 / (mse * time_spent)}
        row["light sampling gain"] = row["light sampling on"]["efficiency"] / row["light sampling off"]["efficiency"]
        log(f"roughness {roughness:6.3f}: light sampling efficiency x{row['light sampling gain']:.2f}")
        rows.append(row)
    return rows


def plot(path: Path, result: dict) -> None:
    rows = result["rows"]
    chart = figure(6.0, 4.0)
    axis = chart.add_subplot()
    axis.semilogx([r["roughness"] for r in rows], [r["light sampling gain"] for r in rows], "o-")
    axis.axhline(1.0, color="grey", linestyle="--")
    axis.set_yscale("log")
    axis.set_xlabel("GGX roughness (alpha)")
    axis.set_ylabel("efficiency with / without light sampling")
    title = f"light sampling at a glossy vertex, {result['width']}^2, {result['spp']} spp"
    save_figure(chart, path, result, title, dpi=120)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, spp=16, repeats=3)
    parser.add_argument("--size", type=int, default=96, help="image width and height (default 96)")
    parser.add_argument("--reference-spp", type=int, default=512, help="samples per pixel of each reference half")
    args = parse(parser, argv, "size", "reference_spp")
    run = Run()
    rows = measure(args.size, args.spp, args.reference_spp, args.repeats)
    helping = [r["roughness"] for r in rows if r["light sampling gain"] >= 1.0]
    threshold = min(helping) if helping else None
    result = {
        "scene": "a glossy sphere under a small light, at each roughness",
        "width": args.size,
        "height": args.size,
        "spp": args.spp,
        "reference_spp": 2 * args.reference_spp,
        "max_depth": MAX_DEPTH,
        "repeats": args.repeats,
        "rows": rows,
        "smallest_roughness_where_light_sampling_helps": threshold,
    }
    write_result("glossy_light_sampling", result, out=args.out, plot=plot, run=run)
    print(f"light sampling helps from roughness {threshold}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
