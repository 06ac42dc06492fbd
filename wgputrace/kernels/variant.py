"""What a kernel compiles in, stated once: a KernelVariant is the cache key of a compiled kernel,
its label in errors and provenance, the choice of its bind groups and the source of its generated
files. SceneFeatures is the part a scene decides (`SceneMirror.features` makes it); the renderer
adds the integrator, the sampler and what it is asked for (guides, counters, rows).

A boolean feature is one field here, with its label; the hook that reads it (a function of the
variant, listed in HOOKS) and the shader that the hook includes are all that change with it.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING

from ..scene.materials import material_class, material_classes
from .bind_groups import (
    BAND_GROUP,
    GBUFFER_BINDINGS,
    GUIDE_SUMS,
    PIXELS_GROUP,
    RAY_COUNT_GROUP,
    SUBSET_GROUP,
    dispatch_group,
    lights_group,
    scene_group,
    shading_group,
)
from .camera import DEFAULT_CAMERA, camera_label
from .hooks import HOOKS
from .light_dispatch import NO_LIGHTS, LightFeatures
from .principled_lobes import LOBE_SHADERS, check_lobes
from .sampler import DEFAULT_SAMPLER, check_sampler
from .traversal import BVH_STACK_SIZE

if TYPE_CHECKING:
    from ..gpu.bindings import BindGroup
    from ..integrators import Integrator


def flag(label: str) -> bool:
    """A boolean feature, off by default, named `label` in a kernel's label when on."""
    return field(default=False, metadata={"label": label})


def shaded_kinds(kinds) -> tuple[int, ...]:
    """Material `kinds` in id order, each a registered kind: what the generated code covers."""
    return tuple(material_class(kind).kind for kind in sorted(set(kinds)))


# every registered material kind: a kernel that draws no particular scene compiles them all
ALL_KINDS = shaded_kinds(cls.kind for cls in material_classes())


def _flag_labels(value) -> list[str]:
    return [f.metadata["label"] for f in fields(value) if "label" in f.metadata and getattr(value, f.name)]


@dataclass(frozen=True)
class SceneFeatures:
    """What a scene compiles into every kernel that traces it."""

    acceleration: str = "bvh"
    # entries of the BVH traversal's stack: as many as the scene's tree needs, rounded up
    stack_size: int = BVH_STACK_SIZE
    # the material kinds whose BSDF code is compiled in
    material_kinds: tuple[int, ...] = ALL_KINDS
    # the optional lobes of material kinds whose code is compiled in (`Material.lobes`)
    lobes: tuple[str, ...] = tuple(LOBE_SHADERS)
    # the lights besides emissive triangles
    lights: LightFeatures = NO_LIGHTS
    # the camera kind (a registered kind's id): how camera rays are made and bdpt connects to the camera
    camera: int = DEFAULT_CAMERA
    # per-vertex normals
    smooth: bool = flag("smooth shading")
    # materials that read textures or have a texture record
    textured: bool = flag("textured")
    # surfaces that let rays through (alpha modes, single-sided), asked by every ray's triangle test
    see_through: bool = flag("see-through")
    # materials that emit through their texture record
    emissive_surfaces: bool = flag("emissive surfaces")
    # per-vertex colours multiplying the materials' colours (vertex_colors_hook)
    vertex_colors: bool = flag("vertex colours")
    # materials that absorb the light inside them (absorption_hook)
    absorbing: bool = flag("absorbing")
    # instances (two-level traversal, `instancing_hook`): the bits of a hit word that index the
    # triangle, the rest its instance's slot; 0: no instances
    instance_triangle_bits: int = 0

    def __post_init__(self) -> None:
        scene_group(self.acceleration)  # refuses an unknown acceleration
        camera_label(self.camera)  # refuses an unregistered camera kind
        object.__setattr__(self, "material_kinds", shaded_kinds(self.material_kinds))
        object.__setattr__(self, "lobes", check_lobes(self.lobes))

    @property
    def labels(self) -> list[str]:
        lights = [self.lights.description] if self.lights.any else []
        lobes = [f"{lobe} lobe" for lobe in self.lobes]
        instanced = ["instances"] if self.instance_triangle_bits else []
        return lights + lobes + _flag_labels(self) + instanced + camera_label(self.camera)

    def groups(self) -> tuple[BindGroup, ...]:
        """The bind groups a kernel tracing this scene declares besides its own: the scene group,
        the lights group and the shading group where used."""
        lights = (lights_group(self.lights),) if self.lights.any else ()
        shaded = self.smooth or self.textured or self.vertex_colors
        shading = (shading_group(self.smooth, self.textured, self.vertex_colors),) if shaded else ()
        return (scene_group(self.acceleration, self.instance_triangle_bits > 0), *lights, *shading)


@dataclass(frozen=True)
class KernelVariant:
    """A tracing kernel: a scene's features, the integrator (None: a kernel that traces but does not
    integrate, such as the viewer's guides or a test harness), the sampler, and the extras."""

    scene: SceneFeatures = SceneFeatures()
    integrator: Integrator | None = None
    sampler: str = DEFAULT_SAMPLER
    # the entry point that renders a band of rows (the viewer's)
    rows: bool = flag("rows")
    # the entry point that renders one pixel of each block (temporal upsampling's)
    subset: bool = flag("pixel subset")
    # the integrator's pre-pass over the whole image (`Integrator.prepass_entry`)
    prepass: bool = flag("pre-pass")
    # the ray counters
    count_rays: bool = flag("counting rays")
    # the lane counters (subgroup operations: an adapter with subgroups)
    count_lanes: bool = flag("counting lanes")
    # the denoiser's albedo and normal guides
    guides: bool = flag("guides")
    # the G-buffer of each pixel's centre and its motion since the previous frame's camera, for
    # temporal accumulation (`write_gbuffer`)
    gbuffer: bool = flag("G-buffer")
    # the adapter ends an invocation's loops after a budget of iterations (`loop_iteration_limit`),
    # which the samples of a regenerating invocation share
    loop_budget: bool = flag("loop budget")
    # other override constants of the entry file, sorted (name, value) pairs (for measurements)
    overrides: tuple[tuple[str, float], ...] = ()
    # the most samples of its pixel an invocation takes in one dispatch (path regeneration); the
    # viewer's band-of-rows kernel takes one
    samples_per_dispatch: int = 1

    def __post_init__(self) -> None:
        check_sampler(self.sampler)
        if self.samples_per_dispatch < 1:
            raise ValueError(f"samples_per_dispatch must be at least 1, got {self.samples_per_dispatch}")
        if self.rows + self.subset + self.prepass > 1:
            raise ValueError("a kernel renders a band of rows, a subset of pixels or a pre-pass, not two of them")
        if self.prepass and self.require_integrator().prepass_entry is None:
            raise ValueError(f"the {self.require_integrator().name} integrator has no pre-pass")
        if self.rows:
            self.require_integrator().check_rows()
        if self.subset:
            self.require_integrator().check_subset()
        # the viewer's bands, the subsets and a pre-pass's kernels take one sample per pixel each,
        # and nothing takes owed ones
        if self.rows or self.subset or self.prepass or (self.integrator and self.integrator.uses_prepass(self)):
            object.__setattr__(self, "samples_per_dispatch", 1)
            object.__setattr__(self, "loop_budget", False)
        if self.samples_per_dispatch > 1:
            self.require_integrator().check_regeneration()
        if self.gbuffer:
            self.require_integrator().check_gbuffer()
        object.__setattr__(self, "overrides", tuple(sorted(dict(self.overrides).items())))

    def require_integrator(self) -> Integrator:
        if self.integrator is None:
            raise ValueError("this kernel variant names no integrator")
        return self.integrator

    def with_scene(self, scene: SceneFeatures) -> KernelVariant:
        return replace(self, scene=scene)

    @property
    def label(self) -> str:
        """How errors, compile messages and provenance name it."""
        integrator = [] if self.integrator is None else [self.integrator.name]
        regenerating = [f"{self.samples_per_dispatch} samples per dispatch"] if self.samples_per_dispatch > 1 else []
        parts = [self.scene.acceleration, *integrator, *_flag_labels(self), *regenerating, *self.scene.labels]
        return f"{', '.join(parts)}, {self.sampler} sampler"

    @property
    def entry(self) -> tuple[str, str]:
        """The integrator's entry file and entry point for this variant."""
        integrator = self.require_integrator()
        if self.prepass:
            return (integrator.prepass_entry, "main_prepass")
        if self.subset:
            return (integrator.subset_entry, "main_subset")
        return (integrator.rows_entry, "main_rows") if self.rows else (integrator.entry, "main")

    @property
    def constants(self) -> dict[str, float]:
        """The override constants its entry file is compiled with: the integrator's and `overrides`."""
        return {**dict(self.require_integrator().constants), **dict(self.overrides)}

    def pixels_group(self) -> BindGroup:
        """The pixels group: the guide sums where guides are on, the G-buffer, the previous
        frame's camera and the objects' motions where it is written, with the arrays the integrator
        keeps from frame to frame, and the integrator's own arrays."""
        integrator = self.integrator
        frame_arrays = integrator.frame_arrays if integrator and self.gbuffer else ()
        extra = (
            ((GUIDE_SUMS,) if self.guides else ())
            + (GBUFFER_BINDINGS if self.gbuffer else ())
            + tuple(binding for array in frame_arrays for binding in (array.binding, array.previous))
            + tuple(array.binding for array in (integrator.pixel_arrays if integrator else ()))
        )
        group = PIXELS_GROUP
        for binding in extra:
            group = group.extended(binding)
        return group

    def groups(self) -> tuple[BindGroup, ...]:
        """Every bind group the integrator's kernel for this variant declares."""
        scene, *scene_extras = self.scene.groups()
        own = (self.pixels_group(), *((BAND_GROUP,) if self.rows else ()), *((SUBSET_GROUP,) if self.subset else ()))
        own += (dispatch_group(self.loop_budget),) if self.samples_per_dispatch > 1 else ()
        own += (RAY_COUNT_GROUP,) if self.count_rays or self.count_lanes else ()
        return (scene, *own, *scene_extras)

    def files(self) -> dict[str, str]:
        """Its generated files by name: every hook's, and the integrator's own."""
        files = {name: hook(self) for name, hook in HOOKS.items()}
        return files | (self.integrator.files(self) if self.integrator else {})


# A kernel that draws no particular scene: every material kind and lobe, no lights, flat and untextured.
DEFAULT_VARIANT = KernelVariant()
