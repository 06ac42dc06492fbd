"""Tiles, without a cluster: they cover the image exactly; a tile sees what the whole image sees
there (a tiled render converges to wgputrace.render's picture); one tile is the untiled render."""

from __future__ import annotations

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.cluster.batches import split_samples
from wgputrace.cluster.merge import TiledSum
from wgputrace.cluster.tiles import check_tileable, split_image
from wgputrace.cluster.worker import RenderSettings, RenderWorker
from wgputrace.testing.image_statistics import BLOCKS, CHANNELS, block_z_scores
from wgputrace.testing.stats import sidak, z_limit

SIZE = 32
SPP = 16
SEED = 2
SIGNIFICANCE = 1e-3
INDEPENDENT_SEED = 1000  # wgputrace.render's seed in the comparison: none of the tiles' seeds


@pytest.mark.parametrize(("width", "height", "side"), [(10, 7, 3), (2048, 1000, 1024), (5, 5, None), (4, 4, 9)])
def test_tiles_cover_the_image_once(width, height, side):
    tiles = split_image(width, height, side)
    covered = np.zeros((height, width), int)
    for tile in tiles:
        covered[tile.y : tile.y + tile.height, tile.x : tile.x + tile.width] += 1
        assert side is None or max(tile.shape) <= side
    assert (covered == 1).all()
    assert len({tile.shape for tile in tiles}) <= 4
    assert [tile.index for tile in tiles] == list(range(len(tiles)))


def _tiled_image(side: int | None) -> np.ndarray:
    settings = RenderSettings(SIZE, SIZE, SEED, tile_side=side)
    worker = RenderWorker()
    worker.prepare(wt.default_scene(), settings)
    merged = TiledSum(SIZE, SIZE, settings.tiles())
    for batch in split_samples(SPP, SEED, 2):
        for tile in settings.tiles():
            merged.add(tile, worker.render_batch(batch, tile).image)
    return merged.image()


@pytest.mark.gpu
def test_one_tile_is_the_untiled_render():
    assert np.array_equal(_tiled_image(SIZE), _tiled_image(None))


@pytest.mark.gpu
def test_a_tiled_render_converges_to_wgputrace_render():
    tiled = _tiled_image(SIZE // 2 - 3)  # 3 x 3 tiles of three shapes
    reference = wt.render(wt.default_scene(), spp=SPP, width=SIZE, height=SIZE, seed=INDEPENDENT_SEED)
    scores = block_z_scores(tiled, reference)
    limit = z_limit(sidak(SIGNIFICANCE, BLOCKS * BLOCKS * CHANNELS))
    assert np.abs(scores).max() < limit, f"block z-scores {np.round(scores, 1).tolist()} beyond {limit:.2f}"


def test_tiles_cut_the_pinhole_only():
    """TileCamera cuts a pinhole's view; another camera kind would lose its lens or projection."""
    check_tileable(wt.Camera())
    lens = wt.ThinLensCamera(aperture_radius=0.1, focus_distance=2.0)
    with pytest.raises(ValueError, match="tiles cut the pinhole Camera's view only: a ThinLensCamera renders untiled"):
        check_tileable(lens)
