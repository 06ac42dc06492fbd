"""WGSL `normal_mapped` against a numpy oracle and hand-worked cases: the texel's tangent-space normal
(x and y scaled) in the frame of the shading normal and the Gram-Schmidt tangent, bitangent
cross(n, t) * w; the unmapped normal where the tangent or texel is degenerate, the mapped normal
would fall below the geometric surface or hide the viewer; never NaN."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.testing.harness import run_per_case
from wgputrace.testing.oracles import normalized

pytestmark = pytest.mark.gpu

SEED = 20_261_202
COUNT = 4096
ATOL = 1e-4
# cases this close to a decision (a side, a horizon, a degenerate length) may fall either way in f32
DECISION_MARGIN = 1e-3
# a case's fields, in normal_mapped's order
ARGUMENTS = ("shading", "tangent", "texel", "scale", "geometric", "towards_viewer")
Z, X = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])


def run(gpu_context, case: dict[str, np.ndarray]) -> np.ndarray:
    arguments = {name: case[name] for name in ARGUMENTS}
    body = f"return vec4<f32>(normal_mapped({', '.join(ARGUMENTS)}), 0.0);"
    return run_per_case(gpu_context, ["shading/normal_map.wgsl"], arguments, body)[:, :3].astype(np.float64)


def one_case(**fields) -> dict[str, np.ndarray]:
    defaults = {"shading": Z, "tangent": (*X, 1.0), "texel": (0.5, 0.5, 1.0), "scale": 1.0, "geometric": Z}
    case = {**defaults, "towards_viewer": Z, **fields}
    return {name: np.atleast_1d(np.asarray(value, np.float64))[None] for name, value in case.items()}


def cases(rng: np.random.Generator) -> dict[str, np.ndarray]:
    geometric = normalized(rng.normal(size=(COUNT, 3)))
    shading = normalized(geometric + 0.4 * rng.normal(size=(COUNT, 3)))
    tangent = np.concatenate([rng.normal(size=(COUNT, 3)), rng.choice([-1.0, 1.0], (COUNT, 1))], axis=1)
    case = {
        "shading": shading,
        "tangent": tangent,
        # mostly outward texels, as normal maps hold, some pointing below the surface
        "texel": np.concatenate([rng.random((COUNT, 2)), rng.uniform(0.3, 1.0, (COUNT, 1))], axis=1),
        "scale": rng.uniform(0.0, 2.0, COUNT),
        "geometric": geometric,
        "towards_viewer": normalized(geometric + 1.2 * rng.normal(size=(COUNT, 3))),
    }
    return {name: values.astype(np.float32).astype(np.float64) for name, values in case.items()}


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("nd,nd->n", a, b)


def oracle(case: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Expected normals, and which cases sit clear of every decision."""
    shading, tangent, geometric, viewer = case["shading"], case["tangent"], case["geometric"], case["towards_viewer"]
    t = tangent[:, :3] - shading * dot(shading, tangent[:, :3])[:, None]
    t_length = np.linalg.norm(t, axis=1)
    t = t / t_length[:, None]
    b = np.cross(shading, t) * np.where(tangent[:, 3] < 0, -1.0, 1.0)[:, None]
    m = case["texel"] * 2.0 - 1.0
    m[:, :2] *= case["scale"][:, None]
    n = m[:, :1] * t + m[:, 1:2] * b + m[:, 2:] * shading
    n_length = np.linalg.norm(n, axis=1)
    n = n / n_length[:, None]
    keep = (dot(n, geometric) > 0) & (dot(n, viewer) * dot(geometric, viewer) > 0)
    clear = np.minimum.reduce([t_length, n_length, np.abs(dot(n, geometric)), np.abs(dot(n, viewer))]) > DECISION_MARGIN
    return np.where(keep[:, None], n, shading), clear & (np.abs(dot(geometric, viewer)) > DECISION_MARGIN)


def test_normal_mapped_matches_the_oracle(gpu_context):
    case = cases(np.random.default_rng(SEED))
    result = run(gpu_context, case)
    assert np.isfinite(result).all()
    expected, clear = oracle(case)
    assert clear.mean() > 0.9  # the margin leaves most cases compared
    np.testing.assert_allclose(result[clear], expected[clear], atol=ATOL)
    # both outcomes are exercised: bent normals and fallbacks to the shading normal
    bent = np.linalg.norm(expected - case["shading"], axis=1) > 1e-3
    assert bent[clear].mean() > 0.5 and (~bent[clear]).any()


HAND_WORKED = [
    # the flat texel (0.5, 0.5, 1) leaves the shading normal as it is, at any scale
    ({"scale": 3.0}, Z),
    # +X of the texture tilts towards the tangent; scale 0 flattens it again
    ({"texel": (1.0, 0.5, 1.0)}, normalized(np.array([1.0, 0.0, 1.0]))),
    ({"texel": (1.0, 0.5, 1.0), "scale": 0.0}, Z),
    # +Y tilts towards the bitangent cross(z, x) = +y, or -y where w = -1
    ({"texel": (0.5, 1.0, 1.0)}, normalized(np.array([0.0, 1.0, 1.0]))),
    ({"texel": (0.5, 1.0, 1.0), "tangent": (1.0, 0.0, 0.0, -1.0)}, normalized(np.array([0.0, -1.0, 1.0]))),
    # a tangent with a component along the normal is made perpendicular first
    ({"texel": (1.0, 0.5, 1.0), "tangent": (1.0, 0.0, 5.0, 1.0)}, normalized(np.array([1.0, 0.0, 1.0]))),
    # degenerate tangents: zero, along the normal, NaN
    ({"texel": (1.0, 0.5, 1.0), "tangent": (0.0, 0.0, 0.0, 1.0)}, Z),
    ({"texel": (1.0, 0.5, 1.0), "tangent": (0.0, 0.0, 1.0, 1.0)}, Z),
    ({"texel": (1.0, 0.5, 1.0), "tangent": (np.nan, 0.0, 0.0, 1.0)}, Z),
    # a texel that encodes the zero vector
    ({"texel": (0.5, 0.5, 0.5)}, Z),
    # a texel pointing below the surface, and one that hides a grazing viewer
    ({"texel": (1.0, 0.5, 0.0)}, Z),
    ({"texel": (0.0, 0.5, 0.75), "towards_viewer": normalized(np.array([1.0, 0.0, 0.05]))}, Z),
]


def test_hand_worked_cases(gpu_context):
    """All in one dispatch; each row against its expected normal."""
    rows = [one_case(**fields) for fields, _ in HAND_WORKED]
    result = run(gpu_context, {name: np.concatenate([row[name] for row in rows]) for name in rows[0]})
    np.testing.assert_allclose(result, np.array([expected for _, expected in HAND_WORKED]), atol=1e-6)
