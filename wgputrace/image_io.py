"""Images to files: PNG (tone-mapped sRGB, 8 bit), EXR (linear float) or NPY (linear float32), chosen
by the file's extension, with text metadata: PNG text chunks, EXR string attributes, or an .npy's
sidecar JSON named after it (`out.npy.json`, so it sorts beside its image). An EXR can carry more
images as layers (channels `<layer>.R`, `.G`, `.B`, as OpenEXR names them); `load_image` reads the
main RGB, `load_layers` the rest.

Every file is written whole or not at all: into a hidden temporary file in the target's folder
(the same filesystem, where `os.replace` is atomic), renamed over the target once complete, and
removed when anything (Ctrl-C included) stops the write.
"""

from __future__ import annotations

import json
import os
import re
import secrets
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
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


def tonemap(linear: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    """Linear radiance -> 8-bit sRGB: multiplied by `exposure`, clipped at 1 (as Mitsuba's PNG
    output does, so PNGs of ours and of references compare directly), then sRGB-encoded."""
    scaled = np.nan_to_num(np.asarray(linear, dtype=np.float64) * exposure, nan=0.0, posinf=1.0, neginf=0.0)
    return np.round(linear_to_srgb(scaled) * 255.0).astype(np.uint8)


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


# Each writer writes the whole file at the temporary path it is given, whose name says nothing of
# the format: the format is passed explicitly or implied by the writer. Only the EXR writer takes
# layers, and gets them only when there are some (save_image refuses them for the other formats).
def _write_png(path: Path, image: np.ndarray, exposure: float, metadata: dict[str, str]) -> None:
    from PIL import Image, PngImagePlugin

    text = PngImagePlugin.PngInfo()
    for key, value in metadata.items():
        text.add_text(key, value)  # tEXt, or iTXt (UTF-8) for text outside Latin-1
    Image.fromarray(tonemap(image, exposure), mode="RGB").save(path, format="PNG", pnginfo=text)


def _write_exr(
    path: Path,
    image: np.ndarray,
    exposure: float,
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


def _write_npy(path: Path, image: np.ndarray, exposure: float, metadata: dict[str, str]) -> None:
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
    exposure: float = 1.0,
    metadata: Mapping[str, str] | None = None,
    layers: Mapping[str, np.ndarray] | None = None,
) -> Path:
    """Write a linear (H, W, 3) `image` to `path` atomically (the old file or the new one, never a
    part); the extension picks the format: .png (sRGB, 8 bit), .exr or .npy (linear float32).

    Args:
        path: the file; its folder is made where missing.
        image: linear radiance, (H, W, 3).
        exposure: a .png's radiance is multiplied by this before it is clipped at 1 and encoded.
        metadata: str to str, written into the file, or for an .npy into its sidecar
            `sidecar_path(path)` (an old sidecar is removed when there is none).
        layers: (EXR only) more linear images of the same shape by layer name ("raw", "albedo"),
            written as the channels `<name>.R`, `<name>.G`, `<name>.B` beside the image's R, G, B.

    Returns:
        `path`, as a Path.

    Raises:
        ValueError: an unknown extension, an image not (H, W, 3), bad metadata or layers, naming the file.
    """
    path = Path(path)
    image = _check(image)
    suffix = _format(path)
    metadata = _check_metadata(path, metadata)
    layers = _check_layers(path, image, layers)
    path.parent.mkdir(parents=True, exist_ok=True)
    with _temporary_beside(path) as temporary:
        _WRITERS[suffix](temporary, image, exposure, metadata, **({"layers": layers} if layers else {}))
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
