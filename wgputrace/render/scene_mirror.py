"""The scene's GPU records kept on the host and brought up to date after edits (`SceneMirror.update`),
doing only the work each edit needs and reporting which rows changed, so only those are uploaded.

Rows are compared as bytes before they count as changed (`changed_rows`), so an edit that restores
a value uploads nothing and does not restart accumulation; and the records after an edit are those
a fresh mirror of the edited scene makes (up to exact ties of two hit distances), so the picture
after an edit is a fresh Renderer's. Arrays a scene does not use (vertex normals, texture records,
light sources, an environment map) are not kept.
"""

from __future__ import annotations

import numpy as np

from ..bvh import BVH, Refitter
from ..gpu.layout import LIGHT_SOURCE, LIGHTING, VERTEX_COLOR, VERTEX_NORMAL, VERTEX_TANGENT, VERTEX_UV
from ..kernels.light_dispatch import LightFeatures
from ..kernels.traversal import BVH_STACK_SIZE, traversal_stack_size
from ..kernels.variant import SceneFeatures
from ..scene import Scene, SceneError, Shape
from ..scene.materials.volume import is_absorbing
from ..scene.scene import zero_area
from ..scene.shapes import corner_colors, corner_normals, corner_uvs
from ..scene.tangents import corner_tangents
from .emission_footprints import footprint_means
from .environment_records import environment_state, environment_table_words, environment_texels
from .instance_records import InstanceRecords, joined
from .lights import LUMINANCE_WEIGHTS, LightTable, emitting, light_table
from .scene_records import (
    SceneRecords,
    build_acceleration,
    gpu_node_records,
    material_records,
    set_wide_bounds,
    triangle_records,
)
from .shared_vertices import shared_vertices, triangle_vertex_records, vertex_records
from .texture_atlas import light_density, material_texture_records, needs_material_record, pack_atlas, used_textures

# Rebuild the BVH when refits have made its SAH cost this many times the cost it had when built
# (`python -m bench.refit_threshold`: spheres wandering through the Cornell box). Render time grew
# about 1 + 1.38 (D - 1) on lavapipe, so at 1.2 a refit tree renders ~28% slower, while rebuilding
# that scene cost about a quarter of one sample per pixel at 64x64: past this value a rebuild pays
# for itself within the next sample.
REBUILD_DEGRADATION = 1.2

TRIANGLES, NODES, MATERIALS, LIGHTS = "triangles", "bvh nodes", "materials", "lights"
TEXTURE_ATLAS, TEXTURES, MATERIAL_TEXTURES = "texture atlas", "textures", "material textures"
# The shading attributes per vertex (`shared_vertices`) and each triangle's vertices, in BVH order.
VERTEX_INDICES = "triangle vertices"
VERTEX_NORMALS, VERTEX_UVS, VERTEX_TANGENTS, VERTEX_COLORS = (
    "vertex normals",
    "vertex uvs",
    "vertex tangents",
    "vertex colors",
)
# A vertex's attribute where its side of an instanced scene has none (`_instanced_vertices`): flat, white.
_MISSING_VERTEX = {
    VERTEX_NORMALS: np.zeros(3, np.float32),
    VERTEX_UVS: np.zeros(2, np.float32),
    VERTEX_TANGENTS: np.zeros(4, np.float32),
    VERTEX_COLORS: np.ones(4, np.float32),
}
VERTEX_ARRAYS = {
    VERTEX_NORMALS: VERTEX_NORMAL,
    VERTEX_UVS: VERTEX_UV,
    VERTEX_TANGENTS: VERTEX_TANGENT,
    VERTEX_COLORS: VERTEX_COLOR,
}
INSTANCES = "instances"
# the top level's changed rows inside `update` before `_assemble` makes them rows of NODES
_TOP_NODES = "top-level nodes"
TRIANGLE_LIGHT_DENSITIES = "triangle light densities"
# WebGPU's default max-texture-dimension-2d: the atlas side where no device says otherwise
DEFAULT_TEXTURE_SIDE = 8192
LIGHT_SOURCES, LIGHTING_PARAMETERS = "light sources", "lighting"
ENVIRONMENT_TEXELS, ENVIRONMENT_TABLES = "environment map", "environment tables"


def changed_rows(old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """Rows of `new` whose fields differ from `old` bit for bit (so -0.0 differs from 0.0, and a NaN
    from itself only if its bits do); rows beyond old's length all count. Fields, not whole rows:
    numpy leaves the padding between fields undefined when it copies records."""
    common = min(len(old), len(new))
    differs = np.zeros(common, bool)
    for name in new.dtype.names if common else ():  # every GPU field is made of 4-byte words
        a, b = old[name][:common].view(np.uint32), new[name][:common].view(np.uint32)
        differs |= (a != b).reshape(common, -1).any(axis=1)
    return np.concatenate([np.flatnonzero(differs), np.arange(common, len(new))])


class SceneMirror:
    """GPU records of `scene` (triangles in BVH order, nodes as the GPU traverses them, materials)
    and the state needed to update them incrementally."""

    def __init__(self, scene: Scene, acceleration: str, texture_side: int = DEFAULT_TEXTURE_SIDE) -> None:
        self.scene, self.acceleration_kind = scene, acceleration
        self.triangles = self.nodes = self.materials = None
        # the shading attributes by name (VERTEX_ARRAYS: their records) and TRIANGLE_VERTICES
        # records in BVH order (VERTEX_INDICES), only those the scene has (`_update_vertices`):
        # normals where a shape has them, uvs and tangents with textures (tangents one zero record
        # unless a material reads a normal map or is anisotropic), colours where a shape has them
        self.vertices: dict[str, np.ndarray] = {}
        # for a scene with textures (else None): the atlas's texels (float32 (H, W, 4), at most
        # texture_side per side), TEXTURE and MATERIAL_TEXTURES records
        self.texture_side = texture_side
        self.atlas_texels = self.texture_records = self.material_textures = None
        self._reads_tangents = False
        self._textures: list = []
        # float32 in BVH order: each triangle's light table weight per unit area from what it emits
        # through a texture record (`footprint_means`); one zero where none emits so
        self.triangle_light_densities = np.zeros(1, np.float32)
        self.lights: LightTable | None = None
        # the light sources' records (LIGHT_SOURCE), the lighting parameters (one LIGHTING record),
        # and an environment map's texels (float32 (H, W, 4)) and sampling tables (uint32 words)
        self.sources = LIGHT_SOURCE.zeros(0)
        self.lighting = LIGHTING.zeros(1)
        self.environment_texels: np.ndarray | None = None
        self.environment_tables: np.ndarray | None = None
        self.light_features = LightFeatures()
        self._environment = self._environment_state = self._environment_generation = None
        self.rebuilds = self.refits = 0
        # set while the BVH is out of step with the records (a refit that must become a rebuild,
        # which then did not finish: interrupted, out of memory): the next update rebuilds
        self._needs_rebuild = False
        # the two-level structure's records for a scene with instances (else None), and every array
        # as the GPU holds it: the world's with the instanced meshes' appended (`_assemble`)
        self.instancing: InstanceRecords | None = None
        self._assembled: dict[str, np.ndarray | None] = {}
        self._rebuild()

    @property
    def records(self) -> SceneRecords:
        return SceneRecords(
            self.triangles, self.nodes, self.materials, self.bvh, self.wide, self.lights.entries, dict(self.vertices)
        )

    @property
    def arrays(self) -> dict[str, np.ndarray | None]:
        """Every array of records by name (None: the scene has none of it now), as the GPU holds it."""
        return {**self._world_arrays, **self._assembled}

    @property
    def _world_arrays(self) -> dict[str, np.ndarray | None]:
        """The arrays of the scene's own shapes (all of them, in a scene without instances)."""
        return {
            TRIANGLES: self.triangles,
            NODES: self.nodes,
            MATERIALS: self.materials,
            LIGHTS: self.lights.entries,
            LIGHTING_PARAMETERS: self.lighting,
            LIGHT_SOURCES: self.sources,
            ENVIRONMENT_TEXELS: self.environment_texels,
            ENVIRONMENT_TABLES: self.environment_tables,
            **{name: self.vertices.get(name) for name in (VERTEX_INDICES, *VERTEX_ARRAYS)},
            TEXTURE_ATLAS: self.atlas_texels,
            TEXTURES: self.texture_records,
            MATERIAL_TEXTURES: self.material_textures,
            TRIANGLE_LIGHT_DENSITIES: self.triangle_light_densities,
            INSTANCES: None,  # the instances' records come with the other arrays `_assemble` makes
        }

    @property
    def features(self) -> SceneFeatures:
        """What the scene compiles into every kernel that traces it, as it is now."""
        return SceneFeatures(
            acceleration=self.acceleration_kind,
            stack_size=BVH_STACK_SIZE if self.wide is None else traversal_stack_size(self._stack_entries),
            material_kinds=self.material_kinds,
            lobes=tuple(set().union(*(material.lobes() for material in self.scene.materials))),
            lights=self.light_features,
            camera=self.scene.camera.kind,
            smooth=self.arrays[VERTEX_NORMALS] is not None,
            textured=self.textured,
            see_through=self.see_through,
            emissive_surfaces=self.emissive_surfaces,
            vertex_colors=self.arrays[VERTEX_COLORS] is not None,
            absorbing=any(is_absorbing(material) for material in self.scene.materials),
            instance_triangle_bits=0 if self.instancing is None else self.instancing.triangle_bits,
        )

    @property
    def _stack_entries(self) -> int:
        return self.wide.max_stack if self.instancing is None else self.instancing.stack_entries

    @property
    def textured(self) -> bool:
        """Whether a material reads a texture or lets rays through some of its surface (and the
        texture records exist)."""
        return self.texture_records is not None

    @property
    def see_through(self) -> bool:
        """Whether a material lets rays through some of its surface (alpha modes, single-sided), so
        that every ray's triangle test must ask its material."""
        return any(material.lets_rays_through() for material in self.scene.materials)

    @property
    def emissive_surfaces(self) -> bool:
        """Whether a material emits through its texture record (`Material.surface_emission`)."""
        return any(max(material.surface_emission()) > 0 for material in self.scene.materials)

    def _surface_light_densities(self) -> np.ndarray:
        """Each material's light table weight per unit area from its texture record (0: none)."""
        return np.array([light_density(material) for material in self.scene.materials], np.float64)

    @property
    def material_kinds(self) -> frozenset:
        return frozenset(material.kind for material in self._materials)

    def update(self) -> dict[str, np.ndarray]:
        """Bring the records up to date with the scene; return the changed rows of each array (only
        arrays with changes appear). Textures and lights: `_update_textures`, `_update_lights`.

        | edit                                        | work                                          | rows that change                     |
        |---------------------------------------------|-----------------------------------------------|--------------------------------------|
        | material parameter                          | that material's record                        | one material record                  |
        | shape transform (same zero-area triangles)  | its world triangles (and vertices), BVH refit | its triangles and vertices, nodes whose bounds moved |
        | shape material reassigned                   | material list and every triangle's index      | materials and triangles whose index moved |
        | shapes added/removed, vertices or normals replaced | arrays, BVH build                      | whatever differs (nearly all)        |

        A refit whose SAH cost exceeds the built tree's by REBUILD_DEGRADATION becomes a rebuild.
        """
        shapes = list(self.scene.shapes)
        same_shapes = len(shapes) == len(self._shapes) and all(
            a is b for a, b in zip(shapes, self._shapes, strict=False)
        )
        if (
            self._needs_rebuild
            or not same_shapes
            or any(
                not isinstance(s, Shape) or s.geometry_version != v[0]
                for s, v in zip(shapes, self._versions, strict=True)
            )
            or self._instance_state() != self._instances
        ):
            return self._rebuild()
        changes: dict[str, np.ndarray] = {}
        moved = [i for i, (s, v) in enumerate(zip(shapes, self._versions, strict=True)) if s.transform_version != v[1]]
        if moved:
            refit = self._refit(moved)
            if refit is None:
                self._needs_rebuild = True
                return self._rebuild()
            changes.update(refit)
        placed = self._instance_placements() != self._placements
        if self.instancing is not None and (moved or placed):
            top_nodes, records = self.instancing.top_nodes.copy(), self.instancing.records.copy()
            if not self.instancing.refit():
                self._needs_rebuild = True
                return self._rebuild()
            changes[_TOP_NODES] = changed_rows(top_nodes, self.instancing.top_nodes)
            changes[INSTANCES] = changed_rows(records, self.instancing.records)
        reassigned = any(s.material_version != v[2] for s, v in zip(shapes, self._versions, strict=True))
        if (reassigned or self.scene.materials != self._materials) and self.instancing is not None:
            return self._rebuild()  # the meshes' triangles index the material list too
        if reassigned or self.scene.materials != self._materials:
            changes = _union(changes, self._reassign_materials())
        else:
            changes = _union(changes, self._update_material_records())
        densities = self._surface_light_densities()
        emitter = emitting(self.materials) | (densities > 0)
        emission_edited = any(
            density > 0 and material.version != version
            for material, density, version in zip(
                self.scene.materials, densities, self._material_versions, strict=False
            )
        )
        if (
            not np.array_equal(densities, self._light_densities)
            or emission_edited
            or reassigned
            or emitter[self.triangles["material"][changes.get(TRIANGLES, [])]].any()
            or emitter[changes.get(MATERIALS, [])].any()
            or self._lights_edited()
            or ((TRIANGLES in changes or placed) and self._has_distant_lights())
        ):
            changes.update(self._update_lights())
        shading = (self.textured, self._reads_tangents)
        changes.update(self._update_textures())
        if (moved and self._moves_vertices(moved)) or shading != (self.textured, self._reads_tangents):
            changes.update(self._update_vertices())
        self._snapshot()
        return {name: rows for name, rows in self._assemble(changes).items() if rows.size}

    def _instance_state(self) -> list[tuple]:
        """What an instance edit other than a new transform changes (a rebuild): the instances, their
        meshes and the meshes' versions."""
        return [
            (id(i), id(i.mesh), i.mesh.geometry_version, i.mesh.transform_version, i.mesh.material_version)
            for i in self.scene.instances
        ]

    def _instance_placements(self) -> list[int]:
        return [instance.transform_version for instance in self.scene.instances]

    def _assemble(self, changes: dict[str, np.ndarray], rebuilt: bool = False) -> dict[str, np.ndarray]:
        """The arrays as the GPU holds them in a scene with instances (`InstanceRecords`: the top
        level's records first, the meshes' triangles and attributes after the world's) from the
        world's arrays, and `changes` (rows of the world's arrays, and _TOP_NODES) as rows of them:
        every row after a rebuild."""
        instancing = self.instancing
        if instancing is None:
            self._assembled = {}
            return changes
        world = self._world_arrays
        assembled = {
            TRIANGLES: joined([self.triangles, instancing.triangles]),
            NODES: instancing.nodes(self.nodes),
            INSTANCES: instancing.records,
            **self._instanced_vertices(instancing),
        }
        densities = world[TRIANGLE_LIGHT_DENSITIES]
        if len(densities) > 1:  # the meshes emit nothing (InstanceRecords refuses emitting meshes)
            assembled[TRIANGLE_LIGHT_DENSITIES] = np.concatenate(
                [densities, np.zeros(len(instancing.triangles), np.float32)]
            )
        before, self._assembled = self._assembled, assembled
        if rebuilt:
            return {name: np.arange(len(array)) for name, array in self.arrays.items() if array is not None}
        changes = dict(changes)
        for name, array in assembled.items():  # an attribute the meshes' side gained, or grew
            if array is not None and (before.get(name) is None or len(before[name]) != len(array)):
                changes[name] = np.arange(len(array))
            elif name in (VERTEX_INDICES, *VERTEX_ARRAYS):  # the meshes' indices follow the world's vertex count
                changes[name] = np.union1d(changes.get(name, []), changed_rows(before[name], array)).astype(np.int64)
        top = changes.pop(_TOP_NODES, np.zeros(0, np.int64))
        if NODES in changes:
            changes[NODES] = changes[NODES] + instancing.top_records
        changes[NODES] = np.union1d(top, changes.get(NODES, [])).astype(np.int64)
        return changes

    def _instanced_vertices(self, instancing: InstanceRecords) -> dict[str, np.ndarray]:
        """The vertex arrays with the meshes' vertices after the world's (`shared_vertices` of their
        corners, object space) and their triangles' vertex indices offset past the world's; an
        attribute one side lacks takes its default there (_MISSING_VERTEX). Empty where neither side
        has an attribute. A textured scene without tangents (no normal map, no anisotropy) keeps the world's one zero tangent."""
        kinds = {VERTEX_NORMALS: "normals", VERTEX_COLORS: "colors"}
        if self.textured:
            kinds[VERTEX_UVS] = "uvs"
            if self._reads_tangents:
                kinds[VERTEX_TANGENTS] = "tangents"
        meshes = {name: instancing.corner_values(kind) for name, kind in kinds.items()}
        names = [name for name in kinds if name in self.vertices or meshes[name] is not None]
        if not names:
            return {}
        if VERTEX_INDICES in self.vertices:
            world_indices = self.vertices[VERTEX_INDICES]
            world_count = next(len(self.vertices[name]) for name in names if name in self.vertices)
        else:  # every world triangle names one default vertex
            world_indices, world_count = triangle_vertex_records(np.zeros((len(self.triangles), 3), np.uint32)), 1
        mesh_count = len(instancing.triangles)
        mesh_corners = {
            name: np.broadcast_to(_MISSING_VERTEX[name], (mesh_count, 3, len(_MISSING_VERTEX[name])))
            if meshes[name] is None
            else meshes[name]
            for name in names
        }
        indices, values = shared_vertices(mesh_corners)
        vertices = {VERTEX_INDICES: joined([world_indices, triangle_vertex_records(indices + np.uint32(world_count))])}
        for name in names:
            world = self.vertices.get(name)
            if world is None:
                world = vertex_records(VERTEX_ARRAYS[name], np.tile(_MISSING_VERTEX[name], (world_count, 1)))
            vertices[name] = joined([world, vertex_records(VERTEX_ARRAYS[name], values[name])])
        return vertices

    def _snapshot(self) -> None:
        self._instances, self._placements = self._instance_state(), self._instance_placements()
        self._shapes = list(self.scene.shapes)
        self._versions = [(s.geometry_version, s.transform_version, s.material_version) for s in self._shapes]
        self._materials = self.scene.materials
        self._material_versions = [m.version for m in self._materials]
        self._lights = self.scene.lights
        self._light_versions = [light.version for light in self._lights]

    def _lights_edited(self) -> bool:
        """A light added, removed or edited, or the environment replaced or edited, since the snapshot."""
        lights = self.scene.lights
        environment = self.scene.environment
        return (
            len(lights) != len(self._lights)
            or any(
                a is not b or a.version != v for a, b, v in zip(lights, self._lights, self._light_versions, strict=True)
            )
            or environment is not self._environment
            or environment_state(environment) != self._environment_state
            or (environment is not None and environment.generation != self._environment_generation)
        )

    def _update_textures(self) -> dict[str, np.ndarray]:
        """The texture records of the scene's materials, repacking the atlas where the set of textures
        changed (a texture swapped for one of its size and kind keeps the others' rectangles); their
        changed rows. A scene without textures keeps none of them, whatever UVs its shapes have.
        """
        materials = self.scene.materials
        textures = used_textures(materials)
        if not textures and not any(needs_material_record(material) for material in materials):
            self.atlas_texels = self.texture_records = self.material_textures = None
            self._textures, self._reads_tangents = [], False
            return {}
        changes = {}
        # normal maps and anisotropic BSDFs (`surface_frame`) read the vertex tangents
        self._reads_tangents = any("normal" in m.textures() or m.reads_tangent() for m in materials)
        if [id(t) for t in textures] != [id(t) for t in self._textures] or self.atlas_texels is None:
            atlas = pack_atlas(textures, self.texture_side)
            changes[TEXTURE_ATLAS] = _changed_texel_rows(self.atlas_texels, atlas.texels)
            self.atlas_texels = atlas.texels
            old = self.texture_records
            changes[TEXTURES] = np.arange(len(textures)) if old is None else changed_rows(old, atlas.records)
            self.texture_records, self._textures = atlas.records, textures
        records = material_texture_records(materials, textures)
        old = self.material_textures
        changes[MATERIAL_TEXTURES] = np.arange(len(records)) if old is None else changed_rows(old, records)
        self.material_textures = records
        return changes

    def _moves_vertices(self, moved: list[int]) -> bool:
        """Whether moving the shapes `moved` (indices) can change a vertex: one with attributes of its
        own (a turn turns its normals, a mirror swaps its corners), or any under a normal map or anisotropy
        (MikkTSpace's tangents follow the positions). Moving the others leaves the vertices as they
        are, which spares a large smooth mesh's table when something beside it moves."""
        if self._reads_tangents:
            return True
        shapes = [self.scene.shapes[index] for index in moved]
        return any(
            attribute is not None
            for shape in shapes
            for attribute in (shape.normals, shape.uvs, shape.tangents, shape.colors)
        )

    def _input_shapes(self) -> np.ndarray:
        """Each kept triangle's shape (its index in scene.shapes), in input order."""
        return np.repeat(np.arange(len(self._input_start) - 1), np.diff(self._input_start))

    @property
    def triangle_shapes(self) -> np.ndarray:
        """Each world triangle's shape (its index in scene.shapes) in BVH order, uint32."""
        shapes = np.empty(len(self._position), np.uint32)
        shapes[self._position] = self._input_shapes()
        return shapes

    def _corner_attributes(self) -> dict[str, np.ndarray]:
        """The shading attributes the scene has, per corner (n, 3, k) float32 in BVH order, from the
        shapes as they are: normals (zero for shapes without: flat), texture coordinates with
        textures (zero for shapes without) and tangents where a material reads them (normal maps, anisotropy),
        colours (white for shapes without)."""
        shapes = self.scene.shapes
        shape_index = self._input_shapes()
        scene_order = {VERTEX_NORMALS: corner_normals(shapes, shape_index, self._local_index)}
        if self.textured:
            uvs = corner_uvs(shapes, shape_index, self._local_index)
            scene_order[VERTEX_UVS] = np.zeros((len(shape_index), 3, 2), np.float32) if uvs is None else uvs
            if self._reads_tangents:
                scene_order[VERTEX_TANGENTS] = corner_tangents(shapes, shape_index, self._local_index)
        scene_order[VERTEX_COLORS] = corner_colors(shapes, shape_index, self._local_index)
        corners = {}
        for name, values in scene_order.items():
            if values is not None:
                corners[name] = np.empty_like(values)
                corners[name][self._position] = values
        return corners

    def _update_vertices(self) -> dict[str, np.ndarray]:
        """The shading attributes per vertex and each triangle's vertices (`shared_vertices`), from
        the shapes as they are (none where the scene has no attribute); their changed rows. A
        textured scene without tangents binds one zero tangent."""
        corners = self._corner_attributes()
        vertices = {}
        if corners:
            indices, values = shared_vertices(corners)
            vertices[VERTEX_INDICES] = triangle_vertex_records(indices)
            vertices |= {name: vertex_records(VERTEX_ARRAYS[name], v) for name, v in values.items()}
        if self.textured and not self._reads_tangents:
            vertices[VERTEX_TANGENTS] = VERTEX_TANGENT.zeros(1)
        old, self.vertices = self.vertices, vertices
        return {
            name: np.arange(len(records)) if name not in old else changed_rows(old[name], records)
            for name, records in vertices.items()
        }

    def _triangle_light_densities(self) -> np.ndarray:
        """Each triangle's light table weight per unit area, in scene order, from what its material
        emits through its texture record: the luminance of the emitted radiance x the emission
        texture's mean over the triangle's footprint (`footprint_means`)."""
        material_of = self.triangles["material"][self._position]
        densities = self._light_densities[material_of]
        textured = [
            (index, material)
            for index, material in enumerate(self.scene.materials)
            if self._light_densities[index] > 0 and "emission" in material.textures()
        ]
        if textured:
            shapes = self.scene.shapes
            shape_index = np.repeat(np.arange(len(shapes)), np.diff(self._input_start))
            uvs = corner_uvs(shapes, shape_index, self._local_index)
            uvs = np.zeros((len(material_of), 3, 2), np.float32) if uvs is None else uvs
            for index, material in textured:
                rows = material_of == index
                means = footprint_means(material.textures()["emission"], uvs[rows])
                densities[rows] = (means * material.surface_emission()) @ LUMINANCE_WEIGHTS
        return densities

    def _update_triangle_light_densities(self, densities: np.ndarray) -> np.ndarray:
        """The GPU's copy of `densities` (scene order) in BVH order, or one zero where no triangle
        emits through a texture record; its changed rows."""
        records = np.zeros(len(densities) if densities.any() else 1, np.float32)
        if densities.any():
            records[self._position] = densities
        old = self.triangle_light_densities
        self.triangle_light_densities = records
        return np.arange(len(records)) if len(old) != len(records) else np.flatnonzero(old != records)

    def _update_environment_map(self) -> dict[str, np.ndarray]:
        """A new environment or new texels: the map's texels and sampling tables as the GPU holds
        them (none for a constant environment, nor for an all-black map, which lights nothing)."""
        environment = self.scene.environment
        tables = None if environment is None or environment.texels is None else environment.sampling_tables()
        self._environment_generation = None if environment is None else environment.generation
        if tables is None:
            self.environment_texels = self.environment_tables = None
            return {}
        self.environment_texels = environment_texels(environment)
        self.environment_tables = environment_table_words(tables)
        return {
            ENVIRONMENT_TEXELS: np.arange(len(self.environment_texels)),
            ENVIRONMENT_TABLES: np.arange(len(self.environment_tables)),
        }

    def _environment_holds(self) -> str | None:
        """How the GPU holds the scene's environment (`Environment.held_as`): None where it has none."""
        environment = self.scene.environment
        return None if environment is None else environment.held_as

    def _has_distant_lights(self) -> bool:
        """Lights whose power depends on the scene's size: distant ones and the environment."""
        return self.scene.environment is not None or any(light.distant for light in self.scene.lights)

    def scene_bounding_sphere(self) -> tuple[np.ndarray, float]:
        """The centre and radius of the scene's bounding sphere (around its box: half the box's
        diagonal), which the power of distant lights and the environment is measured through and
        light paths from them start on (`distant_emission_origin`)."""
        corners = np.concatenate([self.triangles[corner] for corner in ("v0", "v1", "v2")]).astype(np.float64)
        if self.instancing is not None:  # the top level's root box holds the instances' boxes
            top = self.instancing.top
            corners = np.concatenate([corners, top.bounds_min[:1], top.bounds_max[:1]]).astype(np.float64)
        low, high = corners.min(axis=0), corners.max(axis=0)
        return 0.5 * (low + high), 0.5 * float(np.linalg.norm(high - low))

    def scene_radius(self) -> float:
        return self.scene_bounding_sphere()[1]

    def _rebuild(self) -> dict[str, np.ndarray]:
        if self.scene.instances and not self.scene.shapes:
            raise SceneError(
                f"the scene has {len(self.scene.instances)} instances and no Shape: add at least one Shape beside "
                "them (the scene's own shapes are an item of the instances' top level), e.g. a ground"
            )
        arrays = self.scene.arrays()
        bvh = build_acceleration(arrays, self.acceleration_kind)
        order = bvh.triangle_order
        vertices = arrays.vertices[order]
        nodes, wide = gpu_node_records(bvh)
        new = {
            TRIANGLES: triangle_records(vertices, arrays.material_index[order]),
            NODES: nodes,
            MATERIALS: material_records(arrays.materials),
        }
        old = {TRIANGLES: self.triangles, NODES: self.nodes, MATERIALS: self.materials}
        changes = {
            name: np.arange(len(new[name])) if old[name] is None else changed_rows(old[name], new[name]) for name in new
        }
        self.triangles, self.nodes, self.materials = new[TRIANGLES], new[NODES], new[MATERIALS]
        self.bvh: BVH = bvh
        self.wide = wide
        self.refitter = Refitter(bvh, vertices)
        self.instancing = None
        if self.scene.instances:
            if wide is None:
                raise SceneError(f"instances need the 'bvh' acceleration, not {self.acceleration_kind!r}")
            slot = {id(material): index for index, material in enumerate(arrays.materials)}
            self.instancing = InstanceRecords(self.scene, bvh, wide, len(vertices), slot)
        # where each shape's kept triangles start in input order, their local indices, and the
        # BVH position of every input triangle
        counts = np.bincount(arrays.shape_index, minlength=len(self.scene.shapes))
        self._input_start = np.concatenate([[0], np.cumsum(counts)])
        self._local_index = arrays.local_index
        self._position = np.empty(len(order), np.int64)
        self._position[order] = np.arange(len(order))
        changes.update(self._update_lights())
        changes.update(self._update_textures())
        changes.update(self._update_vertices())
        self.rebuilds += 1
        self._needs_rebuild = False
        self._snapshot()
        changes = self._assemble(changes, rebuilt=self.instancing is not None)
        return {name: rows for name, rows in changes.items() if rows.size}

    def _refit(self, moved: list[int]) -> dict[str, np.ndarray] | None:
        """New world triangles of the moved shapes and a refit BVH; None where only a rebuild will do
        (a triangle turned zero-area or back, or the refit tree got too slow)."""
        positions, corners = [], []
        for index in moved:
            shape = self.scene.shapes[index]
            span = slice(self._input_start[index], self._input_start[index + 1])
            kept = self._local_index[span]
            world = shape.world_vertices
            if not np.array_equal(np.flatnonzero(~zero_area(world)), kept):
                return None
            positions.append(self._position[span])
            corners.append(world[kept])
        positions, corners = np.concatenate(positions), np.concatenate(corners)
        order = np.argsort(positions)
        positions, corners = positions[order], corners[order]
        touched = self.refitter.move(positions, corners)
        if self.bvh.kind == "bvh" and self.refitter.degradation > REBUILD_DEGRADATION:
            return None
        self.refits += 1
        triangles = self.triangles[positions]
        for corner in range(3):
            triangles[f"v{corner}"] = corners[:, corner]
        rows = positions[changed_rows(self.triangles[positions], triangles)]
        self.triangles[positions] = triangles
        return {TRIANGLES: rows, NODES: self._refit_nodes(touched)}

    def _refit_nodes(self, touched: np.ndarray) -> np.ndarray:
        """Bring the GPU node records up to date with the refit `touched` binary nodes; the rows that
        changed. A refit keeps the topology, so the wide records holding a touched node regather their
        boxes (through `WideBVH.slot_node`) instead of collapsing again.
        """
        if self.wide is None:  # the flat list uploads its boxes as they are
            self.nodes["bounds_min"][touched] = self.bvh.bounds_min[touched]
            self.nodes["bounds_max"][touched] = self.bvh.bounds_max[touched]
            return touched
        moved = np.zeros(self.bvh.node_count + 1, bool)  # the last entry stands for empty slots
        moved[touched] = True
        rows = np.flatnonzero(moved[self.wide.slot_node].any(axis=1))
        before = self.nodes[rows]
        set_wide_bounds(self.nodes, self.wide, self.bvh, rows)
        return rows[changed_rows(before, self.nodes[rows])]

    def _reassign_materials(self) -> dict[str, np.ndarray]:
        """A shape got another material: new material list, every triangle's index recomputed."""
        materials = self.scene.materials
        slot = {id(material): index for index, material in enumerate(materials)}
        kept_counts = np.diff(self._input_start)
        material_index = np.repeat(np.array([slot[id(s.material)] for s in self.scene.shapes], np.uint32), kept_counts)
        indices = material_index[self.bvh.triangle_order]
        triangle_rows = np.flatnonzero(indices != self.triangles["material"])
        self.triangles["material"] = indices
        records = material_records(materials)
        material_rows = changed_rows(self.materials, records)
        self.materials = records
        return {TRIANGLES: triangle_rows, MATERIALS: material_rows}

    def _update_material_records(self) -> dict[str, np.ndarray]:
        edited = [
            i for i, (m, v) in enumerate(zip(self._materials, self._material_versions, strict=True)) if m.version != v
        ]
        if not edited:
            return {}
        records = material_records([self._materials[i] for i in edited])
        rows = np.asarray(edited)[changed_rows(self.materials[edited], records)]
        self.materials[edited] = records
        return {MATERIALS: rows}

    def _update_lights(self) -> dict[str, np.ndarray]:
        """The light table in scene order pointing at BVH positions, the light sources' records, the
        lighting parameters and, for a new map, its texels and tables; the changed rows of each. Scene
        order, not the BVH's, so a refit tree and a fresh build sample the same light for the same
        random numbers. `update` calls this when an emitter or a light changes, and when geometry moves
        under distant lights or an environment (whose power is what crosses the bounding sphere):

        | light edit                                   | rows that change                                      |
        |----------------------------------------------|-------------------------------------------------------|
        | a light's parameter                          | its light source record; the table where its power moved |
        | a light added or removed                     | the light source records and the table                |
        | environment rotation or visibility           | the lighting parameters only                          |
        | environment intensity or constant radiance   | the lighting parameters; the table where other lights share it |
        | a new map (`generation`) or environment      | the map, its sampling tables, the lighting parameters, the table |
        """
        lights, environment = self.scene.lights, self.scene.environment
        center, radius = self.scene_bounding_sphere() if self._has_distant_lights() else (np.zeros(3), 0.0)
        environment_changed = environment is not self._environment or (
            environment is not None and environment.generation != self._environment_generation
        )
        changes = {}
        if environment_changed:
            changes.update(self._update_environment_map())
        holds = self._environment_holds()
        environment_weight = environment.weight(radius) if holds is not None else 0.0
        self._light_densities = self._surface_light_densities()
        densities = self._triangle_light_densities()
        table = light_table(
            self.triangles[self._position],
            self.materials,
            np.array([light.weight(radius) for light in lights]),
            environment_weight,
            densities,
        )
        changes[TRIANGLE_LIGHT_DENSITIES] = self._update_triangle_light_densities(densities)
        triangle_entries = table.entries["triangle"] < len(self._position)
        table.entries["triangle"][triangle_entries] = self._position[table.entries["triangle"][triangle_entries]]
        changes[LIGHTS] = (
            np.arange(table.count) if self.lights is None else changed_rows(self.lights.entries, table.entries)
        )
        self.lights = table
        sources = LIGHT_SOURCE.zeros(len(lights))
        for record, light, probability in zip(sources, lights, table.source_probability, strict=True):
            record["kind"], record["probability"] = light.kind, probability
            light.fill_record(record)
        changes[LIGHT_SOURCES] = changed_rows(self.sources, sources)
        self.sources = sources
        lighting = LIGHTING.zeros(1)
        lighting["source_count"] = len(lights)
        lighting["scene_center"], lighting["scene_radius"] = center, radius
        if holds is not None:
            environment.fill_record(lighting[0])
            lighting["environment_probability"] = table.environment_probability
        changes[LIGHTING_PARAMETERS] = changed_rows(self.lighting, lighting)
        self.lighting = lighting
        self.light_features = LightFeatures(tuple(light.kind for light in lights), holds)
        self._environment = environment
        self._environment_state = environment_state(environment)
        return changes


def _changed_texel_rows(old: np.ndarray | None, new: np.ndarray) -> np.ndarray:
    """The rows of texels that differ, all of them where the atlas was packed another size or type
    (a texture swapped for one of its size and kind repacks to the same rectangles)."""
    if old is None or old.shape != new.shape or old.dtype != new.dtype:
        return np.arange(len(new))
    return np.flatnonzero((old != new).reshape(len(new), -1).any(axis=1))


def _union(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name: np.union1d(a.get(name, []), b.get(name, [])).astype(np.int64) for name in a.keys() | b.keys()}


def scene_records(scene: Scene, acceleration: str = "bvh") -> SceneRecords:
    """The GPU records of `scene` exactly as a Renderer assembles them (the one assembly path)."""
    return SceneMirror(scene, acceleration).records
