"""Mitsuba 3 references (tests/references/<scene>.npz in the checkout, made by `python
scripts/make_references.py`), batched renders of ours (of a `ReferenceCase` too), the per-block
comparison of two estimates, and images of a failed comparison for a person to look at.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgputrace import Renderer, save_image
from wgputrace.scene import DegenerateTrianglesWarning
from wgputrace.scenes import scene_by_name
from wgputrace.testing.checkout import checkout_file
from wgputrace.testing.image_statistics import BlockComparison, Estimate, compare_blocks
from wgputrace.testing.reference_cases import FAMILY_SIGNIFICANCE, ReferenceCase, family_block_tests
from wgputrace.testing.stats import sidak

# References are stored as float16, whose 11 significant bits move a value by at most this fraction
# when rounding. Pixels of one value all round alike, so this is a bias bound, not noise.
STORAGE_RTOL = 2.0**-11
# How many of the blocks with the smallest p-values a failed comparison lists.
WORST_BLOCKS_SHOWN = 5


def reference_dir() -> Path:
    """The checkout's tests/references/."""
    return checkout_file("tests", "references")


@dataclass
class Reference:
    estimate: Estimate
    metadata: dict


def load_reference(name: str) -> Reference:
    """The reference's mean with its variance, the squared standard error of Mitsuba's passes."""
    path = reference_dir() / f"{name}.npz"
    with np.load(path) as data:
        metadata = json.loads(str(data["metadata"]))
        mean = data["mean"].astype(np.float64)
        standard_error = data["standard_error"].astype(np.float64)
    return Reference(Estimate(mean, standard_error**2, metadata["passes"] - 1.0), metadata)


@dataclass
class BatchedRender:
    batches: np.ndarray  # (K, H, W, 3) float32: K independent images of equal sample counts
    nonfinite_samples: int  # over all batches

    @property
    def estimate(self) -> Estimate:
        return Estimate.from_batches(self.batches)


def render_batches(
    scene_name: str, size: int, *, batches: int, spp: int, seed: int, max_depth: int, **renderer_options
) -> BatchedRender:
    """`batches` images of `spp` samples each, from one renderer (`renderer_options`: integrator,
    sampler, shader_overrides, ...) reset between them, so the batches are independent."""
    with warnings.catch_warnings():
        # the slivers scene drops its zero-area triangles on purpose (the scene tests check the warning)
        warnings.simplefilter("ignore", DegenerateTrianglesWarning)
        renderer = Renderer(scene_by_name(scene_name), size, size, seed=seed, max_depth=max_depth, **renderer_options)
    return batches_of(renderer, batches, spp)


def batches_of(renderer: Renderer, batches: int, spp: int) -> BatchedRender:
    """`batches` images of `spp` samples each from `renderer`, reset between them (independent)."""
    images, nonfinite = [], 0
    for _ in range(batches):
        renderer.render(spp)
        images.append(renderer.image())
        nonfinite += renderer.nonfinite_samples
        renderer.reset()
    return BatchedRender(np.stack(images), nonfinite)


def render_case(case: ReferenceCase) -> BatchedRender:
    """`case`'s batches, rendered as it says."""
    return render_batches(
        case.scene, case.size, batches=case.batches, spp=case.spp, seed=case.seed, **case.renderer_options
    )


def block_test_significance(case: ReferenceCase) -> float:
    """The level of each block test of `case`: Sidak's share of FAMILY_SIGNIFICANCE over its family."""
    return sidak(FAMILY_SIGNIFICANCE, family_block_tests(case.family))


def severity_image(comparison: BlockComparison, per_test_significance: float, size: int) -> np.ndarray:
    """Blocks coloured by log p / log(per-test level): red where ours is brighter, blue where darker,
    full colour where the test failed (>= 1), dimmer as the evidence weakens; channels summed."""
    strength = np.log(np.maximum(comparison.p_value, 1e-300)) / np.log(per_test_significance)
    signed = (np.sign(comparison.difference) * strength).sum(axis=2) / 3.0
    image = np.zeros((*signed.shape, 3))
    image[..., 0] = np.clip(signed, 0.0, 1.0)
    image[..., 2] = np.clip(-signed, 0.0, 1.0)
    image[np.abs(signed) >= 1.0, 1] = 1.0  # failing blocks: yellow (brighter) or cyan (darker)
    block = size // signed.shape[0]
    return np.repeat(np.repeat(image, block, axis=0), block, axis=1)


def write_failure_images(
    folder: Path,
    name: str,
    ours: np.ndarray,
    reference: np.ndarray,
    comparison: BlockComparison,
    per_test_significance: float,
) -> list[Path]:
    """ours, reference and ours - reference as EXR; ours | reference | severity as one PNG."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = [
        save_image(folder / f"{name}_ours.exr", ours),
        save_image(folder / f"{name}_reference.exr", reference),
        save_image(folder / f"{name}_difference.exr", ours - reference),
    ]
    severity = severity_image(comparison, per_test_significance, ours.shape[0])
    gap = np.ones((ours.shape[0], 2, 3))
    paths.append(save_image(folder / f"{name}.png", np.concatenate([ours, gap, reference, gap, severity], axis=1)))
    return paths


def worst_blocks(comparison: BlockComparison, ours: Estimate, reference: Estimate, size: int, count: int) -> str:
    """The `count` blocks with the smallest p-values, one line each."""
    ours_blocks, reference_blocks = ours.blocks(size)[0], reference.blocks(size)[0]
    order = np.argsort(comparison.p_value, axis=None)[:count]
    lines = []
    for flat in order:
        row, column, channel = np.unravel_index(flat, comparison.p_value.shape)
        index = (row, column, channel)
        lines.append(
            f"block row {row} column {column} channel {'rgb'[channel]}: ours {ours_blocks[index]:.5g}, "
            f"reference {reference_blocks[index]:.5g}, z {comparison.z[index]:.2f}, "
            f"dof {comparison.dof[index]:.0f}, p {comparison.p_value[index]:.3g}"
        )
    return "\n".join(lines)


def assert_same_expectation(
    label: str,
    ours: Estimate,
    other: Estimate,
    other_image: np.ndarray,
    relative_tolerance: float,
    failure_dir: Path,
    *,
    blocks: Sequence[int],
    per_test_significance: float,
) -> None:
    """Every block of `ours` (of each size in `blocks`, per channel) has the expectation of `other`'s
    by Welch's t-test at `per_test_significance`, up to `relative_tolerance` of `other_image`'s
    block mean (a systematic difference that more samples would not reduce). A failure writes the
    images under `failure_dir` and names the worst blocks."""
    for block in blocks:
        image_blocks = Estimate(other_image, np.zeros_like(other_image), np.inf).blocks(block)[0]
        comparison = compare_blocks(ours, other, block, relative_tolerance * np.abs(image_blocks))
        failing = comparison.p_value < per_test_significance
        if failing.any():
            paths = write_failure_images(failure_dir, label, ours.mean, other_image, comparison, per_test_significance)
            raise AssertionError(
                f"{label}: {int(failing.sum())} of {failing.size} tests of {block}x{block} blocks reject equal "
                f"expectations at p < {per_test_significance:.3g}; worst:\n"
                f"{worst_blocks(comparison, ours, other, block, WORST_BLOCKS_SHOWN)}\nimages: {', '.join(map(str, paths))}"
            )


def assert_matches_reference(
    label: str,
    render: BatchedRender,
    reference: Reference,
    failure_dir: Path,
    *,
    blocks: Sequence[int],
    per_test_significance: float,
) -> None:
    """`render` has no non-finite sample or pixel and the expectation of `reference` (Mitsuba's,
    averaged down to the render's size) block by block, up to the reference's float16 storage."""
    assert render.nonfinite_samples == 0, f"{label}: {render.nonfinite_samples} non-finite samples"
    # a NaN block would pass the t-test below (its p-value is NaN, never below the level)
    assert np.isfinite(render.batches).all(), f"{label}: {(~np.isfinite(render.batches)).sum()} non-finite pixels"
    expected = reference.estimate.downsampled(reference.metadata["width"] // render.batches.shape[2])
    assert_same_expectation(
        label,
        render.estimate,
        expected,
        expected.mean,
        STORAGE_RTOL,
        failure_dir,
        blocks=blocks,
        per_test_significance=per_test_significance,
    )
