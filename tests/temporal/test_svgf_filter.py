"""SVGF's variance-guided filter (`render_frame(filtered=True)`, VarianceGuidedFilter): it keeps a
flat wall's energy (its radiance in closed form: albedo times the sky), keeps a lit card's light on
the card (its radiance in closed form: a point light's), and makes no NaN or infinity of black
surfaces, the sky, noiseless pixels or a young history. Its first pass feeds the history while the
camera moves, and never at rest."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Emitter, Environment, PointLight, Renderer, Scene, make_box
from wgputrace.render.svgf_filter import SVGF_HALF_RESOLUTION_FROM, svgf_steps
from wgputrace.scene.lights.directional import DirectionalLight
from wgputrace.testing.reprojection import (
    CARD_DISTANCE,
    SIZE,
    WHITE,
    card_scene,
    centre_hits,
    pinhole,
    wall_scene,
)

pytestmark = pytest.mark.gpu

FRAMES = 8
SKY = 0.5
# the filtered mean may differ from the truth by this many standard errors of the unfiltered mean
Z_BOUND = 4.0
CARD_BLUR_BOUND = 0.01
FED_SPREAD_RATIO = 1.5
# How far a fed history's mean may be from the wall's radiance, relative. Not a bound in standard
# errors of the plain mean: the filtered colour fed back spreads each sample over its neighbours,
# so the fed mean varies between seeds about 2.4 times as much, and SVGF's luminance stop lifts it
# a little. Measured with seeds 11 to 18: -0.53% to +0.78% at 1x, -0.14% to +0.85% at 2x.
FED_ENERGY_RTOL = 0.015
# how far from a crease its light would leak: the first passes' reach
CREASE_PIXELS = 4
LIGHT_POSITION = (-0.6, 0.0, 0.0)
LIGHT_INTENSITY = 3.0
# radiance that counts as black: a black wall's filtered light, where the lamp's taps beside it
# weigh next to nothing through the stops (up to 8e-13 measured, the lamp's being 2)
BLACK_ATOL = 1e-9


# the box filter's footprint of a pixel, as a grid of points per axis
SUBPIXELS = (np.arange(8) + 0.5) / 8


def _card_radiance(within: tuple[float, float]) -> np.ndarray:
    """The card's radiance through the point `within` each pixel: its front sees nothing but the
    point light, so a diffuse surface's radiance under it (SIZE, SIZE)."""
    points, _ = centre_hits(pinhole(0.0), within)
    distance_squared = ((np.asarray(LIGHT_POSITION) - points) ** 2).sum(-1)
    cosine = CARD_DISTANCE / np.sqrt(distance_squared)
    return WHITE[0] / np.pi * LIGHT_INTENSITY * cosine / distance_squared


def _frames(renderer: Renderer, upscale: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The filtered picture and the history's mean (upsampled by `upscale`: the rebuilt picture)
    after FRAMES samples per pixel at rest (upsampled, FRAMES * upscale**2 frames)."""
    for _ in range(FRAMES * upscale**2):
        filtered = renderer.render_frame(filtered=True, upscale=upscale)
    return filtered, (renderer._temporal if upscale == 1 else renderer._upsampling).image()


# full resolution, and upsampled at a factor whose filter runs at half resolution
UPSCALES = [1, SVGF_HALF_RESOLUTION_FROM]


def _standard_error(values: np.ndarray) -> float:
    return float(values.std() / np.sqrt(values.size))


@pytest.mark.parametrize("upscale", UPSCALES)
def test_a_flat_wall_keeps_its_energy(upscale):
    filtered, unfiltered = _frames(Renderer(wall_scene(sky=SKY), SIZE, SIZE, seed=11), upscale)
    truth = WHITE[0] * SKY
    assert abs(unfiltered.mean() - truth) < Z_BOUND * _standard_error(unfiltered)
    # the filter keeps its input's energy (upsampled, its taps reach across the whole image, whose
    # pixels' errors it weighs unevenly: seeds 11-13 moved the mean by 0.05, 0.05 and 0.7 standard
    # errors at full resolution, 2.6, 0.9 and 0.8 at 4x)
    assert abs(filtered.mean() - unfiltered.mean()) < Z_BOUND * _standard_error(unfiltered)
    # and it did filter: the pixels spread far less than the history's
    assert filtered.std() < unfiltered.std() / 3


@pytest.mark.parametrize("upscale", UPSCALES)
def test_a_lit_card_keeps_its_light_and_the_wall_its_own(upscale):
    scene = card_scene(sky=0.0).add_light(PointLight(position=LIGHT_POSITION, intensity=LIGHT_INTENSITY))
    filtered, unfiltered = _frames(Renderer(scene, SIZE, SIZE, seed=11), upscale)
    _, on_card = centre_hits(pinhole(0.0))
    radiance = np.mean([_card_radiance((x, y)) for x in SUBPIXELS for y in SUBPIXELS], axis=0)
    # the card's pixels whose whole footprint is on it
    inner = (
        on_card & np.roll(on_card, 1, 0) & np.roll(on_card, -1, 0) & np.roll(on_card, 1, 1) & np.roll(on_card, -1, 1)
    )
    error = _standard_error(unfiltered[inner] - radiance[inner, None])
    assert abs(unfiltered[inner].mean() - radiance[inner].mean()) < Z_BOUND * error
    # The filter blurs the card's own falloff a little (0.2% measured); taking even 2% of its
    # taps from the wall, ten times darker, would lower it by nearly 2%.
    np.testing.assert_allclose(filtered[inner].mean(), radiance[inner].mean(), rtol=CARD_BLUR_BOUND)
    # the wall, ten times darker, is not lifted by the card beside it
    wall = ~on_card
    assert abs(filtered[wall].mean() - unfiltered[wall].mean()) < Z_BOUND * _standard_error(unfiltered[wall])


@pytest.mark.parametrize("upscale", UPSCALES)
def test_black_surfaces_the_sky_and_young_histories_stay_finite(upscale):
    # max_depth 1: a black wall (albedo 0), a lamp card and the sky, each without noise (variance 0)
    scene = card_scene(wall=Diffuse("black", color=(0.0, 0.0, 0.0)), card=Emitter("lamp", emittance=2.0))
    renderer = Renderer(scene, SIZE, SIZE, max_depth=1)
    guide = Renderer(scene, SIZE, SIZE, max_depth=1)
    for camera in (pinhole(0.0), pinhole(0.5, 40.0), pinhole(-0.5, 75.0)):
        filtered = renderer.render_frame(camera, filtered=True, upscale=upscale)
        assert np.isfinite(filtered).all()
        # the sky passes through as it is (where a full-resolution frame sees it: an upsampled
        # frame's G-buffer is the traced pixels', and beside the sky an upsampled pixel's history
        # may show the black wall, whose light is 0 either way)
        guide.render_frame(camera)
        sky = guide.gbuffer()["surface"] == 0
        unfiltered = (renderer._temporal if upscale == 1 else renderer._upsampling).image()
        np.testing.assert_allclose(filtered[sky], unfiltered[sky], rtol=1e-6, atol=BLACK_ATOL)


@pytest.mark.parametrize("upscale", [SVGF_HALF_RESOLUTION_FROM, 8])
def test_a_half_resolution_filter_of_an_odd_sized_image_keeps_the_walls_energy(upscale):
    # 33 x 31: the half-resolution blocks of the last column and row are cut by the edge
    width, height = 33, 31
    renderer = Renderer(wall_scene(sky=SKY), width, height, seed=11)
    for _ in range(upscale**2):
        filtered = renderer.render_frame(filtered=True, upscale=upscale)
    unfiltered = renderer._upsampling.image()
    assert np.isfinite(filtered).all() and filtered.shape == (height, width, 3)
    assert abs(filtered.mean() - unfiltered.mean()) < Z_BOUND * _standard_error(unfiltered)
    # the edge's cut blocks are neither black nor brighter than the wall's light allows
    edges = np.concatenate([filtered[-1], filtered[:, -1]])
    assert abs(edges.mean() - unfiltered.mean()) < Z_BOUND * _standard_error(
        np.concatenate([unfiltered[-1], unfiltered[:, -1]])
    )


def test_filtering_at_rest_leaves_the_history_the_plain_mean_bit_for_bit():
    # the first frame sets a new camera: a new history, not one that moved
    frames = Renderer(wall_scene(sky=SKY), SIZE, SIZE, seed=11)
    for _ in range(FRAMES):
        frames.render_frame(pinhole(0.3), filtered=True)
    scene = wall_scene(sky=SKY)
    scene.camera = pinhole(0.3)
    plain = Renderer(scene, SIZE, SIZE, seed=11)
    plain.render(FRAMES)
    np.testing.assert_array_equal(frames._temporal.image(), plain.image())


def _history_after_sliding(filtered: bool, upscale: int) -> np.ndarray:
    """The unfiltered history's picture of the wall after FRAMES frames of a camera sliding along it
    (a twenty-fifth of a pixel a frame), filtered or not, upsampled by `upscale` or not. Independent
    samples: the Sobol sampler's frames are stratified against each other, so their plain mean is
    nearly as smooth already."""
    renderer = Renderer(wall_scene(sky=SKY), SIZE, SIZE, seed=11, sampler="independent")
    for step in range(FRAMES):
        renderer.render_frame(pinhole(0.01 * step), filtered=filtered, upscale=upscale)
    return (renderer._temporal if upscale == 1 else renderer._upsampling).image()


@pytest.mark.parametrize("upscale", [1, 2])
def test_while_moving_the_first_pass_feeds_the_history(upscale):
    fed, plain = _history_after_sliding(True, upscale), _history_after_sliding(False, upscale)
    # the history took the filtered colour: its spread falls about as 1 / frames, the plain mean's
    # as 1 / sqrt(frames) (less with the reprojection's blur and clamp; 2 times measured) ...
    assert fed.std() < plain.std() / FED_SPREAD_RATIO
    # ... and as bright
    assert abs(fed.mean() / (WHITE[0] * SKY) - 1.0) < FED_ENERGY_RTOL


@pytest.mark.parametrize("upscale", UPSCALES)
def test_the_filter_crosses_no_crease(upscale):
    # A box seen corner-on, its near edge on the image's middle pixel boundary: the left face lit by
    # a directional light and the sky, the right face by the sky alone, both noisy. The right face
    # keeps its own light beside the crease, where the normal stop is all that holds the left's back.
    box = make_box((0.0, 0.0, 3.0), (0.0, np.radians(45.0), 0.0), 2.0, Diffuse("white", color=WHITE))
    scene = Scene([box], pinhole(0.0), environment=Environment(SKY))
    scene.add_light(DirectionalLight(direction=(1.0, 0.0, 0.3), irradiance=3.0))
    renderer = Renderer(scene, SIZE, SIZE, seed=11, sampler="independent")
    filtered, unfiltered = _frames(renderer, upscale)
    # every pixel's normal, from a full-resolution frame (an upsampled one's G-buffer is the traced pixels')
    guide = Renderer(scene, SIZE, SIZE)
    guide.render_frame()
    normal_x = guide.gbuffer()["normal"][..., 0]
    columns = np.arange(SIZE)[None, :]
    # the right face's pixels within CREASE_PIXELS of the crease, and the left face's
    right = (normal_x > 0.5) & (columns < SIZE // 2 + CREASE_PIXELS)
    left = normal_x < -0.5
    assert right.sum() > 40 and left.sum() > 40
    assert unfiltered[left].mean() > 2 * unfiltered[right].mean()
    for face in (left, right):
        error = _standard_error(unfiltered[face])
        assert abs(filtered[face].mean() - unfiltered[face].mean()) < Z_BOUND * error


def test_upsampled_pictures_spread_their_taps_wider_up_to_schieds_widest():
    assert svgf_steps(1) == (1, 2, 4)
    assert svgf_steps(2) == (1, 2, 4, 8)
    # the interpolated samples smoothed the pixel scale already: from 4x the first step is 2
    assert svgf_steps(4) == svgf_steps(8) == (2, 4, 8, 16)
