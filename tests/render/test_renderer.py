"""The renderer's contract: determinism, progressive accumulation, orientation, accelerations."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Emitter, Renderer, Scene, default_scene, make_plane, render

SIZE = 32
SEED = 3


@pytest.fixture(scope="module")
def cornell():
    return default_scene()


def test_same_seed_same_image_other_seed_other_image(gpu_context, cornell):
    a = render(cornell, spp=2, width=SIZE, height=SIZE, seed=SEED)
    b = render(cornell, spp=2, width=SIZE, height=SIZE, seed=SEED)
    c = render(cornell, spp=2, width=SIZE, height=SIZE, seed=SEED + 1)
    np.testing.assert_array_equal(a, b)
    lit = np.any((a > 0) | (c > 0), axis=2)
    assert np.mean(np.any(a != c, axis=2)[lit]) > 0.5


def test_progressive_rendering_continues_the_same_sequence(gpu_context, cornell):
    progressive = Renderer(cornell, SIZE, SIZE, seed=SEED)
    progressive.render(2)
    progressive.render(3)
    assert progressive.samples_per_pixel == 5
    np.testing.assert_array_equal(progressive.image(), render(cornell, spp=5, width=SIZE, height=SIZE, seed=SEED))


def test_reset_starts_a_new_mean(gpu_context, cornell):
    renderer = Renderer(cornell, SIZE, SIZE, seed=SEED)
    renderer.render(2)
    first = renderer.image()
    renderer.reset()
    assert renderer.samples_per_pixel == 0
    renderer.render(2)
    second = renderer.image()
    assert np.all(np.isfinite(second))
    lit = np.any((first > 0) | (second > 0), axis=2)
    assert np.mean(np.any(first != second, axis=2)[lit]) > 0.5


def test_row_zero_is_the_top_and_image_right_is_cross_forward_up(gpu_context):
    """A lamp up and to the right of the view (image right = cross(+z, +y) = -x) lights only the
    top-right quadrant."""
    lamp = make_plane((-1.0, 1.0, 4.0), (-np.pi / 2, 0, 0), (1.5, 1.5), Emitter("lamp"), "lamp")
    scene = Scene([lamp], Camera((0, 0, 0), (0, 0, 1), (0, 1, 0), 60.0))
    image = render(scene, spp=1, width=SIZE, height=SIZE, max_depth=1).sum(axis=2)
    half = SIZE // 2
    assert image[:half, half:].mean() > 0.5
    assert image[half:, :].max() == 0 and image[:, :half].max() == 0


def test_bvh_and_flat_trace_the_same_paths(gpu_context, cornell):
    """Same seed, same closest hits: the two accelerations consume the same random numbers and
    agree pixel for pixel, except where two triangles tie at one distance."""
    bvh = render(cornell, spp=2, width=SIZE, height=SIZE, seed=SEED, accel="bvh")
    flat = render(cornell, spp=2, width=SIZE, height=SIZE, seed=SEED, accel="flat")
    same = np.all(np.isclose(bvh, flat, rtol=1e-5, atol=1e-6), axis=2)
    assert same.mean() > 0.98


def test_cornell_box_looks_like_the_thesis_picture(gpu_context, cornell):
    image = render(cornell, spp=64, width=SIZE, height=SIZE, seed=SEED)
    assert np.all(np.isfinite(image)) and image.min() >= 0
    middle = slice(SIZE // 4, 3 * SIZE // 4)
    left = image[middle, : SIZE // 6].reshape(-1, 3).mean(axis=0)
    right = image[middle, -SIZE // 6 :].reshape(-1, 3).mean(axis=0)
    assert left[0] > 4 * left[1]  # the red wall on the left
    assert right[1] > 1.5 * right[0]  # the green wall on the right
    top_center = image[: SIZE // 8, SIZE // 3 : 2 * SIZE // 3].mean()
    assert top_center > image.mean()  # the lamp is at the top


def test_bad_arguments_are_named(gpu_context, cornell):
    with pytest.raises(ValueError, match="max_depth"):
        Renderer(cornell, SIZE, SIZE, max_depth=0)
    with pytest.raises(ValueError, match="image size"):
        Renderer(cornell, 0, SIZE)
    with pytest.raises(ValueError, match="acceleration"):
        Renderer(cornell, SIZE, SIZE, accel="kdtree")
