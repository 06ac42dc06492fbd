"""Ray/triangle and ray/box intersection (WGSL `intersect_triangle`, `intersect_box`, `offset_ray_origin`)
against float64 numpy: random rays, shared edges and vertices, axis-parallel rays, degenerate
triangles, and rays leaving a surface."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Scene, Shape, make_box, make_icosphere
from wgputrace.gpu.layout import BVH_NODE
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.render.scene_mirror import scene_records
from wgputrace.render.scene_records import SceneRecords
from wgputrace.testing.harness import node_binding, run_kernel
from wgputrace.testing.oracles import (
    EDGE_MARGIN,
    FLOAT_MAX,
    UNIT_ROUNDOFF,
    as_vec4,
    ray_box,
    ray_triangle,
    record_corners,
    t_tolerance,
    triangle_normals,
    triangle_records,
    unit_vectors,
)

pytestmark = pytest.mark.gpu

RANDOM_PAIRS = 100_000
EDGE_RAYS = 4_000
# Box entry distances are three operations deep (subtract, multiply, max): 16 roundings is ample.
BOX_T_ROUNDINGS = 16
# intersect_box widens the exit distance by BOX_FAR_SCALE (4 roundings); a box grown by this
# relative amount must contain every near-miss the widening lets through.
BOX_GROWTH = 1e-5

TRIANGLE_KERNEL = """
//! include "generated/structs.wgsl"
//! include "geometry/intersect_triangle.wgsl"
fn compute(i: u32) -> f32 {
    let triangle = inputs_2[i];
    let sheared = shear_ray(Ray(inputs_0[i].xyz, inputs_1[i].xyz));
    return intersect_triangle(sheared, triangle.v0, triangle.v1, triangle.v2, FLOAT_MAX);
}
"""

BOX_KERNEL = """
//! include "generated/structs.wgsl"
//! include "geometry/intersect_box.wgsl"
fn compute(i: u32) -> f32 {
    let box = inputs_2[i];
    let inverse_direction = safe_inverse_direction(inputs_1[i].xyz);
    return intersect_box(inputs_0[i].xyz, inverse_direction, box.bounds_min, box.bounds_max, FLOAT_MAX);
}
"""

# Leaves triangle inputs_2[i] at inputs_0[i] towards inputs_1[i]: .xy from the point itself,
# .zw from the point moved off the surface by offset_ray_origin. Both skip the triangle left.
LEAVE_SURFACE_KERNEL = """
//! include "geometry/traverse_bvh.wgsl"
fn compute(i: u32) -> vec4<f32> {
    let k = inputs_2[i];
    let triangle = scene_triangle(k);
    let p = inputs_0[i].xyz;
    let direction = inputs_1[i].xyz;
    let normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
    let from_point = closest_hit(Ray(p, direction), FLOAT_MAX, k);
    let origin = offset_ray_origin(p, normal, direction, triangle.v0, triangle.v1, triangle.v2);
    let from_offset = closest_hit(Ray(origin, direction), FLOAT_MAX, k);
    return vec4<f32>(from_point.t, bitcast<f32>(from_point.triangle), from_offset.t, bitcast<f32>(from_offset.triangle));
}
"""


def no_nan(t: np.ndarray) -> np.ndarray:
    """GPU distances as float64 with FLOAT_MAX (miss) turned into inf, after checking for NaN."""
    assert not np.isnan(t).any(), f"{np.isnan(t).sum()} NaN distances, first at ray {np.flatnonzero(np.isnan(t))[0]}"
    t = t.astype(np.float64)
    return np.where(t == FLOAT_MAX, np.inf, t)


def intersect_pairs(context, origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """intersect_triangle for ray i against triangle i; inf on a miss."""
    t = run_kernel(
        context,
        TRIANGLE_KERNEL,
        [as_vec4(origins), as_vec4(directions), triangle_records(triangles)],
        np.float32,
        len(origins),
        input_types=["vec4<f32>", "vec4<f32>", "Triangle"],
        output_type="f32",
    )
    return no_nan(t)


def intersect_boxes(context, origins: np.ndarray, directions: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """intersect_box for ray i against box i; inf on a miss."""
    boxes = BVH_NODE.zeros(len(origins))
    boxes["bounds_min"], boxes["bounds_max"] = lo, hi
    t = run_kernel(
        context,
        BOX_KERNEL,
        [as_vec4(origins), as_vec4(directions), boxes],
        np.float32,
        len(origins),
        input_types=["vec4<f32>", "vec4<f32>", "BvhNode"],
        output_type="f32",
    )
    return no_nan(t)


def points_on(triangles: np.ndarray, barycentric: np.ndarray) -> np.ndarray:
    """Points b0 v0 + b1 v1 + b2 v2, computed in float32 like a shader would."""
    b = barycentric.astype(np.float32)[:, :, None]
    return (b * triangles.astype(np.float32)).sum(axis=1, dtype=np.float32)


def random_barycentric(rng: np.random.Generator, count: int) -> np.ndarray:
    """Uniform points of the triangle: Dirichlet(1, 1, 1)."""
    return rng.dirichlet(np.ones(3), size=count)


def aimed_at(targets: np.ndarray, directions: np.ndarray, distance: np.ndarray) -> np.ndarray:
    """float32 origins `distance` before `targets` along `directions`."""
    return (targets.astype(np.float64) - distance[:, None] * directions).astype(np.float32)


def check_against_reference(
    t_gpu: np.ndarray, origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray
) -> None:
    """Hit/miss as the float64 reference except within EDGE_MARGIN of an edge; t within t_tolerance."""
    reference = ray_triangle(origins, directions, triangles)
    decided = np.abs(reference.margin) >= EDGE_MARGIN
    hit_gpu, hit_reference = np.isfinite(t_gpu), np.isfinite(reference.t)
    wrong = np.flatnonzero(decided & (hit_gpu != hit_reference))
    assert wrong.size == 0, (
        f"{wrong.size} of {decided.sum()} rays disagree with the reference on hit/miss; first: ray {wrong[0]} "
        f"origin {origins[wrong[0]]} direction {directions[wrong[0]]} triangle {triangles[wrong[0]].tolist()} "
        f"gpu t {t_gpu[wrong[0]]} reference t {reference.t[wrong[0]]}"
    )
    both = np.flatnonzero(hit_gpu & hit_reference)
    error = np.abs(t_gpu[both] - reference.t[both])
    allowed = t_tolerance(reference.t[both], reference.cos[both], origins[both], triangles[both])
    worst = np.argmax(error / allowed)
    assert error[worst] <= allowed[worst], (
        f"ray {both[worst]}: t {t_gpu[both[worst]]} vs reference {reference.t[both[worst]]} "
        f"(error {error[worst]:.3g} > {allowed[worst]:.3g} at cos {reference.cos[both[worst]]:.3g})"
    )


def test_random_rays_match_reference(gpu_context, rng):
    triangles = rng.uniform(-1.0, 1.0, size=(RANDOM_PAIRS, 3, 3)).astype(np.float32)
    # Origins outside the unit cube aimed into it: about one ray in ten hits its triangle.
    origins = (3.0 * unit_vectors(rng, RANDOM_PAIRS)).astype(np.float32)
    directions = rng.uniform(-1.0, 1.0, size=(RANDOM_PAIRS, 3)) - origins
    directions = (directions / np.linalg.norm(directions, axis=1, keepdims=True)).astype(np.float32)
    t = intersect_pairs(gpu_context, origins, directions, triangles)
    assert np.isfinite(t).sum() > RANDOM_PAIRS // 20, "too few hits to test anything"
    check_against_reference(t, origins, directions, triangles)


def rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def shared_edge_rays(
    rng: np.random.Generator, a: np.ndarray, b: np.ndarray, axis: np.ndarray, min_cos: float
) -> tuple[np.ndarray, np.ndarray]:
    """EDGE_RAYS float32 rays through float32 points of segment a-b (a point if a == b), from both
    sides, at least `min_cos` away from grazing the surface whose normal is near `axis`."""
    s = rng.uniform(0.0, 1.0, size=(EDGE_RAYS, 1)).astype(np.float32)
    targets = (a.astype(np.float32) + s * (b.astype(np.float32) - a.astype(np.float32))).astype(np.float32)
    directions = unit_vectors(rng, 4 * EDGE_RAYS)
    directions = directions[np.abs(directions @ axis) >= min_cos][:EDGE_RAYS]
    origins = aimed_at(targets, directions, rng.uniform(0.5, 2.0, size=EDGE_RAYS))
    return origins, directions


def assert_no_leaks(context, origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray) -> None:
    """Every ray hits at least one of `triangles` (tested pairwise, ray by triangle)."""
    count = len(origins)
    t = intersect_pairs(
        context,
        np.tile(origins, (len(triangles), 1)),
        np.tile(directions, (len(triangles), 1)),
        np.repeat(triangles, count, axis=0),
    ).reshape(len(triangles), count)
    leaks = np.flatnonzero(~np.isfinite(t).any(axis=0))
    assert leaks.size == 0, (
        f"{leaks.size} of {count} rays through a shared edge or vertex hit none of its triangles; first: "
        f"origin {origins[leaks[0]].tolist()} direction {directions[leaks[0]].tolist()}"
    )


def test_shared_edge_of_quad_never_leaks(gpu_context, rng):
    # A quad folded slightly along its diagonal (a-b), turned and moved off the axes so that no
    # coordinate is round; rays through float32 points of the diagonal.
    corners = np.array([[-1.0, -0.7, 0.0], [1.2, 0.9, 0.0], [0.9, -1.1, 0.05], [-0.8, 1.0, 0.05]])
    corners = corners @ rotation(rng).T + np.array([0.3, -0.2, 0.7])
    a, b, c, d = corners.astype(np.float32)
    triangles = np.array([[a, b, c], [b, a, d]], np.float32)
    # exclude the ends: there the quad's outer boundary, not the shared edge, is what rays graze
    a_inner, b_inner = (a + 0.01 * (b - a)).astype(np.float32), (b - 0.01 * (b - a)).astype(np.float32)
    axis = triangle_normals(triangles)[0]
    origins, directions = shared_edge_rays(rng, a_inner, b_inner, axis, min_cos=0.1)
    assert_no_leaks(gpu_context, origins, directions, triangles)


def test_shared_vertex_of_fan_never_leaks(gpu_context, rng):
    # Seven triangles around an apex raised 0.2 over a jittered ring of radius 1 (a flat pyramid;
    # chords stay >= 0.75 from the centre, so no face is steeper than 15 degrees): seen from
    # directions within 60 degrees of its axis the fan covers the apex from both sides.
    fan_size = 7
    angles = (np.arange(fan_size) + rng.uniform(-0.3, 0.3, fan_size)) * (2.0 * np.pi / fan_size)
    ring = np.stack([np.cos(angles), np.sin(angles), np.zeros(fan_size)], axis=1)
    turn = rotation(rng)
    ring = ring @ turn.T + np.array([0.1, 0.4, -0.3])
    apex = np.array([0.0, 0.0, 0.2]) @ turn.T + np.array([0.1, 0.4, -0.3])
    triangles = np.array([[apex, ring[k], ring[(k + 1) % fan_size]] for k in range(fan_size)], np.float32)
    apex32 = triangles[0, 0]
    origins, directions = shared_edge_rays(rng, apex32, apex32, turn[:, 2], min_cos=0.5)
    assert_no_leaks(gpu_context, origins, directions, triangles)


def axis_parallel_directions(rng: np.random.Generator, count: int) -> np.ndarray:
    """Directions with one or two zero components (the six axes among them), float32."""
    axes = np.concatenate([np.eye(3), -np.eye(3)]).astype(np.float32)
    v = rng.normal(size=(count, 3))
    zeros = rng.integers(1, 3, size=count)  # how many components to zero
    for row, n in enumerate(zeros):
        v[row, rng.choice(3, size=n, replace=False)] = 0.0
    v = (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)
    v[: len(axes)] = axes
    return v


def test_axis_parallel_rays_against_triangles(gpu_context, rng):
    count = 20_000
    directions = axis_parallel_directions(rng, count)
    triangles = rng.uniform(-1.0, 1.0, size=(count, 3, 3)).astype(np.float32)
    # A quarter of the triangles lie in an axis plane, like walls and floors.
    flat = rng.random(count) < 0.25
    flat_axis = rng.integers(0, 3, size=count)
    triangles[flat, :, flat_axis[flat]] = triangles[flat, :1, flat_axis[flat]]
    # Aim half the rays at a point of their triangle, the rest at random points near it.
    targets = np.where(
        (rng.random(count) < 0.5)[:, None],
        points_on(triangles, random_barycentric(rng, count)),
        rng.uniform(-1.0, 1.0, size=(count, 3)),
    )
    origins = aimed_at(targets, directions, rng.uniform(0.5, 3.0, size=count))
    t = intersect_pairs(gpu_context, origins, directions, triangles)
    assert np.isfinite(t).sum() > count // 5, "too few hits to test anything"
    check_against_reference(t, origins, directions, triangles)


def test_axis_parallel_rays_against_boxes(gpu_context, rng):
    count = 20_000
    directions = axis_parallel_directions(rng, count)
    corners = rng.uniform(-1.0, 1.0, size=(count, 2, 3)).astype(np.float32)
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    origins = rng.uniform(-2.0, 2.0, size=(count, 3)).astype(np.float32)
    # Put a coordinate of half the origins exactly on a slab plane, preferably of a zero direction
    # component: those rays run along a face of the box (the reference counts the face as the box).
    rows = np.flatnonzero(rng.random(count) < 0.5)
    zero_axis = np.argmin(np.abs(directions[rows]) + rng.random((len(rows), 3)) * 0.5, axis=1)
    plane = np.where(rng.random(len(rows)) < 0.5, lo[rows, zero_axis], hi[rows, zero_axis])
    origins[rows, zero_axis] = plane
    t = intersect_boxes(gpu_context, origins, directions, lo, hi)

    reference = ray_box(origins, directions, lo, hi)
    hit_reference = np.isfinite(reference)
    size = np.max(hi - lo, axis=1, keepdims=True) + np.max(np.abs(origins), axis=1, keepdims=True)
    near_miss = np.isfinite(ray_box(origins, directions, lo - BOX_GROWTH * size, hi + BOX_GROWTH * size))
    missed = np.flatnonzero(hit_reference & ~np.isfinite(t))
    assert missed.size == 0, (
        f"{missed.size} of {hit_reference.sum()} rays miss a box they hit; first: origin {origins[missed[0]].tolist()} "
        f"direction {directions[missed[0]].tolist()} box {lo[missed[0]].tolist()} - {hi[missed[0]].tolist()} "
        f"(reference entry t {reference[missed[0]]})"
    )
    extra = np.flatnonzero(~near_miss & np.isfinite(t))
    assert extra.size == 0, (
        f"{extra.size} rays hit a box they miss by more than {BOX_GROWTH} relative; first: ray {extra[0]}"
    )
    both = np.flatnonzero(hit_reference & np.isfinite(t))
    error = np.abs(t[both] - reference[both])
    allowed = BOX_T_ROUNDINGS * UNIT_ROUNDOFF * (reference[both] + size[both, 0])
    worst = np.argmax(error - allowed)
    assert error[worst] <= allowed[worst], (
        f"ray {both[worst]}: entry t {t[both[worst]]} vs reference {reference[both[worst]]}"
    )


def degenerate_triangles(rng: np.random.Generator, count: int, kind: str) -> np.ndarray:
    """Zero-area triangles with dyadic corners (multiples of 1/8), so that collinear corners are
    exactly collinear in float32 and the float32 cross product of their edges is exactly zero."""
    a = rng.integers(-8, 9, size=(count, 3)) / 8.0
    b = a + rng.integers(-8, 9, size=(count, 3)) / 8.0
    variant = (np.arange(count) % 3)[:, None]
    if kind == "repeated corner":  # (a, b, a), (a, b, b), (a, a, a)
        b = np.where(variant == 2, a, b)
        c = np.where(variant == 1, b, a)
    else:  # the midpoint, a point beyond b, a quarter of the way
        c = np.select([variant == 0, variant == 1], [0.5 * (a + b), 2.0 * b - a], default=a + 0.25 * (b - a))
    return np.stack([a, b, c], axis=1).astype(np.float32)


# Exactly collinear corners are not in this list: f32 rounding of the sheared edge functions can
# leave all three of one sign, so the intersector alone may report them. Scenes drop them before
# upload (wgputrace.scene.scene.zero_area); `test_zero_area_triangles_never_reach_the_gpu` checks a render.
@pytest.mark.parametrize("kind", ["repeated corner"])
def test_degenerate_triangles_are_never_hit(gpu_context, rng, kind):
    count = 3_000
    triangles = degenerate_triangles(rng, count, kind)
    # Rays through points of the degenerate triangle (a segment or a point) and through its surroundings.
    targets = np.where(
        (rng.random(count) < 0.7)[:, None],
        points_on(triangles, random_barycentric(rng, count)),
        triangles[:, 0] + rng.normal(scale=0.1, size=(count, 3)),
    )
    directions = np.concatenate([axis_parallel_directions(rng, count // 3), unit_vectors(rng, count - count // 3)])
    origins = aimed_at(targets, directions, rng.uniform(0.5, 3.0, size=count))
    t = intersect_pairs(gpu_context, origins, directions, triangles)
    hits = np.flatnonzero(np.isfinite(t))
    assert hits.size == 0, (
        f"{hits.size} of {count} rays hit a zero-area triangle ({kind}); first: triangle {triangles[hits[0]].tolist()} "
        f"origin {origins[hits[0]].tolist()} direction {directions[hits[0]].tolist()} t {t[hits[0]]}"
    )


def mesh_records(shape: Shape) -> SceneRecords:
    return scene_records(Scene([shape]), "bvh")


def leave_surface(
    context, records: SceneRecords, triangle: np.ndarray, barycentric: np.ndarray, directions: np.ndarray
) -> np.ndarray:
    """(t, triangle) from the float32 point itself and (t, triangle) from the offset origin, per ray."""
    points = points_on(record_corners(records.triangles)[triangle], barycentric)
    out = run_kernel(
        context,
        LEAVE_SURFACE_KERNEL,
        [as_vec4(points), as_vec4(directions), triangle.astype(np.uint32)],
        np.dtype((np.float32, 4)),
        len(points),
        input_types=["vec4<f32>", "vec4<f32>", "u32"],
        output_type="vec4<f32>",
        scene={"triangles": records.triangles, "nodes": node_binding(context, records)},
    )
    return out


def surface_samples(rng: np.random.Generator, triangle_count: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Triangle indices and barycentric points: interior points, and points on or within 1e-6 of an
    edge or a corner, where neighbours sharing it are closest."""
    triangle = rng.integers(0, triangle_count, size=count)
    barycentric = random_barycentric(rng, count)
    edge = rng.random(count) < 0.5
    barycentric[edge, rng.integers(0, 3, size=edge.sum())] = rng.choice([0.0, 1e-6], size=edge.sum())
    corner = rng.random(count) < 0.1
    barycentric[corner] = np.eye(3)[rng.integers(0, 3, size=corner.sum())] * (1.0 - 2e-6) + 1e-6
    return triangle, barycentric / barycentric.sum(axis=1, keepdims=True)


def test_ray_leaving_a_triangle_skips_it(gpu_context, rng):
    count = 5_000
    sphere = make_icosphere((0.2, -0.1, 0.3), (0.1, 0.2, 0.3), 0.7, 2, Diffuse("white"))
    records = mesh_records(sphere)
    triangle, barycentric = surface_samples(rng, len(records.triangles), count)
    out = leave_surface(gpu_context, records, triangle, barycentric, unit_vectors(rng, count))
    again = np.flatnonzero(out[:, 1].view(np.uint32) == triangle)
    assert again.size == 0, (
        f"{again.size} of {count} rays hit the triangle they leave (skip_triangle); first: ray {again[0]}"
    )


def test_offset_origin_leaves_closed_mesh(gpu_context, rng):
    count = 5_000
    box = make_box((0.3, -0.2, 0.5), (0.4, -0.3, 0.9), (1.0, 0.6, 1.7), Diffuse("white"))
    records = mesh_records(box)
    triangle, barycentric = surface_samples(rng, len(records.triangles), count)
    outward = triangle_normals(record_corners(records.triangles))[triangle]
    # Outward directions down to grazing (cos 1e-3), where a neighbour in the same plane is nearest.
    directions = unit_vectors(rng, count).astype(np.float64)
    directions -= np.sum(directions * outward, axis=1, keepdims=True) * outward
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    cos = np.where(rng.random(count) < 0.5, rng.uniform(1e-3, 1e-2, count), rng.uniform(1e-2, 1.0, count))
    directions = (np.sqrt(1.0 - cos**2)[:, None] * directions + cos[:, None] * outward).astype(np.float32)
    out = leave_surface(gpu_context, records, triangle, barycentric, directions)
    # Control: from the float32 point itself some rays do hit a neighbour at t ~ 0 (the point is a
    # rounding off the surface), so these rays probe what the offset is for.
    assert (out[:, 1].view(np.uint32) != NO_TRIANGLE).sum() > count // 100, "no self-intersection without the offset"
    hit = np.flatnonzero(out[:, 3].view(np.uint32) != NO_TRIANGLE)
    assert hit.size == 0, (
        f"{hit.size} of {count} rays leaving a convex box outwards from an offset origin hit it again; first: "
        f"leaving triangle {triangle[hit[0]]}, hit triangle {out[hit[0], 3].view(np.uint32)} at t {out[hit[0], 2]}"
    )
