"""The environment map as the GPU holds it: its texels, and its sampling tables packed into one
buffer of 32-bit words (`environment_table_words`). The tables do not change with intensity,
rotation or visibility, so an edit of those uploads the lighting parameters only.
"""

from __future__ import annotations

import numpy as np

# (H, W, 4): rgba32float texels, the fourth channel unused (WebGPU has no three-channel float format)
TEXEL_CHANNELS = 4


def environment_state(environment) -> tuple | None:
    """What the lighting parameters hold of `environment` (None: there is none): an edit changes it."""
    if environment is None:
        return None
    radiance = None if environment.radiance is None else tuple(environment.radiance)
    return (radiance, environment.intensity, environment.rotation_degrees, environment.visible)


def environment_texels(environment) -> np.ndarray:
    """The map as rgba32float texels: float32 (H, W, 4)."""
    texels = np.zeros((*environment.texels.shape[:2], TEXEL_CHANNELS), np.float32)
    texels[..., :3] = environment.texels
    return texels


def _alias_words(entries) -> np.ndarray:
    """(threshold bits, alias) pairs of alias entries, interleaved."""
    threshold = np.asarray(entries["threshold"], np.float32).view(np.uint32)
    return np.column_stack([threshold, np.asarray(entries["alias"], np.uint32)]).reshape(-1)


def environment_table_words(tables) -> np.ndarray:
    """The sampling tables (the environment's `sampling_tables()`, an `EnvironmentTables`) as one
    uint32 array, at the offsets `environment_sample` and `environment_pdf` derive from the map's size. An H x W map
    has R = max(H - 1, 1) cell rows of W cells:

    | words (uint32)  | count   | what                                                            |
    |-----------------|---------|-----------------------------------------------------------------|
    | rows            | 2 R     | per cell row: threshold (f32 bits), alias: picks a cell row      |
    | columns         | 2 R W   | per cell row, per cell: threshold, alias: picks a cell in the row |
    | cell densities  | R W     | f32 bits: the density per steradian of a direction in the cell  |
    """
    return np.concatenate(
        [
            _alias_words(tables.rows),
            _alias_words(tables.columns),
            np.ascontiguousarray(tables.cell_pdf, np.float32).reshape(-1).view(np.uint32),
        ]
    )
