"""Is a noisy picture the expected one? Block-wise z-tests of the mean difference of two
independent Monte Carlo images, with the standard error taken from the per-pixel differences."""

from __future__ import annotations

import numpy as np

# Each image is cut into BLOCKS x BLOCKS regions and each channel tested in each: a shifted,
# mirrored or wrongly lit picture fails in some region even where the whole-image mean agrees.
BLOCKS = 4
CHANNELS = 3


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
