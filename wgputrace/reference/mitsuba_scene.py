"""Our scenes as Mitsuba 3 scenes: same triangles, materials mapped one-to-one, same camera, for the
test references (`python scripts/make_references.py`) and `python -m bench.versus_mitsuba`.

    from wgputrace.reference.mitsuba_scene import load_mitsuba, mitsuba_scene
    mi = load_mitsuba("llvm_ad_rgb")
    scene = mitsuba_scene(mi, wgputrace.default_scene(), 128, 128, max_depth=9)
    image = mi.render(scene, spp=64, seed=1)

Each material becomes one mesh (`mitsuba_mesh`) with the BSDF and emitter its class maps it to
(`bsdf_dict`, `emitter_dict`) and, where it absorbs, an interior `homogeneous` medium
(`mitsuba_medium`), flat unless its shapes have corner normals, its colour read from the vertex
colours where its triangles have any (`vertex_colored`); each light brings its own
`mitsuba_emitter()`, the environment is a `constant` or an `envmap` (`environment_dict`). The
integrator is `path` at our max depth (`volpath` where a material absorbs, which traces the
media; otherwise the same), the pixel filter a box. `llvm_ad_rgb` is much faster than
`scalar_rgb` but needs LLVM 16 or newer (`libllvm_path`).
"""

from __future__ import annotations

import os
from pathlib import Path
from types import ModuleType

import numpy as np

from wgputrace.scene import Light, Material, Scene, Sensor
from wgputrace.scene.lights.environment import Environment
from wgputrace.scene.materials.volume import mitsuba_medium
from wgputrace.scene.registry import mitsuba_rgb
from wgputrace.scene.shapes import corner_colors, corner_normals, corner_uvs
from wgputrace.scene.tangents import corner_tangents

# Debian's libllvm19: drjit aborts with the stock LLVM 15, and 14 is too old.
DEBIAN_LIBLLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
LLVM_VARIANT = "llvm_ad_rgb"
SCALAR_VARIANT = "scalar_rgb"

# Mitsuba's area emitters shine from their front side only; ours shine from both. Each emitter
# becomes two meshes: ours, and a copy wound the other way and moved behind it along its normal by
# this fraction of the largest coordinate, far more than float32 intersection error and far less
# than any gap in our scenes, so a ray from either side meets the copy that faces it.
EMITTER_BACK_OFFSET_RELATIVE = 1e-4
# Mitsuba's cameras clip at near_clip (default 0.01, an absolute length; its orthographic and thin
# lens rays start there); ours clip nothing. Near and far clip as fractions of the scene's extent
# keep every surface in view.
NEAR_CLIP_RELATIVE = 1e-6
FAR_CLIP_RELATIVE = 1e3
# The per-vertex mesh attribute our corner colours become, which Mitsuba's `mesh_attribute` texture reads
VERTEX_COLOR_ATTRIBUTE = "vertex_color"


def sensor_dict(mi: ModuleType, camera: Sensor, width: int, height: int) -> dict:
    """The camera kind's Mitsuba sensor (`Sensor.mitsuba_sensor`) with its transform made: Mitsuba's
    look_at gives image right = cross(forward, up), as ours (checked: the Cornell box's red wall is
    left), then the kind's scale. ValueError for a kind no Mitsuba sensor is."""
    sensor = camera.mitsuba_sensor(width, height)
    if sensor is None:
        raise ValueError(f"Mitsuba 3 has no sensor for the {type(camera).__name__}")
    pose = sensor["to_world"]
    to_world = mi.ScalarTransform4f().look_at(**pose["look_at"])
    if "scale" in pose:
        to_world = to_world @ mi.ScalarTransform4f().scale(list(pose["scale"]))
    return {**sensor, "to_world": to_world}


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


def bsdf_dict(material: Material, tangents: np.ndarray | None = None, colored: bool = False) -> dict:
    """Our material as a Mitsuba BSDF: its class's mapping (`mitsuba_bsdf`), in `twosided` where ours
    is two-sided; black where it reflects nothing (an emitter). A normal-mapped material is given
    the handedness of its triangles' corner `tangents` (one for all: Mitsuba's `normalmap` has one
    texture per BSDF); a `colored` one reads its colour from VERTEX_COLOR_ATTRIBUTE."""
    if material.shader is None:
        return {"type": "diffuse", "reflectance": mitsuba_rgb((0.0, 0.0, 0.0))}
    if "normal" not in material.textures():
        bsdf = material.mitsuba_bsdf()
    else:
        bsdf = material.mitsuba_bsdf(tangent_handedness=uniform_handedness(material, tangents))
    if colored:
        bsdf = bsdf | {material.mitsuba_color: {"type": "mesh_attribute", "name": VERTEX_COLOR_ATTRIBUTE}}
    if not material.two_sided or transmits(bsdf):
        return bsdf
    if bsdf["type"] == "mask":  # Mitsuba's twosided refuses a BSDF that transmits: it goes inside
        return bsdf | {"bsdf": {"type": "twosided", "bsdf": bsdf["bsdf"]}}
    return {"type": "twosided", "bsdf": bsdf}


def transmits(bsdf: dict) -> bool:
    """Whether a BSDF dict (inside its wrappers) is a `principled` with transmission, whose back is
    its inside: Mitsuba's `twosided` refuses it, and it needs none."""
    while "bsdf" in bsdf:
        bsdf = bsdf["bsdf"]
    return bsdf["type"] == "principled" and bsdf.get("spec_trans", 0.0) > 0.0


def uniform_handedness(material: Material, tangents: np.ndarray | None) -> float:
    """The w shared by every corner tangent of `material`'s triangles; ValueError where they differ
    or where there are none (a material exported without its triangles). Mitsuba's `normalmap`
    frames the texel with the triangle's dP/du, ours with these tangents: the same frame where
    they follow dP/du (a flat, undistorted UV map)."""
    signs = np.unique(np.sign(tangents[..., 3])) if tangents is not None else np.zeros(0)
    if len(signs) != 1 or signs[0] == 0:
        raise ValueError(
            f"material {material.name!r}: its normal map's triangles have tangent handedness {signs.tolist()}; "
            "Mitsuba's normalmap export needs one (+1 or -1)"
        )
    return float(signs[0])


def vertex_colored(material: Material, colors: np.ndarray) -> np.ndarray | None:
    """The (n, 3, 3) values of VERTEX_COLOR_ATTRIBUTE for `material`'s triangles of (n, 3, 4) corner
    `colors`: their RGB times the material's colour, whose BSDF parameter (`mitsuba_color`) then
    reads them; None where they are all white or the material reflects nothing (vertex colours
    leave an emitter alone). The export's meshes share no vertices, so a corner colour is a vertex
    colour there, interpolated over the triangle as ours; and the product of a constant and an
    interpolation is the interpolation of the products. ValueError for a material whose colour
    is no plain BSDF parameter (textured, or of a kind without `mitsuba_color`) or whose vertex
    alpha would matter."""
    if material.shader is None or np.all(colors == 1.0):
        return None
    if material.mitsuba_color is None or material.textures():
        raise ValueError(f"{material.label}: vertex colours on a {type(material).__name__} have no Mitsuba 3 export")
    if material.lets_rays_through() and np.any(colors[..., 3] != 1.0):
        raise ValueError(f"{material.label}: vertex alpha has no Mitsuba 3 export")
    color = material.mitsuba_bsdf()[material.mitsuba_color]["value"]
    return colors[..., :3] * np.asarray(color, np.float32)


def emitter_dict(material: Material) -> dict | None:
    """Our material's emission as a Mitsuba emitter (of one side), None where it emits nothing."""
    emitter = material.mitsuba_emitter()
    if emitter is None and material.emission_wgsl is not None:
        raise ValueError(f"material {material.name!r} ({type(material).__name__}) emits but has no Mitsuba emitter")
    return emitter


def transform(mi: ModuleType, value):
    """A light dict's {"look_at": {...}} as Mitsuba's ScalarTransform4f; anything else unchanged."""
    if isinstance(value, dict) and set(value) == {"look_at"}:
        return mi.ScalarTransform4f().look_at(**value["look_at"])
    return value


def light_dict(mi: ModuleType, light: Light) -> dict:
    """One of our lights as a Mitsuba emitter dict; ValueError for a kind no Mitsuba plugin is."""
    emitter = light.mitsuba_emitter()
    if emitter is None:
        raise ValueError(f"{light.label} has no Mitsuba 3 emitter ({type(light).__module__})")
    return {key: transform(mi, value) for key, value in emitter.items()}


def environment_dict(mi: ModuleType, environment: Environment) -> dict:
    """`constant` for a constant environment; for a map, `envmap` of its texels as a bitmap, which
    Mitsuba reads as it reads an .exr file (linear float RGB), scaled and turned as ours."""
    if environment.texels is None:
        radiance = np.asarray(environment.radiance) * environment.intensity
        return {"type": "constant", "radiance": mitsuba_rgb(radiance)}
    return {
        "type": "envmap",
        # a writable copy: the binding refuses read-only arrays, and our texels are read-only
        "bitmap": mi.Bitmap(np.array(environment.texels, dtype=np.float32, order="C")),
        "scale": environment.intensity,
        "to_world": mi.ScalarTransform4f().rotate([0.0, 1.0, 0.0], environment.rotation_degrees),
    }


def emitters(mi: ModuleType, scene: Scene, has_emitting_triangles: bool) -> tuple[dict, bool]:
    """The scene's environment and lights as Mitsuba emitter dicts by name, and whether camera rays
    must not see emitters (a hidden environment)."""
    found = {f"light_{index}": light_dict(mi, light) for index, light in enumerate(scene.lights)}
    environment = scene.environment
    if environment is None or environment.black:
        return found, False
    if not environment.visible and has_emitting_triangles:
        raise ValueError(
            "a hidden environment (visible=False) with emitting triangles has no Mitsuba 3 equivalent: "
            "hide_emitters would hide the triangles too"
        )
    found["environment"] = environment_dict(mi, environment)
    return found, not environment.visible


def with_mitsuba_objects(mi: ModuleType, value):
    """A plugin dict with the numpy arrays our materials give (Texture.mitsuba_bitmap) as the
    objects Mitsuba's parser takes: a bitmap's `data` as a tensor, its `to_uv` as a transform."""
    if not isinstance(value, dict):
        return value
    converted = {key: with_mitsuba_objects(mi, item) for key, item in value.items()}
    if value.get("type") == "bitmap":
        converted["data"] = mi.TensorXf(value["data"])
        converted["to_uv"] = mi.ScalarTransform4f(value["to_uv"].tolist())
    return converted


def mitsuba_mesh(
    mi: ModuleType,
    name: str,
    triangles: np.ndarray,
    bsdf: dict,
    emitter: dict | None,
    normals: np.ndarray | None = None,
    uvs: np.ndarray | None = None,
    colors: np.ndarray | None = None,
    interior: dict | None = None,
):
    """A Mitsuba mesh of (n, 3, 3) float32 triangles, corners not shared: flat shaded, or smooth
    with (n, 3, 3) corner `normals`; (n, 3, 2) corner `uvs` become its texture coordinates,
    (n, 3, 3) corner `colors` its VERTEX_COLOR_ATTRIBUTE, and `interior` its interior medium (the
    side its normals point away from)."""
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(with_mitsuba_objects(mi, bsdf))
    if interior is not None:
        props["interior"] = mi.load_dict(interior)
    if emitter is not None:
        props["emitter"] = mi.load_dict(with_mitsuba_objects(mi, emitter))
    smooth = normals is not None
    if smooth:
        props["face_normals"] = False
    count = len(triangles)
    textured = uvs is not None
    mesh = mi.Mesh(name, 3 * count, count, props=props, has_vertex_normals=smooth, has_vertex_texcoords=textured)
    params = mi.traverse(mesh)
    # the buffers' own types: dynamic arrays in scalar variants, JIT arrays in llvm ones
    positions, faces = type(params["vertex_positions"]), type(params["faces"])
    params["vertex_positions"] = positions(np.ascontiguousarray(triangles, dtype=np.float32).ravel())
    params["faces"] = faces(np.arange(3 * count, dtype=np.uint32))
    if smooth:
        params["vertex_normals"] = type(params["vertex_normals"])(np.ascontiguousarray(normals, np.float32).ravel())
    if textured:
        params["vertex_texcoords"] = type(params["vertex_texcoords"])(np.ascontiguousarray(uvs, np.float32).ravel())
    params.update()
    if colors is not None:
        mesh.add_attribute(VERTEX_COLOR_ATTRIBUTE, 3, np.ascontiguousarray(colors, np.float32).ravel())
    return mesh


def face_normals_where_flat(triangles: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """`normals` with the all-zero corners of flat triangles replaced by their face normal."""
    v = triangles.astype(np.float64)
    face = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    flat = ~normals.any(axis=(1, 2))
    filled = normals.copy()
    filled[flat] = face[flat, None, :].astype(np.float32)
    return filled


def behind(triangles: np.ndarray, distance: float) -> np.ndarray:
    """The triangles wound the other way and moved `distance` against their normals."""
    v = triangles.astype(np.float64)
    normal = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return rewound((v - distance * normal[:, None, :]).astype(np.float32))


def rewound(corners: np.ndarray | None) -> np.ndarray | None:
    """Per-corner values (n, 3, ...) in the order of triangles wound the other way (behind's)."""
    return None if corners is None else corners[:, [0, 2, 1]]


def mitsuba_scene(mi: ModuleType, scene: Scene, width: int, height: int, max_depth: int):
    """`scene` as a loaded Mitsuba scene: `path` integrator (`volpath` with media) at `max_depth`,
    box-filtered width x height film; its instances flattened into triangles of their own."""
    if scene.instances:
        scene = scene.flattened()
    arrays = scene.arrays()
    corners = arrays.vertices.reshape(-1, 3).astype(np.float64)
    extent = float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    magnitude = float(np.max(np.abs(corners)))
    all_normals = corner_normals(scene.shapes, arrays.shape_index, arrays.local_index)
    all_uvs = corner_uvs(scene.shapes, arrays.shape_index, arrays.local_index)
    all_tangents = corner_tangents(scene.shapes, arrays.shape_index, arrays.local_index)
    all_colors = corner_colors(scene.shapes, arrays.shape_index, arrays.local_index)
    shapes = {}
    emitting = absorbing = False
    for index, material in enumerate(arrays.materials):
        mine = arrays.material_index == index
        triangles = arrays.vertices[mine]
        normals = None
        if all_normals is not None and all_normals[mine].any():
            normals = face_normals_where_flat(triangles, all_normals[mine])
        uvs = None if all_uvs is None else all_uvs[mine]
        colors = None if all_colors is None else vertex_colored(material, all_colors[mine])
        bsdf = bsdf_dict(material, all_tangents[mine], colored=colors is not None)
        emitter = emitter_dict(material)
        interior = mitsuba_medium(material.absorption())
        absorbing = absorbing or interior is not None
        if emitter is not None and interior is not None:
            raise ValueError(
                f"material {material.name!r} both emits and absorbs: its export has two meshes, one medium"
            )
        if emitter is not None:
            emitting = True
            front = mitsuba_mesh(mi, f"{material.name}_front", triangles, bsdf, emitter, normals, uvs, colors)
            back = behind(triangles, EMITTER_BACK_OFFSET_RELATIVE * magnitude)
            back_normals = None if normals is None else -rewound(normals)
            shapes[f"{index}_front"] = front
            shapes[f"{index}_back"] = mitsuba_mesh(
                mi, f"{material.name}_back", back, bsdf, emitter, back_normals, rewound(uvs), rewound(colors)
            )
        else:
            shapes[f"{index}"] = mitsuba_mesh(mi, material.name, triangles, bsdf, None, normals, uvs, colors, interior)
    lights, hide_emitters = emitters(mi, scene, emitting)
    sensor = {
        **sensor_dict(mi, scene.camera, width, height),
        "near_clip": NEAR_CLIP_RELATIVE * extent,
        "far_clip": FAR_CLIP_RELATIVE * extent,
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
    integrator = {"type": "volpath" if absorbing else "path", "max_depth": max_depth, "hide_emitters": hide_emitters}
    return mi.load_dict({"type": "scene", "integrator": integrator, "sensor": sensor, **shapes, **lights})
