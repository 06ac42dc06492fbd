"""Images to files: PNG (tone-mapped sRGB, 8 bit), EXR (linear float) or NPY (linear float32), chosen
by the file's extension, with text metadata: PNG text chunks, EXR string attributes, or an .npy's
sidecar JSON named after it (`out.npy.json`, so it sorts beside its image). An EXR can carry more
images as layers (channels `<layer>.R`, `.G`, `.B`, as OpenEXR names them); `load_image` reads the
main RGB, `load_layers` the rest.

The picture a PNG holds is `tonemap`'s: radiance scaled by an exposure in stops (EV), through a
tone curve (TONEMAP_OPERATORS: `clip`, the default, Khronos PBR Neutral, AgX, ACES), sRGB-encoded.

Every file is written whole or not at all: into a hidden temporary file in the target's folder
(the same filesystem, where `os.replace` is atomic), renamed over the target once complete, and
removed when anything (Ctrl-C included) stops the write.
"""

from __future__ import annotations

import json
import math
import os
import re
import secrets
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

FORMATS = (".png", ".exr", ".npy")
# Environment maps: OpenEXR, or Radiance RGBE through the hdr extra's OpenImageIO.
ENVIRONMENT_MAP_SUFFIXES = (".exr", ".hdr", ".pic")
_HDR_EXTRA = "pip install 'wgputrace[hdr]'"
SIDECAR_SUFFIX = ".json"
TEMPORARY_SUFFIX = ".tmp"
# An EXR layer's name: words joined by dots (OpenEXR's nested layers, "light.key"), each channel
# of the layer named `<name>.R` and so on.
_LAYER_NAME = re.compile(r"\w+(\.\w+)*")
_RGB = "RGB"

# Header attributes the EXR writer sets itself (or OpenEXR derives from the pixels): metadata under
# these names would be lost or break the file.
_EXR_OWN_ATTRIBUTES = frozenset(
    {
        "channels",
        "compression",
        "dataWindow",
        "displayWindow",
        "lineOrder",
        "pixelAspectRatio",
        "screenWindowCenter",
        "screenWindowWidth",
        "type",
    }
)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) on values clipped to [0, 1]."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


# The tone curves, by the name `tonemap`, `save_image`, `--tonemap` and the viewer take; their index
# is the id the viewer's shader switches on (TONEMAP_<NAME>). `clip` is the default everywhere: it
# is Mitsuba's PNG output, so our PNGs and the references' compare directly, and it keeps every
# PNG written before the other curves existed.
TONEMAP_OPERATORS = ("clip", "pbr_neutral", "agx", "aces")
DEFAULT_TONEMAP = "clip"
# `exposure="auto"`: the exposure that takes the image's log-average luminance to MIDDLE_GREY
# (Reinhard et al. 2002, "Photographic Tone Reproduction for Digital Images", its key value a).
AUTO_EXPOSURE = "auto"
MIDDLE_GREY = 0.18
# Luminances below this count as it in the log average: black pixels would drag it to -inf (the
# paper's delta), and an all-black image gets a finite exposure.
LOG_AVERAGE_FLOOR = 1e-4
# Rec. 709 luminance of linear sRGB.
REC709_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
# Exposed radiance above this counts as this much (+inf too): white through every curve, and the
# curves' squares stay finite in float32 (the viewer's shader limits it alike).
TONE_RADIANCE_MAX = 1e15

# Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral/README.md, 2024): F90, the Fresnel
# reflectance of IoR 1.5 at normal incidence, offsets the darks; highlights compress from
# K_s = 0.8 - F90 and desaturate at rate K_d.
PBR_NEUTRAL_F90 = 0.04
PBR_NEUTRAL_COMPRESSION_START = 0.8 - PBR_NEUTRAL_F90
PBR_NEUTRAL_DESATURATION = 0.15

# AgX as three.js r162 ships it (AgXToneMapping, after Filament's port of Blender 4's AgX by
# EaryChow): linear sRGB to Rec. 2020 (ITU-R BT.2407 matrices), the inset matrix, log2 encoding
# from AGX_MIN_EV to AGX_MAX_EV (middle grey +-, log2(2^-10 x 0.18) and log2(2^6.5 x 0.18)), the
# sigmoid as Wrensch's 6th-degree polynomial fit ("Minimal AgX implementation", iolite-engine.com,
# 2023; mean squared error 3.7e-6), the outset matrix, a 2.2 power to display-linear, back to sRGB.
# Matrices act on column vectors (rows as written; three.js writes GLSL columns).
REC2020_TO_SRGB = np.array([[1.6605, -0.5876, -0.0728], [-0.1246, 1.1329, -0.0083], [-0.0182, -0.1006, 1.1187]])
SRGB_TO_REC2020 = np.linalg.inv(REC2020_TO_SRGB)
AGX_INSET = np.array(
    [
        [0.856627153315983, 0.137318972929847, 0.11189821299995],
        [0.0951212405381588, 0.761241990602591, 0.0767994186031903],
        [0.0482516061458583, 0.101439036467562, 0.811302368396859],
    ]
).T
AGX_OUTSET = np.linalg.inv(
    np.array(
        [
            [0.899796955911611, 0.11142098895748, 0.11142098895748],
            [0.0871996192028351, 0.875575586156966, 0.0871996192028349],
            [0.013003424885555, 0.0130034248855548, 0.801379391839686],
        ]
    ).T
)
AGX_MIN_EV, AGX_MAX_EV = -12.47393, 4.026069
# the sigmoid's polynomial, highest power first (x^6 ... x^0)
AGX_SIGMOID = (15.5, -40.14, 31.96, -6.868, 0.4298, 0.1191, -0.00232)
# log2 of what the inset leaves of a black channel: keeps log2 finite (three.js's 1e-10)
AGX_FLOOR = 1e-10
AGX_DISPLAY_GAMMA = 2.2

# ACES: Stephen Hill's fit of the ACES 1.0 RRT and sRGB ODT (BakingLab, ACES.hlsl, 2016): linear
# sRGB to the RRT's saturated AP1, a rational curve, back to linear sRGB. Not three.js's variant,
# which also multiplies the exposure by 1 / 0.6 (+0.74 EV) for brighter viewing.
ACES_INPUT = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
ACES_OUTPUT = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]])
# RRTAndODTFit(v) = (v (v + a) - b) / (v (c v + d) + e)
ACES_FIT = (0.0245786, 0.000090537, 0.983729, 0.4329510, 0.238081)


def _clip(c: np.ndarray) -> np.ndarray:
    return np.clip(c, 0.0, 1.0)


def _pbr_neutral(c: np.ndarray) -> np.ndarray:
    x = c.min(axis=-1, keepdims=True)
    offset = np.where(x < 2.0 * PBR_NEUTRAL_F90, x - x * x / (4.0 * PBR_NEUTRAL_F90), PBR_NEUTRAL_F90)
    c = c - offset
    peak = c.max(axis=-1, keepdims=True)
    d = 1.0 - PBR_NEUTRAL_COMPRESSION_START
    new_peak = 1.0 - d * d / (peak + d - PBR_NEUTRAL_COMPRESSION_START)
    mix = 1.0 - 1.0 / (PBR_NEUTRAL_DESATURATION * (peak - new_peak) + 1.0)
    compressed = c * (new_peak / np.maximum(peak, PBR_NEUTRAL_COMPRESSION_START)) * (1.0 - mix) + new_peak * mix
    return np.where(peak < PBR_NEUTRAL_COMPRESSION_START, c, compressed)


def _agx(c: np.ndarray) -> np.ndarray:
    v = np.maximum(c @ SRGB_TO_REC2020.T, 0.0) @ AGX_INSET.T
    encoded = np.clip((np.log2(np.maximum(v, AGX_FLOOR)) - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV), 0.0, 1.0)
    display = np.polyval(AGX_SIGMOID, encoded) @ AGX_OUTSET.T
    return np.clip(np.maximum(display, 0.0) ** AGX_DISPLAY_GAMMA @ REC2020_TO_SRGB.T, 0.0, 1.0)


def _aces(c: np.ndarray) -> np.ndarray:
    a, b, c2, d, e = ACES_FIT
    v = c @ ACES_INPUT.T
    fitted = (v * (v + a) - b) / (v * (c2 * v + d) + e)
    return np.clip(fitted @ ACES_OUTPUT.T, 0.0, 1.0)


_CURVES = {"clip": _clip, "pbr_neutral": _pbr_neutral, "agx": _agx, "aces": _aces}


def check_tonemap(operator: str) -> None:
    """ValueError naming the operators unless `operator` is one of TONEMAP_OPERATORS."""
    if operator not in TONEMAP_OPERATORS:
        raise ValueError(f"tonemap must be one of {', '.join(TONEMAP_OPERATORS)}, got {operator!r}")


def tone_curve(exposed: np.ndarray, operator: str = DEFAULT_TONEMAP) -> np.ndarray:
    """The operator's curve, float64: exposed linear sRGB (..., 3), >= 0 and not NaN, to display-linear
    values in [0, 1] (before the sRGB transfer function). The viewer's shader computes the same."""
    check_tonemap(operator)
    return _CURVES[operator](np.minimum(np.asarray(exposed, dtype=np.float64), TONE_RADIANCE_MAX))


def auto_exposure(image: np.ndarray) -> float:
    """The exposure in EV that takes `image`'s log-average luminance to MIDDLE_GREY (non-finite
    pixels left out; an image with none finite gets 0)."""
    luminance = np.asarray(image, dtype=np.float64).reshape(-1, 3) @ REC709_LUMINANCE
    luminance = luminance[np.isfinite(luminance)]
    if luminance.size == 0:
        return 0.0
    log_average = np.mean(np.log(np.maximum(luminance, LOG_AVERAGE_FLOOR)))
    return float(np.log2(MIDDLE_GREY) - log_average / np.log(2.0))


def exposure_ev(image: np.ndarray, exposure: float | str) -> float:
    """`exposure` in EV, AUTO_EXPOSURE resolved for `image` (`auto_exposure`); ValueError for anything else."""
    if exposure == AUTO_EXPOSURE:
        return auto_exposure(image)
    try:
        stops = float(exposure)
    except (TypeError, ValueError):
        stops = math.nan
    if not math.isfinite(stops):
        raise ValueError(f"exposure must be a finite number of stops (EV) or {AUTO_EXPOSURE!r}, got {exposure!r}")
    return stops


def _display(linear: np.ndarray, operator: str, exposure: float | str) -> np.ndarray:
    """float64 sRGB-encoded display values in [0, 1] (tonemap's, before its rounding to float32)."""
    check_tonemap(operator)
    linear = np.asarray(linear, dtype=np.float64)
    scale = 2.0 ** exposure_ev(linear, exposure)
    # NaN is black and +inf full white, as a clipped PNG always showed them
    exposed = np.nan_to_num(linear * scale, nan=0.0, posinf=TONE_RADIANCE_MAX, neginf=0.0)
    return linear_to_srgb(tone_curve(np.maximum(exposed, 0.0), operator))


def tonemap(image: np.ndarray, operator: str = DEFAULT_TONEMAP, exposure: float | str = 0.0) -> np.ndarray:
    """The picture of linear radiance `image` (H, W, 3) as a screen shows it: float32 sRGB-encoded
    values in [0, 1] (matplotlib's imshow takes them; times 255, rounded, an 8-bit image). Radiance
    is scaled by 2^`exposure` (stops; "auto": `auto_exposure`) and mapped by `operator`'s curve
    (TONEMAP_OPERATORS, `tone_curve`)."""
    return _display(image, operator, exposure).astype(np.float32)


def srgb8(display: np.ndarray) -> np.ndarray:
    """sRGB-encoded values in [0, 1] as 8-bit, rounded to the nearest step."""
    return np.round(np.asarray(display, dtype=np.float64) * 255.0).astype(np.uint8)


def sidecar_path(path: str | Path) -> Path:
    """Where the metadata of the .npy `path` is kept: `out.npy` -> `out.npy.json`."""
    path = Path(path)
    return path.with_name(path.name + SIDECAR_SUFFIX)


def _check(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an (H, W, 3) image, got shape {image.shape}")
    return np.ascontiguousarray(image, dtype=np.float32)


def _check_layers(path: Path, image: np.ndarray, layers: Mapping[str, np.ndarray] | None) -> dict[str, np.ndarray]:
    """The layers as float32 (H, W, 3) arrays of the image's shape, by valid names; only an EXR has any."""
    layers = dict(layers or {})
    if layers and path.suffix.lower() != ".exr":
        raise ValueError(f"{path}: only .exr files carry layers ({', '.join(layers)}); write an .exr")
    checked = {}
    for name, layer in layers.items():
        if not isinstance(name, str) or not _LAYER_NAME.fullmatch(name):
            raise ValueError(f"{path}: layer name {name!r} must be letters, digits or _, parts joined by dots")
        layer = np.asarray(layer)
        if layer.shape != image.shape:
            raise ValueError(f"{path}: layer {name!r} has shape {layer.shape} but the image {image.shape}")
        checked[name] = np.ascontiguousarray(layer, dtype=np.float32)
    return checked


def _format(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"{path}: unknown image format {suffix!r}; use one of {', '.join(FORMATS)}")
    return suffix


def _check_metadata(path: Path, metadata: Mapping[str, str] | None) -> dict[str, str]:
    metadata = dict(metadata or {})
    for key, value in metadata.items():
        if not isinstance(key, str) or not isinstance(value, str):
            raise ValueError(f"{path}: metadata must map str to str, got {key!r}: {value!r}")
    clashes = sorted(_EXR_OWN_ATTRIBUTES & metadata.keys()) if path.suffix.lower() == ".exr" else []
    if clashes:
        raise ValueError(f"{path}: metadata key {clashes[0]!r} is an attribute the EXR header sets itself")
    return metadata


@contextmanager
def _temporary_beside(target: Path) -> Iterator[Path]:
    """A new hidden file in `target`'s folder; whatever is left of it when the block ends (by an
    exception or not) is removed, so a block that renames it over `target` leaves nothing behind.
    Opened with mode 0o666 like any new file (the umask applies), unlike mkstemp's 0o600, which
    os.replace would pass on to the target."""
    temporary = target.with_name(f".{target.name}.{secrets.token_hex(8)}{TEMPORARY_SUFFIX}")
    os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
    try:
        yield temporary
    finally:
        temporary.unlink(missing_ok=True)


@dataclass(frozen=True)
class ToneMapping:
    """How a PNG shows radiance: `operator` (TONEMAP_OPERATORS) after 2^`exposure` (EV or "auto")."""

    operator: str = DEFAULT_TONEMAP
    exposure: float | str = 0.0


# Each writer writes the whole file at the temporary path it is given, whose name says nothing of
# the format: the format is passed explicitly or implied by the writer. Only the PNG writer tone
# maps; only the EXR writer takes layers, and gets them only when there are some (save_image
# refuses them for the other formats).
def _write_png(path: Path, image: np.ndarray, tone: ToneMapping, metadata: dict[str, str]) -> None:
    from PIL import Image, PngImagePlugin

    text = PngImagePlugin.PngInfo()
    for key, value in metadata.items():
        text.add_text(key, value)  # tEXt, or iTXt (UTF-8) for text outside Latin-1
    pixels = srgb8(_display(image, tone.operator, tone.exposure))
    Image.fromarray(pixels, mode="RGB").save(path, format="PNG", pnginfo=text)


def _write_exr(
    path: Path,
    image: np.ndarray,
    tone: ToneMapping,
    metadata: dict[str, str],
    layers: Mapping[str, np.ndarray] | None = None,
) -> None:
    import OpenEXR

    header = {**metadata, "compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    # One array per channel, named in full: OpenEXR's python writer names the channels of an
    # (H, W, 3) array under the key "raw.RGB" "raw.RGB.R", "raw.RGB.G", ..., not "raw.R".
    channels = {
        f"{name}.{letter}": np.ascontiguousarray(layer[..., index])
        for name, layer in (layers or {}).items()
        for index, letter in enumerate(_RGB)
    }
    with OpenEXR.File(header, {_RGB: image, **channels}) as exr:
        exr.write(str(path))


def _write_npy(path: Path, image: np.ndarray, tone: ToneMapping, metadata: dict[str, str]) -> None:
    with open(path, "wb") as file:  # a file object: np.save would append ".npy" to the temporary's name
        np.save(file, image)


_WRITERS: dict[str, Callable[..., None]] = {
    ".png": _write_png,
    ".exr": _write_exr,
    ".npy": _write_npy,
}


def _replace_npy(temporary: Path, path: Path, metadata: dict[str, str]) -> None:
    """Rename the written .npy `temporary` over `path` and put `metadata` in its sidecar (none when
    empty). Two renames cannot be one atomic step, so the old sidecar goes first: an interruption
    leaves an image without metadata, never one with another image's."""
    sidecar = sidecar_path(path)
    with _temporary_beside(sidecar) as sidecar_temporary:
        sidecar_temporary.write_text(json.dumps(metadata, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        sidecar.unlink(missing_ok=True)
        os.replace(temporary, path)
        if metadata:
            os.replace(sidecar_temporary, sidecar)


def save_image(
    path: str | Path,
    image: np.ndarray,
    exposure: float | str = 0.0,
    metadata: Mapping[str, str] | None = None,
    layers: Mapping[str, np.ndarray] | None = None,
    tonemap: str = DEFAULT_TONEMAP,
) -> Path:
    """Write a linear (H, W, 3) `image` to `path` atomically (the old file or the new one, never a
    part); the extension picks the format: .png (tone mapped, sRGB, 8 bit), .exr or .npy (linear float32).

    Args:
        path: the file; its folder is made where missing.
        image: linear radiance, (H, W, 3).
        exposure: a .png's exposure in stops (EV: the radiance is scaled by 2**exposure), or
            "auto" (`auto_exposure`); EXR and NPY keep the linear values and ignore it.
        metadata: str to str, written into the file, or for an .npy into its sidecar
            `sidecar_path(path)` (an old sidecar is removed when there is none).
        layers: (EXR only) more linear images of the same shape by layer name ("raw", "albedo"),
            written as the channels `<name>.R`, `<name>.G`, `<name>.B` beside the image's R, G, B.
        tonemap: a .png's tone curve (`TONEMAP_OPERATORS`); EXR and NPY ignore it.

    Returns:
        `path`, as a Path.

    Raises:
        ValueError: an unknown extension, an image not (H, W, 3), bad metadata or layers, a bad
            exposure or tone curve, naming the file.
    """
    path = Path(path)
    image = _check(image)
    suffix = _format(path)
    tone = ToneMapping(tonemap, exposure)
    check_tonemap(tone.operator)
    exposure_ev(image, tone.exposure)  # refuses a bad exposure before anything is written
    metadata = _check_metadata(path, metadata)
    layers = _check_layers(path, image, layers)
    path.parent.mkdir(parents=True, exist_ok=True)
    with _temporary_beside(path) as temporary:
        _WRITERS[suffix](temporary, image, tone, metadata, **({"layers": layers} if layers else {}))
        if suffix == ".npy":
            _replace_npy(temporary, path, metadata)
        else:
            os.replace(temporary, path)
    return path


def load_image(path: str | Path) -> np.ndarray:
    """Read back the image at `path` that save_image wrote: linear float32 (H, W, 3) for .exr and
    .npy, decoded sRGB for .png. ValueError for an unknown extension or an image not (H, W, 3)."""
    path = Path(path)
    suffix = _format(path)
    if suffix == ".npy":
        return _check(np.load(path))
    if suffix == ".exr":
        import OpenEXR

        with OpenEXR.File(str(path)) as exr:
            return _check(exr.channels()[_RGB].pixels)
    from PIL import Image

    encoded = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    return _check(np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4))


def load_layers(path: str | Path) -> dict[str, np.ndarray]:
    """The layers of the EXR file at `path` (save_image's `layers`): linear float32 (H, W, 3) by
    name, for every layer holding R, G and B channels; {} for a file with none. ValueError for a
    file that is not an .exr."""
    path = Path(path)
    if _format(path) != ".exr":
        raise ValueError(f"{path}: only .exr files carry layers")
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = {name: channel.pixels for name, channel in exr.channels().items()}
    layers = _rgb_layers(channels)
    return {name: _check(_stacked(channels, layers[name])) for name in sorted(layers) if name}


def load_environment_map(path: str | Path) -> np.ndarray:
    """float32 (H, W, 3) texels of an equirectangular map: one RGB layer of an .exr (the unnamed
    layer's, else the only layer's), or an .hdr/.pic (Radiance RGBE, through OpenImageIO)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in ENVIRONMENT_MAP_SUFFIXES:
        formats = ", ".join(ENVIRONMENT_MAP_SUFFIXES)
        raise ValueError(f"{path}: environment maps must be {formats} files, not {suffix or 'without extension'}")
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    return _read_exr_map(path) if suffix == ".exr" else _read_radiance_map(path)


def _read_exr_map(path: Path) -> np.ndarray:
    import OpenEXR

    try:
        with OpenEXR.File(str(path), separate_channels=True) as exr:
            channels = {name: channel.pixels for name, channel in exr.channels().items()}
    except RuntimeError as error:  # OpenEXR's error for a file it cannot read
        raise ValueError(f"{path}: not a readable OpenEXR file ({error})") from None
    layers = _rgb_layers(channels)
    if "" not in layers and len(layers) != 1:
        found = ", ".join(sorted(channels)) or "none"
        raise ValueError(f"{path}: expected one layer of R, G and B channels, found channels {found}")
    names = layers[""] if "" in layers else next(iter(layers.values()))
    return _stacked(channels, names).astype(np.float32)


def _rgb_layers(channels: Mapping[str, np.ndarray]) -> dict[str, tuple[str, str, str]]:
    """Every layer with R, G and B channels (letters in either case), by layer name ("" for the
    unnamed layer's `R`, `G`, `B`): its channels' names in RGB order."""
    layers: dict[str, dict[str, str]] = {}
    for name in channels:
        layer, _, letter = name.rpartition(".")
        if letter.upper() in ("R", "G", "B"):
            layers.setdefault(layer, {})[letter.upper()] = name
    return {layer: tuple(names[letter] for letter in _RGB) for layer, names in layers.items() if len(names) == 3}


def _stacked(channels: Mapping[str, np.ndarray], names: tuple[str, str, str]) -> np.ndarray:
    return np.stack([channels[name] for name in names], axis=2)


def _read_radiance_map(path: Path) -> np.ndarray:
    try:
        import OpenImageIO
    except ImportError:
        raise ValueError(f"{path}: reading Radiance .hdr files needs OpenImageIO: {_HDR_EXTRA}") from None
    image = OpenImageIO.ImageInput.open(str(path))
    if image is None:
        raise ValueError(f"{path}: not a readable Radiance file ({OpenImageIO.geterror().strip()})")
    try:
        pixels = image.read_image(0, 0, 0, 3, "float")
    finally:
        image.close()
    if pixels is None or pixels.ndim != 3:
        raise ValueError(f"{path}: not a readable Radiance file ({OpenImageIO.geterror().strip()})")
    return np.ascontiguousarray(pixels, dtype=np.float32)


def read_text_metadata(path: str | Path) -> dict[str, str]:
    """The text metadata of an image file: a PNG's text chunks, an EXR's string attributes, an
    .npy's sidecar JSON ({} when it has none). Raises a one-line ValueError naming the file when
    it does not exist or cannot be read as its extension says."""
    path = Path(path)
    suffix = _format(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    if suffix == ".npy":
        return _read_sidecar(sidecar_path(path))
    try:
        if suffix == ".exr":
            import OpenEXR

            with OpenEXR.File(str(path), header_only=True) as exr:  # its header() is emptied on close
                return {key: value for key, value in exr.header().items() if isinstance(value, str)}
        from PIL import Image

        with Image.open(path, formats=["PNG"]) as png:
            return {str(key): str(value) for key, value in png.text.items()}
    except (OSError, RuntimeError) as error:  # PIL's UnidentifiedImageError is an OSError; OpenEXR's a RuntimeError
        raise ValueError(f"{path}: not a readable {suffix[1:].upper()} file ({error})") from None


def _read_sidecar(sidecar: Path) -> dict[str, str]:
    if not sidecar.is_file():
        return {}
    try:
        metadata = json.loads(sidecar.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"{sidecar}: not a JSON metadata file ({error})") from None
    if not isinstance(metadata, dict) or not all(isinstance(value, str) for value in metadata.values()):
        raise ValueError(f"{sidecar}: expected a JSON object of strings")
    return metadata
