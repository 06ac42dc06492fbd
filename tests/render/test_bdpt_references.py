"""Bidirectional path tracing against Mitsuba 3's references, per block of pixels, as
tests/render/test_references.py compares the path tracer (Welch's t-test per block and channel,
Sidak's share of FAMILY_SIGNIFICANCE over every block, channel and scene of this module).

Issue 18 asks bdpt to converge to the same image as `mis`. The scenes here are those where its light
subpaths meet something of their own: the light kinds they leave (a light triangle in the Cornell
box, the environment mixed with a sun, point, spot and directional lights), materials a light
subpath scatters from with the adjoint BSDF (diffuse, glossy and glass in the box, principled
transmission), textures on light and camera vertices alike (textured_asset: base colour, normal map,
emission through a texture), the shading normal a light subpath's vertex is shaded with
(normal_mapped_plane, compared without our terms as test_shading_normal_references.py does), the box
at 1e-4 of its size (connections' shadow rays between points moved off their surfaces) and the
scenes that break path tracers. What bdpt shares with the path tracer (traversal, the BSDFs' values,
texture lookups, cut-outs and stochastic transparency in every traversal, the scenes' geometry) the
path tracer's own reference tests cover.

Kept out for CI time, each bdpt variant compiling for seconds on lavapipe (all passed at 64x64 and
at this module's settings, 2026-12-02): principled_spheres, textured_quads, alpha_cutout,
alpha_blend, smooth_sphere, glass_grazing, glossy_spheres, slivers, axis_boxes, constant_env,
env_one_texel; tests/render/test_bdpt_weights.py weighs paths on some of them,
tests/render/test_bdpt.py checks others for non-finite samples.

32x32 images from the 128x128 references (a box filter makes the average exact), 8 batches: a moved
lobe, texel block or caustic shows in an 8x8 block, a small error spread everywhere in the whole
image; weaker statistics than test_references.py's at 64x64, the price of CI time.
"""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from wgputrace.kernels.shading_normals import MITSUBA_SHADING_NORMALS
from wgputrace.testing.references import assert_matches_reference, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SIZE = 32
BLOCKS = (8, SIZE)
BATCHES = 8
FAMILY_SIGNIFICANCE = 1e-3


@dataclass(frozen=True)
class Case:
    scene: str
    reference: str
    seed: int
    spp: int  # per batch
    overrides: tuple[tuple[str, bool], ...] = ()


MITSUBA_TERMS = tuple(MITSUBA_SHADING_NORMALS.items())
CASES = {
    case.scene: case
    for case in (
        Case("cornell", "cornell", 20261211, spp=16),
        Case("cornell_1e-4", "cornell", 20261212, spp=16),
        Case("env_sun_spheres", "env_sun_spheres", 20261215, spp=16),
        Case("point_spot_directional", "point_spot_directional", 20261216, spp=16),
        Case("principled_transmission", "principled_transmission", 20261218, spp=16),
        Case("textured_asset", "textured_asset", 20261220, spp=16),
        Case("normal_mapped_plane", "normal_mapped_plane", 20261224, spp=16, overrides=MITSUBA_TERMS),
        Case("door_ajar", "door_ajar", 20261225, spp=16),
        Case("caustic", "caustic", 20261226, spp=16),
        Case("glossy_through_glossy", "glossy_through_glossy", 20261227, spp=16),
    )
}
BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3 * len(CASES)
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS)


@pytest.mark.slow
@pytest.mark.parametrize("scene", CASES)
def test_bdpt_matches_mitsuba_reference(gpu_context, failure_dir, scene):
    case = CASES[scene]
    reference = load_reference(case.reference)
    render = render_batches(
        scene,
        SIZE,
        batches=BATCHES,
        spp=case.spp,
        seed=case.seed,
        max_depth=reference.metadata["max_depth"],
        integrator="bdpt",
        shader_overrides=dict(case.overrides),
    )
    assert_matches_reference(
        f"{scene}_bdpt_vs_mitsuba",
        render,
        reference,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )
