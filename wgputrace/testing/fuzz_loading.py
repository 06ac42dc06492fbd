"""What a fuzzed scene file may end in: a Scene with finite shapes, lights and cameras, or a one-line
SceneLoadError naming the file (and, for a glTF whose JSON alone was mutated, the JSON path), within
`fuzzing.time_limit`. Anything else (another exception, a hang, a NaN) fails the test."""

from __future__ import annotations

import re
import warnings

import numpy as np

from .. import Scene, SceneLoadError, load_scene
from .fuzzing import time_limit

# A glTF error's problem starts with the JSON path at fault: a top-level key and the path below it.
GLTF_JSON_PATH = re.compile(
    r"(glTF|asset|scenes?|nodes|meshes|accessors|bufferViews|buffers|materials|textures|images|samplers|"
    r"cameras|skins|animations|extensions|extensionsUsed|extensionsRequired)\b[\[.:\s-]"
)
# The one glTF problem about the whole file rather than a field
WHOLE_FILE_PROBLEMS = ("holds no triangles",)


def outcome(path, names_json_path: bool = False) -> Scene | SceneLoadError:
    """Load `path` under the time limit: a Scene or the documented error, anything else fails.
    `names_json_path`: an error must name the glTF JSON path at fault."""
    with time_limit(), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # repairs and skips are warnings; here only errors matter
        try:
            scene = load_scene(path)
        except SceneLoadError as error:
            message = str(error)
            assert message.startswith(str(error.path)) and "\n" not in message, message
            if names_json_path and not error.problem.startswith(WHOLE_FILE_PROBLEMS):
                assert GLTF_JSON_PATH.match(error.problem), message
            return error
    assert isinstance(scene, Scene) and scene.triangle_count > 0
    for shape in scene.shapes:
        assert np.all(np.isfinite(shape.world_vertices))
        assert shape.uvs is None or np.all(np.isfinite(shape.uvs))
        assert shape.colors is None or np.all((shape.colors >= 0) & (shape.colors <= 1))
    for item in [*scene.lights, *(camera for _, camera in scene.cameras)]:
        values = [getattr(item, name) for name in item.parameter_names()]
        assert all(np.all(np.isfinite(value)) for value in values if value is not None), item
    return scene
