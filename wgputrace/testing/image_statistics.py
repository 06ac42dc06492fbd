"""Comparing Monte Carlo images statistically: per-pixel estimates with their variance and
per-block Welch t-tests between two estimates; per-block z-scores of two single images; and the
error of an image as it is displayed (MSE and PSNR of the clipped, sRGB-encoded values).

Every pixel of our renderer has its own random stream, and Mitsuba's passes are independent, so
pixel estimates are independent of each other: the variance of a block's mean is the sum of its
pixels' variances over the pixel count squared, and the Welch-Satterthwaite formula gives the
degrees of freedom of that sum from each pixel's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from wgputrace.image_io import linear_to_srgb

# Each image is cut into BLOCKS x BLOCKS regions and each channel tested in each: a shifted,
# mirrored or wrongly lit picture fails in some region even where the whole-image mean agrees.
BLOCKS = 4
CHANNELS = 3


@dataclass
class Estimate:
    """Per-pixel estimates (H, W, 3) with the variance of each and that variance's degrees of
    freedom (infinite where the variance is known exactly)."""

    mean: np.ndarray
    variance: np.ndarray
    dof: float

    @classmethod
    def from_batches(cls, batches: np.ndarray) -> Estimate:
        """The mean of K independent batch images (K, H, W, 3) of equal sample counts."""
        batches = np.asarray(batches, dtype=np.float64)
        count = len(batches)
        return cls(batches.mean(axis=0), batches.var(axis=0, ddof=1) / count, count - 1.0)

    def blocks(self, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mean of each size x size block, its variance, and the sum of squared per-pixel variance
        shares over their dof (the Welch-Satterthwaite denominator's part from this estimate)."""
        height, width, channels = self.mean.shape
        if height % size or width % size:
            raise ValueError(f"a {width}x{height} image does not split into {size}x{size} blocks")
        shape = (height // size, size, width // size, size, channels)
        pixels = size * size
        share = self.variance.reshape(shape) / pixels**2
        return (
            self.mean.reshape(shape).mean(axis=(1, 3)),
            share.sum(axis=(1, 3)),
            (share**2).sum(axis=(1, 3)) / self.dof,
        )

    def downsampled(self, factor: int) -> Estimate:
        """Each factor x factor square of pixels as one pixel: with a box filter, its expectation
        is exactly that of a pixel factor times larger."""
        mean, variance, _ = self.blocks(factor)
        return Estimate(mean, variance, self.dof)


@dataclass
class BlockComparison:
    """Welch's test per block and channel that two estimates have the same expectation, up to an
    accepted systematic difference (`tolerance`, e.g. rounding, which averaging does not reduce)."""

    difference: np.ndarray  # (blocks_y, blocks_x, 3): mean of `a` minus mean of `b`
    tolerance: np.ndarray
    standard_error: np.ndarray
    dof: np.ndarray
    p_value: np.ndarray

    @property
    def excess(self) -> np.ndarray:
        """The part of the difference beyond the tolerance, with its sign."""
        return np.sign(self.difference) * np.maximum(np.abs(self.difference) - self.tolerance, 0.0)

    @property
    def z(self) -> np.ndarray:
        return np.divide(
            self.excess, self.standard_error, out=np.zeros_like(self.excess), where=self.standard_error > 0
        )


def compare_blocks(a: Estimate, b: Estimate, size: int, tolerance: np.ndarray | float = 0.0) -> BlockComparison:
    mean_a, variance_a, denominator_a = a.blocks(size)
    mean_b, variance_b, denominator_b = b.blocks(size)
    variance = variance_a + variance_b
    denominator = denominator_a + denominator_b
    dof = np.divide(variance**2, denominator, out=np.full_like(variance, np.inf), where=denominator > 0)
    comparison = BlockComparison(
        mean_a - mean_b, np.broadcast_to(tolerance, variance.shape), np.sqrt(variance), dof, np.empty_like(variance)
    )
    excess = comparison.excess
    noisy = comparison.standard_error > 0
    comparison.p_value[noisy] = 2.0 * stats.t.sf(np.abs(comparison.z[noisy]), dof[noisy])
    # no noise on either side: equal or not at all
    comparison.p_value[~noisy] = np.where(excess[~noisy] == 0.0, 1.0, 0.0)
    return comparison


def block_z_scores(image: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(BLOCKS, BLOCKS, 3) z-scores of mean(image - other) per block and channel.

    Every pixel of each image has its own random stream, so the per-pixel differences are
    independent; if both images estimate the same picture, each difference has expectation zero.
    Differences within a block are not identically distributed, but their mean over ~10^3 pixels
    is normal (Lyapunov) with variance sum(Var D_p) / n^2. Under that hypothesis every D_p has
    expectation zero, so the sample variance of the block's differences estimates mean(Var D_p).
    """
    difference = image.astype(np.float64) - other.astype(np.float64)
    height, width = difference.shape[:2]
    scores = np.zeros((BLOCKS, BLOCKS, CHANNELS))
    for row in range(BLOCKS):
        for column in range(BLOCKS):
            block = difference[
                row * height // BLOCKS : (row + 1) * height // BLOCKS,
                column * width // BLOCKS : (column + 1) * width // BLOCKS,
            ].reshape(-1, CHANNELS)
            error = block.std(axis=0, ddof=1) / np.sqrt(len(block))
            scores[row, column] = np.divide(block.mean(axis=0), error, out=np.zeros(CHANNELS), where=error > 0)
    return scores


def displayed_mse(image: np.ndarray, reference: np.ndarray) -> float:
    """The mean squared difference of the displayed values: clipped to [0, 1] and sRGB-encoded, so
    that an error weighs as much as it shows."""
    shown, expected = (linear_to_srgb(np.asarray(x, np.float64)) for x in (image, reference))
    return float(np.mean((shown - expected) ** 2))


def displayed_psnr(image: np.ndarray, reference: np.ndarray) -> float:
    """10 log10(1 / displayed_mse), in dB: the displayed values' peak is 1."""
    return float(10.0 * np.log10(1.0 / displayed_mse(image, reference)))


def equal_neighbour_fraction(pixels: np.ndarray) -> float:
    """The fraction of horizontally or vertically adjacent pixels of (h, w, c) `pixels` that are
    equal in every channel: about half or more in a picture scaled up from half the size or less
    (blocks of copies), few in a noisy or smooth full-resolution one."""
    across = (pixels[:, 1:] == pixels[:, :-1]).all(axis=-1)
    down = (pixels[1:] == pixels[:-1]).all(axis=-1)
    return float((across.sum() + down.sum()) / (across.size + down.size))
