"""Wavefront OBJ with MTL materials, read line by line so that every error names its file and line.

Why not trimesh's OBJ reader, which the other formats use: it renamed and reordered the objects
of tests/data/cornell_trac0r.obj (all ten came back as "wall_left_N", last first), skips
lines it cannot parse without saying which, and keeps MTL keys it does not know only as strings.

Geometry: `v x y z` (a fourth coordinate or vertex colours are ignored); `f` with `i`, `i/t`,
`i//n` or `i/t/n` references, negative ones counting back from the latest vertex; a polygon
becomes a fan of triangles (right for convex polygons). `o`, `g` and `usemtl` each start a new
shape, named after the latest `o` or `g` (the file's stem before any). `vn` normals referenced by
faces (`i//n`, `i/t/n`) become the shape's corner normals (smooth shading); a shape none of whose
faces names a normal shades flat, and a face without them in a shape with some takes its flat
normal at its corners. Texture coordinates, smoothing groups, lines, points and free-form
geometry are ignored. Closed shapes are wound outwards (orientation.py), which Glass needs.

Materials come from `mtllib` files beside the OBJ. The first rule that applies:

| MTL statements                                           | wgputrace material                              |
|----------------------------------------------------------|-------------------------------------------------|
| `Ke` with a component > 0                                | Emitter: color = Ke / max(Ke), emittance = max(Ke), so radiance = Ke |
| `d` < 1, `Tr` > 0, or `illum` 4, 6, 7 or 9 (transparent) | Glass: color = `Tf` (default 1), ior = `Ni` (default 1.5) |
| `Pm` >= 0.5, or no `Pm` and `Ks` > 0 with `Kd` = 0       | Glossy: color = `Ks` if > 0, else `Kd`; roughness = `Pr` as the GGX alpha, else sqrt(2 / (`Ns` + 2)) (Walter et al. 2007's Phong-to-microfacet rule), else 0.1 |
| anything else                                            | Diffuse: color = `Kd` (default 0.8)             |

`Ka`, texture maps and the other `illum` models have no counterpart and are ignored. A `usemtl`
naming no material, or a missing `mtllib` file, is a SceneLoadWarning and a grey Diffuse. The
materials check their values: a negative or NaN value, `Kd` above 1 or `Ni 0` is a SceneLoadError
at the line that set it.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scene import Diffuse, Emitter, Glass, Glossy, Material, MaterialError, SceneError, Shape
from .errors import SceneLoadError, SceneLoadWarning
from .orientation import wind_outwards

DEFAULT_DIFFUSE = 0.8
DEFAULT_IOR = 1.5
DEFAULT_ROUGHNESS = 0.1
# We have no blend of metal and dielectric: a shape is Glossy from this metallic factor up.
METALLIC_THRESHOLD = 0.5
TRANSPARENT_ILLUM_MODELS = (4, 6, 7, 9)
NO_NORMAL = -1
_COLOR_KEYS = ("kd", "ks", "ke", "tf")
_NUMBER_KEYS = ("ns", "ni", "d", "tr", "pr", "pm", "illum")


@dataclass
class _MtlEntry:
    name: str
    line: int
    values: dict[str, tuple[tuple[float, ...], int]] = field(default_factory=dict)  # key -> (numbers, line)

    def get(self, key: str) -> tuple[float, ...] | None:
        return self.values[key][0] if key in self.values else None


def read_obj(path: Path) -> list[Shape]:
    """The shapes of an OBJ file, in file order, with their MTL materials."""
    library: dict[str, Material] = {}
    default = Diffuse("default", color=(DEFAULT_DIFFUSE,) * 3)
    vertices: list[tuple[float, float, float]] = []
    normals: list[tuple[float, float, float]] = []
    runs: list[tuple[str, Material, list[int], list[int]]] = []
    # normal_refs: a normal index (0-based) per corner of `faces`, NO_NORMAL where the face names none
    name, material, faces, normal_refs = path.stem, default, [], []

    def close_run() -> None:
        if faces:
            runs.append((name, material, faces, normal_refs))

    lines = _text_lines(path)
    for number, line in enumerate(lines, start=1):
        tokens = (line.split("#", 1)[0] if "#" in line else line).split()
        if not tokens:
            continue
        key = tokens[0]
        if key == "v":
            vertices.append(_vertex(path, number, tokens))
        elif key == "f":
            # the common case first, "f a b c" with 1-based indices in range; anything else
            # (references with slashes, negative indices, polygons, errors) takes the full path
            count = len(vertices)
            try:
                a, b, c = int(tokens[1]), int(tokens[2]), int(tokens[3])
                plain = len(tokens) == 4 and 0 < a <= count and 0 < b <= count and 0 < c <= count
            except (ValueError, IndexError):
                plain = False
            if plain:
                faces.extend((a - 1, b - 1, c - 1))
                normal_refs.extend((NO_NORMAL,) * 3)
            else:
                fan, fan_normals = _face(path, number, tokens, count, len(normals))
                faces.extend(fan)
                normal_refs.extend(fan_normals)
        elif key == "vn":
            normal = _vertex(path, number, tokens, "a normal")
            if normal == (0.0, 0.0, 0.0):
                raise SceneLoadError(path, "a normal must have a direction, got vn 0 0 0", number)
            normals.append(normal)
        elif key in ("o", "g"):
            close_run()
            name, faces, normal_refs = " ".join(tokens[1:]) or path.stem, [], []
        elif key == "usemtl":
            close_run()
            faces, normal_refs = [], []
            wanted = " ".join(tokens[1:])
            material = library.get(wanted, default)
            if wanted not in library:
                warnings.warn(
                    f"{path}:{number}: usemtl {wanted!r} names no material of the mtllib files read so far; "
                    f"using a grey Diffuse",
                    SceneLoadWarning,
                    stacklevel=3,
                )
        elif key == "mtllib":
            for file_name in tokens[1:]:
                library.update(_read_mtl(path, number, path.parent / file_name))
    close_run()

    corners = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    with np.errstate(over="ignore"):
        corners = corners.astype(np.float32)
    bad = np.flatnonzero(~np.isfinite(corners).all(axis=1))
    if bad.size:  # rare: find the line again rather than keep one per vertex
        vertex_lines = [n for n, line in enumerate(lines, start=1) if line.split()[:1] == ["v"]]
        raise SceneLoadError(
            path,
            f"vertex {bad[0] + 1} {corners[bad[0]].tolist()} is beyond float32's range (3.4e38)",
            vertex_lines[bad[0]],
        )
    return _shapes(path, corners, np.array(normals, dtype=np.float64).reshape(-1, 3), runs)


def _shapes(path: Path, corners: np.ndarray, normals: np.ndarray, runs) -> list[Shape]:
    shapes, seen = [], {}
    for name, material, faces, normal_refs in runs:
        seen[name] = seen.get(name, 0) + 1
        triangles = corners[np.asarray(faces, np.int64).reshape(-1, 3)]
        refs = np.asarray(normal_refs, np.int64).reshape(-1, 3)
        corner_normals = _corner_normals(triangles, normals, refs) if (refs != NO_NORMAL).any() else None
        before = triangles.copy()
        wind_outwards(triangles, path, f"shape {name!r}", stacklevel=4)
        if corner_normals is not None:  # a turned triangle's corners 1 and 2 swapped: its normals follow
            turned = (triangles != before).any(axis=(1, 2))
            corner_normals[turned] = corner_normals[turned][:, [0, 2, 1]]
        label = name if seen[name] == 1 else f"{name}#{seen[name]}"
        try:
            shapes.append(Shape(label, triangles, material, normals=corner_normals))
        except SceneError as error:
            raise SceneLoadError(path, str(error)) from None
    return shapes


def _corner_normals(triangles: np.ndarray, normals: np.ndarray, refs: np.ndarray) -> np.ndarray:
    """(n, 3, 3) corner normals: the referenced `vn`, or the face's own normal where a face names
    none (flat shading there); a degenerate face without normals gets +z, its shading unseen."""
    face = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]).astype(np.float64)
    length = np.linalg.norm(face, axis=1, keepdims=True)
    face = np.where(length > 0.0, face / np.where(length > 0.0, length, 1.0), [0.0, 0.0, 1.0])
    corner = np.repeat(face[:, None, :], 3, axis=1)
    named = refs != NO_NORMAL
    corner[named] = normals[refs[named]]
    return corner


def _text_lines(path: Path) -> list[str]:
    try:
        data = path.read_bytes()
    except OSError as error:
        raise SceneLoadError(path, f"cannot read the file: {error.strerror or error}") from None
    # Undecodable bytes become U+FFFD, so a garbled file fails on the statement that holds them.
    return data.decode("utf-8", errors="replace").splitlines()


def _numbers(path: Path, number: int, tokens: list[str], what: str) -> tuple[float, ...]:
    try:
        values = tuple(float(token) for token in tokens)
    except ValueError:
        raise SceneLoadError(path, f"{what} must be numbers, got {' '.join(tokens)!r}", number) from None
    if not all(math.isfinite(value) for value in values):
        raise SceneLoadError(path, f"{what} must be finite, got {' '.join(tokens)!r}", number)
    return values


def _vertex(path: Path, number: int, tokens: list[str], what: str = "a vertex") -> tuple[float, float, float]:
    if len(tokens) < 4:
        raise SceneLoadError(path, f"{what} needs 3 coordinates, got {' '.join(tokens)!r}", number)
    try:
        x, y, z = float(tokens[1]), float(tokens[2]), float(tokens[3])
    except ValueError:
        x = math.nan  # _numbers below names the token
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
        x, y, z = _numbers(path, number, tokens[1:4], "vertex coordinates")
    return x, y, z


def _face(path: Path, number: int, tokens: list[str], vertex_count: int, normal_count: int) -> tuple[list, list]:
    """Vertex indices and normal indices (NO_NORMAL where a reference has none), 0-based, of the
    face's fan triangles, flattened."""
    if len(tokens) < 4:
        raise SceneLoadError(path, f"a face needs at least 3 vertices, got {' '.join(tokens)!r}", number)
    indices, normal_indices = [], []
    for reference in tokens[1:]:
        parts = reference.split("/")
        try:
            index = int(parts[0])
        except ValueError:
            raise SceneLoadError(path, f"face vertex {reference!r} does not start with an index", number) from None
        indices.append(_resolved(path, number, index, vertex_count, "vertex", "vertices"))
        normal_text = parts[2] if len(parts) > 2 else ""
        if not normal_text:
            normal_indices.append(NO_NORMAL)
            continue
        try:
            normal = int(normal_text)
        except ValueError:
            raise SceneLoadError(
                path, f"face vertex {reference!r} has a normal reference that is no index", number
            ) from None
        normal_indices.append(_resolved(path, number, normal, normal_count, "normal", "normals (vn)"))
    fan, fan_normals = [], []
    for k in range(1, len(indices) - 1):
        fan += (indices[0], indices[k], indices[k + 1])
        fan_normals += (normal_indices[0], normal_indices[k], normal_indices[k + 1])
    return fan, fan_normals


def _resolved(path: Path, number: int, index: int, count: int, what: str, plural: str) -> int:
    """A 1-based or negative (counting back) OBJ index made 0-based, or SceneLoadError."""
    resolved = index - 1 if index > 0 else count + index
    if index == 0 or not 0 <= resolved < count:
        raise SceneLoadError(
            path,
            f"face {what} index {index} is out of range: {count} {plural} are defined before this line "
            "(indices count from 1, negative ones back from the latest)",
            number,
        )
    return resolved


def _read_mtl(obj_path: Path, obj_line: int, path: Path) -> dict[str, Material]:
    if not path.is_file():
        warnings.warn(
            f"{obj_path}:{obj_line}: mtllib file {path} not found; its materials become a grey Diffuse",
            SceneLoadWarning,
            stacklevel=4,
        )
        return {}
    entries: list[_MtlEntry] = []
    for number, line in enumerate(_text_lines(path), start=1):
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            entries.append(_MtlEntry(" ".join(tokens[1:]), number))
        elif key in _COLOR_KEYS + _NUMBER_KEYS:
            if not entries:
                raise SceneLoadError(path, f"{tokens[0]} before any newmtl", number)
            values = _numbers(path, number, tokens[1:], tokens[0])
            wanted = (1, 3) if key in _COLOR_KEYS else (1,)
            if len(values) not in wanted:
                raise SceneLoadError(
                    path, f"{tokens[0]} takes {' or '.join(map(str, wanted))} numbers, got {len(values)}", number
                )
            entries[-1].values[key] = (values * 3 if len(values) == 1 and key in _COLOR_KEYS else values, number)
    return {entry.name: _material(path, entry) for entry in entries}


def _material(path: Path, entry: _MtlEntry) -> Material:
    """The wgputrace material for one MTL entry, by the table in this module's docstring."""
    kind, parameters, sources = _mapping(path, entry)
    try:
        return kind(entry.name, **parameters)
    except MaterialError as error:
        source = sources.get(error.parameter, "newmtl")
        line = entry.values[source][1] if source in entry.values else entry.line
        raise SceneLoadError(path, f"{error} (from {source})", line) from None


def _mapping(path: Path, entry: _MtlEntry) -> tuple[type[Material], dict, dict[str, str]]:
    """(material class, its parameters, the MTL key each parameter came from)."""
    kd, ks, ke, tf = (entry.get(key) for key in _COLOR_KEYS)
    ns, ni, dissolve, tr, pr, pm, illum = (
        None if entry.get(key) is None else entry.get(key)[0] for key in _NUMBER_KEYS
    )
    if ke is not None and max(ke) > 0:
        brightest = max(ke)
        color = tuple(c / brightest for c in ke)
        return Emitter, {"color": color, "emittance": brightest}, {"color": "ke", "emittance": "ke"}
    if (dissolve is not None and dissolve < 1) or (tr is not None and tr > 0) or illum in TRANSPARENT_ILLUM_MODELS:
        parameters = {"color": tf or (1.0, 1.0, 1.0), "ior": DEFAULT_IOR if ni is None else ni}
        return Glass, parameters, {"color": "tf", "ior": "ni"}
    specular = ks is not None and max(ks) > 0
    if (pm is not None and pm >= METALLIC_THRESHOLD) or (pm is None and specular and kd is not None and max(kd) == 0):
        sources = {"color": "ks" if specular else "kd", "roughness": "pr" if pr is not None else "ns"}
        if pr is not None:
            roughness = pr
        elif ns is not None:
            if ns < 0:
                raise SceneLoadError(path, f"Ns (a specular exponent) must be >= 0, got {ns}", entry.values["ns"][1])
            roughness = math.sqrt(2.0 / (ns + 2.0))
        else:
            roughness = DEFAULT_ROUGHNESS
        color = ks if specular else (kd or (DEFAULT_DIFFUSE,) * 3)
        return Glossy, {"color": color, "roughness": roughness}, sources
    return Diffuse, {"color": kd or (DEFAULT_DIFFUSE,) * 3}, {"color": "kd"}
