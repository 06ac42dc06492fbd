"""GPU memory per triangle by buffer, flat against smooth and textured meshes, this checkout against a
baseline revision (issue 25: textured smooth meshes cost several times the flat Cornell box).

    python -m bench.attribute_memory
    python -m bench.attribute_memory --baseline 2a58982 --segments 256

Four scenes: the flat Cornell box (the yardstick), the built-in `textured_asset` (a 4-triangle
textured panel: its fixed records, not its triangles, dominate), a smooth trefoil knot
(`scripts/make_knot_glb.py`, 49,152 triangles, normals) and a UV sphere with normals, texture
coordinates, a base colour and a normal map (4 segments^2 - 4 segments triangles), the last two as .glb files
read by the glTF loader as a user's would be. Each checkout measures them in its own process (the
baseline a git worktree of --baseline): the bytes allocated for the scene by buffer (the renderer's
`gpu_scene_bytes`) per triangle, the texture atlas left out (it grows with the images, not the
triangles) and reported apart; each scene first renders one finite sample per pixel. Target: a
smooth textured mesh at most TARGET_RATIO times the flat Cornell box's bytes per triangle. Writes
bench/results/attribute_memory_<adapter>.json and .png.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import REPO_ROOT, Run, worktree
from bench.result_files import write_result
from wgputrace.testing.gltf_files import (
    MATERIALS,
    gltf_document,
    light_node,
    marked_pixels,
    png_bytes,
    with_images,
    with_lights,
    with_vertex_attribute,
    write_glb,
)
from wgputrace.testing.uv_sphere import uv_sphere

BASELINE = "2a58982"  # main before the vertices were shared
TARGET_RATIO = 2.0
SEGMENTS = 128  # the sphere's rings, twice as many slices: 65,024 triangles (4 s^2 - 4 s)
FLAT, BUILT_IN, KNOT, SPHERE = (
    "cornell (flat)",
    "textured_asset (built-in)",
    "knot (smooth)",
    "sphere (smooth, textured)",
)
TEXTURE_ATLAS = "texture atlas"
SUN = {"type": "directional", "color": [1, 1, 1], "intensity": 3}
SIZE = 8

# Run by each checkout's Python in that checkout (so `python -c` imports its wgputrace); it uses
# only API both revisions have. Prints one JSON line: the module it imported and, per scene, its
# triangles, buffers and texture bytes, and whether its sample was finite.
MEMORY_WORKER = f"""
import json, sys
import numpy as np
import wgputrace
from wgputrace import Renderer, load_scene
from wgputrace.scenes import BUILTIN_SCENES
measured = {{}}
for name, source in json.loads(sys.argv[1]).items():
    scene = load_scene(source) if source.endswith(".glb") else BUILTIN_SCENES[source]()
    renderer = Renderer(scene, {SIZE}, {SIZE}, seed=1)
    renderer.render(1)
    measured[name] = {{
        "triangles": renderer.triangle_count,
        "buffers": renderer.gpu_scene_bytes,
        "texture_bytes": renderer.gpu_texture_bytes,
        "finite": bool(np.isfinite(renderer.image()).all()),
    }}
print(json.dumps({{"module": wgputrace.__file__, "scenes": measured}}))
"""


def sphere_glb(path: Path, segments: int) -> Path:
    """`uv_sphere` as a .glb: NORMAL, TEXCOORD_0 and indices, a base colour and a normal texture."""
    positions, normals, uvs, triangles = uv_sphere(segments)
    material = {
        **MATERIALS[0],
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
        "normalTexture": {"index": 0},
    }
    document, blob = gltf_document([(positions, triangles, 0)], materials=[material])
    blob = with_vertex_attribute(document, blob, 0, "NORMAL", normals)
    blob = with_vertex_attribute(document, blob, 0, "TEXCOORD_0", uvs)
    blob = with_images(document, blob, [png_bytes(marked_pixels(16))], "bufferView")
    document = with_lights(document, [SUN], [light_node(0, rotation=[-0.33, -0.2, 0.0, 0.92])])
    return write_glb(path, document, blob)


def knot_glb(path: Path) -> Path:
    """The smooth knot the scene-files guide compresses, written by its script."""
    subprocess.run(
        [sys.executable, str(REPO_ROOT / "scripts" / "make_knot_glb.py"), str(path)],
        check=True,
        env={"PYTHONPATH": str(REPO_ROOT), "PATH": ""},
    )
    return path


def measure(checkout: Path, sources: dict[str, str]) -> dict:
    """MEMORY_WORKER's measurement in `checkout`; SystemExit if it imported another checkout's
    wgputrace or a scene's sample was not finite."""
    finished = subprocess.run(
        [sys.executable, "-c", MEMORY_WORKER, json.dumps(sources)],
        cwd=checkout,
        capture_output=True,
        text=True,
    )
    if finished.returncode:
        raise SystemExit(f"measuring in {checkout} failed:\n{finished.stderr}")
    measured = json.loads(finished.stdout.strip().splitlines()[-1])
    if not Path(measured["module"]).is_relative_to(checkout):
        raise SystemExit(f"the process in {checkout} imported {measured['module']}, not that checkout's wgputrace")
    for name, scene in measured["scenes"].items():
        if not scene["finite"]:
            raise SystemExit(f"{name} in {checkout}: the sample is not finite, nothing measured")
    return measured["scenes"]


def per_triangle(scene: dict) -> dict:
    """Bytes per triangle by buffer (the texture atlas left out) and their total."""
    buffers = {name: size / scene["triangles"] for name, size in scene["buffers"].items() if name != TEXTURE_ATLAS}
    return {"buffers": buffers, "total": sum(buffers.values())}


def plot(path: Path, result: dict) -> None:
    import matplotlib

    chart = figure(11.0, 4.6)
    axes = chart.add_subplot(1, 1, 1)
    bars = [(scene, checkout) for scene in result["scenes"] for checkout in ("baseline", "current")]
    names = sorted({name for scene, checkout in bars for name in result["scenes"][scene][checkout]["buffers"]})
    colours = dict(zip(names, matplotlib.colormaps["tab20"].colors, strict=False))
    bottoms = np.zeros(len(bars))
    for name in names:
        heights = np.array([result["scenes"][s][c]["buffers"].get(name, 0.0) for s, c in bars])
        axes.bar(np.arange(len(bars)), heights, bottom=bottoms, label=name, color=colours.get(name))
        bottoms += heights
    for x in range(len(bars)):
        axes.text(x, bottoms[x], f"{bottoms[x]:.0f}", ha="center", va="bottom", fontsize=7)
    flat = result["scenes"][FLAT]["current"]["total"]
    axes.axhline(TARGET_RATIO * flat, color="grey", linestyle=":", label=f"{TARGET_RATIO:g} x the flat Cornell box")
    revisions = {"baseline": result["baseline_revision"], "current": result["git_revision"]}
    labels = [f"{scene.split(' (')[0]}\n{revisions[checkout]}" for scene, checkout in bars]
    axes.set_xticks(np.arange(len(bars)), labels, fontsize=7)
    axes.set_ylabel("GPU bytes per triangle (textures apart)")
    axes.legend(fontsize=6, ncols=2)
    save_figure(chart, path, result, "Scene memory on the GPU per triangle, by buffer")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__)
    parser.add_argument("--baseline", default=BASELINE, help=f"revision to compare against (default {BASELINE})")
    parser.add_argument("--segments", type=int, default=SEGMENTS, help=f"the sphere's rings (default {SEGMENTS})")
    args = parse(parser, argv, "segments")
    run = Run()
    with tempfile.TemporaryDirectory(prefix="wgputrace-memory-") as folder:
        sources = {
            FLAT: "cornell",
            BUILT_IN: "textured_asset",
            KNOT: str(knot_glb(Path(folder) / "knot.glb")),
            SPHERE: str(sphere_glb(Path(folder) / "sphere.glb", args.segments)),
        }
        log("measuring this checkout")
        current = measure(REPO_ROOT, sources)
        with worktree(args.baseline) as baseline:
            log(f"measuring {args.baseline}")
            old = measure(baseline, sources)
    scenes = {}
    for name in sources:
        scenes[name] = {
            "triangles": current[name]["triangles"],
            "texture_bytes": current[name]["texture_bytes"],
            "baseline": per_triangle(old[name]),
            "current": per_triangle(current[name]),
        }
    flat = scenes[FLAT]["current"]["total"]
    targets = {
        name: {
            "ratio_to_flat": scenes[name]["current"]["total"] / flat,
            "met": scenes[name]["current"]["total"] <= TARGET_RATIO * flat,
        }
        for name in (KNOT, SPHERE)
    }
    print(f"{'scene':<28}{'triangles':>10}{args.baseline:>10}{'now':>10}  B per triangle, textures apart")
    for name, scene in scenes.items():
        print(
            f"{name:<28}{scene['triangles']:>10,}{scene['baseline']['total']:>10.1f}{scene['current']['total']:>10.1f}"
        )
    for name, target in targets.items():
        print(
            f"{name}: {target['ratio_to_flat']:.2f} x the flat Cornell box (target <= {TARGET_RATIO:g}: {'met' if target['met'] else 'NOT met'})"
        )
    result = {
        "scene": "; ".join(sources),
        "width": SIZE,
        "height": SIZE,
        "spp": 1,
        "max_depth": None,
        "baseline_revision": args.baseline,
        "sphere_segments": args.segments,
        "excluded": "the texture atlas (texture_bytes per scene): it grows with the images, not the triangles",
        "scenes": scenes,
        "target_ratio": TARGET_RATIO,
        "targets": targets,
    }
    write_result("attribute_memory", result, out=args.out, plot=plot, run=run)
    return 0 if all(target["met"] for target in targets.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
