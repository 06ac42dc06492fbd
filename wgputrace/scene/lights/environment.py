"""The environment: radiance arriving from infinitely far away, a constant or an equirectangular map,
with exactly Mitsuba 3's `envmap` convention (and `constant` for a constant), and the numpy
references of its lookup and importance sampling that the GPU code must match.

| parameter | type | default | meaning (Mitsuba 3) |
|---|---|---|---|
| radiance | RGB or float | - | a constant environment's radiance (`constant`, radiance) |
| texels | float32 (H, W, 3) | - | a map's radiance, row 0 the top row of the image (`envmap`, filename/bitmap) |
| intensity | float >= 0 | 1.0 | multiplies the radiance (`envmap`, scale) |
| rotation_degrees | float | 0.0 | turns the map about +y (`envmap`, to_world = rotate([0, 1, 0], angle)) |
| visible | bool | True | camera rays that escape see it; False: they see black while it still lights |

Which way each texel looks: `uv_of_local` and `bilinear`; how a map is sampled: `build_tables`.
Texels must be finite (`checked_texels`). The sampling tables do not depend on intensity,
rotation or visibility: those edits change only the parameters.
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...image_io import load_environment_map
from ..errors import SceneError
from .alias_table import alias_table
from .light import LUMINANCE_WEIGHTS

# The radiance of the environment a scene without any light gets (Mitsuba's `constant` emitter
# with radiance 1): a diffuse surface of albedo a under it, unshadowed, has radiance a.
DEFAULT_RADIANCE = 1.0

# One alias table entry as the GPU reads it: keep the slot when the draw's remainder is below
# `threshold`, else take `alias` (an index into the same table).
ALIAS_ENTRY = np.dtype([("threshold", np.float32), ("alias", np.uint32)])

# How the GPU holds an environment (`Environment.held_as`), and the WGSL of each: one radiance for
# every direction, or a map with its sampling tables.
CONSTANT_ENVIRONMENT, ENVIRONMENT_MAP = "constant", "map"
ENVIRONMENT_SHADERS = {
    CONSTANT_ENVIRONMENT: "lights/environment_constant.wgsl",
    ENVIRONMENT_MAP: "lights/environment_map.wgsl",
}

# A direction this close to the poles has no defined azimuth; its u is taken as 0.
_POLE_EPSILON = 1e-12

# Every map (every Environment and every edit of texels) gets a number no other has had, so a
# renderer that remembers which one it uploaded knows when to upload again.
_generations = itertools.count(1)


class EnvironmentWarning(UserWarning):
    """An environment map was changed to be usable: negative texels set to 0, or downscaled."""


@dataclass(frozen=True)
class EnvironmentTables:
    """The importance-sampling tables of a map (the cells: `build_tables`).

    `rows`: `cell_rows` ALIAS_ENTRY entries, a cell row drawn in proportion to its weight;
    `columns`: cell_rows x cell_columns ALIAS_ENTRY entries, row-major, each cell row its own alias
    table over its cells (`alias` is a column within the row); `cell_pdf`: cell_rows x cell_columns
    float32, the density per steradian of a direction in that cell (the same for any direction in it).
    Cell (j, i) spans u in [(i + 1/2) / W, (i + 3/2) / W] (wrapping) and theta in
    [pi j / cell_rows, pi (j + 1) / cell_rows]."""

    rows: np.ndarray
    columns: np.ndarray
    cell_pdf: np.ndarray
    cell_rows: int
    cell_columns: int


class Environment:
    """The light arriving from infinitely far away: a constant or an equirectangular map, as
    Mitsuba 3's `constant` and `envmap`.

    Args:
        radiance: a constant environment's RGB radiance (one number: grey).
        texels: a map's float32 (H, W, 3) radiance, row 0 looking straight up (or `from_file`).
        intensity: multiplies the radiance (Mitsuba's `scale`).
        rotation_degrees: turns the map about +y (Mitsuba's to_world rotate).
        visible: camera rays that escape see it; False: they see black while it still lights.
        source: what made the map (the file `from_file` read), in its repr and errors.

    Raises:
        SceneError: (a ValueError) both or neither of radiance and texels, or a value out of
            range (non-finite texels, a negative intensity), naming it.
    """

    def __init__(
        self,
        radiance: float | tuple[float, float, float] | None = None,
        *,
        texels: np.ndarray | None = None,
        intensity: float = 1.0,
        rotation_degrees: float = 0.0,
        visible: bool = True,
        source: str = "environment",
    ) -> None:
        if (radiance is None) == (texels is None):
            raise SceneError("Environment takes either radiance (a constant) or texels (a map), not both or neither")
        self._source = source
        self._radiance: np.ndarray | None = None
        self._texels: np.ndarray | None = None
        self._tables: EnvironmentTables | None = None
        self._tables_generation = 0
        # the map's luminance integral over the sphere, and the generation it is of (a 4k map takes 0.4 s)
        self._luminance_integral = (0, 0.0)
        self.generation = 0
        if texels is None:
            self.radiance = radiance
        else:
            self.texels = texels
        self.intensity = intensity
        self.rotation_degrees = rotation_degrees
        self.visible = visible

    @classmethod
    def from_file(
        cls, path: str | Path, intensity: float = 1.0, rotation_degrees: float = 0.0, visible: bool = True
    ) -> Environment:
        """An equirectangular map read from the OpenEXR (.exr) or Radiance (.hdr, .pic; the hdr
        extra) file at `path`; its texel values times `intensity` are radiance (Mitsuba's `envmap`
        with scale = intensity), `rotation_degrees` and `visible` as Environment takes them.
        SceneError naming the file where it cannot be read."""
        try:
            texels = load_environment_map(path)
        except ValueError as error:
            raise SceneError(str(error)) from None
        return cls(
            texels=texels, intensity=intensity, rotation_degrees=rotation_degrees, visible=visible, source=str(path)
        )

    def __repr__(self) -> str:
        what = f"radiance={tuple(self._radiance)}" if self._texels is None else f"{self._source!r} {self.size}"
        return f"Environment({what}, intensity={self.intensity}, rotation_degrees={self.rotation_degrees}, visible={self.visible})"

    # ---- parameters ------------------------------------------------------------------------

    @property
    def radiance(self) -> tuple[float, float, float] | None:
        """A constant environment's RGB radiance (before intensity); None for a map."""
        return None if self._radiance is None else tuple(float(c) for c in self._radiance)

    @radiance.setter
    def radiance(self, value: float | tuple[float, float, float]) -> None:
        rgb = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,)) if np.ndim(value) == 0 else np.asarray(value)
        if rgb.shape != (3,) or not np.issubdtype(rgb.dtype, np.number):
            raise SceneError(f"{self._source}: radiance must be a number or (r, g, b), got {value!r}")
        rgb = rgb.astype(np.float64)
        if not np.all(np.isfinite(rgb)) or np.any(rgb < 0):
            raise SceneError(f"{self._source}: radiance must be finite and >= 0, got {tuple(rgb.tolist())}")
        if self._texels is not None:
            self._texels = None
            self.generation = next(_generations)
        self._radiance = rgb.copy()

    @property
    def texels(self) -> np.ndarray | None:
        """A map's float32 (H, W, 3) radiance (before intensity), read-only; None for a constant.
        Assigning an array makes this a map (checked as from_file checks a file's)."""
        return self._texels

    @texels.setter
    def texels(self, value: np.ndarray) -> None:
        texels = checked_texels(value, self._source)
        texels.flags.writeable = False
        self._texels = texels
        self._radiance = None
        self.generation = next(_generations)

    @property
    def source(self) -> str:
        """Where the map came from (the file Environment.from_file read), or what made it."""
        return self._source

    @property
    def size(self) -> tuple[int, int] | None:
        """(width, height) of the map in texels; None for a constant."""
        return None if self._texels is None else (self._texels.shape[1], self._texels.shape[0])

    @property
    def intensity(self) -> float:
        return self._intensity

    @intensity.setter
    def intensity(self, value: float) -> None:
        self._intensity = _finite(value, self._source, "intensity", minimum=0.0)

    @property
    def rotation_degrees(self) -> float:
        return self._rotation_degrees

    @rotation_degrees.setter
    def rotation_degrees(self, value: float) -> None:
        self._rotation_degrees = _finite(value, self._source, "rotation_degrees")

    @property
    def visible(self) -> bool:
        return self._visible

    @visible.setter
    def visible(self, value: bool) -> None:
        if not isinstance(value, (bool, np.bool_)):
            raise SceneError(f"{self._source}: visible must be True or False, got {value!r}")
        self._visible = bool(value)

    def rotation_matrix(self) -> np.ndarray:
        """(3, 3) float64: world = R @ local (Mitsuba's to_world, a right-handed rotation about +y),
        so the image's centre, which looks along +z unturned, looks along (sin a, 0, cos a)."""
        a = math.radians(self._rotation_degrees)
        c, s = math.cos(a), math.sin(a)
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])

    # ---- the convention --------------------------------------------------------------------

    def uv(self, directions: np.ndarray) -> np.ndarray:
        """(n, 2) float64 map coordinates (u in [0, 1), v in [0, 1]) of world `directions` (n, 3)."""
        return uv_of_local(_unit(directions) @ self.rotation_matrix())

    def direction(self, uv: np.ndarray) -> np.ndarray:
        """(n, 3) float64 world unit directions of map coordinates `uv` (n, 2); aim at texel (row j,
        column i) of an H x W map with uv ((i + 0.5) / W, j / (H - 1))."""
        return local_of_uv(np.asarray(uv, dtype=np.float64)) @ self.rotation_matrix().T

    def lookup(self, directions: np.ndarray) -> np.ndarray:
        """(n, 3) float64 radiance arriving from world `directions` (n, 3), intensity applied:
        the constant, or the map's bilinear value as Mitsuba's `envmap` evaluates it."""
        directions = np.asarray(directions, dtype=np.float64)
        if self._texels is None:
            return np.broadcast_to(self._radiance * self._intensity, (len(directions), 3)).copy()
        return bilinear(self._texels, self.uv(directions)) * self._intensity

    # ---- importance sampling -----------------------------------------------------------------

    @property
    def black(self) -> bool:
        """Whether it sends no light whatever its intensity (all texels, or the constant, zero):
        light samplers skip it."""
        if self._texels is None:
            return not np.any(self._radiance > 0.0)
        return self.sampling_tables() is None

    @property
    def held_as(self) -> str | None:
        """How the GPU holds it (an ENVIRONMENT_SHADERS key), None for an all-black map, which lights
        nothing and is left out as no environment."""
        if self._texels is None:
            return CONSTANT_ENVIRONMENT
        return ENVIRONMENT_MAP if self.sampling_tables() is not None else None

    def weight(self, scene_radius: float) -> float:
        """The light sampler's weight, in its units (`Light.weight`): its power through the scene's
        bounding sphere over 2 pi."""
        return float(self.power(scene_radius)) / (2.0 * math.pi)

    def fill_record(self, record: np.void) -> None:
        """The environment's fields of the LIGHTING record: a constant's radiance (intensity applied)
        or a map's intensity, whether camera rays see it, the rotation about +y as (cos, sin), and
        the map's size."""
        if self._texels is None:
            record["environment_radiance"] = np.asarray(self.radiance) * self.intensity
        else:
            record["environment_radiance"] = (self.intensity,) * 3
            height, width = self._texels.shape[:2]
            record["environment_size"] = (width, height)
        angle = math.radians(self.rotation_degrees)
        record["environment_rotation"] = (math.cos(angle), math.sin(angle))
        record["environment_visible"] = bool(self.visible)

    def sampling_tables(self) -> EnvironmentTables | None:
        """The map's alias tables and densities, built once per texel generation; None for a
        constant (sampled uniformly over the sphere, as a 1x1 map would be) or a black map (never
        sampled: its power is 0)."""
        if self._texels is None:
            return None
        if self._tables_generation != self.generation:
            self._tables = build_tables(self._texels)
            self._tables_generation = self.generation
        return self._tables

    def sample(self, u: np.ndarray, u_texel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Directions drawn by the tables, and their density per steradian: ((n, 3), (n,)).

        `u_texel[:, 0]` draws the cell row from `rows` and `u_texel[:, 1]` the cell from that row's
        `columns` table, each as the triangle light table is drawn but from one number: slot =
        min(floor(x n), n - 1), kept when the remainder x n - slot is below its threshold, else its
        alias. `u[:, 0]` places phi and `u[:, 1]` cos(theta) uniformly within the cell, from the
        cell's start (u = (i + 1/2) / W, theta = pi j / cell_rows). A constant environment draws as
        a map of one cell. Raises for a black environment, which has nothing to sample."""
        u = np.asarray(u, dtype=np.float64)
        u_texel = np.asarray(u_texel, dtype=np.float64)
        if self.black:
            raise SceneError(f"{self._source}: a black environment sends no light to sample")
        tables = self.sampling_tables()
        if tables is None:
            row = column = np.zeros(len(u), dtype=np.int64)
            shape, density = (1, 1), np.full(len(u), 1.0 / (4.0 * math.pi))
        else:
            row = draw_alias(tables.rows, u_texel[:, 0])
            column = draw_alias(tables.columns.reshape(tables.cell_rows, tables.cell_columns), u_texel[:, 1], row)
            shape = (tables.cell_rows, tables.cell_columns)
            density = tables.cell_pdf.astype(np.float64)[row * tables.cell_columns + column]
        local = local_in_cell(row, column, shape, u)
        return local @ self.rotation_matrix().T, density

    def pdf(self, directions: np.ndarray) -> np.ndarray:
        """(n,) density per steradian with which `sample` draws world `directions` (n, 3)."""
        directions = np.asarray(directions, dtype=np.float64)
        if self.black:
            return np.zeros(len(directions))
        tables = self.sampling_tables()
        if tables is None:
            return np.full(len(directions), 1.0 / (4.0 * math.pi))
        row, column = cell_of_uv(self.uv(directions), tables.cell_rows, tables.cell_columns)
        return tables.cell_pdf.astype(np.float64)[row * tables.cell_columns + column]

    def power(self, radius: float) -> float:
        """Luminance flux through a disc of `radius` (the scene's bounding sphere) facing each
        direction in turn: pi r^2 x the integral of luminance over the sphere (pbrt-v4's
        ImageInfiniteLight::Phi, 4 pi^2 r^2 x the mean luminance). Not divided by pi, unlike the
        triangle light table's weights (area x luminance, `light_table`): a light
        sampler mixing them must multiply those by pi (one-sided Lambertian flux; 2 pi both sides)."""
        if self._texels is None:
            integral = 4.0 * math.pi * float(luminance(self._radiance))
        else:
            if self._luminance_integral[0] != self.generation:
                weight = _cell_luminance(self._texels) * _cell_solid_angles(self._texels.shape[:2])
                self._luminance_integral = (self.generation, float(np.sum(weight)))
            integral = self._luminance_integral[1]
        return math.pi * radius * radius * integral * self._intensity

    # ---- device limits ---------------------------------------------------------------------

    def fit_to(self, max_width: int, max_height: int, max_texels: int | None = None) -> Environment:
        """This environment, or (for a map larger than the limits: width > max_width, height >
        max_height or width x height > max_texels) a copy whose map is box-filtered down to fit,
        keeping the mean texel, with an EnvironmentWarning naming the sizes and the limit. The
        renderer passes the device's max_texture_dimension_2d and the texel count its storage
        binding holds for the tables."""
        if self._texels is None:
            return self
        height, width = self._texels.shape[:2]
        scale = min(1.0, max_width / width, max_height / height)
        if max_texels is not None:
            scale = min(scale, math.sqrt(max_texels / (width * height)))
        if scale >= 1.0:
            return self
        new_width, new_height = max(1, min(max_width, int(width * scale))), max(1, min(max_height, int(height * scale)))
        limit = f"{max_width}x{max_height}" + ("" if max_texels is None else f", {max_texels} texels")
        warnings.warn(
            f"{self._source}: {width}x{height} map downscaled to {new_width}x{new_height} to fit the device ({limit})",
            EnvironmentWarning,
            stacklevel=2,
        )
        smaller = box_downscale(box_downscale(self._texels, new_height, axis=0), new_width, axis=1)
        return Environment(
            texels=smaller.astype(np.float32),
            intensity=self._intensity,
            rotation_degrees=self._rotation_degrees,
            visible=self._visible,
            source=self._source,
        )


def default_environment() -> Environment:
    """The environment of a scene that brings no light: a constant radiance of DEFAULT_RADIANCE
    (Mitsuba's `constant` with radiance 1), a new one each call since environments are edited."""
    return Environment(radiance=DEFAULT_RADIANCE)


# ---- checking maps ----------------------------------------------------------------------------


def checked_texels(texels: np.ndarray, source: str) -> np.ndarray:
    """A float32 (H, W, 3) copy of `texels`, refused (SceneError naming `source` and the first bad
    texel, row and column from the top left) when empty, misshapen, NaN or infinite; negative
    texels are set to 0 with an EnvironmentWarning: real captures carry small negative values
    from colour-space conversion and resampling, radiance cannot be negative, and refusing them
    would refuse those files (Mitsuba keeps them, so such a map's reference differs there)."""
    array = np.asarray(texels)
    if array.ndim != 3 or array.shape[2] != 3 or not np.issubdtype(array.dtype, np.number):
        raise SceneError(
            f"{source}: environment texels must be an (H, W, 3) array of numbers, got {array.shape} {array.dtype}"
        )
    if array.shape[0] == 0 or array.shape[1] == 0:
        raise SceneError(f"{source}: the environment map is empty ({array.shape[1]}x{array.shape[0]} texels)")
    array = array.astype(np.float32)
    bad = ~np.isfinite(array)
    if bad.any():
        row, column, channel = np.argwhere(bad)[0]
        raise SceneError(
            f"{source}: texel (row {row}, column {column}) is {_texel_text(array[row, column])}: environment maps must be finite"
        )
    negative = array < 0
    if negative.any():
        row, column, _ = np.argwhere(negative)[0]
        warnings.warn(
            f"{source}: {int(negative.any(axis=2).sum())} texels with negative values set to 0, the first (row {row}, "
            f"column {column}) {_texel_text(array[row, column])}",
            EnvironmentWarning,
            stacklevel=3,
        )
        array = np.maximum(array, 0.0)
    return np.ascontiguousarray(array)


def _texel_text(rgb: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(c):g}" for c in rgb) + ")"


def _finite(value: float, source: str, field: str, minimum: float | None = None) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{source}: {field} must be a number, got {value!r}") from None
    if not math.isfinite(number) or (minimum is not None and number < minimum):
        bound = "" if minimum is None else f" and >= {minimum:g}"
        raise SceneError(f"{source}: {field} must be finite{bound}, got {value!r}")
    return number


def box_downscale(texels: np.ndarray, size: int, axis: int) -> np.ndarray:
    """`texels` resampled to `size` along `axis` by area: each new texel is the mean of the old ones
    it covers (fractions of a texel counted by the fraction), so the mean over the axis is kept."""
    count = texels.shape[axis]
    values = np.moveaxis(np.asarray(texels, dtype=np.float64), axis, 0)
    # the integral of the piecewise-constant texels from 0 to x, at each new texel's edges
    cumulative = np.concatenate([np.zeros((1, *values.shape[1:])), np.cumsum(values, axis=0)])
    edges = np.arange(size + 1) * (count / size)
    whole = np.minimum(np.floor(edges).astype(np.int64), count - 1)
    fraction = (edges - whole)[(...,) + (None,) * (values.ndim - 1)]
    integral = cumulative[whole] + fraction * values[whole]
    return np.moveaxis((integral[1:] - integral[:-1]) * (size / count), 0, axis)


# ---- the convention, in the map's own frame --------------------------------------------------


def _unit(directions: np.ndarray) -> np.ndarray:
    directions = np.asarray(directions, dtype=np.float64)
    return directions / np.linalg.norm(directions, axis=-1, keepdims=True)


def uv_of_local(d: np.ndarray) -> np.ndarray:
    """Mitsuba's direction_to_uv, u wrapped into [0, 1): unit local directions (n, 3) -> (n, 2).
    u = atan2(d.x, -d.z) / (2 pi), v = acos(d.y) / pi: the image's left edge looks along -z, its
    first quarter along +x, its centre along +z, its third quarter along -x."""
    on_axis = d[:, 0] ** 2 + d[:, 2] ** 2 < _POLE_EPSILON**2
    u = np.where(on_axis, 0.0, np.arctan2(d[:, 0], -d[:, 2]) / (2.0 * math.pi))
    u = u - np.floor(u)
    u = np.where(u >= 1.0, 0.0, u)  # -tiny wraps to 1.0 in floating point
    return np.stack([u, np.arccos(np.clip(d[:, 1], -1.0, 1.0)) / math.pi], axis=1)


def local_of_uv(uv: np.ndarray) -> np.ndarray:
    """Mitsuba's uv_to_direction: (n, 2) -> unit local directions (n, 3)."""
    phi, theta = 2.0 * math.pi * uv[:, 0], math.pi * uv[:, 1]
    return np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)], axis=1)


def bilinear(texels: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Mitsuba's eval_spectrum: texel columns at u = (i + 1/2) / W (column W - 1 blending with
    column 0 across the seam), rows at v = j / (H - 1), not at row centres (the whole top row looks
    straight up). Mitsuba refuses maps under 2x3 texels; here a one-row map is constant in v and a
    one-column map in u."""
    height, width = texels.shape[:2]
    x = (uv[:, 0] - 0.5 / width) % 1.0 * width
    y = uv[:, 1] * (height - 1)
    column = np.minimum(np.floor(x).astype(np.int64), width - 1)
    row = np.clip(np.floor(y).astype(np.int64), 0, max(height - 2, 0))
    wx, wy = (x - column)[:, None], (y - row)[:, None]
    next_column, next_row = (column + 1) % width, np.minimum(row + 1, height - 1)
    t = texels.astype(np.float64)
    top = t[row, column] * (1.0 - wx) + t[row, next_column] * wx
    bottom = t[next_row, column] * (1.0 - wx) + t[next_row, next_column] * wx
    return top * (1.0 - wy) + bottom * wy


# ---- the sampling distribution -----------------------------------------------------------------


def _cell_luminance(texels: np.ndarray) -> np.ndarray:
    """(cell rows, W): each cell's mean luminance, the mean of its four corner texels' (the integral
    of the bilinear lookup's luminance over the cell in (u, v), per unit area)."""
    texel_luminance = luminance(texels.astype(np.float64))
    across = 0.5 * (texel_luminance + np.roll(texel_luminance, -1, axis=1))
    if len(across) == 1:
        return across
    return 0.5 * (across[:-1] + across[1:])


def _cell_solid_angles(shape: tuple[int, int]) -> np.ndarray:
    """(cell rows, 1): the solid angle of one cell of each cell row, 2 pi / W x (cos theta_j -
    cos theta_j+1) with theta_j = pi j / cell rows."""
    height, width = shape
    bounds = np.cos(np.pi * np.arange(max(height - 1, 1) + 1) / max(height - 1, 1))
    return ((bounds[:-1] - bounds[1:]) * (2.0 * math.pi / width))[:, None]


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of linear RGB (..., 3), weighed as the triangle lights are."""
    return rgb @ LUMINANCE_WEIGHTS


def build_tables(texels: np.ndarray) -> EnvironmentTables | None:
    """The alias tables and per-cell densities of a map; None when it is all black.

    The lookup is bilinear inside each cell between four neighbouring texels (W cells around,
    H - 1 cell rows; a one-row map has one). A cell is drawn in proportion to its mean luminance
    times its solid angle, then a direction uniform in its solid angle, so the density is constant
    over a cell. A cell is drawn exactly where some corner texel is non-zero, which is where the
    lookup is non-zero, so light sampling alone (nee) misses no radiance."""
    cell_luminance = _cell_luminance(texels)
    weight = cell_luminance * _cell_solid_angles(texels.shape[:2])
    total = float(weight.sum())
    if total <= 0.0:
        return None
    cell_rows, cell_columns = weight.shape
    rows = _alias_entries(weight.sum(axis=1), alias_table)
    columns = np.concatenate([_alias_entries(row_weight, alias_table) for row_weight in weight])
    cell_pdf = (cell_luminance / total).astype(np.float32).ravel()
    return EnvironmentTables(rows, columns, cell_pdf, cell_rows, cell_columns)


def _alias_entries(weights: np.ndarray, alias_table) -> np.ndarray:
    """ALIAS_ENTRY records of `weights`; a row of zero weight (never drawn) keeps every slot."""
    entries = np.zeros(len(weights), dtype=ALIAS_ENTRY)
    if weights.sum() > 0.0:
        entries["threshold"], entries["alias"] = alias_table(weights)
    else:
        entries["threshold"], entries["alias"] = 1.0, np.arange(len(weights))
    return entries


def draw_alias(entries: np.ndarray, x: np.ndarray, table: np.ndarray | None = None) -> np.ndarray:
    """Indices drawn from alias tables by one uniform each (see Environment.sample): `entries` one
    table, or (tables, n) rows of which `table` picks each draw's."""
    count = entries.shape[-1]
    scaled = x * count
    slot = np.minimum(np.floor(scaled).astype(np.int64), count - 1)
    chosen = entries[slot] if table is None else entries[table, slot]
    keep = (scaled - slot) < chosen["threshold"]
    return np.where(keep, slot, chosen["alias"].astype(np.int64))


def local_in_cell(row: np.ndarray, column: np.ndarray, shape: tuple[int, int], u: np.ndarray) -> np.ndarray:
    """Local directions uniform in solid angle within cells (row, column) of a (cell rows, W) grid."""
    cell_rows, width = shape
    phi = 2.0 * math.pi * (column + 0.5 + u[:, 0]) / width
    top, bottom = np.cos(np.pi * row / cell_rows), np.cos(np.pi * (row + 1) / cell_rows)
    cos_theta = top + (bottom - top) * u[:, 1]
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta * cos_theta))
    return np.stack([np.sin(phi) * sin_theta, cos_theta, -np.cos(phi) * sin_theta], axis=1)


def cell_of_uv(uv: np.ndarray, cell_rows: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """(row, column) of the cell holding map coordinates `uv`."""
    column = np.floor(uv[:, 0] * width - 0.5).astype(np.int64) % width
    row = np.minimum(np.floor(uv[:, 1] * cell_rows).astype(np.int64), cell_rows - 1)
    return row, column
