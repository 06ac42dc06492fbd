"""glTF cameras: every node that places a camera gives the scene one (name, camera) pair, the camera
at the node's world transform, looking along its -z with its +y up (`Scene.cameras`, in the order
the node tree is walked). The values the glTF specification restricts are checked; each failure is
a SceneLoadError naming the JSON path.

| glTF camera                             | wgputrace camera                                              |
|-----------------------------------------|---------------------------------------------------------------|
| `perspective`: yfov (radians, in (0, pi)) | Camera: vfov_degrees                                        |
| `orthographic`: ymag (half the height, not 0) | OrthographicCamera: view_height = 2 ymag x the node's y scale |
| checked, then ignored: aspectRatio (> 0; the image's own aspect sets the width), xmag (not 0), znear (> 0 perspective, >= 0 orthographic), zfar (> znear): nothing is clipped | |

A camera's name is its `name`, else its node's, else `cameras[i]`; one camera placed by two nodes
is two cameras. A camera no node places has no pose and is not listed. A camera of another type
warns and is left out.
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..scene import Camera, OrthographicCamera, Sensor
from .errors import SceneLoadWarning

if TYPE_CHECKING:
    from .gltf import _Reader

CAMERA_TYPES = ("perspective", "orthographic")


def node_camera(reader: _Reader, node: dict, world: np.ndarray, where: str) -> tuple[str, Sensor] | None:
    """The (name, camera) that node `node` (at JSON path `where`, world matrix `world`) places, or None."""
    index = node["camera"]
    entry = reader.item("cameras", index, f"{where}.camera")
    camera_where = f"cameras[{index}]"
    kind = reader.get(entry, "type", str, camera_where, "perspective")
    if kind not in CAMERA_TYPES:
        warnings.warn(
            f"{reader.path}: {camera_where} is of type {kind!r:.40}, neither perspective nor orthographic: left out",
            SceneLoadWarning,
            stacklevel=4,
        )
        return None
    projection = reader.get(entry, kind, dict, camera_where)
    size = _checked_projection(reader, projection, kind, f"{camera_where}.{kind}")
    name = next((n for n in (entry.get("name"), node.get("name")) if isinstance(n, str) and n), camera_where)
    linear = world[:3, :3]
    pose = (tuple(world[:3, 3]), tuple(linear @ [0.0, 0.0, -1.0]), tuple(linear @ [0.0, 1.0, 0.0]))
    try:
        if kind == "orthographic":
            return name, OrthographicCamera(*pose, view_height=2.0 * size * float(np.linalg.norm(linear[:, 1])))
        return name, Camera(*pose, math.degrees(size))
    except ValueError as error:  # a node whose scale flattens the camera's axes
        raise reader.fail(f"{camera_where} at {where}", str(error)) from None


def _checked_projection(reader: _Reader, projection: dict, kind: str, where: str) -> float:
    """The perspective's yfov or the orthographic's |ymag|, once every field glTF restricts is checked."""

    def number(key: str, test, rule: str, required: bool = False) -> float | None:
        value = reader.get(projection, key, float, where, None if required else math.nan)
        if key in projection and not (math.isfinite(value) and test(value)):
            raise reader.fail(f"{where}.{key}", f"must be {rule}, got {value!r:.20}")
        return value if key in projection else None

    if kind == "perspective":
        size = number("yfov", lambda v: 0.0 < v < math.pi, "in (0, pi) radians", required=True)
        number("aspectRatio", lambda v: v > 0.0, "> 0")
        near = number("znear", lambda v: v > 0.0, "> 0")
    else:
        number("xmag", lambda v: v != 0.0, "a number other than 0")
        size = abs(number("ymag", lambda v: v != 0.0, "a number other than 0", required=True))
        near = number("znear", lambda v: v >= 0.0, ">= 0")
    number("zfar", lambda v: near is None or v > near, "finite" if near is None else f"> znear ({near!r:.20})")
    return size
