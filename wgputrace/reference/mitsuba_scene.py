"""Our scenes as Mitsuba 3 scenes: same triangles, materials mapped one-to-one, same camera.

    from wgputrace.reference.mitsuba_scene import load_mitsuba, mitsuba_scene
    mi = load_mitsuba("llvm_ad_rgb")
    scene = mitsuba_scene(mi, wgputrace.default_scene(), 128, 128, max_depth=9)
    image = mi.render(scene, spp=64, seed=1)

Used by scripts/make_references.py (the test references) and bench/versus_mitsuba.py. Each of
our materials becomes one mesh, flat shaded (README: Conventions; tests/data/README.md);
the integrator is Mitsuba's `path` at our max depth, the pixel filter a box.

The `llvm_ad_rgb` variant is much faster than `scalar_rgb` but needs LLVM 16 or newer (Debian:
libllvm19; the stock LLVM 15 aborts, 14 is too old), found through DRJIT_LIBLLVM_PATH or at
Debian's path of libLLVM-19.
"""

from __future__ import annotations

import os
from pathlib import Path
from types import ModuleType

import numpy as np

from wgputrace.scene import Material, Scene
from wgputrace.scene.materials.material import mitsuba_rgb

DEBIAN_LIBLLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
LLVM_VARIANT = "llvm_ad_rgb"
SCALAR_VARIANT = "scalar_rgb"

# Mitsuba's area emitters shine from their front side only; ours shine from both. Each emitter
# becomes two meshes: ours, and a copy wound the other way and moved behind it along its normal by
# this fraction of the largest coordinate, far more than float32 intersection error and far less
# than any gap in our scenes, so a ray from either side meets the copy that faces it.
EMITTER_BACK_OFFSET_RELATIVE = 1e-4
# Mitsuba's perspective camera clips at near_clip (default 0.01, an absolute length); ours clips
# nothing. Near and far clip as fractions of the scene's extent keep every surface in view.
NEAR_CLIP_RELATIVE = 1e-6
FAR_CLIP_RELATIVE = 1e3


def libllvm_path() -> str | None:
    """The LLVM library drjit's LLVM backend will load: DRJIT_LIBLLVM_PATH, else Debian's libLLVM-19."""
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        return os.environ["DRJIT_LIBLLVM_PATH"]
    return str(DEBIAN_LIBLLVM) if DEBIAN_LIBLLVM.exists() else None


def choose_variant(requested: str | None) -> str:
    """`requested`, else the LLVM variant where a usable LLVM is found, else the scalar one."""
    if requested:
        return requested
    return LLVM_VARIANT if libllvm_path() else SCALAR_VARIANT


def load_mitsuba(variant: str) -> ModuleType:
    """Mitsuba with `variant` set, DRJIT_LIBLLVM_PATH pointing at LLVM >= 16 for LLVM variants.

    Raises ImportError when mitsuba is not installed, RuntimeError naming what is missing otherwise.
    """
    if variant.startswith("llvm"):
        path = libllvm_path()
        if path is None:
            raise RuntimeError(
                f"Mitsuba's {variant} needs LLVM >= 16: set DRJIT_LIBLLVM_PATH or install Debian's libllvm19 "
                f"({DEBIAN_LIBLLVM} not found)"
            )
        # drjit reads it when it first initialises its LLVM backend, which set_variant triggers
        os.environ["DRJIT_LIBLLVM_PATH"] = path
    import mitsuba as mi

    if variant not in mi.variants():
        raise RuntimeError(f"this Mitsuba {mi.__version__} build has no variant {variant!r}; it has {mi.variants()}")
    mi.set_variant(variant)
    return mi


def bsdf_dict(material: Material) -> dict:
    """Our material as a Mitsuba BSDF: its class's mapping (material.py), in `twosided` where ours
    is two-sided; black where it reflects nothing (an emitter)."""
    if material.shader is None:
        return {"type": "diffuse", "reflectance": mitsuba_rgb((0.0, 0.0, 0.0))}
    bsdf = material.mitsuba_bsdf()
    return {"type": "twosided", "bsdf": bsdf} if material.two_sided else bsdf


def emitter_dict(material: Material) -> dict | None:
    """Our material's emission as a Mitsuba emitter (of one side), None where it emits nothing."""
    if material.emission is None:
        return None
    emitter = material.mitsuba_emitter()
    if emitter is None:
        raise ValueError(f"material {material.name!r} ({type(material).__name__}) emits but has no Mitsuba emitter")
    return emitter


def mitsuba_mesh(mi: ModuleType, name: str, triangles: np.ndarray, bsdf: dict, emitter: dict | None):
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


def mitsuba_scene(mi: ModuleType, scene: Scene, width: int, height: int, max_depth: int):
    """`scene` as a loaded Mitsuba scene: `path` integrator at `max_depth`, box-filtered width x height film."""
    arrays = scene.arrays()
    corners = arrays.vertices.reshape(-1, 3).astype(np.float64)
    extent = float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    magnitude = float(np.max(np.abs(corners)))
    shapes = {}
    for index, material in enumerate(arrays.materials):
        triangles = arrays.vertices[arrays.material_index == index]
        bsdf, emitter = bsdf_dict(material), emitter_dict(material)
        if emitter is not None:
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
