"""WGSL `shading_normal` against a numpy oracle: the interpolated, normalised corner normal turned to
the geometric side, the geometric normal where a triangle is flat, the interpolation cancels or the
viewer is between the two horizons; the weight 0 where geometric and shading normals disagree on
reflection against transmission, else Chiang et al. 2019's shadowing term, never above 1."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu.buffers import storage_buffer
from wgputrace.gpu.layout import VERTEX_NORMAL
from wgputrace.kernels.bind_groups import shading_group
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.render.shared_vertices import triangle_vertex_records, vertex_records
from wgputrace.testing.harness import run_per_case
from wgputrace.testing.oracles import normalized

pytestmark = pytest.mark.gpu

SEED = 20_261_201
COUNT = 4096
# float32 against float64 arithmetic: the barycentric solve loses up to its condition number's
# share of float32's precision on the random triangles' slivers (measured up to 3.3e-4)
ATOL = 1e-3
# cases this close to a decision (a side, a horizon) may fall either way in float32: not compared
DECISION_MARGIN = 1e-3
INCLUDES = ("generated/structs.wgsl", "generated/shading_normals.wgsl")
BODY = """
    let triangle = Triangle(corner0, 0u, corner1, corner2);
    let geometric = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
    let shading = shading_normal(i, triangle, p, geometric, towards_viewer);
    return vec4<f32>(shading, shading_weight(shading, geometric, towards_viewer, direction));
"""


def cases(rng: np.random.Generator) -> dict[str, np.ndarray]:
    corners = rng.normal(size=(COUNT, 3, 3))
    geometric = normalized(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]))
    # corner normals near the geometric one, some flipped against it, some of triangles shaded flat
    normals = normalized(geometric[:, None, :] + 0.6 * rng.normal(size=(COUNT, 3, 3)))
    normals *= np.where(rng.random(COUNT) < 0.1, -1.0, 1.0)[:, None, None]
    normals[rng.random(COUNT) < 0.1] = 0.0
    # corner normals that cancel at the centroid (the records need not be unit length)
    cancelling = rng.random(COUNT) < 0.05
    normals[cancelling] = [[0, 0, 1], [0, 1, 0], [0, -1, -1]]
    weights = rng.dirichlet((1.0, 1.0, 1.0), COUNT)
    weights[cancelling] = 1.0 / 3.0
    p = np.einsum("nk,nkd->nd", weights, corners)
    case = {
        "corners": corners,
        "normals": normals,
        "p": p,
        "towards_viewer": normalized(rng.normal(size=(COUNT, 3))),
        "direction": normalized(rng.normal(size=(COUNT, 3))),
    }
    # the oracle works on the float32 values the shader reads
    return {name: values.astype(np.float32).astype(np.float64) for name, values in case.items()}


def oracle(case: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Expected shading normals and weights, and which cases sit clear of every decision."""
    v0, v1, v2 = (case["corners"][:, k] for k in range(3))
    geometric = normalized(np.cross(v1 - v0, v2 - v0))
    e1, e2, d = v1 - v0, v2 - v0, case["p"] - v0
    d11, d12, d22 = (np.einsum("nd,nd->n", a, b) for a, b in ((e1, e1), (e1, e2), (e2, e2)))
    d1, d2 = np.einsum("nd,nd->n", d, e1), np.einsum("nd,nd->n", d, e2)
    det = d11 * d22 - d12 * d12
    b1 = np.clip((d22 * d1 - d12 * d2) / det, 0.0, 1.0)
    b2 = np.clip((d11 * d2 - d12 * d1) / det, 0.0, 1.0 - b1)
    normals = case["normals"]
    n = (1 - b1 - b2)[:, None] * normals[:, 0] + b1[:, None] * normals[:, 1] + b2[:, None] * normals[:, 2]
    length = np.linalg.norm(n, axis=1)
    n = n / np.maximum(length, 1e-30)[:, None]
    n *= np.where(np.einsum("nd,nd->n", n, geometric) < 0, -1.0, 1.0)[:, None]
    viewer = case["towards_viewer"]
    view_s, view_g = np.einsum("nd,nd->n", n, viewer), np.einsum("nd,nd->n", geometric, viewer)
    flat = ~normals[:, 0].any(axis=1) | (length <= 1e-6) | (view_s * view_g <= 0)
    shading = np.where(flat[:, None], geometric, n)
    direction = case["direction"]
    s_i, s_o = np.einsum("nd,nd->n", shading, viewer), np.einsum("nd,nd->n", shading, direction)
    g_o = np.einsum("nd,nd->n", geometric, direction)
    agree = (view_g * g_o > 0) == (s_i * s_o > 0)
    g = np.minimum(1.0, np.abs(g_o) / np.maximum(np.abs(s_o) * np.einsum("nd,nd->n", shading, geometric), 1e-6))
    weight = np.where(agree, g * (1 + g - g * g), 0.0)
    clear = (np.minimum.reduce([np.abs(view_s), np.abs(view_g), np.abs(s_o), np.abs(g_o)]) > DECISION_MARGIN) & (
        (length > 1e-3) | ~normals[:, 0].any(axis=1)
    )
    return shading, weight, clear


def test_shading_normal_and_weight_match_the_oracle(gpu_context):
    case = cases(np.random.default_rng(SEED))
    arguments = {f"corner{k}": case["corners"][:, k] for k in range(3)}
    arguments.update((name, case[name]) for name in ("p", "towards_viewer", "direction"))
    # every corner its own vertex
    vertices = triangle_vertex_records(np.arange(3 * COUNT).reshape(COUNT, 3))
    normals = vertex_records(VERTEX_NORMAL, case["normals"].reshape(3 * COUNT, 3))
    result = run_per_case(
        gpu_context,
        INCLUDES,
        arguments,
        BODY,
        groups={
            shading_group(smooth=True, textured=False): {
                "triangle_vertices": storage_buffer(gpu_context, "triangle vertices", vertices),
                "vertex_normals": storage_buffer(gpu_context, "vertex normals", normals),
            }
        },
        variant=KernelVariant(SceneFeatures(smooth=True)),
    )
    assert np.isfinite(result).all()
    assert (result[:, 3] >= 0).all() and (result[:, 3] <= 1 + ATOL).all()
    shading, weight, clear = oracle(case)
    assert clear.mean() > 0.8  # the margin leaves most cases compared
    np.testing.assert_allclose(result[clear, :3], shading[clear], atol=ATOL)
    np.testing.assert_allclose(result[clear, 3], weight[clear], atol=ATOL)
    # every kind of case is exercised: flat, dropped, shadowed and full weight
    assert (weight[clear] == 0).any() and ((weight[clear] > 0) & (weight[clear] < 0.99)).any()
    assert (weight[clear] > 0.999).any()
