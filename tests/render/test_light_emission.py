"""Light paths' first vertex (WGSL `sample_emission`) for every light kind, on the GPU against
theory: radiance x cos / (pdf_position x pdf_direction) estimates each light's emitted power in
closed form (z-tested, bounds from the sample variance); sampled directions follow the density
they report (chi-square); emission_pdf and emission_pdf_distant give back the sample's densities;
degenerate and powerless lights give no non-finite sample."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import (
    Camera,
    Diffuse,
    DirectionalLight,
    Emitter,
    Environment,
    PointLight,
    Principled,
    Renderer,
    Scene,
    Shape,
    SpotLight,
    Sun,
    Texture,
    make_plane,
)
from wgputrace.gpu.layout import FRAME, LIGHT, MATERIAL, TRIANGLE
from wgputrace.kernels.light_dispatch import (
    GENERATED_LIGHT_EMISSION,
    LIGHT_SOURCE_FLAG,
    LightFeatures,
    light_emission_dispatch,
)
from wgputrace.kernels.variant import KernelVariant
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.testing.harness import run_kernel
from wgputrace.testing.stats import chi_square, sidak, z_limit

pytestmark = pytest.mark.gpu

SEED = 18
SAMPLES = 400_000
# Family-wise significance of this file's statistical tests, Sidak-split between them: the power
# of each group of lights and channel (8 groups in two scenes, 3 channels), one chi-square per
# direction distribution (4), and the share of a two-sided lamp's paths leaving its back (1).
SIGNIFICANCE = 1e-3
POWER_TESTS = 8 * 3
CHI_SQUARE_TESTS = 4
LEVEL = sidak(SIGNIFICANCE, POWER_TESTS + CHI_SQUARE_TESTS + 1)
# f32 densities against each other: a few ulps through normalisation and trigonometry
PDF_RTOL = 1e-4
# f32 sums of the estimator against float64 closed forms, where a light's estimate has no variance
POWER_RTOL = 1e-5
# direction bins of the chi-square tests: bands of the cosine to the axis, sectors around it
BANDS, SECTORS = 16, 12

EMISSION_KERNEL = """
//! include "lights/light_path_sampler.wgsl"
struct EmissionRow {
    position: vec4<f32>,
    direction: vec4<f32>,
    radiance: vec4<f32>,
    flags: vec4<f32>,
    pdfs: vec4<f32>,
}
fn compute(i: u32) -> EmissionRow {
    let s = sample_emission(inputs_0[i].xy, inputs_0[i].zw, inputs_1[i].xy);
    let again = emission_pdf(s.triangle, s.direction);
    let distant = emission_pdf_distant(s.direction);
    let flags = vec3<f32>(select(0.0, 1.0, s.delta_position), select(0.0, 1.0, s.delta_direction), select(0.0, 1.0, s.distant));
    return EmissionRow(
        vec4<f32>(s.position, s.pdf_position),
        vec4<f32>(s.direction, s.pdf_direction),
        vec4<f32>(s.radiance, dot(s.normal, s.direction)),
        vec4<f32>(bitcast<f32>(s.triangle), flags),
        vec4<f32>(again.position, again.direction, distant.position, distant.direction),
    );
}
"""
ROW = np.dtype(
    [
        ("position", "<f4", 3),
        ("pdf_position", "<f4"),
        ("direction", "<f4", 3),
        ("pdf_direction", "<f4"),
        ("radiance", "<f4", 3),
        ("cos", "<f4"),
        ("word", "<u4"),
        ("delta_position", "<f4"),
        ("delta_direction", "<f4"),
        ("distant", "<f4"),
        ("pdf_again", "<f4", 2),
        ("pdf_distant", "<f4", 2),
    ]
)


def emission_samples(context, scene: Scene, count: int, rng) -> np.ndarray:
    """`count` light path starts (ROW records) drawn by sample_emission with the records, bind
    groups and generated hooks a Renderer makes for `scene`."""
    renderer = Renderer(scene, 4, 4)
    features, resources = renderer.variant.scene, renderer.resources
    scene_group, *extras = features.groups()
    bound = {group: {binding.name: resources[binding.name] for binding in group.bindings} for group in extras}
    scene_bindings = {binding.name: resources[binding.name] for binding in scene_group.bindings}
    uniforms = rng.random((count, 8), dtype=np.float32)
    return run_kernel(
        context,
        EMISSION_KERNEL,
        [np.ascontiguousarray(uniforms[:, :4]), np.ascontiguousarray(uniforms[:, 4:])],
        ROW,
        count,
        input_types=["vec4<f32>", "vec4<f32>"],
        output_type="EmissionRow",
        scene=scene_bindings,
        groups=bound,
        variant=KernelVariant(features),
        generated={GENERATED_LIGHT_EMISSION: light_emission_dispatch(features.lights)},
    )


def power_estimates(rows: np.ndarray) -> np.ndarray:
    """(n, 3) float64: radiance x cos / (pdf_position x pdf_direction) per sample."""
    density = rows["pdf_position"].astype(np.float64) * rows["pdf_direction"]
    return rows["radiance"] * (rows["cos"] / density)[:, None]


def assert_power(estimates: np.ndarray, members: np.ndarray, expected, what: str) -> None:
    """The mean over every sample of the estimates of the samples in `members` (zero elsewhere)
    estimates the power of that group of lights: within the z bound of its standard error."""
    values = np.where(members[:, None], estimates, 0.0)
    mean = values.mean(axis=0)
    error = values.std(axis=0, ddof=1) / math.sqrt(len(values))
    expected = np.asarray(expected, np.float64)
    bound = z_limit(LEVEL) * error + POWER_RTOL * np.abs(expected)
    assert np.all(np.abs(mean - expected) <= bound), f"{what}: power {mean}, expected {expected} (bound {bound})"


def spot_power(light: SpotLight) -> np.ndarray:
    """The spot's intensity integrated over the sphere: full to the beam width, falling linearly in
    angle to the cutoff: 2 pi I (1 - (sin cutoff - sin beam) / (cutoff - beam))."""
    outer, inner = math.radians(light.cutoff_angle_degrees), math.radians(light.beam_width)
    fraction = 1.0 - (math.sin(outer) - math.sin(inner)) / (outer - inner)
    return 2.0 * math.pi * light.intensity * np.asarray(light.color) * fraction


def sun_cone_solid_angle(sun: Sun) -> float:
    half = math.radians(sun.angular_diameter_degrees) / 2.0
    return 2.0 * math.pi * 2.0 * math.sin(half / 2.0) ** 2


def is_source(rows: np.ndarray) -> np.ndarray:
    return rows["word"] >= LIGHT_SOURCE_FLAG


def source_words(rows: np.ndarray, index: int) -> np.ndarray:
    return rows["word"] == (LIGHT_SOURCE_FLAG | index)


# ---- every kind in one scene: an emitting quad, a point light at the centre of the scene's
# bounding sphere (the ground's and the lamp's box: y from 0 to 1), a spot, a directional light, a
# sun, a constant environment, and lights of no power that must never be chosen

LAMP = Emitter("lamp", (1.0, 0.6, 0.3), 3.0)
LAMP_SIZE = (0.5, 0.4)
POINT = PointLight((0.0, 0.5, 0.0), 2.0, color=(0.2, 1.0, 0.5))
SPOT = SpotLight((0.5, 1.5, 0.0), (0.2, -1.0, 0.1), 4.0, cutoff_angle_degrees=30.0, color=(1.0, 0.9, 0.8))
DIRECTIONAL = DirectionalLight((1.0, -2.0, 0.5), 0.7, color=(0.9, 1.0, 1.1))
SUN = Sun((-0.3, -1.0, 0.2), 2.0, angular_diameter_degrees=5.0, color=(1.0, 0.95, 0.9))
SKY = (0.05, 0.1, 0.2)


def every_kind() -> Scene:
    ground = make_plane((0, 0, 0), (0, 0, 0), (2, 2), Diffuse("ground", (0.5, 0.5, 0.5)))
    lamp = make_plane((0, 1.0, 0), (math.pi, 0, 0), LAMP_SIZE, LAMP, name="lamp")  # facing down
    scene = Scene([ground, lamp], Camera(position=(0, 1, 3), forward=(0, 0, -1), up=(0, 1, 0)))
    for light in (POINT, SPOT, DIRECTIONAL, SUN, PointLight((0, 0.5, 0), 0.0), Sun((0, -1, 0), 0.0)):
        scene.add_light(light)
    scene.environment = Environment(radiance=SKY)
    return scene


@pytest.fixture(scope="module")
def every_kind_samples(gpu_context):
    scene = every_kind()
    rows = emission_samples(gpu_context, scene, SAMPLES, np.random.default_rng(SEED))
    return scene, SceneMirror(scene, "bvh"), rows


def test_each_kind_emits_its_closed_form_power(every_kind_samples):
    scene, mirror, rows = every_kind_samples
    assert np.isfinite(power_estimates(rows)).all()
    estimates = power_estimates(rows)
    center, radius = mirror.scene_bounding_sphere()
    disc = math.pi * radius**2
    lamp_area = LAMP_SIZE[0] * LAMP_SIZE[1]
    # an emitter sends pi L per unit area from each of its two sides
    assert_power(estimates, ~is_source(rows), 2 * math.pi * lamp_area * np.asarray(LAMP.radiance), "lamp")
    assert_power(estimates, source_words(rows, 0), 4 * math.pi * POINT.intensity * np.asarray(POINT.color), "point")
    assert_power(estimates, source_words(rows, 1), spot_power(SPOT), "spot")
    # distant lights: what crosses the disc of the scene's radius facing each direction
    assert_power(
        estimates, source_words(rows, 2), disc * DIRECTIONAL.irradiance * np.asarray(DIRECTIONAL.color), "directional"
    )
    sky = 4 * math.pi * np.asarray(SKY) + sun_cone_solid_angle(SUN) * np.asarray(SUN.radiance)
    mixed = source_words(rows, 3) | (rows["word"] == 0xFFFFFFFF)
    assert_power(estimates, mixed, disc * sky, "environment and sun")
    # the powerless lights are never chosen
    assert not (source_words(rows, 4) | source_words(rows, 5)).any()


def test_samples_say_their_kind_and_start_where_their_light_is(every_kind_samples):
    scene, mirror, rows = every_kind_samples
    center, radius = mirror.scene_bounding_sphere()
    point, spot = source_words(rows, 0), source_words(rows, 1)
    np.testing.assert_allclose(rows["position"][point], np.broadcast_to(POINT.position, (point.sum(), 3)))
    np.testing.assert_allclose(rows["position"][spot], np.broadcast_to(SPOT.position, (spot.sum(), 3)), rtol=1e-6)
    assert (rows["delta_position"] == (point | spot)).all()
    directional = source_words(rows, 2)
    assert (rows["delta_direction"] == directional).all()
    distant = directional | source_words(rows, 3) | (rows["word"] == 0xFFFFFFFF)
    assert (rows["distant"] == distant).all()
    np.testing.assert_allclose(
        rows["direction"][directional], np.broadcast_to(DIRECTIONAL.direction, (directional.sum(), 3)), rtol=1e-6
    )
    # distant starts lie on the disc one radius behind the centre, facing their direction
    offset = rows["position"][distant] - center
    along = np.einsum("ij,ij->i", offset, rows["direction"][distant])
    np.testing.assert_allclose(along, -radius, rtol=1e-5)
    across = offset - along[:, None] * rows["direction"][distant]
    assert (np.linalg.norm(across, axis=1) <= radius * (1 + 1e-5)).all()
    # lamp points lie on the lamp, which faces down (its front) and emits from both sides
    lamp = ~is_source(rows)
    np.testing.assert_allclose(rows["position"][lamp][:, 1], 1.0, rtol=1e-6)
    assert (np.abs(rows["position"][lamp][:, [0, 2]]) <= np.array(LAMP_SIZE) / 2 + 1e-6).all()
    assert (rows["cos"][lamp] > 0).all()
    down = rows["direction"][lamp][:, 1] < 0
    assert abs(down.mean() - 0.5) <= z_limit(LEVEL) * 0.5 / math.sqrt(len(down)), "one side in two"


def test_emission_pdfs_give_back_the_sampled_densities(every_kind_samples):
    scene, mirror, rows = every_kind_samples
    delta_direction = rows["delta_direction"] > 0
    checked = rows[~delta_direction]
    np.testing.assert_allclose(checked["pdf_again"][:, 0], checked["pdf_position"], rtol=PDF_RTOL)
    # a spot's direction on its cone's very edge may round outside it (density 0, falloff 0 there)
    agrees = np.isclose(checked["pdf_again"][:, 1], checked["pdf_direction"], rtol=PDF_RTOL)
    assert agrees.mean() > 1 - 1e-4, f"{np.count_nonzero(~agrees)} direction densities differ"
    distant = checked[checked["distant"] > 0]
    np.testing.assert_allclose(distant["pdf_distant"][:, 0], distant["pdf_position"], rtol=PDF_RTOL)
    np.testing.assert_allclose(distant["pdf_distant"][:, 1], distant["pdf_direction"], rtol=PDF_RTOL)
    # a lamp point's density: the lamp's share of the table's weight over its area
    lamp = ~is_source(rows)
    lamp_weight = LAMP_SIZE[0] * LAMP_SIZE[1] * float(np.asarray(LAMP.radiance) @ [0.2126, 0.7152, 0.0722])
    expected = lamp_weight / mirror.lights.total_weight / (LAMP_SIZE[0] * LAMP_SIZE[1])
    np.testing.assert_allclose(rows["pdf_position"][lamp], expected, rtol=PDF_RTOL)
    # point and spot: their selection probability alone
    for index in (0, 1):
        words = source_words(rows, index)
        np.testing.assert_allclose(rows["pdf_position"][words], mirror.lights.source_probability[index], rtol=PDF_RTOL)


def axis_bins(directions: np.ndarray, axis) -> tuple[np.ndarray, np.ndarray]:
    """Each direction's cosine to `axis` and its angle around it in [0, 2 pi)."""
    axis = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    tangent = np.cross(axis, helper)
    tangent /= np.linalg.norm(tangent)
    bitangent = np.cross(axis, tangent)
    d = directions.astype(np.float64)
    return d @ axis, np.arctan2(d @ bitangent, d @ tangent) % (2 * np.pi)


def assert_directions_follow(directions: np.ndarray, axis, cdf, low: float, failure_dir, name: str) -> None:
    """Chi-square of directions, rotationally symmetric about `axis`, whose cosine to it has the
    distribution function `cdf` on [low, 1], in BANDS bands of the cosine x SECTORS around."""
    cosine, angle = axis_bins(directions, axis)
    edges = np.linspace(low, 1.0, BANDS + 1)
    band = np.clip(np.searchsorted(edges, cosine, side="right") - 1, 0, BANDS - 1)
    sector = np.minimum((angle / (2 * np.pi) * SECTORS).astype(int), SECTORS - 1)
    observed = np.bincount(band * SECTORS + sector, minlength=BANDS * SECTORS)
    expected = np.repeat(np.diff(cdf(edges)), SECTORS) / SECTORS * len(directions)
    result = chi_square(observed, expected)
    if result.p_value < LEVEL:
        np.savetxt(failure_dir / f"emission_directions_{name}.txt", np.column_stack([observed, expected]))
    assert result.p_value >= LEVEL, f"{name}: chi-square {result.statistic:.1f} on {result.dof} dof"


def test_sampled_directions_follow_their_densities(every_kind_samples, failure_dir):
    scene, mirror, rows = every_kind_samples
    # the lamp's front faces down; two-sided, |cos| / 2 pi: the cosine's CDF (1 + sign(c) c^2) / 2
    lamp = rows[~is_source(rows)]
    assert_directions_follow(
        lamp["direction"], (0, -1, 0), lambda c: (1 + np.sign(c) * c**2) / 2, -1.0, failure_dir, "lamp"
    )
    point = rows[source_words(rows, 0)]
    assert_directions_follow(point["direction"], (0, 0, 1), lambda c: (c + 1) / 2, -1.0, failure_dir, "point")
    # the spot: uniform in its cutoff cone
    cos_cutoff = math.cos(math.radians(SPOT.cutoff_angle_degrees))
    spot = rows[source_words(rows, 1)]
    assert_directions_follow(
        spot["direction"],
        SPOT.direction,
        lambda c: (c - cos_cutoff) / (1 - cos_cutoff),
        cos_cutoff,
        failure_dir,
        "spot",
    )


# ---- emission through texture records (one-sided and two-sided) beside an environment map and a sun

CHECKER = Texture(np.kron([[0, 255], [255, 0]], np.ones((4, 4)))[..., None].repeat(3, axis=2).astype(np.uint8))
# decoded, the checker's texels are 0 and 1: over whole periods its bilinear lookup averages 1/2
CHECKER_MEAN = 0.5
GLOW = (2.0, 1.0, 0.5)
GLOW_STRENGTH = 1.5
PANEL_SIZE = 0.6


def glowing_panel(x: float, double_sided: bool) -> Shape:
    """A square panel at height 1 facing down (its front), the checker repeated twice across it."""
    material = Principled(
        f"glow {double_sided}",
        base_color=(0, 0, 0),
        metallic=1.0,
        emission=GLOW,
        emission_texture=CHECKER,
        emission_strength=GLOW_STRENGTH,
        double_sided=double_sided,
    )
    h = PANEL_SIZE / 2
    corners = np.array([(x - h, 1, -h), (x + h, 1, -h), (x + h, 1, h), (x - h, 1, h)], np.float32)
    faces = [(0, 1, 2), (0, 2, 3)]  # counter-clockwise seen from below
    uvs = np.array([(0, 0), (2, 0), (2, 2), (0, 2)], np.float32)
    return Shape(f"panel {double_sided}", corners[faces], material, uvs=uvs[faces])


def sky_map(rng) -> np.ndarray:
    texels = rng.uniform(0.0, 0.3, (6, 10, 3)).astype(np.float32)
    texels[1, 4] = (30.0, 20.0, 10.0)
    return texels


def map_integral(environment: Environment, rows: int = 600, columns: int = 1200) -> np.ndarray:
    """The environment's radiance integrated over the sphere (midpoint rule in theta and phi)."""
    theta = (np.arange(rows) + 0.5) * np.pi / rows
    phi = (np.arange(columns) + 0.5) * 2 * np.pi / columns
    t, p = np.meshgrid(theta, phi, indexing="ij")
    directions = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    weights = (np.sin(t) * (np.pi / rows) * (2 * np.pi / columns)).reshape(-1)
    return weights @ environment.lookup(directions)


def test_textured_emitters_and_an_environment_map_emit_their_power(gpu_context, failure_dir):
    rng = np.random.default_rng(SEED)
    ground = make_plane((0, 0, 0), (0, 0, 0), (3, 3), Diffuse("ground", (0.5, 0.5, 0.5)))
    scene = Scene(
        [ground, glowing_panel(-0.5, double_sided=False), glowing_panel(0.5, double_sided=True)],
        Camera(position=(0, 1, 3), forward=(0, 0, -1), up=(0, 1, 0)),
    )
    sun = Sun((0.2, -1.0, -0.4), 1.5, angular_diameter_degrees=3.0)
    scene.add_light(sun)
    scene.environment = Environment(texels=sky_map(rng), intensity=0.8, rotation_degrees=25.0)
    rows = emission_samples(gpu_context, scene, SAMPLES, rng)
    estimates = power_estimates(rows)
    assert np.isfinite(estimates).all()
    radius = SceneMirror(scene, "bvh").scene_bounding_sphere()[1]
    panel = PANEL_SIZE**2 * math.pi * CHECKER_MEAN * GLOW_STRENGTH * np.asarray(GLOW)
    triangles = ~is_source(rows)
    one_sided, two_sided = triangles & (rows["position"][:, 0] < 0), triangles & (rows["position"][:, 0] > 0)
    assert_power(estimates, one_sided, panel, "single-sided panel")
    assert_power(estimates, two_sided, 2 * panel, "double-sided panel")
    sky = map_integral(scene.environment) + sun_cone_solid_angle(sun) * np.asarray(sun.radiance)
    assert_power(estimates, is_source(rows), math.pi * radius**2 * sky, "environment map and sun")
    # the single-sided panel leaves its front (down) only, cosine-weighted: the cosine's CDF c^2
    assert (rows["direction"][one_sided][:, 1] < 0).all()
    assert_directions_follow(rows["direction"][one_sided], (0, -1, 0), lambda c: c**2, 0.0, failure_dir, "single-sided")
    checked = rows[is_source(rows)]
    np.testing.assert_allclose(checked["pdf_distant"][:, 0], checked["pdf_position"], rtol=PDF_RTOL)
    np.testing.assert_allclose(checked["pdf_distant"][:, 1], checked["pdf_direction"], rtol=PDF_RTOL)
    np.testing.assert_allclose(rows["pdf_again"][:, 1], rows["pdf_direction"], rtol=PDF_RTOL)


# ---- degenerate input: a zero-area light triangle, no light at all (the table's total weight 0)

DEGENERATE_KERNEL = """
//! include "lights/light_path_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let s = sample_emission(inputs_0[i].xy, inputs_0[i].zw, vec2<f32>(0.3, 0.7));
    let pdf = emission_pdf(s.triangle, s.direction);
    let finite = is_finite_vec3(s.position) && is_finite_vec3(s.direction) && is_finite_vec3(s.normal)
        && is_finite_f32(pdf.position) && is_finite_f32(pdf.direction) && is_finite_f32(s.pdf_position) && is_finite_f32(s.pdf_direction);
    return vec4<f32>(s.radiance, select(0.0, 1.0, finite));
}
"""


@pytest.mark.parametrize("light_count", [0, 2])
def test_degenerate_triangles_and_no_lights_give_finite_samples(gpu_context, rng, light_count):
    triangles = TRIANGLE.zeros(2)
    triangles["v0"], triangles["v1"], triangles["v2"] = (0, 0, 0), (1, 0, 0), (0, 0, 1)
    triangles["v1"][0] = triangles["v2"][0] = (0.5, 0.5, 0.5)  # the first: a point
    materials = MATERIAL.zeros(1)
    materials["kind"], materials["color"] = Emitter.kind, 1.0
    lights = LIGHT.zeros(2)
    lights["triangle"], lights["alias_index"], lights["threshold"] = [0, 1], [0, 1], 1.0
    frame = FRAME.zeros(1)
    frame["light_count"], frame["light_weight_total"] = light_count, float(light_count)
    out = run_kernel(
        gpu_context,
        '//! include "common/finite.wgsl"\n' + DEGENERATE_KERNEL,
        [rng.random((4096, 4), dtype=np.float32)],
        np.dtype((np.float32, 4)),
        4096,
        input_types=["vec4<f32>"],
        output_type="vec4<f32>",
        scene={"frame": frame, "triangles": triangles, "materials": materials, "lights": lights},
        generated={GENERATED_LIGHT_EMISSION: light_emission_dispatch()},
    )
    assert (out[:, 3] == 1.0).all(), "a sample or its densities are not finite"
    if light_count:
        chose_point = out[:, :3].sum(axis=1) == 0
        assert 0.4 < chose_point.mean() < 0.6, "the point triangle emits nothing, the other its radiance"


def test_the_generated_dispatch_holds_only_the_kinds_a_scene_has():
    points = light_emission_dispatch(LightFeatures((PointLight.kind,)))
    assert "point_emission_sample" in points and "sun_emission_sample" not in points
    assert "environment_emission_sample" not in points
    sky = light_emission_dispatch(LightFeatures((), "map"))
    assert "environment_emission_sample" in sky and "light_sources" not in sky
    assert "lighting" not in light_emission_dispatch(), "a scene lit by triangles alone binds no lights group"
