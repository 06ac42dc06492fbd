"""The light sampler: the alias table reproduces its weights, and the shipped WGSL sampler draws
triangles in proportion to power and points on them uniformly in area (triangles too small in
solid angle) or in solid angle (the rest, Arvo's spherical triangle sampling), with the density
pdf_light reports."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu.layout import MATERIAL, TRIANGLE
from wgputrace.render.lights import LUMINANCE_WEIGHTS, alias_table, light_table
from wgputrace.scene import Diffuse, Emitter
from wgputrace.testing.harness import frame_record, run_kernel
from wgputrace.testing.stats import chi_square, sidak

SEED = 11
SAMPLES = 200_000
# Family-wise significance of this file's chi-square tests; Sidak-split between them.
SIGNIFICANCE = 1e-3
CHI_SQUARE_TESTS = 1
# Subcells per light triangle: its three corner triangles and the middle one, each 1/4 of the area.
SUBCELLS = 4
# the direct light sampler's override SPHERICAL_SAMPLING_MIN_SOLID_ANGLE (its default)
SPHERICAL_SAMPLING_MIN_SOLID_ANGLE = 3e-4
# f32 solid angles of a few steradians down to 1e-3 carry a few ulps of rounding each
PDF_RTOL = 1e-4


def chi_square_limit(degrees_of_freedom: int, significance: float) -> float:
    """Upper quantile of the chi-square distribution (Wilson-Hilferty; within 1% for dof >= 10)."""
    from statistics import NormalDist

    z = NormalDist().inv_cdf(1 - significance)
    k = degrees_of_freedom
    return k * (1 - 2 / (9 * k) + z * np.sqrt(2 / (9 * k))) ** 3


@pytest.mark.parametrize("weights", [[1.0], [1, 1, 1, 1], [1e-4, 3.0, 0.5, 1e3, 0.0, 7.0, 2e-2]])
def test_alias_table_reproduces_its_distribution_exactly(weights):
    weights = np.asarray(weights, dtype=np.float64)
    threshold, alias = alias_table(weights)
    count = len(weights)
    # probability of i: its own column kept, plus every column whose alias is i when not kept
    implied = threshold.copy()
    np.add.at(implied, alias, 1.0 - threshold)
    np.testing.assert_allclose(implied / count, weights / weights.sum(), rtol=1e-12, atol=1e-15)


def test_alias_table_rejects_bad_weights():
    for weights in ([], [0.0, 0.0], [1.0, -1.0], [np.nan]):
        with pytest.raises(ValueError, match="alias table needs"):
            alias_table(np.asarray(weights))


def light_scene(rng):
    """Emissive triangles of areas over five decades and radiances over four, between
    non-emissive ones that must never be chosen."""
    scales = np.array([0.01, 0.1, 0.3, 1.0, 3.0, 0.03])
    radiance = np.array([[100, 50, 10], [1, 1, 1], [0.1, 0.5, 0.2], [2, 0, 0], [0, 0, 0.3], [30, 30, 30]])
    count = 2 * len(scales)
    triangles = TRIANGLE.zeros(count)
    corners = rng.normal(size=(count, 3, 3))
    corners[0::2] *= scales[:, None, None]
    triangles["v0"], triangles["v1"], triangles["v2"] = corners[:, 0], corners[:, 1], corners[:, 2]
    triangles["material"][0::2] = np.arange(len(scales))
    triangles["material"][1::2] = len(scales)  # a diffuse material
    materials = MATERIAL.zeros(len(scales) + 1)
    materials["kind"][: len(scales)] = Emitter.kind
    materials["color"][: len(scales)] = radiance
    materials["kind"][-1] = Diffuse.kind
    materials["color"][-1] = 0.5
    return triangles, materials


# Seen from this far away every triangle of light_scene subtends far less than
# SPHERICAL_SAMPLING_MIN_SOLID_ANGLE: points are sampled by area.
FAR_AWAY = (3e3, 0.0, 0.0)

SAMPLE_KERNEL = """
//! include "lights/direct_light_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let u = inputs_0[i];
    let p = inputs_1[0].xyz;
    let light = sample_light(p, u.xy, u.zw);
    // the reported density must be the one pdf_light gives for that light point
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    let cos_light = abs(dot(light.normal, to_light)) / sqrt(distance_squared);
    let triangle = scene_triangle(light.triangle);
    let consistent = light.pdf == pdf_light(p, light.triangle, triangle, distance_squared, cos_light);
    return vec4<f32>(light.position, bitcast<f32>(light.triangle | select(0x80000000u, 0u, consistent)));
}
"""


def sample_lights(gpu_context, triangles, materials, lights, uniforms, receiver) -> np.ndarray:
    """sample_light from `receiver` for each row of `uniforms`: (position xyz, triangle index with
    the top bit set where the reported pdf differs from pdf_light's)."""
    frame = frame_record()
    frame["light_count"], frame["light_weight_total"] = lights.count, lights.total_weight
    return run_kernel(
        gpu_context,
        SAMPLE_KERNEL,
        [uniforms, np.array([[*receiver, 0.0]], np.float32)],
        np.dtype((np.float32, 4)),
        len(uniforms),
        input_types=["vec4<f32>", "vec4<f32>"],
        output_type="vec4<f32>",
        scene={"frame": frame, "triangles": triangles, "materials": materials, "lights": lights.entries},
    )


def barycentric_coordinates(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(n, 3) barycentric coordinates of points (n, 3) in triangles (n, 3, 3), by least squares in the plane."""
    edges = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=2)  # (n, 3, 2)
    normal_matrix = np.einsum("nki,nkj->nij", edges, edges)
    offset = np.einsum("nki,nk->ni", edges, points - corners[:, 0])
    b12 = np.linalg.solve(normal_matrix, offset[..., None])[..., 0]
    return np.column_stack([1 - b12.sum(axis=1), b12])


def test_light_sampler_matches_power_and_area(gpu_context, failure_dir):
    rng = np.random.default_rng(SEED)
    triangles, materials = light_scene(rng)
    lights = light_table(triangles, materials)
    uniforms = rng.random((SAMPLES, 4), dtype=np.float32)
    out = sample_lights(gpu_context, triangles, materials, lights, uniforms, FAR_AWAY)
    chosen = out[:, 3].view(np.uint32)
    assert np.all(chosen & 0x80000000 == 0), "sample_light's pdf differs from pdf_light's"
    assert np.all(materials["kind"][triangles["material"][chosen]] == Emitter.kind)

    # the sampled point lies on the chosen triangle: barycentric coordinates in [0, 1]
    corners = np.stack([triangles[c][chosen] for c in ("v0", "v1", "v2")], axis=1).astype(np.float64)
    barycentric = barycentric_coordinates(out[:, :3].astype(np.float64), corners)
    assert barycentric.min() > -1e-4 and barycentric.max() < 1 + 1e-4

    # chi-square over (triangle, quarter of the triangle) cells
    quarter = np.where(barycentric.max(axis=1) > 0.5, barycentric.argmax(axis=1), 3)
    slot = np.searchsorted(np.sort(lights.entries["triangle"]), chosen)
    observed = np.bincount(slot * SUBCELLS + quarter, minlength=lights.count * SUBCELLS)
    corners_all = np.stack([triangles[c] for c in ("v0", "v1", "v2")], axis=1).astype(np.float64)
    area = 0.5 * np.linalg.norm(
        np.cross(corners_all[:, 1] - corners_all[:, 0], corners_all[:, 2] - corners_all[:, 0]), axis=1
    )
    weight = area * (materials["color"][triangles["material"]] @ LUMINANCE_WEIGHTS)
    light_triangles = np.sort(lights.entries["triangle"])
    expected = np.repeat(weight[light_triangles] / weight[light_triangles].sum() * SAMPLES / SUBCELLS, SUBCELLS)
    pooled = expected >= 5  # cells expected to be nearly empty are pooled into one
    observed_cells = np.append(observed[pooled], observed[~pooled].sum())
    expected_cells = np.append(expected[pooled], expected[~pooled].sum())
    if expected_cells[-1] < 5:
        observed_cells, expected_cells = observed_cells[:-1], expected_cells[:-1]
    statistic = float(np.sum((observed_cells - expected_cells) ** 2 / expected_cells))
    limit = chi_square_limit(len(expected_cells) - 1, 1 - (1 - SIGNIFICANCE) ** (1 / CHI_SQUARE_TESTS))
    if statistic > limit:
        np.savetxt(failure_dir / "light_sampler_cells.txt", np.column_stack([observed_cells, expected_cells]))
    assert statistic < limit, f"chi-square {statistic:.1f} > {limit:.1f} over {len(expected_cells)} cells"


SPHERICAL_SAMPLES = 100_000
# Cells per side of the barycentric grid over the light triangle: SPHERICAL_GRID^2 cells.
SPHERICAL_GRID = 8
# Receiving points around the triangle of spherical_case: right above it (a large solid angle), just
# above its plane beside it (the ceiling beside the Cornell box's lamp: grazing, the case area
# sampling serves worst), behind it (its back side), and far enough that its solid angle is a few
# times SPHERICAL_SAMPLING_MIN_SOLID_ANGLE (where f32 precision is least).
RECEIVERS = {"above": (0.3, 0.4, 0.2), "beside": (1.2, 0.05, 0.3), "behind": (0.2, -0.3, 0.5), "far": (0.3, 20.0, 0.3)}
SPHERICAL_KERNEL = """
//! include "lights/direct_light_sampler.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let p = inputs_1[0].xyz;
    let light = sample_light(p, inputs_0[i].xy, inputs_0[i].zw);
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    let cos_light = abs(dot(light.normal, to_light)) / sqrt(distance_squared);
    let triangle = scene_triangle(light.triangle);
    let consistent = light.pdf == pdf_light(p, light.triangle, triangle, distance_squared, cos_light);
    return vec4<f32>(light.position, select(-light.pdf, light.pdf, consistent));
}
"""


def spherical_case():
    """One emissive triangle in the y = 0 plane (normal +y)."""
    triangles = TRIANGLE.zeros(1)
    triangles["v0"], triangles["v1"], triangles["v2"] = (0, 0, 0), (0, 0, 1), (1, 0, 0)
    materials = MATERIAL.zeros(1)
    materials["kind"], materials["color"] = Emitter.kind, (2.0, 1.0, 0.5)
    return triangles, materials


def solid_angle(p: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Float64 solid angle of triangles (..., 3, 3) seen from p (Van Oosterom and Strackee)."""
    a, b, c = (corners[..., k, :] - p for k in range(3))
    la, lb, lc = (np.linalg.norm(v, axis=-1) for v in (a, b, c))
    triple = np.abs(np.sum(a * np.cross(b, c), axis=-1))
    dots = la * lb * lc + np.sum(a * b, axis=-1) * lc + np.sum(a * c, axis=-1) * lb + np.sum(b * c, axis=-1) * la
    return 2.0 * np.arctan2(triple, dots)


def grid_cells(corners: np.ndarray, n: int) -> np.ndarray:
    """The n^2 sub-triangles of a barycentric grid over the triangle `corners` (3, 3): (n^2, 3, 3),
    ordered as grid_cell_index numbers them."""
    cells = []
    for i in range(n):
        for j in range(n - i):
            up = [(i, j), (i + 1, j), (i, j + 1)]
            down = [(i + 1, j), (i + 1, j + 1), (i, j + 1)] if i + j < n - 1 else None
            for cell in (up, down):
                if cell is not None:
                    cells.append(
                        [
                            corners[0] + (b1 * (corners[1] - corners[0]) + b2 * (corners[2] - corners[0])) / n
                            for b1, b2 in cell
                        ]
                    )
    return np.array(cells)


def grid_cell_index(barycentric: np.ndarray, n: int) -> np.ndarray:
    """Index into grid_cells of the cell holding each point, from barycentric coordinates (m, 3)."""
    scaled = np.clip(barycentric[:, 1:], 0.0, 1.0) * n
    i, j = (np.minimum(np.floor(scaled[:, k]), n - 1).astype(np.int64) for k in range(2))
    j = np.minimum(j, n - 1 - i)
    down = (scaled[:, 0] - i + scaled[:, 1] - j > 1.0) & (i + j < n - 1)
    # cells before row i: rows of n - r up cells and n - r - 1 down cells
    row_start = np.array([sum(2 * (n - r) - 1 for r in range(row)) for row in range(n)])
    return row_start[i] + 2 * j + down


@pytest.mark.parametrize("receiver", list(RECEIVERS))
def test_spherical_light_sampling_is_uniform_in_solid_angle(gpu_context, failure_dir, receiver):
    rng = np.random.default_rng(SEED)
    triangles, materials = spherical_case()
    lights = light_table(triangles, materials)
    p = np.asarray(RECEIVERS[receiver], np.float64)
    corners = np.stack([triangles[c][0] for c in ("v0", "v1", "v2")]).astype(np.float64)
    total = float(solid_angle(p, corners))
    assert total > 2 * SPHERICAL_SAMPLING_MIN_SOLID_ANGLE, f"{receiver}: {total} sr would be sampled by area"
    uniforms = rng.random((SPHERICAL_SAMPLES, 4), dtype=np.float32)
    frame = frame_record()
    frame["light_count"], frame["light_weight_total"] = lights.count, lights.total_weight
    out = run_kernel(
        gpu_context,
        SPHERICAL_KERNEL,
        [uniforms, np.array([[*p, 0.0]], np.float32)],
        np.dtype((np.float32, 4)),
        SPHERICAL_SAMPLES,
        input_types=["vec4<f32>", "vec4<f32>"],
        output_type="vec4<f32>",
        scene={"frame": frame, "triangles": triangles, "materials": materials, "lights": lights.entries},
    )
    assert np.all(out[:, 3] > 0), f"{receiver}: sample_light's pdf differs from pdf_light's"
    # one triangle: chosen with probability 1, so the density is 1 / solid angle
    np.testing.assert_allclose(out[:, 3], 1.0 / total, rtol=PDF_RTOL, err_msg=f"{receiver}: pdf is not 1 / solid angle")
    barycentric = barycentric_coordinates(out[:, :3].astype(np.float64), np.repeat(corners[None], len(out), axis=0))
    assert barycentric.min() > -1e-4 and barycentric.max() < 1 + 1e-4, f"{receiver}: points off the triangle"
    observed = np.bincount(grid_cell_index(barycentric, SPHERICAL_GRID), minlength=SPHERICAL_GRID**2)
    expected = solid_angle(p, grid_cells(corners, SPHERICAL_GRID)) / total * SPHERICAL_SAMPLES
    result = chi_square(observed, expected)
    level = sidak(SIGNIFICANCE, len(RECEIVERS))
    if result.p_value < level:
        np.savetxt(failure_dir / f"spherical_light_{receiver}_cells.txt", np.column_stack([observed, expected]))
    assert result.p_value >= level, (
        f"{receiver}: chi-square {result.statistic:.1f} on {result.dof} dof, p {result.p_value:.3g}"
    )
