"""Lights besides emissive triangles: each kind's shipped WGSL against its definition (Mitsuba 3's
point, spot and directional; the sun's cone sampled against its pdf by chi-square), the environment
map's GPU lookup, density and sampling against the numpy references of `Environment`, the one
light table's choices (chi-square over every kind), closed forms rendered (a white furnace under a
constant environment, a plane under a directional and under a point light), no non-finite sample
for degenerate lights and maps, and edits that upload only what they change."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Environment, Renderer, Scene, make_icosphere, make_plane
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.gpu.layout import FRAME, LIGHT_SOURCE
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.kernels.bind_groups import lights_group
from wgputrace.kernels.compile import tracing_kernel
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.render.gpu_records import GpuRecords
from wgputrace.render.limits import SceneCounts, check_scene_counts, environment_table_words
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.scene import DirectionalLight, LightError, PointLight, SpotLight, Sun
from wgputrace.scene.lights.environment import cell_of_uv
from wgputrace.testing.harness import run_kernel
from wgputrace.testing.stats import chi_square, sidak, z_limit
from wgputrace.view.banded import BandedRenderer

pytestmark = pytest.mark.gpu

SEED = 7
# Family-wise significance of this file's statistical tests, Sidak-split between them.
SIGNIFICANCE = 1e-3
STATISTICAL_TESTS = 5
LEVEL = sidak(SIGNIFICANCE, STATISTICAL_TESTS)
# f32 against float64 references: a few ulps through trigonometry and a bilinear blend
RTOL = 2e-4
# how far (radians) f32 trigonometry on llvmpipe may turn a direction on its way to map coordinates
ANGLE_TOLERANCE = 2e-4


def source_record(light) -> np.ndarray:
    record = LIGHT_SOURCE.zeros(1)
    record["kind"], record["probability"] = light.kind, 1.0
    light.fill_record(record[0])
    return record


KIND_KERNEL = """
//! include "lights/{file}.wgsl"
fn compute(i: u32) -> vec4<f32> {{
    let sample = {call};
    return vec4<f32>(sample.radiance.x, sample.pdf, select(0.0, 1.0, sample.delta), select(0.0, 1.0, sample.distant));
}}
"""


def kind_samples(gpu_context, light, file: str, call: str, points: np.ndarray) -> np.ndarray:
    """(radiance.x, pdf, delta, distant) of `call` for `light` seen from each of `points`."""
    return run_kernel(
        gpu_context,
        KIND_KERNEL.format(file=file, call=call.replace("p)", "inputs_1[i].xyz)")),
        [source_record(light), np.column_stack([points, np.zeros(len(points))]).astype(np.float32)],
        np.dtype((np.float32, 4)),
        len(points),
        input_types=["LightSource", "vec4<f32>"],
        output_type="vec4<f32>",
    )


def test_point_light_sends_its_intensity_over_the_squared_distance(gpu_context, rng):
    light = PointLight((0.5, 2.0, -1.0), 3.0, color=(1.0, 0.5, 0.25))
    points = rng.uniform(-3, 3, (64, 3))
    out = kind_samples(gpu_context, light, "point", "point_light_sample(inputs_0[0], p)", points)
    distance_squared = np.sum((points - light.position) ** 2, axis=1)
    np.testing.assert_allclose(out[:, 0], 3.0 / distance_squared, rtol=RTOL)
    assert np.all(out[:, 1:] == [1.0, 1.0, 0.0]), "a point light is a delta at a finite distance, chosen with 1"


def test_spot_light_falls_off_linearly_in_angle_as_mitsuba(gpu_context):
    light = SpotLight((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), 2.0, cutoff_angle_degrees=30.0, beam_width_degrees=10.0)
    angles = np.radians(np.array([0.0, 5.0, 9.9, 10.1, 15.0, 20.0, 25.0, 29.9, 30.1, 60.0, 120.0]))
    points = np.column_stack([np.sin(angles), -np.cos(angles), np.zeros_like(angles)]) * 2.0
    out = kind_samples(gpu_context, light, "spot", "spot_light_sample(inputs_0[0], p)", points)
    # Mitsuba 3's spot: 1 within the beam, (cutoff - angle) / (cutoff - beam) to the cutoff, 0 beyond
    cutoff, beam = math.radians(30.0), math.radians(10.0)
    falloff = np.where(angles <= beam, 1.0, np.clip((cutoff - angles) / (cutoff - beam), 0.0, 1.0))
    # llvmpipe's f32 acos is good to ~5e-5 radians, which the falloff's slope 1 / (cutoff - beam) scales
    np.testing.assert_allclose(out[:, 0], 2.0 * falloff / 4.0, atol=2.0 / 4.0 * 5e-5 / (cutoff - beam))


def test_directional_light_is_a_distant_delta(gpu_context, rng):
    light = DirectionalLight((1.0, -2.0, 0.5), 4.0)
    out = kind_samples(
        gpu_context, light, "directional", "directional_light_sample(inputs_0[0], p)", rng.normal(size=(8, 3))
    )
    assert np.all(out == [4.0, 1.0, 1.0, 1.0])


SUN_KERNEL = """
//! include "lights/sun.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let sample = sun_sample(inputs_0[0], vec3<f32>(0.0), inputs_1[i].xy);
    // the reported density must be sun_pdf's for that direction
    let consistent = sample.pdf == sun_pdf(inputs_0[0], sample.direction);
    return vec4<f32>(sample.direction, select(-sample.pdf, sample.pdf, consistent));
}
"""
SUN_SAMPLES = 100_000
# rings of equal solid angle and sectors around the sun's axis
SUN_RINGS, SUN_SECTORS = 8, 8


def test_sun_samples_its_cone_uniformly_with_the_pdf_it_reports(gpu_context, rng, failure_dir):
    # a wide sun, so that f32 directions resolve its cells finely
    sun = Sun((0.0, -1.0, 0.0), 2.0, angular_diameter_degrees=20.0)
    out = run_kernel(
        gpu_context,
        SUN_KERNEL,
        [source_record(sun), rng.random((SUN_SAMPLES, 4), dtype=np.float32)],
        np.dtype((np.float32, 4)),
        SUN_SAMPLES,
        input_types=["LightSource", "vec4<f32>"],
        output_type="vec4<f32>",
    )
    cone = 1.0 - math.cos(math.radians(10.0))
    assert np.all(out[:, 3] > 0), "sun_sample's pdf differs from sun_pdf's"
    np.testing.assert_allclose(out[:, 3], 1.0 / (2.0 * math.pi * cone), rtol=RTOL)
    direction = out[:, :3].astype(np.float64)
    ring = np.minimum(((1.0 - direction[:, 1]) / cone * SUN_RINGS).astype(int), SUN_RINGS - 1)
    sector = ((np.arctan2(direction[:, 2], direction[:, 0]) / (2 * math.pi)) % 1.0 * SUN_SECTORS).astype(int)
    observed = np.bincount(ring * SUN_SECTORS + sector % SUN_SECTORS, minlength=SUN_RINGS * SUN_SECTORS)
    result = chi_square(observed, np.full(SUN_RINGS * SUN_SECTORS, SUN_SAMPLES / (SUN_RINGS * SUN_SECTORS)))
    if result.p_value < LEVEL:
        np.savetxt(failure_dir / "sun_cells.txt", observed)
    assert result.p_value >= LEVEL, f"chi-square {result.statistic:.1f} on {result.dof} dof"


def test_light_parameters_are_checked_where_set():
    light = SpotLight((0, 0, 0), (0, -1, 0), 1.0, cutoff_angle_degrees=20.0)
    with pytest.raises(LightError, match="beam_width_degrees 25 is wider than cutoff_angle_degrees 20"):
        light.beam_width_degrees = 25.0
    assert light.beam_width == 15.0 and light.version == 0, "a refused edit leaves the light as it was"
    with pytest.raises(LightError, match="PointLight 'bulb': intensity must be in"):
        PointLight((0, 0, 0), -1.0, name="bulb")
    with pytest.raises(LightError, match="direction must not be zero"):
        DirectionalLight((0, 0, 0), 1.0)
    with pytest.raises(LightError, match="intensity must be in"):
        PointLight((0, 0, 0), float("nan"))
    sun = Sun((0, -2, 0), 1.0)
    assert sun.direction == (0.0, -1.0, 0.0), "directions are normalised"
    sun.irradiance = 3.0
    assert sun.version == 1


# ---- the GPU side with a lights group: the harness binds the scene group and this file's lights group


def run_with_lights(context, scene: Scene, wgsl: str, inputs: np.ndarray, count: int) -> np.ndarray:
    """`wgsl`'s `compute(i) -> vec4<f32>` over `inputs` (vec4 rows, `inputs_0`) with `scene`'s
    records bound as the renderer binds them: its scene group and its lights group."""
    mirror = SceneMirror(scene, "bvh")
    features = mirror.light_features
    frame = FRAME.zeros(1)
    frame["light_count"], frame["light_weight_total"] = mirror.lights.count, mirror.lights.total_weight
    group, records = lights_group(features), GpuRecords(context)
    records.sync(mirror.arrays, {}, [group])
    scene_records = {
        "frame": frame,
        "triangles": mirror.triangles,
        "nodes": TrackedTexels(context, "nodes", mirror.nodes).resource,
        "materials": mirror.materials,
        "lights": mirror.lights.entries,
    }
    return run_kernel(
        context,
        wgsl,
        [inputs],
        np.dtype((np.float32, 4)),
        count,
        input_types=["vec4<f32>"],
        output_type="vec4<f32>",
        scene=scene_records,
        groups={group: records.bound_in(group.name)},
        variant=KernelVariant(SceneFeatures(lights=features)),
    )


def ground(material=None) -> Scene:
    """A diffuse square in the y = 0 plane, seen from above."""
    plane = make_plane((0, 0, 0), (0, 0, 0), (4, 4), material or Diffuse("ground", (0.5, 0.5, 0.5)))
    return Scene([plane], Camera(position=(0, 3, 0), forward=(0, -1, 0), up=(0, 0, 1)))


def sunny_map(rng) -> np.ndarray:
    """A small map: dim sky with a few bright texels, rows of different colour."""
    texels = rng.uniform(0.0, 0.2, (7, 12, 3)).astype(np.float32)
    texels[2, 3] = (40.0, 30.0, 20.0)
    texels[5, 10] = (0.0, 5.0, 9.0)
    return texels


ENVIRONMENT_KERNEL = """
//! include "lights/direct_light_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let d = inputs_0[i].xyz;
    return vec4<f32>(environment_radiance(d), environment_pdf(d));
}
"""


def test_environment_map_lookup_and_pdf_match_the_numpy_references(gpu_context, rng):
    scene = ground()
    scene.environment = Environment(texels=sunny_map(rng), intensity=2.5, rotation_degrees=37.0)
    directions = rng.normal(size=(4096, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    inputs = np.column_stack([directions, np.zeros(len(directions))]).astype(np.float32)
    out = run_with_lights(gpu_context, scene, ENVIRONMENT_KERNEL, inputs, len(inputs))
    reference = scene.environment
    expected = reference.lookup(inputs[:, :3])
    # f32 trigonometry (llvmpipe's atan2 and acos) places a direction to within ANGLE_TOLERANCE,
    # which the lookup's steepest change nearby turns into radiance
    tangents = np.cross(inputs[:, :3], rng.normal(size=(len(inputs), 3)))
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    others = np.cross(inputs[:, :3], tangents)
    nearby = [
        reference.lookup(inputs[:, :3] + ANGLE_TOLERANCE * step) for step in (tangents, -tangents, others, -others)
    ]
    slack = np.max([np.abs(value - expected) for value in nearby], axis=0)
    assert np.all(np.abs(out[:, :3] - expected) <= RTOL * expected + 1e-6 + slack)
    # directions within f32 rounding of a cell border may fall in the neighbouring cell
    agrees = np.isclose(out[:, 3], reference.pdf(inputs[:, :3]), rtol=RTOL)
    assert agrees.mean() > 0.998, f"{np.count_nonzero(~agrees)} of {len(agrees)} densities differ"


SAMPLE_KERNEL = """
//! include "lights/direct_light_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let light = sample_light(vec3<f32>(0.0, 1.0, 0.0), inputs_0[i].xy, inputs_0[i].zw);
    return vec4<f32>(light.direction, light.pdf);
}
"""
ENVIRONMENT_SAMPLES = 200_000


def test_environment_map_samples_follow_its_pdf(gpu_context, rng, failure_dir):
    scene = ground()  # no emitter: the environment is the only light
    environment = Environment(texels=sunny_map(rng), rotation_degrees=-75.0)
    scene.environment = environment
    uniforms = rng.random((ENVIRONMENT_SAMPLES, 4), dtype=np.float32)
    out = run_with_lights(gpu_context, scene, SAMPLE_KERNEL, uniforms, ENVIRONMENT_SAMPLES)
    directions = out[:, :3].astype(np.float64)
    agrees = np.isclose(out[:, 3], environment.pdf(directions), rtol=RTOL)
    assert agrees.mean() > 0.998, "the sampled directions' densities differ from the reference pdf"
    tables = environment.sampling_tables()
    row, column = cell_of_uv(environment.uv(directions), tables.cell_rows, tables.cell_columns)
    observed = np.bincount(row * tables.cell_columns + column, minlength=tables.cell_pdf.size)
    bounds = np.cos(np.pi * np.arange(tables.cell_rows + 1) / tables.cell_rows)
    solid_angle = np.repeat((bounds[:-1] - bounds[1:]) * 2 * np.pi / tables.cell_columns, tables.cell_columns)
    expected = tables.cell_pdf * solid_angle * ENVIRONMENT_SAMPLES
    result = chi_square(observed, expected)
    if result.p_value < LEVEL:
        np.savetxt(failure_dir / "environment_cells.txt", np.column_stack([observed, expected]))
    assert result.p_value >= LEVEL, f"chi-square {result.statistic:.1f} on {result.dof} dof"


CHOICE_KERNEL = """
//! include "lights/direct_light_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let light = sample_light(vec3<f32>(0.0, 1.0, 0.0), inputs_0[i].xy, inputs_0[i].zw);
    return vec4<f32>(light.radiance.x, light.radiance.y, light.radiance.z, light.pdf);
}
"""
CHOICE_SAMPLES = 100_000


def test_one_table_chooses_every_kind_by_power(gpu_context, rng, failure_dir):
    scene = ground()
    lamp = make_plane((0, 2, 0), (180, 0, 0), (0.5, 0.5), Emitter("lamp", (1.0, 0.0, 0.0), 4.0))
    scene.add(lamp)
    # each light a colour of its own, so the sample says which was chosen
    scene.add_light(PointLight((0, 1, 0.5), 3.0, color=(0.0, 1.0, 0.0)))
    scene.add_light(DirectionalLight((0, -1, 0), 0.5, color=(0.0, 0.0, 1.0)))
    scene.environment = Environment(radiance=(0.0, 0.0, 0.0))  # black: never in the table
    mirror = SceneMirror(scene, "bvh")
    out = run_with_lights(
        gpu_context, scene, CHOICE_KERNEL, rng.random((CHOICE_SAMPLES, 4), dtype=np.float32), CHOICE_SAMPLES
    )
    chosen = np.argmax(out[:, :3] > 0, axis=1)  # 0: lamp (red), 1: point (green), 2: directional (blue)
    triangle_weight = 2 * 0.125 * 0.2126 * 4.0  # two triangles of area 1/8, luminance of (4, 0, 0)
    radius = mirror.scene_radius()
    weights = np.array([triangle_weight, 2 * 0.7152 * 3.0, 0.0722 * 0.5 * radius**2 / 2])
    np.testing.assert_allclose(mirror.lights.total_weight, weights.sum(), rtol=1e-6)
    result = chi_square(np.bincount(chosen, minlength=3), weights / weights.sum() * CHOICE_SAMPLES)
    if result.p_value < LEVEL:
        np.savetxt(failure_dir / "light_choices.txt", np.bincount(chosen, minlength=3))
    assert result.p_value >= LEVEL, f"chi-square {result.statistic:.1f} on {result.dof} dof"
    # a delta light's density is its selection probability
    np.testing.assert_allclose(out[chosen == 1, 3], weights[1] / weights.sum(), rtol=1e-5)


# ---- rendered closed forms


def pixel_mean_within_bounds(image: np.ndarray, expected: float, level: float) -> None:
    """The mean over pixels (independent estimates of the same value) within z standard errors of
    `expected`, the standard error from the pixels' spread."""
    values = image.mean(axis=2).ravel().astype(np.float64)
    error = values.std(ddof=1) / math.sqrt(len(values))
    assert abs(values.mean() - expected) <= z_limit(level) * error + 1e-6 * expected, (
        f"mean {values.mean():.5f} vs {expected:.5f} (standard error {error:.2g})"
    )


@pytest.mark.parametrize("integrator", ["bsdf", "nee", "mis"])
def test_white_furnace_under_a_constant_environment(gpu_context, integrator):
    albedo, radiance = 0.6, 1.5
    sphere = make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 3, Diffuse("ball", (albedo,) * 3))
    # close enough that the sphere fills the picture
    scene = Scene([sphere], Camera(position=(0, 0, -1.6), forward=(0, 0, 1), vfov_degrees=30.0))
    scene.environment = Environment(radiance=radiance)
    renderer = Renderer(scene, 12, 12, seed=SEED, max_depth=-1, integrator=integrator)
    renderer.render(32)
    pixel_mean_within_bounds(renderer.image(), albedo * radiance, sidak(LEVEL, 3))
    assert renderer.dropped_samples == 0


@pytest.mark.parametrize("integrator", ["bsdf", "mis"])
def test_plane_under_a_directional_light(gpu_context, integrator):
    albedo, irradiance, angle = 0.5, 3.0, math.radians(40.0)
    scene = ground(Diffuse("ground", (albedo,) * 3))
    scene.add_light(DirectionalLight((math.sin(angle), -math.cos(angle), 0.0), irradiance))
    renderer = Renderer(scene, 8, 8, seed=SEED, max_depth=2, integrator=integrator)
    renderer.render(2)
    # a delta light with no other light: every sample is exact
    np.testing.assert_allclose(renderer.image(), albedo * irradiance * math.cos(angle) / math.pi, rtol=1e-5)


def test_plane_under_a_point_light(gpu_context):
    albedo, intensity = 0.5, 2.0
    light = np.array([0.6, 1.5, 0.0])
    scene = ground(Diffuse("ground", (albedo,) * 3))
    scene.add_light(PointLight(light, intensity))
    # a narrow view of the origin: the radiance hardly varies over the picture
    scene.camera = Camera(position=(0, 2, -1), forward=(0, -2, 1), vfov_degrees=0.05)
    renderer = Renderer(scene, 8, 8, seed=SEED, max_depth=2)
    renderer.render(2)
    distance_squared = float(light @ light)
    expected = albedo * intensity * (light[1] / math.sqrt(distance_squared)) / (math.pi * distance_squared)
    np.testing.assert_allclose(renderer.image(), expected, rtol=2e-3)


# ---- degenerate lights and maps


@pytest.mark.parametrize(
    "lighting",
    ["zero point", "huge point", "black map", "1x1 map", "2x1 map", "zero sun", "hard spot"],
)
def test_degenerate_lights_give_no_non_finite_sample(gpu_context, lighting):
    scene = ground()
    scene.add(make_icosphere((0, 0.5, 0), (0, 0, 0), 0.4, 1, Diffuse("ball")))
    lights = {
        "zero point": lambda: scene.add_light(PointLight((0, 1, 0), 0.0)),
        "huge point": lambda: scene.add_light(PointLight((0, 1.2, 0), 1e19)),
        "zero sun": lambda: scene.add_light(Sun((0, -1, 0), 0.0)),
        "hard spot": lambda: scene.add_light(SpotLight((0, 2, 0), (0, -1, 0), 5.0, 30.0, 30.0)),
        "black map": lambda: setattr(scene, "environment", Environment(texels=np.zeros((4, 8, 3), np.float32))),
        "1x1 map": lambda: setattr(scene, "environment", Environment(texels=np.full((1, 1, 3), 2.0, np.float32))),
        "2x1 map": lambda: setattr(
            scene, "environment", Environment(texels=np.array([[[1.0, 2, 3]], [[0.0, 0, 0]]], np.float32))
        ),
    }
    lights[lighting]()
    for integrator in ("bsdf", "mis"):
        renderer = Renderer(scene, 8, 8, seed=SEED, integrator=integrator)
        renderer.render(2)
        assert renderer.nonfinite_samples == 0 and np.all(np.isfinite(renderer.image())), integrator


# ---- editing


def test_light_edits_upload_only_what_they_change(gpu_context, rng):
    scene = ground()
    point = PointLight((0, 1, 0), 1.0)
    scene.add_light(point, Sun((0.2, -1, 0.1), 2.0))
    scene.environment = Environment(texels=sunny_map(rng))
    renderer = Renderer(scene, 8, 8, seed=SEED)
    renderer.render(1)
    point.position = (0.1, 1.0, 0.0)  # same power: its record alone
    renderer.render(1)
    assert renderer.upload_stats == {"light sources": renderer.upload_stats["light sources"]}
    assert renderer.upload_stats["light sources"].bytes == LIGHT_SOURCE.size
    for edit in (lambda e: setattr(e, "rotation_degrees", 90.0), lambda e: setattr(e, "visible", False)):
        edit(scene.environment)
        renderer.render(1)
        assert set(renderer.upload_stats) == {"lighting"}, renderer.upload_stats
    scene.environment.intensity = 3.0  # its power moves: the light table too, never the map
    renderer.render(1)
    assert "lighting" in renderer.upload_stats and "environment map" not in renderer.upload_stats
    scene.environment.texels = sunny_map(rng)[::-1].copy()
    renderer.render(1)
    assert {"environment map", "environment tables"} <= set(renderer.upload_stats)
    scene.remove_light(point)
    renderer.render(1)
    assert renderer.kernel is tracing_kernel(renderer.context, renderer.variant)
    assert "PointLight" not in renderer.kernel.label
    scene.environment = None
    scene.remove_light(*scene.lights)
    renderer.render(1)
    assert "lights" not in renderer.bind_groups, "a scene without such lights binds no lights group"


def test_environment_maps_are_checked_against_the_adapter(gpu_context):
    def counts(width: int, height: int) -> SceneCounts:
        return SceneCounts(2, 1, 1, 0, environment=True, environment_map=(width, height))

    limits = gpu_context.device.limits
    words = environment_table_words(4096, 2048)
    if words * 4 <= limits["max-storage-buffer-binding-size"]:
        check_scene_counts(gpu_context, counts(4096, 2048))  # a 4k map fits lavapipe's 128 MiB binding
    widest = limits["max-texture-dimension-2d"]
    with pytest.raises(DeviceLimitError, match="texture 'environment map'.*max-texture-dimension-2d"):
        check_scene_counts(gpu_context, counts(widest + 1, 2))
    # the largest texture the adapter allows, whose tables (12 B a texel) outgrow the storage binding
    assert environment_table_words(widest, widest) * 4 > limits["max-storage-buffer-binding-size"]
    with pytest.raises(DeviceLimitError, match="buffer 'environment tables'"):
        check_scene_counts(gpu_context, counts(widest, widest))


def test_a_hidden_environment_still_lights(gpu_context):
    scene = ground(Diffuse("ground", (0.5, 0.5, 0.5)))
    scene.camera = Camera(position=(0, 1, -3), forward=(0, -0.2, 1))  # the horizon: sky above, ground below
    scene.environment = Environment(radiance=2.0, visible=False)
    renderer = Renderer(scene, 16, 16, seed=SEED, max_depth=2)
    renderer.render(4)
    image = renderer.image()
    assert np.all(image[0] == 0.0), "camera rays see black where the environment is hidden"
    assert np.all(image[-1] > 0.0), "the ground it lights is not black"


def test_the_viewer_renders_the_same_lights_band_by_band(gpu_context, rng):
    scene = ground()
    scene.add_light(SpotLight((0, 1, 0), (0.2, -1, 0), 3.0))
    scene.environment = Environment(texels=sunny_map(rng))
    renderer = Renderer(scene, 16, 16, seed=SEED)
    renderer.render(2)
    expected = renderer.image()
    renderer.restart()
    banded = BandedRenderer(renderer)
    banded.add_passes(2)
    np.testing.assert_array_equal(renderer.image(), expected)
