"""Images to files: PNG (tone-mapped sRGB, 8 bit), EXR (linear float) or NPY (linear float32),
chosen by the file's extension."""

from __future__ import annotations

from pathlib import Path

import numpy as np

FORMATS = (".png", ".exr", ".npy")


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) on values clipped to [0, 1]."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def tonemap(linear: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    """Linear radiance -> 8-bit sRGB: multiplied by `exposure`, clipped at 1 (as Mitsuba's PNG
    output does, so PNGs of ours and of references compare directly), then sRGB-encoded."""
    scaled = np.nan_to_num(np.asarray(linear, dtype=np.float64) * exposure, nan=0.0, posinf=1.0, neginf=0.0)
    return np.round(linear_to_srgb(scaled) * 255.0).astype(np.uint8)


def _check(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an (H, W, 3) image, got shape {image.shape}")
    return np.ascontiguousarray(image, dtype=np.float32)


def save_image(path: str | Path, image: np.ndarray, exposure: float = 1.0) -> Path:
    """Write a linear (H, W, 3) image; the extension picks the format (.png, .exr, .npy)."""
    path = Path(path)
    image = _check(image)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"{path}: unknown image format {suffix!r}; use one of {', '.join(FORMATS)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".png":
        from PIL import Image

        Image.fromarray(tonemap(image, exposure), mode="RGB").save(path)
    elif suffix == ".exr":
        import OpenEXR

        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        with OpenEXR.File(header, {"RGB": image}) as exr:
            exr.write(str(path))
    else:
        np.save(path, image)
    return path


def load_image(path: str | Path) -> np.ndarray:
    """Read back what save_image wrote: linear float32 for .exr and .npy, decoded sRGB for .png."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        return _check(np.load(path))
    if suffix == ".exr":
        import OpenEXR

        with OpenEXR.File(str(path)) as exr:
            return _check(exr.channels()["RGB"].pixels)
    if suffix == ".png":
        from PIL import Image

        encoded = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
        return _check(np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4))
    raise ValueError(f"{path}: unknown image format {suffix!r}; use one of {', '.join(FORMATS)}")
