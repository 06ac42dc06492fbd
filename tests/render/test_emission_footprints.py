"""footprint_means against a brute-force box filter: the mean of the
texels in each triangle's padded bounding rectangle, indices wrapped as the GPU wraps them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.render.emission_footprints import footprint_means
from wgputrace.scene import Texture, TextureTransform


def brute_force_mean(texture: Texture, uvs: np.ndarray) -> np.ndarray:
    texels = texture.linear_texels[..., :3].astype(np.float64)
    height, width = texels.shape[:2]
    st = uvs.astype(np.float64) @ texture.transform.rows()[:, :2].T.astype(np.float64) + texture.transform.rows()[:, 2]
    xy = st * (width, height) - 0.5
    low, high = np.floor(xy.min(axis=0)).astype(int), np.floor(xy.max(axis=0)).astype(int) + 2

    def indices(a: int, b: int, n: int, mode: str) -> np.ndarray:
        reached = np.arange(a, b)
        return np.mod(reached, n) if mode == "repeat" else np.unique(np.clip(reached, 0, n - 1))

    columns = indices(low[0], high[0], width, texture.wrap_s)
    rows = indices(low[1], high[1], height, texture.wrap_t)
    return texels[np.ix_(rows, columns)].reshape(-1, 3).mean(axis=0)


@pytest.mark.parametrize("mode", ["repeat", "clamp"])
def test_footprint_means_match_the_brute_force_box(mode):
    rng = np.random.default_rng(3)
    texture = Texture(
        rng.integers(0, 256, (8, 16, 3)).astype(np.uint8),
        wrap_s=mode,
        wrap_t=mode,
        transform=TextureTransform(offset=(0.3, -0.2), rotation=0.4, scale=(0.7, 1.1)),
    )
    # footprints narrower than the texture, across its edges too
    uvs = rng.uniform(-1.5, 2.5, (40, 1, 2)) + rng.uniform(0.0, 0.3, (40, 3, 2))
    means = footprint_means(texture, uvs.astype(np.float32))
    for k in range(len(uvs)):
        assert means[k] == pytest.approx(brute_force_mean(texture, uvs[k].astype(np.float32)), rel=1e-9)


def test_a_footprint_as_wide_as_the_texture_or_mirrored_takes_the_whole_axis():
    texture = Texture(np.arange(48, dtype=np.uint8).reshape(4, 4, 3) * 5, wrap_s="mirror", wrap_t="repeat")
    whole = texture.linear_texels[..., :3].reshape(-1, 3).mean(axis=0)
    uvs = np.array([[[0.1, 0.0], [0.2, 3.0], [0.15, 1.5]]], np.float32)
    assert footprint_means(texture, uvs)[0] == pytest.approx(whole, rel=1e-6)
