"""A scene: shapes (triangles sharing a material), the materials they index, a camera, and the
lights that are not emissive triangles: an `Environment` and point, spot, directional and sun
lights (`add_light`).

Editing (Mitsuba's traverse/params.update, with plain attributes): add and remove shapes and lights,
assign a shape's `transform`, `vertices` or `material`, a material's or a light's parameters, the
scene's `camera` or `environment`, or the environment's parameters. Each assignment is checked
where it happens and bumps a version (an environment's new texels its `generation`);
`Renderer.render` (or `Renderer.update`) compares them with what it uploaded and uploads only what
changed.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .cameras import Camera, Sensor, camera_classes
from .errors import SceneError
from .instances import Instance
from .lights import Light
from .lights.environment import Environment
from .materials import Material
from .shapes import Shape


class DegenerateTrianglesWarning(UserWarning):
    """Zero-area triangles were dropped: they have no normal and must never be hit."""


def zero_area(vertices: np.ndarray) -> np.ndarray:
    """True where a triangle's corners coincide or lie on one line.

    The cross product is taken in float64 from the float32 corners, where it is exact for
    corners of similar magnitude, so exactly collinear corners give exactly zero. (On the GPU, f32
    rounding of a collinear triangle's edge functions can leave them all of one sign: a "hit" with
    a NaN normal. Dropping such triangles here keeps that test out of the intersection loop.)
    """
    v = vertices.astype(np.float64)
    return ~np.any(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]) != 0.0, axis=1)


@dataclass
class TriangleArrays:
    """The scene flattened for the GPU: each triangle points at its material, never copies it."""

    vertices: np.ndarray  # (n, 3, 3) float32, world coordinates
    material_index: np.ndarray  # (n,) uint32 into `materials`
    shape_index: np.ndarray  # (n,) uint32 into the scene's shapes
    local_index: np.ndarray  # (n,) uint32: the triangle's index within its shape
    materials: list[Material]


@dataclass
class Scene:
    """Shapes seen by a camera, lit by their emitting materials, an environment and lights.

    Args:
        shapes: the Shapes; `shape(name)` finds one by its name.
        camera: where the picture is taken from.
        environment: the light arriving from infinitely far away (`Environment`); None: none.
        instances: meshes placed by transforms (`Instance`, `add_instance`), each mesh's triangles
            stored once on the GPU however many instances place it.
        cameras: the cameras the scene's file brings, (name, camera) in the file's order, which
            `load_scene(..., camera=NAME_OR_INDEX)` chooses from and the viewer's C key steps
            through; `camera` need not be one of them.

    Assigning `shapes`, `camera` or `environment` checks the value: a SceneError (a ValueError)
    names what is wrong and leaves the scene as it was.
    """

    shapes: list[Shape] = field(default_factory=list)
    camera: Sensor = field(default_factory=Camera)
    # the light arriving from infinitely far in every direction (`Environment`); None: black
    environment: Environment | None = None
    cameras: list[tuple[str, Sensor]] = field(default_factory=list)
    instances: list[Instance] = field(default_factory=list)
    _lights: list[Light] = field(default_factory=list, init=False, repr=False)

    def __setattr__(self, key: str, value) -> None:
        if key == "camera" and not isinstance(value, Sensor):
            kinds = ", ".join(cls.__name__ for cls in camera_classes())
            raise SceneError(
                f"scene camera must be a Camera or another camera kind ({kinds}), got {type(value).__name__}"
            )
        if key == "shapes":
            value = list(value)
            _check_shapes(value)
        if key == "environment":
            _check_environment(value)
        if key == "instances":
            value = list(value)
            _check_instances(value)
        object.__setattr__(self, key, value)

    @property
    def lights(self) -> tuple[Light, ...]:
        """The lights that are not emissive triangles nor the environment, in the order added."""
        return tuple(self._lights)

    def has_light(self) -> bool:
        """Whether anything sends light: a light, an environment, or a material that emits."""
        return bool(self._lights) or self.environment is not None or any(m.emits() for m in self.materials)

    def add_light(self, *lights: Light) -> Scene:
        """Add `lights` (PointLight, SpotLight, DirectionalLight, Sun, ...); returns the scene.
        SceneError for what is not a light or is in the scene already."""
        for light in lights:
            if not isinstance(light, Light):
                raise SceneError(f"add_light takes lights (wgputrace.PointLight, ...), got {type(light).__name__}")
            if any(light is other for other in self._lights):
                raise SceneError(f"{light.label} is in the scene already")
        self._lights.extend(lights)
        return self

    def remove_light(self, *lights: Light) -> Scene:
        """Remove `lights`; returns the scene. SceneError for one that is not in the scene."""
        for light in lights:
            if not any(light is other for other in self._lights):
                raise SceneError(f"cannot remove {light.label}: it is not in the scene")
            self._lights = [other for other in self._lights if other is not light]
        return self

    def add(self, *shapes: Shape) -> Scene:
        """Add `shapes`; returns the scene. SceneError for what is not a Shape."""
        _check_shapes(shapes, first=len(self.shapes))
        self.shapes.extend(shapes)
        return self

    def remove(self, *shapes: Shape | str) -> Scene:
        """Remove `shapes`, given as objects or by (unique) name; returns the scene. SceneError for
        one that is not in the scene."""
        for item in shapes:
            shape = self.shape(item) if isinstance(item, str) else item
            if not any(s is shape for s in self.shapes):
                raise SceneError(f"cannot remove {shape!r}: it is not in the scene")
            self.shapes = [s for s in self.shapes if s is not shape]
        return self

    def add_instance(self, mesh: Shape, transform, name: str | None = None) -> Instance:
        """Place `mesh` (a Shape, not itself in the scene unless added) by `transform` (4x4 affine,
        invertible, not mirroring); returns the new Instance, called `name` (default: the mesh's
        name and the instance's number). SceneError for a bad transform, naming the instance."""
        instance = Instance(f"{mesh.name}[{len(self.instances)}]" if name is None else name, mesh, transform)
        self.instances.append(instance)
        return instance

    def remove_instance(self, instance: Instance) -> Scene:
        """Remove `instance`; returns the scene. SceneError for one that is not in the scene."""
        if not any(other is instance for other in self.instances):
            raise SceneError(f"cannot remove {instance!r}: it is not in the scene")
        self.instances = [other for other in self.instances if other is not instance]
        return self

    def flattened(self) -> Scene:
        """This scene with every instance baked into a Shape of its own world triangles (what a
        renderer without instancing, or Mitsuba, draws); shapes, lights and cameras shared."""
        scene = Scene(
            [*self.shapes, *(instance.flattened() for instance in self.instances)],
            self.camera,
            self.environment,
            list(self.cameras),
        )
        scene.add_light(*self._lights)
        return scene

    def shape(self, name: str) -> Shape:
        """The one shape called `name`; SceneError where there is none or more than one."""
        found = [s for s in self.shapes if s.name == name]
        if len(found) != 1:
            names = ", ".join(repr(s.name) for s in self.shapes[:20])
            problem = "no shape" if not found else f"{len(found)} shapes"
            raise SceneError(f"{problem} called {name!r} in the scene; shapes: {names}")
        return found[0]

    @property
    def materials(self) -> list[Material]:
        """Distinct materials in order of first use: the shapes', then the instanced meshes'."""
        seen: dict[int, Material] = {}
        for shape in [*self.shapes, *(instance.mesh for instance in self.instances)]:
            seen.setdefault(id(shape.material), shape.material)
        return list(seen.values())

    @property
    def triangle_count(self) -> int:
        """Triangles of all shapes, zero-area ones included."""
        _check_shapes(self.shapes)
        return sum(shape.triangle_count for shape in self.shapes)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The (min, max) corners of the box around every triangle, in world coordinates (the
        instances' included)."""
        corners = [self.arrays().vertices.reshape(-1, 3)] if self.shapes else []
        corners += [instance_corners(instance) for instance in self.instances]
        if not corners:
            raise SceneError("the scene has no triangles: add at least one shape")
        vertices = np.concatenate(corners)
        return vertices.min(axis=0), vertices.max(axis=0)

    def arrays(self) -> TriangleArrays:
        """All triangles in world coordinates, zero-area ones dropped with a warning."""
        _check_shapes(self.shapes)
        if self.triangle_count == 0:
            raise SceneError("the scene has no triangles: add at least one shape")
        materials = self.materials
        slot = {id(material): index for index, material in enumerate(materials)}
        counts = [shape.triangle_count for shape in self.shapes]
        vertices = np.concatenate([shape.world_vertices for shape in self.shapes])
        material_index = np.repeat(np.array([slot[id(s.material)] for s in self.shapes], np.uint32), counts)
        shape_index = np.repeat(np.arange(len(self.shapes), dtype=np.uint32), counts)
        local_index = (np.arange(len(vertices)) - np.repeat(np.cumsum(counts) - counts, counts)).astype(np.uint32)
        degenerate = zero_area(vertices)
        if degenerate.any():
            first = int(np.flatnonzero(degenerate)[0])
            warnings.warn(
                f"dropped {int(degenerate.sum())} zero-area triangles; the first is triangle {local_index[first]} of "
                f"shape {self.shapes[shape_index[first]].name!r}",
                DegenerateTrianglesWarning,
                stacklevel=2,
            )
            keep = ~degenerate
            vertices, material_index = vertices[keep], material_index[keep]
            shape_index, local_index = shape_index[keep], local_index[keep]
            if len(vertices) == 0:
                raise SceneError("the scene has no triangles left after dropping zero-area ones")
        return TriangleArrays(vertices, material_index, shape_index, local_index, materials)


def instance_corners(instance: Instance) -> np.ndarray:
    """The 8 corners (float64) of the box around `instance`'s mesh, placed in the world."""
    vertices = instance.mesh.world_vertices.reshape(-1, 3)
    low, high = vertices.min(axis=0).astype(np.float64), vertices.max(axis=0).astype(np.float64)
    box = np.array([[(high if (k >> axis) & 1 else low)[axis] for axis in range(3)] for k in range(8)])
    return box @ instance.transform[:3, :3].T + instance.transform[:3, 3]


def _check_instances(instances) -> None:
    for index, instance in enumerate(instances):
        if not isinstance(instance, Instance):
            raise SceneError(f"scene instances[{index}] is a {type(instance).__name__}, not an Instance")


def _check_environment(environment) -> None:
    if environment is not None and not isinstance(environment, Environment):
        raise SceneError(f"scene environment must be an Environment or None, got {type(environment).__name__}")


def _check_shapes(shapes, first: int = 0) -> None:
    for index, shape in enumerate(shapes, start=first):
        if not isinstance(shape, Shape):
            raise SceneError(f"scene shapes[{index}] is a {type(shape).__name__}, not a Shape")
