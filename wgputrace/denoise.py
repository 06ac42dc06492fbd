"""Intel Open Image Denoise (OIDN) on a rendered image: `denoise(image, albedo, normal)`.

OIDN's `RT` filter (trained on path-traced images) gets the image as linear HDR radiance and,
optionally, the albedo and shading normal of the first non-specular hit averaged over the same
samples. Every input is checked first: one NaN spreads through the network's receptive field.
One device serves the process (CUDA where OIDN's CUDA device loads, else the CPU;
`OIDN_DEVICE_CUDA=0` forces the CPU), filters are kept for the last few image configurations as
OIDN asks, and a lock lets any thread call `denoise`. pyoidn is imported on first use, so
`import wgputrace` works without it; DenoiserMissing says how to install it.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import numpy as np

INSTALL_HINT = 'pip install "wgputrace[denoise]" (pyoidn, which has wheels for x86-64 machines)'
# OIDN's quality modes by name (pyoidn's OIDN_QUALITY_* values).
QUALITIES = {"fast": 4, "balanced": 5, "high": 6}
# OIDN's device types (OIDNDeviceType) by the names denoiser_device() reports.
DEVICE_NAMES = {1: "CPU", 2: "SYCL", 3: "CUDA", 4: "HIP", 5: "Metal"}
# Filter set-ups kept at once: enough for a benchmark or viewer alternating colour-only and guided
# denoising at two qualities, few enough that the images' buffers stay a small multiple of one.
CACHED_PIPELINES = 4
# The range OIDN documents for each input, and what a value outside it is called.
RANGES = {
    "image": (0.0, np.inf, "a negative value"),
    "albedo": (0.0, 1.0, "a value outside [0, 1]"),
    "normal": (-1.0, 1.0, "a value outside [-1, 1]"),
}


class DenoiserMissing(ImportError):
    """pyoidn (Intel Open Image Denoise) is not installed or its library does not load."""


def denoiser_available() -> bool:
    """Whether denoise() can run here: pyoidn imports and OIDN makes a device."""
    try:
        _denoiser()
    except DenoiserMissing:
        return False
    return True


def denoiser_device() -> str:
    """The OIDN device denoise() uses: "CUDA" where OIDN's CUDA device loads, else "CPU"."""
    return _denoiser().device_name


def denoise(
    image: np.ndarray, albedo: np.ndarray | None = None, normal: np.ndarray | None = None, *, quality: str = "high"
) -> np.ndarray:
    """The image denoised by OIDN, guided by the albedo and normal where given.

    image: float32 (H, W, 3) linear radiance, finite and non-negative. albedo: float32 (H, W, 3) in
    [0, 1]; normal: float32 (H, W, 3) in [-1, 1], only with an albedo. quality: "high" (final
    frames), "balanced" or "fast" (interactive), OIDN's modes.
    Returns a new float32 (H, W, 3) array. Raises ValueError for a bad input (naming it),
    DenoiserMissing without pyoidn, RuntimeError when OIDN fails."""
    inputs = _checked_inputs(image, albedo, normal, quality)
    return _denoiser().run(inputs, quality)


def _checked_inputs(
    image: np.ndarray, albedo: np.ndarray | None, normal: np.ndarray | None, quality: str
) -> dict[str, np.ndarray]:
    """The inputs by OIDN's image names, each checked against what OIDN accepts."""
    if quality not in QUALITIES:
        raise ValueError(f"denoise: quality must be one of {', '.join(QUALITIES)}, got {quality!r}")
    if normal is not None and albedo is None:
        raise ValueError(
            "denoise: a normal guide needs an albedo guide too (OIDN uses the normal only beside an albedo)"
        )
    given = {"color": ("image", image), "albedo": ("albedo", albedo), "normal": ("normal", normal)}
    inputs = {}
    for oidn_name, (name, array) in given.items():
        if array is not None:
            _check_array(name, array, image)
            inputs[oidn_name] = np.ascontiguousarray(array)
    return inputs


def _check_array(name: str, array: Any, image: Any) -> None:
    if not isinstance(array, np.ndarray) or array.dtype != np.float32 or array.ndim != 3 or array.shape[2] != 3:
        got = f"{array.dtype} {array.shape}" if isinstance(array, np.ndarray) else type(array).__name__
        raise ValueError(f"denoise: {name} must be a float32 array of shape (H, W, 3), got {got}")
    if array.shape[0] == 0 or array.shape[1] == 0:
        raise ValueError(f"denoise: {name} is empty, shape {array.shape}")
    if array.shape != image.shape:
        raise ValueError(
            f"denoise: {name} has shape {array.shape} but the image {image.shape}; the guides must match it"
        )
    _check_values(name, array)


def _check_values(name: str, array: np.ndarray) -> None:
    """Every value finite and inside the input's range, else a ValueError at the first bad pixel."""
    low, high, outside = RANGES[name]
    for problem, bad in (("a non-finite value", ~np.isfinite(array)), (outside, (array < low) | (array > high))):
        pixels = np.flatnonzero(bad.any(axis=2))
        if pixels.size:
            row, column = divmod(int(pixels[0]), array.shape[1])
            raise ValueError(f"denoise: {name} has {problem} at row {row}, column {column}: {_rgb(array[row, column])}")


def _rgb(pixel: np.ndarray) -> str:
    return "(" + ", ".join(f"{value:.6g}" for value in pixel.tolist()) + ")"


def _pyoidn() -> Any:
    """The pyoidn module, or DenoiserMissing saying how to install it."""
    try:
        import pyoidn
    except ImportError as missing:
        raise DenoiserMissing(f"denoising needs Intel Open Image Denoise ({missing}): {INSTALL_HINT}") from None
    return pyoidn


@dataclass
class _Pipeline:
    """The OIDN buffers and filters that denoise images of one size with one set of guides."""

    buffers: dict[str, Any]  # by OIDN image name, inputs and "output"
    filters: list[Any]  # run in order: the guides' prefilters, then the image's filter

    def release(self) -> None:
        for oidn_object in (*self.filters, *self.buffers.values()):
            oidn_object.release()


@dataclass
class _Denoiser:
    """The process's OIDN device and its cached pipelines, used under one lock."""

    pyoidn: Any
    device: Any
    device_name: str
    pipelines: OrderedDict[tuple, _Pipeline] = field(default_factory=OrderedDict)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def run(self, inputs: dict[str, np.ndarray], quality: str) -> np.ndarray:
        height, width, _ = inputs["color"].shape
        output = np.empty((height, width, 3), np.float32)
        with self.lock:
            pipeline = self.pipeline((height, width, tuple(inputs), quality))
            for name, array in inputs.items():
                pipeline.buffers[name].write(0, array.nbytes, array)
            for oidn_filter in pipeline.filters:
                oidn_filter.execute()
                self.check("execute a filter")
            pipeline.buffers["output"].read(0, output.nbytes, output)
            self.check("read the output")
        return output

    def pipeline(self, key: tuple) -> _Pipeline:
        """The pipeline for (height, width, input names, quality), set up on first use."""
        if key in self.pipelines:
            self.pipelines.move_to_end(key)
            return self.pipelines[key]
        if len(self.pipelines) >= CACHED_PIPELINES:
            self.pipelines.popitem(last=False)[1].release()
        pipeline = self.pipelines[key] = self.new_pipeline(*key)
        return pipeline

    def new_pipeline(self, height: int, width: int, names: tuple[str, ...], quality: str) -> _Pipeline:
        nbytes = height * width * 3 * np.dtype(np.float32).itemsize
        buffers = {name: self.pyoidn.Buffer(self.device, nbytes) for name in (*names, "output")}
        self.check(f"allocate {len(buffers)} buffers of {width}x{height} pixels")
        size = (width, height)
        # Our guides are noisy where a pixel's samples disagree (behind glass, at edges); passed as
        # noisy (`cleanAux` off) OIDN copies that noise into the picture (2 to 5.4 dB below colour
        # only on the glass scene). So each guide's own RT filter denoises it in place first, and the
        # image's filter reads it as clean. Buffers, not shared pointers, serve a GPU device too.
        guide_filters = [
            self.new_filter({guide: buffers[guide], "output": buffers[guide]}, size, quality, {}) for guide in names[1:]
        ]
        image_filter = self.new_filter(buffers, size, quality, {"hdr": True, "cleanAux": True})
        return _Pipeline(buffers, [*guide_filters, image_filter])

    def new_filter(self, images: dict[str, Any], size: tuple[int, int], quality: str, flags: dict[str, bool]) -> Any:
        """A committed RT filter on these buffers (by OIDN image name) with these boolean parameters."""
        oidn = self.pyoidn
        oidn_filter = oidn.Filter(self.device, oidn.OIDN_FILTER_TYPE_RT)
        for name, buffer in images.items():
            oidn_filter.set_image(name, buffer, oidn.OIDN_FORMAT_FLOAT3, *size)
        for flag, value in flags.items():
            oidn_filter.set_bool(flag, value)
        oidn_filter.set_quality(QUALITIES[quality])
        oidn_filter.commit()
        self.check(f"set up the filter of {' and '.join(images)}")
        return oidn_filter

    def check(self, doing: str) -> None:
        message = self.device.get_error()
        if message is not None:
            raise RuntimeError(f"OIDN ({self.device_name}) failed to {doing}: {message}")


_shared: _Denoiser | None = None
_shared_lock = threading.Lock()


def _denoiser() -> _Denoiser:
    """The process's denoiser, made on first use."""
    global _shared
    with _shared_lock:
        if _shared is None:
            oidn = _pyoidn()
            device = _new_device(oidn)
            _shared = _Denoiser(oidn, device, DEVICE_NAMES.get(device.get_int("type"), "unknown"))
        return _shared


def _new_device(oidn: Any) -> Any:
    """A committed OIDN device: CUDA where OIDN's CUDA device loads, else the CPU."""
    try:
        cuda = oidn.Device.is_cuda_available(0)
    except OSError as broken:  # the first call into OIDN loads its library
        raise DenoiserMissing(f"Intel Open Image Denoise's library does not load ({broken}): {INSTALL_HINT}") from None
    if cuda:
        device = _committed(oidn, oidn.OIDN_DEVICE_TYPE_CUDA)
        if device is not None:
            return device
    device = _committed(oidn, oidn.OIDN_DEVICE_TYPE_CPU)
    if device is None:
        raise DenoiserMissing(
            "Intel Open Image Denoise supports no device on this machine (its CPU device needs SSE4.1 or ARM64)"
        )
    return device


def _committed(oidn: Any, device_type: int) -> Any:
    """A committed device of this type, or None where OIDN cannot make one."""
    device = oidn.Device(device_type)
    if device.get_error() is None:
        device.commit()
        if device.get_error() is None:
            return device
    device.release()
    return None
