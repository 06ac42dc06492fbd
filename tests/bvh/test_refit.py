"""BVH refit: bounds equal a from-scratch recomputation, only changed nodes are reported, the
incremental SAH cost equals the full one, and the refit tree still finds every closest hit."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.bvh import Refitter, build_bvh, build_flat
from wgputrace.testing.oracles import brute_force_closest_hit, bvh_bounds_from_scratch, bvh_closest_hit
from wgputrace.testing.scenes import random_rays, random_soup

SEED = 20261123
TRIANGLES = 3000
RAYS = 1500
# The incremental SAH sum adds and subtracts areas in float64: a few roundings per refit.
SAH_RTOL = 1e-12


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(SEED)


def moved_copy(rng, vertices_reordered: np.ndarray, positions: np.ndarray, offset) -> np.ndarray:
    moved = vertices_reordered.copy()
    moved[positions] += np.asarray(offset, np.float32)
    return moved


def test_refit_equals_recomputed_bounds_and_reports_exactly_the_changed_nodes(rng):
    soup = random_soup(rng, TRIANGLES)
    bvh = build_bvh(soup)
    reordered = soup[bvh.triangle_order]
    refitter = Refitter(bvh, reordered)
    positions = np.sort(rng.choice(TRIANGLES, 40, replace=False))
    moved = moved_copy(rng, reordered, positions, (0.5, -0.3, 0.2))
    before_min, before_max = bvh.bounds_min.copy(), bvh.bounds_max.copy()
    touched = refitter.move(positions, moved[positions])
    expected_min, expected_max = bvh_bounds_from_scratch(bvh, moved)
    np.testing.assert_array_equal(bvh.bounds_min, expected_min)
    np.testing.assert_array_equal(bvh.bounds_max, expected_max)
    changed = np.flatnonzero(np.any(before_min != expected_min, axis=1) | np.any(before_max != expected_max, axis=1))
    np.testing.assert_array_equal(touched, changed)
    assert 0 < len(touched) < bvh.node_count // 4  # a local edit touches a few paths to the root
    assert refitter.cost == pytest.approx(bvh.sah_cost(), rel=SAH_RTOL)
    assert refitter.degradation > 1.0


def test_moving_back_restores_the_built_cost(rng):
    soup = random_soup(rng, TRIANGLES)
    bvh = build_bvh(soup)
    reordered = soup[bvh.triangle_order]
    refitter = Refitter(bvh, reordered)
    positions = np.arange(0, TRIANGLES, 7)
    refitter.move(positions, moved_copy(rng, reordered, positions, (3.0, 0.0, 0.0))[positions])
    assert refitter.degradation > 1.5  # scattered triangles pulled far away stretch many boxes
    refitter.move(positions, reordered[positions])
    assert refitter.degradation == pytest.approx(1.0, rel=SAH_RTOL)
    np.testing.assert_array_equal(bvh.bounds_min, build_bvh(soup).bounds_min)


def test_refit_tree_finds_the_same_closest_hits_as_brute_force(rng):
    soup = random_soup(rng, TRIANGLES // 3)
    bvh = build_bvh(soup)
    reordered = soup[bvh.triangle_order]
    positions = np.sort(rng.choice(len(soup), len(soup) // 2, replace=False))
    moved = moved_copy(rng, reordered, positions, rng.normal(0, 0.4, 3))
    Refitter(bvh, reordered).move(positions, moved[positions])
    origins, directions = random_rays(rng, RAYS)
    t, index = bvh_closest_hit(bvh, moved, origins, directions)
    expected_t, expected_index, _ = brute_force_closest_hit(moved, origins, directions)
    np.testing.assert_array_equal(index, expected_index)
    np.testing.assert_array_equal(t, expected_t)


def test_flat_list_refits_its_shape_boxes(rng):
    soup = random_soup(rng, 200)
    groups = np.repeat(np.arange(10), 20)
    flat = build_flat(soup, groups)
    reordered = soup[flat.triangle_order]
    positions = np.flatnonzero(groups[flat.triangle_order] == 3)
    moved = moved_copy(rng, reordered, positions, (1.0, 1.0, 1.0))
    touched = Refitter(flat, reordered).move(positions, moved[positions])
    np.testing.assert_array_equal(touched, [3])
    np.testing.assert_array_equal(flat.bounds_min[3], moved[positions].reshape(-1, 3).min(axis=0))
