"""The light sampler: the alias table reproduces its weights, and the shipped WGSL sampler draws
triangles in proportion to power and points uniformly on them, with the density it reports."""

from __future__ import annotations

import numpy as np
import pytest

from tests.harness import frame_record, run_kernel
from wgputrace.gpu.layout import MATERIAL, TRIANGLE
from wgputrace.render.lights import LUMINANCE_WEIGHTS, alias_table, light_table
from wgputrace.scene import MaterialKind

SEED = 11
SAMPLES = 200_000
# Family-wise significance of this file's chi-square tests; Sidak-split between them.
SIGNIFICANCE = 1e-3
CHI_SQUARE_TESTS = 1
# Subcells per light triangle: its three corner triangles and the middle one, each 1/4 of the area.
SUBCELLS = 4


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
    materials["kind"][: len(scales)] = int(MaterialKind.EMITTER)
    materials["color"][: len(scales)] = radiance
    materials["kind"][-1] = int(MaterialKind.DIFFUSE)
    materials["color"][-1] = 0.5
    return triangles, materials


SAMPLE_KERNEL = """
//! include "light_sampling.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let u = inputs_0[i];
    let light = sample_light(u.xy, u.zw);
    // the reported density must be the one pdf_light_area gives for that light
    let consistent = light.pdf_area == pdf_light_area(materials[triangles[light.triangle].material].color);
    return vec4<f32>(light.position, bitcast<f32>(light.triangle | select(0x80000000u, 0u, consistent)));
}
"""


def test_light_sampler_matches_power_and_area(gpu_context, failure_dir):
    rng = np.random.default_rng(SEED)
    triangles, materials = light_scene(rng)
    lights = light_table(triangles, materials)
    frame = frame_record()
    frame["light_count"], frame["light_weight_total"] = lights.count, lights.total_weight
    uniforms = rng.random((SAMPLES, 4), dtype=np.float32)
    out = run_kernel(
        gpu_context,
        SAMPLE_KERNEL,
        [uniforms],
        np.dtype((np.float32, 4)),
        SAMPLES,
        input_types=["vec4<f32>"],
        output_type="vec4<f32>",
        scene={0: frame, 1: triangles, 3: materials, 6: lights.entries},
    )
    chosen = out[:, 3].view(np.uint32)
    assert np.all(chosen & 0x80000000 == 0), "sample_light's pdf differs from pdf_light_area"
    assert np.all(materials["kind"][triangles["material"][chosen]] == int(MaterialKind.EMITTER))

    # the sampled point lies on the chosen triangle: barycentric coordinates in [0, 1]
    corners = np.stack([triangles[c][chosen] for c in ("v0", "v1", "v2")], axis=1).astype(np.float64)
    edges = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=2)  # (n, 3, 2)
    normal_matrix = np.einsum("nki,nkj->nij", edges, edges)
    offset = np.einsum("nki,nk->ni", edges, out[:, :3] - corners[:, 0])
    b12 = np.linalg.solve(normal_matrix, offset[..., None])[..., 0]  # least squares in the plane
    barycentric = np.column_stack([1 - b12.sum(axis=1), b12])
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
