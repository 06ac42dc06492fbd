"""wt.denoise's checks, which run before OIDN is needed (so these run without pyoidn too), and
what a missing pyoidn says."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

from wgputrace.denoise import DenoiserMissing, denoise, denoiser_available, denoiser_device

# The module itself: `wgputrace.denoise` as an attribute is the function once the package exports it.
denoise_module = importlib.import_module("wgputrace.denoise")

SIZE = 8


def image_and_guides() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    image = np.full((SIZE, SIZE, 3), 0.5, np.float32)
    albedo = np.full((SIZE, SIZE, 3), 0.7, np.float32)
    normal = np.zeros((SIZE, SIZE, 3), np.float32)
    normal[..., 2] = 1.0
    return image, albedo, normal


def spoiled(array: np.ndarray, value: float) -> np.ndarray:
    array = array.copy()
    array[2, 5, 1] = value
    return array


def reshaped(array: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    return np.resize(array, shape)


# (what is wrong, the arguments after the image's replacement, words the message must hold)
BAD_INPUTS = {
    "float64 image": (lambda i, a, n: (i.astype(np.float64), a, n), ("image", "float32", "float64")),
    "four channels": (lambda i, a, n: (reshaped(i, (SIZE, SIZE, 4)), a, n), ("image", "(8, 8, 4)")),
    "two dimensions": (lambda i, a, n: (i[..., 0], a, n), ("image", "(8, 8)")),
    "a list": (lambda i, a, n: (i.tolist(), a, n), ("image", "list")),
    "empty image": (lambda i, a, n: (i[:0], a[:0], n[:0]), ("image", "empty")),
    "albedo of another size": (lambda i, a, n: (i, a[:4], n), ("albedo", "(4, 8, 3)", "(8, 8, 3)")),
    "normal of another size": (lambda i, a, n: (i, a, n[:, :4]), ("normal", "(8, 4, 3)")),
    "float16 albedo": (lambda i, a, n: (i, a.astype(np.float16), n), ("albedo", "float16")),
    "NaN in the image": (lambda i, a, n: (spoiled(i, np.nan), a, n), ("image", "non-finite", "row 2, column 5")),
    "inf in the image": (lambda i, a, n: (spoiled(i, np.inf), a, n), ("image", "non-finite", "inf")),
    "negative image": (lambda i, a, n: (spoiled(i, -0.25), a, n), ("image", "negative", "row 2, column 5", "-0.25")),
    "NaN in the albedo": (lambda i, a, n: (i, spoiled(a, np.nan), n), ("albedo", "non-finite")),
    "albedo above 1": (lambda i, a, n: (i, spoiled(a, 1.5), n), ("albedo", "outside [0, 1]", "1.5")),
    "negative albedo": (lambda i, a, n: (i, spoiled(a, -0.1), n), ("albedo", "outside [0, 1]")),
    "inf in the normal": (lambda i, a, n: (i, a, spoiled(n, -np.inf)), ("normal", "non-finite")),
    "normal below -1": (lambda i, a, n: (i, a, spoiled(n, -1.5)), ("normal", "outside [-1, 1]")),
    "normal without albedo": (lambda i, a, n: (i, None, n), ("normal", "albedo")),
}


@pytest.mark.parametrize("case", BAD_INPUTS, ids=list(BAD_INPUTS))
def test_a_bad_input_is_a_one_line_value_error_naming_it(case):
    make, words = BAD_INPUTS[case]
    image, albedo, normal = make(*image_and_guides())
    with pytest.raises(ValueError) as raised:
        denoise(image, albedo, normal)
    message = str(raised.value)
    assert "\n" not in message
    assert message.startswith("denoise: ")
    for word in words:
        assert word in message, f"{word!r} missing from {message!r}"


def test_an_unknown_quality_is_refused_with_the_known_ones():
    image, _, _ = image_and_guides()
    with pytest.raises(ValueError, match="quality must be one of fast, balanced, high, got 'best'"):
        denoise(image, quality="best")


@pytest.fixture
def without_pyoidn(monkeypatch):
    """As where the extra is not installed: `import pyoidn` fails and no denoiser was made yet."""
    monkeypatch.setitem(sys.modules, "pyoidn", None)
    monkeypatch.setattr(denoise_module, "_shared", None)


def test_without_the_extra_the_error_says_how_to_install_it(without_pyoidn):
    image, _, _ = image_and_guides()
    assert not denoiser_available()
    for call in (lambda: denoise(image), denoiser_device):
        with pytest.raises(DenoiserMissing) as raised:
            call()
        assert isinstance(raised.value, ImportError)
        assert 'pip install "wgputrace[denoise]"' in str(raised.value)
        assert "\n" not in str(raised.value)


def test_wgputrace_imports_without_pyoidn():
    blocked = "import sys; sys.modules['pyoidn'] = None; import wgputrace, wgputrace.denoise"
    subprocess.run([sys.executable, "-c", blocked], check=True)
