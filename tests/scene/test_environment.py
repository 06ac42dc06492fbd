"""The environment on the host: Mitsuba 3's envmap convention pixel by pixel, the numpy references
of lookup and importance sampling (sample against pdf by chi-square, pdf a density), the readers
(.exr through OpenEXR, .hdr through OpenImageIO), every refused input's message, and downscaling."""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
import OpenEXR
import pytest

from wgputrace.scene import SceneError
from wgputrace.scene.lights.environment import (
    DEFAULT_RADIANCE,
    Environment,
    EnvironmentWarning,
    default_environment,
    luminance,
)
from wgputrace.testing.stats import chi_square

SEED = 5
SAMPLES = 200_000
SIGNIFICANCE = 1e-3
# Each table cell is split into SPLIT x SPLIT equal solid angles (phi and cos theta halves) for the
# chi-square test, so that sampling within a cell is tested as well as the choice of cell.
SPLIT = 2
# An equal-area grid this fine integrates the piecewise-constant pdf to about 1e-3.
QUADRATURE = (1024, 512)


def random_map(rng, height: int = 6, width: int = 10) -> np.ndarray:
    """Texels over four decades with some black, the shape of a sky with a sun."""
    texels = (rng.random((height, width, 3)) ** 4 * 10).astype(np.float32)
    texels[rng.random((height, width)) < 0.2] = 0.0
    return texels


def one_texel_map(height: int, width: int, row: int, column: int, value=(50.0, 40.0, 30.0)) -> np.ndarray:
    texels = np.zeros((height, width, 3), np.float32)
    texels[row, column] = value
    return texels


def equal_area_directions(columns: int, rows: int) -> tuple[np.ndarray, float]:
    """Midpoints of a columns x rows grid uniform in phi and cos(theta), and each one's solid angle."""
    phi = 2 * np.pi * (np.arange(columns) + 0.5) / columns
    cos_theta = 1 - 2 * (np.arange(rows) + 0.5) / rows
    phi, cos_theta = np.meshgrid(phi, cos_theta)
    sin_theta = np.sqrt(1 - cos_theta**2)
    directions = np.stack([np.cos(phi) * sin_theta, cos_theta, np.sin(phi) * sin_theta], axis=-1).reshape(-1, 3)
    return directions, 4 * np.pi / (columns * rows)


def rodrigues(axis, degrees: float) -> np.ndarray:
    """A rotation by `degrees` about `axis` as drjit's rotate (Mitsuba's Transform4f.rotate) builds it."""
    a = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    s, c = math.sin(math.radians(degrees)), math.cos(math.radians(degrees))
    cross = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return c * np.eye(3) + (1 - c) * np.outer(a, a) + s * cross


# ---- the convention ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "uv, looks",
    [
        ((0.0, 0.5), (0, 0, -1)),  # the image's left edge: -z
        ((0.25, 0.5), (1, 0, 0)),  # a quarter across: +x
        ((0.5, 0.5), (0, 0, 1)),  # the centre: +z
        ((0.75, 0.5), (-1, 0, 0)),  # three quarters: -x
        ((0.3, 0.0), (0, 1, 0)),  # the top row: up
        ((0.3, 1.0), (0, -1, 0)),  # the bottom row: down
    ],
)
def test_documented_directions(uv, looks):
    np.testing.assert_allclose(Environment(texels=np.ones((3, 4, 3))).direction([uv])[0], looks, atol=1e-12)


def test_one_bright_texel_lights_from_its_documented_direction():
    # row 1 of 3 is the horizon; column 1 of 4 sits at u = 1.5 / 4: phi = 135 degrees, between +x and +z
    env = Environment(texels=one_texel_map(3, 4, row=1, column=1))
    aim = env.direction([[(1 + 0.5) / 4, 1 / (3 - 1)]])[0]
    np.testing.assert_allclose(aim, [math.sqrt(0.5), 0, math.sqrt(0.5)], atol=1e-12)
    directions, _ = equal_area_directions(720, 360)
    radiance = env.lookup(directions)
    brightest = directions[np.argmax(radiance[:, 0])]
    assert np.degrees(np.arccos(np.clip(brightest @ aim, -1, 1))) < 1.0
    np.testing.assert_allclose(env.lookup([aim])[0], [50, 40, 30], rtol=1e-9)
    # bilinear: nothing from the opposite side, half way to the next texel half the radiance
    assert np.all(env.lookup([-aim]) == 0)
    np.testing.assert_allclose(env.lookup(env.direction([[2 / 4, 0.5]]))[0], [25, 20, 15], rtol=1e-9)


def test_columns_wrap_across_the_seam():
    # columns 0 and W-1 blend across u = 0: the image's left edge is their mean
    texels = np.zeros((3, 4, 3), np.float32)
    texels[:, 0], texels[:, 3] = 2.0, 4.0
    env = Environment(texels=texels)
    np.testing.assert_allclose(env.lookup(env.direction([[0.0, 0.5], [0.999999, 0.5]])), 3.0, rtol=1e-5)


def test_uv_and_direction_round_trip(rng):
    env = Environment(texels=random_map(rng), rotation_degrees=-71.5)
    uv = rng.random((1000, 2)) * [1, 0.998] + [0, 0.001]
    np.testing.assert_allclose(env.uv(env.direction(uv)), uv, atol=1e-12)
    directions = rng.normal(size=(1000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    np.testing.assert_allclose(env.direction(env.uv(directions)), directions, atol=1e-12)


@pytest.mark.parametrize("degrees", [90.0, -35.0, 400.0])
def test_rotation_is_mitsubas_to_world(rng, degrees):
    texels = random_map(rng)
    turned = Environment(texels=texels, rotation_degrees=degrees)
    np.testing.assert_allclose(turned.rotation_matrix(), rodrigues((0, 1, 0), degrees), atol=1e-12)
    directions = rng.normal(size=(500, 3))
    world = directions @ rodrigues((0, 1, 0), degrees).T
    np.testing.assert_allclose(turned.lookup(world), Environment(texels=texels).lookup(directions), rtol=1e-9)
    if degrees == 90.0:  # the image's centre, +z unturned, turns to +x
        np.testing.assert_allclose(turned.direction([[0.5, 0.5]])[0], [1, 0, 0], atol=1e-12)


# ---- sampling ----------------------------------------------------------------------------------


@pytest.mark.parametrize("shape", [(6, 10), (1, 1), (1, 2), (2, 1), (2, 3)])
def test_samples_follow_pdf_chi_square(rng, shape):
    env = Environment(texels=random_map(rng, *shape) + 0.01, rotation_degrees=0.0)
    draws = np.random.default_rng(SEED)
    directions, density = env.sample(draws.random((SAMPLES, 2)), draws.random((SAMPLES, 2)))
    np.testing.assert_allclose(env.pdf(directions), density, rtol=1e-12)
    tables = env.sampling_tables()
    rows, columns = tables.cell_rows * SPLIT, tables.cell_columns * SPLIT
    # bins: each cell split evenly in phi (from the cell's start at u = 1/(2W)) and in cos(theta)
    u, v = env.uv(directions).T
    column = np.floor(((u - 0.5 / tables.cell_columns) % 1.0) * columns).astype(int) % columns
    band = np.floor(v * tables.cell_rows).clip(0, tables.cell_rows - 1).astype(int)
    top, bottom = np.cos(np.pi * band / tables.cell_rows), np.cos(np.pi * (band + 1) / tables.cell_rows)
    half = np.floor((top - np.cos(np.pi * v)) / (top - bottom) * SPLIT).clip(0, SPLIT - 1).astype(int)
    observed = np.zeros((rows, columns))
    np.add.at(observed, (band * SPLIT + half, column), 1)
    # expected: the pdf at each bin's centre x the bin's solid angle
    bin_u = ((np.arange(columns) + 0.5) / columns + 0.5 / tables.cell_columns) % 1.0
    cell_top = np.cos(np.pi * (np.arange(rows) // SPLIT) / tables.cell_rows)
    cell_bottom = np.cos(np.pi * (np.arange(rows) // SPLIT + 1) / tables.cell_rows)
    bin_cos = cell_top + (cell_bottom - cell_top) * ((np.arange(rows) % SPLIT) + 0.5) / SPLIT
    bin_v = np.arccos(bin_cos) / np.pi
    uv = np.stack(np.meshgrid(bin_u, bin_v), axis=-1).reshape(-1, 2)
    solid_angle = ((cell_top - cell_bottom) / SPLIT)[:, None] * (2 * np.pi / columns)
    expected = env.pdf(env.direction(uv)).reshape(rows, columns) * solid_angle * SAMPLES
    assert expected.sum() == pytest.approx(SAMPLES, rel=1e-6)  # float32 densities
    result = chi_square(observed, expected)
    assert result.p_value > SIGNIFICANCE, result


@pytest.mark.parametrize("degrees", [0.0, 37.0])
def test_pdf_integrates_to_one(rng, degrees):
    env = Environment(texels=random_map(rng), rotation_degrees=degrees)
    directions, solid_angle = equal_area_directions(*QUADRATURE)
    assert env.pdf(directions).sum() * solid_angle == pytest.approx(1.0, abs=3e-3)
    tables = env.sampling_tables()
    bands = np.cos(np.pi * np.arange(tables.cell_rows + 1) / tables.cell_rows)
    cell_solid_angle = ((bands[:-1] - bands[1:])[:, None] * (2 * np.pi / tables.cell_columns)).repeat(
        tables.cell_columns, axis=1
    )
    assert float(np.sum(tables.cell_pdf.astype(np.float64) * cell_solid_angle.ravel())) == pytest.approx(1, rel=1e-6)


def test_pdf_is_mean_corner_luminance_over_the_total():
    # rows of constant radiance: cell row j's density is proportional to the mean of rows j and j + 1
    rows = np.array([[4.0, 0, 0], [0, 1.0, 0], [0, 0, 2.0], [1.0, 1.0, 1.0]])
    env = Environment(texels=np.repeat(rows[:, None, :], 8, axis=1))
    texel = luminance(rows)
    cell = 0.5 * (texel[:-1] + texel[1:])
    bands = np.cos(np.pi * np.arange(4) / 3)
    total = np.sum(cell * (bands[:-1] - bands[1:]) * 2 * np.pi)
    v = (np.arange(3) + 0.5) / 3
    np.testing.assert_allclose(env.pdf(env.direction(np.stack([np.full(3, 0.3), v], axis=1))), cell / total, rtol=1e-6)


def test_uniform_map_and_constant_sample_the_sphere_uniformly(rng):
    directions = rng.normal(size=(100, 3))
    for env in (Environment(texels=np.full((5, 7, 3), 0.5, np.float32)), Environment(radiance=(1, 2, 3))):
        np.testing.assert_allclose(env.pdf(directions), 1 / (4 * np.pi), rtol=1e-6)
    assert Environment(radiance=(1, 2, 3)).sampling_tables() is None


def test_black_environment_has_no_tables_and_no_power(rng):
    for env in (Environment(texels=np.zeros((4, 8, 3))), Environment(radiance=0.0)):
        assert env.black and env.sampling_tables() is None and env.power(10.0) == 0.0
        assert np.all(env.pdf(rng.normal(size=(10, 3))) == 0)
        with pytest.raises(SceneError, match="black environment"):
            env.sample(rng.random((4, 2)), rng.random((4, 2)))


def test_single_bright_texel_samples_only_its_cells(rng):
    env = Environment(texels=one_texel_map(5, 8, row=2, column=3))
    directions, density = env.sample(rng.random((2000, 2)), rng.random((2000, 2)))
    assert np.all(density > 0) and np.all(np.isfinite(directions))
    # the lookup is non-zero exactly where the pdf is: bilinear spread reaches only the 4 cells around it
    probe, _ = equal_area_directions(256, 128)
    lit = luminance(env.lookup(probe)) > 0
    np.testing.assert_array_equal(env.pdf(probe) > 0, lit)
    assert np.all(luminance(env.lookup(directions)) > 0)


def test_power_is_pi_r_squared_times_the_luminance_integral(rng):
    radius = 3.0
    constant = Environment(radiance=(1, 2, 3), intensity=2.0)
    assert constant.power(radius) == pytest.approx(4 * np.pi**2 * radius**2 * 2.0 * luminance(np.array([1, 2, 3])))
    texels = np.repeat(np.linspace(0.5, 3, 33)[:, None, None], 64, axis=1) * [1.0, 0.8, 0.6]
    env = Environment(texels=texels.astype(np.float32), intensity=0.5, rotation_degrees=20)
    directions, solid_angle = equal_area_directions(*QUADRATURE)
    integral = float(np.sum(luminance(env.lookup(directions))) * solid_angle)
    assert env.power(radius) == pytest.approx(np.pi * radius**2 * integral, rel=2e-3)


def test_parameter_edits_keep_the_tables_texel_edits_rebuild_them(rng):
    env = Environment(texels=random_map(rng))
    tables, generation = env.sampling_tables(), env.generation
    env.intensity, env.rotation_degrees, env.visible = 7.0, 123.0, False
    assert env.sampling_tables() is tables and env.generation == generation
    power = env.power(1.0)
    env.texels = random_map(rng)
    assert env.generation > generation and env.sampling_tables() is not tables and env.power(1.0) != power
    constant = Environment(radiance=1.0)
    generation = constant.generation
    constant.radiance = (2.0, 3.0, 4.0)
    assert constant.generation == generation and constant.radiance == (2.0, 3.0, 4.0)
    constant.texels = np.ones((2, 2, 3))
    assert constant.generation > generation and constant.radiance is None
    # generations are never shared between environments
    assert Environment(texels=np.ones((1, 1, 3))).generation not in (env.generation, constant.generation)


def test_texels_are_read_only(rng):
    env = Environment(texels=random_map(rng))
    with pytest.raises(ValueError):
        env.texels[0, 0, 0] = 1.0


def test_one_by_one_and_two_by_one_maps(rng):
    directions = rng.normal(size=(50, 3))
    single = Environment(texels=np.array([[[1.0, 2.0, 3.0]]]))
    np.testing.assert_allclose(single.lookup(directions), np.tile([1.0, 2.0, 3.0], (50, 1)))
    pair = Environment(texels=np.array([[[1.0, 1, 1], [3.0, 3, 3]]]))
    # column 0 at u = 1/4 (+x), column 1 at u = 3/4 (-x); the same whatever the height
    np.testing.assert_allclose(pair.lookup([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, 0, 1]])[:, 0], [1, 3, 2, 2])
    np.testing.assert_allclose(pair.lookup([[1, 0.5, 0]])[:, 0], [1.0])


def test_default_environment():
    first, second = default_environment(), default_environment()
    assert first.radiance == (DEFAULT_RADIANCE,) * 3 and first.visible and first.intensity == 1.0
    first.intensity = 3.0
    assert second.intensity == 1.0


# ---- downscaling -------------------------------------------------------------------------------


def test_fit_to_keeps_the_mean_and_warns(rng):
    env = Environment(texels=random_map(rng, 150, 301), intensity=2.0, rotation_degrees=10.0, visible=False)
    with pytest.warns(EnvironmentWarning, match=r"301x150 map downscaled to 128x63 .*\(128x128\)"):
        small = env.fit_to(128, 128)
    assert small.size == (128, 63)
    assert (small.intensity, small.rotation_degrees, small.visible) == (2.0, 10.0, False)
    mean = [texels.astype(np.float64).mean(axis=(0, 1)) for texels in (small.texels, env.texels)]
    np.testing.assert_allclose(mean[0], mean[1], rtol=1e-6)
    with pytest.warns(EnvironmentWarning, match="1000 texels"):
        assert np.prod(env.fit_to(4096, 4096, max_texels=1000).size) <= 1000
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert env.fit_to(301, 150) is env and Environment(radiance=1).fit_to(1, 1).radiance == (1, 1, 1)


# ---- files -------------------------------------------------------------------------------------


def write_exr(path, channels: dict[str, np.ndarray]) -> None:
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, channels) as exr:
        exr.write(str(path))


@pytest.mark.parametrize("layout", ["RGB", "RGBA", "layer half", "lower case"])
def test_exr_round_trip(tmp_path, rng, layout):
    texels = random_map(rng)
    if layout == "RGB":
        channels = {"RGB": texels}
    elif layout == "RGBA":
        channels = {"RGBA": np.dstack([texels, np.ones(texels.shape[:2], np.float32)])}
    elif layout == "layer half":
        texels = texels.astype(np.float16).astype(np.float32)
        channels = {f"sky.{c}": texels[..., i].astype(np.float16) for i, c in enumerate("RGB")}
    else:
        channels = {c: np.ascontiguousarray(texels[..., i]) for i, c in enumerate("rgb")}  # the writer reads raw memory
    write_exr(tmp_path / "map.exr", channels)
    env = Environment.from_file(tmp_path / "map.exr", intensity=2.0, rotation_degrees=5.0, visible=False)
    np.testing.assert_array_equal(env.texels, texels)
    assert (env.intensity, env.rotation_degrees, env.visible) == (2.0, 5.0, False)


def test_hdr_round_trip(tmp_path, rng):
    oiio = pytest.importorskip("OpenImageIO", reason="the hdr extra (OpenImageIO) reads .hdr files")
    texels = random_map(rng) + 0.01
    path = str(tmp_path / "map.hdr")
    out = oiio.ImageOutput.create(path)
    assert out.open(path, oiio.ImageSpec(texels.shape[1], texels.shape[0], 3, "float")) and out.write_image(texels)
    out.close()
    read = Environment.from_file(path).texels
    # RGBE: 8-bit mantissas sharing the largest component's exponent
    assert np.all(np.abs(read - texels) <= texels.max(axis=2, keepdims=True) / 128)


def test_hdr_without_openimageio_says_how_to_install(tmp_path, monkeypatch):
    path = tmp_path / "map.hdr"
    path.write_bytes(b"#?RADIANCE\n")
    monkeypatch.setitem(sys.modules, "OpenImageIO", None)
    with pytest.raises(
        SceneError, match=r"map\.hdr: reading Radiance \.hdr files needs OpenImageIO: pip install 'wgputrace\[hdr\]'"
    ):
        Environment.from_file(path)


def nan_map() -> np.ndarray:
    texels = np.ones((4, 6, 3), np.float32)
    texels[2, 5, 1] = np.nan
    texels[3, 0] = np.inf
    return texels


@pytest.mark.parametrize(
    "texels, message",
    [
        (nan_map(), r"map\.exr: texel \(row 2, column 5\) is \(1, nan, 1\): environment maps must be finite"),
        (np.where(np.arange(3) == 2, np.inf, 1.0) * np.ones((2, 2, 3)), r"texel \(row 0, column 0\) is \(1, 1, inf\)"),
    ],
)
def test_bad_texels_name_file_and_texel(tmp_path, texels, message):
    write_exr(tmp_path / "map.exr", {"RGB": texels.astype(np.float32)})
    with pytest.raises(SceneError, match=message):
        Environment.from_file(tmp_path / "map.exr")


def test_empty_and_misshapen_arrays():
    with pytest.raises(SceneError, match=r"environment: the environment map is empty \(0x3 texels\)"):
        Environment(texels=np.ones((3, 0, 3)))
    with pytest.raises(SceneError, match=r"must be an \(H, W, 3\) array of numbers, got \(4, 4\)"):
        Environment(texels=np.ones((4, 4)))


def test_negative_texels_set_to_zero_with_a_warning():
    texels = np.ones((3, 5, 3), np.float32)
    texels[1, 4] = (-0.25, 1.0, 1.0)
    texels[2, 0, 2] = -1e-4
    with pytest.warns(
        EnvironmentWarning,
        match=r"sky: 2 texels with negative values set to 0, the first \(row 1, column 4\) \(-0.25, 1, 1\)",
    ):
        env = Environment(texels=texels, source="sky")
    assert env.texels.min() == 0.0 and env.texels[1, 4, 0] == 0.0 and env.texels[2, 0, 2] == 0.0


def test_exr_without_rgb_names_its_channels(tmp_path):
    write_exr(tmp_path / "grey.exr", {"Y": np.ones((2, 4), np.float32)})
    with pytest.raises(SceneError, match=r"grey\.exr: expected one layer of R, G and B channels, found channels Y"):
        Environment.from_file(tmp_path / "grey.exr")


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("map.png", b"", r"map\.png: environment maps must be \.exr, \.hdr, \.pic files, not \.png"),
        ("missing.exr", None, r"missing\.exr: no such file"),
        ("broken.exr", b"not an exr", r"broken\.exr: not a readable OpenEXR file"),
    ],
)
def test_unreadable_files(tmp_path, name, content, message):
    if content is not None:
        (tmp_path / name).write_bytes(content)
    with pytest.raises(SceneError, match=message):
        Environment.from_file(tmp_path / name)


@pytest.mark.parametrize(
    "field, value, message",
    [
        ("intensity", -1.0, r"environment: intensity must be finite and >= 0, got -1\.0"),
        ("intensity", float("nan"), "intensity must be finite"),
        ("rotation_degrees", float("inf"), r"rotation_degrees must be finite, got inf"),
        ("rotation_degrees", "east", r"rotation_degrees must be a number, got 'east'"),
        ("visible", 1, r"visible must be True or False, got 1"),
        ("radiance", (1.0, -2.0, 0.0), r"radiance must be finite and >= 0, got \(1\.0, -2\.0, 0\.0\)"),
        ("radiance", (1.0, 2.0), r"radiance must be a number or \(r, g, b\), got \(1\.0, 2\.0\)"),
    ],
)
def test_bad_parameters_are_refused_and_change_nothing(field, value, message):
    env = Environment(radiance=(0.5, 0.5, 0.5), intensity=2.0, rotation_degrees=30.0)
    before = (env.radiance, env.intensity, env.rotation_degrees, env.visible)
    with pytest.raises(SceneError, match=message):
        setattr(env, field, value)
    assert (env.radiance, env.intensity, env.rotation_degrees, env.visible) == before


def test_radiance_xor_texels():
    with pytest.raises(SceneError, match="either radiance .* or texels"):
        Environment()
    with pytest.raises(SceneError, match="either radiance .* or texels"):
        Environment(radiance=1.0, texels=np.ones((1, 1, 3)))
