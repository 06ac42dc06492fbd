"""Every comparison of our renderer with a Mitsuba 3 reference: what Mitsuba renders for each
reference image (REFERENCES, read by `python scripts/make_references.py`) and how we render each
case compared with one (CASES, read by the reference tests).

A case renders `batches` images of `spp` samples at size x size and tests, per block of pixels and
channel, whether their expectation is the reference's (Welch's t-test, `assert_matches_reference`).
Each family of cases may report a difference by chance with probability FAMILY_SIGNIFICANCE at
most, Sidak-split over its block tests (`family_block_tests`). Nothing here needs scipy or
Mitsuba, so that the reference script runs with the `reference` extra alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

from wgputrace.kernels.shading_normals import MITSUBA_SHADING_NORMALS

# The overrides that shade smooth and normal-mapped surfaces as Mitsuba does (MITSUBA_SHADING_NORMALS).
MITSUBA_TERMS = tuple(MITSUBA_SHADING_NORMALS.items())
# Every reference is REFERENCE_SIZE x REFERENCE_SIZE: our sizes divide it.
REFERENCE_SIZE = 128
# Probability that a family reports a difference somewhere when there is none.
FAMILY_SIGNIFICANCE = 1e-3
# The smallest block tested: it finds local errors (a moved lobe, texel block, stripe or caustic),
# the whole image small ones spread everywhere (a rare leak through the slivers adds too little to
# any one block to stand out of its noise).
FINEST_BLOCK = 8


@dataclass(frozen=True)
class ReferenceSettings:
    """How Mitsuba renders a reference: its `path` integrator at our max depth, `passes`
    independent renders of `spp` samples per pixel whose spread gives the standard error."""

    max_depth: int
    spp: int = 256  # samples per pixel in one pass
    passes: int = 16  # independent passes (seeds 0 .. passes - 1), for the standard error


# The scenes with a reference of their own (wgputrace.scenes; the scaled Cornell boxes are
# compared with `cornell`'s).
REFERENCES: dict[str, ReferenceSettings] = {
    "cornell": ReferenceSettings(max_depth=9),
    "tiny_light": ReferenceSettings(max_depth=9),
    "glass_grazing": ReferenceSettings(max_depth=12),
    "glossy_spheres": ReferenceSettings(max_depth=6),
    "principled_spheres": ReferenceSettings(max_depth=6),
    "principled_transmission": ReferenceSettings(max_depth=10),
    "principled_clearcoat": ReferenceSettings(max_depth=6),
    "principled_sheen": ReferenceSettings(max_depth=6),
    "principled_anisotropic": ReferenceSettings(max_depth=6),
    "textured_quads": ReferenceSettings(max_depth=6),
    "textured_asset": ReferenceSettings(max_depth=6),
    "alpha_cutout": ReferenceSettings(max_depth=6),
    "smooth_sphere": ReferenceSettings(max_depth=4),
    "alpha_blend": ReferenceSettings(max_depth=6),
    "normal_mapped_plane": ReferenceSettings(max_depth=4),
    "slivers": ReferenceSettings(max_depth=5),
    "axis_boxes": ReferenceSettings(max_depth=6),
    # lit by the environment and by point, spot and directional lights
    "env_sun_spheres": ReferenceSettings(max_depth=6),
    "constant_env": ReferenceSettings(max_depth=6),
    "env_one_texel": ReferenceSettings(max_depth=3),
    "point_spot_directional": ReferenceSettings(max_depth=5),
    # scenes that break path tracers (issue 18): mostly indirect light, a caustic, glossy seen in glossy
    "door_ajar": ReferenceSettings(max_depth=10, spp=4096),
    "caustic": ReferenceSettings(max_depth=8, spp=4096),
    "glossy_through_glossy": ReferenceSettings(max_depth=8, spp=4096),
    # the camera kinds (issue 28): Mitsuba's thinlens and orthographic
    "depth_of_field": ReferenceSettings(max_depth=6),
    "orthographic_boxes": ReferenceSettings(max_depth=6),
    # instances (issue 25): Mitsuba draws them flattened
    "instanced_cornell": ReferenceSettings(max_depth=9),
    # vertex colours (issue 25): Mitsuba's `mesh_attribute` texture
    "vertex_colored_triangles": ReferenceSettings(max_depth=6),
    # absorption inside glass and rough transmission (issue 25's KHR_materials_volume): Mitsuba's volpath
    "absorbing_glass": ReferenceSettings(max_depth=10),
    # many lights (issue 27): 1,065 windows and 24 lamps
    "night_street": ReferenceSettings(max_depth=5),
}


@dataclass(frozen=True)
class ReferenceCase:
    """One comparison: `scene` rendered by us as `batches` x `spp` samples per pixel at `seed`,
    at the reference's max depth, against the reference `reference` (the scene's own by default),
    block by block over `blocks` (FINEST_BLOCK and the whole image by default). `same_paths_as`
    names the case (same family and integrator) whose batches this one's are also compared with,
    pair by pair: the same image, sampled with the same random numbers."""

    scene: str
    family: str
    size: int
    batches: int
    spp: int  # per batch
    seed: int
    integrator: str = "mis"
    shader_overrides: tuple[tuple[str, float], ...] = ()
    blocks: tuple[int, ...] = ()
    reference: str = ""
    same_paths_as: str | None = None
    # a name for the shader overrides where one scene and integrator has cases with and without
    variant: str = ""

    def __post_init__(self) -> None:
        # the defaults that depend on other fields, filled in once (the dataclass is frozen)
        if not self.blocks:
            object.__setattr__(self, "blocks", (FINEST_BLOCK, self.size))
        if not self.reference:
            object.__setattr__(self, "reference", self.scene)

    @property
    def name(self) -> str:
        return f"{self.scene}-{self.integrator}" + (f"-{self.variant}" if self.variant else "")

    @property
    def mitsuba(self) -> ReferenceSettings:
        return REFERENCES[self.reference]

    @property
    def renderer_options(self) -> dict:
        """Renderer's keyword arguments besides the scene, size and seed."""
        return {
            "max_depth": self.mitsuba.max_depth,
            "integrator": self.integrator,
            "shader_overrides": dict(self.shader_overrides),
        }


# --- The path tracer on the test scenes -------------------------------------------------------
# Sample counts: these cases took 100 s (172 s of CPU) on the 2-core lavapipe machine, with the
# other reference-related tests of the time; the budget is about four minutes.
_path_tracer = partial(ReferenceCase, family="path_tracer", size=64, seed=20261123)
# Where mis finds much of the light only in rare paths (the caustic's light reaching the floor
# through the glass, a small lamp after two glossy bounces), the blocks' means at these sample
# counts are heavy-tailed: typical runs fall 20 to 40% short on some 8x8 blocks, which a t-test
# reads as a difference. Larger blocks pool enough paths; at 32x32 a 3 to 5% error still shows.
HEAVY_TAILED_BLOCKS = (32, 64)
PATH_TRACER_CASES = (
    _path_tracer("cornell", batches=16, spp=32),
    _path_tracer("tiny_light", batches=16, spp=32),
    _path_tracer("glass_grazing", batches=16, spp=32),
    _path_tracer("glossy_spheres", batches=16, spp=32),
    _path_tracer("slivers", batches=16, spp=16),
    _path_tracer("axis_boxes", batches=16, spp=24),
    _path_tracer("instanced_cornell", batches=16, spp=16),
    # many lights (issue 27): the scene as Mitsuba sees it, for the restir family's case
    _path_tracer("night_street", batches=16, spp=16),
    # scenes that break path tracers (issue 18): their light comes in rare, bright paths
    _path_tracer("door_ajar", batches=16, spp=16),
    _path_tracer("caustic", batches=16, spp=32, blocks=HEAVY_TAILED_BLOCKS),
    _path_tracer("glossy_through_glossy", batches=16, spp=32, blocks=HEAVY_TAILED_BLOCKS),
    # the same box scaled, camera included: the same image, tested against the same reference
    # and, sample for sample, against the unscaled box's first batches (same seed)
    _path_tracer("cornell_1e-4", batches=8, spp=32, reference="cornell", same_paths_as="cornell"),
    _path_tracer("cornell_1e4", batches=8, spp=32, reference="cornell", same_paths_as="cornell"),
    # The other direct-light strategies converge to the same picture as mis. BSDF sampling alone
    # on the tiny light is left out: a lamp that small is hit so rarely that its estimates are too
    # heavy-tailed for a t-test at any affordable sample count.
    _path_tracer("cornell", batches=8, spp=32, integrator="bsdf"),
    _path_tracer("cornell", batches=8, spp=32, integrator="nee"),
    _path_tracer("tiny_light", batches=8, spp=32, integrator="nee"),
)

# --- Lights: the environment (Mitsuba's `envmap`, `constant`) and point, spot and directional ---
# lights (wgputrace.scenes.environment_lit and .punctual). MIS on every scene; light sampling
# alone and BSDF sampling alone on the environments: BSDF sampling finds the sunny sky's sun (a few
# texels) too rarely for a t-test at an affordable count, so it is tested on the constant sky,
# where every escaped ray counts. `env_one_texel` is the environment map's direction convention
# seen by Mitsuba: a map black but for one texel lights one side of a sphere, and Mitsuba must
# light the same side as brightly (`test_one_bright_texel_lights_the_side_facing_its_documented_direction`
# pins the same map against a closed form).
_lights = partial(ReferenceCase, family="lights", size=64, batches=8, seed=20261123)
LIGHT_CASES = (
    _lights("env_sun_spheres", spp=32),
    _lights("env_sun_spheres", spp=32, integrator="nee"),
    _lights("constant_env", spp=32),
    _lights("constant_env", spp=32, integrator="bsdf"),
    _lights("env_one_texel", spp=16),
    _lights("point_spot_directional", spp=32),
)

# --- Issue 14's materials and assets ---------------------------------------------------------
# The pointwise tests pin each piece (the shaders' `test_principled` the BSDF, the renderer's
# `test_textures` the lookup, `test_alpha_emission` the cut-outs);
# these pin them inside the path tracer and against an independent renderer:
# - principled_spheres (metallic 0 to 1, roughness 0.1 to 1, in the emitting room): the two-sided
#   wrapper, light sampling and MIS weights that use its pdf;
# - textured_quads (a marked sRGB checkerboard repeating past [0, 1], a metallic-roughness texture
#   mirrored and transformed): orientation, sRGB decoding, wrap modes, KHR_texture_transform
#   against Mitsuba's `bitmap`;
# - alpha_cutout (a striped cut-out quad between a small lamp and a wall): camera rays see the
#   stripes and shadow rays draw them on the wall; a cut-out that only one kind of ray honours, a
#   flipped or shifted alpha lookup or a wrong cutoff moves or loses stripes;
# - textured_asset (a panel with base colour, metallic-roughness, normal and emission textures,
#   per-vertex normals and texture coordinates, on a floor its emissive marks light, under a point
#   light): Mitsuba's `normalmap` wrapper (green flipped where our tangents' w is -1, normal_scale
#   baked into the texels) and an `area` emitter with a `bitmap` radiance. Our terminator term for
#   mapped normals, which Mitsuba lacks, is kept out of play by the scene's lighting;
# - alpha_blend (the quad BLEND, its alpha ramping across it): stochastic transparency for camera
#   and shadow rays against its expectation, Mitsuba's `mask` of that alpha.
# Each scene has a seed of its own, so the scenes' noise is independent.
_materials = partial(ReferenceCase, family="materials", size=64, batches=16, spp=32)
MATERIAL_CASES = (
    _materials("principled_spheres", seed=20261201),
    _materials("textured_quads", seed=20261202),
    _materials("alpha_cutout", seed=20261203),
    _materials("textured_asset", seed=20261204),
    _materials("principled_transmission", seed=20261209),
    _materials("alpha_blend", seed=20261206),
    # absorbing glass and rough transmission (`volume`): Mitsuba's interior `homogeneous` media under `volpath`
    _materials("absorbing_glass", seed=20261210),
    _materials("principled_clearcoat", seed=20261401),
    _materials("principled_sheen", seed=20261402),
    # anisotropy: smooth spheres, shaded as Mitsuba shades smooth normals (MITSUBA_SHADING_NORMALS)
    _materials("principled_anisotropic", seed=20261403, shader_overrides=MITSUBA_TERMS),
)

# --- Shading normals without our terms -------------------------------------------------------
# A smooth low-poly sphere (an 80-triangle icosphere with the sphere's normals at its corners,
# above its flat version, lit from the side) and a normal-mapped plane under a grazing light.
# Mitsuba shades with the interpolated and mapped normals as we do, but has no terminator term
# for vertex normals, another one for normal maps (Estevez et al. 2019, which the export turns
# off), and shades a point seen from between the shading and geometric horizons (at silhouettes)
# with the shading normal as well (dark: the viewer is below it), where we take the geometric one.
# Ours is compared with our term and that rule off (MITSUBA_SHADING_NORMALS). With either on, ours
# differs where it should (the smooth sphere darker near its terminator, the bumps darker on their
# lit sides, the sphere's outline brighter); `test_shading_normal_terms` tests what the terms do.
_shading_normals = partial(
    ReferenceCase, family="shading_normals", size=64, batches=16, spp=32, shader_overrides=MITSUBA_TERMS
)
SHADING_NORMAL_CASES = (
    _shading_normals("smooth_sphere", seed=20261205),
    _shading_normals("normal_mapped_plane", seed=20261207),
)

# --- Bidirectional path tracing ----------------------------------------------------------------
# Issue 18 asks bdpt to converge to the same image as mis. The scenes here are those where its
# light subpaths meet something of their own: the light kinds they leave (a light triangle in the
# Cornell box, the environment mixed with a sun, point, spot and directional lights), materials a
# light subpath scatters from with the adjoint BSDF (diffuse, glossy and glass in the box,
# principled transmission), textures on light and camera vertices alike (textured_asset: base
# colour, normal map, emission through a texture), the shading normal a light subpath's vertex is
# shaded with (normal_mapped_plane, without our terms as above), the box at 1e-4 of its size
# (connections' shadow rays between points moved off their surfaces) and the scenes that break
# path tracers. What bdpt shares with the path tracer (traversal, the BSDFs' values, texture
# lookups, cut-outs and stochastic transparency in every traversal, the scenes' geometry) the path
# tracer's own cases cover.
# Kept out for CI time, each bdpt variant compiling for seconds on lavapipe: principled_spheres,
# textured_quads, alpha_cutout, alpha_blend, smooth_sphere, glass_grazing, glossy_spheres, slivers,
# axis_boxes, constant_env, env_one_texel; `test_bdpt_weights` weighs paths on some of them,
# `test_bdpt` checks others for non-finite samples.
# 32x32 and 8 batches: weaker statistics than the path tracer's at 64x64, the price of CI time.
_bdpt = partial(ReferenceCase, family="bdpt", size=32, batches=8, spp=16, integrator="bdpt")
BDPT_CASES = (
    _bdpt("cornell", seed=20261211),
    _bdpt("cornell_1e-4", seed=20261212, reference="cornell"),
    _bdpt("env_sun_spheres", seed=20261215),
    _bdpt("point_spot_directional", seed=20261216),
    _bdpt("principled_transmission", seed=20261218),
    _bdpt("textured_asset", seed=20261220),
    _bdpt("normal_mapped_plane", seed=20261224, shader_overrides=MITSUBA_TERMS),
    _bdpt("door_ajar", seed=20261225),
    _bdpt("caustic", seed=20261226),
    _bdpt("glossy_through_glossy", seed=20261227),
)

# --- Camera kinds ---------------------------------------------------------------------------------
# Issue 28's thin lens and orthographic camera against Mitsuba's `thinlens` and `orthographic`
# (wgputrace.scenes.camera_views says what each scene's blocks catch), under the path tracer and
# under bdpt, whose light tracing splats through the lens and onto the orthographic rectangle.
# The pinhole is every other case's camera; the equirectangular camera has no Mitsuba sensor and is
# held to closed forms (`test_a_360_render_of_a_constant_environment_is_constant` and its neighbours).
_cameras = partial(ReferenceCase, family="cameras", size=64, batches=16, spp=32)
_cameras_bdpt = partial(_cameras, size=32, batches=8, spp=16, integrator="bdpt")
CAMERA_CASES = (
    _cameras("depth_of_field", seed=20261301),
    _cameras("orthographic_boxes", seed=20261302),
    _cameras_bdpt("depth_of_field", seed=20261303),
    _cameras_bdpt("orthographic_boxes", seed=20261304),
)

# --- Vertex colours ----------------------------------------------------------------------------
# Issue 25's glTF COLOR_0 (Shape.colors) multiplying a diffuse and a glossy colour, interpolated per
# vertex and per corner (wgputrace.scenes.vertex_colored says what each shape catches), against
# Mitsuba's `mesh_attribute` texture (`mitsuba_scene.vertex_colored`). A family of its own, so that
# the other families' bounds stay as they were; 8 batches of 16 spp, the price of CI time: the
# colours differ between shapes and corners by far more than these blocks' noise.
VERTEX_COLOR_CASES = (
    ReferenceCase("vertex_colored_triangles", family="vertex_colors", size=64, batches=8, spp=16, seed=20261401),
)

# --- ReSTIR's resampled direct light ----------------------------------------------------------
# Issue 27 asks the restir integrator to converge to the same image as mis on every light kind:
# light triangles (the Cornell box, its tiny lamp, the emitting room's hundreds of cells behind the
# principled spheres, night_street's 1,065 windows and 24 lamps), the environment and the sun,
# point, spot and directional lights, emission through a texture; and on the lobes that resampling
# weighs candidates by (diffuse, glossy, principled, normal-mapped). The first vertex weighs the
# light its BSDF sample finds against the reservoir's, so these cases also catch light counted twice
# or not at all.
_restir = partial(ReferenceCase, family="restir", size=64, batches=8, spp=32, integrator="restir")
# Reservoirs shared with neighbouring pixels (a pre-pass before each sample): the same picture, on
# one lamp, on point, spot and directional lights and on many lights (three scenes, for CI time).
_shared = partial(_restir, shader_overrides=(("RESERVOIR_NEIGHBOURS", 3),), variant="shared")
RESTIR_CASES = (
    _restir("cornell", seed=20261501),
    _restir("tiny_light", seed=20261502),
    _restir("glossy_spheres", seed=20261503),
    _restir("principled_spheres", seed=20261504),
    _restir("env_sun_spheres", seed=20261505),
    _restir("point_spot_directional", seed=20261506),
    _restir("textured_asset", seed=20261507),
    _restir("night_street", seed=20261508),
    _shared("cornell", seed=20261511),
    _shared("point_spot_directional", seed=20261516),
    _shared("night_street", seed=20261518),
)

CASES: tuple[ReferenceCase, ...] = (
    PATH_TRACER_CASES
    + LIGHT_CASES
    + MATERIAL_CASES
    + SHADING_NORMAL_CASES
    + BDPT_CASES
    + CAMERA_CASES
    + VERTEX_COLOR_CASES
    + RESTIR_CASES
)


def block_tests(size: int) -> int:
    """Welch tests of one comparison at `size` x `size`: every FINEST_BLOCK block and the whole image,
    per channel. Cases that test coarser blocks count as many, which errs on the strict side."""
    return sum((size // block) ** 2 for block in (FINEST_BLOCK, size)) * 3


def family_block_tests(family: str) -> int:
    """The block tests `family` makes, over which FAMILY_SIGNIFICANCE is split: every case counts
    once, and once more if it is also compared pair by pair (`same_paths_as`)."""
    cases = [case for case in CASES if case.family == family]
    return sum(block_tests(case.size) * (2 if case.same_paths_as else 1) for case in cases)


def paired_case(case: ReferenceCase) -> ReferenceCase:
    """The case whose batches `case`'s are compared with pair by pair (`same_paths_as`)."""
    (paired,) = (
        other
        for other in CASES
        if (other.family, other.scene, other.integrator) == (case.family, case.same_paths_as, case.integrator)
    )
    return paired
