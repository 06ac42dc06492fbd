"""The light table's weight of a triangle whose material emits through a texture (Principled's
emission_texture): the texture's mean over the triangle's footprint, a box filter over the
rectangle of texels that bilinear lookups inside the triangle read (its corners' transformed
coordinates' bounds, one texel wider), summed from a summed-area table so a triangle costs the
same whatever its footprint. The rectangle holds every texel the GPU can read there, so a zero
mean means a black footprint (no light) and any other weight is positive, as unbiased light
sampling needs. Repeat splits the rectangle at the texture's edge, clamp clips it; a rectangle a
period wide, and mirror in any case, take the whole axis (wider, still holding every texel read).
"""

from __future__ import annotations

import numpy as np

from ..scene.texture import Texture

# beyond 2^24 texels f32 coordinates have no fraction left (`texture_sample` clamps alike)
_COORDINATE_MAX = 2.0**24


def _axis_segments(low: np.ndarray, high: np.ndarray, n: int, mode: str) -> tuple[np.ndarray, ...]:
    """Two segments [a, b) of texel indices 0..n-1 per row (the second possibly empty) holding the
    indices [low, high) reach under the wrap mode."""
    whole = np.zeros_like(low), np.full_like(low, n), np.zeros_like(low), np.zeros_like(low)
    if mode == "clamp":
        a = np.clip(low, 0, n - 1)
        return a, np.clip(high, a + 1, n), *whole[2:]
    if mode == "mirror":
        return whole
    length = high - low
    a = np.mod(low, n)
    split = a + length > n
    first_end = np.where(split, n, a + length)
    second_end = np.where(split, a + length - n, 0)
    wide = length >= n
    return (
        np.where(wide, 0, a),
        np.where(wide, n, first_end),
        np.zeros_like(low),
        np.where(wide, 0, second_end),
    )


def footprint_means(texture: Texture, uvs: np.ndarray) -> np.ndarray:
    """(n, 3) float64: the texture's mean linear RGB over each triangle's footprint, from its (n, 3, 2)
    corner texture coordinates."""
    texels = texture.linear_texels[..., :3].astype(np.float64)
    height, width = texels.shape[:2]
    table = np.zeros((height + 1, width + 1, 3))
    table[1:, 1:] = texels.cumsum(axis=0).cumsum(axis=1)
    rows = texture.transform.rows().astype(np.float64)
    st = np.nan_to_num(uvs.astype(np.float64)) @ rows[:, :2].T + rows[:, 2]
    xy = np.clip(st * (width, height) - 0.5, -_COORDINATE_MAX, _COORDINATE_MAX)
    low = np.floor(xy.min(axis=1)).astype(np.int64)
    high = np.floor(xy.max(axis=1)).astype(np.int64) + 2
    xs = _axis_segments(low[:, 0], high[:, 0], width, texture.wrap_s)
    ys = _axis_segments(low[:, 1], high[:, 1], height, texture.wrap_t)
    total = np.zeros((len(uvs), 3))
    for x0, x1 in (xs[:2], xs[2:]):
        for y0, y1 in (ys[:2], ys[2:]):
            total += table[y1, x1] - table[y0, x1] - table[y1, x0] + table[y0, x0]
    count = ((xs[1] - xs[0]) + (xs[3] - xs[2])) * ((ys[1] - ys[0]) + (ys[3] - ys[2]))
    return total / count[:, None]
