"""Reference images from Mitsuba 3 for the render tests: tests/references/<scene>.npz.

    pip install -e ".[reference]"                     # mitsuba>=3.5
    python scripts/make_references.py                 # every reference scene
    python scripts/make_references.py cornell --passes 8 --variant scalar_rgb

Each scene is built in Mitsuba from our own triangles (one mesh per material, flat shaded), our
materials mapped one-to-one (README: Conventions; ../shared/scenes/README.md) and our camera, and
rendered with Mitsuba's `path` integrator at the same max depth and a box pixel filter. Several
passes with different seeds give a per-pixel mean and its standard error; both are stored as
float16 with the settings and versions used.

The `llvm_ad_rgb` variant is much faster but needs LLVM 16 or newer (Debian: libllvm19; the stock
LLVM 15 aborts, 14 is too old): it is used when DRJIT_LIBLLVM_PATH is set or Debian's libLLVM-19 is
installed, `scalar_rgb` (pip wheels alone) otherwise.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import asdict, dataclass
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
if __package__ in (None, ""):
    sys.path.insert(0, str(REPO_ROOT))

from wgputrace.scene import MaterialKind, Scene  # noqa: E402
from wgputrace.scenes import scene_by_name  # noqa: E402

REFERENCE_DIR = REPO_ROOT / "tests" / "references"
WIDTH = HEIGHT = 128
DEBIAN_LIBLLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
FLOAT16_MAX = float(np.finfo(np.float16).max)

# Mitsuba's area emitters shine from their front side only; ours shine from both. Each emitter
# becomes two meshes: ours, and a copy wound the other way and moved behind it along its normal by
# this fraction of the largest coordinate, far more than float32 intersection error and far less
# than any gap in our scenes, so a ray from either side meets the copy that faces it.
EMITTER_BACK_OFFSET_RELATIVE = 1e-4
# Mitsuba's perspective camera clips at near_clip (default 0.01, an absolute length); ours clips
# nothing. Near and far clip as fractions of the scene's extent keep every surface in view.
NEAR_CLIP_RELATIVE = 1e-6
FAR_CLIP_RELATIVE = 1e3


@dataclass(frozen=True)
class ReferenceSettings:
    max_depth: int
    spp: int  # samples per pixel in one pass
    passes: int  # independent passes (seeds 0 .. passes - 1), for the standard error


# The scenes with a reference of their own (the scaled Cornell boxes are tested against `cornell`).
REFERENCES = {
    "cornell": ReferenceSettings(max_depth=9, spp=256, passes=16),
    "tiny_light": ReferenceSettings(max_depth=9, spp=256, passes=16),
    "glass_grazing": ReferenceSettings(max_depth=12, spp=256, passes=16),
    "glossy_spheres": ReferenceSettings(max_depth=6, spp=256, passes=16),
    "slivers": ReferenceSettings(max_depth=5, spp=256, passes=16),
    "axis_boxes": ReferenceSettings(max_depth=6, spp=256, passes=16),
}


def choose_variant(requested: str | None) -> str:
    if requested:
        return requested
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        return "llvm_ad_rgb"
    if DEBIAN_LIBLLVM.exists():
        os.environ["DRJIT_LIBLLVM_PATH"] = str(DEBIAN_LIBLLVM)
        return "llvm_ad_rgb"
    return "scalar_rgb"


def rgb(value) -> dict:
    return {"type": "rgb", "value": [float(v) for v in value]}


def bsdf_dict(material) -> dict:
    """Our material as a Mitsuba BSDF (emitters get a black one)."""
    if material.kind == MaterialKind.DIFFUSE:
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(material.color)}}
    if material.kind == MaterialKind.GLOSSY:
        conductor = {
            "type": "roughconductor",
            "material": "none",
            "distribution": "ggx",
            "sample_visible": True,
            "alpha": material.roughness,
            "specular_reflectance": rgb(material.color),
        }
        return {"type": "twosided", "bsdf": conductor}
    if material.kind == MaterialKind.GLASS:
        return {
            "type": "dielectric",
            "int_ior": material.ior,
            "ext_ior": 1.0,
            "specular_transmittance": rgb(material.color),
        }
    if material.kind == MaterialKind.EMITTER:
        return {"type": "diffuse", "reflectance": rgb((0.0, 0.0, 0.0))}
    raise ValueError(f"material {material.name!r}: no Mitsuba mapping for kind {material.kind!r}")


def mitsuba_mesh(mi, name: str, triangles: np.ndarray, bsdf: dict, emitter: dict | None):
    """A flat-shaded Mitsuba mesh of (n, 3, 3) float32 triangles, corners not shared."""
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if emitter is not None:
        props["emitter"] = mi.load_dict(emitter)
    count = len(triangles)
    mesh = mi.Mesh(name, 3 * count, count, props=props, has_vertex_normals=False, has_vertex_texcoords=False)
    params = mi.traverse(mesh)
    # the buffers' own types: dynamic arrays in scalar variants, JIT arrays in llvm ones
    positions, faces = type(params["vertex_positions"]), type(params["faces"])
    params["vertex_positions"] = positions(np.ascontiguousarray(triangles, dtype=np.float32).ravel())
    params["faces"] = faces(np.arange(3 * count, dtype=np.uint32))
    params.update()
    return mesh


def behind(triangles: np.ndarray, distance: float) -> np.ndarray:
    """The triangles wound the other way and moved `distance` against their normals."""
    v = triangles.astype(np.float64)
    normal = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return (v - distance * normal[:, None, :])[:, [0, 2, 1]].astype(np.float32)


def mitsuba_scene(mi, scene: Scene, width: int, height: int, max_depth: int):
    arrays = scene.arrays()
    corners = arrays.vertices.reshape(-1, 3).astype(np.float64)
    extent = float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    magnitude = float(np.max(np.abs(corners)))
    shapes = {}
    for index, material in enumerate(arrays.materials):
        triangles = arrays.vertices[arrays.material_index == index]
        bsdf = bsdf_dict(material)
        if material.kind == MaterialKind.EMITTER:
            emitter = {"type": "area", "radiance": rgb(material.radiance)}
            shapes[f"{index}_front"] = mitsuba_mesh(mi, f"{material.name}_front", triangles, bsdf, emitter)
            back = behind(triangles, EMITTER_BACK_OFFSET_RELATIVE * magnitude)
            shapes[f"{index}_back"] = mitsuba_mesh(mi, f"{material.name}_back", back, bsdf, emitter)
        else:
            shapes[f"{index}"] = mitsuba_mesh(mi, material.name, triangles, bsdf, None)
    camera = scene.camera
    position = np.asarray(camera.position)
    sensor = {
        "type": "perspective",
        "fov_axis": "y",
        "fov": camera.vfov_degrees,
        "near_clip": NEAR_CLIP_RELATIVE * extent,
        "far_clip": FAR_CLIP_RELATIVE * extent,
        # Mitsuba's look_at gives image right = cross(forward, up), as ours (checked: red wall left)
        "to_world": mi.ScalarTransform4f().look_at(
            origin=position.tolist(), target=(position + camera.forward).tolist(), up=list(camera.up)
        ),
        "film": {
            "type": "hdrfilm",
            "width": width,
            "height": height,
            "pixel_format": "rgb",
            "component_format": "float32",
            "rfilter": {"type": "box"},
        },
        "sampler": {"type": "independent"},
    }
    return mi.load_dict(
        {"type": "scene", "integrator": {"type": "path", "max_depth": max_depth}, "sensor": sensor, **shapes}
    )


def render_passes(mi, scene, name: str, settings: ReferenceSettings) -> tuple[np.ndarray, np.ndarray]:
    """Per-pixel mean and standard error of `passes` independent Mitsuba renders."""
    images = []
    for seed in range(settings.passes):
        image = np.asarray(mi.render(scene, spp=settings.spp, seed=seed), dtype=np.float64)
        bad = np.argwhere(~np.isfinite(image))
        if len(bad):
            row, column, channel = bad[0]
            raise RuntimeError(
                f"{name}: Mitsuba pass {seed} has {len(bad)} non-finite values, the first at row {row}, "
                f"column {column}, channel {channel}: {image[row, column, channel]}"
            )
        images.append(image)
        print(f"  pass {seed + 1}/{settings.passes}", file=sys.stderr, end="\r", flush=True)
    stack = np.stack(images)
    return stack.mean(axis=0), stack.std(axis=0, ddof=1) / np.sqrt(settings.passes)


def to_float16(name: str, label: str, values: np.ndarray) -> np.ndarray:
    too_big = np.argwhere(values > FLOAT16_MAX)
    if len(too_big):
        row, column, channel = too_big[0]
        raise ValueError(
            f"{name}: {label} at row {row}, column {column}, channel {channel} is {values[row, column, channel]:.6g}, "
            f"above float16's largest value {FLOAT16_MAX}"
        )
    return values.astype(np.float16)


def make_reference(name: str, settings: ReferenceSettings, variant: str, out_dir: Path) -> Path:
    import drjit
    import mitsuba as mi

    mi.set_variant(variant)
    start = time.perf_counter()
    scene = mitsuba_scene(mi, scene_by_name(name), WIDTH, HEIGHT, settings.max_depth)
    mean, standard_error = render_passes(mi, scene, name, settings)
    seconds = time.perf_counter() - start
    metadata = {
        "scene": name,
        "width": WIDTH,
        "height": HEIGHT,
        **asdict(settings),
        "renderer": "mitsuba",
        "integrator": "path",
        "mitsuba": mi.__version__,
        "drjit": drjit.__version__,
        "variant": variant,
        "seconds": round(seconds, 1),
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / f"{name}.npz"
    np.savez_compressed(
        path,
        mean=to_float16(name, "mean", mean),
        standard_error=to_float16(name, "standard error", standard_error),
        metadata=np.array(json.dumps(metadata)),
    )
    print(f"{name}: {settings.passes} x {settings.spp} spp in {seconds:.1f} s -> {path}", file=sys.stderr)
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="*", default=list(REFERENCES), help=f"default: {' '.join(REFERENCES)}")
    parser.add_argument("--variant", help="Mitsuba variant (default: llvm_ad_rgb where LLVM >= 16 is found)")
    parser.add_argument("--spp", type=int, help="samples per pixel per pass (default: per scene)")
    parser.add_argument("--passes", type=int, help="independent passes (default: per scene)")
    parser.add_argument("--out", type=Path, default=REFERENCE_DIR, help=f"output folder (default {REFERENCE_DIR})")
    args = parser.parse_args(argv)
    unknown = [name for name in args.scenes if name not in REFERENCES]
    if unknown:
        parser.error(f"no reference settings for {', '.join(unknown)}; known: {', '.join(REFERENCES)}")
    variant = choose_variant(args.variant)
    for name in args.scenes:
        settings = REFERENCES[name]
        settings = ReferenceSettings(
            settings.max_depth, args.spp or settings.spp, args.passes if args.passes else settings.passes
        )
        make_reference(name, settings, variant, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
