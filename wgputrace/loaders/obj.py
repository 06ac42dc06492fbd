"""Wavefront OBJ with MTL materials, read line by line so that every error names its file and line.

Not trimesh's OBJ reader: it renamed and reordered the Cornell box file's objects, skips lines it
cannot parse without saying which, and keeps MTL keys it does not know only as strings. `o`, `g`
and `usemtl` each start a shape; a polygon becomes a fan (right for convex ones); `vn` and `vt`
referenced by faces become corner normals and, where the material has a map, corner uvs; vertex
colours (`v x y z r g b`, sRGB-encoded in [0, 1] as Blender writes and reads them and MeshLab
writes bytes / 255) become linear corner colours, white at a file's vertices without; closed
shapes are wound outwards (`wind_outwards`), which Glass needs. Smoothing groups, lines, points
and free-form geometry are ignored. Materials come from `mtllib` files beside the OBJ (`_mapping`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scene import Diffuse, Emitter, Glass, Glossy, Material, MaterialError, Principled, SceneError, Shape
from ..scene.texture import srgb_to_linear
from .errors import SceneLoadError, SceneLoadWarning
from .mtl_maps import MAP_KEYS, PRINCIPLED_MAPS, MapImages, TextureMap, parse_map
from .orientation import wind_outwards

DEFAULT_DIFFUSE = 0.8
DEFAULT_IOR = 1.5
DEFAULT_ROUGHNESS = 0.1
# We have no blend of metal and dielectric: a shape is Glossy from this metallic factor up.
METALLIC_THRESHOLD = 0.5
TRANSPARENT_ILLUM_MODELS = (4, 6, 7, 9)
NO_REF = -1
_COLOR_KEYS = ("kd", "ks", "ke", "tf")
_NUMBER_KEYS = ("ns", "ni", "d", "tr", "pr", "pm", "illum")


@dataclass
class _MtlEntry:
    name: str
    line: int
    values: dict[str, tuple[tuple[float, ...], int]] = field(default_factory=dict)  # key -> (numbers, line)
    maps: dict[str, TextureMap] = field(default_factory=dict)  # MAP_KEYS' names -> map

    def get(self, key: str) -> tuple[float, ...] | None:
        return self.values[key][0] if key in self.values else None


def read_obj(path: Path) -> list[Shape]:
    """The shapes of an OBJ file, in file order, with their MTL materials."""
    library: dict[str, Material] = {}
    default = Diffuse("default", color=(DEFAULT_DIFFUSE,) * 3)
    vertices: list[tuple[float, float, float]] = []
    normals: list[tuple[float, float, float]] = []
    texcoords: list[tuple[float, float]] = []
    # the sRGB colour of each `v x y z r g b` line, by 0-based vertex index
    vertex_colors: dict[int, tuple[float, float, float]] = {}
    runs: list[tuple[str, Material, list[int], list[int], list[int]]] = []
    # normal_refs, uv_refs: a normal and a texture coordinate index (0-based) per corner of
    # `faces`, NO_REF where the face names none
    name, material, faces, normal_refs, uv_refs = path.stem, default, [], [], []

    def close_run() -> None:
        if faces:
            runs.append((name, material, faces, normal_refs, uv_refs))

    lines = _text_lines(path)
    for number, line in enumerate(lines, start=1):
        tokens = (line.split("#", 1)[0] if "#" in line else line).split()
        if not tokens:
            continue
        key = tokens[0]
        if key == "v":
            if len(tokens) > 4:
                _vertex_extras(path, number, tokens, len(vertices), vertex_colors)
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
                normal_refs.extend((NO_REF,) * 3)
                uv_refs.extend((NO_REF,) * 3)
            else:
                fan, fan_normals, fan_uvs = _face(path, number, tokens, count, len(normals), len(texcoords))
                faces.extend(fan)
                normal_refs.extend(fan_normals)
                uv_refs.extend(fan_uvs)
        elif key == "vn":
            normal = _vertex(path, number, tokens, "a normal")
            if normal == (0.0, 0.0, 0.0):
                raise SceneLoadError(path, "a normal must have a direction, got vn 0 0 0", number)
            normals.append(normal)
        elif key == "vt":
            texcoords.append(_texcoord(path, number, tokens))
        elif key in ("o", "g"):
            close_run()
            name, faces, normal_refs, uv_refs = " ".join(tokens[1:]) or path.stem, [], [], []
        elif key == "usemtl":
            close_run()
            faces, normal_refs, uv_refs = [], [], []
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
    texcoord_table = np.array(texcoords, dtype=np.float32).reshape(-1, 2)
    color_table = _color_table(vertex_colors, len(corners))
    normal_table = np.array(normals, dtype=np.float64).reshape(-1, 3)
    return _shapes(path, corners, normal_table, texcoord_table, color_table, runs)


def _vertex_extras(path: Path, number: int, tokens: list[str], index: int, colors: dict) -> None:
    """Check what a `v` line has beyond x y z: a weight w (ignored) or a colour r g b in [0, 1],
    kept in `colors` at vertex `index`; SceneLoadError for any other count."""
    extras = len(tokens) - 4
    if extras == 1:
        return
    if extras != 3:
        raise SceneLoadError(
            path, f"a vertex is x y z, x y z w or x y z r g b, got {extras + 3} numbers: {' '.join(tokens)!r}", number
        )
    color = _numbers(path, number, tokens[4:], "vertex colours")
    if not all(0.0 <= value <= 1.0 for value in color):
        raise SceneLoadError(path, f"vertex colours must be in [0, 1], got {' '.join(tokens[4:])!r}", number)
    colors[index] = color


def _color_table(colors: dict[int, tuple[float, float, float]], vertex_count: int) -> np.ndarray | None:
    """(vertex_count, 4) linear RGBA float32 of the `v x y z r g b` colours (decoded from sRGB),
    white at vertices without; None where no vertex has a colour."""
    if not colors:
        return None
    table = np.ones((vertex_count, 4), np.float32)
    indices = np.fromiter(colors, np.int64, len(colors))
    table[indices, :3] = srgb_to_linear(np.array(list(colors.values()), np.float64))
    return table


def _shapes(
    path: Path, corners: np.ndarray, normals: np.ndarray, texcoords: np.ndarray, colors: np.ndarray | None, runs
) -> list[Shape]:
    shapes, seen = [], {}
    for name, material, faces, normal_refs, uv_refs in runs:
        seen[name] = seen.get(name, 0) + 1
        vertex_ids = np.asarray(faces, np.int64).reshape(-1, 3)
        triangles = corners[vertex_ids]
        refs = np.asarray(normal_refs, np.int64).reshape(-1, 3)
        corner = {}
        if colors is not None:
            corner["colors"] = colors[vertex_ids]
        if (refs != NO_REF).any():
            corner["normals"] = _corner_normals(triangles, normals, refs)
        uv_ids = np.asarray(uv_refs, np.int64).reshape(-1, 3)
        if material.textures() and (uv_ids != NO_REF).any():
            # a corner naming no vt reads the texture at (0, 0)
            corner["uvs"] = np.where((uv_ids != NO_REF)[..., None], texcoords[uv_ids], np.float32(0.0))
        before = triangles.copy()
        wind_outwards(triangles, path, f"shape {name!r}", stacklevel=4)
        turned = (triangles != before).any(axis=(1, 2))
        for values in corner.values():  # a turned triangle's corners 1 and 2 swapped: its attributes follow
            values[turned] = values[turned][:, [0, 2, 1]]
        label = name if seen[name] == 1 else f"{name}#{seen[name]}"
        try:
            shapes.append(Shape(label, triangles, material, **corner))
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
    named = refs != NO_REF
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


def _texcoord(path: Path, number: int, tokens: list[str]) -> tuple[float, float]:
    """`vt u [v [w]]` in glTF's convention (v down from the image's top): (u, 1 - v)."""
    if len(tokens) < 2:
        raise SceneLoadError(path, "a texture coordinate needs u (and v), got 'vt'", number)
    u, v = (_numbers(path, number, tokens[1:3], "texture coordinates") + (0.0,))[:2]
    return u, 1.0 - v


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


def _face(
    path: Path, number: int, tokens: list[str], vertex_count: int, normal_count: int, texcoord_count: int
) -> tuple[list, list, list]:
    """Vertex, normal and texture coordinate indices (NO_REF where a reference has none), 0-based,
    of the face's fan triangles, flattened."""
    if len(tokens) < 4:
        raise SceneLoadError(path, f"a face needs at least 3 vertices, got {' '.join(tokens)!r}", number)
    indices, normal_indices, uv_indices = [], [], []
    for reference in tokens[1:]:
        parts = reference.split("/")
        try:
            index = int(parts[0])
        except ValueError:
            raise SceneLoadError(path, f"face vertex {reference!r} does not start with an index", number) from None
        indices.append(_resolved(path, number, index, vertex_count, "vertex", "vertices"))
        uv_indices.append(_reference(path, number, reference, parts, 1, texcoord_count, "texture coordinate", "vt"))
        normal_indices.append(_reference(path, number, reference, parts, 2, normal_count, "normal", "vn"))
    fan, fan_normals, fan_uvs = [], [], []
    for k in range(1, len(indices) - 1):
        corners = (0, k, k + 1)
        fan += [indices[c] for c in corners]
        fan_normals += [normal_indices[c] for c in corners]
        fan_uvs += [uv_indices[c] for c in corners]
    return fan, fan_normals, fan_uvs


def _reference(
    path: Path, number: int, reference: str, parts: list[str], slot: int, count: int, what: str, key: str
) -> int:
    """The 0-based index in slot `slot` of a face vertex's `i/t/n` reference, or NO_REF if empty."""
    text = parts[slot] if len(parts) > slot else ""
    if not text:
        return NO_REF
    try:
        index = int(text)
    except ValueError:
        raise SceneLoadError(
            path, f"face vertex {reference!r} has a {what} reference that is no index", number
        ) from None
    return _resolved(path, number, index, count, what, f"{what}s ({key})")


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
        elif key in MAP_KEYS:
            if not entries:
                raise SceneLoadError(path, f"{tokens[0]} before any newmtl", number)
            entries[-1].maps[MAP_KEYS[key]] = parse_map(path, number, tokens)
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
    images = MapImages(path)
    return {entry.name: _material(path, entry, images) for entry in entries}


def _material(path: Path, entry: _MtlEntry, images: MapImages) -> Material:
    """The wgputrace material for one MTL entry, as `_mapping` maps it, with its maps' textures; a
    value the material refuses (negative, NaN, `Kd` above 1, `Ni 0`) fails at the line that set it.
    """
    kind, parameters, sources = _mapping(path, entry)
    if "map_ks" in entry.maps:
        warnings.warn(
            f"{path}:{entry.maps['map_ks'].line}: map_Ks of {entry.name!r} ignored (no specular tint here)",
            SceneLoadWarning,
            stacklevel=5,
        )
    dropped = [entry.maps[key].statement for key in PRINCIPLED_MAPS if key in entry.maps]
    if kind is not Principled and dropped:
        warnings.warn(
            f"{path}:{entry.line}: {entry.name!r} is transparent (d < 1 or Tr > 0 without map_d), so Glass, "
            f"which takes no textures: {', '.join(dropped)} ignored",
            SceneLoadWarning,
            stacklevel=5,
        )
    try:
        if kind is Principled:
            parameters |= images.principled_textures(entry.maps)
        return kind(entry.name, **parameters)
    except MaterialError as error:
        source = sources.get(error.parameter, "newmtl")
        line = entry.values[source][1] if source in entry.values else entry.line
        raise SceneLoadError(path, f"{error} (from {source})", line) from None
    except SceneError as error:
        raise SceneLoadError(path, str(error), entry.line) from None


def _mapping(path: Path, entry: _MtlEntry) -> tuple[type[Material], dict, dict[str, str]]:
    """(material class, its parameters, the MTL key each parameter came from).

    A material with any map (`PRINCIPLED_MAPS`; options: `parse_map`) becomes a Principled, unless it
    is transparent by `d` < 1 or `Tr` > 0 without a `map_d` (then Glass, its maps ignored):

    | MTL statement                          | Principled parameter                                           |
    |----------------------------------------|----------------------------------------------------------------|
    | `Kd` (default 0.8), `map_Kd` (sRGB)     | base_color = Kd, or 1 where map_Kd is given (exporters write their default Kd beside it); base_color_texture = map_Kd |
    | `Pm` (default 0), `map_Pm`              | metallic; the map's first channel as the metallic-roughness texture's B |
    | `Pr`, else from `Ns` (sqrt of Walter et al.'s alpha), else 0.5; `map_Pr` | roughness; the map's first channel as G |
    | `Ni` (default 1.5)                      | eta                                                            |
    | `Ke` (default 1 under map_Ke), `map_Ke` (sRGB) | emission, emission_texture                              |
    | `d` (default 1), `map_d`                | alpha = d; the map's first channel as the base colour texture's alpha, alpha_mode BLEND (dissolve is a blend) |
    | `bump`, `map_Bump`, `norm` (`-bm` scale) | normal_texture (read as a tangent-space normal map, as exporters of PBR materials write it; not a height map), normal_scale |

    `map_Ks` (no specular tint here) is ignored with a warning; `map_Ka`, `map_Ns`, `disp`, `decal`,
    `refl`, `Ka` and other `illum` models are ignored. Any other material (the first rule that applies):

    | MTL statements                                           | wgputrace material                              |
    |----------------------------------------------------------|-------------------------------------------------|
    | `Ke` with a component > 0                                | Emitter: color = Ke / max(Ke), emittance = max(Ke), so radiance = Ke |
    | `d` < 1, `Tr` > 0, or `illum` 4, 6, 7 or 9 (transparent) | Glass: color = `Tf` (default 1), ior = `Ni` (default 1.5) |
    | `Pm` >= 0.5, or no `Pm` and `Ks` > 0 with `Kd` = 0       | Glossy: color = `Ks` if > 0, else `Kd`; roughness = `Pr` as the GGX alpha, else sqrt(2 / (`Ns` + 2)) (Walter et al. 2007's Phong-to-microfacet rule), else 0.1 |
    | anything else                                            | Diffuse: color = `Kd` (default 0.8)             |
    """
    kd, ks, ke, tf = (entry.get(key) for key in _COLOR_KEYS)
    ns, ni, dissolve, tr, pr, pm, illum = (
        None if entry.get(key) is None else entry.get(key)[0] for key in _NUMBER_KEYS
    )
    transparent = (dissolve is not None and dissolve < 1) or (tr is not None and tr > 0)
    if any(key in entry.maps for key in PRINCIPLED_MAPS) and not (transparent and "map_d" not in entry.maps):
        parameters = {
            "base_color": (1.0, 1.0, 1.0) if "map_kd" in entry.maps else kd or (DEFAULT_DIFFUSE,) * 3,
            "metallic": pm or 0.0,
            "roughness": pr if pr is not None else _phong_roughness(path, entry, ns) ** 0.5 if ns is not None else 0.5,
            "eta": DEFAULT_IOR if ni is None else ni,
        }
        if "map_ke" in entry.maps or (ke is not None and max(ke) > 0):
            parameters["emission"] = ke or (1.0, 1.0, 1.0)
        if "map_d" in entry.maps:
            parameters["alpha_mode"] = "BLEND"
            if dissolve is not None:
                parameters["alpha"] = dissolve
        sources = {"base_color": "kd", "metallic": "pm", "roughness": "pr" if pr is not None else "ns"}
        return Principled, parameters, sources | {"eta": "ni", "emission": "ke", "alpha": "d"}
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
            roughness = _phong_roughness(path, entry, ns)
        else:
            roughness = DEFAULT_ROUGHNESS
        color = ks if specular else (kd or (DEFAULT_DIFFUSE,) * 3)
        return Glossy, {"color": color, "roughness": roughness}, sources
    return Diffuse, {"color": kd or (DEFAULT_DIFFUSE,) * 3}, {"color": "kd"}


def _phong_roughness(path: Path, entry: _MtlEntry, ns: float) -> float:
    """The GGX alpha of Phong exponent `ns` (Walter et al. 2007: sqrt(2 / (Ns + 2)))."""
    if ns < 0:
        raise SceneLoadError(path, f"Ns (a specular exponent) must be >= 0, got {ns}", entry.values["ns"][1])
    return math.sqrt(2.0 / (ns + 2.0))
